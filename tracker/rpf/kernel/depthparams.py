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
    regular : bool
        Whether both axes have equal steps (the last may be shorter): the kernel then finds a
        particle's cell by index arithmetic (`tracker.rpf.kernel.depth.regular_cell`), else
        by a search.
    depth_first_m, depth_inv_step : float
        The depth axis's first value of its regular part, m, and 1 / its step, 1/m (1.0 when
        not ``regular``).
    range_first_m, range_inv_step : float
        The same of the range axis.
    """

    depth_m: np.ndarray
    range_m: np.ndarray
    k_db: np.ndarray
    j0: np.ndarray
    j1: np.ndarray
    w1: np.ndarray
    regular: bool
    depth_first_m: float
    depth_inv_step: float
    range_first_m: float
    range_inv_step: float
    depth_regular_from: int = 0  # the depth axis is regular from this index (near-surface rows before)


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


#: How far, as a share of the step, an axis value may be from first + j step for the axis to
#: count as regular: the cell's weight is then off by as much, and K by that share of K's change
#: across the cell (some 1e-8 dB).
REGULAR_AXIS_TOLERANCE = 1e-9


def regular_step(axis) -> float | None:
    """The step of an axis of equal steps but a last one that may be shorter (a grid's depth axis
    runs to the deepest bottom), m; None for any other axis (fewer than 2 values, an uneven
    step, a last step longer than the others)."""
    a = np.asarray(axis, dtype=float)
    if a.size < 2:
        return None
    step = float(a[1] - a[0])
    if not (np.isfinite(step) and step > 0.0):
        return None
    tol = REGULAR_AXIS_TOLERANCE * step
    inner = a[:-1] - (a[0] + step * np.arange(a.size - 1))
    last = a[-1] - a[-2]
    if np.abs(inner).max() > tol or not (0.0 < last <= step + tol):
        return None
    return step


def regular_part(axis) -> tuple[float | None, int]:
    """The step of an axis regular from some index on, and that index: a table from the observer
    has near-surface rows within its first step (``acoustics.surface.with_surface_rows``: 0,
    s/8, s/4, s/2, s, 2s, ...), which the kernel searches, the rest by index arithmetic."""
    a = np.asarray(axis, dtype=float)
    step = regular_step(a)
    if step is not None or a.size < 3:
        return step, 0
    for start in range(1, min(a.size - 1, 8)):
        step = regular_step(a[start:])
        if step is not None and a[start] - a[0] <= step * (1.0 + REGULAR_AXIS_TOLERANCE):
            return step, start
    return None, 0


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
    depth_m = np.array(target_k.depth_m, dtype=float, order="C")
    range_m = np.array(target_k.range_m, dtype=float, order="C")
    (dz, z_start), dr = regular_part(depth_m), regular_step(range_m)
    regular = dz is not None and dr is not None
    return DepthTable(depth_m=depth_m, range_m=range_m, k_db=target_k.level_table(),
                      j0=np.array(j0, dtype=np.int64), j1=np.array(j1, dtype=np.int64),
                      w1=np.array(w1, dtype=float), regular=bool(regular),
                      depth_first_m=float(depth_m[z_start]), depth_inv_step=1.0 / dz if regular else 1.0,
                      range_first_m=float(range_m[0]), range_inv_step=1.0 / dr if regular else 1.0,
                      depth_regular_from=int(z_start) if regular else 0)
