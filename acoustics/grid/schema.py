"""The grid contract (docs/formats.md "What `open_tables` checks"), checked: what ``open_tables`` lets in.

A grid is refused (``GridFileError``, one line naming the file and what is wrong) when a
dimension, variable, coordinate or attribute is missing or of the wrong type, when its
``area_json`` is missing, unreadable or an area the TOML loader would refuse (the same message
as for an area file), when that area disagrees with the grid's coordinates (class and band
names, band edges, source depths, observer depth), and when ``tl_db`` or ``k_db`` holds no
finite value.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.kerror import MODEL_VARS
from envdata.area import Area
from envdata.areafile import area_from_json
from envdata.errors import AreaError

REQUIRED_DIMS = ("class", "band", "depth", "range")
REQUIRED_VARS = {"tl_db": ("class", "band", "depth", "range"), "k_db": ("class", "band", "range"),
                 "k_urick_db": ("class", "band", "range")}
REQUIRED_COORDS = ("class", "band", "depth", "range", "band_low_hz", "band_high_hz", "band_center_hz",
                   "source_depth_m")
#: A bearing-dependent grid (docs/formats.md "Bearing-dependent grid") adds the dimension
#: ``bearing`` to these variables, and ``bottom_depth_m(bearing, range)``.
BEARING_VARS = {"tl_db": ("class", "band", "bearing", "depth", "range"),
                "k_db": ("class", "band", "bearing", "range"),
                "k_urick_db": ("class", "band", "range"),
                "bottom_depth_m": ("bearing", "range")}
#: Variables a grid may have (a flat grid's TL from the observer depth, written since it could
#: track a target at an unknown depth; older grids of the same format lack it).
FLAT_OPTIONAL_VARS = {"tl_obs_db": ("class", "band", "depth", "range")}
BEARING_ATTRS = {"origin_lat_deg": numbers.Real, "origin_lon_deg": numbers.Real}
FIXED_ENDS = {False: "source", True: "observer"}
#: Optional variables and their dimensions without and with bearings: the K error sd a
#: sensitivity study measured (``tmakit sensitivity --into GRID``), dB, >= 0, NaN where unknown.
OPTIONAL_VARS = {"k_error_sd_db": {False: ("class", "band", "range"), True: ("class", "band", "bearing", "range")}}
#: Global attributes and the type each must have.
REQUIRED_ATTRS = {"Conventions": str, "area": str, "model": str, "observer_depth_m": numbers.Real,
                  "source_hash": str, "area_json": str}


def check_grid(ds: xr.Dataset, source: str = "<grid>", *, area: Area | None = None) -> Area:
    """Raise GridFileError unless ``ds`` is a grid (docs/formats.md); return the area it stores.

    ``area``: the area the dataset was made from in this process; its ``area_json`` is then
    taken as that area (not parsed again) and still checked against the coordinates.
    """
    for dim in REQUIRED_DIMS:
        if dim not in ds.dims:
            raise GridFileError(f"{source}: missing dimension {dim!r}")
    by_bearing = "bearing" in ds.dims
    for name, dims in (BEARING_VARS if by_bearing else REQUIRED_VARS).items():
        if name not in ds.data_vars:
            raise GridFileError(f"{source}: missing variable {name!r}")
        if ds[name].dims != dims:
            raise GridFileError(f"{source}: variable {name!r} has dimensions {ds[name].dims}, "
                                f"expected {dims}")
        if not np.issubdtype(ds[name].dtype, np.floating):
            raise GridFileError(f"{source}: variable {name!r} must hold floating-point numbers, "
                                f"got {ds[name].dtype}")
    for name, dims in ({} if by_bearing else FLAT_OPTIONAL_VARS).items():
        if name in ds.data_vars and (ds[name].dims != dims
                                     or not np.issubdtype(ds[name].dtype, np.floating)):
            raise GridFileError(f"{source}: variable {name!r} must hold floating-point numbers "
                                f"on dimensions {dims}, got {ds[name].dtype} on {ds[name].dims}")
    _check_model_vars(ds, source, by_bearing)
    for name in REQUIRED_COORDS + (("bearing",) if by_bearing else ()):
        if name not in ds.coords:
            raise GridFileError(f"{source}: missing coordinate {name!r}")
    _check_attrs(ds, source, {**REQUIRED_ATTRS, **(BEARING_ATTRS if by_bearing else {})})
    fixed_end = ds["tl_db"].attrs.get("fixed_end", "source")
    if fixed_end != FIXED_ENDS[by_bearing]:
        raise GridFileError(f"{source}: tl_db's fixed_end must be {FIXED_ENDS[by_bearing]!r} for a "
                            f"grid {'with' if by_bearing else 'without'} bearings, got {fixed_end!r}")
    _check_axes(ds, source)
    if by_bearing:
        _check_bearings(ds, source)
    if area is None:
        try:
            area = area_from_json(ds.attrs["area_json"], source)
        except AreaError as exc:
            raise GridFileError(str(exc)) from None
    _check_consistent(ds, area, source)
    _check_optional(ds, source, by_bearing)
    for name in ("tl_db", "k_db"):
        if not np.isfinite(ds[name].values).any():
            raise GridFileError(f"{source}: variable {name!r} holds no finite value")
    return area


def _check_optional(ds: xr.Dataset, source: str, by_bearing: bool) -> None:
    for name, dims_by in OPTIONAL_VARS.items():
        if name not in ds.data_vars:
            continue
        dims = dims_by[by_bearing]
        if ds[name].dims != dims:
            raise GridFileError(f"{source}: variable {name!r} has dimensions {ds[name].dims}, expected {dims}")
        values = np.asarray(ds[name].values)
        if not np.issubdtype(values.dtype, np.floating):
            raise GridFileError(f"{source}: variable {name!r} must hold floating-point numbers, got {values.dtype}")
        bad = np.isfinite(values) & ~((values >= 0.0) & (values <= 100.0))
        if bad.any() or np.isinf(values).any():
            value = values[bad | np.isinf(values)].flat[0]
            raise GridFileError(f"{source}: variable {name!r} holds {value:g} dB; an sd must be in [0, 100] dB "
                                f"(NaN where unknown)")


def _check_attrs(ds: xr.Dataset, source: str, required: dict) -> None:
    for name, kind in required.items():
        if name not in ds.attrs:
            raise GridFileError(f"{source}: missing global attribute {name!r}")
        value = ds.attrs[name]
        if isinstance(value, np.ndarray) and value.size == 1:
            value = value.item()  # netCDF stores a scalar attribute as a one-element array
        if isinstance(value, np.generic):
            value = value.item()
        if isinstance(value, bool) or not isinstance(value, kind):
            want = "a string" if kind is str else "a number"
            raise GridFileError(f"{source}: global attribute {name!r} must be {want}, "
                                f"got {type(value).__name__} {value!r:.60}")
        if kind is numbers.Real and not math.isfinite(value):
            raise GridFileError(f"{source}: global attribute {name!r} must be finite, got {value}")


def _check_axes(ds: xr.Dataset, source: str) -> None:
    rng = np.asarray(ds["range"].values)
    depth = np.asarray(ds["depth"].values)
    for name, values in (("range", rng), ("depth", depth)):
        if not np.issubdtype(values.dtype, np.number) or not np.all(np.isfinite(values)):
            raise GridFileError(f"{source}: coordinate {name!r} must hold finite numbers")
    if rng.size and not (np.all(np.diff(rng) > 0) and rng[0] > 0):
        raise GridFileError(f"{source}: coordinate 'range' must be positive and increasing")
    if depth.size > 1 and not np.all(np.diff(depth) > 0):
        raise GridFileError(f"{source}: coordinate 'depth' must be increasing")
    if depth.size and depth[0] < 0:
        raise GridFileError(f"{source}: coordinate 'depth' must be >= 0 m, got {depth[0]:g} m")


def _check_bearings(ds: xr.Dataset, source: str) -> None:
    bearing = np.asarray(ds["bearing"].values)
    if not (np.issubdtype(bearing.dtype, np.number) and np.all(np.isfinite(bearing))):
        raise GridFileError(f"{source}: coordinate 'bearing' must hold finite numbers")
    if bearing.size and not (np.all(np.diff(bearing) > 0) and bearing[0] >= 0 and bearing[-1] < 360):
        raise GridFileError(f"{source}: coordinate 'bearing' must increase within [0, 360) deg")


def _check_consistent(ds: xr.Dataset, area: Area, source: str) -> None:
    """The stored area against the grid's coordinates and attributes."""
    where = f"{source}: area_json"
    if str(ds.attrs["area"]) != area.name:
        raise GridFileError(f"{where}: area {area.name!r}, but the grid's attribute area is "
                            f"{ds.attrs['area']!r}")
    for kind, coord, names in (("class", "class", [c.name for c in area.classes]),
                               ("band", "band", [b.name for b in area.bands])):
        grid_names = [str(v) for v in ds[coord].values]
        if grid_names != names:
            raise GridFileError(f"{where}: {kind} names {', '.join(names)} do not match the "
                                f"grid's {', '.join(grid_names)}")
    for coord, values, unit in (
            ("band_low_hz", [b.low_hz for b in area.bands], "Hz"),
            ("band_high_hz", [b.high_hz for b in area.bands], "Hz"),
            ("source_depth_m", [c.depth_m for c in area.classes], "m")):
        grid_values = np.asarray(ds[coord].values, dtype=float)
        bad = ~np.isclose(grid_values, values, rtol=1e-9, atol=1e-9)
        if bad.any():
            i = int(np.argmax(bad))
            raise GridFileError(f"{where}: {coord} {values[i]:g} {unit}, but the grid's "
                                f"coordinate has {grid_values[i]:g} {unit}")
    obs = float(np.asarray(ds.attrs["observer_depth_m"]).item())
    if not math.isclose(obs, area.observer.depth_m, rel_tol=1e-9, abs_tol=1e-9):
        raise GridFileError(f"{where}: observer depth {area.observer.depth_m:g} m, but the grid's "
                            f"attribute observer_depth_m is {obs:g} m")


