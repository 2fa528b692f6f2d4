"""BOT CRLB with zero process noise (Ristic et al. 2003 sec. 4.3.3) against a hand computation."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from acoustics.grid.levelprofile import LevelProfile
from tracker.crlb import bot_crlb, bot_spl_crlb, prior_covariance


def test_two_step_bound_matches_the_hand_computation():
    # prior P0 = diag(a, a, b, b); a stationary relative target at (0, 1000) m; dt = 1 s.
    a, b, sigma = 4.0e6, 1.0, math.radians(1.5)
    t = np.array([0.0, 1.0])
    rel = np.array([[0.0, 1000.0, 0.0, 0.0], [0.0, 1000.0, 0.0, 0.0]])
    bound = bot_crlb(t, rel, bearing_sd_rad=sigma, p0=np.diag([a, a, b, b]))
    # step 0: P0 itself
    assert_allclose(bound[0], math.sqrt(2 * a), rtol=1e-12)
    # step 1: J1 = F^-T J0 F^-1 + H^T H / sigma^2, H = [y/r^2, -x/r^2, 0, 0] = [1e-3, 0, 0, 0].
    # The y block [[1/a, -1/a], [-1/a, 1/a + 1/b]] inverts to var_y = a + b; the x block has
    # c = 1 / (sigma^2 r^2) added to its (0, 0) term: var_x = (1/a + 1/b) / det,
    # det = 1/(a b) + c (1/a + 1/b).
    c = 1.0 / (sigma ** 2 * 1000.0 ** 2)
    var_y = a + b
    var_x = (1 / a + 1 / b) / (1 / (a * b) + c * (1 / a + 1 / b))
    assert_allclose(bound[1], math.sqrt(var_x + var_y), rtol=1e-9)


def test_prior_covariance_north_bearing():
    # bearing 0 (north): cross-range along x with sd r * sd_theta, range along y
    p = prior_covariance(0.0, range_mean_m=10_000.0, range_sd_m=2000.0, bearing_sd_rad=0.01,
                         speed_mean_mps=2.0, speed_sd_mps=1.0, course_sd_rad=0.5)
    assert_allclose(np.diag(p), [100.0 ** 2, 2000.0 ** 2, 1.0 ** 2, 1.0 ** 2], rtol=1e-12,
                    atol=1e-9)
    p90 = prior_covariance(math.pi / 2, range_mean_m=10_000.0, range_sd_m=2000.0,
                           bearing_sd_rad=0.01, speed_mean_mps=2.0, speed_sd_mps=1.0,
                           course_sd_rad=0.5)
    assert_allclose(np.diag(p90)[:2], [2000.0 ** 2, 100.0 ** 2], rtol=1e-9)


def test_observer_maneuver_collapses_the_bound():
    # bearings-only needs an observer maneuver: with zero process noise the bound of the
    # maneuvering scenario falls by more than 10 times across the turn (13-17 min)
    from tools.studies.idm_scenarios import get_scenario

    sc = get_scenario("idm-maneuvering")
    t = sc.t_s
    rel = sc.target_state(t) - sc.observer_state(t)
    p0 = prior_covariance(math.atan2(rel[0, 0], rel[0, 1]), range_mean_m=10_000.0,
                          range_sd_m=2000.0, bearing_sd_rad=math.radians(1.5),
                          speed_mean_mps=1.543, speed_sd_mps=1.029,
                          course_sd_rad=math.pi / math.sqrt(12))
    bound = bot_crlb(t, rel, bearing_sd_rad=math.radians(1.5), p0=p0)
    assert bound[24] < 0.1 * bound[13]
    # before the turn the observer and target both move straight: little information
    assert bound[13] > 0.5 * bound[0]


def test_level_adds_its_information_to_the_range_and_speed_axes():
    # as the two-step test, plus a level with K(r) = -0.02 dB/m * r and the target moving north
    # at the Ross reference speed (observer velocity (0, 5.14) m/s, relative velocity 0):
    # H_l = [K' x/r, K' y/r, SL' vx/v, SL' vy/v] = [0, -0.02, 0, d], d = 53 / (5.14 ln 10).
    a, b, sigma, sigma_l = 4.0e6, 1.0, math.radians(1.5), 4.0
    t = np.array([0.0, 1.0])
    rel = np.array([[0.0, 1000.0, 0.0, 0.0], [0.0, 1000.0, 0.0, 0.0]])
    obs_vel = np.array([[0.0, 5.14], [0.0, 5.14]])
    profile = LevelProfile(range_m=np.array([0.0, 2000.0]), k_db=np.array([0.0, -40.0]))
    bound = bot_spl_crlb(t, rel, obs_vel, bearing_sd_rad=sigma, level_sd_db=sigma_l,
                         k_profile=profile, p0=np.diag([a, a, b, b]))
    assert_allclose(bound[0], math.sqrt(2 * a), rtol=1e-12)
    s_, d = -0.02, 53.0 / (5.14 * math.log(10.0))
    c = 1.0 / (sigma ** 2 * 1000.0 ** 2)
    var_x = (1 / a + 1 / b) / (1 / (a * b) + c * (1 / a + 1 / b))
    # (y, vy) block: [[1/a + s^2/sl^2, -1/a + s d/sl^2], [-1/a + s d/sl^2, 1/a + 1/b + d^2/sl^2]]
    j11 = 1 / a + s_ ** 2 / sigma_l ** 2
    j12 = -1 / a + s_ * d / sigma_l ** 2
    j22 = 1 / a + 1 / b + d ** 2 / sigma_l ** 2
    var_y = j22 / (j11 * j22 - j12 ** 2)
    assert_allclose(bound[1], math.sqrt(var_x + var_y), rtol=1e-9)

