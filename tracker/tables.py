"""The grid as the trackers and the simulator see it: K(r) and TL at a depth, bearing and range.

``GridTables.from_grid`` is the one way from a grid dataset to the trackers. It reads the area
stored in the grid (``area_json``, validated by ``envdata`` like an area file) and gives, for a
class and a band:

- the transfer characteristic K(r) (eq. 12: band level W = P0 + K(r) + H). In a grid without
  bearings (``fixed_end = "source"``) ``k_db`` holds K = S - TL at the grid's observer depth,
  and DESIGN.md takes K at the row's observer depth d:

      K(d, r) = k_db(r) + TL(d_grid, r) - TL(d, r),

  with TL linear in depth over ``tl_db(class, band, depth, range)``, so K(d_grid) is ``k_db``
  exactly. A grid without ``tl_db`` (K alone) has K at one depth and serves every depth. In a
  bearing-dependent grid (``fixed_end = "observer"``) TL was computed from the observer at the
  origin, at its depth: K is ``k_db(bearing, range)`` at that depth only, interpolated linearly
  between the two nearest radials (across 0/360 deg);
- TL, bilinear in depth and range (Iglesis & de Montella eq. 13), and in bearing.

One interpolation rule: linear in depth, range and bearing; ranges outside the axis take the
end values; NaN where the grid has no value (below the bottom, beyond land), which the
simulator reads as "not detected" and the filters' level model as a level no target gives
(``LevelProfile``). A receiver depth the tables cannot serve is a ``GridFileError``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.radialinterp import bearing_weights, mix
from acoustics.depthinterp import tl_at_depths
from acoustics.kcurve import spectral_term_db
from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from envdata.area import Area
from envdata.areafile import area_from_json
from envdata.bands import Band
from envdata.classes import TargetClass
from envdata.errors import AreaError

#: A bearing-dependent grid serves observers within this of its observer depth, m.
OBSERVER_DEPTH_TOLERANCE_M = 1.0


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelProfile:
    """K(r) at one receiver depth as the particle filters' level model uses it (W = SL + K(r)).

    Linear in range inside the axis, the first value below it, and beyond the last range the
    last value less `BEYOND_GRID_PENALTY_DB`: the grid's range axis is the horizon of the level
    model, and a particle beyond it keeps a weight only if every particle is beyond it. (Holding
    the end value lets a fast, receding target far outside the grid explain a steady level as
    well as the true one.) Ranges where the grid has no K (beyond land) get the smallest K less
    the same penalty.
    """

    range_m: np.ndarray
    k_db: np.ndarray

    def __post_init__(self) -> None:
        k = np.asarray(self.k_db, dtype=float)
        if not np.all(np.isfinite(k)):
            finite = k[np.isfinite(k)]
            floor = (finite.min() if finite.size else 0.0) - BEYOND_GRID_PENALTY_DB
            object.__setattr__(self, "k_db", np.where(np.isfinite(k), k, floor))

    def __call__(self, range_m) -> np.ndarray:
        """K at the given ranges, dB."""
        r = np.asarray(range_m, dtype=float)
        k = np.interp(r, self.range_m, self.k_db)
        return np.where(r > self.range_m[-1], k - BEYOND_GRID_PENALTY_DB, k)


@dataclass(frozen=True, eq=False, kw_only=True)
class GridTables:
    """K(r) and TL of every class and band of a grid, with the area they were computed for.

    Attributes
    ----------
    source : str
        The grid's name in messages (its file, else its area).
    area : Area
        The area stored in the grid.
    classes : tuple of TargetClass
        The grid's class hypotheses, in grid order.
    bands : tuple of Band
        The grid's bands, in grid order.
    range_m : ndarray, shape (R,)
        Horizontal ranges, m, increasing.
    k_grid_db : ndarray, shape (C, M, R), or (C, M, N, R) with bearings
        K(r) at the grid's observer depth, dB (eq. 12: band level W = P0 + K(r) + H).
    observer_depth_m : float
        Observer depth of ``k_grid_db``, m.
    depth_m : ndarray, shape (D,), or None
        Depths of ``tl_db``, m, increasing; None for a grid of K alone.
    tl_db : ndarray, shape (C, M, D, R), or (C, M, N, D, R) with bearings, or None
        Band transmission loss, dB: from the class's depth to a receiver at ``depth_m``, or
        with bearings from the observer at the origin to a point at ``depth_m``.
    bearing_deg : ndarray, shape (N,), or None
        Radials of a bearing-dependent grid, deg clockwise from true north at the origin.
    bottom_depth_m : ndarray, shape (N, R), or None
        Water depth along each radial, m; NaN beyond land.
    origin_lat_deg, origin_lon_deg : float
        The origin of a bearing-dependent grid (NaN without bearings).
    """

    source: str
    area: Area
    classes: tuple[TargetClass, ...]
    bands: tuple[Band, ...]
    range_m: np.ndarray
    k_grid_db: np.ndarray
    observer_depth_m: float
    depth_m: np.ndarray | None = None
    tl_db: np.ndarray | None = None
    bearing_deg: np.ndarray | None = None
    bottom_depth_m: np.ndarray | None = None
    origin_lat_deg: float = math.nan
    origin_lon_deg: float = math.nan
    _k_cache: dict = field(default_factory=dict, repr=False)

    @classmethod
    def from_grid(cls, grid: xr.Dataset, source: str | None = None) -> GridTables:
        """The tables of a grid dataset (``acoustics.open_grid``, or one built in memory).

        Raises
        ------
        GridFileError
            No or unreadable ``area_json``, or grid classes or bands the area does not have.
        """
        source = source or str(grid.encoding.get("source") or grid.attrs.get("area", "<grid>"))
        text = grid.attrs.get("area_json")
        if text is None:
            raise GridFileError(f"{source}: no area_json attribute; rebuild the grid with "
                                f"tmakit grids build")
        try:
            area = area_from_json(text, source)
        except AreaError as exc:
            raise GridFileError(str(exc)) from None
        class_names = [str(c) for c in grid["class"].values]
        band_names = [str(b) for b in grid["band"].values]
        by_class = {c.name: c for c in area.classes}
        by_band = {b.name: b for b in area.bands}
        for kind, names, known in (("class", class_names, by_class), ("band", band_names, by_band)):
            missing = [n for n in names if n not in known]
            if missing:
                raise GridFileError(f"{source}: {kind} {missing[0]!r} of the grid is not in its "
                                    f"area_json ({', '.join(known)})")
        lead = ("class", "band", "bearing") if "bearing" in grid.dims else ("class", "band")
        k = np.asarray(grid["k_db"].transpose(*lead, "range").values, dtype=float)
        depth = tl = None
        if "tl_db" in grid and "depth" in grid.dims:
            depth = np.asarray(grid["depth"].values, dtype=float)
            tl = np.asarray(grid["tl_db"].transpose(*lead, "depth", "range").values, dtype=float)
        extra = {}
        if "bearing" in grid.dims:
            extra = dict(bearing_deg=np.asarray(grid["bearing"].values, dtype=float),
                         bottom_depth_m=np.asarray(grid["bottom_depth_m"].transpose(
                             "bearing", "range").values, dtype=float),
                         origin_lat_deg=float(grid.attrs["origin_lat_deg"]),
                         origin_lon_deg=float(grid.attrs["origin_lon_deg"]))
        return cls(source=source, area=area, classes=tuple(by_class[n] for n in class_names),
                   bands=tuple(by_band[n] for n in band_names),
                   range_m=np.asarray(grid["range"].values, dtype=float), k_grid_db=k,
                   observer_depth_m=float(grid.attrs.get("observer_depth_m",
                                                         area.observer.depth_m)),
                   depth_m=depth, tl_db=tl, **extra)

    @property
    def by_bearing(self) -> bool:
        """Whether the tables depend on bearing (a grid with ``[origin]``)."""
        return self.bearing_deg is not None

    @property
    def class_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.classes)

    @property
    def band_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.bands)

    def class_index(self, name: str) -> int:
        """Index of a class hypothesis; GridFileError naming the grid's classes if absent."""
        if name not in self.class_names:
            raise GridFileError(f"{self.source}: class {name!r} is not in the grid (classes: "
                                f"{', '.join(self.class_names)})")
        return self.class_names.index(name)

    def band_index(self, name: str) -> int:
        """Index of a band; GridFileError naming the grid's bands if absent."""
        if name not in self.band_names:
            raise GridFileError(f"{self.source}: band {name!r} is not in the grid (bands: "
                                f"{', '.join(self.band_names)})")
        return self.band_names.index(name)

    @property
    def noise_band_db(self) -> np.ndarray:
        """Sea-noise level in each band, dB re 1 uPa (the spectral level for one frequency)."""
        return np.array([self.area.noise.band_level_db(b) for b in self.bands])

    @property
    def bandwidth_hz(self) -> np.ndarray:
        """Bandwidth of each band in eqs. 11 and 13, Hz (1 Hz for a single frequency)."""
        return np.array([b.width_hz for b in self.bands])

    def spectral_db(self, ic: int, ib: int) -> float:
        """Spectral term S of class ``ic`` in band ``ib``, dB: K = S - TL (eq. 13)."""
        return spectral_term_db(self.classes[ic], self.bands[ib])

    def distance_from_origin_m(self, x_m, y_m) -> np.ndarray:
        """How far an observer position (x east, y north of the origin, m) is from the origin."""
        return np.hypot(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))

    @property
    def depth_range_m(self) -> tuple[float, float]:
        """Observer depths the tables serve, m: the depth axis, or with bearings the grid's own
        observer depth within `OBSERVER_DEPTH_TOLERANCE_M` (-inf, inf for a grid of K alone)."""
        if self.by_bearing:
            return (self.observer_depth_m - OBSERVER_DEPTH_TOLERANCE_M,
                    self.observer_depth_m + OBSERVER_DEPTH_TOLERANCE_M)
        if self.depth_m is None:
            return -math.inf, math.inf
        return float(self.depth_m[0]), float(self.depth_m[-1])

    def outside_depth(self, depth_m) -> np.ndarray:
        """Mask of observer depths the tables cannot serve (all False for a grid of K alone)."""
        lo, hi = self.depth_range_m
        d = np.asarray(depth_m, dtype=float)
        return ~((d >= lo) & (d <= hi))

    def depth_problem(self, depth_m: float) -> str:
        """Why an observer depth cannot be served, for a message (after ``outside_depth``)."""
        lo, hi = self.depth_range_m
        if self.by_bearing:
            return (f"{depth_m:g} m is not the observer depth {self.observer_depth_m:g} m of the "
                    f"bearing-dependent grid (its TL is computed from the observer; rebuild it "
                    f"with [observer] depth_m = {depth_m:g})")
        return f"{depth_m:g} m is outside the grid's depth axis [{lo:g}, {hi:g}] m"

    def check_depth(self, depth_m, what: str = "") -> None:
        """Raise GridFileError if a receiver depth lies outside the depth axis."""
        bad = self.outside_depth(depth_m)
        if np.any(bad):
            value = float(np.asarray(depth_m, dtype=float)[bad].flat[0])
            if self.by_bearing:
                raise GridFileError(f"{self.source}: observer depth {self.depth_problem(value)}{what}")
            lo, hi = self.depth_range_m
            raise GridFileError(f"{self.source}: receiver depth {value:g} m is outside the grid's "
                                f"depth axis [{lo:g}, {hi:g}] m{what}")

    def _need_bearing(self, bearing_deg) -> None:
        if self.by_bearing and bearing_deg is None:
            raise ValueError(f"{self.source}: the grid depends on bearing; give bearing_deg")

    def _tl_rows(self, depth_m: float) -> np.ndarray:
        """TL of every class and band along range at one depth, linear in depth, (C, M, R)."""
        return tl_at_depths(self.tl_db, self.depth_m, [depth_m])[:, :, 0]

    def k_db(self, depth_m: float | None = None, bearing_deg: float | None = None) -> np.ndarray:
        """K(r) of every class and band at an observer depth (and bearing), dB, (C, M, R).

        ``None`` depth means the grid's observer depth; a grid of K alone gives its K at any
        depth. A bearing-dependent grid needs ``bearing_deg`` (from the observer to the target);
        an array of B bearings gives (C, M, B, R).
        """
        self._need_bearing(bearing_deg)
        if self.by_bearing:
            if depth_m is not None:
                self.check_depth(depth_m)
            j0, j1, w1 = bearing_weights(self.bearing_deg, bearing_deg)
            # (C, M, R), or (C, M, B, R) for B bearings
            return mix(self.k_grid_db[:, :, j0], self.k_grid_db[:, :, j1], np.asarray(w1)[..., None])
        if depth_m is None or self.tl_db is None:
            return self.k_grid_db
        d = float(depth_m)
        if d == self.observer_depth_m:
            return self.k_grid_db
        if d not in self._k_cache:
            self.check_depth(d)
            self._k_cache[d] = self.k_grid_db + self._tl_rows(self.observer_depth_m) - self._tl_rows(d)
        return self._k_cache[d]

    def k_at(self, ic: int, range_m, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        """K of class ``ic`` in every band at given ranges (and bearings), dB.

        Shape ``range_m.shape + (M,)``. Linear in range (ranges outside the axis take the end
        values) and in bearing; NaN where the grid has no value.
        """
        self._need_bearing(bearing_deg)
        r = np.asarray(range_m, dtype=float)
        x = self.range_m
        rc = np.clip(r, x[0], x[-1])
        i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, max(x.size - 2, 0))
        fr = (rc - x[i]) / (x[i + 1] - x[i]) if x.size > 1 else np.zeros(r.shape)
        i1 = np.minimum(i + 1, x.size - 1)
        if not self.by_bearing:
            kc = self.k_db(depth_m)[ic]                                 # (M, R)
            out = (1.0 - fr) * kc[:, i] + fr * kc[:, i1]                # (M, ...)
            return np.moveaxis(out, 0, -1)
        if depth_m is not None:
            self.check_depth(depth_m)
        kc = self.k_grid_db[ic]                                         # (M, N, R)
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.broadcast_to(bearing_deg, r.shape))
        along0 = (1.0 - fr) * kc[:, j0, i] + fr * kc[:, j0, i1]
        along1 = (1.0 - fr) * kc[:, j1, i] + fr * kc[:, j1, i1]
        return np.moveaxis(mix(along0, along1, w1), 0, -1)

    def level_profile(self, ic: int, ib: int, depth_m: float | None = None,
                      bearing_deg: float | None = None) -> LevelProfile:
        """K(r) of one class and band at an observer depth (and bearing), as the filters'
        level model."""
        return LevelProfile(range_m=self.range_m, k_db=self.k_db(depth_m, bearing_deg)[ic, ib])

    def tl_profile_db(self, ic: int, ib: int, depth_m: float, bearing_deg: float | None = None
                      ) -> np.ndarray:
        """TL of one class and band along the range axis at one depth (and bearing), dB.

        Without bearings the depth is the receiver's; with bearings, the point's the observer
        at the origin looks at.
        """
        return self.tl_at(ic, ib, np.full(self.range_m.shape, float(depth_m)), self.range_m,
                          bearing_deg=None if bearing_deg is None
                          else np.full(self.range_m.shape, float(bearing_deg)))

    def tl_at(self, ic: int, ib: int, depth_m, range_m, bearing_deg=None) -> np.ndarray:
        """TL at depths and ranges (and bearings), broadcast together, linear in each, dB.

        Ranges outside the axis take the end values.
        """
        self._need_tl()
        self._need_bearing(bearing_deg)
        d, r = np.broadcast_arrays(np.asarray(depth_m, dtype=float),
                                   np.asarray(range_m, dtype=float))
        z, x = self.depth_m, self.range_m
        if not self.by_bearing:
            self.check_depth(d)
            return _bilinear(self.tl_db[ic, ib], z, x, d, r)
        lo, hi = float(z[0]), float(z[-1])
        if np.any((d < lo) | (d > hi)):
            raise GridFileError(f"{self.source}: depth {float(d[(d < lo) | (d > hi)].flat[0]):g} m "
                                f"is outside the grid's depth axis [{lo:g}, {hi:g}] m")
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.broadcast_to(bearing_deg, d.shape))
        t = self.tl_db[ic, ib]                                          # (N, D, R)
        out = np.zeros(d.shape)
        for j in np.unique(np.concatenate([j0.ravel(), j1.ravel()])):
            a = _bilinear(t[j], z, x, d, r)
            for jj, w in ((j0, 1.0 - w1), (j1, w1)):
                take = (jj == j) & (w > 0)  # a radial of weight 0 adds nothing, even a NaN
                out = out + np.where(take, w * a, 0.0)
        return out

    def _need_tl(self) -> None:
        if self.tl_db is None:
            raise GridFileError(f"{self.source}: the grid holds K(r) alone, no tl_db")


def _bilinear(table: np.ndarray, z: np.ndarray, x: np.ndarray, d: np.ndarray,
              r: np.ndarray) -> np.ndarray:
    """``table(depth, range)`` at (d, r), bilinear; ranges outside the axis take the end values."""
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
