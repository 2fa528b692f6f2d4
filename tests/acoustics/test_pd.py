"""The P_D formulas (acoustics.pd): Phi of the signal excess, any band, the cumulative P_D over
independent looks with a persistent offset (against a Monte Carlo of the same model), the first
detection's times and K's tail extrapolated beyond the table."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.pd import (
    any_band,
    cumulative_pd,
    first_detection_times,
    normal_cdf,
    normal_quantile,
    pd_of_excess,
    tail_reach_m,
)


def test_phi_is_the_normal_distribution_function():
    # Phi(0) = 1/2, Phi(1.959964) = 0.975, Phi(-1.281552) = 0.1 (tables of the normal distribution)
    assert_allclose(normal_cdf([0.0, 1.959964, -1.281552]), [0.5, 0.975, 0.1], rtol=0, atol=1e-7)
    assert normal_quantile(0.5) == 0.0
    assert_allclose([normal_quantile(0.9), normal_quantile(0.1)], [1.2815516, -1.2815516], atol=1e-7)


def test_pd_is_one_half_at_zero_excess_and_the_step_without_scatter():
    assert pd_of_excess(0.0, 3.0) == 0.5
    assert_allclose(pd_of_excess([3.0, -3.0], 3.0), [normal_cdf(1.0), normal_cdf(-1.0)], rtol=1e-12)
    assert list(pd_of_excess([-1e-9, 0.0, 2.0], 0.0)) == [0.0, 1.0, 1.0]
    assert pd_of_excess(np.nan, 2.0) == 0.0   # no K (beyond land): never detected


def test_any_band_is_one_minus_the_product_of_misses():
    assert_allclose(any_band([[0.5, 0.2], [0.5, 0.0]], axis=0), [0.75, 0.2])


def _monte_carlo(se, s, w, draws, rng):
    z = rng.standard_normal(draws)[:, None]
    hit = (se[None, :] + s[None, :] * z + w[None, :] * rng.standard_normal((draws, se.size))) >= 0.0
    return np.logical_or.accumulate(hit & np.isfinite(se)[None, :], axis=1).mean(axis=0)


@pytest.mark.parametrize("look_sd", [0.0, 0.4, 2.0])
def test_the_cumulative_pd_is_the_monte_carlo_of_the_same_model(rng, look_sd):
    # an excess that rises and falls along a track, a look beyond land, a persistent part
    # growing with range: the integral over the offset against 200 000 tracks drawn
    t = np.arange(120)
    se = 6.0 * np.sin(t / 25.0) - 3.0 + rng.normal(0.0, 1.5, t.size)
    se[40] = np.nan
    s = 2.5 + 0.01 * t
    w = np.full(t.size, look_sd)
    draws = 200_000   # binomial sd at most 0.0011: the 0.01 bound is 9 of them
    assert_allclose(cumulative_pd(se, s, w), _monte_carlo(se, s, w, draws, rng), rtol=0, atol=0.01)


def test_without_per_look_part_the_cumulative_pd_is_the_best_look_s():
    # one offset for the whole track and no per-look part: detected by t iff z >= min(-SE_i / s_i)
    se = np.array([-4.0, -1.0, -2.5, 0.5, -6.0])
    s = np.array([2.0, 2.0, 1.0, 3.0, 2.0])
    expected = normal_cdf(np.maximum.accumulate(se / s))
    assert_allclose(cumulative_pd(se, s, 0.0), expected, rtol=0, atol=1e-12)
    # and without the persistent part, independent looks: 1 - prod(1 - P_i)
    w = np.full(se.size, 1.5)
    assert_allclose(cumulative_pd(se, 0.0, w), 1.0 - np.cumprod(1.0 - pd_of_excess(se, w)), rtol=0, atol=1e-12)


def test_the_first_detection_times():
    t = np.array([0.0, 10.0, 20.0, 30.0])
    p = np.array([0.0, 0.25, 0.5, 0.6])
    got = first_detection_times(t, p)
    # (10 * 0.25 + 20 * 0.25 + 30 * 0.1) / 0.6
    assert_allclose(got["mean_s_given_detected"], (2.5 + 5.0 + 3.0) / 0.6)
    assert got["median_s"] == 20.0 and got["p90_s"] is None and got["p_detected_by_end"] == 0.6
    assert first_detection_times(t, np.zeros(4))["mean_s_given_detected"] is None


def test_the_tail_extrapolation_finds_a_spreading_law_s_range():
    # K(r) = A - 15 lg r - beta r exactly: the fit finds 15 dB per decade and the range where K
    # falls to the target, solved here by hand: 40 - 15 lg r - 0.0001 r = -60 at r = 3.88e5 m
    r = np.arange(1000.0, 50001.0, 1000.0)
    beta = 0.1   # dB/km
    k = 40.0 - 15.0 * np.log10(r) - beta / 1000.0 * r
    reach, m = tail_reach_m(r, k, beta, -60.0)
    assert_allclose(m, 15.0, atol=1e-9)
    assert_allclose(40.0 - 15.0 * math.log10(reach) - 1e-4 * reach, -60.0, atol=1e-6)
    # a tail already below the target ends at the table's last range; a NaN tail (land) says nothing
    assert tail_reach_m(r, k, beta, 0.0)[0] == r[-1]
    assert np.isnan(tail_reach_m(r, np.where(r > 40000, np.nan, k), beta, -60.0)[0])
    # a flatter tail than cylindrical spreading is taken as cylindrical (10 dB per decade)
    assert tail_reach_m(r, 40.0 - 3.0 * np.log10(r), 0.0, -60.0)[1] == 10.0
