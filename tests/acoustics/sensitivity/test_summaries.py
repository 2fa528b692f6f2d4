"""Summaries of synthetic studies with known answers: constant offsets, ramps, eq. 20 ranging."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from acoustics import sensitivity as sens
from envdata.errors import InputError


def synthetic_study(offsets_db, ramp_db=None, n_range=400):
    """A study whose members are the nominal K(r) = -20 lg r - 60 (eq. 13 with A = 1, beta = 0)
    plus a constant offset per member (and optionally a zero-mean ramp)."""
    r = 100.0 * np.arange(1, n_range + 1)
    nominal = -20 * np.log10(r / 1000.0) - 60.0
    k_nom = np.broadcast_to(nominal, (1, 2, n_range)).copy()
    offsets = np.asarray(offsets_db, dtype=float)
    k = k_nom[None] + offsets[:, None, None, None]
    if ramp_db is not None:
        ramp = np.linspace(-1.0, 1.0, n_range)
        k = k + np.asarray(ramp_db)[:, None, None, None] * ramp
    return sens.study_face(xr.Dataset({"k_db": (("member", "class", "band", "range"), k),
                                       "k_nominal_db": (("class", "band", "range"), k_nom)},
                                      coords={"member": np.arange(offsets.size), "class": ["C"], "band": ["B1", "B2"],
                                              "range": r, "bottom_speed_mps": ("member", 1600.0 + 10.0 * offsets)}))


def test_constant_offsets_are_recognised_as_constant():
    offsets = np.array([-2.0, -1.0, 0.5, 1.0, 1.5])
    summary = sens.summarize(synthetic_study(offsets), eval_ranges_m=(5000.0, 20000.0))
    assert_allclose(summary["k_constant_fraction"], 1.0)
    assert_allclose(summary["k_residual_rms_db"], 0.0, atol=1e-12)
    assert_allclose(summary["k_offset_sd_db"], offsets.std(ddof=1))
    assert_allclose(summary["k_sd_db"], offsets.std(ddof=1))
    assert_allclose(summary["k_bias_db"], offsets.mean(), atol=1e-12)
    assert_allclose(summary["k_error_sd_db"], np.sqrt(np.mean(offsets ** 2)))
    assert list(summary["parameter"].values) == ["bottom_speed_mps"]
    assert_allclose(summary["k_offset_correlation"], 1.0)  # the offsets were made as 0.1 dB per m/s
    # eq. 20 with K = -20 lg r: a level dK dB too high reads as a range 10^(-dK/20) times the truth
    for i, r0 in enumerate((5000.0, 20000.0)):
        expect = r0 * 10 ** (-offsets / 20.0)
        assert_allclose(summary["range_error_m"].values[:, 0, i] + r0, expect, atol=50.0)  # 100 m grid


def test_zero_mean_ramps_are_recognised_as_range_varying():
    summary = sens.summarize(synthetic_study(np.zeros(4), ramp_db=[-3.0, -1.0, 1.0, 3.0]))
    assert_allclose(summary["k_constant_fraction"], 0.0, atol=1e-12)
    assert_allclose(summary["k_offset_sd_db"], 0.0, atol=1e-12)
    assert float(summary["k_residual_rms_db"][0, 0]) > 1.0


def test_summary_window_must_hold_ranges():
    with pytest.raises(InputError, match=r"range window \[50000, 60000\] m contains no range of the study"):
        sens.summarize(synthetic_study([1.0, 2.0], n_range=100), range_min_m=50000.0, range_max_m=60000.0)


def test_level_ranging_eq20_weights_bands_by_their_sd():
    r = 100.0 * np.arange(1, 101)
    table = np.stack([-20 * np.log10(r), -30 * np.log10(r)])
    levels = np.array([-20 * np.log10(4000.0), -30 * np.log10(6000.0)])  # the two bands disagree
    assert sens.level_range_m(levels, table, r, sigma_db=np.array([0.1, 10.0])) == pytest.approx(4000.0)
    assert sens.level_range_m(levels, table, r, sigma_db=np.array([10.0, 0.1])) == pytest.approx(6000.0)
