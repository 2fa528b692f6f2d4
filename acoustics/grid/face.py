"""The face: what every set of propagation tables answers, whatever the geometry.

``acoustics.open_tables`` (``acoustics.grid.opentables``) is the one way in: a grid file, an
atlas store or a grid dataset in memory comes out as a `Tables`. The trackers, the simulator,
the figures, the detection maps and the commands all take that object and ask it, never a
dataset, what K and TL are; nothing outside this package asks tables what shape they have.

Names say which object answers and which holds: a ``...Tables`` is a face (it answers K and
TL: `Tables`, ``FlatTables``, ``RadialTables``, ``FollowingTables``); an ``AtlasStore`` holds
an atlas's tables on disk (``acoustics.grid.atlas.store``) and answers nothing itself.

The implementations:

- ``acoustics.grid.flattables.FlatTables``, a grid without bearings (``fixed_end = "source"``):
  ``k_db`` holds K = S - TL at the grid's observer depth, and K at another observer depth d is

      K(d, r) = k_db(r) + TL(d_grid, r) - TL(d, r),

  TL linear in depth over ``tl_db(class, band, depth, range)``, so K(d_grid) is ``k_db``
  exactly. K does not depend on bearing: a bearing given is accepted and has no effect, and K
  comes without a bearing axis (it broadcasts against one).
- ``acoustics.grid.radialtables.RadialTables``, a bearing-dependent grid (``fixed_end =
  "observer"``): TL was computed from the observer at the origin at its depth, so K is
  ``k_db(bearing, range)`` at that depth only, linear between the two nearest radials (across
  0/360 deg); TL is the loss to a point at ``depth``, ``range`` along the bearing. An atlas's
  tables at one observer position are such tables, mixed from the positions around it.
- ``acoustics.grid.atlas.follow.FollowingTables``, an atlas of one month: the tables around the
  observer at every cycle (`Tables.at_observer`).

Every face answers K with the target at any depth (``acoustics.grid.targetdepth``) from its TL
from the observer (a flat grid's ``tl_obs_db``; grids built before it was written lack it and
are refused for this with the command that rebuilds them), the filters' level model
(``acoustics.grid.levelprofile``) and the measured K error (``k_error_sd_db``). How values are
read between cells is one rule for all (``acoustics.grid.lookup``). A receiver depth the tables
cannot serve is a ``GridFileError``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.kerror import KErrorModel, MeasuredKError
from acoustics.grid.levelprofile import LevelProfile
from acoustics.grid.targetdepth import TargetDepthK, k_at_target_depth, target_depth_span, target_depth_table
from acoustics.kcurve import spectral_term_db
from envdata.area import Area
from envdata.bands import Band
from envdata.classes import TargetClass

if TYPE_CHECKING:
    from envdata.receiver import Receiver

#: A bearing-dependent grid serves observers within this of its observer depth, m.
OBSERVER_DEPTH_TOLERANCE_M = 1.0


@dataclass(frozen=True, slots=True, kw_only=True)
class OriginOffset:
    """How far an observer went from the origin its bearing-dependent tables are computed from."""

    distance_m: float
    origin_lat_deg: float
    origin_lon_deg: float


@dataclass(frozen=True, eq=False, kw_only=True)
class Tables(ABC):
    """K(r) and TL of every class and band, with the area they were computed for: the face.

    Attributes
    ----------
    source : str
        The tables' name in messages (their file, else their area).
    area : Area
        The area stored with the tables, validated like an area file.
    dataset : xr.Dataset
        The grid dataset that was checked (for figures that draw its labelled fields).
    classes : tuple of TargetClass
        The class hypotheses, in the tables' order.
    bands : tuple of Band
        The bands, in the tables' order.
    range_m : ndarray, shape (R,)
        Horizontal ranges, m, increasing.
    depth_m : ndarray, shape (D,)
        Depths of ``tl_db``, m, increasing.
    k_grid_db : ndarray, shape (C, M, R), or (C, M, N, R) with bearings
        K(r) at the observer depth, dB (eq. 12: band level W = P0 + K(r) + H).
    tl_db : ndarray, shape (C, M, D, R), or (C, M, N, D, R) with bearings
        Band transmission loss, dB: from the class's depth to a receiver at ``depth_m``, or
        with bearings from the observer at the origin to a point at ``depth_m``.
    observer_depth_m : float
        Observer depth of ``k_grid_db``, m.
    target_depth_m : float or None
        None: ``k_grid_db`` is K with the target at its class's depth (as built); else the depth
        of the target these tables give K for (`at_target_depth`), m.
    k_error_sd_grid_db : ndarray or None
        The measured K error sd, shaped like ``k_grid_db``, dB, NaN where unknown; None: the
        tables have none (the classes' ``k_error_sd_db`` serve). Grids of format 2 (an older
        ``tmakit sensitivity --into``).
    k_error_measured : MeasuredKError or None
        K's error model a study measured (`acoustics.grid.kerror`), or None.
    sonar_name : str or None
        The sonar file these tables listen with (`with_receiver`); None: the area's sonar.
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
    k_error_measured: MeasuredKError | None = None
    sonar_name: str | None = None
    _cache: dict = field(default_factory=dict, repr=False)

    # -- what the implementations answer -------------------------------------------------------

    @property
    @abstractmethod
    def depth_range_m(self) -> tuple[float, float]:
        """Observer depths the tables serve, m."""

    @abstractmethod
    def depth_problem(self, depth_m: float) -> str:
        """Why an observer depth cannot be served, for a message (after ``outside_depth``)."""

    @abstractmethod
    def k_db(self, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        """K(r) of every class and band at an observer depth and bearing, dB.

        ``None`` depth means the observer depth of the tables. Shape (C, M, R); with an array of
        B bearings (C, M, B, R) where K depends on bearing (it broadcasts where it does not).
        """

    @abstractmethod
    def k_at(self, ic: int, range_m, depth_m: float | None = None, bearing_deg=None) -> np.ndarray:
        """K of class ``ic`` in every band at given ranges and bearings, dB.

        Shape ``range_m.shape + (M,)``. Linear in range (ranges outside the axis take the end
        values) and in bearing; NaN where the tables have no value.
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

    @property
    @abstractmethod
    def serves_target_depth(self) -> bool:
        """Whether the tables hold TL from the observer at every depth (K at any target depth)."""

    @abstractmethod
    def observer_tl_db(self) -> np.ndarray:
        """TL from the observer to a point at each depth, (C, M, [N,] D, R), dB."""

    @abstractmethod
    def k_error_lookup(self, ic: int, range_m: np.ndarray, bearing_deg) -> np.ndarray:
        """The stored ``k_error_sd_db`` of class ``ic`` at ranges (and bearings), (..., M), dB."""

    @abstractmethod
    def bearing_key(self, bearing_deg):
        """What of a bearing changes K (None where nothing does): the level profiles' cache key."""

    @abstractmethod
    def geometry(self) -> dict[str, float | int | str]:
        """Facts of the geometry for a summary ({} for a flat grid; for radials the origin,
        their number, the bottom's span and the share of range cells beyond land)."""

    @abstractmethod
    def observer_offset(self, x_m, y_m) -> OriginOffset | None:
        """How far observer positions (x east, y north of the origin, m) go from the origin the
        tables are computed from (the largest distance); None where the tables hold everywhere."""

    def as_everywhere(self) -> Tables:
        """These tables read as if they had been computed wherever the observer is: a sea that
        moves with the observer (a study's member: the simulator reads it from the observer too),
        so that no error grows with the observer's distance from their origin. Tables that hold
        everywhere already are returned as they are."""
        return self

    def distance_from_origin_m(self, x_m, y_m) -> np.ndarray | None:
        """Each observer position's distance from where the tables were computed, m (x east, y
        north of the origin); None for tables that hold everywhere (a flat area's). An atlas's
        (`acoustics.grid.atlas.follow.FollowingTables`) is its blended positions' distances."""
        x, y = np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)
        if self.observer_offset(x, y) is None:
            return None
        return np.hypot(x, y)

    # -- names and the area's terms ------------------------------------------------------------

    @property
    def class_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.classes)

    @property
    def band_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.bands)

    @property
    def model(self) -> str:
        """The propagation model the tables were computed with (``bellhop``, ``urick``, ...)."""
        return str(self.dataset.attrs.get("model", ""))

    @property
    def area_name(self) -> str:
        """The area as the tables name it (the figures' titles)."""
        return str(self.dataset.attrs.get("area", self.area.name))

    @property
    def k_urick_grid_db(self) -> np.ndarray | None:
        """K(r) by the Urick formula (eq. 13), shaped like ``k_grid_db``, dB; None where the
        tables hold none."""
        ds = self.dataset
        return ds["k_urick_db"].transpose(*ds["k_db"].dims).values if "k_urick_db" in ds else None

    @property
    def input_files(self) -> str | None:
        """What the tables record of the files they were computed from, the grid's
        ``input_files`` text (JSON: {role: {name, sha256}}); None where nothing is recorded."""
        text = self.dataset.attrs.get("input_files")
        return None if text is None else str(text)

    @property
    def bearing_axis_deg(self) -> np.ndarray | None:
        """The radials' bearings, deg (None: K does not depend on bearing)."""
        return None

    def class_index(self, name: str) -> int:
        """Index of a class hypothesis; GridFileError naming the tables' classes if absent."""
        return _index(self.source, "class", name, self.class_names)

    def band_index(self, name: str) -> int:
        """Index of a band; GridFileError naming the tables' bands if absent."""
        return _index(self.source, "band", name, self.band_names)

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

    def check_point_depth(self, d: np.ndarray) -> None:
        """Raise GridFileError for a depth off the TL table's depth axis."""
        lo, hi = float(self.depth_m[0]), float(self.depth_m[-1])
        out = (d < lo) | (d > hi)
        if np.any(out):
            raise GridFileError(f"{self.source}: depth {float(d[out].flat[0]):g} m is outside the "
                                f"grid's depth axis [{lo:g}, {hi:g}] m")

    # -- the filters' level model ---------------------------------------------------------------

    def level_profile(self, ic: int, ib: int, depth_m: float | None = None,
                      bearing_deg: float | None = None) -> LevelProfile:
        """K(r) of one class and band at an observer depth and bearing, as the filters' level
        model (kept: the same depth and bearing give the same profile)."""
        d = self.observer_depth_m if depth_m is None else float(depth_m)
        key = ("profile", ic, ib, d, self.bearing_key(bearing_deg))
        if key not in self._cache:
            sd = self.k_error_sd_profile_db(ic, ib, key[-1]) if self.has_k_error_map else None
            self._cache[key] = LevelProfile(range_m=self.range_m, k_db=self.k_db(d, key[-1])[ic, ib], k_sd_db=sd)
        return self._cache[key]

    def level_profiles_at(self, ic: int, ib: int, x_m, y_m, depth_m, bearing_deg) -> list[LevelProfile]:
        """`level_profile` of the tables where the observer is, along its path: one profile per
        cycle, for the one class, band and bearing a particle filter asks each cycle.

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

        A grid answers from its own tables; an atlas mixes only that K(r) of the positions
        around the observer (``acoustics.grid.atlas.follow.FollowingTables``), not every table.
        """
        return [self.at_observer(x, y).level_profile(ic, ib, d, b)
                for x, y, d, b in zip(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float),
                                      np.asarray(depth_m, dtype=float), bearing_deg)]

    def tl_profile_db(self, ic: int, ib: int, depth_m: float, bearing_deg: float | None = None
                      ) -> np.ndarray:
        """TL of one class and band along the range axis at one depth and bearing, dB."""
        return self.tl_at(ic, ib, np.full(self.range_m.shape, float(depth_m)), self.range_m,
                          bearing_deg=None if bearing_deg is None
                          else np.full(self.range_m.shape, float(bearing_deg)))

    # -- the target at another depth (acoustics.grid.targetdepth) ---------------------------------

    def _need_target_depth(self) -> None:
        if not self.serves_target_depth:
            raise GridFileError(
                f"{self.source}: the grid has no TL from the observer depth (variable "
                f"tl_obs_db), needed for K at a target depth other than its class's; give the "
                f"class a depth_range_m in the area file and rebuild it with tmakit grids build")

    def target_depth_k(self, ic: int, ib: int) -> TargetDepthK:
        """K of one class and band with the target at every depth of the axis, per radial
        (kept: the same class and band give the same table); GridFileError for a flat grid
        built without ``tl_obs_db``."""
        self._need_target_depth()
        key = ("target-depth-k", ic, ib)
        if key not in self._cache:
            self._cache[key] = target_depth_table(self, ic, ib)
        return self._cache[key]

    def target_depth_span_m(self, ic: int) -> tuple[float, float]:
        """Depths a target of class ``ic`` may be at, m: the class's ``depth_range_m``, else
        the water column the tables hold."""
        if self.classes[ic].depth_range_m is None:
            self._need_target_depth()
        return target_depth_span(self, ic)

    def at_target_depth(self, depth_m: float) -> Tables:
        """These tables with K of every class for a target at ``depth_m`` (the class's ``depth_m``
        is only where the tables were computed): every tracker and the simulator take it as
        they take the tables. Only the tables' observer depth is served.

        Raises
        ------
        GridFileError
            A depth off the depth axis, or a flat grid without ``tl_obs_db``.
        """
        self._need_target_depth()
        z = float(depth_m)
        self.check_point_depth(np.array([z]))
        return replace(self, k_grid_db=k_at_target_depth(self, z), target_depth_m=z, _cache={})

    def with_receiver(self, receiver: Receiver) -> Tables:
        """The same tables heard by another sonar (``envdata.receiver``): its ``[sonar]``, and its
        ``[noise]`` when it has one, in place of the area's. K is the propagation to the
        observer's depth and does not change; the detection rule, P_D and the levels' SNR do."""
        area = replace(self.area, sonar=receiver.sonar,
                       noise=self.area.noise if receiver.noise is None else receiver.noise)
        return replace(self, area=area, sonar_name=receiver.name, _cache={})

    def sonar_label(self) -> str:
        """One line for figures: which sonar and noise the detection rule uses."""
        s, n = self.area.sonar, self.area.noise
        who = "the area's sonar" if self.sonar_name is None else f"sonar {self.sonar_name}"
        return (f"{who}: DI {s.directivity_index_db:g} dB, T {s.integration_time_s:g} s, Q \u2265 "
                f"{s.detection_threshold:g}, sea noise {n.spectrum_level_1khz_db:g} dB re 1 \u00b5Pa\u00b2/Hz at 1 kHz")

    # -- the K error the trackers allow for ------------------------------------------------------

    @property
    def has_k_error_map(self) -> bool:
        """Whether the tables carry a measured ``k_error_sd_db`` by range (and bearing)."""
        return self.k_error_sd_grid_db is not None

    def k_error_sd_at(self, ic: int, range_m, bearing_deg=None) -> np.ndarray:
        """sd of the K error of class ``ic`` in every band at given ranges and bearings, dB.

        Shape ``range_m.shape + (M,)``. Where the tables carry ``k_error_sd_db`` (a sensitivity
        study's, ``tmakit sensitivity --into``) it is read like K (linear in range and bearing,
        ranges outside the axis take the end values); where that holds no value, and in tables
        without it, the class's one ``k_error_sd_db``.
        """
        r = np.asarray(range_m, dtype=float)
        fallback = float(self.classes[ic].k_error_sd_db)
        if self.k_error_sd_grid_db is None:
            return np.full(r.shape + (len(self.bands),), fallback)
        sd = self.k_error_lookup(ic, r, bearing_deg)
        return np.where(np.isfinite(sd), sd, fallback)

    @property
    def computed_at_one_position(self) -> bool:
        """Whether the tables were computed with the observer at one position (a bearing-dependent
        grid), so that they hold less well the farther the observer is from it."""
        return self.observer_offset(np.zeros(1), np.zeros(1)) is not None

    def k_error_model(self, ic: int, bearing_deg: float | None = None) -> KErrorModel:
        """K's error of class ``ic``, with its structure (`acoustics.grid.kerror`), both parts
        growing away from where tables of one position were computed: a study's model where the
        tables carry one (``tmakit sensitivity --into``; at ``bearing_deg``, or the median over the
        radials), else the class's one ``k_error_sd_db`` as the offset with the tables' own
        residual beside it. A measured ``k_error_sd_db`` map (format 2: the rms of K's error over
        a study's members) gives the offset its median over the map's ranges and bearings, band
        by band."""
        one = self.computed_at_one_position
        n = len(self.bands)
        if self.k_error_measured is not None:
            return KErrorModel.measured(self.k_error_measured, ic, one_position=one, bearing_deg=bearing_deg)
        model = KErrorModel.of_class(self.classes[ic].k_error_sd_db, n, one_position=one)
        if self.k_error_sd_grid_db is None:
            return model
        sd = np.moveaxis(np.asarray(self.k_error_sd_grid_db[ic], dtype=float), 0, -1).reshape(-1, n)
        med = np.nanmedian(np.where(np.isfinite(sd), sd, np.nan), axis=0)
        fallback = float(self.classes[ic].k_error_sd_db)
        return replace(model, offset_sd_db=tuple(float(v) if np.isfinite(v) else fallback for v in med),
                       source="the median of the grid's k_error_sd_db map")

    def k_error_sd_profile_db(self, ic: int, ib: int, bearing_deg=None) -> np.ndarray:
        """`k_error_sd_at` of one class and band along the range axis at one bearing, dB."""
        b = None if bearing_deg is None else np.full(self.range_m.shape, float(bearing_deg))
        return self.k_error_sd_at(ic, self.range_m, b)[:, ib]

    # -- where the observer is ------------------------------------------------------------------

    def at_observer(self, x_m: float, y_m: float) -> Tables:
        """The tables for an observer at (x east, y north of the area's origin, m): the trackers
        and the simulator ask this every cycle, then ask the result for K and TL.

        A grid's tables are the same wherever the observer is (these tables); an atlas's are
        mixed from the positions around the observer (``acoustics.grid.atlas.follow``).
        """
        return self

    @property
    def follows_observer(self) -> bool:
        """Whether `at_observer` gives other tables at other observer positions (an atlas)."""
        return False

    def check_observers(self, x_m, y_m) -> None:
        """Raise ``ObserverPositionError`` (its ``index`` the first observer position, from 0,
        the tables cannot serve: outside an atlas's positions); a grid serves every position."""
        return None


def _index(source: str, what: str, name: str, names: tuple[str, ...]) -> int:
    if name not in names:
        raise GridFileError(f"{source}: {what} {name!r} is not in the grid ({what}es: {', '.join(names)})"
                            if what == "class" else
                            f"{source}: {what} {name!r} is not in the grid ({what}s: {', '.join(names)})")
    return names.index(name)


__all__ = ["OBSERVER_DEPTH_TOLERANCE_M", "OriginOffset", "Tables"]
