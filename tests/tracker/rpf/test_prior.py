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
