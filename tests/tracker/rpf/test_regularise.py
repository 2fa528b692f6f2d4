"""Regularization (Iglesis & de Montella eqs. 21-28): the MISE-optimal bandwidth, the
Epanechnikov kernel and the jitter x = x' + h D eps."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy import stats

from tracker.rpf.estimate import weighted_covariance
from tracker.rpf.regularise import epanechnikov_sample, optimal_bandwidth, regularise, unit_ball_volume


@pytest.mark.parametrize("n_dim, a_silverman", [(1, 2.34), (2, 2.40), (3, 2.49)])
def test_bandwidth_constant_matches_silverman_table_4_4(n_dim, a_silverman):
    # Silverman (1986) Table 4.4 prints A(K) of the Epanechnikov kernel to 2 decimals
    a = optimal_bandwidth(1, n_dim)  # N = 1: h = A(K)
    assert_allclose(a, a_silverman, rtol=0, atol=0.006)


def test_bandwidth_eq27_28_for_the_papers_filter():
    # n = 4: c_4 = pi^2 / 2, so A = (8 * 2/pi^2 * 8 * (2 sqrt(pi))^4)^(1/8) = 2048^(1/8)
    expected = 2048.0 ** (1 / 8) * 5000.0 ** (-1 / 8)
    assert_allclose(optimal_bandwidth(5000, 4), expected, rtol=1e-12)
    assert_allclose(unit_ball_volume(4), math.pi ** 2 / 2, rtol=1e-12)
    assert_allclose(unit_ball_volume(3), 4 * math.pi / 3, rtol=1e-12)



@pytest.mark.parametrize("n_dim", [2, 4, 5])
def test_epanechnikov_samples_follow_the_kernel(n_dim, rng):
    eps = epanechnikov_sample(n_dim, 200_000, rng)
    r2 = np.einsum("i...,i...->...", eps, eps)
    assert eps.shape == (n_dim, 200_000)
    assert r2.max() < 1.0  # support is the unit ball
    # density (1 - |x|^2) on the ball: |x|^2 ~ Beta(n/2, 2), each component variance 1/(n+4)
    ks = stats.kstest(r2, stats.beta(n_dim / 2, 2).cdf)
    assert ks.pvalue > 1e-3
    assert_allclose(np.cov(eps), np.eye(n_dim) / (n_dim + 4), atol=0.003)
    assert_allclose(eps.mean(axis=1), 0.0, atol=0.004)



def test_regularise_keeps_the_mean_and_inflates_the_covariance_by_h2_over_n_plus_4(rng):
    n, runs, d = 5000, 40, 4
    cov = np.array([[4e6, 1e6, 0, 0], [1e6, 1e6, 0, 0], [0, 0, 1.0, 0.2], [0, 0, 0.2, 0.5]])
    chol = np.linalg.cholesky(cov)
    state = np.einsum("ij,jrn->irn", chol, rng.standard_normal((d, runs, n)))
    state += np.array([5000.0, 800.0, -1.0, -2.0])[:, None, None]
    w = np.full((runs, n), 1.0 / n)
    new = regularise(state, w, rng)
    h = optimal_bandwidth(n, d)
    _, before = weighted_covariance(state, w)
    _, after = weighted_covariance(new, w)
    # resampling keeps the covariance on average, the kernel adds h^2 P / (n + 4)
    ratio = after.mean(axis=0) / before.mean(axis=0)
    assert_allclose(np.diag(ratio), 1.0 + h * h / (d + 4), atol=0.02)
    # the mean moves only by the resampling noise: sd sqrt(var / (n runs)); allow 5 sd
    shift = np.abs(new.mean(axis=(1, 2)) - state.mean(axis=(1, 2)))
    assert (shift < 5 * np.sqrt(np.diag(cov) / (n * runs) * (1 + h * h / (d + 4)))).all()


def test_shrunk_regularisation_keeps_the_mean_and_the_covariance(rng):
    # x = m + a (x' - m) + h D eps with a^2 = 1 - h^2/(n+4): a^2 P + h^2 P/(n+4) = P
    n, runs, d = 5000, 40, 4
    cov = np.array([[4e6, 1e6, 0, 0], [1e6, 1e6, 0, 0], [0, 0, 1.0, 0.2], [0, 0, 0.2, 0.5]])
    state = np.einsum("ij,jrn->irn", np.linalg.cholesky(cov), rng.standard_normal((d, runs, n)))
    state += np.array([5000.0, 800.0, -1.0, -2.0])[:, None, None]
    w = np.full((runs, n), 1.0 / n)
    new = regularise(state, w, rng, shrink=True)
    _, before = weighted_covariance(state, w)
    _, after = weighted_covariance(new, w)
    # 40 runs x 5000 particles: the sampling error of a variance ratio is ~0.005; 0.02 is 4 sd
    assert_allclose(np.diag(after.mean(axis=0) / before.mean(axis=0)), 1.0, atol=0.02)
    shift = np.abs(new.mean(axis=(1, 2)) - state.mean(axis=(1, 2)))
    assert (shift < 5 * np.sqrt(np.diag(cov) / (n * runs))).all()


def test_regularise_of_a_degenerate_cloud_stays_finite(rng):
    state = np.ones((4, 2, 100))
    w = np.full((2, 100), 0.01)
    new = regularise(state, w, rng)
    assert np.isfinite(new).all()
    assert_allclose(new, 1.0, atol=1e-6)
