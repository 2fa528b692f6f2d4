"""Inputs of the compiled loop for the target's depth as a state: the K table (every band) and
the depth model, in named groups as `tracker.rpf.kernel.params`, and how they are built."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from tracker.rpf.depthlevel import cycle_bearings_deg, level_arrays


class DepthTable(NamedTuple):
    """K against the target's depth and range, per band and radial, and each cycle's two radials.

    Attributes
    ----------
    depth_m : ndarray, shape (Z,)
        Target depths, m, increasing.
    range_m : ndarray, shape (R,)
        Ranges, m, increasing.
    k_db : ndarray, shape (B, J, Z, R)
        K of each band, dB, the cells without water at the penalty (`TargetDepthK.level_table`).
    k_sd_db : ndarray, shape (B, J, Z, R), or (1, 1, 1, 1) without one
        sd of K's error there, dB: the level's variance is sigma_l^2 + sd^2 (`has_sd`).
    has_sd : bool
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
    depth_regular_from : int
        The depth axis is regular from this index (near-surface rows before).
    """

    depth_m: np.ndarray
    range_m: np.ndarray
    k_db: np.ndarray
    k_sd_db: np.ndarray
    has_sd: bool
    j0: np.ndarray
    j1: np.ndarray
    w1: np.ndarray
    regular: bool
    depth_first_m: float
    depth_inv_step: float
    range_first_m: float
    range_inv_step: float
    depth_regular_from: int


class DepthModel(NamedTuple):
    """The depth state: whether there is one, its span (uniform prior, reflecting walls) and its
    random walk.

    Attributes
    ----------
    on : bool
        The target's depth is the state's last component (else the level model is `Profiles`).
    lo_m, hi_m : float
        The span, m.
    walk_m_per_sqrt_s : float
        Random-walk sd per square root of time, m s^-1/2.
    """

    on: bool
    lo_m: float
    hi_m: float
    walk_m_per_sqrt_s: float


def no_depth(n_cycles: int) -> tuple[DepthTable, DepthModel]:
    """The table and model of a loop with the depth fixed (the level model is `Profiles`): the
    same types, one cell."""
    one = np.zeros((1, 1, 1, 1))
    zero = np.zeros(n_cycles, dtype=np.int64)
    return (DepthTable(depth_m=np.zeros(1), range_m=np.ones(1), k_db=one, k_sd_db=one.copy(),
                       has_sd=False, j0=zero, j1=zero.copy(), w1=np.zeros(n_cycles), regular=False,
                       depth_first_m=0.0, depth_inv_step=1.0, range_first_m=1.0, range_inv_step=1.0,
                       depth_regular_from=0),
            DepthModel(on=False, lo_m=0.0, hi_m=0.0, walk_m_per_sqrt_s=0.0))


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


def depth_table(target_k, bearing_deg, n_cycles: int, *, smoothing=None) -> DepthTable:
    """The kernel's table from the `acoustics.grid.targetdepth.TargetDepthK` of each band (one,
    or a sequence) and the bearing of each cycle, deg (NaN: the last bearing measured before
    it; before any, the first one).

    ``smoothing`` (a `tracker.kstructure.RangeSmoothing`): K averaged over that range
    uncertainty, its spread there the sd of K's error (`has_sd`); None: K as it is.
    """
    first = (list(target_k) if isinstance(target_k, (list, tuple)) else [target_k])[0]
    j0, j1, w1 = first.cells(cycle_bearings_deg(bearing_deg, n_cycles))
    depth_m = np.array(first.depth_m, dtype=float, order="C")
    range_m = np.array(first.range_m, dtype=float, order="C")
    k_db, k_sd = level_arrays(target_k, smoothing)
    has_sd = k_sd is not None
    if not has_sd:
        k_sd = np.zeros((1, 1, 1, 1))
    (dz, z_start), dr = regular_part(depth_m), regular_step(range_m)
    regular = dz is not None and dr is not None
    return DepthTable(depth_m=depth_m, range_m=range_m, k_db=k_db, k_sd_db=k_sd, has_sd=bool(has_sd),
                      j0=np.array(j0, dtype=np.int64), j1=np.array(j1, dtype=np.int64),
                      w1=np.array(w1, dtype=float), regular=bool(regular),
                      depth_first_m=float(depth_m[z_start]), depth_inv_step=1.0 / dz if regular else 1.0,
                      range_first_m=float(range_m[0]), range_inv_step=1.0 / dr if regular else 1.0,
                      depth_regular_from=int(z_start) if regular else 0)
