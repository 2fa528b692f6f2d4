"""When the bearings say enough: eq. 30 and the curvature test before eq. 8, and section 4
step 8's test before eq. 25 (section 3 steps 5 and 8).

Until eq. 8 may be used, the reverse bearing is the relative course; until eq. 25 may be used,
the estimates are the fallbacks listed after eq. 25.
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.course import wrap180
from tracker.mltma.window import TackWindow


def eq30_passes(bearing_now_deg, bearing_start_deg, bearing_sd_deg, cycles_on_tack,
                factor: float):
    """Eq. 30: the bearing changed since the tack start by more than ``factor`` sigma_P.

    Parameters
    ----------
    bearing_now_deg, bearing_start_deg : ndarray, shape (B,)
        Bearing now and at the tack start, deg.
    bearing_sd_deg : ndarray, shape (B,)
        sigma_P of the current bearing (eq. 2), deg.
    cycles_on_tack : ndarray of int, shape (B,)
        At least 3 are needed (eq. 8 takes a triple).
    factor : float
        4.5 in eq. 30.
    """
    change = np.abs(wrap180(bearing_now_deg - bearing_start_deg))
    return (change > factor * bearing_sd_deg) & (cycles_on_tack >= 3)


def bearing_curvature_significant(window: TackWindow, factor: float):
    """Rows whose bearings over the tack curve significantly (eq. 8 is then determined).

    Weighted least-squares fit P(t) = a + b t + c t^2 over the tack (bearings unwrapped from
    the tack's first, weights 1 / sigma_P^2); True where |c| > factor x sd(c) and the tack has
    at least 5 cycles. Eq. 8 rests on the bearing's curvature (a straight bearing trace leaves
    the relative course undetermined), as eq. 30 rests on its change.

    Parameters
    ----------
    window : TackWindow
        Every row's tack up to the current cycle.
    factor : float
        `MLParams.curvature_factor`.

    Returns
    -------
    curved : ndarray of bool, shape (b,)
    """
    on = window.on_tack
    b = on.shape[0]
    t0 = window.t_s[window.start][:, None]
    tc = np.where(on, window.t_s[None, :] - t0, 0.0)
    scale = np.maximum(tc.max(1, keepdims=True), 1.0)
    x = tc / scale
    y = wrap180(window.bearing_deg - window.bearing_deg[np.arange(b), window.start][:, None])
    w = np.where(on, 1.0 / np.square(window.bearing_sd_deg), 0.0)
    X = np.stack([np.ones_like(x), x, x * x], axis=2)                  # (B, N, 3)
    XtWX = np.einsum("bni,bn,bnj->bij", X, w, X)
    XtWy = np.einsum("bni,bn,bn->bi", X, w, y)
    ok = on.sum(1) >= 5
    XtWX = np.where(ok[:, None, None], XtWX, np.eye(3)[None])
    try:
        cov = np.linalg.inv(XtWX)
    except np.linalg.LinAlgError:
        return np.zeros(b, dtype=bool)
    coef = np.einsum("bij,bj->bi", cov, np.where(ok[:, None], XtWy, 0.0))
    sd_c = np.sqrt(np.maximum(cov[:, 2, 2], 1e-300))
    return ok & (np.abs(coef[:, 2]) > factor * sd_c)


def eq25_applies(t_now_s, t_s, bearing_deg, tack_start, n, bearing_sd_deg, range_prior_m, *,
                 window_s: float, factor: float, min_cycles: int):
    """Section 4 step 8 (Russian original): the bearing changed over the last ``window_s``
    (3 min) by more than ``factor`` (3) sigma_P, the tack has ``min_cycles`` cycles, and eq. 25
    has a range term.

    Parameters
    ----------
    t_now_s : float
        Time of the current cycle n, s.
    t_s : ndarray, shape (T,)
        Cycle times, s (cycles 0..n are read).
    bearing_deg : ndarray, shape (B, T)
        Bearings of every cycle so far, deg; column n is the current one.
    tack_start : ndarray of int, shape (B,)
    n : int
    bearing_sd_deg : ndarray, shape (B,)
        sigma_P of the current bearing, deg.
    range_prior_m : ndarray, shape (B,)
        Range of eq. 25's range term (NaN: none).
    """
    b = len(tack_start)
    back = np.searchsorted(t_s[:n + 1], t_now_s - window_s)
    back = np.maximum(back, tack_start)
    change = np.abs(wrap180(bearing_deg[:, n] - bearing_deg[np.arange(b), back]))
    return ((change > factor * bearing_sd_deg) & (n - tack_start + 1 >= min_cycles)
            & np.isfinite(range_prior_m))
