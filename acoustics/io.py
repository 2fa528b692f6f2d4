"""Grid files: CF-1.8 netCDF4, written atomically; ``open_grid`` is the only way in."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from envdata.files import atomic_path

REQUIRED_DIMS = ("class", "band", "depth", "range")
REQUIRED_VARS = {"tl_db": ("class", "band", "depth", "range"), "k_db": ("class", "band", "range"),
                 "k_urick_db": ("class", "band", "range")}
REQUIRED_COORDS = ("class", "band", "depth", "range", "band_low_hz", "band_high_hz", "band_center_hz",
                   "source_depth_m")
REQUIRED_ATTRS = ("Conventions", "area", "model", "observer_depth_m", "source_hash")


def write_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` as compressed netCDF4 via a temporary file (no half-written file, ever)."""
    path = Path(path)
    encoding = {}
    for name, var in ds.variables.items():
        if name in ds.coords:
            encoding[name] = {"_FillValue": None}
        elif np.issubdtype(var.dtype, np.floating):
            encoding[name] = {"zlib": True, "complevel": 1, "shuffle": True, "_FillValue": None}
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, format="NETCDF4", engine="netcdf4", encoding=encoding)
    return path


def load_netcdf(path: str | Path, error: type[ValueError], what: str) -> xr.Dataset:
    """Open a netCDF file and load it into memory; every way it can be unreadable raises ``error``."""
    path = Path(path)
    if not path.exists():
        raise error(f"{path}: {what} file not found")
    if path.is_dir():
        raise error(f"{path}: is a directory, not a {what} file")
    with open(path, "rb") as fh:
        magic = fh.read(8)
    if not magic:
        raise error(f"{path}: empty file, not a netCDF {what}")
    if not (magic.startswith(b"\x89HDF") or magic.startswith(b"CDF")):
        raise error(f"{path}: not a netCDF file")
    try:
        with xr.open_dataset(path, engine="netcdf4") as raw:
            return raw.load()
    except Exception as exc:  # netCDF4/HDF5 raise many types for damaged files
        first = str(exc).splitlines()[0] if str(exc) else ""
        raise error(f"{path}: cannot read netCDF (truncated or damaged): "
                    f"{type(exc).__name__}: {first}") from None


def write_grid(ds: xr.Dataset, path: str | Path) -> Path:
    """Write a grid dataset as netCDF4 to ``path`` via a temporary file."""
    return write_netcdf(ds, path)


def open_grid(path: str | Path) -> xr.Dataset:
    """Open a grid file, load it into memory and check it against the contract."""
    ds = load_netcdf(path, GridFileError, "grid")
    check_grid(ds, str(path))
    return ds


def check_grid(ds: xr.Dataset, source: str = "<grid>") -> None:
    """Raise GridFileError unless ``ds`` has the dimensions, variables and attributes of DESIGN.md."""
    for dim in REQUIRED_DIMS:
        if dim not in ds.dims:
            raise GridFileError(f"{source}: missing dimension {dim!r}")
    for name, dims in REQUIRED_VARS.items():
        if name not in ds.data_vars:
            raise GridFileError(f"{source}: missing variable {name!r}")
        if ds[name].dims != dims:
            raise GridFileError(f"{source}: variable {name!r} has dimensions {ds[name].dims}, "
                                f"expected {dims}")
    for name in REQUIRED_COORDS:
        if name not in ds.coords:
            raise GridFileError(f"{source}: missing coordinate {name!r}")
    for name in REQUIRED_ATTRS:
        if name not in ds.attrs:
            raise GridFileError(f"{source}: missing global attribute {name!r}")
    if ds.sizes["range"] and not (np.all(np.diff(ds["range"].values) > 0) and ds["range"].values[0] > 0):
        raise GridFileError(f"{source}: coordinate 'range' must be positive and increasing")
    if ds.sizes["depth"] > 1 and not np.all(np.diff(ds["depth"].values) > 0):
        raise GridFileError(f"{source}: coordinate 'depth' must be increasing")
