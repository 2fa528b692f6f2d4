"""K against the target's depth and range: what a tracker with an unknown target depth reads.

A class's tables are computed at one depth; a submarine may be elsewhere in the water. K at a
target depth z is the spectral term less the band TL between the observer and a point at z:

    K(z, r) = S - TL_obs(z, r)    (Grinenkov & Mashoshin eqs. 12-13),

TL_obs from the observer end: on a bearing-dependent grid ``tl_db`` itself (computed from the
observer at the origin), on a flat grid ``tl_obs_db`` (runs with the source at the observer
depth; by reciprocity the loss from a target at z to the observer). `TargetDepthK` holds it
for one class and band, bearing by bearing: a (depth, range) slab per radial (one slab on a
flat grid), NaN below the bottom and beyond land. Between depths and ranges it is bilinear,
between radials linear (``acoustics.grid.lookup``: a radial of weight 0 does not count).

The trackers' rule for where the table has no value (`level_table`): as
``acoustics.grid.levelprofile.LevelProfile``, the smallest K less ``BEYOND_GRID_PENALTY_DB`` (no
target gives that level), and beyond the range axis the last value less the same penalty.

The faces answer through the functions below (``Tables.target_depth_k``,
``Tables.target_depth_span_m``, ``Tables.at_target_depth``): K from the TL the face holds from
the observer (``Tables.observer_tl_db``) and the classes' spectral terms.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.grid.lookup import bearing_weights, mix, nearest_radial, slab_bilinear, tl_at_depths
from acoustics.kcurve import spectral_term_db
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
        k0 = slab_bilinear(self.k_db, j0, self.depth_m, self.range_m, d, r)
        k1 = slab_bilinear(self.k_db, j1, self.depth_m, self.range_m, d, r)
        return mix(k0, k1, w1)

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


def spectral_db(tables) -> np.ndarray:
    """The spectral term S of every class and band of a face, (C, M), dB (eq. 13)."""
    return np.array([[spectral_term_db(cls, band) for band in tables.bands] for cls in tables.classes])


def target_depth_table(tables, ic: int, ib: int) -> TargetDepthK:
    """K of one class and band with the target at every depth of a face's axis, per radial:
    K(z, r) = S - TL_obs(z, r), S the class's spectral term in the band (eq. 13), TL_obs the band
    TL between the observer and a point at depth z (docs/formats.md, ``tl_obs_db``)."""
    tl = tables.observer_tl_db()[ic, ib]
    k = spectral_term_db(tables.classes[ic], tables.bands[ib]) - (tl if tl.ndim == 3 else tl[None])
    bearings = tables.bearing_axis_deg
    return TargetDepthK(bearing_deg=np.zeros(0) if bearings is None else np.asarray(bearings, dtype=float),
                        depth_m=tables.depth_m, range_m=tables.range_m, k_db=k)


def target_depth_span(tables, ic: int) -> tuple[float, float]:
    """Depths a target of class ``ic`` may be at, m: the class's ``depth_range_m``, else the
    water column a face holds (the top of the depth axis to the deepest water)."""
    cls = tables.classes[ic]
    if cls.depth_range_m is not None:
        return cls.depth_range_m
    wet = np.isfinite(tables.observer_tl_db()[ic, 0])
    wet = wet.any(axis=tuple(a for a in range(wet.ndim) if a != wet.ndim - 2))
    return float(tables.depth_m[0]), float(tables.depth_m[wet][-1] if wet.any() else tables.depth_m[-1])


def k_at_target_depth(tables, depth_m: float) -> np.ndarray:
    """K of every class and band of a face with the target at ``depth_m``, shaped like its
    ``k_grid_db``, dB: S - TL_obs at that depth (linear in depth)."""
    s = spectral_db(tables)
    tl = tl_at_depths(tables.observer_tl_db(), tables.depth_m, [float(depth_m)])[..., 0, :]
    return s.reshape(s.shape + (1,) * (tl.ndim - 2)) - tl


__all__ = ["TargetDepthK", "k_at_target_depth", "spectral_db", "target_depth_span", "target_depth_table"]
