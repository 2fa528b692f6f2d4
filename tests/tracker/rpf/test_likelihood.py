"""Measurements (Iglesis & de Montella eqs. 9, 12, 16, 32-33): bearing and level functions and
their log-likelihoods."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from tracker.rpf.likelihood import bearing_loglik, bearing_rad, level_loglik, predicted_level_db


def test_bearing_is_clockwise_from_north_and_residual_wraps():
    assert_allclose(np.degrees(bearing_rad(1.0, 0.0)), 90.0)
    assert_allclose(np.degrees(bearing_rad(0.0, -1.0)), 180.0)
    state = np.zeros((4, 1, 1))
    state[0], state[1] = math.sin(math.radians(1.0)), math.cos(math.radians(1.0))
    ll = bearing_loglik(state, math.radians(359.0), math.radians(1.0))
    assert_allclose(ll[0, 0], -0.5 * 2.0 ** 2, rtol=1e-9)  # 2 deg apart, not 358


def test_predicted_level_uses_each_particles_target_speed():
    state = np.zeros((4, 1, 2))
    state[0] = [3000.0, 4000.0]  # ranges 3000 and 4000 m
    state[2] = [2.0, 4.14]       # relative vx; the observer adds 1 m/s east
    k = lambda r: -20.0 * np.log10(r)  # noqa: E731 - spherical spreading as K(r)
    level = predicted_level_db(state, [1.0, 0.0], k)
    expected = 170 + 53 * np.log10(np.array([3.0, 5.14]) / 5.14) - 20 * np.log10([3000.0, 4000.0])
    assert_allclose(level[0], expected, atol=1e-9)
    ll = level_loglik(state, expected[0], [1.0, 0.0], k, 10.0)
    assert_allclose(ll[0, 0], 0.0, atol=1e-12)
    assert ll[0, 1] < -0.1
