"""Cross-check: our .env writer and .shd reader against arlpy.uwapm driving the same BELLHOP.

arlpy runs in its own environment (.venv-arlpy, made by ``make test``; see bench/crosscheck/).
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from acoustics.bellhop.envfile import RunSpec, env_text
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from bench.crosscheck.run_arlpy import arlpy_tl_db

pytestmark = pytest.mark.bellhop


def test_tl_agrees_with_arlpy_on_the_munk_1000_environment(tmp_path):
    area = envdata.load_area("munk-1000")
    ssp = area.water.ssp
    rx_depth = np.arange(50.0, 1000.0, 100.0)
    rx_range = np.arange(500.0, 20_001.0, 500.0)
    case = {
        "frequency_hz": 50.0, "source_depth_m": 5.0,
        "receiver_depth_m": rx_depth.tolist(), "receiver_range_m": rx_range.tolist(),
        "water_depth_m": area.water.depth_m,
        "ssp": {"depth_m": np.asarray(ssp.depth_m, dtype=float).tolist(),
                "speed_mps": np.asarray(ssp.speed_mps, dtype=float).tolist()},
        "ssp_interpolation": "linear",  # tabulated profiles are linear (BELLHOP C), as in docs/formats.md
        "bottom": {"speed_mps": area.bottom.speed_mps, "density_gcc": area.bottom.density_gcc,
                   "attenuation_db_per_wavelength": area.bottom.attenuation_db_per_wavelength},
        "beams": {"count": 2000, "min_angle_deg": -80.0, "max_angle_deg": 80.0},
        "mode": "incoherent", "tl_max_db": 200.0,
    }
    arlpy = arlpy_tl_db(case, tmp_path)
    assert arlpy["arlpy_version"] == "1.9.3"
    assert_allclose(arlpy["receiver_depth_m"], rx_depth, rtol=0, atol=1e-3)
    assert_allclose(arlpy["receiver_range_m"], rx_range, rtol=0, atol=1e-2)
    tl_arlpy = arlpy["tl_db"]

    # arlpy always asks BELLHOP for Thorp absorption ('CVWT') and geometric beams ('IG')
    spec = RunSpec(title="cross-check", freq_hz=50.0, source_depth_m=(5.0,), receiver_depth_m=tuple(rx_depth),
                   range_m=tuple(rx_range), n_beams=2000, angle_min_deg=-80.0, angle_max_deg=80.0,
                   absorption=envdata.Absorption.THORP)
    tl_ours = tl_from_pressure(run_env(env_text(area, spec)).field.pressure[0], 200.0)
    assert tl_ours.shape == tl_arlpy.shape == (rx_depth.size, rx_range.size)
    # same executable and physics; the two env files differ only in formatting and box size,
    # so the fields agree to rounding of the written numbers
    assert_allclose(tl_ours, tl_arlpy, rtol=0, atol=0.05)
