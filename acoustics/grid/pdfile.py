"""P_D maps as CF netCDF on latitude and longitude: the file a GIS opens beside the PNG.

A regular latitude-longitude raster around the tables' origin (WGS84: a ``crs`` variable with
``grid_mapping_name = "latitude_longitude"`` that every data variable names in
``grid_mapping``; ``lat``, ``lon`` with their standard names and units; Conventions CF-1.8),
readable by xarray and by GDAL's netCDF driver (QGIS). Each cell's P_D is that of a target there
seen from the observer at the origin: its range and bearing in the azimuthal equidistant plane
of the origin (true distances and azimuths from it, ``envdata.geometry``), K between radials as
the trackers take it, sigma and P_D as on the PNG (``acoustics.grid.pdmap``).

Variables (``pd`` per class, or per position of an atlas):

- ``pd(class|origin, lat, lon)``: P_D of one look in the band (or any band), 1; NaN beyond land
  (no K) and beyond the table's last range;
- ``beyond_table(class|origin, lat, lon)``: 1 where the cell is beyond the table's last range on a
  bearing where P_D still reaches 0.1 there (detection may go on; the table cannot say), else 0;
- ``detection_range_m(class|origin, level, bearing)``: the largest range where P_D >= level, m,
  NaN where it never is or where it is beyond the table (``detection_beyond_table`` then 1).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from acoustics.grid.detectionsigma import SigmaOverride, detection_sigma_db
from acoustics.grid.face import Tables
from acoustics.grid.formats import PD_MAP_FORMAT
from acoustics.grid.pdmap import ANY_BAND, REACH_LEVEL, PDMap, pd_map
from acoustics.pd import PD_LEVELS, any_band, pd_of_excess
from envdata.files import atomic_path
from envdata.geometry import lat_lon_to_local_plane

#: Cells across the raster's widest side at most (the cell is then coarser than the range step).
MAX_CELLS = 400
#: WGS84, as the ``crs`` variable says it.
WGS84 = {"grid_mapping_name": "latitude_longitude", "semi_major_axis": 6378137.0,
         "inverse_flattening": 298.257223563, "longitude_of_prime_meridian": 0.0,
         "crs_wkt": 'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
                    'PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]]'}


def latlon_axes(lat_deg, lon_deg, radius_m: float, cell_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Cell centres, deg, of a raster covering ``radius_m`` around every given point."""
    lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
    lon = np.atleast_1d(np.asarray(lon_deg, dtype=float))
    mid = math.radians(float(np.mean(lat)))
    dlat = cell_m / 111_132.0                            # m per degree of latitude, mid-latitudes
    dlon = cell_m / (111_320.0 * math.cos(mid))
    pad_lat = radius_m / 111_132.0 + dlat
    pad_lon = radius_m / (111_320.0 * math.cos(mid)) + dlon
    lat_axis = np.arange(lat.min() - pad_lat, lat.max() + pad_lat + dlat / 2, dlat)
    lon_axis = np.arange(lon.min() - pad_lon, lon.max() + pad_lon + dlon / 2, dlon)
    return lat_axis, lon_axis


def cell_size_m(tables: Tables, span_m: float) -> float:
    """The raster's cell: the range step, coarsened to at most `MAX_CELLS` across ``span_m``."""
    step = float(np.median(np.diff(tables.range_m))) if tables.range_m.size > 1 else float(tables.range_m[0])
    return max(step, span_m / MAX_CELLS)


