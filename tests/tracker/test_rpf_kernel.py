"""The compiled fused cycle loop (tracker.rpf_kernel) against the numpy reference (tracker.rpf):
each piece on fixed particles and noise, the random draws by their distributions, and the
whole filter by its RMSE curves."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy import stats

from tracker import rpf
from tracker.rpf import config
from tracker import rpf_kernel as kern
from tracker.idm_experiment import simulate
from tracker.idm_scenarios import get_scenario
from tracker.tables import BEYOND_GRID_PENALTY_DB, LevelProfile

RTOL = 1e-9  # the brief's bar for the exact pieces; both sides are double precision


def _particles(rng, n=4000, d=4):
    s = np.empty((d, n))
    s[0] = rng.normal(3000.0, 4000.0, n)
    s[1] = rng.normal(-2000.0, 4000.0, n)
    s[2] = rng.normal(0.5, 2.0, n)
    s[3] = rng.normal(-1.0, 2.0, n)
    if d > 4:
        s[4] = rng.normal(0.0, 3.0, n)
    return s


def _profile(uniform=False):
    r = np.linspace(100.0, 20_000.0, 60 if not uniform else 400)
    if not uniform:
        r[10:] += 37.0  # not uniform: the index guess must walk (`k_at`)
    return LevelProfile(range_m=r, k_db=-20.0 * np.log10(r) - 1e-4 * r + 5.0 * np.sin(r / 900.0))


# --- random numbers --------------------------------------------------------------------------

def test_generator_is_seeded_per_run_and_reproducible():
    a = kern.seed_states(np.random.default_rng(3), 5)
    b = kern.seed_states(np.random.default_rng(3), 5)
    assert a.dtype == np.uint64 and a.shape == (5, 4)
    assert_allclose(a.astype(float), b.astype(float), rtol=0, atol=0)
    u = kern.uniforms(a[0].copy(), 200_000)
    assert 0.0 <= u.min() and u.max() < 1.0
    assert stats.kstest(u, "uniform").pvalue > 1e-3
    assert not np.array_equal(kern.uniforms(a[0].copy(), 10), kern.uniforms(a[1].copy(), 10))


def test_ziggurat_layers_have_equal_areas():
    # Marsaglia & Tsang's 256-layer table: each layer x_i (f(x_(i+1)) - f(x_i)) is v
    x, f = kern.ZIGGURAT_X, kern.ZIGGURAT_F
    areas = x[1:-1] * (f[2:] - f[1:-1])
    assert_allclose(areas, 0.00492867323399, rtol=1e-8)  # v to its 12 printed digits


def test_ziggurat_normals_are_standard_normal():
    g = kern.normals(kern.seed_states(np.random.default_rng(1), 1)[0], 500_000)
    assert stats.kstest(g, "norm").pvalue > 1e-3
    assert_allclose([g.mean(), g.var()], [0.0, 1.0], atol=0.006)  # 4.5 standard errors
    # the tail beyond r = 3.654 comes from the separate tail sampler: 2 (1 - Phi(r)) = 2.58e-4,
    # so ~258 of 1e6 draws (Poisson sd 16)
    tail = np.sum(np.abs(g) > kern.ZIGGURAT_R)
    assert abs(tail - 1e6 * 2 * stats.norm.sf(kern.ZIGGURAT_R)) < 5 * 16
    assert stats.kstest(np.abs(g[np.abs(g) > 2.5]) - 2.5,
                        lambda x: 1 - stats.norm.sf(x + 2.5) / stats.norm.sf(2.5)).pvalue > 1e-3


def test_fused_noise_fill_is_the_same_stream_as_normal():
    s = kern.seed_states(np.random.default_rng(7), 1)[0]
    gx, gy = kern.normal_pairs_filled(s.copy(), 100_000)
    g = kern.normals(s.copy(), 100_000)
    # the same draws; a tail value may differ by an ulp (FMA contraction differs by inlining)
    assert_allclose(gx, g[0::2], rtol=1e-15, atol=0)
    assert_allclose(gy, g[1::2], rtol=1e-15, atol=0)
    e = kern.exponentials_filled(s.copy(), 100_000)
    assert_allclose(e, kern.exponentials(s.copy(), 100_000), rtol=1e-15, atol=0)


def test_ziggurat_exponentials_are_standard_exponential():
    x, f = kern.ZIGGURAT_EXP_X, kern.ZIGGURAT_EXP_F
    assert_allclose(x[1:-1] * (f[2:] - f[1:-1]), 0.0039496598225815571993, rtol=1e-8)
    e = kern.exponentials(kern.seed_states(np.random.default_rng(6), 1)[0], 500_000)
    assert e.min() >= 0.0
    assert stats.kstest(e, "expon").pvalue > 1e-3
    assert_allclose([e.mean(), e.var()], [1.0, 1.0], atol=0.012)  # ~4 standard errors
    # beyond r = 7.697 (probability 4.5e-4, ~226 draws, Poisson sd 15) the tail is r + E
    tail = e[e > kern.ZIGGURAT_EXP_R]
    assert abs(tail.size - 5e5 * math.exp(-kern.ZIGGURAT_EXP_R)) < 5 * 15
    assert stats.kstest(tail - kern.ZIGGURAT_EXP_R, "expon").pvalue > 1e-3


@pytest.mark.parametrize("d", [4, 5])
def test_epanechnikov_draws_follow_the_kernel(d):
    eps = kern.epanechnikov_draws(kern.seed_states(np.random.default_rng(2), 1)[0], d, 200_000)
    r2 = np.einsum("ni,ni->n", eps, eps)
    assert r2.max() < 1.0
    assert stats.kstest(r2, stats.beta(d / 2, 2).cdf).pvalue > 1e-3  # eq. 26
    assert_allclose(np.cov(eps.T), np.eye(d) / (d + 4), atol=0.003)


def test_multinomial_resampling_counts_follow_the_weights():
    w = np.array([0.5, 0.25, 0.125, 0.0625, 0.0625, 0.0])
    s = kern.seed_states(np.random.default_rng(4), 1)[0]
    idx = np.concatenate([kern.resample_draw(w, s) for _ in range(20_000)])
    total = np.bincount(idx, minlength=w.size)
    assert total[-1] == 0
    expected = idx.size * w[:-1]
    assert ((total[:-1] - expected) ** 2 / expected).sum() < stats.chi2(4).ppf(0.999)
    one = kern.resample_draw(w, s)
    assert np.all(np.diff(one) >= 0)  # sorted, as rpf.multinomial_resample


# --- exact pieces on fixed particles and noise -----------------------------------------------

def test_atan2_and_exp_match_the_library():
    rng = np.random.default_rng(5)
    y = rng.standard_normal(100_000) * 10.0 ** rng.uniform(-8, 4, 100_000)
    x = rng.standard_normal(100_000) * 10.0 ** rng.uniform(-8, 4, 100_000)
    a = kern.bearing_loglik_arrays(np.stack([y, x, x, x]), 0.0, math.sqrt(0.5))  # -atan2^2
    assert_allclose(np.sqrt(-a), np.abs(np.arctan2(y, x)), rtol=1e-14, atol=1e-300)
    log_w = -rng.random(10_000) * 700.0
    w = np.empty_like(log_w)
    kern.normalise_run(log_w.copy(), w)
    top = log_w.max()
    assert_allclose(w, np.exp(log_w - top) / np.exp(log_w - top).sum(), rtol=1e-13,
                    atol=1e-300)


def test_prediction_matches_eq4_and_rpf_predict():
    rng = np.random.default_rng(6)
    state = _particles(rng)
    obs_k, obs_k1 = np.array([100.0, -50.0, 2.0, 1.5]), np.array([220.0, 40.0, 1.0, 2.5])
    dt, sa = 60.0, 1.5e-3
    # the noise rpf.predict draws from this seed (its first call of standard_normal_pairs)
    nu = rpf.standard_normal_pairs(state.shape[1:], np.random.default_rng(8))
    gx, gy = nu[0].astype(float), nu[1].astype(float)
    ref = state.copy()
    rpf.predict(ref, dt_s=dt, obs_k=obs_k, obs_k1=obs_k1, sigma_a_mps2=sa,
                rng=np.random.default_rng(8))
    got = state.copy()
    kern.predict_arrays(got, gx, gy, dt, dt * sa, obs_k[0] + dt * obs_k[2] - obs_k1[0],
                        obs_k[1] + dt * obs_k[3] - obs_k1[1], obs_k[2] - obs_k1[2],
                        obs_k[3] - obs_k1[3])
    # eq. 4 in float64: absolute target state advanced by F and G nu, minus the new observer
    dv = np.stack([gx, gy]) * dt * sa
    tgt = state[:4] + obs_k[:, None]
    expect = np.empty_like(tgt)
    expect[:2] = tgt[:2] + dt * tgt[2:] + 0.5 * dt * dv
    expect[2:] = tgt[2:] + dv
    expect -= obs_k1[:, None]
    assert_allclose(got[:2], expect[:2], rtol=RTOL)
    assert_allclose(got[2:], expect[2:], rtol=RTOL, atol=1e-12)
    # rpf.predict scales the float32 noise in float32: agreement to float32 rounding of dv
    assert_allclose(got, ref, rtol=0, atol=dt * 1e-7 * np.abs(dv).max())


def test_bearing_loglik_matches_rpf():
    rng = np.random.default_rng(9)
    state = _particles(rng)
    for z in (0.3, -2.9, math.pi):  # the last wraps most residuals through +-pi
        ref = rpf.bearing_loglik(state, z, math.radians(1.5))
        got = kern.bearing_loglik_arrays(state, z, math.radians(1.5))
        assert_allclose(got, ref, rtol=RTOL, atol=1e-12)


@pytest.mark.parametrize("uniform", [False, True])
def test_k_profile_follows_level_profile_rule(uniform):
    p = _profile(uniform)
    r = np.concatenate([np.random.default_rng(10).uniform(0.0, 25_000.0, 20_000), p.range_m,
                        [0.0, p.range_m[-1] + 1e-6, np.nextafter(p.range_m[-1], np.inf)]])
    got = kern.k_at_arrays(r, p.range_m, p.k_db)
    assert_allclose(got, p(r), rtol=RTOL, atol=1e-12)
    beyond = r > p.range_m[-1]
    assert_allclose(got[beyond], p.k_db[-1] - BEYOND_GRID_PENALTY_DB, rtol=1e-12)


@pytest.mark.parametrize("uniform", [False, True])
@pytest.mark.parametrize("model", ["ross", "p0"])
@pytest.mark.parametrize("d", [4, 5])
def test_level_loglik_matches_rpf(model, d, uniform):
    rng = np.random.default_rng(11)
    state = _particles(rng, d=d)
    state[:2] *= 2.0  # out to ~30 km: some beyond the 20 km range axis
    state[2, :50] = -1.2  # target speed below 0.01 m/s: held at it
    state[3, :50] = 2.0
    p = _profile(uniform)
    obs_vel = np.array([1.2, -2.0])
    p0 = 131.5 if model == "p0" else math.nan
    ref = rpf.level_loglik(state, 95.0, obs_vel, p, 10.0, source_level_model=model, p0_db=p0)
    got = kern.level_loglik_arrays(state, 95.0, obs_vel[0], obs_vel[1], model == "ross", p0,
                                   p.range_m, p.k_db, 10.0)
    assert_allclose(got, ref, rtol=RTOL)
    assert np.any(ref < -4000)  # some particles beyond the grid: the penalty is exercised


def test_weights_neff_and_moments_match_rpf():
    rng = np.random.default_rng(12)
    state = _particles(rng, d=5)
    log_w = -0.5 * rng.chisquare(3, state.shape[1]) * 4.0 - 1e5
    ref_lw, ref_w = rpf.normalise_exp(log_w[None].copy())
    lw, w = log_w.copy(), np.empty_like(log_w)
    neff = kern.normalise_run(lw, w)
    assert_allclose(lw, ref_lw[0], rtol=RTOL)
    assert_allclose(w, ref_w[0], rtol=RTOL)
    assert_allclose(neff, rpf.n_eff(ref_w)[0], rtol=RTOL)
    mean, cov = np.empty(5), np.empty((5, 5))
    kern.moments_run(state, w, mean, cov)
    ref_mean, ref_cov = rpf.estimate(state[:, None], ref_w)
    assert_allclose(mean, ref_mean[:, 0], rtol=RTOL)
    assert_allclose(cov, ref_cov[0], rtol=RTOL)
    four_m, four_c = np.empty(4), np.empty((4, 4))  # the unrolled 4-state covariance
    kern.moments_run(np.ascontiguousarray(state[:4]), w, four_m, four_c)
    assert_allclose(four_c, ref_cov[0, :4, :4], rtol=RTOL)


@pytest.mark.parametrize("shrink", [False, True])
def test_regularisation_step_is_eq21(shrink):
    rng = np.random.default_rng(13)
    state = _particles(rng, n=500)
    w = rng.random(500)
    w /= w.sum()
    mean, cov, chol = np.empty(4), np.empty((4, 4)), np.empty((4, 4))
    kern.moments_run(state, w, mean, cov)
    kern.cholesky_loaded(cov, chol)
    load = 1e-12 * cov.diagonal().max() + 1e-18
    assert_allclose(chol, np.linalg.cholesky(cov + load * np.eye(4)), rtol=RTOL, atol=1e-12)
    idx = np.sort(rng.integers(0, 500, 500))
    eps = rng.uniform(-0.5, 0.5, (500, 4))
    h = rpf.optimal_bandwidth(500, 4)
    new = np.empty_like(state)
    kern.regularise_run(state, idx, mean, chol, np.ascontiguousarray(eps.T), h, shrink, new)
    base = state[:, idx]
    if shrink:
        a = math.sqrt(1.0 - h * h / 8.0)
        base = mean[:, None] + a * (base - mean[:, None])
    assert_allclose(new, base + h * chol @ eps.T, rtol=RTOL)


def test_prior_particles_match_rpf_initial_particles():
    cfg = rpf.RpfConfig(n_particles=3000)
    ref = rpf.initial_particles(0.7, [1.0, -2.0], cfg, 1, np.random.default_rng(14))[:, 0]
    g = np.random.default_rng(14).standard_normal((4, 1, 3000))[:, 0]
    prior = np.array([cfg.range_mean_m, cfg.range_sd_m, math.radians(cfg.bearing_sigma_deg),
                      cfg.speed_mean_mps, cfg.speed_sd_mps, math.radians(cfg.course_sd_deg)])
    got = kern.init_arrays(np.ascontiguousarray(g), 0.7, 1.0, -2.0, prior)
    assert_allclose(got, ref, rtol=RTOL, atol=1e-9)


# --- the whole filter ------------------------------------------------------------------------

def _batch(engine, monkeypatch, *, runs, n, levels, seed, threads=1, shrink=False):
    monkeypatch.setattr(config, "ENGINE", engine)
    sc = get_scenario("idm-static")
    p = _profile(uniform=shrink)  # both K(r) paths of the kernel: the walk and the uniform axis
    t = sc.t_s
    obs = sc.observer_state(t)
    rel = sc.target_state(t) - obs
    b, lv = simulate(sc, p, runs, np.random.default_rng(100))  # same measurements for both
    cfg = rpf.RpfConfig(n_particles=n, shrink=shrink)
    res = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b,
                        level_db_meas=lv if levels else None, k_profiles=[p] * t.size, cfg=cfg,
                        rng=np.random.default_rng(seed), threads=threads)
    err = np.hypot(res.mean[:, :, 0] - rel[None, :, 0], res.mean[:, :, 1] - rel[None, :, 1])
    return res, err


def test_kernel_is_the_default_and_independent_of_threads(monkeypatch):
    assert config.ENGINE == "kernel"
    a, _ = _batch("kernel", monkeypatch, runs=9, n=500, levels=True, seed=3, threads=1)
    b, _ = _batch("kernel", monkeypatch, runs=9, n=500, levels=True, seed=3, threads=2)
    c, _ = _batch("kernel", monkeypatch, runs=9, n=500, levels=True, seed=4, threads=1)
    assert_allclose(a.mean, b.mean, rtol=0, atol=0)
    assert_allclose(a.cov, b.cov, rtol=0, atol=0)
    assert np.array_equal(a.resampled, b.resampled)
    assert not np.allclose(a.mean, c.mean)


@pytest.mark.slow
@pytest.mark.parametrize("levels, shrink", [(False, False), (True, False), (True, True)])
def test_rmse_curves_agree_with_the_numpy_reference(levels, shrink, monkeypatch):
    # 100 runs, N = 1000 on idm-static (bearings only, and bearings + SPL with a synthetic
    # K(r)), the same measurements for both engines. The RMSE's Monte Carlo standard error is
    # sd(e^2) / (2 RMSE sqrt(R)) (delta method); the two curves are independent estimates, so
    # their difference is within 4 combined standard errors at each checked cycle unless the
    # statistics differ (4 sd: ~1e-3 false-alarm risk over the 6 checked cycles).
    runs = 100
    res_k, err_k = _batch("kernel", monkeypatch, runs=runs, n=1000, levels=levels, seed=21,
                          shrink=shrink)
    res_n, err_n = _batch("numpy", monkeypatch, runs=runs, n=1000, levels=levels, seed=22,
                          shrink=shrink)
    for k in (10, 30, 60, 90, 120, 150):
        rm_k, rm_n = (np.sqrt(np.mean(e[:, k] ** 2)) for e in (err_k, err_n))
        se = math.hypot(*(np.std(e[:, k] ** 2) / (2 * np.sqrt(np.mean(e[:, k] ** 2))
                                                  * math.sqrt(runs)) for e in (err_k, err_n)))
        assert abs(rm_k - rm_n) < 4 * se, (k, rm_k, rm_n, se)
    # resampling fraction: per-run fractions' standard error, same 4-sd rule
    fk, fn = (r.resampled[:, 1:].mean(axis=1) for r in (res_k, res_n))
    se = math.hypot(fk.std(), fn.std()) / math.sqrt(runs)
    assert abs(fk.mean() - fn.mean()) < 4 * se + 1e-3
    # the filters' own spread: mean position sd at the end within 15 % (a systematic
    # difference in the regularization would show here first)
    sd_k, sd_n = (np.sqrt(r.cov[:, -1, 0, 0] + r.cov[:, -1, 1, 1]).mean() for r in (res_k, res_n))
    assert abs(sd_k / sd_n - 1) < 0.15, (sd_k, sd_n)


def test_summaries_match_rpf_particle_sds():
    rng = np.random.default_rng(15)
    state = _particles(rng)
    w = rng.random(state.shape[1])
    w /= w.sum()
    ref = rpf.particle_sds(state[:, None], w[None], [1.0, -0.5])[0]
    assert_allclose(kern.summaries_arrays(state, w, 1.0, -0.5), ref, rtol=RTOL)


def test_track_summaries_and_missing_bearings(monkeypatch):
    monkeypatch.setattr(config, "ENGINE", "kernel")
    t = np.arange(0.0, 600.0, 60.0)
    obs = np.zeros((t.size, 4))
    obs[:, 2] = 2.0
    obs[:, 0] = 2.0 * t
    b = np.full((1, t.size), math.radians(80.0))
    b[0, 3] = np.nan  # a cycle without a bearing: prediction alone
    res = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None,
                        k_profiles=None, cfg=rpf.RpfConfig(n_particles=400),
                        rng=np.random.default_rng(1), summaries=True)
    sd = res.extra["sd"]
    assert sd.shape == (1, t.size, 3) and np.all(np.isfinite(sd))
    assert np.all(np.isfinite(res.mean)) and np.all(np.isfinite(res.cov))
