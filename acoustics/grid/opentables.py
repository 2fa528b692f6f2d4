"""``--grid`` of the trackers and the simulator: a grid file or an atlas store, as one grid face.

A grid (netCDF) opens with ``acoustics.open_grid``; an atlas (a Zarr store, README "Atlases")
with ``open_atlas(path).follow(month)``, the tables of that month around the observer at every
cycle (``acoustics.grid.atlasfollow``). The month is the atlas's choice among its months; a
grid has one, its own.
"""

from __future__ import annotations

from pathlib import Path

from acoustics.grid.atlas import open_atlas
from acoustics.grid.atlasstore import is_atlas_store
from acoustics.grid.io import open_grid
from acoustics.grid.tables import GridTables
from envdata.errors import InputError


def open_tables(path: str | Path, *, month: int | None = None) -> GridTables:
    """The grid face of a grid file or an atlas store.

    Parameters
    ----------
    path : path-like
    month : int, optional
        The atlas's month (needed when it has several); for a grid, only its own month.

    Raises
    ------
    GridFileError, AtlasFileError
        An unreadable grid or atlas.
    InputError
        A month the atlas lacks, no month for an atlas of several, a month for a grid of another.
    """
    path = Path(path)
    if path.is_dir() and is_atlas_store(path):
        return open_atlas(path).follow(month)
    tables = open_grid(path)
    if month is not None:
        clim = tables.area.water.climatology
        own = None if clim is None else clim.month
        if own != month:
            raise InputError(f"{path}: month {month}: the grid holds one sea, "
                             f"{'of month ' + str(own) if own else 'without a month'}; months are an "
                             f"atlas's (a Zarr store built by tmakit atlas build)")
    return tables


__all__ = ["open_tables"]
