"""Maneuver detection (eqs. 26-27 from the bearings, eq. 29 from the levels) and the start of a
new tack from the last estimates (section 3 step 1).

Eq. 28 (propeller shaft rate) needs the noise envelope spectrum, which the measurements do not
carry. A maneuver is taken as detected when a test fires on ``maneuver_confirm`` consecutive
cycles (the batch counts them).
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.course import wrap180

#: Levenberg-Marquardt steps of the straight-track fit after the reweighted linear fit; on far,
#: slow windows (12-16 km, 0.05 deg, tests/tracker/mltma/test_maneuver.py) the misses then exceed
#: 3 sd in 0.24 % of the cycles and 4.5 sd in none of 8000 (the normal law's 0.27 % and 0.0007 %).
LM_STEPS = 8


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


def straight_track_extrapolation(t_s, bearing_deg, n: int, *, s_cycles: int, l_cycles: int,
                                 motion_prior=None, bearing_sd_deg=None):
    """The bearing at cycle n extrapolated from the straight relative track that fits the bearings
    of cycles n - L to n - S, and its error in units of the bearing sd.

    The relative track x(t) = x0 + vx t, y(t) = y0 + vy t (t from t_N) makes each bearing P_i
    satisfy (x0 + vx t_i) cos P_i - (y0 + vy t_i) sin P_i = rho_i sin(e_i) ~ 0, rho_i the
    relative range, e_i the bearing error; the range scale is not observable, so it is fixed by
    the range along the last bearing of the window being 1. The fit is maximum likelihood in the
    bearings: the linear (pseudo-linear) least squares first, reweighted by 1 / rho_i^2 twice (its
    residuals then measure bearing errors), then Levenberg-Marquardt steps on the exact bearing residuals
    in (beta, u, w), P(t) = atan2(sin beta + u t, cos beta + w t), beta the extrapolated bearing at
    t_N, (u, w) the relative velocity in ranges per window. The extrapolation's own error is
    sigma_P sqrt(h), h = [(J^T J)^-1]_beta,beta.

    Far away the window's trace is nearly straight and the fit's curvature is noise: with no
    bound on (u, w) the best fit may be a track through the observer's neighbourhood, whose
    extrapolation is wild (at 110 km, 3 sd exceeded in 10 % of the cycles). ``motion_prior``
    bounds them: (u, w) ~ N(0, s^2), s the largest relative speed over the window in ranges (the
    caller's relative speed x the window's duration / the tracked range), as two more residuals.

    The linear fit alone (or the eigenvector of the homogeneous rows, which the first version
    used) is not the likelihood's: on the follow study's bearings (0.05 deg, 9-13 km, slow
    bearing rate) its miss exceeded 3 sd of the quadratic-fit leverage in 16 % of the cycles
    and 4.5 sd in 7 %, a false manoeuvre per run (`LM_STEPS`).

    Parameters
    ----------
    t_s : ndarray, shape (T,)
        Cycle times, s.
    bearing_deg : ndarray, shape (B, T)
        Bearings, deg (the rows tested).
    n : int
        Current cycle N (needs n >= L).
    s_cycles, l_cycles : int
        S and L of eqs. 26-27.
    motion_prior : ndarray, shape (B,), optional
        sigma_P / s of each row (both in radians per window: the bearing sd at cycle n over the
        prior's sd of u and w); 0 or absent: no prior.
    bearing_sd_deg : ndarray, shape (B, T), optional
        Each cycle's bearing sd, deg: the fit weighs bearing i by (sigma_P,n / sigma_P,i)^2 (a
        cycle heard in a weak band has a bearing sd many times another's); absent: equal.

    Returns
    -------
    miss_deg : ndarray, shape (B,)
        P_N less its extrapolation, deg, in (-180, 180].
    leverage : ndarray, shape (B,)
        h: the variance of the extrapolation in units of sigma_P^2.
    """
    idx = np.arange(n - l_cycles, n - s_cycles + 1)
    dt = t_s[idx] - t_s[n]                                          # <= 0, s
    tau = dt / max(float(-dt[0]), 1.0)
    p = np.radians(bearing_deg[:, idx])                             # (B, k)
    c, s = np.cos(p), np.sin(p)
    rows = np.stack([c, tau * c, -s, -tau * s], axis=-1)            # rows . z = rho_i sin(e_i)
    zero = np.zeros(len(p))
    scale = np.stack([s[:, -1], zero, c[:, -1], zero], axis=-1)     # z . scale = 1
    ridge = np.zeros(len(p)) if motion_prior is None else np.square(np.broadcast_to(motion_prior, (len(p),)))
    on_velocity = np.diag([0.0, 1.0, 0.0, 1.0])
    relative = (np.ones_like(p) if bearing_sd_deg is None
                else np.square(bearing_sd_deg[:, n:n + 1] / bearing_sd_deg[:, idx]))   # (B, k)
    weight = np.ones_like(p)
    for _ in range(3):                                              # the linear fit, reweighted twice
        m = np.einsum("bk,bki,bkj->bij", weight * relative, rows, rows) + ridge[:, None, None] * on_velocity
        m += 1e-14 * np.einsum("bii->b", m)[:, None, None] * np.eye(4)
        z = np.linalg.solve(m, scale[..., None])[..., 0]
        z /= np.einsum("bi,bi->b", scale, z)[:, None]
        rx, ry = z[:, :1] + z[:, 1:2] * tau, z[:, 2:3] + z[:, 3:4] * tau
        weight = 1.0 / np.maximum(rx * rx + ry * ry, 1e-30)
    rho = np.hypot(z[:, 0], z[:, 2])
    theta = np.stack([np.arctan2(z[:, 0], z[:, 2]), z[:, 1] / rho, z[:, 3] / rho], axis=-1)
    prior = ridge[:, None, None] * np.diag([0.0, 1.0, 1.0])
    root = np.sqrt(relative)

    def residuals(theta):
        resid, jac = _straight_track_residuals(p, tau, theta)
        resid, jac = resid * root, jac * root[..., None]
        cost = np.einsum("bk,bk->b", resid, resid) + np.einsum("bi,bij,bj->b", theta, prior, theta)
        return cost, resid, jac

    # Levenberg-Marquardt: a step is kept only where it lowers the cost (plain Gauss-Newton
    # diverged from the linear fit on 0.3 % of far, slow windows: misses of 50-140 deg)
    cost, resid, jac = residuals(theta)
    damping = np.full(len(p), 1e-3)
    for _ in range(LM_STEPS):
        a = _normal_matrix(jac) + prior
        grad = np.einsum("bki,bk->bi", jac, resid) - np.einsum("bij,bj->bi", prior, theta)
        a_damped = a + damping[:, None, None] * np.einsum("bii->bi", a)[:, :, None] * np.eye(3)
        trial = theta + np.linalg.solve(a_damped, grad[..., None])[..., 0]
        cost_t, resid_t, jac_t = residuals(trial)
        keep = cost_t <= cost
        theta = np.where(keep[:, None], trial, theta)
        cost = np.where(keep, cost_t, cost)
        resid = np.where(keep[:, None], resid_t, resid)
        jac = np.where(keep[:, None, None], jac_t, jac)
        damping = np.where(keep, damping * 0.1, damping * 10.0)
    leverage = np.linalg.inv(_normal_matrix(jac) + prior)[:, 0, 0]
    return wrap180(bearing_deg[:, n] - np.degrees(theta[:, 0])), leverage


def _normal_matrix(jac):
    """J^T J (B, 3, 3), its diagonal loaded by 1e-12 of the trace (a degenerate window stays solvable)."""
    a = np.einsum("bki,bkj->bij", jac, jac)
    return a + 1e-12 * np.einsum("bii->b", a)[:, None, None] * np.eye(3)


def _straight_track_residuals(p, tau, theta):
    """Bearing residuals (B, k), rad, of P(t) = atan2(sin beta + u t, cos beta + w t) and their
    Jacobian (B, k, 3) in (beta, u, w)."""
    beta, u, w = theta[:, :1], theta[:, 1:2], theta[:, 2:3]
    x, y = np.sin(beta) + u * tau, np.cos(beta) + w * tau
    r2 = x * x + y * y
    resid = np.angle(np.exp(1j * (p - np.arctan2(x, y))))
    jac = np.stack([(y * np.cos(beta) + x * np.sin(beta)) / r2, tau * y / r2, -tau * x / r2], axis=-1)
    return resid, jac


def bearing_maneuver_curved(t_s, bearing_deg, tack_start, n, bearing_sd_deg, *, s_cycles: int,
                            l_cycles: int, factor: float, range_m=None, relative_speed_mps=None,
                            bearing_sd_history_deg=None):
    """Eqs. 26-27 with the bearing trace of a straight relative track: the bearing at cycle n
    departs from the bearing extrapolated from the track that fits cycles n - L to n - S, by
    more than ``factor`` sd of the difference.

    A target that does not manoeuvre, seen from an observer that does not, has a bearing trace
    that curves: its rate changes with the range and the aspect, most near the closest approach.
    Eq. 27 extrapolates a straight line through two bearings, and over the test's L cycles the
    curvature alone departs from that line by more than eq. 26's 4.5 sigma_P at a few km with
    sigma_P of a tenth of a degree (docs/atlas-tracking.md). Here the relative track is straight
    (`straight_track_extrapolation`): a manoeuvre breaks it. The sd of the difference is
    sigma_P sqrt(1 + h), h the extrapolation's own variance in units of sigma_P^2 (which eq. 26
    leaves out). Arguments and return as `bearing_maneuver`, and ``range_m``,
    ``relative_speed_mps`` (B,): the tracked range and the largest relative speed, which bound the
    relative velocity of the fit (its ``motion_prior``; NaN or absent: unbounded), and
    ``bearing_sd_history_deg`` (B, T), the bearing sd of every cycle, which weighs the fit.
    """
    ok = (n - tack_start) >= l_cycles
    if not ok.any():
        return np.zeros(len(tack_start), dtype=bool)
    rows = np.flatnonzero(ok)
    prior = np.zeros(rows.size)
    if range_m is not None and relative_speed_mps is not None:
        window_s = t_s[n] - t_s[n - l_cycles]
        with np.errstate(invalid="ignore", divide="ignore"):
            s_uw = relative_speed_mps[rows] * window_s / range_m[rows]        # ranges per window
        good = np.isfinite(s_uw) & (s_uw > 0)
        prior[good] = np.radians(bearing_sd_deg[rows][good]) / s_uw[good]
    # rows with the same bearings and prior (class hypotheses of one track) are fitted once
    sds = None if bearing_sd_history_deg is None else bearing_sd_history_deg[rows, :n + 1]
    key = np.column_stack([bearing_deg[rows][:, n - l_cycles:n + 1], prior]
                          + ([] if sds is None else [sds[:, n - l_cycles:n + 1]]))
    _, first, back = np.unique(key, axis=0, return_index=True, return_inverse=True)
    miss, leverage = straight_track_extrapolation(t_s[:n + 1], bearing_deg[rows[first], :n + 1], n,
                                                  s_cycles=s_cycles, l_cycles=l_cycles,
                                                  motion_prior=prior[first],
                                                  bearing_sd_deg=None if sds is None else sds[first])
    back = np.ravel(back)
    fired = np.zeros(len(tack_start), dtype=bool)
    fired[rows] = np.abs(miss[back]) > factor * bearing_sd_deg[rows] * np.sqrt(1.0 + leverage[back])
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


def level_step_db(top_band, level_db, tack_start, n, *, f_cycles: int, k_window_db=None, k_now_db=None):
    """Eq. 29's statistic: the level at cycle n less its mean over the F cycles before the last 3,
    those of the same highest band (more than F / 2 of them); with K, of the level less K.

    Parameters
    ----------
    top_band : ndarray of int, shape (B, T)
        Highest detected band of every cycle so far, -1: none.
    level_db : ndarray, shape (B, T)
        That band's level, dB.
    tack_start : ndarray of int, shape (B,)
    n : int
    f_cycles : int
    k_window_db : ndarray, shape (B, F), optional
        K at the window's cycles n - 3 - F .. n - 4 (their ranges on the track tracked now), dB.
    k_now_db : ndarray, shape (B,), optional
        K at cycle n, dB.

    Returns
    -------
    step_db : ndarray, shape (B,)
        NaN where the tack is shorter than F + 3 cycles or the window has too few cycles.
    """
    ok = (n - tack_start) >= f_cycles + 3
    out = np.full(len(tack_start), np.nan)
    if not ok.any():
        return out
    top = top_band[:, n]
    lo = n - 3 - f_cycles
    win = level_db[:, lo:n - 3] - (0.0 if k_window_db is None else k_window_db)
    win = np.where(top_band[:, lo:n - 3] == top[:, None], win, np.nan)
    cnt = np.isfinite(win).sum(1)
    use = ok & (top >= 0) & (cnt > f_cycles // 2)
    now = level_db[:, n] - (0.0 if k_now_db is None else k_now_db)
    mean = np.nansum(win, axis=1) / np.maximum(cnt, 1)
    out[use] = now[use] - mean[use]
    return out


def k_along_range(k_db, range_axis_m, range_m):
    """K profiles read at ranges: linear on the range axis, held at its ends, dB.

    Parameters
    ----------
    k_db : ndarray, shape (B, R) or (B, J, R)
        One K profile per row, or per row and column of ``range_m``, dB.
    range_axis_m : ndarray, shape (R,)
    range_m : ndarray, shape (B,) or (B, J)
        Finite ranges, m.
    """
    r = np.clip(range_m, range_axis_m[0], range_axis_m[-1])
    i = np.clip(np.searchsorted(range_axis_m, r, side="right") - 1, 0, range_axis_m.size - 2)
    f = (r - range_axis_m[i]) / (range_axis_m[i + 1] - range_axis_m[i])
    rows = np.arange(len(r))[:, None] if r.ndim == 2 else np.arange(len(r))
    if k_db.ndim == 3:
        cols = np.arange(r.shape[1])[None, :]
        return (1.0 - f) * k_db[rows, cols, i] + f * k_db[rows, cols, i + 1]
    return (1.0 - f) * k_db[rows, i] + f * k_db[rows, i + 1]


def k_structure_var_db2(k_row_db, range_axis_m, range_now_m, range_window_m, range_sd_m, nodes: int = 7,
                        k_window_db=None):
    """How much a range error moves eq. 29's statistic on the level less K, dB^2.

    With the tracked ranges off by a factor (1 + e / R_N) (a range error without an observer
    manoeuvre is mostly one of scale), K read at the current range R_N and at the window's R_i is
    off by g(e) = [K_N(R_N + e) - K_N(R_N)] - mean_i [K_i(R_i (1 + e / R_N)) - K_i(R_i)]; returned
    is E[g^2] for e ~ N(0, range_sd^2) (Gauss-Hermite nodes). Where K is smooth this is small even
    for a large range sd (the two differences cancel); across a caustic or a steep ripple it is
    the K structure the tracked range cannot place.

    Parameters
    ----------
    k_row_db : ndarray, shape (B, R)
        Each row's K on the range axis now (K_N), dB.
    range_axis_m : ndarray, shape (R,)
    range_now_m : ndarray, shape (B,)
    range_window_m : ndarray, shape (B, F)
        The window's ranges (NaN: a cycle left out).
    range_sd_m : ndarray, shape (B,)
        NaN where unknown: 0 returned.
    nodes : int
    k_window_db : ndarray, shape (B, F, R), optional
        Each window cycle's own K (K_i: the tables where the observer was then, at that cycle's
        bearing), dB; default ``k_row_db`` for every cycle.
    """
    u, w = np.polynomial.hermite_e.hermegauss(nodes)
    w = w / w.sum()
    ok = np.isfinite(range_now_m) & np.isfinite(range_sd_m) & np.isfinite(range_window_m).any(axis=1)
    rn = np.where(ok, range_now_m, range_axis_m[0])
    sd = np.where(ok, range_sd_m, 0.0)
    use = np.isfinite(range_window_m) & ok[:, None]
    rw = np.where(use, range_window_m, rn[:, None])
    cnt = np.maximum(use.sum(axis=1), 1)
    k_win = k_row_db if k_window_db is None else k_window_db

    k_n, k_w = k_along_range(k_row_db, range_axis_m, rn), k_along_range(k_win, range_axis_m, rw)
    g2 = np.zeros(len(rn))
    for uj, wj in zip(u, w):
        scale = 1.0 + uj * sd / np.maximum(rn, 1.0)
        d_w = np.where(use, k_along_range(k_win, range_axis_m, rw * scale[:, None]) - k_w, 0.0).sum(axis=1) / cnt
        g2 += wj * np.square(k_along_range(k_row_db, range_axis_m, rn * scale) - k_n - d_w)
    return np.where(ok, g2, 0.0)


def level_maneuver_robust(step_db, step_history_db, n, model_sd_db, *, factor: float, history_cycles: int,
                          min_history: int):
    """Eq. 29 on the better of two predictions of the level, each against the spread its
    statistic has had on this track.

    The statistics (`level_step_db`) are the step of the level itself (the paper's: the level
    should not change) and of the level less K along the track tracked now (the level should
    change as K does along it). Each has a model sd (sigma_dW's; for the first, also the change
    of K that the tracked track predicts over the window; for the second, K's structure under
    the range error, `k_structure_var_db2`) and a spread measured on the track, 1.4826 median
    |step| over the last ``history_cycles`` cycles before n - 2. Each row tests the statistic
    whose sd, max(model sd, spread), is the smaller, and fires where |step| > factor x that sd.

    Why both, and why the measured spread: levels from another model than the tables' (BELLHOP
    along the true path, docs/atlas-tracking.md) move the level less K by 5-10 dB in a few
    minutes even at the true range, which the grid's numbers do not say; a K error constant along
    the track (the dK of eq. 31) cancels in the step, so the class's ``k_error_sd_db`` is no
    threshold either (joined to sigma_dW it made the test miss the transport's +4 dB of
    Grinenkov & Mashoshin section 4). Where K is flat over the ranges crossed (the transport at
    30 or 110 km) the level itself steps least, and the level less K carries a poor range's
    error; near the closest approach K's change along the track is the level's, and the level
    less K steps least. The history spans tacks (the tables' error is not the tack's); with fewer
    than ``min_history`` finite values a statistic is not used.

    Parameters
    ----------
    step_db : ndarray, shape (S, B)
        The S statistics at cycle n (NaN: not computed).
    step_history_db : ndarray, shape (S, B, T)
        Their values at the earlier cycles (NaN where not computed).
    n : int
    model_sd_db : ndarray, shape (S, B)
        Each statistic's sd from the measurement model, dB.
    factor : float
        4.5 of eq. 29.
    history_cycles, min_history : int

    Returns
    -------
    fired : ndarray of bool, shape (B,)
    """
    hist = np.abs(step_history_db[:, :, max(n - 2 - history_cycles, 0):max(n - 2, 0)])
    spread = np.full(step_db.shape, np.inf)
    enough = np.isfinite(hist).sum(axis=2) >= min_history
    if enough.any():
        spread[enough] = 1.4826 * np.nanmedian(hist[enough], axis=1)
    sd = np.where(np.isfinite(step_db), np.maximum(model_sd_db, spread), np.inf)
    best = np.argmin(sd, axis=0)                                       # (B,)
    rows = np.arange(step_db.shape[1])
    sd, step = sd[best, rows], step_db[best, rows]
    return np.isfinite(step) & np.isfinite(sd) & (np.abs(np.nan_to_num(step)) > factor * sd)


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
