"""A study's K error fed back into a grid: ``k_error_sd_db(class, band[, bearing], range)``.

``tmakit sensitivity ... --into GRID`` writes the study's ``k_rms_db`` (the rms over members of
K - K_nominal at each class, band, bearing and range) into the grid of the same area as its
``k_error_sd_db`` (docs/formats.md); the trackers then take the sd at each measurement's bearing
and range in place of the class's one number (``acoustics.grid.tables.GridTables.k_error_sd_at``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.io import open_grid, write_netcdf
from acoustics.grid.tables import GridTables


def check_into_grid(path: str | Path, study: xr.Dataset) -> GridTables:
    """Open the grid to write into and check it is the study's area, classes, bands and bearings.

    Raises
    ------
    GridFileError
        Not a grid, or another area, class, band or bearing set than the study's.
    """
    tables = open_grid(path)
    where = f"{path}"
    if tables.area.name != study.attrs["area"]:
        raise GridFileError(f"{where}: the grid is of area {tables.area.name!r}, the study of "
                            f"{study.attrs['area']!r}")
    for what, grid_names, study_names in (("classes", tables.class_names, study["class"].values),
                                          ("bands", tables.band_names, study["band"].values)):
        if tuple(grid_names) != tuple(str(n) for n in study_names):
            raise GridFileError(f"{where}: the grid's {what} ({', '.join(grid_names)}) are not the study's "
                                f"({', '.join(str(n) for n in study_names)})")
    grid_bearings = tables.bearing_axis_deg
    study_bearings = study["bearing"].values if "bearing" in study.dims else None
    if (grid_bearings is None) != (study_bearings is None) or (
            grid_bearings is not None and not np.allclose(grid_bearings, study_bearings, atol=1e-6)):
        raise GridFileError(f"{where}: the grid's bearings do not match the study's "
                            f"({'none' if study_bearings is None else ', '.join(f'{b:g}' for b in study_bearings)} "
                            f"deg)")
    return tables


def k_error_grid(tables: GridTables, summary: xr.Dataset, study: xr.Dataset, study_name: str) -> xr.Dataset:
    """The grid dataset with the study's ``k_rms_db`` as ``k_error_sd_db`` on the grid's range axis
    (linear in range; NaN beyond the study's ranges, where the class's one number serves)."""
    dims = ("class", "band", "bearing", "range") if "bearing" in summary.dims else ("class", "band", "range")
    rms = summary["k_rms_db"].transpose(*dims).values
    r_study = summary["range"].values
    flat = rms.reshape(-1, r_study.size)
    out = np.full((flat.shape[0], tables.range_m.size), np.nan)
    for i, row in enumerate(flat):
        ok = np.isfinite(row)
        if ok.sum() >= 2:
            out[i] = np.interp(tables.range_m, r_study[ok], row[ok], left=np.nan, right=np.nan)
    sd = out.reshape(rms.shape[:-1] + (tables.range_m.size,))
    comment = (f"rms over {study.sizes['member']} members of K - K_nominal, tmakit sensitivity study "
               f"{study_name} (source_hash {study.attrs.get('source_hash', '?')[:12]})")
    return tables.dataset_with_k_error_sd(sd, comment)


def write_k_error_grid(ds: xr.Dataset, path: str | Path, *, atomic: bool = True) -> Path:
    """Write the grid with its ``k_error_sd_db`` (through a temporary file unless ``atomic`` is False)."""
    return write_netcdf(ds, path, atomic=atomic)
