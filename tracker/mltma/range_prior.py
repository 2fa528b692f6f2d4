"""The range term of eq. 25: the level-based ML range (eq. 20) with its a-posteriori sd
(eq. 21) for each row's class, or, on a cycle without a detected band, the last range as a weak
prior (section 3 step 7).
"""

from __future__ import annotations

import numpy as np

from acoustics.levelrange import level_range


def level_ranges_m(level_db, detected, level_sd_db, p0_db, class_index, k_db, range_axis_m,
                   level_offsets, gain_db, row_offsets=None):
    """Level-based range (eq. 20) and its sd (eq. 21) of every row, each with its class's K(r).

    Parameters
    ----------
    level_db : ndarray, shape (B, M)
        Band levels W, dB re 1 uPa; NaN where the band is not detected.
    detected : ndarray of bool, shape (B, M)
    level_sd_db : ndarray, shape (B, M)
        sigma_dW (eq. 11), with each band's own K error where the model has one, dB.
    p0_db : ndarray, shape (B,)
        Class mean P0 of each row, dB re 1 uPa.
    class_index : ndarray of int, shape (B,)
    k_db : ndarray, shape (C, M, R), or (C, M, B, R) with one K per row
        K(r) of each class and band at the observer's depth, dB; per row on a bearing-dependent
        grid (K at the row's bearing).
    range_axis_m : ndarray, shape (R,)
    level_offsets : list of (offsets_db, weights)
        Eq. 21 quadrature of each class (`tracker.ranging.offset_nodes`).
    gain_db : float
        Receiver gain H of eq. 12, dB.
    row_offsets : (offsets (n, B), weights (n,)), optional
        Each row's own eq. 21 nodes (`tracker.ranging.offset_nodes_per_row`), in place of its
        class's: where the grid carries a K error sd by bearing and range.

    Returns
    -------
    range_m, range_sd_m : ndarray, shape (B,)
        NaN where no band is detected; the sd is at least one range step.
    """
    b = len(class_index)
    r_opt = np.full(b, np.nan)
    r_sd = np.full(b, np.nan)
    for c in np.unique(class_index):
        rows = np.flatnonzero(class_index == c)
        off, wts = level_offsets[c] if row_offsets is None else (row_offsets[0][:, rows], row_offsets[1])
        k_class = k_db[c] if k_db.ndim == 3 else np.moveaxis(k_db[c][:, rows], 1, 0)  # (M, R) or
        r_opt[rows], r_sd[rows] = level_range(                                    # (rows, M, R)
            level_db[rows], detected[rows], level_sd_db[rows], p0_db[rows], k_class, range_axis_m,
            offsets_db=off, weights=wts, gain_db=gain_db)
    return r_opt, np.maximum(r_sd, range_axis_m[1] - range_axis_m[0])


def range_prior_m(level_range_m, level_range_sd_m, last_range_m):
    """The range and sd entering eq. 25: the level range, else the last range with sd half of it.

    Parameters
    ----------
    level_range_m, level_range_sd_m : ndarray, shape (B,)
        `level_ranges_m` (NaN: no band detected this cycle).
    last_range_m : ndarray, shape (B,)
        The last smoothed range (NaN: none yet).

    Returns
    -------
    range_m, range_sd_m : ndarray, shape (B,)
        NaN and inf where neither exists (no range term in eq. 25).
    """
    have = np.isfinite(level_range_m)
    prior = np.where(have, level_range_m, last_range_m)
    prior_sd = np.where(have, level_range_sd_m, np.where(np.isfinite(last_range_m),
                                                         0.5 * last_range_m, np.inf))
    return prior, prior_sd
