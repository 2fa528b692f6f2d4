"""The depth likelihood with the errors that persist integrated out, and the posterior over depth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.stats import multivariate_normal

from tracker.depth.errors import LevelErrors, log_marginal
from tracker.depth.posterior import SUBMERGED_MIN_M, SURFACE_MAX_M, posterior

ERR = LevelErrors(offset_sd_db=3.0)


def _covariance(idx, t_s, v, err):
    """The levels' covariance the model says, term by term (module docstring of tracker.depth.errors)."""
    n = len(idx)
    c = np.zeros((n, n))
    for a, (t, m) in enumerate(idx):
        for b, (u, k) in enumerate(idx):
            dt = abs(t_s[t] - t_s[u])
            fine, slow = math.exp(-dt / err.fine_time_s), math.exp(-dt / err.slow_time_s)
            c[a, b] = err.offset_sd_db ** 2 + err.fine_sd_db ** 2 * fine + err.slow_sd_db ** 2 * slow
            if m == k:
                c[a, b] += err.band_sd_db ** 2 + err.fine_band_sd_db ** 2 * fine
            if a == b:
                c[a, b] += v[t, m]
    return c


def test_the_kalman_filter_is_the_models_gaussian_density():
    rng = np.random.default_rng(0)
    t_n, m_n = 12, 3
    t_s = np.cumsum(rng.uniform(5.0, 90.0, t_n))
    e, v = rng.normal(0.0, 3.0, (t_n, m_n)), rng.uniform(0.3, 2.0, (t_n, m_n))
    e[4, 1] = np.nan  # a band without a level
    e[7] = np.nan     # a cycle without any
    ll = log_marginal(e, v, t_s, ERR)
    idx = [(t, m) for t in range(t_n) for m in range(m_n) if np.isfinite(e[t, m])]
    y = np.array([e[t, m] for t, m in idx])
    c = _covariance(idx, t_s, v, ERR)
    assert_allclose(ll[-1], multivariate_normal(np.zeros(len(y)), c).logpdf(y), rtol=1e-10)
    first = [i for i, (t, _) in enumerate(idx) if t <= 5]  # after cycle 5: its cycles only
    assert_allclose(ll[5], multivariate_normal(np.zeros(len(first)), c[np.ix_(first, first)]).logpdf(y[first]),
                    rtol=1e-10)
    assert ll[7] == ll[6]


def test_fine_errors_that_grow_with_the_observers_distance_are_the_models_density():
    # the observer moving away from the tables' origin: b's, g's, f_m's and c_m's variance at a cycle
    # is sd^2 + (growth d)^2, and two cycles share the earlier one's (g and f_m forget it over
    # fine_time_s)
    err = LevelErrors(offset_sd_db=3.0, fine_growth_db_per_km=1.9, fine_band_growth_db_per_km=0.75,
                      band_growth_db_per_km=0.4, offset_growth_db_per_km=1.3)
    rng = np.random.default_rng(2)
    t_n, m_n = 10, 3
    t_s = np.cumsum(rng.uniform(5.0, 60.0, t_n))
    d_m = np.sort(rng.uniform(0.0, 5000.0, t_n))
    e, v = rng.normal(0.0, 4.0, (t_n, m_n)), rng.uniform(0.3, 2.0, (t_n, m_n))
    ll = log_marginal(e, v, t_s, err, d_m)
    idx = [(t, m) for t in range(t_n) for m in range(m_n)]
    c = np.zeros((len(idx), len(idx)))
    for a, (t, m) in enumerate(idx):
        for b, (u, k) in enumerate(idx):
            dt, first = abs(t_s[t] - t_s[u]), min(t, u)
            fine = math.exp(-dt / err.fine_time_s)
            # b's variance grows as c_m's does, its increments kept
            c[a, b] = (err.offset_sd_db ** 2 + (err.offset_growth_db_per_km * d_m[first] / 1e3) ** 2
                       + err.slow_sd_db ** 2 * math.exp(-dt / err.slow_time_s)
                       + fine * (err.fine_sd_db ** 2 + (err.fine_growth_db_per_km * d_m[first] / 1e3) ** 2))
            if m == k:  # c_m's variance grows too, its increments kept (a random walk)
                c[a, b] += err.band_sd_db ** 2 + (err.band_growth_db_per_km * d_m[first] / 1e3) ** 2
                c[a, b] += fine * (err.fine_band_sd_db ** 2
                                                         + (err.fine_band_growth_db_per_km * d_m[first] / 1e3) ** 2)
            if a == b:
                c[a, b] += v[t, m]
    y = np.array([e[t, m] for t, m in idx])
    assert_allclose(ll[-1], multivariate_normal(np.zeros(len(y)), c).logpdf(y), rtol=1e-10)
    # at the origin all along: the fine errors of the tables where they were computed
    assert_allclose(log_marginal(e, v, t_s, err, np.zeros(t_n)), log_marginal(e, v, t_s, ERR), rtol=1e-12)


def test_a_band_ratio_far_from_the_tables_origin_says_less():
    # a band 6 dB off the others, the observer at the origin or 4 km from it all along
    t_s = 10.0 * np.arange(60)
    v = np.full((60, 3), 0.04)
    noise = np.random.default_rng(1).normal(0.0, 0.2, (60, 3))
    err = LevelErrors(offset_sd_db=3.0, fine_growth_db_per_km=1.9, fine_band_growth_db_per_km=0.75)
    shift = np.array([6.0, 0.0, 0.0])

    def diff(d_m):
        return (log_marginal(noise, v, t_s, err, np.full(60, d_m))[-1]
                - log_marginal(noise - shift, v, t_s, err, np.full(60, d_m))[-1])

    assert diff(0.0) > 2.0 * diff(4000.0) > 0.0


