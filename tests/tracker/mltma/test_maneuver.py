"""The manoeuvre tests of eqs. 26-27: a straight track seen close by curves its bearing trace."""

from __future__ import annotations

import numpy as np

from tracker.mltma.maneuver import bearing_maneuver, bearing_maneuver_curved, straight_track_extrapolation


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


def _far_bearings(rng, runs=200):
    """Bearings, deg, every 20 s for 20 min, of a transport 12 km away heading 060 deg at 6 m/s,
    seen from an observer heading south at 4.5 m/s (the follow study's first minutes), with
    0.05 deg noise; and the true ranges, m."""
    t = np.arange(0.0, 1200.0, 20.0)
    ox, oy = np.zeros_like(t), -4.5 * t
    x = -9000.0 + 6.0 * np.sin(np.radians(60.0)) * t
    y = -14000.0 + 6.0 * np.cos(np.radians(60.0)) * t
    true = np.mod(np.degrees(np.arctan2(x - ox, y - oy)), 360.0)
    return t, true[None] + rng.normal(0.0, 0.05, (runs, t.size)), np.hypot(x - ox, y - oy)


def test_the_straight_track_fit_says_how_far_its_extrapolation_may_miss(rng):
    """|miss| / (sigma_P sqrt(1 + h)) is a unit normal on a straight track: 3 sd are exceeded in
    ~0.3 % of the cycles. The first version (the eigenvector of the homogeneous rows, h of a
    quadratic) exceeded them in 16 % of the follow study's cycles."""
    t, b, r = _far_bearings(rng)
    z = []
    for n in range(20, t.size):
        prior = np.radians(0.05) / ((4.5 + 7.5 + 3.0) * (t[n] - t[n - 20]) / r[n])
        miss, h = straight_track_extrapolation(t, b, n, s_cycles=2, l_cycles=20, motion_prior=np.full(len(b), prior))
        z.append(np.abs(miss) / (0.05 * np.sqrt(1.0 + h)))
    z = np.array(z)
    assert 0.27 < np.mean(z > 1.0) < 0.37
    assert np.mean(z > 3.0) < 0.01
    assert np.mean(z > 4.5) < 0.001


def test_eq29_on_the_level_fires_on_a_step_of_a_smooth_level_not_on_a_rough_one(rng):
    """A +4 dB step (the transport's speed change, Grinenkov & Mashoshin section 4) fires on the
    first cycle it is seen where the statistic has stayed within 0.1 dB; where it has wandered
    by 3 dB on the track (levels the tables did not make), the same step does not."""
    from tracker.mltma.maneuver import level_maneuver_robust, level_step_db

    t = 60
    top = np.zeros((2, t), dtype=int)
    level = np.vstack([100.0 + rng.normal(0.0, 0.1, t), 100.0 + np.cumsum(rng.normal(0.0, 3.0, t))])
    level[:, 50:] += 4.0
    history = np.full((1, 2, t), np.nan)
    fired = []
    for n in range(t):
        step = level_step_db(top, level, np.zeros(2, dtype=int), n, f_cycles=10)
        fired.append(level_maneuver_robust(step[None], history, n, np.full((1, 2), 0.5), factor=4.5,
                                           history_cycles=30, min_history=10))
        history[0, :, n] = step
    fired = np.array(fired)
    assert np.flatnonzero(fired[:, 0]).tolist()[:1] == [50] and not fired[:50, 0].any()
    assert not fired[:, 1].any()


def test_a_range_error_moves_the_level_less_k_only_where_k_has_structure():
    """K linear in range: a range error of scale shifts K now and over the window alike, up to
    the slope times the range change (small); a caustic between them moves it by its height."""
    from tracker.mltma.maneuver import k_structure_var_db2

    r = np.arange(100.0, 20000.0, 100.0)
    smooth = -60.0 - 1e-3 * r
    caustic = smooth + np.where((r > 10000.0) & (r < 10600.0), 8.0, 0.0)
    window = np.linspace(9000.0, 9800.0, 10)[None]
    args = (r, np.array([10300.0]), window, np.array([500.0]))
    assert k_structure_var_db2(smooth[None], *args)[0] < 0.1
    assert k_structure_var_db2(caustic[None], *args)[0] > 4.0 ** 2


def test_the_k_structure_takes_each_window_cycle_s_own_k():
    """Window cycles with their own K (the tables where the observer was then): the same K for
    every cycle gives the one-profile figure; K that differs by a constant from cycle to cycle
    moves nothing (a range error moves K's differences, not its level); a caustic in the window
    cycles' own K counts where the current K has none."""
    from tracker.mltma.maneuver import k_structure_var_db2

    r = np.arange(100.0, 20000.0, 100.0)
    smooth = -60.0 - 1e-3 * r
    caustic = smooth + np.where((r > 10000.0) & (r < 10600.0), 8.0, 0.0)
    window = np.linspace(9000.0, 9800.0, 10)[None]
    args = (r, np.array([10300.0]), window, np.array([500.0]))
    one = k_structure_var_db2(caustic[None], *args)
    same = np.broadcast_to(caustic, (1, 10, r.size))
    assert k_structure_var_db2(caustic[None], *args, k_window_db=same) == one
    shifted = same + np.linspace(-3.0, 3.0, 10)[None, :, None]
    np.testing.assert_allclose(k_structure_var_db2(caustic[None], *args, k_window_db=shifted), one, rtol=1e-9)
    # each window cycle's own K with a caustic just beyond that cycle's range: the window's K
    # structure counts though the current K is smooth
    window_caustic = (smooth + np.where((r[None] > window[0, :, None] + 100.0)
                                        & (r[None] < window[0, :, None] + 600.0), 8.0, 0.0))[None]
    assert k_structure_var_db2(smooth[None], *args, k_window_db=window_caustic)[0] > 4.0
    assert k_structure_var_db2(smooth[None], *args)[0] < 0.1
