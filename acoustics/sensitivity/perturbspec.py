"""Perturbation specs for environmental sensitivity studies: what is uncertain, and how much.

A perturbation names a quantity of the area and a standard deviation (`Perturbation`); specs
come from ``--perturb`` or a TOML file (`parse_spec`), or the default set (`default_perturbations`).
Drawing and applying them is `acoustics.sensitivity.perturb`.

Spec syntax (``--perturb``), ``KIND:KEY=VALUE,KEY=VALUE``, or a TOML file of ``[[perturb]]``
tables with ``kind = "..."`` and the same keys:

===================== ======================================= ===============================
kind                  keys (default)                          what is drawn
===================== ======================================= ===============================
displace              sd_m                                    vertical displacement of the
                                                              profile, mode 1: zeta(z) =
                                                              d sin(pi z / D)
mixed-layer           sd_m, mean_m (50)                       depth h of an isothermal surface
                                                              mixed layer (c = c(h) - g (h-z))
temperature           sd_c, scale_m (200)                     temperature change dT exp(-z/L),
                                                              converted with TEOS-10
salinity              sd_psu, scale_m (200)                   salinity change, TEOS-10
eof                   sd_mps, modes (3), depth_m (1000)       EOF-style speed modes
                                                              cos((n-1/2) pi z/H), sd/n each
bottom-speed          sd_mps                                  bottom compressional speed
bottom-density        sd_gcc                                  bottom density
bottom-attenuation    sd_db_per_wavelength                    bottom attenuation
water-depth           sd_m                                    water depth (profile cut or
                                                              extended with its last gradient)
source-depth          sd_frac                                 class depths x (1 + e)
observer-depth        sd_m                                    observer depth
relief                sd_m (0), sd_frac (0), corr_km (5)      a smooth random field added to
                                                              the bathymetry (areas with data)
water                 sd_factor (1), sd_c, sd_psu (the        T and S changed by smooth fields
                      file's t_sd/s_sd), scale_m (200),       scaled by their sds
                      corr_km (20)
front                 sd_km (0), east_km, north_km            the whole T/S field displaced;
                                                              a given east/north: a what-if
month                 sd_months (0), offset_months            a mix of the area's month and a
                                                              neighbour; given: a what-if
===================== ======================================= ===============================

The first block perturbs one profile over a flat bottom (areas without ``[origin]``); relief,
water, front and month perturb the data files of an area with an ``[origin]``
(``envdata.fieldchange``); the bottom, source and observer kinds serve both.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

from envdata.area import Area
from envdata.errors import AreaError, InputError
from envdata.tomlfile import read_toml


class PerturbationError(InputError):
    """A malformed or unphysical perturbation spec."""


class Kind(StrEnum):
    MIXED_LAYER = "mixed-layer"
    DISPLACE = "displace"
    TEMPERATURE = "temperature"
    SALINITY = "salinity"
    EOF = "eof"
    WATER_DEPTH = "water-depth"
    BOTTOM_SPEED = "bottom-speed"
    BOTTOM_DENSITY = "bottom-density"
    BOTTOM_ATTENUATION = "bottom-attenuation"
    SOURCE_DEPTH = "source-depth"
    OBSERVER_DEPTH = "observer-depth"
    RELIEF = "relief"
    WATER = "water"
    FRONT = "front"
    MONTH = "month"


#: Kinds that change one profile over a flat bottom (areas without [origin]).
PROFILE_KINDS = frozenset({Kind.MIXED_LAYER, Kind.DISPLACE, Kind.TEMPERATURE, Kind.SALINITY, Kind.EOF,
                           Kind.WATER_DEPTH})
#: Kinds that change the data an area with [origin] reads (``envdata.fieldchange``).
FIELD_KINDS = frozenset({Kind.RELIEF, Kind.WATER, Kind.FRONT, Kind.MONTH})
#: The sd key of these kinds may be left out (its default follows).
SD_DEFAULTS = {Kind.RELIEF: 0.0, Kind.WATER: 1.0, Kind.FRONT: 0.0, Kind.MONTH: 0.0}
#: Options whose default is "not given" (NaN): a file's own sd, or a drawn value.
UNSET_OPTIONS = frozenset({"sd_c", "sd_psu", "east_km", "north_km", "offset_months"})


# kind -> (sd key, {other key: default}); the enum order above is the order of application
KEYS: dict[Kind, tuple[str, dict[str, float]]] = {
    Kind.MIXED_LAYER: ("sd_m", {"mean_m": 50.0}),
    Kind.DISPLACE: ("sd_m", {}),
    Kind.TEMPERATURE: ("sd_c", {"scale_m": 200.0}),
    Kind.SALINITY: ("sd_psu", {"scale_m": 200.0}),
    Kind.EOF: ("sd_mps", {"modes": 3, "depth_m": 1000.0}),
    Kind.WATER_DEPTH: ("sd_m", {}),
    Kind.BOTTOM_SPEED: ("sd_mps", {}),
    Kind.BOTTOM_DENSITY: ("sd_gcc", {}),
    Kind.BOTTOM_ATTENUATION: ("sd_db_per_wavelength", {}),
    Kind.SOURCE_DEPTH: ("sd_frac", {}),
    Kind.OBSERVER_DEPTH: ("sd_m", {}),
    Kind.RELIEF: ("sd_m", {"sd_frac": 0.0, "corr_km": 5.0}),
    Kind.WATER: ("sd_factor", {"sd_c": math.nan, "sd_psu": math.nan, "scale_m": 200.0, "corr_km": 20.0}),
    Kind.FRONT: ("sd_km", {"east_km": math.nan, "north_km": math.nan}),
    Kind.MONTH: ("sd_months", {"offset_months": math.nan}),
}


@dataclass(frozen=True, slots=True, kw_only=True)
class Perturbation:
    """One uncertain quantity: its kind, standard deviation and shape options."""

    kind: Kind
    sd: float
    options: tuple[tuple[str, float], ...] = ()
    source: str = "perturbation"  # where the spec came from, for messages

    def __post_init__(self) -> None:
        sd_key, _ = KEYS[self.kind]
        if not (math.isfinite(self.sd) and self.sd >= 0.0):
            raise PerturbationError(f"{self.source}: perturbation {self.kind}: {sd_key} must be a finite "
                                    f"number >= 0, got {self.sd}")
        for key, value in self.options:
            if not math.isfinite(value) and not (key in UNSET_OPTIONS and math.isnan(value)):
                raise PerturbationError(f"{self.source}: perturbation {self.kind}: {key} must be finite, "
                                        f"got {value}")
        opts = dict(self.options)
        for key in ("sd_frac", "sd_c", "sd_psu"):
            if key in opts and opts[key] < 0:
                raise PerturbationError(f"{self.source}: perturbation {self.kind}: {key} must be >= 0, "
                                        f"got {opts[key]:g}")
        if "corr_km" in opts and not opts["corr_km"] > 0:
            raise PerturbationError(f"{self.source}: perturbation {self.kind}: corr_km must be > 0 km, "
                                    f"got {opts['corr_km']:g}")
        if self.kind is Kind.RELIEF and opts["sd_frac"] > 1.0:
            raise PerturbationError(f"{self.source}: perturbation relief: sd_frac must be <= 1 (a fraction "
                                    f"of the depth), got {opts['sd_frac']:g}")
        if self.kind is Kind.FRONT:
            for key in ("east_km", "north_km"):
                if abs(opts[key]) > 500.0:
                    raise PerturbationError(f"{self.source}: perturbation front: {key} must be within "
                                            f"+-500 km, got {opts[key]:g}")
            if self.sd > 500.0:
                raise PerturbationError(f"{self.source}: perturbation front: sd_km must be <= 500 km, "
                                        f"got {self.sd:g}")
        if self.kind is Kind.MONTH:
            offset = opts["offset_months"]
            if self.sd > 0.25:
                raise PerturbationError(f"{self.source}: perturbation month: sd_months must be <= 0.25 (the draws, "
                                        f"truncated at 4 sd, stay within a month of the area's), got {self.sd:g}")
            if not math.isnan(offset) and not (abs(offset) <= 1.0 or (offset == int(offset) and abs(offset) <= 6)):
                raise PerturbationError(f"{self.source}: perturbation month: offset_months must be within +-1 "
                                        f"(a mix with the neighbouring month) or a whole number of months "
                                        f"within +-6, got {offset:g}")
        if self.kind is Kind.EOF and not (opts["modes"] == int(opts["modes"]) and 1 <= opts["modes"] <= 10):
            raise PerturbationError(f"{self.source}: perturbation eof: modes must be an integer in [1, 10], "
                                    f"got {opts['modes']:g}")
        for key in ("scale_m", "depth_m"):
            if key in opts and not opts[key] > 0:
                raise PerturbationError(f"{self.source}: perturbation {self.kind}: {key} must be > 0 m, "
                                        f"got {opts[key]:g}")
        if "mean_m" in opts and not opts["mean_m"] >= 0:
            raise PerturbationError(f"{self.source}: perturbation {self.kind}: mean_m must be >= 0 m, "
                                    f"got {opts['mean_m']:g}")

    def option(self, key: str) -> float:
        return dict(self.options)[key]

    @property
    def sd_key(self) -> str:
        return KEYS[self.kind][0]

    @property
    def n_draws(self) -> int:
        return int(self.option("modes")) if self.kind is Kind.EOF else 2 if self.kind is Kind.FRONT else 1

    @property
    def is_what_if(self) -> bool:
        """A fixed change (``front:north_km=5``, ``month:offset_months=1``) rather than a draw."""
        return any(key in UNSET_OPTIONS and key not in ("sd_c", "sd_psu") and not math.isnan(v)
                   for key, v in self.options)

    def param_names(self) -> list[str]:
        """Names of the member coordinates this perturbation records."""
        return {Kind.MIXED_LAYER: ["mixed_layer_depth_m"], Kind.DISPLACE: ["displace_dz_m"],
                Kind.TEMPERATURE: ["temperature_dt_c"], Kind.SALINITY: ["salinity_ds_psu"],
                Kind.EOF: [f"eof_a{n + 1}_mps" for n in range(self.n_draws)],
                Kind.WATER_DEPTH: ["water_depth_m"], Kind.BOTTOM_SPEED: ["bottom_speed_mps"],
                Kind.BOTTOM_DENSITY: ["bottom_density_gcc"],
                Kind.BOTTOM_ATTENUATION: ["bottom_attenuation_db_per_wavelength"],
                Kind.SOURCE_DEPTH: ["source_depth_factor"],
                Kind.OBSERVER_DEPTH: ["observer_depth_m"],
                Kind.RELIEF: ["relief_dz_origin_m"], Kind.WATER: ["water_t_index", "water_s_index"],
                Kind.FRONT: ["front_east_km", "front_north_km"], Kind.MONTH: ["month_offset"]}[self.kind]

    def given_options(self) -> tuple[tuple[str, float], ...]:
        """The options with a value (those left unset, NaN, are not shown or stored)."""
        return tuple((k, v) for k, v in self.options if not math.isnan(v))

    def describe(self) -> str:
        opts = ",".join(f"{k}={v:g}" for k, v in self.given_options())
        return f"{self.kind}:{self.sd_key}={self.sd:g}" + (f",{opts}" if opts else "")

    def to_dict(self) -> dict:
        return {"kind": str(self.kind), self.sd_key: self.sd, **dict(self.given_options())}


def make_perturbation(kind: str, values: dict, source: str) -> Perturbation:
    """Build a Perturbation from a kind name and its keys, checking names and types."""
    if kind not in {k.value for k in Kind}:
        raise PerturbationError(f"{source}: unknown perturbation kind {kind!r} (known: "
                                f"{', '.join(k.value for k in Kind)})")
    k = Kind(kind)
    sd_key, defaults = KEYS[k]
    unknown = sorted(set(values) - {sd_key, *defaults})
    if unknown:
        raise PerturbationError(f"{source}: perturbation {kind}: unknown key {unknown[0]!r} (keys: "
                                f"{', '.join([sd_key, *defaults])})")
    if sd_key not in values and k not in SD_DEFAULTS:
        raise PerturbationError(f"{source}: perturbation {kind}: missing required key {sd_key!r}")
    parsed = {}
    for key, value in values.items():
        if isinstance(value, str):
            try:
                value = float(value)
            except ValueError:
                raise PerturbationError(f"{source}: perturbation {kind}: {key} must be a number, "
                                        f"got {value!r}") from None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise PerturbationError(f"{source}: perturbation {kind}: {key} must be a number, got {value!r}")
        parsed[key] = float(value)
    options = tuple((key, parsed.get(key, default)) for key, default in defaults.items())
    return Perturbation(kind=k, sd=parsed.get(sd_key, SD_DEFAULTS.get(k, 0.0)), options=options, source=source)


def parse_spec(text: str, source: str | None = None) -> list[Perturbation]:
    """Parse one perturbation spec: ``KIND:KEY=VALUE,...`` or the path of a TOML spec file;
    ``source`` names it in messages (default ``perturbation TEXT``)."""
    text = text.strip()
    if text.endswith(".toml") or (Path(text).exists() and ":" not in text):
        return load_perturbations(text)
    source = source or f"perturbation {text}"
    kind, sep, rest = text.partition(":")
    if not sep or not rest.strip():
        raise PerturbationError(f"{source}: expected KIND:KEY=VALUE[,KEY=VALUE...], e.g. displace:sd_m=10")
    values = {}
    for item in rest.split(","):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise PerturbationError(f"{source}: expected KEY=VALUE, got {item!r}")
        if key.strip() in values:
            raise PerturbationError(f"{source}: key {key.strip()!r} given twice")
        values[key.strip()] = value.strip()
    return [make_perturbation(kind.strip(), values, source)]


def load_perturbations(path: str | Path) -> list[Perturbation]:
    """Read a TOML file of ``[[perturb]]`` tables (each ``kind = ...`` plus its keys)."""
    try:
        data, source = read_toml(path, what="perturbation file")
    except AreaError as exc:
        raise PerturbationError(str(exc)) from None
    unknown = sorted(set(data) - {"perturb"})
    if unknown:
        raise PerturbationError(f"{source}: unknown top-level key {unknown[0]!r} (expected [[perturb]] tables)")
    items = data.get("perturb")
    if not isinstance(items, list) or not items or not all(isinstance(i, dict) for i in items):
        raise PerturbationError(f"{source}: need at least one [[perturb]] table")
    out = []
    for i, item in enumerate(items):
        where = f"{source}: [[perturb]] #{i + 1}"
        item = dict(item)
        kind = item.pop("kind", None)
        if not isinstance(kind, str):
            raise PerturbationError(f"{where}: missing or non-string 'kind', got {kind!r}")
        out.append(make_perturbation(kind, item, where))
    return out


def check_kind_fits(area: Area, p: Perturbation) -> None:
    """Refuse a kind the area cannot take: a profile kind on an area with [origin], a data kind
    on one without, or on one without the data it changes."""
    if p.kind in PROFILE_KINDS and area.is_bearing_dependent:
        raise PerturbationError(f"{p.source}: perturbation {p.kind} changes one profile over a flat bottom; "
                                f"area {area.name} is computed along radials from its data (use relief, "
                                f"water, front or month)")
    if p.kind in FIELD_KINDS:
        water = area.water
        if not area.is_bearing_dependent:
            raise PerturbationError(f"{p.source}: perturbation {p.kind} changes the data of an area with "
                                    f"[origin]; area {area.name} has one profile over a flat bottom")
        if p.kind is Kind.RELIEF and water.bathymetry is None:
            raise PerturbationError(f"{p.source}: perturbation relief: area {area.name} has no [water] "
                                    f"bathymetry file to perturb")
        if p.kind is not Kind.RELIEF and water.climatology is None:
            raise PerturbationError(f"{p.source}: perturbation {p.kind}: area {area.name} has no "
                                    f"climatology ([water] temperature/salinity or climatology) to perturb")


def default_perturbations(area: Area) -> list[Perturbation]:
    """What the usual tables leave uncertain (see docs/sensitivity.md): on a flat area a profile
    measured well, an uncertain bottom and target depth; on an area with data, the relief between
    soundings and the water masses, the bottom and the depths."""
    if area.is_bearing_dependent:
        return _default_field_perturbations(area)
    depth = area.water.depth_m
    # a 10 m displacement, less in shallow water (|d| pi / depth <= 0.5 at 4 sd: no truncation)
    specs = [f"displace:sd_m={min(10.0, 0.04 * depth):g}", "temperature:sd_c=0.3,scale_m=300", "bottom-speed:sd_mps=30",
             "bottom-density:sd_gcc=0.1", "bottom-attenuation:sd_db_per_wavelength=0.2",
             f"water-depth:sd_m={0.01 * depth:g}", "source-depth:sd_frac=0.15",
             "observer-depth:sd_m=2"]
    out = [p for s in specs for p in parse_spec(s)]
    return [dataclasses.replace(p, source="default perturbations") for p in out]


def _default_field_perturbations(area: Area) -> list[Perturbation]:
    specs = ["bottom-speed:sd_mps=30", "bottom-density:sd_gcc=0.1",
             "bottom-attenuation:sd_db_per_wavelength=0.2", "source-depth:sd_frac=0.15", "observer-depth:sd_m=2"]
    if area.water.bathymetry is not None:
        specs.insert(0, "relief:sd_frac=0.05,corr_km=5")
    if area.water.climatology is not None:
        from envdata.climatology import open_climatology

        with open_climatology(area.water.climatology) as clim:
            own = clim.has_sd
        specs.insert(1, "water:sd_factor=1" if own else "water:sd_c=0.3,sd_psu=0.05")
    out = [p for s in specs for p in parse_spec(s)]
    return [dataclasses.replace(p, source="default perturbations") for p in out]
