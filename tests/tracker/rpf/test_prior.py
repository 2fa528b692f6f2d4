"""Initial particles from the first bearing (Ristic et al. sec. 6.4.1.1, the paper's sec. 5)."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from tracker.rpf.config import RpfConfig
from tracker.rpf.likelihood import bearing_rad
from tracker.rpf.prior import initial_particles


def test_initial_particles_follow_the_prior(rng):
    cfg = RpfConfig()
    state = initial_particles(math.radians(80.0), [0.0, 0.0], cfg, 2, rng)
    r = np.hypot(state[0], state[1])
    assert_allclose(r.mean(), 10_000.0, atol=50.0)
    assert_allclose(r.std(), 2000.0, atol=50.0)
    b = np.degrees(bearing_rad(state[0], state[1]))
    assert_allclose(b.mean(), 80.0, atol=0.05)
    assert_allclose(b.std(), 1.5, atol=0.05)
    # speed N(s, sd) on course N(z0 + pi, sd_c): E[v] = s * exp(-sd_c^2 / 2) along z0 + pi
    shrink = math.exp(-0.5 * math.radians(cfg.course_sd_deg) ** 2)
    c = math.radians(260.0)
    assert_allclose(state[2].mean(), cfg.speed_mean_mps * shrink * math.sin(c), atol=0.02)
    assert_allclose(state[3].mean(), cfg.speed_mean_mps * shrink * math.cos(c), atol=0.02)


def test_range_span_draws_the_range_log_uniform(rng):
    """Each factor of range between the span's ends equally likely: ln r uniform, so its
    quartiles at a quarter, half and three quarters of ln(far / near); nothing outside."""
    cfg = RpfConfig(range_span_m=(1000.0, 40_000.0), n_particles=20_000)
    state = initial_particles(0.2, [0.0, 0.0], cfg, 2, rng)
    r = np.hypot(state[0], state[1]).ravel()
    assert r.min() >= 1000.0 and r.max() <= 40_000.0
    u = np.log(r / 1000.0) / math.log(40.0)
    # 40 000 draws: a quartile's sd is about 0.0022; 0.01 is 4.5 sd
    assert_allclose(np.quantile(u, [0.25, 0.5, 0.75]), [0.25, 0.5, 0.75], atol=0.01)


def test_range_span_must_be_two_increasing_ranges():
    for bad in ((1000.0,), (0.0, 1000.0), (5000.0, 1000.0), (1000.0, float("inf"))):
        try:
            RpfConfig(range_span_m=bad)
        except ValueError as err:
            assert "range_span_m" in str(err)
        else:
            raise AssertionError(f"{bad} accepted")
