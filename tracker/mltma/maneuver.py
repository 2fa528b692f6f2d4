"""Maneuver detection (eqs. 26-27 from the bearings, eq. 29 from the levels) and the start of a
new tack from the last estimates (section 3 step 1).

Eq. 28 (propeller shaft rate) needs the noise envelope spectrum, which the measurements do not
carry. A maneuver is taken as detected when a test fires on ``maneuver_confirm`` consecutive
cycles (the batch counts them).
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.course import wrap180


def bearing_maneuver(t_s, bearing_deg, tack_start, n, bearing_sd_deg, *, s_cycles: int,
                     l_cycles: int, factor: float):
    """Eqs. 26-27: the bearing at cycle n departs from the line through cycles n - L and n - S.

    |P_(N-S) + Pdot (t_N - t_(N-S)) - P_N| > factor sigma_P, Pdot = (P_(N-S) - P_(N-L)) /
    (t_(N-S) - t_(N-L)); tested on rows with at least L cycles on the tack.

    Parameters
    ----------
    t_s : ndarray, shape (T,)
        Cycle times, s.
    bearing_deg : ndarray, shape (B, T)
        Bearings of every cycle so far, deg.
    tack_start : ndarray of int, shape (B,)
    n : int
        Current cycle N.
    bearing_sd_deg : ndarray, shape (B,)
        sigma_P of the current bearing, deg.
    s_cycles, l_cycles : int
        S and L of eqs. 26-27.
    factor : float
        4.5 in eq. 26.

    Returns
    -------
    fired : ndarray of bool, shape (B,)
    """
    ok = (n - tack_start) >= l_cycles
    if not ok.any():
        return np.zeros(len(tack_start), dtype=bool)
    i_s, i_l = n - s_cycles, n - l_cycles
    ts, tl, tn = t_s[i_s], t_s[i_l], t_s[n]
    ps, pl, pn = bearing_deg[:, i_s], bearing_deg[:, i_l], bearing_deg[:, n]
    rate = wrap180(ps - pl) / (ts - tl)                                     # eq. 27
    return ok & (np.abs(wrap180(ps + rate * (tn - ts) - pn)) > factor * bearing_sd_deg)


def bearing_maneuver_curved(t_s, bearing_deg, tack_start, n, bearing_sd_deg, *, s_cycles: int,
                            l_cycles: int, factor: float):
    """Eqs. 26-27 with the bearing trace of a straight relative track: the bearing at cycle n
    departs from the bearing extrapolated from the track that fits cycles n - L to n - S, by
    more than ``factor`` sd of the difference.

    A target that does not manoeuvre, seen from an observer that does not, has a bearing trace
    that curves: its rate changes with the range and the aspect, most near the closest approach.
    Eq. 27 extrapolates a straight line through two bearings, and over the test's L cycles the
    curvature alone departs from that line by more than eq. 26's 4.5 sigma_P at a few km with
    sigma_P of a tenth of a degree (docs/atlas-tracking.md). Here the relative track is straight,
    x(t) = x0 + vx t, y(t) = y0 + vy t, each bearing P_i giving (x0 + vx t_i) cos P_i - (y0 + vy
    t_i) sin P_i = 0; (x0, vx, y0, vy) up to scale is the least singular vector of those rows
    (the range scale is not observable, the bearing trace is). A manoeuvre breaks the straight
    track. The sd of the difference is taken as sigma_P sqrt(1 + h), h the leverage of t_N in a
    three-parameter (quadratic) fit over the same cycles: the fitted bearing's own error, which
    eq. 26 leaves out. Arguments and return as `bearing_maneuver`.
    """
    ok = (n - tack_start) >= l_cycles
    if not ok.any():
        return np.zeros(len(tack_start), dtype=bool)
    idx = np.arange(n - l_cycles, n - s_cycles + 1)
    dt = t_s[idx] - t_s[n]                                          # <= 0, s
    scale = max(float(-dt[0]), 1.0)
    tau = dt / scale
    rows = np.flatnonzero(ok)
    # rows with the same bearings (class hypotheses of one track) are fitted once
    window, back = np.unique(bearing_deg[rows][:, idx], axis=0, return_inverse=True)
    p = np.radians(window)                                          # (u, k)
    c, s_ = np.cos(p), np.sin(p)
    a = np.stack([c, tau * c, -s_, -tau * s_], axis=-1)             # (u, k, 4)
    # the least singular vector of a: the eigenvector of a^T a with the least eigenvalue
    z = np.linalg.eigh(np.einsum("uki,ukj->uij", a, a))[1][:, :, 0][np.ravel(back)]  # x0, vx, y0, vy at t_N
    pred = np.degrees(np.arctan2(z[:, 0], z[:, 2]))
    ref = bearing_deg[rows, n - s_cycles]
    pred = np.where(np.abs(wrap180(pred - ref)) > 90.0, pred + 180.0, pred)  # the direction, not its opposite
    x = np.stack([np.ones(idx.size), tau, tau ** 2], axis=1)
    leverage = np.linalg.inv(x.T @ x)[0, 0]
    fired = np.zeros(len(tack_start), dtype=bool)
    miss = wrap180(bearing_deg[rows, n] - pred)
    fired[rows] = np.abs(miss) > factor * bearing_sd_deg[rows] * np.sqrt(1.0 + leverage)
    return fired


def level_maneuver(top_band, top_level_db, level_sd_db, tack_start, n, *, f_cycles: int,
                   factor: float, sd_floor_db: float):
    """Eq. 29: the level in the highest detected band departs from its mean over the F cycles
    before the last 3.

    The mean is taken over the cycles whose highest detected band was the same band, and only
    when more than F / 2 of them were; sigma_dW is floored at ``sd_floor_db`` (K(r) ripple).

    Parameters
    ----------
    top_band : ndarray of int, shape (B, T)
        Highest detected band of every cycle so far, -1: none.
    top_level_db : ndarray, shape (B, T)
        Its level, dB re 1 uPa.
    level_sd_db : ndarray, shape (B, M)
        sigma_dW (eq. 11) of the current cycle's bands, dB.
    tack_start : ndarray of int, shape (B,)
    n : int
        Current cycle N.
    f_cycles : int
        F of eq. 29.
    factor : float
        4.5 in eq. 29.
    sd_floor_db : float

    Returns
    -------
    fired : ndarray of bool, shape (B,)
    """
    ok = (n - tack_start) >= f_cycles + 3
    if not ok.any():
        return np.zeros(len(tack_start), dtype=bool)
    top = top_band[:, n]
    lo = n - 3 - f_cycles
    win_b = top_band[:, lo:n - 3]
    win = np.where(win_b == top[:, None], top_level_db[:, lo:n - 3], np.nan)
    cnt = np.isfinite(win).sum(1)
    mean = np.where(cnt > f_cycles // 2, np.nansum(win, 1) / np.maximum(cnt, 1), np.nan)
    sdw = np.maximum(level_sd_db[np.arange(len(top)), np.maximum(top, 0)], sd_floor_db)
    return ok & (top >= 0) & np.isfinite(mean) & \
        (np.abs(mean - top_level_db[:, n]) > factor * sdw)


def carried_estimates(last: dict, dt_s: float, obs_x_m: float, obs_y_m: float):
    """The last smoothed estimates carried over ``dt_s``: a new tack starts from them (step 1).

    Parameters
    ----------
    last : dict
        The previous cycle's output of `MLBatch.update` (``course_deg``, ``speed_mps``,
        ``x_m``, ``y_m``).
    dt_s : float
        Time since that cycle, s.
    obs_x_m, obs_y_m : float
        Observer position now, m.

    Returns
    -------
    course_deg, speed_mps, range_m : ndarray, shape (B,)
        Course and speed as they were; the range of the position moved on with them.
    """
    a = np.radians(last["course_deg"])
    px = last["x_m"] + last["speed_mps"] * np.sin(a) * dt_s
    py = last["y_m"] + last["speed_mps"] * np.cos(a) * dt_s
    return last["course_deg"], last["speed_mps"], np.hypot(px - obs_x_m, py - obs_y_m)
