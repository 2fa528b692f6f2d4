"""File formats: the ``tmakit_format`` every file tmakit writes carries, and reading older ones.

Each kind of file has its own integer format, raised when what a reader relies on changes
(docs/formats.md, "Versions"):

- grid netCDF, `GRID_FORMAT`: 3 may carry K's error model a study measured
  (``acoustics.grid.kerror.MODEL_VARS``: the offset that persists along a track, the residual
  and its correlation length, the offset's correlation between bands); 2 carries
  ``tmakit_format`` and may carry a study's one K error sd by range (``k_error_sd_db``), read as
  what it meant, the offset (its median, ``Tables.k_error_model``); 1 is the same file without
  ``tmakit_format`` (from before formats were numbered; ``area_json`` holds the area-file
  document); both are read as they are, the attribute set in memory; 0 (``area_json`` a record
  of the program's objects, not the area-file document) is refused.
- sensitivity study netCDF, `STUDY_FORMAT`: 2 carries it; 1 is the same file without it.
- the studies' JSON result files, `RESULT_FORMAT`: a key ``tmakit_format`` (1). tmakit writes
  them and reads none back; CSVs are known by their header.
- atlas Zarr store, `ATLAS_FORMAT`: 1, the first (docs/formats.md "Atlas (Zarr store)").
- P_D map netCDF, `PD_MAP_FORMAT`: 1, the first (docs/formats.md "P_D map"); tmakit writes
  them for a GIS and reads none back.

A file of a format this version cannot read is refused with an error that names the file's
format, the formats this version reads and the command that writes the file anew.
"""

from __future__ import annotations

import json

import xarray as xr

#: The grid format this version writes, and the oldest it reads.
GRID_FORMAT = 3
GRID_FORMAT_OLDEST = 1
#: The sensitivity-study format this version writes, and the oldest it reads.
STUDY_FORMAT = 2
STUDY_FORMAT_OLDEST = 1
#: The format of the studies' JSON result files (gm, idm, shelf, schmidt): a key ``tmakit_format``.
RESULT_FORMAT = 1
#: The atlas (Zarr store) format this version writes and reads (the first atlas format).
ATLAS_FORMAT = 1
#: The P_D map netCDF format (``acoustics.grid.pdfile``; written, never read back).
PD_MAP_FORMAT = 1


def file_format(ds: xr.Dataset, source: str, error: type[ValueError], what: str) -> int | None:
    """The ``tmakit_format`` of a dataset (None when it has none); ``error`` if it is not an
    integer."""
    value = ds.attrs.get("tmakit_format")
    if value is None:
        return None
    try:
        number = int(getattr(value, "item", lambda: value)())
    except (TypeError, ValueError):
        number = None
    if number is None or isinstance(value, (bool, str)) or number != value:
        raise error(f"{source}: global attribute tmakit_format must be an integer, got {value!r:.40}")
    return number


def refuse(source: str, error: type[ValueError], what: str, fmt: int, oldest: int, newest: int,
           rebuild: str, why: str = "") -> ValueError:
    """The error for a file of a format this version does not read."""
    reads = f"format {newest}" if oldest == newest else f"formats {oldest}-{newest}"
    newer = " (written by a newer tmakit)" if fmt > newest else ""
    return error(f"{source}: a {what} of tmakit format {fmt}{newer}{why}; this version reads "
                 f"{reads}; write it anew with {rebuild}")


def upgrade_grid(ds: xr.Dataset, source: str, error: type[ValueError]) -> xr.Dataset:
    """A grid dataset in this version's format: as it is, or read through the upgrade from an
    older format (``tmakit_format`` added); ``error`` for a format this version does not read."""
    fmt = file_format(ds, source, error, "grid")
    rebuild = f"tmakit grids build {ds.attrs.get('area', 'AREA')}"
    if fmt is None:
        if _area_json_is_a_record(ds):
            raise refuse(source, error, "grid", 0, GRID_FORMAT_OLDEST, GRID_FORMAT, rebuild,
                         " (its area_json is not an area-file document)")
        fmt = 1
    if not GRID_FORMAT_OLDEST <= fmt <= GRID_FORMAT:
        raise refuse(source, error, "grid", fmt, GRID_FORMAT_OLDEST, GRID_FORMAT, rebuild)
    if fmt == GRID_FORMAT:
        return ds
    # formats 1 and 2 -> 3: the attribute alone (a format-2 k_error_sd_db map is read by the face)
    return ds.assign_attrs(tmakit_format=GRID_FORMAT)


def upgrade_study(ds: xr.Dataset, source: str, error: type[ValueError]) -> xr.Dataset:
    """A study dataset in this version's format (see `upgrade_grid`)."""
    fmt = file_format(ds, source, error, "sensitivity study")
    fmt = 1 if fmt is None else fmt
    if not STUDY_FORMAT_OLDEST <= fmt <= STUDY_FORMAT:
        raise refuse(source, error, "sensitivity study", fmt, STUDY_FORMAT_OLDEST, STUDY_FORMAT,
                     f"tmakit sensitivity {ds.attrs.get('area', 'AREA')}")
    return ds if fmt == STUDY_FORMAT else ds.assign_attrs(tmakit_format=STUDY_FORMAT)


def _area_json_is_a_record(ds: xr.Dataset) -> bool:
    """Whether ``area_json`` is the format-0 record: a JSON object whose top level is the
    area's fields (``bands``, ``classes``, ...) instead of the area file's tables (``[area]``)."""
    text = ds.attrs.get("area_json")
    if not isinstance(text, str):
        return False
    try:
        doc = json.loads(text)
    except ValueError:
        return False
    return isinstance(doc, dict) and "area" not in doc and "bands" in doc and "classes" in doc
