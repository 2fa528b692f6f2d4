"""Robust smoothing of the per-cycle estimates (section 3 step 9, section 4 step 9).

Over the last L cycles of each row's tack, every estimate is ranked, the largest and smallest
few dropped and the rest averaged (L = 19, 2 + 2 dropped in section 4). Ranges are first carried
to the current time with each cycle's own velocity; courses are unwrapped around the current
one. "The smoothing procedure can be repeated twice": a second pass smooths the smoothed series.

The smoothed estimate is an average of the window's estimates, each with the sd its cycle stated
(eq. 25's marginal sd, `tracker.mltma.covariance`). Its own sd (`window_sd`) is the latest of
those sds, or the window's spread where the estimates scatter more than that (the root of the
mean of their squared deviations from the mean of the kept ones), whichever is larger. The
window's estimates share most of their bearings and the levels' lasting errors, so their
average is hardly better than the latest, whose sd is from the most bearings; where the raw
estimates wander more than their sds say (a tack's first minutes after a manoeuvre, a course
from a few bearings), the spread is the honest figure. (The root mean square of the window's
sds with the spread added, as a mixture's, stated the shelf study's smoothed ranges about 1.4x
too wide: docs/uncertainty.md.)
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.course import wrap180


def _kept(values, count, drop_per_19: int, length: int):
    """The entries `trimmed_mean` averages, (B, W) bool (the window's first ``count`` valid
    entries less the ``drop`` largest and smallest)."""
    valid = (np.arange(values.shape[1])[None, :] < count[:, None]) & np.isfinite(values)
    order = np.argsort(np.where(valid, values, np.inf), axis=1, kind="stable")
    n_valid = valid.sum(1)
    drop = (drop_per_19 * n_valid) // length
    rank = np.empty_like(order)
    np.put_along_axis(rank, order, np.arange(values.shape[1])[None, :].repeat(len(values), 0), axis=1)
    return valid & (rank >= drop[:, None]) & (rank < (n_valid - drop)[:, None])


def window_sd(values, sds, count, drop_per_19: int, length: int):
    """sd of the smoothed estimate of each row's window (module docstring): the larger of the sd
    stated by the latest of its first ``count`` entries that has one and the spread of the entries
    `trimmed_mean` keeps; NaN where no entry has an sd.

    Parameters
    ----------
    values, sds : ndarray, shape (B, W)
        The window's estimates and the sds their cycles stated (NaN: none), oldest first.
    count, drop_per_19, length
        As `trimmed_mean`.
    """
    stated = (np.arange(sds.shape[1])[None, :] < count[:, None]) & np.isfinite(sds)
    latest = np.take_along_axis(sds, (sds.shape[1] - 1 - np.argmax(stated[:, ::-1], axis=1))[:, None], axis=1)[:, 0]
    keep = _kept(values, count, drop_per_19, length)
    n = np.maximum(keep.sum(1), 1)
    mean = np.where(keep, values, 0.0).sum(1) / n
    spread2 = np.where(keep, np.square(values - mean[:, None]), 0.0).sum(1) / n
    return np.where(stated.any(1), np.sqrt(np.maximum(np.square(latest), spread2)), np.nan)


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
    sds : dict of str to ndarray, shape (B,)
        ``range_sd_m``, ``course_sd_deg``, ``speed_sd_mps`` of the smoothed estimates
        (`window_sd`), where ``raw`` holds the raw sds under those keys (else not returned).
    """
    take = lambda key: np.take_along_axis(raw[key], idx, axis=1)  # noqa: E731
    dt = t_s[n] - t_s[idx]
    px = take("x_m") + take("vx_mps") * dt
    py = take("y_m") + take("vy_mps") * dt
    rng = np.hypot(px - obs_x_m, py - obs_y_m)
    ref = raw["course_deg"][:, n]
    course_u = ref[:, None] + wrap180(take("course_deg") - ref[:, None])
    values = {"range_sd_m": rng, "course_sd_deg": course_u, "speed_sd_mps": take("speed_mps")}
    sds = {key: window_sd(v, take(key), count, drop, width) for key, v in values.items() if key in raw}
    return (trimmed_mean(rng, count, drop, width), trimmed_mean(course_u, count, drop, width),
            trimmed_mean(take("speed_mps"), count, drop, width), sds)


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
