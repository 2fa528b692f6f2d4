"""Bathymetry files in GEBCO's and EMODnet's layouts: ``elevation(lat, lon)``, m.

GEBCO's netCDF grid has a 2-D ``elevation`` variable (int16, metres above mean sea level: the sea
floor is negative) on 1-D ``lat`` and ``lon`` coordinate variables (cell centres, degrees north
and east), with values on land too. EMODnet Bathymetry's DTM (netCDF tiles, and its ERDDAP
subsets on ``latitude``/``longitude``) has an ``elevation`` too, float, m relative to Lowest
Astronomical Tide, negative at sea, but no value on land: there the cells hold the variable's
``_FillValue`` or ``missing_value``. Another variable name may be given (``[water]
bathymetry_variable``); without one the variable is ``elevation``, ``depth``, or the one whose CF
``standard_name`` is a height (positive up, GEBCO uses ``height_above_reference_ellipsoid``) or a
sea-floor depth (positive down, negated here). A ``positive`` attribute, where present, decides
the sign; without one (and no standard_name) a variable named ``depth`` is positive down. Units
must be metres.

Cells with no value (a declared ``_FillValue``/``missing_value``, NaN, or an undeclared fill
beyond 1e5 m) are land: a radial that reaches one ends there (``envdata.radials``), as at a cell
of elevation >= 0.

The file is opened lazily and only the box of cells around the requested positions is loaded;
elevations between cell centres are interpolated bilinearly.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from envdata.datafiles import BathymetrySource
from envdata.errors import AreaError
from envdata.geogrid import METRE_UNITS, LatLonAxes, bilinear_corners, find_variable, open_dataset, units_of
from envdata.limits import check_memory

ELEVATION_NAMES = ("elevation", "depth")
#: CF standard names of a surface height, positive up.
HEIGHT_STANDARD_NAMES = ("height_above_reference_ellipsoid", "height_above_mean_sea_level",
                         "height_above_geoid", "surface_altitude", "altitude", "bedrock_altitude")
#: CF standard names of a sea-floor depth, positive down.
DEPTH_STANDARD_NAMES = ("sea_floor_depth_below_geoid", "sea_floor_depth_below_mean_sea_level",
                        "sea_floor_depth_below_sea_surface", "sea_floor_depth_below_reference_ellipsoid")
#: Cells beyond the box of the positions loaded on each side (so a bilinear neighbour is there).
MARGIN_CELLS = 2


@dataclass(frozen=True, eq=False)
class ElevationGrid:
    """A box of a bathymetry file in memory: elevation, m, positive up, on increasing axes."""

    path: Path
    lat_deg: np.ndarray  # (ny,) increasing cell centres
    lon_deg: np.ndarray  # (nx,) increasing, in the file's longitude convention
    elevation_m: np.ndarray  # (ny, nx), NaN where the file has no value
    axes: LatLonAxes

    def elevation_at(self, lat_deg, lon_deg) -> np.ndarray:
        """Elevation at positions, m, positive up, interpolated bilinearly between cell centres.

        NaN where a neighbouring cell has no value. Positions must lie in the loaded box.
        """
        lon = self.axes.file_lon(lon_deg)
        iy, ix, w = bilinear_corners(self.lat_deg, self.lon_deg, lat_deg, lon)
        corners = self.elevation_m[iy, ix]
        # a corner of zero weight does not matter even when it has no value; one that has weight
        # and no value makes the result NaN
        return np.sum(w * np.where(w > 0, corners, 0.0), axis=1)

    def sea_elevation_at(self, lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
        """Elevation at positions, m, positive up, and where the file has no value (land).

        A cell with no value (a ``_FillValue``/``missing_value``, NaN, or beyond ``1e5`` m) is
        land, as EMODnet marks land: a position whose nearest cell centre has no value is on
        land (``no_data`` True, elevation NaN); elsewhere the elevation is bilinear between the
        cells around it that have values, their weights renormalised (so the sea floor holds up
        to the edge of the land cells instead of turning NaN half a cell before it).

        Returns
        -------
        elevation_m : ndarray, shape (M,)
            NaN where ``no_data``.
        no_data : ndarray of bool, shape (M,)
        """
        lon = self.axes.file_lon(lon_deg)
        iy, ix, w = bilinear_corners(self.lat_deg, self.lon_deg, lat_deg, lon)
        corners = self.elevation_m[iy, ix]
        valid = np.isfinite(corners)
        rows = np.arange(w.shape[0])
        no_data = ~valid[rows, np.argmax(w, axis=1)]  # the nearest centre has the largest weight
        w = np.where(valid, w, 0.0)
        total = w.sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            elevation = np.sum(w * np.where(valid, corners, 0.0), axis=1) / total
        return np.where(no_data | (total <= 0.0), np.nan, elevation), no_data | (total <= 0.0)


class BathymetryFile:
    """An open bathymetry file: its variable, sign and axes, read lazily. Use as a context manager.

    Parameters
    ----------
    source : BathymetrySource
        The area's reference to the file.

    Raises
    ------
    AreaError
        The file is missing or not netCDF, has no elevation variable, the variable is not 2-D on
        lat/lon, or its units are not metres.
    """

    def __init__(self, source: BathymetrySource):
        self.path = source.file.resolved()
        self._ds = open_dataset(self.path, "bathymetry file")
        try:
            ds = self._ds
            self.variable = _find_elevation(ds, self.path, source.variable)
            var = ds[self.variable]
            self.axes = LatLonAxes.of(ds, self.variable, self.path)
            if set(map(str, var.dims)) != {self.axes.lat_dim, self.axes.lon_dim}:
                raise AreaError(f"{self.path}: variable {self.variable!r} must be 2-D on "
                                f"({self.axes.lat_dim}, {self.axes.lon_dim}), got dimensions "
                                f"({', '.join(map(str, var.dims))})")
            units = units_of(var)
            if units not in METRE_UNITS:
                raise AreaError(f"{self.path}: variable {self.variable!r} must be in metres (units = \"m\"), "
                                f"got units = {units!r}")
            self.sign = _sign(var)
        except BaseException:
            self._ds.close()
            raise

    def __enter__(self) -> "BathymetryFile":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self._ds.close()

    def describe(self) -> str:
        return f"{self.path} (variable {self.variable!r}, {self.axes.describe()})"

    def load_box(self, lat_deg, lon_deg) -> ElevationGrid:
        """Load the cells around the given positions (a margin of `MARGIN_CELLS` cells).

        Raises
        ------
        AreaError
            A position outside the file's cells (check ``axes.contains`` first to say which).
        """
        lat_slice, lon_slice, lat_flip, lon_flip = self.axes.box_inside(self.path, lat_deg, lon_deg, MARGIN_CELLS)
        ny, nx = lat_slice.stop - lat_slice.start, lon_slice.stop - lon_slice.start
        check_memory(3.0 * 8 * ny * nx, f"{self.path}: the {ny} x {nx} cells of bathymetry the radials cross")
        block = self._ds[self.variable].isel({self.axes.lat_dim: lat_slice, self.axes.lon_dim: lon_slice})
        block = block.transpose(self.axes.lat_dim, self.axes.lon_dim)
        values = np.asarray(block.values, dtype=float) * self.sign
        lat_axis = self.axes.lat_deg[lat_slice]
        lon_axis = self.axes.lon_deg[lon_slice]
        if lat_flip:
            values, lat_axis = values[::-1, :], lat_axis[::-1]
        if lon_flip:
            values, lon_axis = values[:, ::-1], lon_axis[::-1]
        values[np.abs(values) > 1.0e5] = np.nan  # a fill value the file did not declare
        return ElevationGrid(path=self.path, lat_deg=lat_axis.copy(), lon_deg=lon_axis.copy(),
                             elevation_m=values, axes=self.axes)


def open_bathymetry(source: BathymetrySource) -> BathymetryFile:
    """Open a bathymetry file lazily (see `BathymetryFile`)."""
    return BathymetryFile(source)


def _find_elevation(ds, path: Path, given: str | None) -> str:
    return find_variable(ds, path, "elevation", ELEVATION_NAMES, HEIGHT_STANDARD_NAMES + DEPTH_STANDARD_NAMES,
                         given)


def _sign(var) -> float:
    """+1 for a height (positive up), -1 for a depth (positive down): by the ``positive``
    attribute, else the standard_name, else the name (``depth`` is down)."""
    positive = str(var.attrs.get("positive", "")).strip().lower()
    if positive in ("up", "down"):
        return 1.0 if positive == "up" else -1.0
    if var.attrs.get("standard_name") in DEPTH_STANDARD_NAMES:
        return -1.0
    if var.attrs.get("standard_name") in HEIGHT_STANDARD_NAMES:
        return 1.0
    return -1.0 if str(var.name).lower() == "depth" else 1.0
