"""Regularized particle filter (Iglesis & de Montella sec. 4): kernel, bandwidth, resampling,
motion model, likelihoods and estimate."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from scipy import stats

from tracker import rpf


# --- eqs. 27-28: the MISE-optimal bandwidth -------------------------------------------------

@pytest.mark.parametrize("n_dim, a_silverman", [(1, 2.34), (2, 2.40), (3, 2.49)])
def test_bandwidth_constant_matches_silverman_table_4_4(n_dim, a_silverman):
    # Silverman (1986) Table 4.4 prints A(K) of the Epanechnikov kernel to 2 decimals
    a = rpf.optimal_bandwidth(1, n_dim)  # N = 1: h = A(K)
    assert_allclose(a, a_silverman, rtol=0, atol=0.006)


def test_bandwidth_eq27_28_for_the_papers_filter():
    # n = 4: c_4 = pi^2 / 2, so A = (8 * 2/pi^2 * 8 * (2 sqrt(pi))^4)^(1/8) = 2048^(1/8)
    expected = 2048.0 ** (1 / 8) * 5000.0 ** (-1 / 8)
    assert_allclose(rpf.optimal_bandwidth(5000, 4), expected, rtol=1e-12)
    assert_allclose(rpf.unit_ball_volume(4), math.pi ** 2 / 2, rtol=1e-12)
    assert_allclose(rpf.unit_ball_volume(3), 4 * math.pi / 3, rtol=1e-12)


# --- eq. 26: the Epanechnikov kernel ---------------------------------------------------------

@pytest.mark.parametrize("n_dim", [2, 4, 5])
def test_epanechnikov_samples_follow_the_kernel(n_dim, rng):
    eps = rpf.epanechnikov_sample(n_dim, 200_000, rng)
    r2 = np.einsum("i...,i...->...", eps, eps)
    assert eps.shape == (n_dim, 200_000)
    assert r2.max() < 1.0  # support is the unit ball
    # density (1 - |x|^2) on the ball: |x|^2 ~ Beta(n/2, 2), each component variance 1/(n+4)
    ks = stats.kstest(r2, stats.beta(n_dim / 2, 2).cdf)
    assert ks.pvalue > 1e-3
    assert_allclose(np.cov(eps), np.eye(n_dim) / (n_dim + 4), atol=0.003)
    assert_allclose(eps.mean(axis=1), 0.0, atol=0.004)


# --- eqs. 19-20: weights ---------------------------------------------------------------------

def test_normalise_with_logsumexp_survives_huge_log_likelihoods():
    log_w = np.array([[-1e5, -1e5 - 1.0, -1e5 - 2.0], [0.0, 0.0, 0.0]])
    w = np.exp(rpf.normalise(log_w))
    assert_allclose(w.sum(axis=1), 1.0, rtol=1e-9)  # logs near -1e5 keep ~11 digits
    assert_allclose(w[0], np.exp([0, -1, -2]) / np.exp([0, -1, -2]).sum(), rtol=1e-9)


def test_n_eff_eq20():
    assert_allclose(rpf.n_eff(np.full((1, 50), 1 / 50)), [50.0])
    assert_allclose(rpf.n_eff(np.array([[1.0, 0.0, 0.0]])), [1.0])
    assert_allclose(rpf.n_eff(np.array([[0.5, 0.5, 0.0, 0.0]])), [2.0])


# --- resampling ------------------------------------------------------------------------------

def test_multinomial_resampling_counts_follow_the_weights(rng):
    w = np.array([0.5, 0.25, 0.125, 0.0625, 0.0625, 0.0])
    n = w.size
    runs = 20_000  # every row is an independent draw of n particles
    idx = rpf.multinomial_resample(np.tile(w, (runs, 1)), rng)
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
    idx = rpf.multinomial_resample(w, rng)
    assert (idx[0] == 2).all() and (idx[1] == 0).all() and (idx[2] == 3).all()


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=2, max_size=40).filter(lambda v: sum(v) > 1e-6),
       st.integers(0, 2**32 - 1))
def test_resampling_keeps_n_and_draws_only_weighted_particles(values, seed):
    w = np.array(values) / np.sum(values)
    idx = rpf.multinomial_resample(w[None], np.random.default_rng(seed))
    assert idx.shape == (1, w.size)
    assert (w[idx[0]] > 0).all()


# --- eq. 21: regularisation ------------------------------------------------------------------

def test_regularise_keeps_the_mean_and_inflates_the_covariance_by_h2_over_n_plus_4(rng):
    n, runs, d = 5000, 40, 4
    cov = np.array([[4e6, 1e6, 0, 0], [1e6, 1e6, 0, 0], [0, 0, 1.0, 0.2], [0, 0, 0.2, 0.5]])
    chol = np.linalg.cholesky(cov)
    state = np.einsum("ij,jrn->irn", chol, rng.standard_normal((d, runs, n)))
    state += np.array([5000.0, 800.0, -1.0, -2.0])[:, None, None]
    w = np.full((runs, n), 1.0 / n)
    new = rpf.regularise(state, w, rng)
    h = rpf.optimal_bandwidth(n, d)
    _, before = rpf.weighted_covariance(state, w)
    _, after = rpf.weighted_covariance(new, w)
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
    new = rpf.regularise(state, w, rng, shrink=True)
    _, before = rpf.weighted_covariance(state, w)
    _, after = rpf.weighted_covariance(new, w)
    # 40 runs x 5000 particles: the sampling error of a variance ratio is ~0.005; 0.02 is 4 sd
    assert_allclose(np.diag(after.mean(axis=0) / before.mean(axis=0)), 1.0, atol=0.02)
    shift = np.abs(new.mean(axis=(1, 2)) - state.mean(axis=(1, 2)))
    assert (shift < 5 * np.sqrt(np.diag(cov) / (n * runs))).all()


def test_regularise_of_a_degenerate_cloud_stays_finite(rng):
    state = np.ones((4, 2, 100))
    w = np.full((2, 100), 0.01)
    new = rpf.regularise(state, w, rng)
    assert np.isfinite(new).all()
    assert_allclose(new, 1.0, atol=1e-6)


# --- eqs. 29-30 ------------------------------------------------------------------------------

def test_estimate_is_the_weighted_mean_and_covariance(rng):
    state = rng.normal(size=(4, 1, 500))
    w = rng.random(500)
    w /= w.sum()
    mean, cov = rpf.estimate(state, w[None])
    assert_allclose(mean[:, 0], np.average(state[:, 0], axis=1, weights=w), rtol=1e-12)
    assert_allclose(cov[0], np.cov(state[:, 0], aweights=w, bias=True), rtol=1e-10, atol=1e-14)


# --- eqs. 4-6: motion model ------------------------------------------------------------------

def test_predict_without_noise_is_eq4(rng):
    x = np.array([5000.0, 800.0, -1.65, -1.97])
    obs_k = np.array([10.0, 20.0, 1.0, -2.0])
    obs_k1 = np.array([70.0, -100.0, 0.5, 0.5])
    state = np.tile(x[:, None, None], (1, 1, 3))
    rpf.predict(state, dt_s=60.0, obs_k=obs_k, obs_k1=obs_k1, sigma_a_mps2=0.0, rng=rng)
    f = np.array([[1, 0, 60, 0], [0, 1, 0, 60], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    assert_allclose(state[:, 0, 0], f @ (x + obs_k) - obs_k1, rtol=1e-12)


def test_process_noise_covariance_is_sigma_a2_gamma_gamma_t(rng):
    dt, sa = 60.0, 1.5e-3
    state = np.zeros((4, 1, 400_000))
    zero = np.zeros(4)
    rpf.predict(state, dt_s=dt, obs_k=zero, obs_k1=zero, sigma_a_mps2=sa, rng=rng)
    gamma = np.array([[dt * dt / 2, 0], [0, dt * dt / 2], [dt, 0], [0, dt]])
    expected = sa ** 2 * gamma @ gamma.T
    # sampling sd of a covariance entry: sqrt((s_ii s_jj + s_ij^2) / n); allow 5 sd (a zero
    # entry, x with y, has sd 7.3 / sqrt(400000) = 0.012)
    n = state.shape[2]
    sd = np.sqrt((np.outer(np.diag(expected), np.diag(expected)) + expected ** 2) / n)
    assert (np.abs(np.cov(state[:, 0]) - expected) < 5 * sd).all()


# --- eqs. 9, 12, 16, 32-33: measurements ------------------------------------------------------

def test_bearing_is_clockwise_from_north_and_residual_wraps():
    assert_allclose(np.degrees(rpf.bearing_rad(1.0, 0.0)), 90.0)
    assert_allclose(np.degrees(rpf.bearing_rad(0.0, -1.0)), 180.0)
    state = np.zeros((4, 1, 1))
    state[0], state[1] = math.sin(math.radians(1.0)), math.cos(math.radians(1.0))
    ll = rpf.bearing_loglik(state, math.radians(359.0), math.radians(1.0))
    assert_allclose(ll[0, 0], -0.5 * 2.0 ** 2, rtol=1e-9)  # 2 deg apart, not 358


def test_predicted_level_uses_each_particles_target_speed():
    state = np.zeros((4, 1, 2))
    state[0] = [3000.0, 4000.0]  # ranges 3000 and 4000 m
    state[2] = [2.0, 4.14]       # relative vx; the observer adds 1 m/s east
    k = lambda r: -20.0 * np.log10(r)  # noqa: E731 - spherical spreading as K(r)
    level = rpf.predicted_level_db(state, [1.0, 0.0], k)
    expected = 170 + 53 * np.log10(np.array([3.0, 5.14]) / 5.14) - 20 * np.log10([3000.0, 4000.0])
    assert_allclose(level[0], expected, atol=1e-9)
    ll = rpf.level_loglik(state, expected[0], [1.0, 0.0], k, 10.0)
    assert_allclose(ll[0, 0], 0.0, atol=1e-12)
    assert ll[0, 1] < -0.1


def test_initial_particles_follow_the_prior(rng):
    cfg = rpf.RpfConfig()
    state = rpf.initial_particles(math.radians(80.0), [0.0, 0.0], cfg, 2, rng)
    r = np.hypot(state[0], state[1])
    assert_allclose(r.mean(), 10_000.0, atol=50.0)
    assert_allclose(r.std(), 2000.0, atol=50.0)
    b = np.degrees(rpf.bearing_rad(state[0], state[1]))
    assert_allclose(b.mean(), 80.0, atol=0.05)
    assert_allclose(b.std(), 1.5, atol=0.05)
    # speed N(s, sd) on course N(z0 + pi, sd_c): E[v] = s * exp(-sd_c^2 / 2) along z0 + pi
    shrink = math.exp(-0.5 * math.radians(cfg.course_sd_deg) ** 2)
    c = math.radians(260.0)
    assert_allclose(state[2].mean(), cfg.speed_mean_mps * shrink * math.sin(c), atol=0.02)
    assert_allclose(state[3].mean(), cfg.speed_mean_mps * shrink * math.cos(c), atol=0.02)


def test_run_batch_is_deterministic_given_the_seed():
    t = np.arange(0.0, 600.0, 60.0)
    obs = np.zeros((t.size, 4))
    b = np.full((2, t.size), math.radians(80.0))
    cfg = rpf.RpfConfig(n_particles=300)
    a = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None,
                      k_profiles=None, cfg=cfg, rng=np.random.default_rng(7))
    c = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None,
                      k_profiles=None, cfg=cfg, rng=np.random.default_rng(7))
    assert_allclose(a.mean, c.mean, rtol=0, atol=0)
    assert a.mean.shape == (2, t.size, 4) and a.cov.shape == (2, t.size, 4, 4)


def test_config_rejects_bad_values():
    with pytest.raises(ValueError, match="n_particles"):
        rpf.RpfConfig(n_particles=1)
    with pytest.raises(ValueError, match="level_sigma_db"):
        rpf.RpfConfig(level_sigma_db=0.0)
