"""A bearing-dependent grid: N x 2D radials from the observer at an origin (the face of
``acoustics.grid.face``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.grid.face import OBSERVER_DEPTH_TOLERANCE_M, GridTables, OriginOffset, _bilinear, _range_cells
from acoustics.grid.radialinterp import at_bearings, bearing_weights, mix, nearest_radial


@dataclass(frozen=True, eq=False, kw_only=True)
class RadialTables(GridTables):
    """A bearing-dependent grid: N x 2D radials from the observer at an origin.

    Attributes (beyond `GridTables`)
    --------------------------------
    bearing_deg : ndarray, shape (N,)
        Radials, deg clockwise from true north at the origin.
    bottom_depth_m : ndarray, shape (N, R)
        Water depth along each radial, m; NaN beyond land.
    origin_lat_deg, origin_lon_deg : float
        The origin (WGS84).
    """

    bearing_deg: np.ndarray
    bottom_depth_m: np.ndarray
    origin_lat_deg: float
    origin_lon_deg: float
    _depth_role = "observer"

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

    def _observer_tl_db(self) -> np.ndarray:
        return self.tl_db

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
        r = np.asarray(range_m, dtype=float)
        i, i1, fr = _range_cells(self.range_m, r)
        if depth_m is not None:
            self.check_depth(depth_m)
        kc = self.k_grid_db[ic]                                         # (M, N, R)
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.broadcast_to(bearing_deg, r.shape))
        along0 = (1.0 - fr) * kc[:, j0, i] + fr * kc[:, j0, i1]
        along1 = (1.0 - fr) * kc[:, j1, i] + fr * kc[:, j1, i1]
        return np.moveaxis(mix(along0, along1, w1), 0, -1)

    def tl_at(self, ic: int, ib: int, depth_m, range_m, bearing_deg=None) -> np.ndarray:
        self._need_bearing(bearing_deg)
        d, r = np.broadcast_arrays(np.asarray(depth_m, dtype=float), np.asarray(range_m, dtype=float))
        self._check_point_depth(d)
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.broadcast_to(bearing_deg, d.shape))
        t = self._observer_tl_db()[ic, ib]                              # (N, D, R)
        out = np.zeros(d.shape)
        for j in np.unique(np.concatenate([j0.ravel(), j1.ravel()])):
            a = _bilinear(t[j], self.depth_m, self.range_m, d, r)
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

    def _bearing_key(self, bearing_deg):
        self._need_bearing(bearing_deg)
        return round(float(bearing_deg), 3)

    def _k_error_lookup(self, ic: int, range_m: np.ndarray, bearing_deg) -> np.ndarray:
        self._need_bearing(bearing_deg)
        i, i1, fr = _range_cells(self.range_m, range_m)
        sd = self.k_error_sd_grid_db[ic]                                # (M, N, R)
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.broadcast_to(bearing_deg, range_m.shape))
        along0 = (1.0 - fr) * sd[:, j0, i] + fr * sd[:, j0, i1]
        along1 = (1.0 - fr) * sd[:, j1, i] + fr * sd[:, j1, i1]
        return np.moveaxis(mix(along0, along1, w1), 0, -1)

    def geometry(self) -> dict[str, float | int | str]:
        bottom = self.bottom_depth_m
        return {"origin_lat_deg": self.origin_lat_deg, "origin_lon_deg": self.origin_lon_deg,
                "radials": int(self.bearing_deg.size), "bottom_min_m": float(np.nanmin(bottom)),
                "bottom_max_m": float(np.nanmax(bottom)),
                "beyond_land_fraction": float(np.mean(np.isnan(bottom))),
                "k_typical": "median over bearings"}

    def observer_offset(self, x_m, y_m) -> OriginOffset | None:
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
