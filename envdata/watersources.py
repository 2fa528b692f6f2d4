"""Data files read once for many tables: a box of bathymetry and of one month's climatology.

An atlas (README "Atlases") computes radials from many origins and months. Opening GEBCO and a
WOA month, and reading their cells, for every table would read the same cells hundreds of
times; instead the box that every table's radials cross is read once per build (bathymetry) and
once per month (climatology), and each table's radials (``envdata.radials.area_radials(...,
sources=...)``) are sampled from these in-memory boxes. They are plain arrays, so a Dask cluster
receives them once per worker.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from envdata.area import Area
from envdata.bathymetry import ElevationGrid, open_bathymetry
from envdata.climatology import TsField, open_climatology
from envdata.errors import AreaError
from envdata.geogrid import LatLonAxes


def _check_in_box(lat_deg, lon_deg, axes: LatLonAxes, lat_axis: np.ndarray, lon_axis: np.ndarray,
                  what: str) -> None:
    lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
    lon = axes.file_lon(np.atleast_1d(np.asarray(lon_deg, dtype=float)))
    outside = ((lat < lat_axis[0]) | (lat > lat_axis[-1]) | (lon < lon_axis[0]) | (lon > lon_axis[-1]))
    if outside.any():
        i = int(np.argmax(outside))
        raise AreaError(f"{what}: position {lat[i]:.5f} N {lon[i]:.5f} E is outside the box read for the "
                        f"atlas ({lat_axis[0]:.4f}..{lat_axis[-1]:.4f} N, {lon_axis[0]:.4f}..{lon_axis[-1]:.4f} E)")


@dataclass(frozen=True, eq=False)
class LoadedBathymetry:
    """A box of a bathymetry file in memory, served like an open ``BathymetryFile``."""

    path: Path
    variable: str
    axes: LatLonAxes
    grid: ElevationGrid
    text: str

    def describe(self) -> str:
        return self.text

    def load_box(self, lat_deg, lon_deg) -> ElevationGrid:
        _check_in_box(lat_deg, lon_deg, self.axes, self.grid.lat_deg, self.grid.lon_deg, str(self.path))
        return self.grid


@dataclass(frozen=True, eq=False)
class LoadedClimatology:
    """A box of one month of a climatology in memory, served like open ``ClimatologyFiles``."""

    path: Path
    axes: LatLonAxes
    field: TsField
    text: str

    def describe(self) -> str:
        return self.text

    def load_box(self, lat_deg, lon_deg) -> TsField:
        _check_in_box(lat_deg, lon_deg, self.axes, self.field.lat_deg, self.field.lon_deg, str(self.path))
        return self.field


@dataclass(frozen=True, eq=False)
class WaterSources:
    """What ``area_radials`` reads instead of opening the files: either may be None (a flat
    bottom, one profile)."""

    bathymetry: LoadedBathymetry | None = None
    climatology: LoadedClimatology | None = None


def load_bathymetry_box(area: Area, lat_deg, lon_deg) -> LoadedBathymetry | None:
    """The cells of the area's bathymetry file around the positions, read once (None: flat)."""
    if area.water.bathymetry is None:
        return None
    with open_bathymetry(area.water.bathymetry) as bathy:
        inside = bathy.axes.contains(np.asarray(lat_deg, dtype=float), lon_deg)
        if not np.all(inside):
            i = int(np.argmin(inside))
            raise AreaError(f"{bathy.path}: the atlas's radials reach {np.ravel(lat_deg)[i]:.4f} N "
                            f"{np.ravel(lon_deg)[i]:.4f} E, outside the bathymetry file "
                            f"({bathy.axes.describe()}); use a larger file, a smaller box or range_max_m")
        grid = bathy.load_box(lat_deg, lon_deg)
        return LoadedBathymetry(path=bathy.path, variable=bathy.variable, axes=bathy.axes, grid=grid,
                                text=bathy.describe())


def single_month(area: Area) -> bool:
    """Whether the area's climatology files hold one time step (one month, used as it is)."""
    clim = area.water.climatology
    if clim is None:
        return True
    with open_climatology(clim) as files:
        var = files.temperature
        return var.time_dim is None or int(var.var.sizes[var.time_dim]) == 1


def load_climatology_box(area: Area, lat_deg, lon_deg) -> LoadedClimatology | None:
    """The cells of the area's climatology (at the area's month) around the positions, read once."""
    if area.water.climatology is None:
        return None
    with open_climatology(area.water.climatology) as clim:
        inside = clim.axes.contains(np.asarray(lat_deg, dtype=float), lon_deg)
        if not np.all(inside):
            i = int(np.argmin(inside))
            raise AreaError(f"{clim.describe()}: the atlas's radials reach {np.ravel(lat_deg)[i]:.4f} N "
                            f"{np.ravel(lon_deg)[i]:.4f} E, outside the climatology")
        field = clim.load_box(lat_deg, lon_deg)
        return LoadedClimatology(path=clim.path, axes=clim.axes, field=field, text=clim.describe())
