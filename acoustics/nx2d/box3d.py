"""An area's environment on a Cartesian box around its origin, for BELLHOP3D.

BELLHOP3D works in one Cartesian frame: x east, y north, metres, the source at (0, 0). tmakit's
radials are WGS84 geodesics from the origin (``envdata.radials``). The box here is the WGS84
azimuthal equidistant projection centred on the origin (pyproj ``+proj=aeqd``): every geodesic
from the origin is a straight line through (0, 0) at its true azimuth and every point on it is
at its true geodesic range, so BELLHOP3D's straight radials pass over the same points as
tmakit's geodesics (``docs/nx2d.md`` measures it). Distances across the radials are stretched by
the projection (by (rho/R)/sin(rho/R), 4 ppm at 30 km); Nx2D never uses them.

On that box, from the same readers as the radials:

- the bottom on a square grid ``step`` metres apart, ``step`` the radials' sampling step
  (min(``[grid] range_step_m``, the bathymetry file's cell)) unless given; elevations bilinear
  between the file's cell centres; land (elevation >= 0) and shallower water are
  `envdata.radials.SHORE_DEPTH_M` deep, as at the end of a radial that meets the shore;
- the sound speed on a coarser grid: columns about the climatology's spacing apart (at most
  `envdata.radials.MAX_COLUMN_SPACING_M`), T and S bilinear and filled down
  (``envdata.climatology``), TEOS-10 with each column's pressure at its latitude, at the depths
  of ``envdata.radials.section_depths`` down to the deepest bottom in the box. An area with one
  profile has the same column at the box's four corners.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass

import numpy as np

from envdata.area import Area
from envdata.bathymetry import open_bathymetry
from envdata.climatology import open_climatology
from envdata.errors import AreaError
from envdata.limits import check_memory
from envdata.radials import MAX_COLUMN_SPACING_M, SHORE_DEPTH_M, column_speeds, one_profile

#: Most bathymetry nodes along one side of the box; a larger box samples more coarsely.
MAX_NODES_PER_SIDE = 2001


@dataclass(frozen=True, eq=False)
class BoxEnvironment:
    """The bottom and the sound speed on a Cartesian box centred on the origin.

    Attributes
    ----------
    origin_lat_deg, origin_lon_deg : float
        The box's centre, WGS84, deg.
    x_m, y_m : ndarray, shape (nx,), (ny,)
        Bathymetry nodes, m east and north of the origin (azimuthal equidistant), increasing.
    bottom_depth_m : ndarray, shape (ny, nx)
        Water depth at the nodes, m, >= `SHORE_DEPTH_M`.
    ssp_x_m, ssp_y_m : ndarray, shape (px,), (py,)
        Sound-speed columns, m, increasing, at least two each.
    ssp_depth_m : ndarray, shape (nz,)
        Depths of the columns, m, from 0 to the deepest bottom in the box (the last value exactly).
    speed_mps : ndarray, shape (nz, py, px)
        Sound speed, m/s.
    """

    origin_lat_deg: float
    origin_lon_deg: float
    x_m: np.ndarray
    y_m: np.ndarray
    bottom_depth_m: np.ndarray
    ssp_x_m: np.ndarray
    ssp_y_m: np.ndarray
    ssp_depth_m: np.ndarray
    speed_mps: np.ndarray

    def __post_init__(self) -> None:
        for name in ("x_m", "y_m", "bottom_depth_m", "ssp_x_m", "ssp_y_m", "ssp_depth_m", "speed_mps"):
            value = np.array(getattr(self, name), dtype=float)
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def max_depth_m(self) -> float:
        """The deepest bottom in the box, m (the sound speed's last depth)."""
        return float(self.ssp_depth_m[-1])

    def bathymetry_half_width_m(self) -> float:
        """Half the side of the largest square about the origin the bottom grid covers, m."""
        return float(min(-self.x_m[0], self.x_m[-1], -self.y_m[0], self.y_m[-1]))

    def ssp_half_width_m(self) -> float:
        """Half the side of the largest square about the origin the sound speed covers, m."""
        return float(min(-self.ssp_x_m[0], self.ssp_x_m[-1], -self.ssp_y_m[0], self.ssp_y_m[-1]))

    def bottom_at(self, x_m, y_m) -> np.ndarray:
        """Water depth at box positions (inside the grid), bilinear between the nodes, m."""
        x, y = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
        points = np.stack([y.ravel(), x.ravel()], axis=1)
        return _bottom_interpolator(self.x_m, self.y_m, self.bottom_depth_m)(points).reshape(x.shape)


def _bottom_interpolator(x_m, y_m, bottom_depth_m):
    from scipy.interpolate import RegularGridInterpolator

    return RegularGridInterpolator((y_m, x_m), bottom_depth_m)


def box_projection(lat_deg: float, lon_deg: float):
    """The WGS84 azimuthal equidistant projection centred on (lat, lon): ``proj(lon, lat) -> (x, y)``
    and ``proj(x, y, inverse=True) -> (lon, lat)``, metres."""
    from pyproj import Proj

    return Proj(proj="aeqd", lat_0=lat_deg, lon_0=lon_deg, ellps="WGS84", units="m")


def box_positions(area: Area, x_m, y_m) -> tuple[np.ndarray, np.ndarray]:
    """Latitudes and longitudes of box positions (x east, y north of the origin, m), deg."""
    proj = box_projection(area.origin.lat_deg, area.origin.lon_deg)
    x, y = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
    if x.size == 1:  # pyproj takes one point as scalars
        lon, lat = proj(float(x.ravel()[0]), float(y.ravel()[0]), inverse=True)
        return np.full(x.shape, lat), np.full(x.shape, lon)
    lon, lat = proj(x, y, inverse=True)
    return np.asarray(lat, dtype=float), np.asarray(lon, dtype=float)


def _axis(half_width_m: float, step_m: float) -> np.ndarray:
    """Nodes at multiples of step_m from -half to +half, both ends covered."""
    n = math.ceil(half_width_m / step_m - 1e-9)
    return step_m * np.arange(-n, n + 1, dtype=float)


def sample_box(area: Area, half_width_m: float, *, bathymetry_step_m: float | None = None,
               ssp_step_m: float | None = None) -> BoxEnvironment:
    """The area's bottom and sound speed on the square [-half, half]^2 about its origin.

    Parameters
    ----------
    area : Area
        An area with an ``[origin]``; its data files are read here.
    half_width_m : float
        Half the side of the box, m (> 0); both grids reach at least this far from the origin
        along x and y.
    bathymetry_step_m : float, optional
        Spacing of the bottom nodes, m; default the radials' step (see the module docstring),
        coarser where the box would need more than `MAX_NODES_PER_SIDE` nodes a side.
    ssp_step_m : float, optional
        Spacing of the sound-speed columns, m; default the climatology's cell, at most
        `MAX_COLUMN_SPACING_M`.

    Raises
    ------
    AreaError
        No ``[origin]``; a data file missing, malformed or not covering the box (naming the file
        and the position); no elevation at a node; the observer not above the bottom at the
        origin; a sound-speed table that does not reach the deepest bottom in the box.
    """
    if area.origin is None:
        raise AreaError(f"area {area.name!r}: has no [origin]; a box about the origin needs one")
    if not (math.isfinite(half_width_m) and half_width_m > 0.0):
        raise ValueError(f"half_width_m: must be > 0 m, got {half_width_m}")
    water = area.water
    with contextlib.ExitStack() as stack:
        bathy = stack.enter_context(open_bathymetry(water.bathymetry)) if water.bathymetry else None
        clim = stack.enter_context(open_climatology(water.climatology)) if water.climatology else None
        x, y, bottom = _bottom_grid(area, bathy, half_width_m, bathymetry_step_m)
        origin_depth = float(_bottom_interpolator(x, y, bottom)([[0.0, 0.0]])[0])
        if not area.observer.depth_m < origin_depth:
            raise AreaError(f"[observer] depth_m: {area.observer.depth_m:g} m is not above the bottom at the "
                            f"origin, {origin_depth:.1f} m deep on the box's bathymetry grid")
        max_depth = float(bottom.max())
        sx, sy, z, speed = _speed_grid(area, clim, half_width_m, ssp_step_m, max_depth)
    return BoxEnvironment(origin_lat_deg=area.origin.lat_deg, origin_lon_deg=area.origin.lon_deg,
                          x_m=x, y_m=y, bottom_depth_m=bottom, ssp_x_m=sx, ssp_y_m=sy, ssp_depth_m=z,
                          speed_mps=speed)


def _bottom_grid(area: Area, bathy, half: float, step_m: float | None):
    if bathy is None:  # flat: two nodes a side carry it
        axis = np.array([-half, half])
        return axis, axis.copy(), np.full((2, 2), float(area.water.depth_m))
    if step_m is None:
        step_m = min(area.grid.range_step_m, bathy.axes.cell_m(area.origin.lat_deg))
    step_m = max(step_m, 2.0 * half / (MAX_NODES_PER_SIDE - 1))
    x = _axis(half, step_m)
    y = x.copy()
    check_memory(6.0 * 8 * x.size * y.size, f"the {x.size} x {y.size} bathymetry nodes of the box")
    xx, yy, lat, lon = _nodes_inside(area, x, y, bathy.axes, lambda i, px, py, la, lo: (
        f"{bathy.path}: the box about the origin (half width {half:.0f} m) leaves the bathymetry file at "
        f"x = {px:.0f} m, y = {py:.0f} m ({la:.4f} N {lo:.4f} E; {bathy.axes.describe()})"))
    elevation = bathy.load_box(lat, lon).elevation_at(lat, lon)
    if not np.all(np.isfinite(elevation)):
        i = int(np.argmin(np.isfinite(elevation)))
        raise AreaError(f"{bathy.path}: no elevation at {lat[i]:.4f} N {lon[i]:.4f} E (a fill value in "
                        f"the file), inside the box about the origin")
    bottom = np.maximum(-elevation, SHORE_DEPTH_M).reshape(yy.shape)
    return x, y, bottom


def _nodes_inside(area: Area, x: np.ndarray, y: np.ndarray, axes, message):
    """The box's nodes (x east, y north of the origin, m) as grids and their latitudes and
    longitudes; AreaError with ``message(i, x, y, lat, lon)`` of the first node outside ``axes``."""
    xx, yy = np.meshgrid(x, y)
    lat, lon = box_positions(area, xx.ravel(), yy.ravel())
    inside = axes.contains(lat, lon)
    if not inside.all():
        i = int(np.argmin(inside))
        raise AreaError(message(i, xx.ravel()[i], yy.ravel()[i], lat[i], lon[i]))
    return xx, yy, lat, lon


def _speed_grid(area: Area, clim, half: float, step_m: float | None, max_depth: float):
    corners = np.array([-half, half])
    one = one_profile(area, max_depth, f" in the box about the origin, {max_depth:.1f} m")
    if one is not None:
        z, column = one
        return corners, corners.copy(), z, np.broadcast_to(column[:, None, None], (z.size, 2, 2))
    if step_m is None:
        step_m = min(MAX_COLUMN_SPACING_M, clim.axes.cell_m(area.origin.lat_deg))
    n = max(2, math.ceil(2.0 * half / step_m - 1e-9) + 1)
    sx = np.linspace(-half, half, n)
    sy = sx.copy()
    _, _, lat, lon = _nodes_inside(area, sx, sy, clim.axes, lambda i, px, py, la, lo: (
        f"{clim.describe()}: the box about the origin (half width {half:.0f} m) leaves the climatology at "
        f"{la:.4f} N {lo:.4f} E"))
    z, speed = column_speeds(clim.load_box(lat, lon), (lat, lon), (lat, lon), max_depth)
    if not np.all(np.isfinite(speed)):
        raise AreaError(f"{clim.describe()}: TEOS-10 gives no sound speed in the box about the origin "
                        f"(T or S out of range)")
    return sx, sy, z, speed.reshape(z.size, sy.size, sx.size)
