"""Robust smoothing of the per-cycle estimates (section 3 step 9, section 4 step 9).

Over the last L cycles of each row's tack, every estimate is ranked, the largest and smallest
few dropped and the rest averaged (L = 19, 2 + 2 dropped in section 4). Ranges are first carried
to the current time with each cycle's own velocity; courses are unwrapped around the current
one. "The smoothing procedure can be repeated twice": a second pass smooths the smoothed series.
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.course import wrap180


def trimmed_mean(values, count, drop_per_19: int, length: int):
    """Robust mean of the first ``count`` entries of each row: sort, drop the ends, average.

    ``drop_per_19`` values are dropped at each end for a full window of ``length``; shorter
    windows drop proportionally fewer (rounded down). Entries without an estimate (NaN: a
    cycle with neither a level range nor an earlier range) are left out of the window; a
    window with none left gives NaN.
    """
    valid = (np.arange(values.shape[1])[None, :] < count[:, None]) & np.isfinite(values)
    v = np.where(valid, values, np.inf)
    v = np.sort(v, axis=1)
    count = valid.sum(1)
    drop = (drop_per_19 * count) // length
    j = np.arange(values.shape[1])[None, :]
    keep = (j >= drop[:, None]) & (j < (count - drop)[:, None])
    s = np.where(keep, v, 0.0).sum(1)
    n = keep.sum(1)
    return np.where(n > 0, s / np.maximum(n, 1), np.nan)


def smoothing_window(tack_start, n, width: int):
    """Cycle indices of each row's window: the last ``width`` cycles of its tack up to n.

    Returns
    -------
    idx : ndarray of int, shape (B, width)
        Cycles of the window, padded with n past its end.
    count : ndarray of int, shape (B,)
        Cycles in the window.
    """
    lo = np.maximum(tack_start, n - width + 1)
    idx = np.minimum(lo[:, None] + np.arange(width)[None, :], n)
    return idx, n - lo + 1


def smooth_raw(raw: dict, t_s, n, idx, count, obs_x_m: float, obs_y_m: float, *, drop: int,
               width: int):
    """First pass: robust means of range, course and speed over each row's window.

    Parameters
    ----------
    raw : dict of str to ndarray, shape (B, T)
        Raw estimates of every cycle: ``course_deg``, ``speed_mps``, ``x_m``, ``y_m``,
        ``vx_mps``, ``vy_mps``.
    t_s : ndarray, shape (T,)
        Cycle times, s.
    n : int
        Current cycle.
    idx, count : ndarray
        `smoothing_window`.
    obs_x_m, obs_y_m : float
        Observer position now, m.
    drop, width : int
        Dropped at each end of a full window, and the window length L (`trimmed_mean`).

    Returns
    -------
    range_m, course_deg, speed_mps : ndarray, shape (B,)
        Course unwrapped around the current raw course (not reduced to [0, 360)).
    """
    take = lambda key: np.take_along_axis(raw[key], idx, axis=1)  # noqa: E731
    dt = t_s[n] - t_s[idx]
    px = take("x_m") + take("vx_mps") * dt
    py = take("y_m") + take("vy_mps") * dt
    rng = np.hypot(px - obs_x_m, py - obs_y_m)
    ref = raw["course_deg"][:, n]
    course_u = ref[:, None] + wrap180(take("course_deg") - ref[:, None])
    return (trimmed_mean(rng, count, drop, width), trimmed_mean(course_u, count, drop, width),
            trimmed_mean(take("speed_mps"), count, drop, width))


def smooth_again(smoothed: dict, idx, count, course_deg, *, drop: int, width: int):
    """Second pass over the first pass's series (``smoothed``, keys ``range_m``, ``course_deg``,
    ``speed_mps``, (B, T), current cycle included); courses unwrapped around ``course_deg``.

    Returns range_m, course_deg, speed_mps, each (B,).
    """
    take = lambda key: np.take_along_axis(smoothed[key], idx, axis=1)  # noqa: E731
    course_u = course_deg[:, None] + wrap180(take("course_deg") - course_deg[:, None])
    return (trimmed_mean(take("range_m"), count, drop, width),
            trimmed_mean(course_u, count, drop, width),
            trimmed_mean(take("speed_mps"), count, drop, width))
