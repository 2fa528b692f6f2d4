"""A sea area: water, bottom, noise, sonar, bands, target classes and the grid to compute.

``envdata.areafile`` reads the TOML format (docs/formats.md) into a frozen, validated ``Area``;
``Area.to_dict`` is its inverse, the document that reads back into an equal ``Area``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

import numpy as np

from envdata.atlas import AtlasSpec
from envdata.bands import Band
from envdata.bottom import Bottom
from envdata.classes import TargetClass
from envdata.datafiles import BathymetrySource, ClimatologySource, DataFile
from envdata.errors import AreaError
from envdata.geometry import Bearings, Origin
from envdata.noise import Noise
from envdata.sonar import Sonar
from envdata.ssp import SoundSpeedProfile, TsProfile

DEFAULT_AREA = "ocean-deep"
#: Most depths a grid's depth axis may have (a finer step is a typing or unit mistake).
MAX_DEPTHS = 100_000


class TlMode(StrEnum):
    INCOHERENT = "incoherent"
    SEMICOHERENT = "semicoherent"
    COHERENT = "coherent"

    @property
    def bellhop_letter(self) -> str:
        return {"incoherent": "I", "semicoherent": "S", "coherent": "C"}[self.value]


class Absorption(StrEnum):
    THORP = "thorp"
    NONE = "none"


#: Depth to which the Munk profile is tabulated for an area whose bottom comes from a
#: bathymetry file, m: deeper than all but the deepest trenches, where the canonical profile
#: passes the 1650 m/s that bounds sea-water speeds; every radial is cut from it.
MUNK_TABLE_DEPTH_M = 10500.0


@dataclass(frozen=True, slots=True, kw_only=True)
class Water:
    """The water of an area: its bottom depth and its sound speed.

    The bottom is flat (``depth_m``) or comes from a bathymetry file (``bathymetry``); the sound
    speed is one profile for the whole area (``ssp``: a table of speeds, the Munk profile, or a
    T/S table converted to speeds; ``ts``: a T/S table or cast kept as T and S, for a bathymetry
    area whose depth is not known until the radials are sampled) or comes from a climatology
    (``climatology``). On a flat bottom ``ssp`` reaches the bottom exactly; over a bathymetry
    file it must reach the deepest bottom of every radial (``envdata.radials`` checks it).
    ``cast`` records the CTD cast the profile was read from (provenance, not part of equality).
    """

    depth_m: float | None = None
    ssp: SoundSpeedProfile | None = None
    ts: TsProfile | None = None
    bathymetry: BathymetrySource | None = None
    climatology: ClimatologySource | None = None
    cast: DataFile | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if (self.depth_m is None) == (self.bathymetry is None):
            raise AreaError("[water]: give the bottom as depth_m (flat) or as a bathymetry file, "
                            "exactly one of the two")
        sources = [name for name, value in (("a sound-speed profile", self.ssp), ("a T/S profile", self.ts),
                                            ("a climatology", self.climatology)) if value is not None]
        if len(sources) != 1:
            raise AreaError("[water]: give the sound speed as exactly one of ssp, a table, a T/S table, "
                            f"a cast or a climatology, got {' and '.join(sources) or 'none'}")
        if self.depth_m is not None:
            if not (math.isfinite(self.depth_m) and 0.0 < self.depth_m <= 12000.0):
                raise AreaError(f"[water] depth_m: must be in (0, 12000] m, got {self.depth_m}")
            if self.ts is not None:
                raise AreaError("[water]: on a flat bottom a T/S profile is converted to speeds "
                                "(envdata.ts_profile); ts is for bathymetry areas")
            if self.ssp is not None:
                if self.ssp.bottom_m > self.depth_m:
                    raise AreaError(f"[water] sound-speed profile goes to {self.ssp.bottom_m} m, deeper "
                                    f"than the water, depth_m = {self.depth_m} m")
                if self.ssp.bottom_m < self.depth_m:
                    raise AreaError(f"[water] sound-speed profile ends at {self.ssp.bottom_m} m and does "
                                    f"not reach the bottom, depth_m = {self.depth_m} m")

    @property
    def is_flat(self) -> bool:
        """True when the bottom is flat (``depth_m``), False when a bathymetry file gives it."""
        return self.depth_m is not None

    @property
    def has_one_profile(self) -> bool:
        """True when one sound-speed profile holds for the whole area (no climatology)."""
        return self.climatology is None

    def to_dict(self) -> dict[str, Any]:
        """The ``[water]`` table: data files as they were given, a profile as its table."""
        out: dict[str, Any] = {}
        if self.depth_m is not None:
            out["depth_m"] = self.depth_m
        else:
            out["bathymetry"] = self.bathymetry.file.path
            if self.bathymetry.variable is not None:
                out["bathymetry_variable"] = self.bathymetry.variable
        if self.ssp is not None:
            if self.depth_m is None and self.ssp.kind == "munk":
                out.update({"ssp": "munk", "ssp_interpolation": self.ssp.interpolation})
            else:
                out.update({"ssp_depth_m": list(self.ssp.depth_m), "ssp_speed_mps": list(self.ssp.speed_mps),
                            "ssp_interpolation": self.ssp.interpolation})
        elif self.ts is not None:
            out.update(self.ts.to_dict())
        else:
            out.update(self.climatology.to_dict())
        return out


@dataclass(frozen=True, slots=True, kw_only=True)
class Observer:
    depth_m: float


@dataclass(frozen=True, slots=True, kw_only=True)
class GridSpec:
    range_max_m: float
    range_step_m: float
    depth_step_m: float

    def __post_init__(self) -> None:
        for name in ("range_max_m", "range_step_m", "depth_step_m"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise AreaError(f"[grid] {name}: must be > 0 m, got {value}")
        if self.range_step_m > self.range_max_m:
            raise AreaError(f"[grid] range_step_m: {self.range_step_m} m exceeds range_max_m "
                            f"{self.range_max_m} m")
        if self.range_max_m / self.range_step_m > 200_000:
            raise AreaError(f"[grid] range_step_m: {self.range_step_m} m gives more than 200000 ranges "
                            f"to {self.range_max_m} m")

    def range_m(self) -> np.ndarray:
        """Range axis: from range_step_m to range_max_m inclusive, m."""
        n = int(round(self.range_max_m / self.range_step_m))
        return self.range_step_m * np.arange(1, n + 1, dtype=float)


#: The surface's arrivals run's beams (the fan's angles) by default: at least this many, and at
#: least twice the fan's. Measured with its water mirrored above the surface
#: (docs/results/image-mirror.json): K of the 6-8 m ships from the observer, worst class and band
#: median, against their own runs on ocean-deep 0.16 dB with 3000 beams and 0.17 with 6000, and
#: against BELLHOP from the ship along the true paths on shelf-break 1.27 and 1.40 dB, means within
#: 0.31 and 0.48 dB of 0; the run with the surface it replaced took 6000 (0.20 and 1.70 dB, means
#: +0.1 to +1.8 dB) and cost 1.4 times BELLHOP's time of 3000 mirrored.
IMAGE_MIN_BEAMS = 3000


@dataclass(frozen=True, slots=True, kw_only=True)
class Propagation:
    """How BELLHOP is run; the defaults are what the accuracy study in bench/ supports."""

    mode: TlMode = TlMode.SEMICOHERENT  # the surface at the target's end (acoustics.surface)
    beam_type: str = "G"  # G: geometric hat beams (Cartesian); B: geometric Gaussian beams
    n_beams: int = 1500  # 0 lets BELLHOP choose (grows with range x frequency)
    angle_min_deg: float = -80.0
    angle_max_deg: float = 80.0
    freqs_per_band: int = 7
    frequency_shortcut: bool = True  # incoherent: one run per band, other frequencies via absorption
    absorption: Absorption = Absorption.THORP
    tl_max_db: float = 200.0  # zero pressure (shadow) is capped here, never inf
    # a BELLHOP run still running after this is killed, s; None: generous, scaled to the run's
    # beams x receivers (acoustics.bellhop.runner.default_timeout_s)
    run_timeout_s: float | None = None
    # BELLHOP's ray step, m; None: not set in the area file (range-dependent areas need one set
    # explicitly: BELLHOP's automatic step, a tenth of the depth, is not converged on deep radials)
    step_m: float | None = None
    # beams of the arrivals run that gives a table from the observer its near-surface rows (the
    # fan's angles); None: the rule of Propagation.image_beams (at least 3000,
    # at least twice n_beams). `tmakit grids check` says whether an area's count is converged.
    surface_image_beams: int | None = None
    # how far (m, in depth) a radial's .bty may pass from the bottom's samples, which are then
    # thinned to the fewest that hold it (acoustics.bellhop.radialfiles.thinned_bottom); 0: every
    # sample. BELLHOP shortens a ray's step at each bottom segment it crosses, so this cuts the
    # runs' time by about a third on a 50 km radial sampled every 100 m; the near-surface rows of
    # tables from the observer move by more than their beam noise (docs/models.md "A thinner bottom")
    bottom_tolerance_m: float = 0.0

    def __post_init__(self) -> None:
        if self.beam_type not in ("G", "g", "B", "R", "C"):
            raise AreaError(f"[propagation] beam_type: must be one of G, g, B, R, C, got {self.beam_type!r}")
        if not 0 <= self.n_beams <= 100_000:
            raise AreaError(f"[propagation] n_beams: must be in [0, 100000], got {self.n_beams}")
        if not -90.0 <= self.angle_min_deg < self.angle_max_deg <= 90.0:
            raise AreaError(f"[propagation] angles: need -90 <= angle_min_deg < angle_max_deg <= 90 deg, "
                            f"got {self.angle_min_deg}, {self.angle_max_deg}")
        if not 1 <= self.freqs_per_band <= 101:
            raise AreaError(f"[propagation] freqs_per_band: must be in [1, 101], got {self.freqs_per_band}")
        if not (math.isfinite(self.tl_max_db) and 50.0 <= self.tl_max_db <= 400.0):
            raise AreaError(f"[propagation] tl_max_db: must be in [50, 400] dB, got {self.tl_max_db}")
        if self.run_timeout_s is not None and not (math.isfinite(self.run_timeout_s)
                                                   and 0.0 < self.run_timeout_s <= 30 * 86400.0):
            raise AreaError(f"[propagation] run_timeout_s: must be in (0, 2592000] s (30 days), "
                            f"got {self.run_timeout_s}")
        if self.step_m is not None and not (math.isfinite(self.step_m) and 0.0 < self.step_m <= 100_000.0):
            raise AreaError(f"[propagation] step_m: must be in (0, 100000] m, got {self.step_m}")
        if self.surface_image_beams is not None and not 100 <= self.surface_image_beams <= 200_000:
            raise AreaError(f"[propagation] surface_image_beams: must be in [100, 200000], "
                            f"got {self.surface_image_beams}")
        if not (math.isfinite(self.bottom_tolerance_m) and 0.0 <= self.bottom_tolerance_m <= 1000.0):
            raise AreaError(f"[propagation] bottom_tolerance_m: must be in [0, 1000] m, got {self.bottom_tolerance_m}")

    @property
    def image_beams(self) -> int:
        """Beams of the surface's arrivals run: ``surface_image_beams``, or the default rule."""
        if self.surface_image_beams is not None:
            return int(self.surface_image_beams)
        return max(IMAGE_MIN_BEAMS, 2 * int(self.n_beams))


