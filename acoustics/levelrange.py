"""Level-based ML ranging, Grinenkov & Mashoshin eqs. 20-21: the range whose K(r) best explains
measured band levels, and its spread over the uncertain noise level and K offset.

Defined once here, in the lowest layer that needs it: the sensitivity studies' range error
(``acoustics.sensitivity.summaries``) and the trackers (``tracker.ranging``) both call it.
"""

from __future__ import annotations

import numpy as np

#: K beyond a table's last range in the trackers' level model is its last value less this, dB (a
#: rejection, not physics); also what K is where a table has none (beyond land, a target deeper
#: than the water): the table's lowest value less this.
BEYOND_GRID_PENALTY_DB = 1000.0


def level_range(level_db, detected, sd_db, p0_db, k_db, range_m, *, offsets_db=(0.0,),
                weights=None, gain_db: float = 0.0, k_sd_db=None):
    """Level-based ML range (eq. 20) and its a-posteriori RMS error (eq. 21), batched.

    Parameters
    ----------
    level_db : ndarray, shape (B, M)
        Measured band levels W_k, dB re 1 uPa (any value where not detected).
    detected : ndarray of bool, shape (B, M)
        Detection indicators I_k.
    sd_db : ndarray, shape (B, M)
        Level error sd sigma_dW_k (eq. 11), dB.
    p0_db : ndarray, shape (B,)
        Expected noise level P0 of the class hypothesis, dB re 1 uPa.
    k_db : ndarray, shape (M, R), or (B, M, R) for one K per row
        Transfer characteristic K_k(r) of the class, dB (eq. 12); per row when it depends on
        the row's bearing (a bearing-dependent grid). Ranges where the grid has no K (NaN:
        beyond land, a target deeper than the water) take a level no target gives.
    range_m : ndarray, shape (R,)
        Range axis of ``k_db``, m.
    offsets_db, weights : sequence
        Offsets c = (p - mP0) + dK of eq. 21 and their weights (``offset_nodes``); offsets of
        shape (n, B) give each row its own nodes (a K error sd that depends on the row's bearing
        and range).
    gain_db : float
        Receiver gain H_k, dB.
    k_sd_db : ndarray, shape (B, M, R), optional
        sd of the K error of each row, band and range, dB (a grid's measured ``k_error_sd_db``
        at the row's bearing): the weights of eq. 20 become 1 / (sigma_k^2 + sd_K,k(r)^2),
        so a band is trusted less at ranges where its K is poorly known.

    Returns
    -------
    r_opt_m : ndarray, shape (B,)
        argmin_r sum_k I_k (W_k - P0 - K_k(r) - H)^2 / sigma_k^2 (eq. 20); NaN where no band
        is detected.
    r_sd_m : ndarray, shape (B,)
        sqrt of eq. 21: the weighted RMS of R(p, dK) - R_opt over the offsets.
    """
    level_db = np.asarray(level_db, dtype=float)
    det = np.asarray(detected, dtype=bool) & np.isfinite(level_db)
    w = np.where(det, 1.0 / np.square(sd_db), 0.0)                     # (B, M)
    d0 = np.where(det, level_db - np.asarray(p0_db)[:, None] - gain_db, 0.0)
    k_db = np.asarray(k_db, dtype=float)
    if not np.all(np.isfinite(k_db)):
        finite = k_db[np.isfinite(k_db)]
        floor = (finite.min() if finite.size else 0.0) - BEYOND_GRID_PENALTY_DB
        k_db = np.where(np.isfinite(k_db), k_db, floor)
    # cost_c(r) = sum w (d0 - c - K)^2 = const(c) - 2 (w d0).K + 2 c w.K + w.K^2
    if k_db.ndim == 2:
        wk = w @ k_db                                                  # (B, R)
        base = w @ np.square(k_db) - 2.0 * ((w * d0) @ k_db)          # (B, R)
    else:
        wk = np.einsum("bm,bmr->br", w, k_db)
        base = (np.einsum("bm,bmr->br", w, np.square(k_db))
                - 2.0 * np.einsum("bm,bmr->br", w * d0, k_db))
    offsets = np.asarray(offsets_db, dtype=float)
    weights = np.full(len(offsets), 1.0 / len(offsets)) if weights is None else np.asarray(weights)
    if k_sd_db is not None:
        return _level_range_weighted(det, d0, np.asarray(sd_db, dtype=float), k_db, np.asarray(k_sd_db, dtype=float),
                                     range_m, offsets, weights)
    r_opt = range_m[np.argmin(base, axis=1)]
    var = np.zeros(len(level_db))
    for c, wc in zip(offsets, weights):
        if np.all(c == 0.0):
            rc = r_opt
        else:
            rc = range_m[np.argmin(base + 2.0 * np.reshape(c, (-1, 1)) * wk, axis=1)]
        var += wc * np.square(rc - r_opt)
    none = ~det.any(axis=1)
    r_opt = np.where(none, np.nan, r_opt)
    return r_opt, np.where(none, np.nan, np.sqrt(var))


def _level_range_weighted(det, d0, sd_db, k_db, k_sd_db, range_m, offsets, weights):
    """`level_range` with weights that depend on range: the whole misfit at every range."""
    kk = k_db if k_db.ndim == 3 else k_db[None]                        # (B or 1, M, R)
    w = np.where(det[:, :, None], 1.0 / (np.square(sd_db)[:, :, None] + np.square(k_sd_db)), 0.0)
    resid = d0[:, :, None] - kk                                         # (B, M, R)
    r_opt = range_m[np.argmin(np.sum(w * np.square(resid), axis=1), axis=1)]
    var = np.zeros(len(d0))
    for c, wc in zip(offsets, weights):
        if np.all(c == 0.0):
            rc = r_opt
        else:
            shift = np.reshape(c, (-1, 1, 1))
            rc = range_m[np.argmin(np.sum(w * np.square(resid - shift), axis=1), axis=1)]
        var += wc * np.square(rc - r_opt)
    none = ~det.any(axis=1)
    return np.where(none, np.nan, r_opt), np.where(none, np.nan, np.sqrt(var))
