"""The one level likelihood (`tracker.levels`): the Kalman filter's density of the levels with the
persistent and along-track errors integrated out is the Gaussian density of the stacked levels,
and the particle filter's per-particle filter (`tracker.rpf.kernel.levelerrors`) is the same."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.stats import multivariate_normal

from tracker.levels import Component, LevelErrors, log_marginal, path_steps_m


def _stacked_covariance(errors: LevelErrors, var_n, t_s, pos_m, d_m, n_bands):
    """The covariance of every cycle's and band's level error written out from the model's
    definition: each component's covariance between cycles i <= j is its variance at i times its
    correlation exp(-|t_j - t_i| / time - s_ij / length), s_ij the path's length between them;
    an offset's (growth by independent increments) is its variance at the earlier cycle."""
    t_n = len(t_s)
    seg = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(pos_m[:, 0]), np.diff(pos_m[:, 1])))])
    cov = np.zeros((t_n * n_bands, t_n * n_bands))
    for c in errors.components:
        var = c.sd_db ** 2 + (c.growth_db_per_km * np.asarray(d_m) / 1000.0) ** 2
        bands = range(n_bands) if c.band < 0 else [c.band]
        for i in range(t_n):
            for j in range(t_n):
                lo = min(i, j)
                if c.persistent:
                    cij = var[lo]
                else:
                    decay = 0.0
                    if c.time_s is not None:
                        decay += abs(t_s[j] - t_s[i]) / c.time_s
                    if c.length_m is not None:
                        decay += abs(seg[j] - seg[i]) / c.length_m
                    # a residual's variance is raised at each cycle, so its covariance carries the
                    # earlier cycle's variance forward
                    cij = var[lo] * math.exp(-decay)
                for a in bands:
                    for b in bands:
                        cov[i * n_bands + a, j * n_bands + b] += cij
    cov += np.diag(np.asarray(var_n, dtype=float).ravel())
    return cov


@pytest.mark.parametrize("n_bands", [1, 3])
def test_the_kalman_density_is_the_stacked_gaussian(n_bands):
    rng = np.random.default_rng(4)
    t_n = 12
    t = np.arange(t_n) * 20.0
    pos = np.cumsum(rng.uniform(20.0, 90.0, (t_n, 2)), axis=0)
    d = np.zeros(t_n)                                   # no growth: the residuals are stationary
    errors = LevelErrors.tracking(offset_sd_db=2.5, band_offset_sd_db=0.8, residual_sd_db=1.9,
                                  band_residual_sd_db=0.6, residual_length_m=400.0, residual_time_s=300.0,
                                  n_bands=n_bands)
    var_n = rng.uniform(0.8, 1.5, (t_n, n_bands))
    e = rng.normal(0.0, 3.0, (t_n, n_bands))
    ll = log_marginal(e, var_n, errors, t_s=t, step_m=path_steps_m(pos[:, 0], pos[:, 1]), displacement_m=d)
    cov = _stacked_covariance(errors, var_n, t, pos, d, n_bands)
    want = multivariate_normal(np.zeros(t_n * n_bands), cov).logpdf(e.ravel())
    assert_allclose(ll[-1], want, rtol=0, atol=1e-9)


def test_a_growing_offset_adds_independent_increments():
    # one band, an offset whose sd grows with the observer's distance: the stacked covariance
    # between cycles is the variance at the earlier one
    t_n = 8
    d = np.linspace(0.0, 5000.0, t_n)
    errors = LevelErrors(components=(Component(sd_db=2.0, growth_db_per_km=1.3),))
    e = np.linspace(-3.0, 4.0, t_n)[:, None]
    ll = log_marginal(e, np.ones((t_n, 1)), errors, displacement_m=d)
    cov = _stacked_covariance(errors, np.ones(t_n), np.zeros(t_n), np.zeros((t_n, 2)), d, 1)
    assert_allclose(ll[-1], multivariate_normal(np.zeros(t_n), cov).logpdf(e.ravel()), rtol=0, atol=1e-9)


def test_a_missing_level_adds_nothing():
    errors = LevelErrors.tracking(offset_sd_db=3.0)
    e = np.array([[1.0], [np.nan], [2.0]])
    ll = log_marginal(e, np.ones((3, 1)), errors)
    assert ll[1] == ll[0] and ll[2] < ll[1]


def test_the_particles_filter_is_the_same(monkeypatch):
    # the compiled per-particle Kalman filter along one path gives log_marginal's density (with the
    # constants the filter's weights leave out added back), the path's steps as the run's
    # estimate gives them
    from tracker.rpf.kernel.levelerrors import errors_gain, errors_init, errors_predict, errors_update_particle
    from tracker.rpf.kernel.params import errors_of

    rng = np.random.default_rng(7)
    t_n = 30
    t = np.arange(t_n) * 10.0
    step = rng.uniform(30.0, 80.0, t_n)
    d = np.linspace(0.0, 3000.0, t_n)
    errors = LevelErrors.tracking(offset_sd_db=2.9, residual_sd_db=1.9, residual_length_m=600.0,
                                  offset_growth_db_per_km=1.33, residual_growth_db_per_km=1.37)
    e = rng.normal(0.0, 4.0, (t_n, 1))
    e[5] = np.nan
    want = log_marginal(e, np.full((t_n, 1), 1.21), errors, t_s=t, step_m=step, displacement_m=d)
    arrays = errors_of(errors, 1, t_n, d)
    s = arrays.h.shape[1]
    mean, cov = np.zeros((s, 1)), np.zeros((s, s))
    rho, ph, gain = np.ones(s), np.empty(s), np.empty(s)
    errors_init(mean, cov, arrays.var[0])
    total, got = 0.0, []
    for k in range(t_n):
        if k > 0:
            errors_predict(mean, cov, t[k] - t[k - 1], step[k], arrays.inv_time_s, arrays.inv_length_m,
                           arrays.var[k - 1], arrays.var[k], rho)
        if np.isfinite(e[k, 0]):
            var = errors_gain(cov, arrays.h[0], 1.21, ph, gain)
            total += (errors_update_particle(mean, 0, arrays.h[0], e[k, 0], gain, 0.5 / var)
                      - 0.5 * math.log(2 * math.pi * var))
        got.append(total)
    assert_allclose(got, want, rtol=0, atol=1e-9)


def test_the_models_parts_need_a_scale():
    with pytest.raises(ValueError, match="correlation length or time"):
        LevelErrors.tracking(offset_sd_db=1.0, residual_sd_db=1.0)
    with pytest.raises(ValueError, match=">= 0 dB"):
        Component(sd_db=-1.0)