def pd_on_latlon(tables: Tables, cls_name: str, row: str, lat_axis, lon_axis, pm: PDMap,
                 override: SigmaOverride | None = None) -> tuple[np.ndarray, np.ndarray]:
    """P_D of a class in a band (or any band) on a raster, and its beyond-the-table flag.

    ``pm`` is the class's P_D map on the tables' radials (for which bearings pass the table's
    end). Returns (pd, beyond), each (lat, lon).
    """
    lat, lon = np.meshgrid(np.asarray(lat_axis, dtype=float), np.asarray(lon_axis, dtype=float), indexing="ij")
    x, y = lat_lon_to_local_plane(tables.origin_lat_deg, tables.origin_lon_deg, lat, lon)
    r = np.hypot(x, y)
    b = np.mod(np.degrees(np.arctan2(x, y)), 360.0)
    inside = r <= tables.range_m[-1]
    ic = tables.class_index(cls_name)
    k = tables.k_at(ic, r[inside], bearing_deg=b[inside])                          # (N, M)
    sigma = detection_sigma_db(tables, ic, r[inside], b[inside], override).total_db
    p_bands = pd_of_excess(k - pm.terms.k_needed_db()[None, :], sigma)
    p = any_band(p_bands, axis=-1) if row == ANY_BAND else p_bands[:, tables.band_index(row)]
    pd = np.full(r.shape, np.nan)
    pd[inside] = np.where(np.isnan(k).all(axis=-1), np.nan, p)
    # beyond the last range: where the nearest radial's P_D still reaches 0.1 at the table's end
    edge = pm.beyond[REACH_LEVEL][pm.row(row)]
    nearest = np.argmin(np.abs((b[..., None] - pm.bearing_deg + 180.0) % 360.0 - 180.0), axis=-1)
    beyond = (~inside) & edge[nearest]
    return pd, beyond.astype(np.int8)


def _attrs(tables: Tables, row: str, pm: PDMap, what: str) -> dict:
    import datetime

    made = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    return {"Conventions": "CF-1.8", "title": f"tmakit P_D map: {what}", "institution": "tmakit",
            "history": f"{made}: P_D map written by tmakit from {tables.source}",
            "source": f"tables {tables.source} (area {tables.area.name}, model {tables.model})",
            "tmakit_format": PD_MAP_FORMAT, "area": tables.area.name, "band": row,
            "observer_depth_m": float(tables.observer_depth_m),
            "integration_time_s": float(pm.terms.integration_time_s), "pd_levels": list(PD_LEVELS),
            "sigma": pm.sigma.source,
            "comment": "P_D = Phi(SE / sigma) of one look, the target at its class's mean level; "
                       + ("any band: 1 - prod(1 - P_band), the bands independent; " if row == ANY_BAND else "")
                       + "NaN beyond land and beyond the table's last range (beyond_table says where "
                         "detection may go on past it)"}


def _layers(which, row: str, lat_axis, lon_axis, override):
    """The raster and the radials' ranges of each (tables, class), stacked: (pd, beyond_table,
    detection_range_m, detection_beyond_table), and the last P_D map (for the attributes)."""
    pds, beyonds, ranges, past = [], [], [], []
    for tables, cls_name in which:
        pm = pd_map(tables, cls_name, tables.bearing_deg, override=override)
        pd, beyond = pd_on_latlon(tables, cls_name, row, lat_axis, lon_axis, pm, override)
        pds.append(pd)
        beyonds.append(beyond)
        ranges.append(np.stack([pm.ranges_m[p][pm.row(row)] for p in PD_LEVELS]))
        past.append(np.stack([pm.beyond[p][pm.row(row)] for p in PD_LEVELS]))
    return (pds, beyonds, ranges, past), pm


def _variables(stack: str, pds, beyonds, ranges, past) -> dict:
    flags = {"flag_values": np.array([0, 1], dtype=np.int8), "flag_meanings": "inside_or_ends beyond_table",
             "grid_mapping": "crs"}
    return {
        "pd": ((stack, "lat", "lon"), np.stack(pds).astype(np.float32),
               {"long_name": "probability of detection in one look", "units": "1", "grid_mapping": "crs",
                "valid_min": np.float32(0.0), "valid_max": np.float32(1.0)}),
        "beyond_table": ((stack, "lat", "lon"), np.stack(beyonds),
                         {"long_name": "beyond the table's last range, P_D >= 0.1 at its end on the "
                                       "nearest radial", **flags}),
        "detection_range_m": ((stack, "level", "bearing"), np.stack(ranges),
                              {"long_name": "largest range where P_D >= level", "units": "m",
                               "comment": "NaN where never, or beyond the table"}),
        "detection_beyond_table": ((stack, "level", "bearing"), np.stack(past).astype(np.int8),
                                   {"long_name": "P_D >= level at the table's last range", "units": "1"}),
    }


