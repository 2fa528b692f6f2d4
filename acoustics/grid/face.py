"""The one face of a grid: K(r) and TL at a depth, bearing and range, for every geometry.

``acoustics.open_grid`` (a file) and ``as_tables`` (a dataset in memory) are the one gate: they
check the dataset against the grid contract (``acoustics.grid.schema``), read back the area it
stores (``area_json``, validated by ``envdata`` like an area file) and return a `GridTables`.
The trackers, the simulator, the figures, the detection maps and the commands all take that
object and ask it, never the dataset, what K and TL are; nothing outside this package asks a
grid what shape it has.

Two geometries implement the face:

- `FlatTables`, a grid without bearings (``fixed_end = "source"``): ``k_db`` holds K = S - TL at
  the grid's observer depth, and K at another observer depth d is

      K(d, r) = k_db(r) + TL(d_grid, r) - TL(d, r),

  TL linear in depth over ``tl_db(class, band, depth, range)``, so K(d_grid) is ``k_db``
  exactly. K does not depend on bearing: a bearing given is accepted and has no effect, and K
  comes without a bearing axis (it broadcasts against one).
- `RadialTables`, a bearing-dependent grid (``fixed_end = "observer"``): TL was computed from
  the observer at the origin at its depth, so K is ``k_db(bearing, range)`` at that depth only,
  linear between the two nearest radials (across 0/360 deg); TL is the loss to a point at
  ``depth``, ``range`` along the bearing.

Both answer K with the target at any depth (`GridTables.target_depth_k`, a
`acoustics.grid.targetdepth.TargetDepthK` of (depth, range) slabs; `GridTables.at_target_depth`,
the same tables with K at another target depth): a bearing-dependent grid from its ``tl_db``, a
flat grid from ``tl_obs_db`` (TL from a source at the observer depth, by reciprocity; grids
built before it was written lack it and are refused for this with the command that rebuilds
them).

One interpolation rule: linear in depth, range and bearing; ranges outside the axis take the
end values; NaN where the grid has no value (below the bottom, beyond land), which the
simulator reads as "not detected" and the filters' level model as a level no target gives
(`LevelProfile`). A receiver depth the tables cannot serve is a ``GridFileError``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.depthinterp import tl_at_depths
from acoustics.grid.targetdepth import TargetDepthK
from acoustics.kcurve import spectral_term_db
from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from envdata.area import Area
from envdata.bands import Band
from envdata.classes import TargetClass

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
    #: sd of the K error along the same ranges, dB, where the grid carries a measured one
    #: (``k_error_sd_db``); None: the filters' sigma_l alone.
    k_sd_db: np.ndarray | None = None

    def sd_at(self, range_m) -> np.ndarray:
        """The K error sd at ranges, dB (linear, end values held); 0 without one."""
        r = np.asarray(range_m, dtype=float)
        if self.k_sd_db is None:
            return np.zeros(r.shape)
        return np.interp(r, self.range_m, self.k_sd_db)

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


@dataclass(frozen=True, slots=True, kw_only=True)
class OriginOffset:
    """How far an observer went from the origin its bearing-dependent tables are computed from."""

    distance_m: float
    origin_lat_deg: float
    origin_lon_deg: float


@dataclass(frozen=True, eq=False, kw_only=True)
class GridTables(ABC):
    """K(r) and TL of every class and band of a grid, with the area they were computed for.

    Attributes
    ----------
    source : str
        The grid's name in messages (its file, else its area).
    area : Area
        The area stored in the grid, validated like an area file.
    dataset : xr.Dataset
        The grid dataset that was checked (for figures that draw its labelled fields).
    classes : tuple of TargetClass
        The grid's class hypotheses, in grid order.
    bands : tuple of Band
        The grid's bands, in grid order.
    range_m : ndarray, shape (R,)
        Horizontal ranges, m, increasing.
    depth_m : ndarray, shape (D,)
        Depths of ``tl_db``, m, increasing.
    k_grid_db : ndarray, shape (C, M, R), or (C, M, N, R) with bearings
        K(r) at the grid's observer depth, dB (eq. 12: band level W = P0 + K(r) + H).
    tl_db : ndarray, shape (C, M, D, R), or (C, M, N, D, R) with bearings
        Band transmission loss, dB: from the class's depth to a receiver at ``depth_m``, or
        with bearings from the observer at the origin to a point at ``depth_m``.
    observer_depth_m : float
        Observer depth of ``k_grid_db``, m.
    target_depth_m : float or None
        None: ``k_grid_db`` is K with the target at its class's depth (as built); else the depth
        of the target these tables give K for (`at_target_depth`), m.
    k_error_sd_grid_db : ndarray or None
        The measured K error sd, shaped like ``k_grid_db``, dB, NaN where unknown; None: the grid
        has none (the classes' ``k_error_sd_db`` serve).
    """

    source: str
    area: Area
    dataset: xr.Dataset = field(repr=False)
    classes: tuple[TargetClass, ...]
    bands: tuple[Band, ...]
    range_m: np.ndarray
    depth_m: np.ndarray
    k_grid_db: np.ndarray
    tl_db: np.ndarray
    observer_depth_m: float
    target_depth_m: float | None = None
    k_error_sd_grid_db: np.ndarray | None = None
    _cache: dict = field(default_factory=dict, repr=False)

    # -- names and the area's terms ------------------------------------------------------------

    @property
    def class_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.classes)

    @property
    def band_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.bands)

    @property
    def model(self) -> str:
        """The propagation model the grid was computed with (``bellhop``, ``urick``, ...)."""
        return str(self.dataset.attrs.get("model", ""))

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

    # -- depths ---------------------------------------------------------------------------------

    @property
    @abstractmethod
    def depth_range_m(self) -> tuple[float, float]:
        """Observer depths the tables serve, m."""

    @abstractmethod
    def depth_problem(self, depth_m: float) -> str:
        """Why an observer depth cannot be served, for a message (after ``outside_depth``)."""

    def outside_depth(self, depth_m) -> np.ndarray:
        """Mask of observer depths the tables cannot serve."""
        lo, hi = self.depth_range_m
        d = np.asarray(depth_m, dtype=float)
        return ~((d >= lo) & (d <= hi))

    def check_depth(self, depth_m, what: str = "") -> None:
        """Raise GridFileError if an observer depth cannot be served."""
        bad = self.outside_depth(depth_m)
        if np.any(bad):
            value = float(np.asarray(depth_m, dtype=float)[bad].flat[0])
            raise GridFileError(f"{self.source}: {self._depth_role} depth {self.depth_problem(value)}{what}")

    def _check_point_depth(self, d: np.ndarray) -> None:
        """Raise GridFileError for a depth off the TL table's depth axis."""
        lo, hi = float(self.depth_m[0]), float(self.depth_m[-1])
        out = (d < lo) | (d > hi)
        if np.any(out):
            raise GridFileError(f"{self.source}: depth {float(d[out].flat[0]):g} m is outside the "
                                f"grid's depth axis [{lo:g}, {hi:g}] m")

    # -- K and TL -------------------------------------------------------------------------------

    @abstractmethod
    def k_db(self, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        """K(r) of every class and band at an observer depth and bearing, dB.

        ``None`` depth means the grid's observer depth. Shape (C, M, R); with an array of B
        bearings (C, M, B, R) where K depends on bearing (it broadcasts where it does not).
        """

    @abstractmethod
    def k_at(self, ic: int, range_m, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        """K of class ``ic`` in every band at given ranges and bearings, dB.

        Shape ``range_m.shape + (M,)``. Linear in range (ranges outside the axis take the end
        values) and in bearing; NaN where the grid has no value.
        """

    @abstractmethod
    def tl_at(self, ic: int, ib: int, depth_m, range_m, bearing_deg=None) -> np.ndarray:
        """TL at depths, ranges and bearings, broadcast together, linear in each, dB.

        The depth is the receiver's of a flat grid, the target's point of a bearing-dependent
        one. Ranges outside the axis take the end values.
        """

    @abstractmethod
    def k_typical_db(self, ic: int, ib: int, range_m) -> np.ndarray:
        """K of one class and band at the observer depth at given ranges, dB: the one K of a flat
        grid, the median over the radials that have K there for a bearing-dependent one (NaN
        where none has)."""

    @abstractmethod
    def _bearing_key(self, bearing_deg):
        """What of a bearing changes K (None where nothing does): the level profiles' cache key."""

    def level_profile(self, ic: int, ib: int, depth_m: float | None = None,
                      bearing_deg: float | None = None) -> LevelProfile:
        """K(r) of one class and band at an observer depth and bearing, as the filters' level
        model (kept: the same depth and bearing give the same profile)."""
        d = self.observer_depth_m if depth_m is None else float(depth_m)
        key = ("profile", ic, ib, d, self._bearing_key(bearing_deg))
        if key not in self._cache:
            sd = self.k_error_sd_profile_db(ic, ib, key[-1]) if self.has_k_error_map else None
            self._cache[key] = LevelProfile(range_m=self.range_m, k_db=self.k_db(d, key[-1])[ic, ib], k_sd_db=sd)
        return self._cache[key]

    def level_profile_at(self, ic: int, ib: int, x_m: float, y_m: float, depth_m: float | None = None,
                         bearing_deg: float | None = None) -> LevelProfile:
        """`level_profile` of the tables where the observer is (x east, y north of the area's
        origin, m): what `at_observer` then `level_profile` give, for the one class, band and
        bearing a particle filter asks each cycle. A grid answers from its own tables; an atlas
        mixes only that K(r) of the positions around the observer
        (``acoustics.grid.atlasfollow.FollowingTables``), not every table.
        """
        return self.at_observer(x_m, y_m).level_profile(ic, ib, depth_m, bearing_deg)

    def level_profiles_at(self, ic: int, ib: int, x_m, y_m, depth_m, bearing_deg) -> list[LevelProfile]:
        """`level_profile_at` along an observer's path, one profile per cycle.

        Parameters
        ----------
        ic, ib : int
            Class and band.
        x_m, y_m : array_like, shape (T,)
            The observer east and north of the area's origin each cycle, m.
        depth_m : array_like, shape (T,)
            The observer's depth each cycle, m.
        bearing_deg : sequence of float or None, length T
            The bearing of each cycle's profile, deg (None for tables without bearings).
        """
        return [self.level_profile_at(ic, ib, x, y, d, b)
                for x, y, d, b in zip(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float),
                                      np.asarray(depth_m, dtype=float), bearing_deg)]

    def tl_profile_db(self, ic: int, ib: int, depth_m: float, bearing_deg: float | None = None
                      ) -> np.ndarray:
        """TL of one class and band along the range axis at one depth and bearing, dB."""
        return self.tl_at(ic, ib, np.full(self.range_m.shape, float(depth_m)), self.range_m,
                          bearing_deg=None if bearing_deg is None
                          else np.full(self.range_m.shape, float(bearing_deg)))

    # -- the target at another depth -----------------------------------------------------------

    @property
    @abstractmethod
    def serves_target_depth(self) -> bool:
        """Whether the tables hold TL from the observer at every depth (K at any target depth)."""

    @abstractmethod
    def _observer_tl_db(self) -> np.ndarray:
        """TL from the observer to a point at each depth, (C, M, [N,] D, R), dB."""

    def _need_target_depth(self) -> None:
        if not self.serves_target_depth:
            raise GridFileError(
                f"{self.source}: the grid has no TL from the observer depth (variable "
                f"tl_obs_db), needed for K at a target depth other than its class's; give the "
                f"class a depth_range_m in the area file and rebuild it with tmakit grids build")

    def target_depth_k(self, ic: int, ib: int) -> TargetDepthK:
        """K of one class and band with the target at every depth of the axis, per radial
        (kept: the same class and band give the same table).

        K(z, r) = S - TL_obs(z, r): S the class's spectral term in the band (eq. 13), TL_obs the
        band TL between the observer and a point at depth z (docs/formats.md, ``tl_obs_db``).

        Raises
        ------
        GridFileError
            A flat grid built without ``tl_obs_db``.
        """
        self._need_target_depth()
        key = ("target-depth-k", ic, ib)
        if key not in self._cache:
            tl = self._observer_tl_db()[ic, ib]
            k = self.spectral_db(ic, ib) - (tl if tl.ndim == 3 else tl[None])
            bearings = getattr(self, "bearing_deg", np.zeros(0))
            self._cache[key] = TargetDepthK(bearing_deg=np.asarray(bearings, dtype=float),
                                            depth_m=self.depth_m, range_m=self.range_m, k_db=k)
        return self._cache[key]

    def target_depth_span_m(self, ic: int) -> tuple[float, float]:
        """Depths a target of class ``ic`` may be at, m: the class's ``depth_range_m``, else
        the water column the tables hold (the top of the depth axis to the deepest water)."""
        cls = self.classes[ic]
        if cls.depth_range_m is not None:
            return cls.depth_range_m
        self._need_target_depth()
        wet = np.isfinite(self._observer_tl_db()[ic, 0])
        wet = wet.any(axis=tuple(a for a in range(wet.ndim) if a != wet.ndim - 2))
        return float(self.depth_m[0]), float(self.depth_m[wet][-1] if wet.any() else self.depth_m[-1])

    def at_target_depth(self, depth_m: float) -> GridTables:
        """These tables with K of every class for a target at ``depth_m`` (the class's ``depth_m``
        is only where the tables were computed): every tracker and the simulator take it as
        they take the grid. Only the grid's observer depth is served.

        Raises
        ------
        GridFileError
            A depth off the grid's depth axis, or a flat grid without ``tl_obs_db``.
        """
        self._need_target_depth()
        z = float(depth_m)
        self._check_point_depth(np.array([z]))
        s = np.array([[self.spectral_db(ic, ib) for ib in range(len(self.bands))]
                      for ic in range(len(self.classes))])
        tl = tl_at_depths(self._observer_tl_db(), self.depth_m, [z])[..., 0, :]
        k = s.reshape(s.shape + (1,) * (tl.ndim - 2)) - tl
        from dataclasses import replace

        return replace(self, k_grid_db=k, target_depth_m=z, _cache={})
    # -- the K error the trackers allow for ------------------------------------------------------

    @property
    def has_k_error_map(self) -> bool:
        """Whether the grid carries a measured ``k_error_sd_db`` by range (and bearing)."""
        return self.k_error_sd_grid_db is not None

    def k_error_sd_at(self, ic: int, range_m, bearing_deg=None) -> np.ndarray:
        """sd of the K error of class ``ic`` in every band at given ranges and bearings, dB.

        Shape ``range_m.shape + (M,)``. Where the grid carries ``k_error_sd_db`` (a sensitivity
        study's, ``tmakit sensitivity --into``) it is read like K (linear in range and bearing,
        ranges outside the axis take the end values); where that holds no value, and in a grid
        without it, the class's one ``k_error_sd_db``.
        """
        r = np.asarray(range_m, dtype=float)
        fallback = float(self.classes[ic].k_error_sd_db)
        if self.k_error_sd_grid_db is None:
            return np.full(r.shape + (len(self.bands),), fallback)
        sd = self._k_error_lookup(ic, r, bearing_deg)
        return np.where(np.isfinite(sd), sd, fallback)

    def k_error_sd_profile_db(self, ic: int, ib: int, bearing_deg=None) -> np.ndarray:
        """`k_error_sd_at` of one class and band along the range axis at one bearing, dB."""
        b = None if bearing_deg is None else np.full(self.range_m.shape, float(bearing_deg))
        return self.k_error_sd_at(ic, self.range_m, b)[:, ib]

    @property
    def bearing_axis_deg(self) -> np.ndarray | None:
        """The radials' bearings, deg (None: K does not depend on bearing)."""
        return getattr(self, "bearing_deg", None)

    def dataset_with_k_error_sd(self, sd_db: np.ndarray, comment: str) -> xr.Dataset:
        """The grid dataset with ``k_error_sd_db`` set (replaced if there), shaped like ``k_db``.

        Parameters
        ----------
        sd_db : ndarray
            (C, M, R), or (C, M, N, R) with bearings, in the grid's order; dB, >= 0, NaN unknown.
        comment : str
            Where the values come from (a study's file and source_hash), for the attribute.
        """
        sd = np.asarray(sd_db, dtype=float)
        if sd.shape != self.k_grid_db.shape:
            raise GridFileError(f"{self.source}: k_error_sd_db of shape {sd.shape} does not fit the grid's K "
                                f"{self.k_grid_db.shape}")
        dims = self.dataset["k_db"].dims
        order = [("class", "band", "bearing", "range").index(d) if self.bearing_axis_deg is not None
                 else ("class", "band", "range").index(d) for d in dims]
        return self.dataset.assign(k_error_sd_db=(dims, np.transpose(sd, order), {
            "units": "dB", "long_name": "sd of the transfer-characteristic error K - K_true",
            "comment": f"{comment}; NaN where unknown: the class's k_error_sd_db serves there"}))

    def _k_error_lookup(self, ic: int, range_m: np.ndarray, bearing_deg) -> np.ndarray:
        """The stored ``k_error_sd_db`` of class ``ic`` at ranges (and bearings), (..., M); NaN
        unknown. Tables without a stored map (an atlas's views) have none to look up."""
        return np.full(np.shape(range_m) + (len(self.bands),), np.nan)

    # -- what a summary says of the geometry ----------------------------------------------------

    @abstractmethod
    def geometry(self) -> dict[str, float | int | str]:
        """Facts of the grid's geometry for a summary ({} for a flat grid; for radials the origin,
        their number, the bottom's span and the share of range cells beyond land)."""

    # -- where the observer is ------------------------------------------------------------------

    @abstractmethod
    def observer_offset(self, x_m, y_m) -> OriginOffset | None:
        """How far observer positions (x east, y north of the origin, m) go from the origin the
        tables are computed from (the largest distance); None where the tables hold everywhere."""

    def at_observer(self, x_m: float, y_m: float) -> GridTables:
        """The tables for an observer at (x east, y north of the area's origin, m): the trackers
        and the simulator ask this every cycle, then ask the result for K and TL.

        A grid's tables are the same wherever the observer is (these tables); an atlas's are
        mixed from the positions around the observer (``acoustics.grid.atlasfollow``).
        """
        return self

    @property
    def follows_observer(self) -> bool:
        """Whether `at_observer` gives other tables at other observer positions (an atlas)."""
        return False

    def check_observers(self, x_m, y_m) -> None:
        """Raise InputError naming the first observer position (from 0) the tables cannot serve
        (outside an atlas's positions); a grid serves every position."""
        return None


def _range_cells(x: np.ndarray, r: np.ndarray):
    """Cells of the range axis around ranges (clipped to the axis) and the weight of the second."""
    rc = np.clip(r, x[0], x[-1])
    i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, max(x.size - 2, 0))
    fr = (rc - x[i]) / (x[i + 1] - x[i]) if x.size > 1 else np.zeros(r.shape)
    return i, np.minimum(i + 1, x.size - 1), fr


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
