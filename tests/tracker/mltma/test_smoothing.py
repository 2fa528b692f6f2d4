"""Robust smoothing (section 4 step 9)."""

import numpy as np
from numpy.testing import assert_allclose

from tracker.mltma import trimmed_mean


def test_robust_smoothing_drops_two_each_end():
    v = np.arange(19.0)[None, :]
    v[0, 0] = 1000.0   # an outlier is dropped
    assert_allclose(trimmed_mean(v, np.array([19]), 2, 19), np.mean(np.arange(3, 18)))  # 3..17 kept


def test_window_sd_is_the_latest_stated_one_or_the_spread_if_larger():
    from tracker.mltma.smoothing import window_sd

    same = np.full((3, 5), 10.0)
    sds = np.array([[9.0, 7.0, 5.0, 3.0, 1.0], [9.0, 7.0, np.nan, np.nan, 1.0], [np.nan] * 5])
    # estimates that agree: the latest sd of the window's first 4 cycles (a cycle without one is
    # passed over, the padding past the window's end is not read); none stated: NaN
    out = window_sd(same, sds, np.array([4, 4, 5]), 0, 19)
    assert_allclose(out[:2], [3.0, 7.0])
    assert np.isnan(out[2])
    # four estimates at +-2 about their mean: the spread (2) where it exceeds the latest sd (1)
    wander = np.array([[8.0, 12.0, 8.0, 12.0, 10.0]])
    assert_allclose(window_sd(wander[:, :4], np.full((1, 4), 1.0), np.array([4]), 0, 19), [2.0], rtol=1e-12)
    assert_allclose(window_sd(wander[:, :4], np.full((1, 4), 3.0), np.array([4]), 0, 19), [3.0], rtol=1e-12)
    # the dropped ends do not count: 19 entries, the outlier dropped with the smallest
    v = np.arange(19.0)[None, :]
    v[0, 0] = 1000.0
    kept = np.arange(3, 18)
    assert_allclose(window_sd(v, np.zeros((1, 19)), np.array([19]), 2, 19), [np.std(kept)], rtol=1e-12)
