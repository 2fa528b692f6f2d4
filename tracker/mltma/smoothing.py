"""Robust smoothing of the per-cycle estimates (section 3 step 9, section 4 step 9)."""

from __future__ import annotations

import numpy as np


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
