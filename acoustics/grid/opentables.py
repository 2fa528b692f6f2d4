"""The one way in, as xarray's ``open_dataset``: ``acoustics.open_tables(source)`` answers for a
grid file, an atlas store or a grid dataset in memory, with the face (``acoustics.grid.face``).

- A grid file (netCDF, docs/formats.md "Grid file") is loaded into memory, read through its
  format's upgrade step, checked against the contract and its stored area read back
  (``acoustics.grid.checked``).
- An atlas (a Zarr store, README "Atlases") opens as the tables of one month around the observer
  at every cycle (``acoustics.grid.atlas.follow.FollowingTables``). The month is the atlas's
  choice among its months; a grid has one, its own.
- A dataset (``acoustics.build_grid``'s, or a grid changed in memory) is checked like a file.
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.face import Tables
from envdata.errors import InputError


def open_tables(source: str | Path | xr.Dataset, *, month: int | None = None, name: str | None = None) -> Tables:
    """The face of a grid file, an atlas store or a grid dataset.

    Parameters
    ----------
    source : path-like or xarray.Dataset
        A grid file, an atlas store (a folder), or a grid dataset in memory.
    month : int, optional
        The atlas's month (needed when it has several); for a grid, only its own month.
    name : str, optional
        The tables' name in messages (default: the file, else the dataset's area).

    Raises
    ------
    GridFileError, AtlasFileError
        An unreadable grid or atlas, or one that breaks the contract (naming what is wrong).
    InputError
        A month the atlas lacks, no month for an atlas of several, a month for a grid of another.
    """
    if isinstance(source, xr.Dataset):
        from acoustics.grid.checked import checked_tables

        return _of_month(checked_tables(source, name), month, name or "the grid")
    path = Path(source)
    if path.is_dir():  # an atlas is a Zarr store, a folder; another folder is refused as a grid file
        from acoustics.grid.atlas.format import is_atlas_attrs, read_attrs

        attrs = read_attrs(path)
        if is_atlas_attrs(attrs):
            from acoustics.grid.atlas.follow import follow
            from acoustics.grid.atlas.store import open_store

            return follow(open_store(path, attrs=attrs), month)
    from acoustics.grid.checked import checked_tables
    from acoustics.grid.io import load_netcdf

    return _of_month(checked_tables(load_netcdf(path, GridFileError, "grid"), name or str(path)), month, str(path))


def _of_month(tables: Tables, month: int | None, where: str) -> Tables:
    """The tables of a grid, refused for a month other than its own."""
    if month is not None:
        clim = tables.area.water.climatology
        own = None if clim is None else clim.month
        if own != month:
            raise InputError(f"{where}: month {month}: the grid holds one sea, "
                             f"{'of month ' + str(own) if own else 'without a month'}; months are an "
                             f"atlas's (a Zarr store built by tmakit atlas build)")
    return tables


__all__ = ["open_tables"]
