"""Study files: the study dataset (and any summaries merged into it) as netCDF4."""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from acoustics.grid.formats import upgrade_study
from acoustics.grid.io import load_netcdf, write_netcdf
from envdata.errors import InputError

REQUIRED_STUDY_VARS = {"k_db": ("member", "class", "band", "range"), "k_nominal_db": ("class", "band", "range")}
#: A study of an area with [origin] has a bearing axis.
REQUIRED_RADIAL_STUDY_VARS = {"k_db": ("member", "class", "band", "bearing", "range"),
                              "k_nominal_db": ("class", "band", "bearing", "range")}


class StudyFileError(InputError):
    """A study file that is missing, not netCDF, or lacks what a study file holds (docs/formats.md)."""


def write_study(ds: xr.Dataset, path: str | Path, *, atomic: bool = True) -> Path:
    """Write the study (and any summaries merged into it) as netCDF4, via a temporary file
    unless ``atomic`` is False (for a caller that renames several files together)."""
    return write_netcdf(ds, path, atomic=atomic)


def open_study(path: str | Path) -> xr.Dataset:
    """Open a study file (an older format through its upgrade step), load it, and check its variables."""
    ds = upgrade_study(load_netcdf(path, StudyFileError, "study"), str(path), StudyFileError)
    required = REQUIRED_RADIAL_STUDY_VARS if "bearing" in ds.dims else REQUIRED_STUDY_VARS
    for name, dims in required.items():
        if name not in ds or ds[name].dims != dims:
            raise StudyFileError(f"{path}: missing variable {name}{dims}")
    return ds
