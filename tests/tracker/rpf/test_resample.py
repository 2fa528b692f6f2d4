"""Multinomial resampling of the particle filter: counts, independence of rows, N kept."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy import stats

from tracker.rpf.resample import multinomial_resample


def test_multinomial_resampling_counts_follow_the_weights(rng):
    w = np.array([0.5, 0.25, 0.125, 0.0625, 0.0625, 0.0])
    n = w.size
    runs = 20_000  # every row is an independent draw of n particles
    idx = multinomial_resample(np.tile(w, (runs, 1)), rng)
    counts = np.stack([np.bincount(row, minlength=n) for row in idx[:2000]])
    total = np.bincount(idx.ravel(), minlength=n)
    assert total[-1] == 0  # zero weight, never drawn
    # pooled counts: multinomial(runs * n, w); chi-square over the non-zero cells
    expected = runs * n * w[:-1]
    chi2 = ((total[:-1] - expected) ** 2 / expected).sum()
    assert chi2 < stats.chi2(len(expected) - 1).ppf(0.999)
    # per-row count of particle 0 ~ Binomial(n, 0.5): mean n/2, variance n/4
    assert_allclose(counts[:, 0].mean(), n * 0.5, atol=0.1)
    assert_allclose(counts[:, 0].var(), n * 0.25, atol=0.15)


def test_multinomial_rows_are_resampled_independently(rng):
    w = np.zeros((3, 4))
    w[0, 2] = w[1, 0] = w[2, 3] = 1.0
    idx = multinomial_resample(w, rng)
    assert (idx[0] == 2).all() and (idx[1] == 0).all() and (idx[2] == 3).all()


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=2, max_size=40).filter(lambda v: sum(v) > 1e-6),
       st.integers(0, 2**32 - 1))
def test_resampling_keeps_n_and_draws_only_weighted_particles(values, seed):
    w = np.array(values) / np.sum(values)
    idx = multinomial_resample(w[None], np.random.default_rng(seed))
    assert idx.shape == (1, w.size)
    assert (w[idx[0]] > 0).all()
