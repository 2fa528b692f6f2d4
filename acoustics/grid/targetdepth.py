"""K against the target's depth and range: what a tracker with an unknown target depth reads.

A class's tables are computed at one depth; a submarine may be elsewhere in the water. K at a
target depth z is the spectral term less the band TL between the observer and a point at z:

    K(z, r) = S - TL_obs(z, r)    (Grinenkov & Mashoshin eqs. 12-13),

TL_obs from the observer end: on a bearing-dependent grid ``tl_db`` itself (computed from the
observer at the origin), on a flat grid ``tl_obs_db`` (runs with the source at the observer
depth; by reciprocity the loss from a target at z to the observer). `TargetDepthK` holds it
for one class and band, bearing by bearing: a (depth, range) slab per radial (one slab on a
flat grid), NaN below the bottom and beyond land. Between depths and ranges it is bilinear,
between radials linear (``acoustics.grid.radialinterp``: a radial of weight 0 does not count).

The trackers' rule for where the table has no value (`level_table`): as
``acoustics.grid.tables.LevelProfile``, the smallest K less ``BEYOND_GRID_PENALTY_DB`` (no
target gives that level), and beyond the range axis the last value less the same penalty.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.grid.radialinterp import bearing_weights, nearest_radial
from acoustics.levelrange import BEYOND_GRID_PENALTY_DB


@dataclass(frozen=True, slots=True, kw_only=True)
class TargetDepthK:
    """K(depth, range) of one class and band with the target at any depth, per radial.

    Attributes
    ----------
    bearing_deg : ndarray, shape (N,)
        The radials, deg; empty for a flat grid (one slab serves every bearing).
    depth_m : ndarray, shape (Z,)
        Target depths, m, increasing.
    range_m : ndarray, shape (R,)
        Ranges, m, increasing.
    k_db : ndarray, shape (max(N, 1), Z, R)
        K with the target at ``depth_m``, ``range_m`` along each radial, dB; NaN where the grid
        has no water.
    """

    bearing_deg: np.ndarray
    depth_m: np.ndarray
    range_m: np.ndarray
    k_db: np.ndarray

    def cells(self, bearing_deg) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The two slabs around bearings and the weight of the second (all 0 on a flat grid)."""
        b = np.asarray(bearing_deg, dtype=float)
        if self.bearing_deg.size == 0:
            zero = np.zeros(b.shape, dtype=np.int64)
            return zero, zero, np.zeros(b.shape)
        j0, j1, w1 = bearing_weights(self.bearing_deg, b)
        return j0.astype(np.int64), j1.astype(np.int64), np.asarray(w1, dtype=float)

    def nearest_slab(self, bearing_deg: float | None = None) -> tuple[int, float | None]:
        """The slab of the radial nearest to a bearing (across 0/360), and that radial's bearing,
        deg; without a bearing the first radial. A flat grid's one slab serves every bearing:
        (0, None)."""
        if self.bearing_deg.size == 0:
            return 0, None
        j = 0 if bearing_deg is None else nearest_radial(self.bearing_deg, float(bearing_deg))
        return j, float(self.bearing_deg[j])

    def at(self, depth_m, range_m, bearing_deg=0.0) -> np.ndarray:
        """K at target depths, ranges and bearings (broadcast together), dB: bilinear in depth
        and range (ends held), linear between radials; NaN where the grid has no water."""
        d, r, b = np.broadcast_arrays(np.asarray(depth_m, dtype=float),
                                      np.asarray(range_m, dtype=float),
                                      np.asarray(bearing_deg, dtype=float))
        j0, j1, w1 = self.cells(b)
        k0 = _bilinear(self.k_db, j0, self.depth_m, self.range_m, d, r)
        k1 = _bilinear(self.k_db, j1, self.depth_m, self.range_m, d, r)
        return np.where(w1 <= 0.0, k0, np.where(w1 >= 1.0, k1, (1.0 - w1) * k0 + w1 * k1))

    def water_depth_m(self) -> float:
        """The deepest depth of the axis with a finite K at some range and bearing, m."""
        wet = np.isfinite(self.k_db).any(axis=(0, 2))
        return float(self.depth_m[wet][-1]) if wet.any() else float(self.depth_m[0])

    def level_table(self) -> np.ndarray:
        """``k_db`` with the trackers' rule for cells without water: the smallest finite K less
        ``BEYOND_GRID_PENALTY_DB`` (float64, C order, for the compiled kernel)."""
        k = np.array(self.k_db, dtype=float, order="C")
        finite = k[np.isfinite(k)]
        floor = (finite.min() if finite.size else 0.0) - BEYOND_GRID_PENALTY_DB
        k[~np.isfinite(k)] = floor
        return k


def _bilinear(k: np.ndarray, j: np.ndarray, z: np.ndarray, x: np.ndarray, d: np.ndarray,
              r: np.ndarray) -> np.ndarray:
    """Slab ``j`` of ``k`` (J, Z, R) at depths ``d`` and ranges ``r``, ends held."""
    rc = np.clip(r, x[0], x[-1])
    i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, max(x.size - 2, 0))
    i1 = np.minimum(i + 1, x.size - 1)
    fr = (rc - x[i]) / (x[i1] - x[i]) if x.size > 1 else np.zeros(r.shape)
    dc = np.clip(d, z[0], z[-1])
    m = np.clip(np.searchsorted(z, dc, side="right") - 1, 0, max(z.size - 2, 0))
    m1 = np.minimum(m + 1, z.size - 1)
    fz = (dc - z[m]) / (z[m1] - z[m]) if z.size > 1 else np.zeros(d.shape)
    low = (1.0 - fr) * k[j, m, i] + fr * k[j, m, i1]
    high = (1.0 - fr) * k[j, m1, i] + fr * k[j, m1, i1]
    return np.where(fz <= 0.0, low, np.where(fz >= 1.0, high, (1.0 - fz) * low + fz * high))


__all__ = ["TargetDepthK"]
