"""K averaged over a range uncertainty, and its spread there."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tracker.depth.kstructure import RangeSmoothing, smoothed_k


def test_a_straight_k_is_kept_and_a_ripple_becomes_its_mean_and_spread():
    r = np.arange(100.0, 30_001.0, 100.0)
    line = -20.0 - 1e-3 * r
    smoothing = RangeSmoothing(fraction=0.05, floor_m=200.0)
    mean, var = smoothed_k(line, r, smoothing)
    inner = (r > 2000.0) & (r < 25_000.0)  # the kernel whole inside the axis
    assert_allclose(mean[inner], line[inner], atol=1e-9)
    # sd of K under N(r, sd_r^2), sd_r = max(200 m, 0.05 r): the floor holds to 4 km
    assert_allclose(var[inner], (1e-3 * smoothing.sd_m(r[inner])) ** 2, rtol=0.05)
    ripple = 3.0 * np.sin(2.0 * np.pi * r / 300.0)  # a 300 m ripple of 3 dB under a 1 km sd at 20 km
    mean, var = smoothed_k(line + ripple, r, RangeSmoothing(fraction=0.05, floor_m=200.0))
    far = (r > 15_000.0) & (r < 25_000.0)
    assert np.max(np.abs(mean[far] - line[far])) < 0.3
    assert_allclose(var[far], 4.5 + (1e-3 * 0.05 * r[far]) ** 2, rtol=0.15)


def test_cells_without_k_get_no_weight_and_stay_empty():
    r = np.arange(100.0, 5001.0, 100.0)
    k = np.where(r > 3000.0, np.nan, -30.0)  # land beyond 3 km
    mean, var = smoothed_k(k, r, RangeSmoothing(fraction=0.1, floor_m=300.0))
    assert np.all(np.isnan(mean[r > 3000.0])) and np.all(np.isnan(var[r > 3000.0]))
    assert_allclose(mean[r <= 3000.0], -30.0)
    assert np.all(var[r <= 3000.0] < 1e-9)
    off, _ = smoothed_k(k, r, RangeSmoothing(fraction=0.0, floor_m=0.0))
    assert_allclose(off, k)
