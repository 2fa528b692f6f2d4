"""Regular latitude-longitude grids in netCDF files: open lazily, find the axes, cut a box, interpolate.

Shared by the bathymetry and climatology readers. Files are opened lazily (xarray on the netCDF4
backend): only the coordinates are read on opening, and only the box of cells that the radials
need is loaded, so a global 15-arc-second GEBCO file (~7 GB) costs a few hundred kilobytes.

Values between cell centres are interpolated bilinearly in latitude and longitude (degrees);
between the outermost centres and the file's edge (half a cell further) the edge value holds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from envdata.errors import AreaError
from envdata.files import check_input_file

#: Mean radius of the Earth, m, for cell sizes and nearest-column distances (not for the radials,
#: which are WGS84 geodesics).
EARTH_RADIUS_M = 6_371_000.0
LAT_NAMES = ("lat", "latitude", "y")
LON_NAMES = ("lon", "longitude", "x")
LAT_UNITS = ("degrees_north", "degree_north", "degree_N", "degrees_N", "degreeN", "degreesN")
LON_UNITS = ("degrees_east", "degree_east", "degree_E", "degrees_E", "degreeE", "degreesE")
METRE_UNITS = ("m", "meter", "meters", "metre", "metres")


def open_dataset(path: Path, what: str):
    """Open a netCDF file lazily (times left undecoded: WOA's "months since" cannot be).

    Raises
    ------
    AreaError
        Not a regular file, or not readable as netCDF; the message names the file.
    """
    import xarray as xr

    check_input_file(path, what, AreaError)
    try:
        return xr.open_dataset(path, decode_times=False, cache=False)
    except Exception as exc:  # the backends raise many kinds for a file that is not netCDF
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise AreaError(f"{path}: cannot read the {what} as netCDF ({reason})") from None


def units_of(var) -> str:
    """The ``units`` attribute of a variable, stripped ("" when absent)."""
    return str(var.attrs.get("units", "")).strip()


def named_variable(ds, path: Path, label: str, names: tuple[str, ...], given: str | None,
                   pool=None) -> str | None:
    """``given`` (AreaError naming ``label`` when ``pool``, the data variables by default, lacks
    it), else the first of ``names`` among the data variables, else None."""
    pool = ds.data_vars if pool is None else pool
    if given is not None:
        if given not in pool:
            raise AreaError(f"{path}: no variable {given!r} ({label}); the file has "
                            f"{', '.join(sorted(map(str, ds.data_vars))) or 'no data variables'}")
        return given
    return next((name for name in names if name in ds.data_vars), None)


def find_variable(ds, path: Path, what: str, names: tuple[str, ...], standard_names: tuple[str, ...],
                  given: str | None = None) -> str:
    """The name of a data variable: ``given``, else the first of ``names``, else the one variable
    whose CF ``standard_name`` is one of ``standard_names``.

    Raises
    ------
    AreaError
        The given name is missing, no variable matches, or several match by standard_name.
    """
    found = named_variable(ds, path, f"the {what}", names, given, ds.variables)
    if found is not None:
        return found
    matches = [str(name) for name, var in ds.data_vars.items()
               if var.attrs.get("standard_name") in standard_names]
    if len(matches) == 1:
        return matches[0]
    if len(matches) > 1:
        raise AreaError(f"{path}: several variables could be the {what} ({', '.join(matches)}, by "
                        f"standard_name); name one")
    raise AreaError(f"{path}: no {what} variable: none is named {' or '.join(names)} or has the "
                    f"standard_name {' or '.join(standard_names)}; the file has "
                    f"{', '.join(sorted(map(str, ds.data_vars))) or 'no data variables'}")


def _is_axis(ds, dim: str, kind: str) -> bool:
    if dim not in ds.variables:
        return False
    attrs = ds[dim].attrs
    if kind == "lat":
        return (dim.lower() in LAT_NAMES or attrs.get("standard_name") == "latitude"
                or attrs.get("units") in LAT_UNITS or attrs.get("axis") == "Y")
    return (dim.lower() in LON_NAMES or attrs.get("standard_name") == "longitude"
            or attrs.get("units") in LON_UNITS or attrs.get("axis") == "X")


def _spacing(values: np.ndarray) -> float:
    return float(np.median(np.abs(np.diff(values)))) if values.size > 1 else 0.0


@dataclass(frozen=True, eq=False)
class LatLonAxes:
    """The latitude and longitude axes of a variable in a file: 1-D cell centres, deg.

    ``lat_deg`` and ``lon_deg`` are as stored (increasing or decreasing); ``lat_sorted`` and
    ``lon_sorted`` increasing. Longitudes are in the file's own convention: [-180, 180) or, when
    the file stores longitudes beyond 180, [0, 360).
    """

    path: Path
    lat_dim: str
    lon_dim: str
    lat_deg: np.ndarray
    lon_deg: np.ndarray

    @classmethod
    def of(cls, ds, var_name: str, path: Path) -> "LatLonAxes":
        """Find the lat/lon axes of ``var_name`` (by name, CF standard_name, units or axis)."""
        dims = [str(d) for d in ds[var_name].dims]
        lat = [d for d in dims if _is_axis(ds, d, "lat")]
        lon = [d for d in dims if _is_axis(ds, d, "lon")]
        if not lat or not lon:
            missing = "latitude" if not lat else "longitude"
            raise AreaError(f"{path}: variable {var_name!r} has no {missing} coordinate among its "
                            f"dimensions ({', '.join(dims)}); need 1-D lat and lon coordinates")
        axes = cls(path=path, lat_dim=lat[0], lon_dim=lon[0],
                   lat_deg=np.asarray(ds[lat[0]].values, dtype=float),
                   lon_deg=np.asarray(ds[lon[0]].values, dtype=float))
        axes._check()
        return axes

    def _check(self) -> None:
        for name, values, lo, hi in (("latitude", self.lat_deg, -90.0, 90.0),
                                     ("longitude", self.lon_deg, -360.0, 360.0)):
            if values.ndim != 1 or values.size < 1:
                raise AreaError(f"{self.path}: the {name} coordinate must be 1-D and not empty")
            if not np.all(np.isfinite(values)) or values.min() < lo or values.max() > hi:
                raise AreaError(f"{self.path}: the {name} coordinate must be finite degrees in "
                                f"[{lo:g}, {hi:g}], got {values.min():g} .. {values.max():g}")
            step = np.diff(values)
            if values.size > 1 and not (np.all(step > 0) or np.all(step < 0)):
                raise AreaError(f"{self.path}: the {name} coordinate must be strictly monotonic")

    @property
    def lat_sorted(self) -> np.ndarray:
        return np.sort(self.lat_deg)

    @property
    def lon_sorted(self) -> np.ndarray:
        return np.sort(self.lon_deg)

    @property
    def lat_step_deg(self) -> float:
        return _spacing(self.lat_deg)

    @property
    def lon_step_deg(self) -> float:
        return _spacing(self.lon_deg)

    @property
    def is_global_in_lon(self) -> bool:
        """True when the cells go all the way round (the file's own seam is then inside it)."""
        span = self.lon_sorted[-1] - self.lon_sorted[0] + self.lon_step_deg
        return span >= 360.0 - 1e-6

    def extent(self) -> tuple[float, float, float, float]:
        """lat_min, lat_max, lon_min, lon_max of the cells (centres +- half a cell), deg."""
        lat, lon = self.lat_sorted, self.lon_sorted
        hy, hx = 0.5 * self.lat_step_deg, 0.5 * self.lon_step_deg
        return (max(-90.0, lat[0] - hy), min(90.0, lat[-1] + hy), lon[0] - hx, lon[-1] + hx)

    def describe(self) -> str:
        """The covered box, for messages."""
        s, n, w, e = self.extent()
        return f"lat {s:.4f} .. {n:.4f} deg, lon {w:.4f} .. {e:.4f} deg"

    def file_lon(self, lon_deg) -> np.ndarray:
        """Longitudes in the file's convention: [0, 360) when it stores longitudes beyond 180,
        else [-180, 180)."""
        lon = np.asarray(lon_deg, dtype=float)
        if self.lon_sorted[-1] > 180.0:
            return np.mod(lon, 360.0)
        return np.mod(lon + 180.0, 360.0) - 180.0

    def contains(self, lat_deg, lon_deg) -> np.ndarray:
        """True where a position lies within the file's cells."""
        s, n, w, e = self.extent()
        lat = np.asarray(lat_deg, dtype=float)
        lon = self.file_lon(lon_deg)
        if self.is_global_in_lon:
            inside_lon = np.ones(lon.shape, dtype=bool)
        else:
            inside_lon = (lon >= w) & (lon <= e)
        return (lat >= s) & (lat <= n) & inside_lon

    def cell_m(self, lat_deg: float) -> float:
        """Size of a cell at ``lat_deg``: the smaller of its north-south and east-west sides, m."""
        ny = math.radians(self.lat_step_deg) * EARTH_RADIUS_M
        nx = math.radians(self.lon_step_deg) * EARTH_RADIUS_M * math.cos(math.radians(lat_deg))
        sizes = [v for v in (ny, nx) if v > 0]
        return min(sizes) if sizes else math.inf

    def box_inside(self, source, lat_deg, lon_deg, margin: int, what: str = "the file"
                   ) -> tuple[slice, slice, bool, bool]:
        """`box` of positions that must all lie within the file's cells; AreaError naming the
        first that does not (``source``: the file, ``what``: what it is in the message)."""
        lat = np.asarray(lat_deg, dtype=float)
        inside = self.contains(lat, lon_deg)
        if not np.all(inside):
            i = int(np.argmin(inside))
            raise AreaError(f"{source}: position {lat.ravel()[i]:.5f} N "
                            f"{np.asarray(lon_deg, dtype=float).ravel()[i]:.5f} E is outside {what} "
                            f"({self.describe()})")
        return self.box(lat, lon_deg, margin)

    def box(self, lat_deg, lon_deg, margin: int = 2) -> tuple[slice, slice, bool, bool]:
        """Index slices (as stored) of the cells around the positions, ``margin`` cells wider.

        Returns the lat and lon slices and whether each axis is stored decreasing (then the
        loaded block is to be flipped to increasing).
        """
        lat = np.asarray(lat_deg, dtype=float)
        lon = self.file_lon(lon_deg)
        out = []
        for values, lo, hi in ((self.lat_deg, lat.min(), lat.max()), (self.lon_deg, lon.min(), lon.max())):
            n = values.size
            decreasing = n > 1 and values[1] < values[0]
            a = values[::-1] if decreasing else values
            i0 = max(0, int(np.searchsorted(a, lo, side="right")) - 1 - margin)
            i1 = min(n, int(np.searchsorted(a, hi, side="left")) + 1 + margin)
            out.append((slice(n - i1, n - i0) if decreasing else slice(i0, i1), decreasing))
        (lat_slice, lat_flip), (lon_slice, lon_flip) = out
        return lat_slice, lon_slice, lat_flip, lon_flip


def _axis_weights(axis: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lower and upper neighbours in an increasing axis and the weight of the upper one; beyond
    the outermost centres the edge value holds."""
    n = axis.size
    if n == 1:
        zero = np.zeros(x.shape, dtype=int)
        return zero, zero, np.zeros(x.shape)
    i = np.clip(np.searchsorted(axis, x, side="right") - 1, 0, n - 2)
    w = np.clip((x - axis[i]) / (axis[i + 1] - axis[i]), 0.0, 1.0)
    return i, i + 1, w


def bilinear_corners(lat_axis: np.ndarray, lon_axis: np.ndarray, lat_deg, lon_deg):
    """The four grid cells around each position and their bilinear weights.

    Parameters
    ----------
    lat_axis, lon_axis : ndarray
        Increasing cell centres, deg.
    lat_deg, lon_deg : array_like, shape (M,)
        Positions, in the axes' longitude convention.

    Returns
    -------
    iy, ix : ndarray of int, shape (M, 4)
        Row and column of each corner.
    w : ndarray, shape (M, 4)
        Bilinear weights, summing to 1 for each position.
    """
    lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
    lon = np.atleast_1d(np.asarray(lon_deg, dtype=float))
    y0, y1, wy = _axis_weights(lat_axis, lat)
    x0, x1, wx = _axis_weights(lon_axis, lon)
    iy = np.stack([y0, y0, y1, y1], axis=1)
    ix = np.stack([x0, x1, x0, x1], axis=1)
    w = np.stack([(1 - wy) * (1 - wx), (1 - wy) * wx, wy * (1 - wx), wy * wx], axis=1)
    return iy, ix, w


def distance_m(lat1_deg, lon1_deg, lat2_deg, lon2_deg) -> np.ndarray:
    """Great-circle distance on the mean sphere (haversine), m; for picking a nearest cell."""
    p1, p2 = np.radians(lat1_deg), np.radians(lat2_deg)
    dp = p2 - p1
    dl = np.radians(np.asarray(lon2_deg) - np.asarray(lon1_deg))
    h = np.sin(dp / 2) ** 2 + np.cos(p1) * np.cos(p2) * np.sin(dl / 2) ** 2
    return 2 * EARTH_RADIUS_M * np.arcsin(np.sqrt(np.clip(h, 0.0, 1.0)))
