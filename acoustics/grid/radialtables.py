"""A bearing-dependent grid: N x 2D radials from the observer at an origin (a face,
``acoustics.grid.face``); an atlas's tables at one observer position are such tables, mixed in dB
from the positions around it (``acoustics.grid.atlas.follow``)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from acoustics.grid.face import OBSERVER_DEPTH_TOLERANCE_M, OriginOffset, Tables
from acoustics.grid.lookup import along_radials, at_bearings, bearing_weights, bilinear, mix, nearest_radial


@dataclass(frozen=True, eq=False, kw_only=True)
class RadialTables(Tables):
    """A bearing-dependent grid: N x 2D radials from the observer at an origin.

    Attributes (beyond `Tables`)
    ----------------------------
    bearing_deg : ndarray, shape (N,)
        Radials, deg clockwise from true north at the origin.
    bottom_depth_m : ndarray, shape (N, R)
        Water depth along each radial, m; NaN beyond land.
    origin_lat_deg, origin_lon_deg : float
        The origin (WGS84).
    tl_parts : tuple of (float, ndarray)
        Tables mixed from others (an atlas's at a position): the weights and TL slabs (C, M, N,
        D, R) of the tables mixed, ``tl_db`` None; the weighted TL is formed the first time it
        is asked for (K at another target depth), never for K alone.
    everywhere : bool
        Read as if computed wherever the observer is (`Tables.as_everywhere`): no distance from
        the origin.
    """

    bearing_deg: np.ndarray
    bottom_depth_m: np.ndarray
    origin_lat_deg: float
    origin_lon_deg: float
    tl_parts: tuple = ()
    everywhere: bool = False
    _depth_role = "observer"

    @property
    def bearing_axis_deg(self) -> np.ndarray:
        return self.bearing_deg

    @property
    def depth_range_m(self) -> tuple[float, float]:
        return (self.observer_depth_m - OBSERVER_DEPTH_TOLERANCE_M,
                self.observer_depth_m + OBSERVER_DEPTH_TOLERANCE_M)

    def depth_problem(self, depth_m: float) -> str:
        return (f"{depth_m:g} m is not the observer depth {self.observer_depth_m:g} m "
                f"of the bearing-dependent grid (its TL is computed from the observer; rebuild it "
                f"with [observer] depth_m = {depth_m:g})")

    @property
    def serves_target_depth(self) -> bool:
        return True

    def observer_tl_db(self) -> np.ndarray:
        if self.tl_db is not None:
            return self.tl_db
        key = ("mixed-tl",)
        if key not in self._cache:
            self._cache[key] = weighted_sum(self.tl_parts)
        return self._cache[key]

    def _need_bearing(self, bearing_deg) -> None:
        if bearing_deg is None:
            raise ValueError(f"{self.source}: the grid depends on bearing; give bearing_deg")

    def k_db(self, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        self._need_bearing(bearing_deg)
        if depth_m is not None:
            self.check_depth(depth_m)
        j0, j1, w1 = bearing_weights(self.bearing_deg, bearing_deg)
        # (C, M, R), or (C, M, B, R) for B bearings
        return mix(self.k_grid_db[:, :, j0], self.k_grid_db[:, :, j1], np.asarray(w1)[..., None])

    def k_at(self, ic: int, range_m, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        self._need_bearing(bearing_deg)
        if depth_m is not None:
            self.check_depth(depth_m)
        return along_radials(self.k_grid_db[ic], self.bearing_deg, self.range_m, range_m, bearing_deg)

    def tl_at(self, ic: int, ib: int, depth_m, range_m, bearing_deg=None) -> np.ndarray:
        self._need_bearing(bearing_deg)
        d, r = np.broadcast_arrays(np.asarray(depth_m, dtype=float), np.asarray(range_m, dtype=float))
        self.check_point_depth(d)
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.broadcast_to(bearing_deg, d.shape))
        t = self.observer_tl_db()[ic, ib]                               # (N, D, R)
        out = np.zeros(d.shape)
        for j in np.unique(np.concatenate([j0.ravel(), j1.ravel()])):
            a = bilinear(t[j], self.depth_m, self.range_m, d, r)
            for jj, w in ((j0, 1.0 - w1), (j1, w1)):
                take = (jj == j) & (w > 0)  # a radial of weight 0 adds nothing, even a NaN
                out = out + np.where(take, w * a, 0.0)
        return out

    def k_typical_db(self, ic: int, ib: int, range_m) -> np.ndarray:
        at = np.asarray(range_m, dtype=float)
        along = np.stack([np.interp(at, self.range_m, row) for row in self.k_grid_db[ic, ib]])
        finite = np.isfinite(along).any(axis=0)
        out = np.full(at.shape, np.nan)
        out[finite] = np.nanmedian(along[:, finite], axis=0)
        return out

    def bearing_key(self, bearing_deg):
        self._need_bearing(bearing_deg)
        return round(float(bearing_deg), 3)

    def k_error_lookup(self, ic: int, range_m: np.ndarray, bearing_deg) -> np.ndarray:
        self._need_bearing(bearing_deg)
        return along_radials(self.k_error_sd_grid_db[ic], self.bearing_deg, self.range_m, range_m, bearing_deg)

    def geometry(self) -> dict[str, float | int | str]:
        bottom = self.bottom_depth_m
        return {"origin_lat_deg": self.origin_lat_deg, "origin_lon_deg": self.origin_lon_deg,
                "radials": int(self.bearing_deg.size), "bottom_min_m": float(np.nanmin(bottom)),
                "bottom_max_m": float(np.nanmax(bottom)),
                "beyond_land_fraction": float(np.mean(np.isnan(bottom))),
                "k_typical": "median over bearings"}

    def as_everywhere(self) -> RadialTables:
        return replace(self, everywhere=True, _cache={})

    def observer_offset(self, x_m, y_m) -> OriginOffset | None:
        if self.everywhere:
            return None
        away = np.hypot(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
        return OriginOffset(distance_m=float(np.max(away)) if away.size else 0.0,
                            origin_lat_deg=self.origin_lat_deg, origin_lon_deg=self.origin_lon_deg)

    # -- what the figures of the radials draw ---------------------------------------------------

    def bottom_at(self, bearing_deg) -> np.ndarray:
        """Water depth along the range axis at given bearings, (B, R), m (linear between radials)."""
        return at_bearings(self.bottom_depth_m, self.bearing_deg, np.atleast_1d(bearing_deg))

    def nearest_radial(self, bearing_deg: float) -> int:
        """Index of the radial nearest to a bearing (a TL section does not mix two bottoms)."""
        return nearest_radial(self.bearing_deg, bearing_deg)


def weighted_sum(parts) -> np.ndarray:
    """The weighted sum of arrays ``[(weight, array), ...]``, float64 (NaN where any array of
    weight > 0 is NaN): how tables are mixed in dB."""
    out = None
    for w, a in parts:
        term = w * np.asarray(a, dtype=float)
        out = term if out is None else out + term
    return out
