"""Inputs of the compiled loop with the target's depth as a state: the K table and the depth
model, in named groups as `tracker.rpf.kernel.params`, and how they are built."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class DepthTable(NamedTuple):
    """K against the target's depth and range, per radial, and each cycle's two radials.

    Attributes
    ----------
    depth_m : ndarray, shape (Z,)
        Target depths, m, increasing.
    range_m : ndarray, shape (R,)
        Ranges, m, increasing.
    k_db : ndarray, shape (J, Z, R)
        K, dB, the cells without water at the penalty (`TargetDepthK.level_table`).
    j0, j1 : ndarray of int64, shape (K,)
        The slabs around each cycle's bearing.
    w1 : ndarray, shape (K,)
        Weight of slab ``j1`` at each cycle.
    """

    depth_m: np.ndarray
    range_m: np.ndarray
    k_db: np.ndarray
    j0: np.ndarray
    j1: np.ndarray
    w1: np.ndarray


class DepthModel(NamedTuple):
    """The depth state: its span (uniform prior, reflecting walls) and its random walk.

    Attributes
    ----------
    lo_m, hi_m : float
        The span, m.
    walk_m_per_sqrt_s : float
        Random-walk sd per square root of time, m s^-1/2.
    """

    lo_m: float
    hi_m: float
    walk_m_per_sqrt_s: float


def depth_table(target_k, bearing_deg, n_cycles: int) -> DepthTable:
    """The kernel's table from a `acoustics.grid.targetdepth.TargetDepthK` and the bearing of
    each cycle, deg (NaN: the last bearing measured before it; before any, the first one)."""
    b = np.asarray(bearing_deg, dtype=float)
    known = np.isfinite(b)
    fill = np.where(known, b, np.nan)
    if known.any():
        idx = np.where(known, np.arange(b.size), 0)
        np.maximum.accumulate(idx, out=idx)
        fill = b[idx]
        fill[~np.isfinite(fill)] = b[known][0]
    else:
        fill = np.zeros(b.size)
    j0, j1, w1 = target_k.cells(fill[:n_cycles])
    return DepthTable(depth_m=np.array(target_k.depth_m, dtype=float, order="C"),
                      range_m=np.array(target_k.range_m, dtype=float, order="C"),
                      k_db=target_k.level_table(),
                      j0=np.array(j0, dtype=np.int64), j1=np.array(j1, dtype=np.int64),
                      w1=np.array(w1, dtype=float))
