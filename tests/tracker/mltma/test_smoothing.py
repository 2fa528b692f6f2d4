"""Robust smoothing (section 4 step 9)."""

import numpy as np
from numpy.testing import assert_allclose

from tracker.mltma import trimmed_mean


def test_robust_smoothing_drops_two_each_end():
    v = np.arange(19.0)[None, :]
    v[0, 0] = 1000.0   # an outlier is dropped
    assert_allclose(trimmed_mean(v, np.array([19]), 2, 19), np.mean(np.arange(3, 18)))  # 3..17 kept


def test_window_sd_is_the_mixture_of_the_kept_estimates():
    from tracker.mltma.smoothing import window_sd

    count = np.array([5, 5])
    same = np.array([[10.0, 10.0, 10.0, 10.0, 10.0], [8.0, 12.0, 8.0, 12.0, 10.0]])
    sds = np.full((2, 5), 3.0)
    out = window_sd(same, sds, count, 0, 19)
    # the same estimate five times: its own sd; four at +-2 about the mean (variance 3.2) add to 9
    assert_allclose(out, [3.0, np.sqrt(9.0 + 3.2)], rtol=1e-12)
    # the dropped ends do not count: 19 entries, the outlier dropped with the smallest
    v = np.arange(19.0)[None, :]
    v[0, 0] = 1000.0
    kept = np.arange(3, 18)
    assert_allclose(window_sd(v, np.zeros((1, 19)), np.array([19]), 2, 19), [np.std(kept)], rtol=1e-12)