def _ll_difference(shift_db, cycles):
    """ln L of the levels of depth A less that of depth B, whose K is A's plus ``shift_db`` (per
    band), along ``cycles`` 10 s cycles of levels from A with eq. 11's small error."""
    rng = np.random.default_rng(1)
    t_s = 10.0 * np.arange(cycles)
    noise = rng.normal(0.0, 0.2, (cycles, 3))
    v = np.full((cycles, 3), 0.04)
    return log_marginal(noise, v, t_s, ERR)[-1] - log_marginal(noise - shift_db, v, t_s, ERR)[-1]


def test_an_error_that_persists_is_counted_once():
    # a depth whose K differs by the same 2 dB in every band and cycle: an offset explains it,
    # however many cycles there are (within the offset's prior, a fraction of a nat)
    assert abs(_ll_difference(np.full(3, 2.0), 30)) < 0.5
    assert abs(_ll_difference(np.full(3, 2.0), 600) - _ll_difference(np.full(3, 2.0), 30)) < 0.1
    # one band 6 dB off the others (the surface's interference takes more from the low band):
    # no common offset explains it, the band offset (1 dB) and the fine errors hardly
    assert _ll_difference(np.array([6.0, 0.0, 0.0]), 30) > 5.0
    # and more cycles say more only as far as the fine error forgets (60 s), not cycle by cycle
    d30, d600 = _ll_difference(np.array([6.0, 0.0, 0.0]), 30), _ll_difference(np.array([6.0, 0.0, 0.0]), 600)
    assert d600 > d30 and d600 < 20.0 * d30


def test_posterior_quantiles_masses_and_sd():
    z = np.array([2.0, 10.0, 50.0, 100.0, 200.0, 300.0])
    span = (2.0, 300.0)
    flat = posterior(z, np.zeros(z.size), span, prior="uniform")  # uniform in depth over the span
    assert_allclose(flat.weight.sum(), 1.0)
    assert_allclose(flat.quantile(0.5), 151.0, atol=1e-9)
    assert_allclose([flat.quantile(0.05), flat.quantile(0.95)], [2.0 + 0.05 * 298, 300.0 - 0.05 * 298], atol=1e-9)
    surf, sub = flat.surface_probability()
    assert_allclose([surf, sub], [(SURFACE_MAX_M - 2.0) / 298.0, (300.0 - SUBMERGED_MIN_M) / 298.0], atol=1e-12)
    assert_allclose(flat.sd(), 298.0 / math.sqrt(12.0), rtol=1e-9)
    # a likelihood sure of 100 m: the mass sits in that depth's cell (75-150 m)
    sure = posterior(z, np.where(z == 100.0, 0.0, -50.0), span)
    assert 75.0 < sure.quantile(0.05) < sure.quantile(0.95) < 150.0
    assert sure.surface_probability()[1] == pytest.approx(1.0)


def test_the_default_prior_leaves_surface_or_submerged_open_when_the_levels_say_nothing():
    # a likelihood that says nothing gives the prior back: uniform in ln(z + 1 m), so that the
    # 90 % interval reaches from a surface ship to a deep submarine, and the surface-or-submerged
    # call is near even; a prior uniform in depth would call it submerged at 11 to 1
    z = np.array([2.0, 2.5, 5.0, 10.0, 20.0, 30.0, 50.0, 100.0, 200.0, 300.0])
    span = (2.0, 300.0)
    flat = posterior(z, np.zeros(z.size), span)
    assert flat.quantile(0.05) < 6.0 and flat.quantile(0.95) > 200.0
    surf, sub = flat.surface_probability()
    assert 0.7 < surf / sub < 1.2
    uni_surf, uni_sub = posterior(z, np.zeros(z.size), span, prior="uniform").surface_probability()
    assert uni_sub / uni_surf > 10.0
    # the mass within a cell follows the prior: the grid does not matter where the likelihood is flat
    fine = posterior(np.linspace(2.0, 300.0, 300), np.zeros(300), span)
    for q in (0.05, 0.5, 0.95):
        assert_allclose(flat.quantile(q), fine.quantile(q), rtol=1e-9)
    assert_allclose(flat.mean(), fine.mean(), rtol=1e-9)
    assert_allclose(flat.sd(), fine.sd(), rtol=1e-9)
    assert_allclose(flat.mass_between(10.0, 60.0), fine.mass_between(10.0, 60.0), rtol=1e-9)
    # a sampled check of the cells' moments: the posterior's mean and sd are those of its draws
    rng = np.random.default_rng(3)
    w = rng.dirichlet(np.ones(z.size))
    post = flat.at_cycle(w)
    cell = rng.choice(z.size, 400_000, p=w)
    u = rng.uniform(np.log(post.edges_m[cell] + 1.0), np.log(post.edges_m[cell + 1] + 1.0))
    draws = np.exp(u) - 1.0
    assert_allclose([post.mean(), post.sd()], [draws.mean(), draws.std()], rtol=5e-3)
    with pytest.raises(ValueError, match="prior"):
        posterior(z, np.zeros(z.size), span, prior="flat")
