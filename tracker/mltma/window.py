"""The cycles of each row's current tack, cut from the batch's history as one window.

Rows start their tacks at different cycles; the window runs from the earliest start to the
current cycle n, and a mask says which columns lie on each row's tack.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, slots=True, kw_only=True)
class TackWindow:
    """Cycles lo..n of the history, lo the earliest tack start of the rows (N = n - lo + 1)."""

    t_s: np.ndarray              # (N,) cycle times, s
    obs_x_m: np.ndarray          # (N,) observer position, m
    obs_y_m: np.ndarray
    bearing_deg: np.ndarray      # (b, N) bearings, deg
    bearing_sd_deg: np.ndarray   # (b, N) their sds sigma_P (eq. 2), deg
    on_tack: np.ndarray          # (b, N) bool: the column is on the row's current tack
    start: np.ndarray            # (b,) column of each row's tack start


def tack_window(t_s, obs_x_m, obs_y_m, bearing_deg, bearing_sd_deg, tack_start, n,
                rows=slice(None)) -> TackWindow:
    """Cut the window of cycles tack_start..n of the chosen rows from the full history.

    Parameters
    ----------
    t_s, obs_x_m, obs_y_m : ndarray, shape (T,)
        Cycle times (s) and observer positions (m) of every cycle so far.
    bearing_deg, bearing_sd_deg : ndarray, shape (B, T)
        Bearings and their sds of every row, deg.
    tack_start : ndarray of int, shape (B,)
        First cycle of each row's current tack.
    n : int
        Current cycle.
    rows : index, optional
        The rows to take (default all).
    """
    start = tack_start[rows]
    lo = int(start.min())
    on = np.arange(lo, n + 1)[None, :] >= start[:, None]
    return TackWindow(t_s=t_s[lo:n + 1], obs_x_m=obs_x_m[lo:n + 1], obs_y_m=obs_y_m[lo:n + 1],
                      bearing_deg=bearing_deg[rows, lo:n + 1],
                      bearing_sd_deg=bearing_sd_deg[rows, lo:n + 1], on_tack=on, start=start - lo)
