"""The kernel's multinomial resampling by its counts."""

from __future__ import annotations

import numpy as np
from scipy import stats

from tests.tracker.rpf.kernel.wrappers import resample_draw
from tracker.rpf.kernel.random import seed_states


def test_multinomial_resampling_counts_follow_the_weights():
    w = np.array([0.5, 0.25, 0.125, 0.0625, 0.0625, 0.0])
    s = seed_states(np.random.default_rng(4), 1)[0]
    idx = np.concatenate([resample_draw(w, s) for _ in range(20_000)])
    total = np.bincount(idx, minlength=w.size)
    assert total[-1] == 0
    expected = idx.size * w[:-1]
    assert ((total[:-1] - expected) ** 2 / expected).sum() < stats.chi2(4).ppf(0.999)
    one = resample_draw(w, s)
    assert np.all(np.diff(one) >= 0)  # sorted, as multinomial_resample