@dataclass(frozen=True, slots=True, kw_only=True)
class Area:
    name: str
    description: str
    water: Water
    bottom: Bottom
    noise: Noise
    observer: Observer
    sonar: Sonar
    bands: tuple[Band, ...]
    classes: tuple[TargetClass, ...]
    grid: GridSpec
    propagation: Propagation = field(default_factory=Propagation)
    latitude_deg: float = 45.0
    longitude_deg: float = -30.0
    # range- and bearing-dependent areas (docs/formats.md "[origin] and [bearings]"): the origin of the radials (then
    # latitude_deg and longitude_deg are the origin's) and their bearings; None: isotropic
    origin: Origin | None = None
    bearings: Bearings | None = None
    # many observer positions and months (README "Atlases"); None: one table at the origin
    atlas: AtlasSpec | None = None

    def __post_init__(self) -> None:
        if not self.bands:
            raise AreaError("[[bands]]: at least one band is required")
        if not self.classes:
            raise AreaError("[[classes]]: at least one class is required")
        for kind, items in (("band", self.bands), ("class", self.classes)):
            names = [item.name for item in items]
            dupes = sorted({n for n in names if names.count(n) > 1})
            if dupes:
                raise AreaError(f"duplicate {kind} name {dupes[0]!r}")
        self._check_origin()
        self._check_atlas()
        if self.water.depth_m is None:  # bathymetry: the radials check the depths (envdata.radials)
            if not (math.isfinite(self.observer.depth_m) and self.observer.depth_m > 0.0):
                raise AreaError(f"[observer] depth_m: must be > 0 m, got {self.observer.depth_m}")
            return
        if not 0.0 < self.observer.depth_m < self.water.depth_m:
            raise AreaError(f"[observer] depth_m: must be inside the water (0, {self.water.depth_m}) m, "
                            f"got {self.observer.depth_m}")
        for cls in self.classes:
            if not cls.depth_m < self.water.depth_m:
                raise AreaError(f"class {cls.name!r}: depth_m {cls.depth_m} m is not above the bottom "
                                f"at {self.water.depth_m} m")
        if self.grid.depth_step_m > self.water.depth_m:
            raise AreaError(f"[grid] depth_step_m: {self.grid.depth_step_m} m exceeds the water depth "
                            f"{self.water.depth_m} m")
        if self.water.depth_m / self.grid.depth_step_m > MAX_DEPTHS:
            raise AreaError(f"[grid] depth_step_m: {self.grid.depth_step_m} m gives more than "
                            f"{MAX_DEPTHS} depths to {self.water.depth_m} m")

    def _check_origin(self) -> None:
        files = [key for key, value in (("bathymetry", self.water.bathymetry),
                                        ("climatology", self.water.climatology)) if value is not None]
        if self.origin is None:
            if files:
                raise AreaError(f"[water] {files[0]}: a data file needs [origin] (lat_deg, lon_deg) and "
                                f"[bearings] to sample it along radials")
            if self.bearings is not None:
                raise AreaError("[bearings]: needs [origin] (lat_deg, lon_deg), the point the radials "
                                "start from")
            return
        if self.bearings is None:
            raise AreaError("[origin]: needs [bearings] (step_deg or bearing_deg), the radials to compute")
        if (self.latitude_deg, self.longitude_deg) != (self.origin.lat_deg, self.origin.lon_deg):
            raise AreaError(f"[area] latitude_deg, longitude_deg: {self.latitude_deg}, {self.longitude_deg} "
                            f"deg differ from [origin] {self.origin.lat_deg}, {self.origin.lon_deg} deg; "
                            f"give the position once, in [origin]")

    def _check_atlas(self) -> None:
        if self.atlas is None:
            return
        if self.origin is None:
            raise AreaError("[atlas]: needs [origin] and [bearings] (the atlas holds bearing-dependent "
                            "tables; [origin] is the reference point of the local plane)")
        months = self.atlas.months
        clim = self.water.climatology
        if months is not None and len(months) > 1 and clim is None:
            raise AreaError(f"[atlas] months: {list(months)}, but the area's sound speed is one profile, the "
                            f"same in every month; give one month, or a climatology")

    @property
    def atlas_months(self) -> tuple[int, ...]:
        """The atlas's months: ``[atlas] months``, else the area's ``[water] month``, else (0,):
        the data files' own water, whatever month that is."""
        if self.atlas is not None and self.atlas.months is not None:
            return self.atlas.months
        clim = self.water.climatology
        return (clim.month,) if clim is not None and clim.month is not None else (0,)

    @property
    def is_bearing_dependent(self) -> bool:
        """True for an area with an ``[origin]``: its grid has a ``bearing`` dimension."""
        return self.origin is not None

    def band(self, name: str) -> Band:
        for band in self.bands:
            if band.name == name:
                return band
        raise KeyError(name)

    def target_class(self, name: str) -> TargetClass:
        for cls in self.classes:
            if cls.name == name:
                return cls
        raise KeyError(name)

    def depth_m(self) -> np.ndarray:
        """Depth axis: 0 to the water depth inclusive, m (the last step may be shorter).

        Raises
        ------
        AreaError
            The bottom comes from a bathymetry file: the depth axis then runs to the deepest bottom
            of the radials (``envdata.radials.area_radials``).
        """
        if self.water.depth_m is None:
            raise AreaError(f"area {self.name!r}: the water depth comes from the bathymetry file "
                            f"{self.water.bathymetry.file.path!r}; the depth axis runs to the deepest "
                            f"bottom of the radials (envdata.radials.area_radials)")
        step = self.grid.depth_step_m
        z = np.arange(0.0, self.water.depth_m, step)
        if z[-1] < self.water.depth_m - 1e-9:
            z = np.append(z, self.water.depth_m)
        return z

    def to_dict(self) -> dict[str, Any]:
        """The area as an area-file document (docs/formats.md "Area file"), plain data.

        ``envdata.parse_area`` reads it back into an equal ``Area``: it is what grids store as
        ``area_json`` and what ``source_hash`` hashes. The profile is written as its table of
        speeds (what BELLHOP is given), whatever form the file gave it in; over a bathymetry file
        a T/S table or cast is written as its T/S table and the Munk profile by name. Data files
        (bathymetry, climatology) are written as the file gave their paths, so the document reads
        back without the files; a cast is written as the T/S table read from it.
        """
        classes = []
        for cls in self.classes:
            item = _plain(dataclasses.asdict(cls))
            if item["noise_mean_db"] is None:
                del item["noise_mean_db"]  # the Ross model needs none
            if item["depth_range_m"] is None:
                del item["depth_range_m"]  # optional: the tables' water column
            classes.append(item)
        out = {
            "area": {"name": self.name, "description": self.description,
                     "latitude_deg": self.latitude_deg, "longitude_deg": self.longitude_deg},
            "water": self.water.to_dict(),
            "bottom": dataclasses.asdict(self.bottom),
            "noise": dataclasses.asdict(self.noise),
            "observer": dataclasses.asdict(self.observer),
            "sonar": dataclasses.asdict(self.sonar),
            "bands": [dataclasses.asdict(band) for band in self.bands],
            "classes": classes,
            "grid": dataclasses.asdict(self.grid),
            # TOML has no null: an unset limit is absent; so is an unthinned bottom, which grids
            # built before the setting existed had (their source hash stays what it was)
            "propagation": {key: value for key, value in
                            _plain(dataclasses.asdict(self.propagation)).items()
                            if value is not None and not (key == "bottom_tolerance_m" and value == 0.0)},
        }
        if self.origin is not None:
            out["origin"] = {"lat_deg": self.origin.lat_deg, "lon_deg": self.origin.lon_deg}
            out["bearings"] = self.bearings.to_dict()
        if self.atlas is not None:
            out["atlas"] = self.atlas.to_dict()
        return out


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, StrEnum):
        return str(value)
    return value
