"""A sea area: water, bottom, noise, sonar, bands, target classes and the grid to compute.

``envdata.areafile`` reads the TOML format of DESIGN.md into a frozen, validated ``Area``;
``Area.to_dict`` is its inverse, the document that reads back into an equal ``Area``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

import numpy as np

from envdata.bands import Band
from envdata.bottom import Bottom
from envdata.classes import TargetClass
from envdata.errors import AreaError
from envdata.noise import Noise
from envdata.sonar import Sonar
from envdata.ssp import SoundSpeedProfile

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


@dataclass(frozen=True, slots=True, kw_only=True)
class Water:
    depth_m: float
    ssp: SoundSpeedProfile

    def __post_init__(self) -> None:
        if not (math.isfinite(self.depth_m) and 0.0 < self.depth_m <= 12000.0):
            raise AreaError(f"[water] depth_m: must be in (0, 12000] m, got {self.depth_m}")
        if self.ssp.bottom_m > self.depth_m:
            raise AreaError(f"[water] sound-speed profile goes to {self.ssp.bottom_m} m, deeper than "
                            f"the water, depth_m = {self.depth_m} m")
        if self.ssp.bottom_m < self.depth_m:
            raise AreaError(f"[water] sound-speed profile ends at {self.ssp.bottom_m} m and does not "
                            f"reach the bottom, depth_m = {self.depth_m} m")


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


@dataclass(frozen=True, slots=True, kw_only=True)
class Propagation:
    """How BELLHOP is run; the defaults are what the accuracy study in bench/ supports."""

    mode: TlMode = TlMode.INCOHERENT
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
        """Depth axis: 0 to the water depth inclusive, m (the last step may be shorter)."""
        step = self.grid.depth_step_m
        z = np.arange(0.0, self.water.depth_m, step)
        if z[-1] < self.water.depth_m - 1e-9:
            z = np.append(z, self.water.depth_m)
        return z

    def to_dict(self) -> dict[str, Any]:
        """The area as an area-file document (DESIGN.md "Area file"), plain data.

        ``envdata.parse_area`` reads it back into an equal ``Area``: it is what grids store as
        ``area_json`` and what ``source_hash`` hashes. The profile is written as its table of
        speeds (what BELLHOP is given), whatever form the file gave it in.
        """
        ssp = self.water.ssp
        classes = []
        for cls in self.classes:
            item = _plain(dataclasses.asdict(cls))
            if item["noise_mean_db"] is None:
                del item["noise_mean_db"]  # the Ross model needs none
            classes.append(item)
        return {
            "area": {"name": self.name, "description": self.description,
                     "latitude_deg": self.latitude_deg, "longitude_deg": self.longitude_deg},
            "water": {"depth_m": self.water.depth_m, "ssp_depth_m": list(ssp.depth_m),
                      "ssp_speed_mps": list(ssp.speed_mps), "ssp_interpolation": ssp.interpolation},
            "bottom": dataclasses.asdict(self.bottom),
            "noise": dataclasses.asdict(self.noise),
            "observer": dataclasses.asdict(self.observer),
            "sonar": dataclasses.asdict(self.sonar),
            "bands": [dataclasses.asdict(band) for band in self.bands],
            "classes": classes,
            "grid": dataclasses.asdict(self.grid),
            "propagation": {key: value for key, value in
                            _plain(dataclasses.asdict(self.propagation)).items()
                            if value is not None},  # TOML has no null: an unset limit is absent
        }


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, StrEnum):
        return str(value)
    return value
