"""A sea area: water, bottom, noise, sonar, bands, target classes and the grid to compute.

``load_area`` reads the TOML format of DESIGN.md into a frozen, validated ``Area``.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from enum import StrEnum
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from envdata.bands import Band
from envdata.bottom import Bottom
from envdata.classes import F_MINUS_2_DB_PER_OCTAVE, SourceLevelModel, TargetClass
from envdata.errors import AreaError
from envdata.noise import Noise
from envdata.sonar import Sonar
from envdata.ssp import SoundSpeedProfile, munk_profile, ts_profile

DEFAULT_AREA = "ocean-deep"


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
        """Plain-data form (for hashing and for writing back to TOML)."""
        return _plain(dataclasses.asdict(self))


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, StrEnum):
        return str(value)
    return value


# --------------------------------------------------------------------------- loading


class _Table:
    """Typed, key-checked access to one TOML table, with messages naming file and field."""

    def __init__(self, data: Any, where: str, source: str):
        self.source = source
        self.where = where
        if not isinstance(data, dict):
            raise AreaError(f"{source}: {where} must be a table, got {type(data).__name__}")
        self.data = dict(data)
        self.used: set[str] = set()

    def _fail(self, key: str, message: str) -> AreaError:
        return AreaError(f"{self.source}: {self.where} {key}: {message}")

    def _get(self, key: str, default: Any, required: bool) -> Any:
        self.used.add(key)
        if key not in self.data:
            if required:
                raise AreaError(f"{self.source}: {self.where}: missing required key {key!r}")
            return default
        return self.data[key]

    def number(self, key: str, default: float | None = None, *, required: bool = True) -> float | None:
        value = self._get(key, default, required and default is None)
        if value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self._fail(key, f"must be a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise self._fail(key, f"must be finite, got {value}")
        return value

    def integer(self, key: str, default: int) -> int:
        value = self._get(key, default, False)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self._fail(key, f"must be an integer, got {value!r}")
        return value

    def boolean(self, key: str, default: bool) -> bool:
        value = self._get(key, default, False)
        if not isinstance(value, bool):
            raise self._fail(key, f"must be true or false, got {value!r}")
        return value

    def string(self, key: str, default: str | None = None, *, required: bool = True,
               choices: tuple[str, ...] | None = None) -> str | None:
        value = self._get(key, default, required and default is None)
        if value is None:
            return None
        if not isinstance(value, str):
            raise self._fail(key, f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            raise self._fail(key, f"must be one of {', '.join(choices)}, got {value!r}")
        return value

    def numbers(self, key: str, *, required: bool = True) -> list[float] | None:
        value = self._get(key, None, required)
        if value is None:
            return None
        if not isinstance(value, list) or not value:
            raise self._fail(key, f"must be a non-empty list of numbers, got {value!r}")
        out = []
        for item in value:
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                raise self._fail(key, f"must be a list of numbers, got item {item!r}")
            if not math.isfinite(float(item)):
                raise self._fail(key, f"must be finite, got {item}")
            out.append(float(item))
        return out

    def has(self, key: str) -> bool:
        return key in self.data

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise AreaError(f"{self.source}: {self.where}: unknown key {unknown[0]!r}")

    def wrap(self, fn, *args, **kwargs):
        """Build a dataclass, prefixing its validation message with the file name."""
        try:
            return fn(*args, **kwargs)
        except AreaError as exc:
            raise AreaError(f"{self.source}: {exc}") from None


def read_toml(path: str | Path, what: str = "area file") -> tuple[dict[str, Any], str]:
    """Read a TOML file, turning every way it can be unreadable into an AreaError."""
    path = Path(path)
    source = str(path)
    if not path.exists():
        raise AreaError(f"{source}: {what} not found")
    if path.is_dir():
        raise AreaError(f"{source}: is a directory, not an {what}")
    raw = path.read_bytes()
    if not raw.strip():
        raise AreaError(f"{source}: empty {what}")
    if b"\x00" in raw:
        raise AreaError(f"{source}: binary file, not a TOML {what}")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise AreaError(f"{source}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    try:
        return tomllib.loads(text), source
    except tomllib.TOMLDecodeError as exc:
        raise AreaError(f"{source}: TOML syntax error: {exc}") from None


def builtin_area_names() -> list[str]:
    folder = resources.files("envdata") / "areas"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def area_path(name_or_path: str | Path) -> Path:
    """Resolve a built-in area name or a path to a TOML file."""
    text = str(name_or_path)
    if text in builtin_area_names():
        return Path(str(resources.files("envdata") / "areas" / f"{text}.toml"))
    path = Path(text)
    if path.suffix != ".toml" and not path.exists():
        raise AreaError(f"{text}: no built-in area of that name (built-in: "
                        f"{', '.join(builtin_area_names())}) and no such file")
    return path


def load_area(name_or_path: str | Path) -> Area:
    """Load a built-in area by name or an area TOML file; raises AreaError on bad input."""
    data, source = read_toml(area_path(name_or_path))
    return parse_area(data, source)


def parse_area(data: dict[str, Any], source: str = "<area>") -> Area:
    top = _Table(data, "top level", source)
    for key in ("area", "water", "bottom", "noise", "observer", "sonar", "bands", "classes", "grid"):
        top._get(key, None, True)
    top._get("propagation", None, False)
    top.done()

    t = _Table(data["area"], "[area]", source)
    name = t.string("name")
    if not name.strip() or any(ch in name for ch in "/\\ "):
        raise AreaError(f"{source}: [area] name: must be a non-empty identifier without spaces or "
                        f"slashes, got {name!r}")
    description = t.string("description", "")
    latitude = t.number("latitude_deg", 45.0)
    longitude = t.number("longitude_deg", -30.0)
    if not -90.0 <= latitude <= 90.0:
        raise AreaError(f"{source}: [area] latitude_deg: must be in [-90, 90] deg, got {latitude}")
    t.done()

    t = _Table(data["water"], "[water]", source)
    depth = t.number("depth_m")
    if not depth > 0:
        raise AreaError(f"{source}: [water] depth_m: must be > 0 m, got {depth}")
    interpolation = t.string("ssp_interpolation", "C", choices=("C", "S", "N", "P"))
    if t.has("ssp"):
        kind = t.string("ssp", choices=("munk",))
        ssp = t.wrap(munk_profile, depth)
        ssp = dataclasses.replace(ssp, interpolation=interpolation)
    elif t.has("temperature_c") or t.has("salinity_psu"):
        z = t.numbers("ssp_depth_m")
        temp = t.numbers("temperature_c")
        sal = t.numbers("salinity_psu")
        _check_depths(z, source)
        ssp = t.wrap(ts_profile, z, temp, sal, latitude_deg=latitude, longitude_deg=longitude)
        ssp = t.wrap(dataclasses.replace, ssp, interpolation=interpolation)
    else:
        z = t.numbers("ssp_depth_m")
        c = t.numbers("ssp_speed_mps")
        _check_depths(z, source)
        ssp = t.wrap(SoundSpeedProfile, depth_m=tuple(z), speed_mps=tuple(c), interpolation=interpolation)
    t.done()
    water = t.wrap(Water, depth_m=depth, ssp=ssp)

    t = _Table(data["bottom"], "[bottom]", source)
    bottom = t.wrap(Bottom, speed_mps=t.number("speed_mps"), density_gcc=t.number("density_gcc"),
                    attenuation_db_per_wavelength=t.number("attenuation_db_per_wavelength", 0.0),
                    shear_speed_mps=t.number("shear_speed_mps", 0.0))
    t.done()

    t = _Table(data["noise"], "[noise]", source)
    noise = t.wrap(Noise, spectrum_level_1khz_db=t.number("spectrum_level_1khz_db"),
                   slope_db_per_octave=t.number("slope_db_per_octave", -5.0))
    t.done()

    t = _Table(data["observer"], "[observer]", source)
    observer = Observer(depth_m=t.number("depth_m"))
    t.done()

    t = _Table(data["sonar"], "[sonar]", source)
    sonar = t.wrap(Sonar, beamwidth_deg=t.number("beamwidth_deg"),
                   directivity_index_db=t.number("directivity_index_db"),
                   integration_time_s=t.number("integration_time_s"),
                   detection_threshold=t.number("detection_threshold"),
                   receiver_gain_db=t.number("receiver_gain_db", 0.0))
    t.done()

    bands = []
    for i, item in enumerate(_array_of_tables(data["bands"], "[[bands]]", source)):
        t = _Table(item, f"[[bands]] #{i + 1}", source)
        bands.append(t.wrap(Band, name=t.string("name"), low_hz=t.number("low_hz"),
                            high_hz=t.number("high_hz")))
        t.done()

    classes = []
    for i, item in enumerate(_array_of_tables(data["classes"], "[[classes]]", source)):
        t = _Table(item, f"[[classes]] #{i + 1}", source)
        model = t.string("source_level_model", "p0", choices=tuple(m.value for m in SourceLevelModel))
        classes.append(t.wrap(
            TargetClass, name=t.string("name"), depth_m=t.number("depth_m"),
            speed_mean_mps=t.number("speed_mean_mps"), speed_sd_mps=t.number("speed_sd_mps"),
            noise_mean_db=t.number("noise_mean_db", required=model == "p0"),
            noise_sd_db=t.number("noise_sd_db", 0.0), k_error_sd_db=t.number("k_error_sd_db", 2.0),
            source_slope_db_per_octave=t.number("source_slope_db_per_octave", F_MINUS_2_DB_PER_OCTAVE),
            source_level_model=SourceLevelModel(model)))
        t.done()

    t = _Table(data["grid"], "[grid]", source)
    grid = t.wrap(GridSpec, range_max_m=t.number("range_max_m"), range_step_m=t.number("range_step_m"),
                  depth_step_m=t.number("depth_step_m"))
    t.done()

    defaults = Propagation()
    if "propagation" in data:
        t = _Table(data["propagation"], "[propagation]", source)
        propagation = t.wrap(
            Propagation,
            mode=TlMode(t.string("mode", defaults.mode.value, choices=tuple(m.value for m in TlMode))),
            beam_type=t.string("beam_type", defaults.beam_type),
            n_beams=t.integer("n_beams", defaults.n_beams),
            angle_min_deg=t.number("angle_min_deg", defaults.angle_min_deg),
            angle_max_deg=t.number("angle_max_deg", defaults.angle_max_deg),
            freqs_per_band=t.integer("freqs_per_band", defaults.freqs_per_band),
            frequency_shortcut=t.boolean("frequency_shortcut", defaults.frequency_shortcut),
            absorption=Absorption(t.string("absorption", defaults.absorption.value,
                                           choices=tuple(a.value for a in Absorption))),
            tl_max_db=t.number("tl_max_db", defaults.tl_max_db))
        t.done()
    else:
        propagation = defaults

    return _wrap_area(source, name=name, description=description, water=water, bottom=bottom,
                      noise=noise, observer=observer, sonar=sonar, bands=tuple(bands),
                      classes=tuple(classes), grid=grid, propagation=propagation,
                      latitude_deg=latitude, longitude_deg=longitude)


def _wrap_area(source: str, **kwargs) -> Area:
    try:
        return Area(**kwargs)
    except AreaError as exc:
        raise AreaError(f"{source}: {exc}") from None


def _array_of_tables(value: Any, where: str, source: str) -> list:
    if not isinstance(value, list) or not value:
        raise AreaError(f"{source}: {where}: need at least one entry (an array of tables)")
    return value


def _check_depths(z: list[float], source: str) -> None:
    if any(v < 0 for v in z):
        raise AreaError(f"{source}: [water] ssp_depth_m: depths must be >= 0 m, "
                        f"got {min(z)} m")
