"""A study's K error fed back into a grid: ``k_error_sd_db(class, band[, bearing], range)``.

``tmakit sensitivity ... --into GRID`` writes the study's ``k_rms_db`` (the rms over members of
K - K_nominal at each class, band, bearing and range) into the grid of the same area as its
``k_error_sd_db`` (docs/formats.md); the trackers then take the sd at each measurement's bearing
and range in place of the class's one number (``Tables.k_error_sd_at``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.dataset import with_k_error_sd
from acoustics.grid.face import Tables
from acoustics.grid.io import write_netcdf
from acoustics.grid.opentables import open_tables
from acoustics.sensitivity.face import Study
from envdata.area import Area


def check_into_grid(path: str | Path, area: Area) -> Tables:
    """Open the grid to write into and check it is the study area's, classes, bands and bearings
    (before the members run).

    Raises
    ------
    GridFileError
        Not a grid, or another area, class, band or bearing set than the study's.
    """
    tables = open_tables(path)
    where = f"{path}"
    if tables.area.name != area.name:
        raise GridFileError(f"{where}: the grid is of area {tables.area.name!r}, the study of {area.name!r}")
    for what, grid_names, study_names in (("classes", tables.class_names, [c.name for c in area.classes]),
                                          ("bands", tables.band_names, [b.name for b in area.bands])):
        if tuple(grid_names) != tuple(str(n) for n in study_names):
            raise GridFileError(f"{where}: the grid's {what} ({', '.join(grid_names)}) are not the study's "
                                f"({', '.join(str(n) for n in study_names)})")
    grid_bearings = tables.bearing_axis_deg
    study_bearings = np.asarray(area.bearings.bearing_deg, dtype=float) if area.is_bearing_dependent else None
    if (grid_bearings is None) != (study_bearings is None) or (
            grid_bearings is not None and (grid_bearings.shape != study_bearings.shape
                                           or not np.allclose(grid_bearings, study_bearings, atol=1e-6))):
        def text(b):
            return "none" if b is None else ", ".join(f"{v:g}" for v in b) + " deg"

        raise GridFileError(f"{where}: the grid's bearings ({text(grid_bearings)}) are not the study's "
                            f"({text(study_bearings)})")
    return tables


def k_error_grid(tables: Tables, summary: xr.Dataset, study: Study, study_name: str) -> xr.Dataset:
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
    comment = (f"rms over {study.members} members of K - K_nominal, tmakit sensitivity study "
               f"{study_name} (source_hash {study.source_hash[:12]})")
    return with_k_error_sd(tables.dataset, sd, comment, tables.source)


def write_k_error_grid(ds: xr.Dataset, path: str | Path, *, atomic: bool = True) -> Path:
    """Write the grid with its ``k_error_sd_db`` (through a temporary file unless ``atomic`` is False)."""
    return write_netcdf(ds, path, atomic=atomic)
