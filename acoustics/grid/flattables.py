"""A grid without bearings: one profile over a flat bottom (a face, ``acoustics.grid.face``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.grid.face import OBSERVER_DEPTH_TOLERANCE_M, OriginOffset, Tables
from acoustics.grid.lookup import at_ranges, bilinear, tl_at_depths


@dataclass(frozen=True, eq=False, kw_only=True)
class FlatTables(Tables):
    """A grid without bearings: one profile over a flat bottom, the same along every bearing.

    Attributes (beyond `Tables`)
    ----------------------------
    tl_obs_db : ndarray, shape (C, M, D, R), or None
        Band TL from a source at the observer depth to a receiver at ``depth_m``, dB (by
        reciprocity the loss from a target there to the observer); None in grids built before
        it was written.
    """

    tl_obs_db: np.ndarray | None = None
    _depth_role = "receiver"

    @property
    def depth_range_m(self) -> tuple[float, float]:
        if self.target_depth_m is not None:  # K for another target depth: the observer's only
            return (self.observer_depth_m - OBSERVER_DEPTH_TOLERANCE_M,
                    self.observer_depth_m + OBSERVER_DEPTH_TOLERANCE_M)
        return float(self.depth_m[0]), float(self.depth_m[-1])

    def depth_problem(self, depth_m: float) -> str:
        if self.target_depth_m is not None:
            return (f"{depth_m:g} m is not the grid's observer depth {self.observer_depth_m:g} m "
                    f"(with the target at {self.target_depth_m:g} m the grid has TL from the "
                    f"observer depth only)")
        lo, hi = self.depth_range_m
        return f"{depth_m:g} m is outside the grid's depth axis [{lo:g}, {hi:g}] m"

    @property
    def serves_target_depth(self) -> bool:
        return self.tl_obs_db is not None

    def observer_tl_db(self) -> np.ndarray:
        return self.tl_obs_db

    def _tl_rows(self, depth_m: float) -> np.ndarray:
        """TL of every class and band along range at one depth, linear in depth, (C, M, R)."""
        return tl_at_depths(self.tl_db, self.depth_m, [depth_m])[:, :, 0]

    def k_db(self, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        if depth_m is None:
            return self.k_grid_db
        d = float(depth_m)
        if d == self.observer_depth_m:
            return self.k_grid_db
        if self.target_depth_m is not None:
            self.check_depth(d)  # within the observer tolerance: the one K there is
            return self.k_grid_db
        key = ("k", d)
        if key not in self._cache:
            self.check_depth(d)
            self._cache[key] = self.k_grid_db + self._tl_rows(self.observer_depth_m) - self._tl_rows(d)
        return self._cache[key]

    def k_at(self, ic: int, range_m, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        return at_ranges(self.k_db(depth_m)[ic], self.range_m, range_m)

    def tl_at(self, ic: int, ib: int, depth_m, range_m, bearing_deg=None) -> np.ndarray:
        d, r = np.broadcast_arrays(np.asarray(depth_m, dtype=float), np.asarray(range_m, dtype=float))
        self.check_depth(d)
        return bilinear(self.tl_db[ic, ib], self.depth_m, self.range_m, d, r)

    def k_typical_db(self, ic: int, ib: int, range_m) -> np.ndarray:
        return np.interp(np.asarray(range_m, dtype=float), self.range_m, self.k_grid_db[ic, ib])

    def bearing_key(self, bearing_deg):
        return None

    def k_error_lookup(self, ic: int, range_m: np.ndarray, bearing_deg) -> np.ndarray:
        return at_ranges(self.k_error_sd_grid_db[ic], self.range_m, range_m)

    def geometry(self) -> dict[str, float | int | str]:
        return {}

    def observer_offset(self, x_m, y_m) -> OriginOffset | None:
        return None
