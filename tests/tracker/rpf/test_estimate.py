"""Estimate and covariance of the particles (Iglesis & de Montella eqs. 29-30)."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tracker.rpf.estimate import estimate


def test_estimate_is_the_weighted_mean_and_covariance(rng):
    state = rng.normal(size=(4, 1, 500))
    w = rng.random(500)
    w /= w.sum()
    mean, cov = estimate(state, w[None])
    assert_allclose(mean[:, 0], np.average(state[:, 0], axis=1, weights=w), rtol=1e-12)
    assert_allclose(cov[0], np.cov(state[:, 0], aweights=w, bias=True), rtol=1e-10, atol=1e-14)
