"""One variable of a climatology or reanalysis file (``envdata.climatology``): found by its
given, common or CF standard name, what it holds (in-situ, potential or Conservative
Temperature; practical or Absolute Salinity) and in which units, its time steps for a month,
its depth axis, and its values cut to a box of cells."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from envdata.datafiles import DataFile
from envdata.errors import AreaError
from envdata.geogrid import (
    METRE_UNITS,
    LatLonAxes,
    named_variable,
    open_dataset,
    units_of,
)
from envdata.limits import check_memory
from envdata.seawater import SALINITY_STANDARD_NAMES as SALINITY_KINDS
from envdata.seawater import TEMPERATURE_STANDARD_NAMES as TEMPERATURE_KINDS
from envdata.seawater import SalinityKind, TemperatureKind

#: Common names, and what each holds (None: told by its attributes, else in-situ / practical).
TEMPERATURE_NAMES = {"t_an": TemperatureKind.IN_SITU, "thetao": TemperatureKind.POTENTIAL,
                     "votemper": TemperatureKind.POTENTIAL, "bigthetao": TemperatureKind.CONSERVATIVE,
                     "water_temp": TemperatureKind.IN_SITU, "temperature": None, "temp": None}
SALINITY_NAMES = {"s_an": SalinityKind.PRACTICAL, "so": SalinityKind.PRACTICAL,
                  "vosaline": SalinityKind.PRACTICAL, "absso": SalinityKind.ABSOLUTE, "salinity": None,
                  "salt": None}
TEMPERATURE_STANDARD_NAMES = tuple(TEMPERATURE_KINDS)  # in-situ first
SALINITY_STANDARD_NAMES = tuple(SALINITY_KINDS)
#: Other CF quantities a climatology may hold; refused with a message.
OTHER_KINDS = {"sea_water_preformed_salinity": "preformed salinity",
               "sea_water_reference_salinity": "Reference Salinity",
               "sea_water_cox_salinity": "Cox salinity",
               "sea_water_knudsen_salinity": "Knudsen salinity"}
TEMPERATURE_UNITS = ("degrees_celsius", "degree_celsius", "degrees_c", "degree_c", "degc", "deg_c",
                     "celsius", "degreec", "degreesc", "°c")
KELVIN_UNITS = ("k", "kelvin", "kelvins", "degk", "deg_k", "degree_k", "degrees_k")
SALINITY_UNITS = ("", "1", "psu", "pss-78", "pss78", "pss", "0.001", "1e-3", "unitless", "g/kg", "g_kg-1",
                  "g_kg^-1", "g.kg-1", "g_kg**-1")
#: Kelvin to degrees Celsius.
ZERO_CELSIUS_K = 273.15
#: Values beyond this are a fill value the file did not declare.
MAX_ABS_VALUE = 1.0e5



@dataclass(eq=False)
class ClimVariable:
    """One climatology variable in one file: where it is, what it holds and how to cut it."""

    path: Path
    name: str
    what: str  # "temperature" or "salinity", for messages
    var: object
    kind: TemperatureKind | SalinityKind
    offset: float  # added on loading (kelvin to degC)
    axes: LatLonAxes
    depth_dim: str
    depth_values: np.ndarray  # as stored, m positive down
    time_dim: str | None
    time_index: tuple[int, ...] | None  # the steps to load (several: their mean)
    sd_name: str | None = None  # WOA's standard deviation beside it (t_sd, s_sd)
    sd_var: object = None

    @property
    def depth_sorted(self) -> np.ndarray:
        return np.sort(self.depth_values)

    @classmethod
    def open(cls, file: DataFile, what: str, month, opened: list, given: str | None = None) -> "ClimVariable":
        path = file.resolved()
        ds = open_dataset(path, f"{what} climatology file")
        opened.append(ds)
        name = _find(ds, path, what, given)
        var = ds[name]
        std = var.attrs.get("standard_name")
        if std in OTHER_KINDS:
            raise AreaError(f"{path}: {name!r} holds {OTHER_KINDS[std]} ({std}); tmakit reads in-situ, "
                            f"potential or Conservative Temperature and practical or Absolute Salinity")
        kind = _kind_of(var, name, what)
        if what == "temperature" and std is not None and std not in TEMPERATURE_KINDS and given is not None:
            raise AreaError(f"{path}: variable {name!r} (the temperature) has standard_name {std!r}; need one "
                            f"of {', '.join(TEMPERATURE_KINDS)}")
        if what == "salinity" and std is not None and std not in SALINITY_KINDS and given is not None:
            raise AreaError(f"{path}: variable {name!r} (the salinity) has standard_name {std!r}; need one "
                            f"of {', '.join(SALINITY_KINDS)}")
        offset = _unit_offset(var, name, what, path)
        axes = LatLonAxes.of(ds, name, path)
        others = [str(d) for d in var.dims if str(d) not in (axes.lat_dim, axes.lon_dim)]
        depth_dim = next((d for d in others if _is_depth(ds, d)), None)
        if depth_dim is None:
            raise AreaError(f"{path}: variable {name!r} has no depth axis among its dimensions "
                            f"({', '.join(map(str, var.dims))})")
        depth = _depth_values(ds, depth_dim, path)
        rest = [d for d in others if d != depth_dim]
        if len(rest) > 1:
            raise AreaError(f"{path}: variable {name!r} has dimensions ({', '.join(map(str, var.dims))}); "
                            f"need (time, depth, lat, lon)")
        time_dim = rest[0] if rest else None
        index = _time_steps(ds, path, name, var, time_dim, month)
        sd_name = sd_var = None
        if name.endswith("_an") and f"{name[:-3]}_sd" in ds.data_vars:
            sd_name = f"{name[:-3]}_sd"
            sd_var = ds[sd_name]
            if tuple(sd_var.dims) != tuple(var.dims):
                raise AreaError(f"{path}: {sd_name!r} has dimensions ({', '.join(map(str, sd_var.dims))}), "
                                f"not those of {name!r} ({', '.join(map(str, var.dims))})")
            _unit_offset(sd_var, sd_name, what, path)  # the same units (a kelvin sd needs no offset)
        return cls(path=path, name=name, what=what, var=var, kind=kind, offset=offset, axes=axes,
                   depth_dim=depth_dim, depth_values=depth, time_dim=time_dim, time_index=index,
                   sd_name=sd_name, sd_var=sd_var)

    def load(self, lat_slice: slice, lon_slice: slice, lat_flip: bool, lon_flip: bool) -> np.ndarray:
        """(Z, ny, nx) values of the box, levels increasing, axes increasing; NaN for no value;
        degC for a temperature."""
        return self._load(self.var, lat_slice, lon_slice, lat_flip, lon_flip) + self.offset

    def load_sd(self, lat_slice: slice, lon_slice: slice, lat_flip: bool, lon_flip: bool) -> np.ndarray | None:
        """The standard deviation's box like `load` (no offset: a spread in K is one in degC);
        None when the file has none."""
        if self.sd_var is None:
            return None
        return self._load(self.sd_var, lat_slice, lon_slice, lat_flip, lon_flip)

    def _load(self, var, lat_slice: slice, lon_slice: slice, lat_flip: bool, lon_flip: bool) -> np.ndarray:
        ny, nx = lat_slice.stop - lat_slice.start, lon_slice.stop - lon_slice.start
        steps = len(self.time_index) if self.time_index is not None else 1
        check_memory(4.0 * 8 * steps * self.depth_values.size * ny * nx,
                     f"{self.path}: the {steps} x {self.depth_values.size} x {ny} x {nx} climatology cells "
                     f"the radials cross")
        sel = {self.axes.lat_dim: lat_slice, self.axes.lon_dim: lon_slice}
        dims = (self.depth_dim, self.axes.lat_dim, self.axes.lon_dim)
        if self.time_dim is not None:
            sel[self.time_dim] = list(self.time_index)
            dims = (self.time_dim,) + dims
        block = var.isel(sel).transpose(*dims)
        values = np.asarray(block.values, dtype=float)
        values[~(np.abs(values) <= MAX_ABS_VALUE)] = np.nan
        if self.time_dim is not None:  # the mean of the steps picked (one, mostly)
            valid = np.isfinite(values)
            count = valid.sum(axis=0)
            total = np.where(valid, values, 0.0).sum(axis=0)
            values = np.where(count > 0, total / np.maximum(count, 1), np.nan)
        order = np.argsort(self.depth_values)
        values = values[order]
        if lat_flip:
            values = values[:, ::-1, :]
        if lon_flip:
            values = values[:, :, ::-1]
        return values


def _find(ds, path: Path, what: str, given: str | None) -> str:
    """The variable holding the temperature or salinity: given, by name, or by standard_name."""
    names, kinds = ((TEMPERATURE_NAMES, TEMPERATURE_KINDS) if what == "temperature"
                    else (SALINITY_NAMES, SALINITY_KINDS))
    key = f"[water] {what}_variable"
    found = named_variable(ds, path, f"the {what}, {key}", names, given)
    if found is not None:
        return found
    for standard_name in kinds:  # in-situ (or practical) first
        matches = [str(n) for n, v in ds.data_vars.items() if v.attrs.get("standard_name") == standard_name]
        if len(matches) == 1:
            return matches[0]
        if len(matches) > 1:
            raise AreaError(f"{path}: several variables could be the {what} ({', '.join(matches)}, by "
                            f"standard_name {standard_name}); name one with {key}")
    other = next((str(n) for n, v in ds.data_vars.items() if v.attrs.get("standard_name") in OTHER_KINDS), None)
    if other is not None:
        return other  # refused with its kind named
    raise AreaError(f"{path}: no {what} variable: none is named {' or '.join(names)} or has the "
                    f"standard_name {' or '.join(kinds)}; the file has "
                    f"{', '.join(sorted(map(str, ds.data_vars))) or 'no data variables'} (name it with {key})")


def _kind_of(var, name: str, what: str) -> TemperatureKind | SalinityKind:
    """What a variable holds: its standard_name, else its name, else its long_name, else in-situ
    temperature or practical salinity."""
    kinds, names = ((TEMPERATURE_KINDS, TEMPERATURE_NAMES) if what == "temperature"
                    else (SALINITY_KINDS, SALINITY_NAMES))
    std = var.attrs.get("standard_name")
    if std in kinds:
        return kinds[std]
    if names.get(name) is not None:
        return names[name]
    long_name = str(var.attrs.get("long_name", "")).lower()
    if what == "temperature":
        if "conservative" in long_name:
            return TemperatureKind.CONSERVATIVE
        return TemperatureKind.POTENTIAL if "potential" in long_name else TemperatureKind.IN_SITU
    return SalinityKind.ABSOLUTE if "absolute" in long_name else SalinityKind.PRACTICAL


def _unit_offset(var, name: str, what: str, path: Path) -> float:
    """What to add to the values for degC (kelvin: -273.15; degC and salinity: 0)."""
    unit = units_of(var)
    key = unit.lower().replace(" ", "_")
    if what == "temperature":
        if key in TEMPERATURE_UNITS:
            return 0.0
        if key in KELVIN_UNITS:
            return -ZERO_CELSIUS_K
        raise AreaError(f"{path}: variable {name!r} (temperature) has units {unit!r}; need degrees_celsius "
                        f"or K")
    if key in SALINITY_UNITS:
        return 0.0
    raise AreaError(f"{path}: variable {name!r} (salinity) has units {unit!r}; need practical salinity "
                    f"(1, 1e-3 or psu) or g/kg")


def _time_steps(ds, path: Path, name: str, var, time_dim: str | None, month: int | None) -> tuple[int, ...] | None:
    """The time steps to read: one step as it is; else by ``month``, by calendar where the time
    axis decodes, else the month-th of 12."""
    if time_dim is None:
        return None
    steps = int(var.sizes[time_dim])
    if steps == 1:
        return (0,)
    months = _calendar_months(ds, time_dim)
    if months is not None:
        if month is None:
            raise AreaError(f"{path}: {name!r} has {steps} time steps (months {_month_list(months)}); give "
                            f"[water] month = 1..12 (the steps in that month are averaged)")
        picked = tuple(i for i, m in enumerate(months) if m == month)
        if not picked:
            raise AreaError(f"{path}: {name!r} has no time step in month {month} (its {steps} steps are in "
                            f"months {_month_list(months)})")
        return picked
    if steps == 12:
        if month is None:
            raise AreaError(f"{path}: {name!r} has 12 time steps (months); give [water] month = 1..12")
        return (month - 1,)
    raise AreaError(f"{path}: {name!r} has {steps} time steps and a time axis that does not decode "
                    f"(units {units_of(ds[time_dim]) if time_dim in ds.variables else ''!r}); need 1 (used as "
                    f"it is) or 12 (one per month, picked by [water] month)")


def _calendar_months(ds, time_dim: str) -> list[int] | None:
    """The calendar month of each time step, or None when the axis does not decode (WOA's
    "months since")."""
    if time_dim not in ds.variables:
        return None
    import cftime

    coord = ds[time_dim]
    units = str(coord.attrs.get("units", ""))
    if "since" not in units:
        return None
    try:
        dates = cftime.num2date(np.asarray(coord.values, dtype=float), units,
                                str(coord.attrs.get("calendar", "standard")))
    except (ValueError, TypeError, OverflowError):
        return None
    return [int(d.month) for d in np.atleast_1d(dates)]


def _month_list(months: list[int]) -> str:
    return ", ".join(str(m) for m in sorted(set(months)))


def _is_depth(ds, dim: str) -> bool:
    if dim not in ds.variables:
        return dim.lower() == "depth"
    attrs = ds[dim].attrs
    return (dim.lower() in ("depth", "z", "lev", "level") or attrs.get("standard_name") == "depth"
            or attrs.get("axis") == "Z" or "positive" in attrs)


def _depth_values(ds, dim: str, path: Path) -> np.ndarray:
    if dim not in ds.variables:
        raise AreaError(f"{path}: the depth dimension {dim!r} has no coordinate variable")
    coord = ds[dim]
    unit = units_of(coord)
    if unit not in METRE_UNITS:
        raise AreaError(f"{path}: depth coordinate {dim!r} must be in metres, got units {unit!r}")
    values = np.asarray(coord.values, dtype=float)
    if str(coord.attrs.get("positive", "down")).strip().lower() == "up":
        values = -values
    if values.ndim != 1 or values.size < 1 or not np.all(np.isfinite(values)) or values.min() < 0.0:
        raise AreaError(f"{path}: depth coordinate {dim!r} must be finite depths >= 0 m")
    step = np.diff(np.sort(values))
    if np.any(step <= 0):
        raise AreaError(f"{path}: depth coordinate {dim!r} has repeated levels")
    return values


def check_same_grid(a: ClimVariable, b: ClimVariable) -> None:
    if a.path == b.path:
        return
    for what, x, y in (("depth levels", a.depth_sorted, b.depth_sorted),
                       ("latitudes", a.axes.lat_sorted, b.axes.lat_sorted),
                       ("longitudes", a.axes.lon_sorted, b.axes.lon_sorted)):
        if x.shape != y.shape or not np.allclose(x, y, rtol=0, atol=1e-6):
            raise AreaError(f"{b.path}: its {what} differ from those of the temperature file {a.path}; "
                            f"the two files must be on one grid")
