"""netCDF files: CF-1.8 netCDF4, written atomically, and loaded with every way they can be
unreadable turned into one error; grid files are opened by ``acoustics.open_tables``."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from envdata.files import atomic_path, check_input_file

if TYPE_CHECKING:  # a build imports xarray beside its runs (acoustics.builder.preload)
    import xarray as xr


def write_netcdf(ds: xr.Dataset, path: str | Path, *, atomic: bool = True) -> Path:
    """Write ``ds`` as compressed netCDF4 via a temporary file (no half-written file, ever).

    Without ``atomic`` straight to ``path``, for a caller that renames several files together.
    """
    path = Path(path)
    encoding = {}
    for name, var in ds.variables.items():
        if var.dtype.kind in "UO":
            # text as fixed-width characters, not HDF5 variable-length strings: reading the fill
            # value of a variable-length string variable crashed HDF5 (H5T__vlen_disk_isnull on a
            # stale file address) once other files had been opened and closed in the process
            encoding[name] = {"dtype": "S1", "_FillValue": None}
        elif name in ds.coords:
            encoding[name] = {"_FillValue": None}
        elif np.issubdtype(var.dtype, np.floating):
            encoding[name] = {"zlib": True, "complevel": 1, "shuffle": True, "_FillValue": None,
                              "chunksizes": slab_chunks(var.shape)}
    if not atomic:
        _dump(ds, path, encoding)
        return path
    with atomic_path(path) as tmp:
        _dump(ds, tmp, encoding)
    return path


def slab_chunks(shape) -> tuple[int, ...]:
    """A compressed variable's chunks: its last two axes whole (a table's depth x range), one
    index of each axis before them. netCDF's own choice for a grid's TL, (2, 2, 251, 600) on
    ocean-deep's (3, 3, 501, 1200), took about 1.8 times as long to write, the file the same size
    (by hand, notes of the stop that chose it); a reader takes a (class, band) table in one chunk."""
    return tuple(1 if i < len(shape) - 2 else max(1, int(n)) for i, n in enumerate(shape))


def _dump(ds: xr.Dataset, path: Path, encoding: dict) -> None:
    """``ds.to_netcdf(path, format="NETCDF4", engine="netcdf4", encoding=encoding)`` without its
    look for a dask scheduler, which imports dask.distributed (0.3 s of a build's fixed cost) to
    write arrays that are all in memory; the lock is the one it would take for the netCDF library.
    The file is the same."""
    from xarray.backends import NetCDF4DataStore
    from xarray.backends.locks import NETCDFC_LOCK

    store = NetCDF4DataStore.open(path, mode="w", format="NETCDF4", lock=NETCDFC_LOCK)
    try:
        ds.dump_to_store(store, encoding=encoding)
    finally:
        store.close()


def load_netcdf(path: str | Path, error: type[ValueError], what: str) -> xr.Dataset:
    """Open a netCDF file and load it into memory; every way it can be unreadable raises ``error``."""
    path = check_input_file(path, f"{what} file", error)
    try:
        with open(path, "rb") as fh:
            magic = fh.read(8)
    except OSError as exc:
        raise error(f"{path}: cannot read the {what} file: {exc.strerror or exc}") from None
    if not magic:
        raise error(f"{path}: empty file, not a netCDF {what}")
    if not (magic.startswith(b"\x89HDF") or magic.startswith(b"CDF")):
        raise error(f"{path}: not a netCDF file")
    import xarray as xr

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
