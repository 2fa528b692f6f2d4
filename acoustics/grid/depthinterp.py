"""TL at given depths from a table on a depth axis: the one depth rule of tmakit.

Linear in depth between the axis' depths; a depth below the axis' last one has no value (NaN);
a table on a single depth (K-only or one-receiver grids) gives that row at every depth. The
trackers (``acoustics.grid.tables``: K and TL at an observer's depth) and the sensitivity studies (a
member's TL on the nominal area's depths) both use it.
"""

from __future__ import annotations

import numpy as np


def tl_at_depths(tl_db: np.ndarray, depth_m: np.ndarray, target_m) -> np.ndarray:
    """``tl_db(..., depth, range)`` at ``target_m``, linear in depth, shape ``(..., target, range)``.

    Parameters
    ----------
    tl_db : ndarray, (..., depth, range)
        The table, dB.
    depth_m : ndarray, (depth,)
        Its depth axis, increasing, m.
    target_m : array_like, (target,)
        Depths wanted, m; NaN below ``depth_m[-1]``, the first row above ``depth_m[0]``.
    """
    tl = np.asarray(tl_db)
    z = np.asarray(depth_m, dtype=float)
    t = np.atleast_1d(np.asarray(target_m, dtype=float))
    if z.size == 1:
        return np.repeat(tl[..., :1, :], t.size, axis=-2).astype(float)
    j = np.clip(np.searchsorted(z, t, side="right") - 1, 0, z.size - 2)
    w = np.clip((t - z[j]) / (z[j + 1] - z[j]), 0.0, 1.0)[:, None]
    out = (1.0 - w) * tl[..., j, :] + w * tl[..., j + 1, :]
    below = t > z[-1] + 1e-9
    if below.any():
        out = np.array(out, dtype=float)
        out[..., below, :] = np.nan
    return out
