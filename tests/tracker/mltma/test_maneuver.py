"""The manoeuvre tests of eqs. 26-27: a straight track seen close by curves its bearing trace."""

from __future__ import annotations

import numpy as np

from tracker.mltma.maneuver import bearing_maneuver, bearing_maneuver_curved


def _bearings(turn_at_s=None, turn_deg=30.0):
    """Bearings, deg, every 20 s, of a target passing 3 km from an observer heading north at 4 m/s;
    the target heads east at 7 m/s and turns by ``turn_deg`` at ``turn_at_s``."""
    t = np.arange(0.0, 1800.0, 20.0)
    ox, oy = np.zeros_like(t), 4.0 * t
    course = np.where(t < (turn_at_s if turn_at_s is not None else np.inf), 90.0, 90.0 + turn_deg)
    vx, vy = 7.0 * np.sin(np.radians(course)), 7.0 * np.cos(np.radians(course))
    x = -6000.0 + np.concatenate([[0.0], np.cumsum(vx[:-1] * 20.0)])
    y = 3000.0 + np.concatenate([[0.0], np.cumsum(vy[:-1] * 20.0)])
    return t, np.mod(np.degrees(np.arctan2(x - ox, y - oy)), 360.0)[None]


def _fired(test, t, b, sd_deg=0.1):
    return [n for n in range(20, t.size) if test(t, b, np.array([0]), n, np.array([sd_deg]), s_cycles=2,
                                                 l_cycles=20, factor=4.5)[0]]


def test_a_straight_track_close_by_fires_the_paper_test_but_not_the_straight_track_fit():
    t, b = _bearings()
    # eq. 27's straight line through two bearings misses the curving trace by degrees
    assert len(_fired(bearing_maneuver, t, b)) > 10
    assert _fired(bearing_maneuver_curved, t, b) == []  # noiseless: exact up to rounding


def test_a_turn_is_still_detected_within_a_few_cycles():
    t, b = _bearings(turn_at_s=900.0)
    fired = _fired(bearing_maneuver_curved, t, b)
    assert fired and 900.0 <= t[fired[0]] <= 900.0 + 5 * 20.0


def test_bearing_noise_at_its_sd_rarely_fires():
    t, b = _bearings()
    rng = np.random.default_rng(3)
    noisy = b + rng.normal(0.0, 0.1, b.shape)
    # threshold 4.5 sd of the difference: a false alarm per cycle well below 1 %
    assert len(_fired(bearing_maneuver_curved, t, noisy)) <= 1