def _check_model_vars(ds: xr.Dataset, source: str, by_bearing: bool) -> None:
    """K's error model a study measured (``tmakit sensitivity --into``): every variable of
    `MODEL_VARS` or none, each floating-point on its dimensions, its sds and length >= 0 and its
    correlation in [0, 1] where given (NaN: unknown)."""
    have = [name for name in MODEL_VARS if name in ds.data_vars]
    if not have:
        return
    if len(have) != len(MODEL_VARS):
        missing = [name for name in MODEL_VARS if name not in ds.data_vars]
        raise GridFileError(f"{source}: K's error model needs {', '.join(MODEL_VARS)}; missing {', '.join(missing)}")
    for name, dims in MODEL_VARS.items():
        want = dims[by_bearing]
        if ds[name].dims != want or not np.issubdtype(ds[name].dtype, np.floating):
            raise GridFileError(f"{source}: variable {name!r} must hold floating-point numbers on dimensions "
                                f"{want}, got {ds[name].dtype} on {ds[name].dims}")
        v = np.asarray(ds[name].values, dtype=float)
        top = 1.0 if name == "k_offset_band_correlation" else np.inf
        bad = np.isfinite(v) & ((v < 0.0) | (v > top))
        if bad.any():
            raise GridFileError(f"{source}: variable {name!r} holds {float(v[bad][0]):g}, "
                                f"outside [0, {top:g}]")
