"""The grid as the trackers and the simulator see it: K(r) and TL at a depth and range.

``GridTables.from_grid`` is the one way from a grid dataset to the trackers. It reads the area
stored in the grid (``area_json``, validated by ``envdata`` like an area file) and gives, for a
class and a band:

- the transfer characteristic K(r) at a receiver depth (DESIGN.md: "TL and K(r) are taken at the
  row's obs_depth_m"). The grid's ``k_db`` holds K = S - TL at its observer depth; at depth d

      K(d, r) = k_db(r) + TL(d_grid, r) - TL(d, r),

  with TL linear in depth over ``tl_db(class, band, depth, range)``, so K(d_grid) is ``k_db``
  exactly. A grid without ``tl_db`` (K alone) has K at one depth and serves every depth;
- TL at receiver depths and ranges, bilinear in depth and range (Iglesis & de Montella eq. 13).

One interpolation rule: linear in depth and in range; ranges outside the axis take the end
values. The particle filters' level model adds its own horizon on top (``LevelProfile``).
A receiver depth outside the depth axis is a ``GridFileError``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.kcurve import spectral_term_db
from envdata.area import Area
from envdata.areafile import area_from_json
from envdata.bands import Band
from envdata.classes import TargetClass
from envdata.errors import AreaError

#: K beyond the grid's last range in the filters' level model: its last value less this, dB
#: (a rejection, not physics).
BEYOND_GRID_PENALTY_DB = 1000.0


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelProfile:
    """K(r) at one receiver depth as the particle filters' level model uses it (W = SL + K(r)).

    Linear in range inside the axis, the first value below it, and beyond the last range the
    last value less `BEYOND_GRID_PENALTY_DB`: the grid's range axis is the horizon of the level
    model, and a particle beyond it keeps a weight only if every particle is beyond it. (Holding
    the end value lets a fast, receding target far outside the grid explain a steady level as
    well as the true one.)
    """

    range_m: np.ndarray
    k_db: np.ndarray

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
    k_grid_db : ndarray, shape (C, M, R)
        K(r) at the grid's observer depth, dB (eq. 12: band level W = P0 + K(r) + H).
    observer_depth_m : float
        Receiver depth of ``k_grid_db``, m.
    depth_m : ndarray, shape (D,), or None
        Receiver depths of ``tl_db``, m, increasing; None for a grid of K alone.
    tl_db : ndarray, shape (C, M, D, R), or None
        Band transmission loss from the class's depth to a receiver at ``depth_m``, dB.
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
        k = np.asarray(grid["k_db"].transpose("class", "band", "range").values, dtype=float)
        depth = tl = None
        if "tl_db" in grid and "depth" in grid.dims:
            depth = np.asarray(grid["depth"].values, dtype=float)
            tl = np.asarray(grid["tl_db"].transpose("class", "band", "depth", "range").values,
                            dtype=float)
        return cls(source=source, area=area, classes=tuple(by_class[n] for n in class_names),
                   bands=tuple(by_band[n] for n in band_names),
                   range_m=np.asarray(grid["range"].values, dtype=float), k_grid_db=k,
                   observer_depth_m=float(grid.attrs.get("observer_depth_m",
                                                         area.observer.depth_m)),
                   depth_m=depth, tl_db=tl)

    # -------------------------------------------------------------- names and figures
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

    # -------------------------------------------------------------- depth
    @property
    def depth_range_m(self) -> tuple[float, float]:
        """First and last receiver depth of the tables, m (-inf, inf for a grid of K alone)."""
        if self.depth_m is None:
            return -math.inf, math.inf
        return float(self.depth_m[0]), float(self.depth_m[-1])

    def outside_depth(self, depth_m) -> np.ndarray:
        """Mask of receiver depths outside the depth axis (all False for a grid of K alone)."""
        lo, hi = self.depth_range_m
        d = np.asarray(depth_m, dtype=float)
        return ~((d >= lo) & (d <= hi))

    def check_depth(self, depth_m, what: str = "") -> None:
        """Raise GridFileError if a receiver depth lies outside the depth axis."""
        bad = self.outside_depth(depth_m)
        if np.any(bad):
            lo, hi = self.depth_range_m
            value = float(np.asarray(depth_m, dtype=float)[bad].flat[0])
            raise GridFileError(f"{self.source}: receiver depth {value:g} m is outside the grid's "
                                f"depth axis [{lo:g}, {hi:g}] m{what}")

    def _tl_rows(self, depth_m: float) -> np.ndarray:
        """TL of every class and band along range at one depth, linear in depth, (C, M, R)."""
        z = self.depth_m
        if z.size == 1:
            return self.tl_db[:, :, 0]
        j = int(np.clip(np.searchsorted(z, depth_m, side="right") - 1, 0, z.size - 2))
        f = (depth_m - z[j]) / (z[j + 1] - z[j])
        return (1.0 - f) * self.tl_db[:, :, j] + f * self.tl_db[:, :, j + 1]

    # -------------------------------------------------------------- K and TL
    def k_db(self, depth_m: float | None = None) -> np.ndarray:
        """K(r) of every class and band at a receiver depth, dB, shape (C, M, R).

        ``None`` means the grid's observer depth; a grid of K alone gives its K at any depth.
        """
        if depth_m is None or self.tl_db is None:
            return self.k_grid_db
        d = float(depth_m)
        if d == self.observer_depth_m:
            return self.k_grid_db
        if d not in self._k_cache:
            self.check_depth(d)
            self._k_cache[d] = self.k_grid_db + self._tl_rows(self.observer_depth_m) - self._tl_rows(d)
        return self._k_cache[d]

    def k_at(self, ic: int, range_m, depth_m: float | None = None) -> np.ndarray:
        """K of class ``ic`` in every band at given ranges, dB, shape ``range_m.shape + (M,)``.

        Linear in range; ranges outside the axis take the end values.
        """
        kc = self.k_db(depth_m)[ic]                                    # (M, R)
        r = np.asarray(range_m, dtype=float)
        return np.stack([np.interp(r, self.range_m, kc[ib]) for ib in range(kc.shape[0])], axis=-1)

    def level_profile(self, ic: int, ib: int, depth_m: float | None = None) -> LevelProfile:
        """K(r) of one class and band at a receiver depth, as the filters' level model."""
        return LevelProfile(range_m=self.range_m, k_db=self.k_db(depth_m)[ic, ib])

    def tl_profile_db(self, ic: int, ib: int, depth_m: float) -> np.ndarray:
        """TL of one class and band along the range axis at one receiver depth, dB."""
        self._need_tl()
        self.check_depth(depth_m)
        return self._tl_rows(float(depth_m))[ic, ib]

    def tl_at(self, ic: int, ib: int, depth_m, range_m) -> np.ndarray:
        """TL at receiver depths and ranges (broadcast together), bilinear, dB.

        Ranges outside the axis take the end values.
        """
        self._need_tl()
        d, r = np.broadcast_arrays(np.asarray(depth_m, dtype=float),
                                   np.asarray(range_m, dtype=float))
        self.check_depth(d)
        z, x, t = self.depth_m, self.range_m, self.tl_db[ic, ib]
        rc = np.clip(r, x[0], x[-1])
        i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, x.size - 2)
        fr = (rc - x[i]) / (x[i + 1] - x[i])
        if z.size == 1:
            return (1.0 - fr) * t[0, i] + fr * t[0, i + 1]
        j = np.clip(np.searchsorted(z, d, side="right") - 1, 0, z.size - 2)
        fz = (d - z[j]) / (z[j + 1] - z[j])
        low = (1.0 - fr) * t[j, i] + fr * t[j, i + 1]
        high = (1.0 - fr) * t[j + 1, i] + fr * t[j + 1, i + 1]
        return (1.0 - fz) * low + fz * high

    def _need_tl(self) -> None:
        if self.tl_db is None:
            raise GridFileError(f"{self.source}: the grid holds K(r) alone, no tl_db")
