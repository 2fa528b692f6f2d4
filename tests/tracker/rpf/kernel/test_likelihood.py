"""The kernel's bearing and level log-likelihoods (eqs. 32-33) and K(r) against the numpy
functions and the LevelProfile rule."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from tests.tracker.rpf.kernel.conftest import RTOL, particles, profile
from tests.tracker.rpf.kernel.wrappers import (
    bearing_loglik_arrays,
    k_at_arrays,
    level_loglik_arrays,
    level_loglik_sd_arrays,
)
from tracker.rpf.likelihood import bearing_loglik, level_loglik


def test_bearing_loglik_matches_rpf():
    rng = np.random.default_rng(9)
    state = particles(rng)
    for z in (0.3, -2.9, math.pi):  # the last wraps most residuals through +-pi
        ref = bearing_loglik(state, z, math.radians(1.5))
        got = bearing_loglik_arrays(state, z, math.radians(1.5))
        assert_allclose(got, ref, rtol=RTOL, atol=1e-12)


@pytest.mark.parametrize("uniform", [False, True])
def test_k_profile_follows_level_profile_rule(uniform):
    p = profile(uniform)
    r = np.concatenate([np.random.default_rng(10).uniform(0.0, 25_000.0, 20_000), p.range_m,
                        [0.0, p.range_m[-1] + 1e-6, np.nextafter(p.range_m[-1], np.inf)]])
    got = k_at_arrays(r, p.range_m, p.k_db)
    assert_allclose(got, p(r), rtol=RTOL, atol=1e-12)
    beyond = r > p.range_m[-1]
    assert_allclose(got[beyond], p.k_db[-1] - BEYOND_GRID_PENALTY_DB, rtol=1e-12)


@pytest.mark.parametrize("uniform", [False, True])
@pytest.mark.parametrize("model", ["ross", "p0"])
@pytest.mark.parametrize("d", [4, 5])
def test_level_loglik_matches_rpf(model, d, uniform):
    rng = np.random.default_rng(11)
    state = particles(rng, d=d)
    state[:2] *= 2.0  # out to ~30 km: some beyond the 20 km range axis
    state[2, :50] = -1.2  # target speed below 0.01 m/s: held at it
    state[3, :50] = 2.0
    p = profile(uniform)
    obs_vel = np.array([1.2, -2.0])
    p0 = 131.5 if model == "p0" else math.nan
    ref = level_loglik(state, 95.0, obs_vel, p, 10.0, source_level_model=model, p0_db=p0)
    got = level_loglik_arrays(state, 95.0, obs_vel[0], obs_vel[1], model == "ross", p0,
                              p.range_m, p.k_db, 10.0)
    assert_allclose(got, ref, rtol=RTOL)
    assert np.any(ref < -4000)  # some particles beyond the grid: the penalty is exercised


@pytest.mark.parametrize("uniform", [False, True])
def test_level_loglik_with_the_grids_k_error_sd_matches_rpf(uniform):
    import dataclasses

    rng = np.random.default_rng(12)
    state = particles(rng)
    base = profile(uniform)
    # a K error sd growing along range, 0.5 to 4 dB (a study's k_error_sd_db in the grid)
    p = dataclasses.replace(base, k_sd_db=np.linspace(0.5, 4.0, base.range_m.size))
    obs_vel = np.array([1.2, -2.0])
    ref = level_loglik(state, 95.0, obs_vel, p, 2.0)
    got = level_loglik_sd_arrays(state, 95.0, obs_vel[0], obs_vel[1], True, math.nan, p.range_m, p.k_db,
                                 p.k_sd_db, 2.0)
    assert_allclose(got, ref, rtol=RTOL, atol=1e-9)
    # the variance grew by sd(r)^2 at each particle's range: the same misfit costs less
    plain = level_loglik(state, 95.0, obs_vel, base, 2.0)
    r = np.hypot(state[0], state[1])
    var = 4.0 + np.interp(r, p.range_m, p.k_sd_db) ** 2
    assert_allclose(ref, plain * 4.0 / var, rtol=1e-9, atol=1e-9)
