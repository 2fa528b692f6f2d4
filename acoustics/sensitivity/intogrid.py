"""A study's K error fed back into a grid: K's error model with its structure.

``tmakit sensitivity ... --into GRID`` writes the model the study's members measure
(`acoustics.sensitivity.errormodel`: the offset that persists along a track, the residual that
changes along it and its correlation length, the offset's correlation between bands; per class,
band and bearing) into the grid of the same area (docs/formats.md); the trackers then take it in
place of the class's one number (``Tables.k_error_model``, `tracker.levels`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.dataset import with_k_error_model
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
    """The grid dataset with the study's K error model (`acoustics.sensitivity.errormodel`) over the
    summary's range window."""
    from acoustics.sensitivity.errormodel import k_error_model

    model = k_error_model(study, summary.attrs.get("summary_range_min_m"), summary.attrs.get("summary_range_max_m"))
    comment = (f"measured over {study.members} members by tmakit sensitivity study {study_name} "
               f"(source_hash {study.source_hash[:12]})")
    return with_k_error_model(tables.dataset, model, comment, tables.source)


def write_k_error_grid(ds: xr.Dataset, path: str | Path, *, atomic: bool = True) -> Path:
    """Write the grid with its K error model (through a temporary file unless ``atomic`` is False)."""
    return write_netcdf(ds, path, atomic=atomic)