def _coords(stack: str, names, lat_axis, lon_axis, bearings) -> dict:
    return {stack: (stack, np.asarray(names)),
            "lat": ("lat", lat_axis, {"standard_name": "latitude", "long_name": "latitude",
                                      "units": "degrees_north", "axis": "Y"}),
            "lon": ("lon", lon_axis, {"standard_name": "longitude", "long_name": "longitude",
                                      "units": "degrees_east", "axis": "X"}),
            "level": ("level", np.array(PD_LEVELS), {"long_name": "P_D level", "units": "1"}),
            "bearing": ("bearing", np.asarray(bearings, dtype=float),
                        {"long_name": "bearing clockwise from true north at the observer", "units": "degree"})}


def grid_pd_dataset(tables: Tables, row: str, *, classes=None, override: SigmaOverride | None = None,
                    cell_m: float | None = None) -> xr.Dataset:
    """The P_D map of a bearing-dependent grid's classes as a CF dataset (module docstring)."""
    classes = list(tables.class_names) if classes is None else list(classes)
    r_max = float(tables.range_m[-1])
    cell = cell_size_m(tables, 2 * r_max) if cell_m is None else cell_m
    lat_axis, lon_axis = latlon_axes(tables.origin_lat_deg, tables.origin_lon_deg, r_max, cell)
    layers, pm = _layers([(tables, c) for c in classes], row, lat_axis, lon_axis, override)
    ds = xr.Dataset(_variables("class", *layers), coords=_coords("class", classes, lat_axis, lon_axis,
                                                                 tables.bearing_deg))
    ds = ds.assign(crs=((), np.int32(0), WGS84))
    ds["class"].attrs["long_name"] = "target class"
    ds.attrs.update(_attrs(tables, row, pm, f"{row} of the classes of {tables.area.name}"),
                    origin_lat_deg=float(tables.origin_lat_deg), origin_lon_deg=float(tables.origin_lon_deg))
    return ds


def atlas_pd_dataset(store, month: int, cls_name: str, row: str, *, override: SigmaOverride | None = None,
                     cell_m: float | None = None) -> xr.Dataset:
    """The P_D maps of one class at every built position of an atlas's month, on one raster."""
    m = store.month_index(month)
    built = [o for o in range(store.lat_deg.size) if store.done[m, o]]
    r_max = float(store.range_m[-1])
    lat0, lon0 = store.lat_deg[built], store.lon_deg[built]
    span = 2 * r_max + 111_132.0 * float(np.ptp(lat0) if lat0.size else 0.0)
    first = store.sel(month=month, origin=built[0])
    cell = cell_size_m(first, span) if cell_m is None else cell_m
    lat_axis, lon_axis = latlon_axes(lat0, lon0, r_max, cell)
    layers, pm = _layers([(store.sel(month=month, origin=o), cls_name) for o in built], row, lat_axis, lon_axis,
                         override)
    ds = xr.Dataset(_variables("origin", *layers), coords=_coords("origin", built, lat_axis, lon_axis,
                                                                  store.bearing_deg))
    ds = ds.assign_coords(origin_lat_deg=("origin", lat0, {"standard_name": "latitude", "units": "degrees_north",
                                                           "long_name": "observer position"}),
                          origin_lon_deg=("origin", lon0, {"standard_name": "longitude", "units": "degrees_east",
                                                           "long_name": "observer position"}))
    ds = ds.assign(crs=((), np.int32(0), WGS84))
    ds["origin"].attrs["long_name"] = "index of the atlas's observer position"
    ds.attrs.update(_attrs(first, row, pm, f"class {cls_name}, {row}, month {month}, every position of the "
                                           f"atlas {store.path.name}"), month=int(month), cls_name=cls_name)
    return ds


def write_pd_file(ds: xr.Dataset, path, *, atomic: bool = True) -> None:
    """Write a P_D map dataset as netCDF4 (coordinates without ``_FillValue``, as CF wants): through
    a temporary file, or straight to ``path`` for a caller that renames several files together."""
    encoding = {name: {"_FillValue": None} for name in ds.coords}
    encoding.update({name: {"zlib": True, "complevel": 4} for name in ("pd", "beyond_table")})
    encoding["pd"]["_FillValue"] = np.float32(np.nan)
    if not atomic:
        ds.to_netcdf(path, format="NETCDF4", encoding=encoding)
        return
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, format="NETCDF4", encoding=encoding)


__all__ = ["atlas_pd_dataset", "grid_pd_dataset", "latlon_axes", "pd_on_latlon", "write_pd_file"]
