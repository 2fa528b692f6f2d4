"""The lookup kernels: how a value is read between the cells of a table, for every face.

One rule, for the trackers, the simulator and the figures alike: linear in depth, range and
bearing; ranges outside the axis take the end values; NaN where the table has no value.

- depth (`tl_at_depths`): linear between the axis' depths; a depth below the axis' last one
  has no value (NaN); a table on a single depth (K-only or one-receiver grids) gives that row
  at every depth. The sensitivity studies read a member's TL on the nominal area's depths with
  it too.
- range (`range_cells`, `at_ranges`): the two cells around each range, clipped to the axis.
- bearing (`bearing_weights`, `mix`, `at_bearings`; README "Real areas": the trackers and the
  simulator take K interpolated between radials): the two radials around a bearing
  (clockwise), weighted linearly by the angle from each; a radial of weight 0 does not count,
  even where it holds NaN, so a bearing on a radial gives that radial's values exactly. A TL
  section takes the nearest radial instead (`nearest_radial`): TL over two different bottoms
  does not mix.
- depth and range together (`bilinear`, `slab_bilinear`), and both over radials
  (`along_radials`).
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


def range_cells(x: np.ndarray, r: np.ndarray):
    """Cells of the range axis ``x`` around ranges ``r`` (clipped to the axis) and the weight of
    the second: ``(i, i1, fr)``."""
    rc = np.clip(r, x[0], x[-1])
    i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, max(x.size - 2, 0))
    fr = (rc - x[i]) / (x[i + 1] - x[i]) if x.size > 1 else np.zeros(r.shape)
    return i, np.minimum(i + 1, x.size - 1), fr


def axis_cells(axis: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Indices around values on an increasing axis and the weight of the second; the ends held.

    A value on a node takes it as the second cell with weight 1 (`range_cells` takes it as the
    first with weight 0): where the neighbour holds NaN the two differ, so each reader keeps
    the one it was measured with (an atlas's sampled points use this one)."""
    v = np.clip(values, axis[0], axis[-1])
    i1 = np.clip(np.searchsorted(axis, v, side="left"), 1, max(axis.size - 1, 1)) if axis.size > 1 else \
        np.zeros(v.shape, int)
    i0 = np.maximum(i1 - 1, 0)
    span = axis[i1] - axis[i0]
    w = np.where(span > 0, (v - axis[i0]) / np.where(span > 0, span, 1.0), 0.0)
    return i0, i1, w


def at_ranges(table: np.ndarray, range_axis: np.ndarray, range_m) -> np.ndarray:
    """``table(M, R)`` at ranges, linear (ends held): shape ``range_m.shape + (M,)``."""
    i, i1, fr = range_cells(range_axis, np.asarray(range_m, dtype=float))
    return np.moveaxis((1.0 - fr) * table[:, i] + fr * table[:, i1], 0, -1)


def along_radials(table: np.ndarray, bearing_axis: np.ndarray, range_axis: np.ndarray, range_m,
                  bearing_deg) -> np.ndarray:
    """``table(M, N, R)`` at ranges and bearings (broadcast to the ranges' shape): linear in
    range along the two radials around each bearing, then between them (`mix`); shape
    ``range_m.shape + (M,)``."""
    r = np.asarray(range_m, dtype=float)
    i, i1, fr = range_cells(range_axis, r)
    j0, j1, w1 = bearing_weights(bearing_axis, np.broadcast_to(bearing_deg, r.shape))
    along0 = (1.0 - fr) * table[:, j0, i] + fr * table[:, j0, i1]
    along1 = (1.0 - fr) * table[:, j1, i] + fr * table[:, j1, i1]
    return np.moveaxis(mix(along0, along1, w1), 0, -1)


