"""The kernel's regularization: the Epanechnikov draws (eq. 26) and the step of eq. 21."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy import stats

from tests.tracker.rpf.kernel.conftest import RTOL, particles
from tests.tracker.rpf.kernel.wrappers import epanechnikov_draws
from tracker.rpf.kernel.estimate import moments_run
from tracker.rpf.kernel.random import seed_states
from tracker.rpf.kernel.regularise import cholesky_loaded, regularise_run
from tracker.rpf.regularise import optimal_bandwidth


@pytest.mark.parametrize("d", [4, 5])
def test_epanechnikov_draws_follow_the_kernel(d):
    eps = epanechnikov_draws(seed_states(np.random.default_rng(2), 1)[0], d, 200_000)
    r2 = np.einsum("ni,ni->n", eps, eps)
    assert r2.max() < 1.0
    assert stats.kstest(r2, stats.beta(d / 2, 2).cdf).pvalue > 1e-3  # eq. 26
    assert_allclose(np.cov(eps.T), np.eye(d) / (d + 4), atol=0.003)


@pytest.mark.parametrize("shrink", [False, True])
def test_regularisation_step_is_eq21(shrink):
    rng = np.random.default_rng(13)
    state = particles(rng, n=500)
    w = rng.random(500)
    w /= w.sum()
    mean, cov, chol = np.empty(4), np.empty((4, 4)), np.empty((4, 4))
    moments_run(state, w, mean, cov)
    cholesky_loaded(cov, chol)
    load = 1e-12 * cov.diagonal().max() + 1e-18
    assert_allclose(chol, np.linalg.cholesky(cov + load * np.eye(4)), rtol=RTOL, atol=1e-12)
    idx = np.sort(rng.integers(0, 500, 500))
    eps = rng.uniform(-0.5, 0.5, (500, 4))
    h = optimal_bandwidth(500, 4)
    new = np.empty_like(state)
    regularise_run(state, idx, mean, chol, np.ascontiguousarray(eps.T), h, shrink, new)
    base = state[:, idx]
    if shrink:
        a = math.sqrt(1.0 - h * h / 8.0)
        base = mean[:, None] + a * (base - mean[:, None])
    assert_allclose(new, base + h * chol @ eps.T, rtol=RTOL)
