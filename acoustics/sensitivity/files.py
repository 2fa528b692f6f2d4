"""Study files: the study dataset (and any summaries merged into it) as netCDF4, and back as its face."""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from acoustics.grid.formats import upgrade_study
from acoustics.grid.io import load_netcdf, write_netcdf
from acoustics.sensitivity.face import Study, StudyFileError, study_face


def write_study(ds: xr.Dataset, path: str | Path, *, atomic: bool = True) -> Path:
    """Write the study (and any summaries merged into it) as netCDF4, via a temporary file
    unless ``atomic`` is False (for a caller that renames several files together)."""
    return write_netcdf(ds, path, atomic=atomic)


def open_study(path: str | Path) -> Study:
    """Open a study file (an older format through its upgrade step), load it, check it and return
    its face (``acoustics.sensitivity.face.Study``)."""
    ds = upgrade_study(load_netcdf(path, StudyFileError, "study"), str(path), StudyFileError)
    return study_face(ds, str(path))


__all__ = ["StudyFileError", "open_study", "write_study"]