def bilinear(table: np.ndarray, z: np.ndarray, x: np.ndarray, d: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``table(depth, range)`` at (d, r), bilinear; ranges outside the axis take the end values
    (depths are checked against the axis by the caller)."""
    rc = np.clip(r, x[0], x[-1])
    i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, x.size - 2)
    fr = (rc - x[i]) / (x[i + 1] - x[i])
    if z.size == 1:
        return (1.0 - fr) * table[0, i] + fr * table[0, i + 1]
    j = np.clip(np.searchsorted(z, d, side="right") - 1, 0, z.size - 2)
    fz = (d - z[j]) / (z[j + 1] - z[j])
    low = (1.0 - fr) * table[j, i] + fr * table[j, i + 1]
    high = (1.0 - fr) * table[j + 1, i] + fr * table[j + 1, i + 1]
    return (1.0 - fz) * low + fz * high


def slab_bilinear(k: np.ndarray, j: np.ndarray, z: np.ndarray, x: np.ndarray, d: np.ndarray,
                  r: np.ndarray) -> np.ndarray:
    """Slab ``j`` of ``k`` (J, Z, R) at depths ``d`` and ranges ``r``, both ends held; a cell
    of weight 0 does not count (even a NaN)."""
    i, i1, fr = range_cells(x, r)
    dc = np.clip(d, z[0], z[-1])
    m = np.clip(np.searchsorted(z, dc, side="right") - 1, 0, max(z.size - 2, 0))
    m1 = np.minimum(m + 1, z.size - 1)
    fz = (dc - z[m]) / (z[m1] - z[m]) if z.size > 1 else np.zeros(d.shape)
    low = (1.0 - fr) * k[j, m, i] + fr * k[j, m, i1]
    high = (1.0 - fr) * k[j, m1, i] + fr * k[j, m1, i1]
    return mix(low, high, fz)


def bearing_weights(bearings_deg: np.ndarray, bearing_deg) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The two radials around each bearing and the weight of the second.

    Parameters
    ----------
    bearings_deg : ndarray, shape (N,)
        The grid's radials, deg, increasing in [0, 360).
    bearing_deg : array_like
        Bearings to interpolate at, deg (taken modulo 360).

    Returns
    -------
    j0, j1 : ndarray of int
        Indices of the radials before and after each bearing (clockwise).
    w1 : ndarray
        Weight of radial ``j1``; ``1 - w1`` that of ``j0``.
    """
    grid = np.asarray(bearings_deg, dtype=float)
    b = np.mod(np.asarray(bearing_deg, dtype=float), 360.0)
    n = grid.size
    if n == 1:
        zero = np.zeros(b.shape, dtype=int)
        return zero, zero, np.zeros(b.shape)
    j1 = np.searchsorted(grid, b, side="right") % n
    j0 = (j1 - 1) % n
    span = np.mod(grid[j1] - grid[j0], 360.0)
    span = np.where(span == 0.0, 360.0, span)
    w1 = np.mod(b - grid[j0], 360.0) / span
    return j0, j1, w1


def at_bearings(values, bearings_deg: np.ndarray, bearing_deg) -> np.ndarray:
    """Values on the radials (bearing the first axis) at other bearings, linear between radials.

    Parameters
    ----------
    values : array_like, shape (N, ...)
        One entry per radial of ``bearings_deg``.
    bearings_deg : ndarray, shape (N,)
        The grid's radials, deg, increasing in [0, 360).
    bearing_deg : array_like, shape (B,) or scalar
        Bearings wanted, deg.

    Returns
    -------
    ndarray, shape (B, ...) (or ``values.shape[1:]`` for a scalar bearing)
        NaN where a radial of non-zero weight holds NaN.
    """
    v = np.asarray(values, dtype=float)
    j0, j1, w1 = bearing_weights(bearings_deg, bearing_deg)
    return mix(v[j0], v[j1], np.reshape(w1, np.shape(w1) + (1,) * (v.ndim - 1)))


def mix(a0, a1, w1):
    """(1 - w1) a0 + w1 a1, where a value of weight 0 does not count (even a NaN)."""
    return np.where(w1 <= 0.0, a0, np.where(w1 >= 1.0, a1, (1.0 - w1) * a0 + w1 * a1))


def nearest_radial(bearings_deg: np.ndarray, bearing_deg: float) -> int:
    """Index of the radial nearest to a bearing, across 0/360 (halfway: the one before it,
    counter-clockwise)."""
    j0, j1, w1 = bearing_weights(bearings_deg, bearing_deg)
    return int(j1) if float(w1) > 0.5 else int(j0)
