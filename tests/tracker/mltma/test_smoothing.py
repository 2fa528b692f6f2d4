"""Robust smoothing (section 4 step 9)."""

import numpy as np
from numpy.testing import assert_allclose

from tracker.mltma import trimmed_mean


def test_robust_smoothing_drops_two_each_end():
    v = np.arange(19.0)[None, :]
    v[0, 0] = 1000.0   # an outlier is dropped
    assert_allclose(trimmed_mean(v, np.array([19]), 2, 19), np.mean(np.arange(3, 18)))  # 3..17 kept
