"""Write netCDF files in the layouts of GEBCO's grid, EMODnet's DTM and the World Ocean Atlas (sample and test data).

The layouts (dimension and variable names, dtypes, attributes) are those of the products, so
that tmakit's readers are exercised on what users download; the values are whatever the caller
gives (synthetic: these files say in their titles that they are not GEBCO or WOA data).

- GEBCO: ``elevation(lat, lon)`` int16, m, positive up, on double ``lat``/``lon`` cell centres
  (the 15-arc-second grid: centres at (k + 1/2)/240 deg), a ``crs`` variable.
- EMODnet Bathymetry DTM tiles: ``elevation(lat, lon)`` float32, m relative to LAT, positive up,
  with no value on land (a ``_FillValue`` or ``missing_value``) and the product's companions
  (``elevation_min``/``_max``, ``stdev``, ``value_count``, ``interpolation_flag``).
- WOA: one file per variable (``t``: ``t_an``/``t_mn`` in degrees_celsius; ``s``:
  ``s_an``/``s_mn``, practical salinity, units "1") on (time, depth, lat, lon), float32 with
  ``_FillValue`` 9.96921e36 below the sea floor and on land; float32 ``lat``/``lon``/``depth``
  with bounds; ``time`` in "months since 1955-01-01 00:00:00" (no calendar, undecodable) with
  ``climatology_bounds``; the standard depth levels (57 to 1500 m for a month); optionally the
  standard deviations ``t_sd``/``s_sd``.
- Sea-Bird ``.cnv`` (a CTD cast as SBE Data Processing writes it): ``*`` instrument and NMEA
  header lines, ``**`` user lines, ``#`` lines (``nquan``, ``nvalues``, one ``name N = short:
  long [unit]`` per column, ``span``, ``interval``, ``start_time``, ``bad_flag``), ``*END*``, then
  the scans in fixed-width columns of 11 characters; Windows line ends; a missing or bad value and
  a scan Loop Edit marks bad hold ``bad_flag`` (-9.990e-29).
"""

from __future__ import annotations

import datetime
from pathlib import Path

import numpy as np

#: WOA's standard depth levels, m: 102 to 5500 m; monthly fields use the first 57 (to 1500 m).
WOA_LEVELS_M = np.concatenate([np.arange(0.0, 100.1, 5.0), np.arange(125.0, 500.1, 25.0),
                               np.arange(550.0, 2000.1, 50.0), np.arange(2100.0, 5500.1, 100.0)])
WOA_MONTHLY_LEVELS = 57
WOA_FILL = np.float32(9.96921e36)
#: WOA's time stamps: month m of the 1955-2022 climatology is 395.5 + m "months since 1955-01-01",
#: its climatology bounds [m - 1, 804 + m].
WOA_TIME_UNITS = "months since 1955-01-01 00:00:00"

_CRS = {"grid_mapping_name": "latitude_longitude", "epsg_code": "EPSG:4326",
        "longitude_of_prime_meridian": 0.0, "semi_major_axis": 6378137.0,
        "inverse_flattening": 298.257223563}


def gebco_axis_deg(first_deg: float, last_deg: float, per_degree: int = 240) -> np.ndarray:
    """GEBCO cell centres between two edges, deg: (k + 1/2) / per_degree."""
    k0 = int(round(first_deg * per_degree))
    k1 = int(round(last_deg * per_degree))
    return (np.arange(k0, k1) + 0.5) / per_degree


def write_gebco(path: str | Path, lat_deg, lon_deg, elevation_m, *, title: str,
                variable: str = "elevation") -> None:
    """Write ``elevation(lat, lon)`` in GEBCO's layout (values rounded to int16 metres)."""
    import netCDF4

    lat = np.asarray(lat_deg, dtype=float)
    lon = np.asarray(lon_deg, dtype=float)
    z = np.asarray(elevation_m, dtype=float)
    with netCDF4.Dataset(path, "w", format="NETCDF4_CLASSIC") as nc:
        nc.setncatts({"Conventions": "CF-1.6", "title": title,
                      "institution": "tmakit (synthetic sample data in the layout of the GEBCO grid)",
                      "source": "tools/make_sample_data.py", "node_offset": np.int32(1)})
        nc.createDimension("lat", lat.size)
        nc.createDimension("lon", lon.size)
        crs = nc.createVariable("crs", "i4")
        crs.setncatts(_CRS)
        v = nc.createVariable("lat", "f8", ("lat",))
        v.setncatts({"standard_name": "latitude", "long_name": "latitude", "units": "degrees_north",
                     "axis": "Y", "sdn_parameter_urn": "SDN:P01::ALATZZ01",
                     "sdn_parameter_name": "Latitude north", "sdn_uom_urn": "SDN:P06::DEGN",
                     "sdn_uom_name": "Degrees north"})
        v[:] = lat
        v = nc.createVariable("lon", "f8", ("lon",))
        v.setncatts({"standard_name": "longitude", "long_name": "longitude", "units": "degrees_east",
                     "axis": "X", "sdn_parameter_urn": "SDN:P01::ALONZZ01",
                     "sdn_parameter_name": "Longitude east", "sdn_uom_urn": "SDN:P06::DEGE",
                     "sdn_uom_name": "Degrees east"})
        v[:] = lon
        v = nc.createVariable(variable, "i2", ("lat", "lon"), zlib=True, complevel=9, shuffle=True,
                              chunksizes=(min(lat.size, 240), min(lon.size, 240)))
        v.setncatts({"standard_name": "height_above_reference_ellipsoid",
                     "long_name": "Elevation relative to sea level", "units": "m",
                     "sdn_parameter_urn": "SDN:P01::BATHHGHT",
                     "sdn_parameter_name": "Sea floor height (above mean sea level) {bathymetric height}",
                     "sdn_uom_urn": "SDN:P06::ULAA", "sdn_uom_name": "Metres", "grid_mapping": "crs"})
        v[:, :] = np.clip(np.round(z), -32767, 32767).astype(np.int16)


#: EMODnet Bathymetry DTM cells: 1/16 arc-minute, centres at (k + 1/2)/960 deg.
EMODNET_PER_DEGREE = 960
#: The fill value of the EMODnet-layout files written here (land and cells without data).
EMODNET_FILL = np.float32(-9999.0)


def write_emodnet(path: str | Path, lat_deg, lon_deg, elevation_m, *, title: str, positive: str = "up",
                  fill: str = "_FillValue", lat_name: str = "lat", lon_name: str = "lon") -> None:
    """Write a DTM in the layout of EMODnet Bathymetry's netCDF tiles: no value on land.

    ``elevation(lat, lon)`` float32, m relative to Lowest Astronomical Tide, negative at sea, with
    the product's companions (``elevation_min``, ``elevation_max``, ``stdev``, ``value_count``,
    ``interpolation_flag``; the min and max written 50 m off the mean, so that a reader that
    picks them is caught), on double ``lat``/``lon`` cell centres and a ``crs`` variable.

    Parameters
    ----------
    elevation_m : array_like, shape (lat, lon)
        m, positive up; NaN where the cell has no value (land, or no data).
    positive : {"up", "down"}
        "down" writes ``depth`` (positive down, standard_name
        ``sea_floor_depth_below_sea_surface``) instead of ``elevation``, as some DTM exports do.
    fill : {"_FillValue", "missing_value", "nan"}
        How the cells with no value are marked: `EMODNET_FILL` declared by either attribute, or
        NaN with no attribute at all (a file another tool wrote).
    lat_name, lon_name : str
        The coordinate names (EMODnet's ERDDAP serves ``latitude``/``longitude``).
    """
    import netCDF4

    lat = np.asarray(lat_deg, dtype=float)
    lon = np.asarray(lon_deg, dtype=float)
    z = np.asarray(elevation_m, dtype=float)
    if positive not in ("up", "down"):
        raise ValueError(f"positive must be 'up' or 'down', got {positive!r}")
    if fill not in ("_FillValue", "missing_value", "nan"):
        raise ValueError(f"fill must be '_FillValue', 'missing_value' or 'nan', got {fill!r}")
    sign = 1.0 if positive == "up" else -1.0
    with netCDF4.Dataset(path, "w", format="NETCDF4") as nc:
        nc.setncatts({"Conventions": "CF-1.8", "title": title,
                      "institution": "tmakit (synthetic sample data in the layout of EMODnet Bathymetry's "
                                     "DTM netCDF tiles, not EMODnet data)",
                      "source": "tools/sample_layouts.py", "vertical_datum": "Lowest Astronomical Tide"})
        nc.createDimension(lat_name, lat.size)
        nc.createDimension(lon_name, lon.size)
        crs = nc.createVariable("crs", "i4")
        crs.setncatts(_CRS)
        for name, centres, axis in ((lat_name, lat, "Y"), (lon_name, lon, "X")):
            v = nc.createVariable(name, "f8", (name,))
            v.setncatts({"standard_name": "latitude" if axis == "Y" else "longitude",
                         "long_name": "latitude" if axis == "Y" else "longitude",
                         "units": "degrees_north" if axis == "Y" else "degrees_east", "axis": axis})
            v[:] = centres
        dims = (lat_name, lon_name)

        def values(offset: float) -> np.ndarray:
            out = sign * (z + offset)
            if fill == "nan":
                return out.astype(np.float32)
            return np.where(np.isfinite(out), out, EMODNET_FILL).astype(np.float32)

        def variable(name: str, attrs: dict, data: np.ndarray, dtype: str = "f4") -> None:
            kwargs = {"fill_value": EMODNET_FILL} if fill == "_FillValue" and dtype == "f4" else {"fill_value": False}
            v = nc.createVariable(name, dtype, dims, zlib=True, complevel=4, **kwargs)
            if fill == "missing_value" and dtype == "f4":
                attrs = {**attrs, "missing_value": EMODNET_FILL}
            v.setncatts({**attrs, "grid_mapping": "crs"})
            v[:, :] = data

        main = "elevation" if positive == "up" else "depth"
        standard = ("height_above_mean_sea_level" if positive == "up"
                    else "sea_floor_depth_below_sea_surface")
        variable(main, {"standard_name": standard, "long_name": "Average water depth relative to LAT",
                        "units": "m", "positive": positive}, values(0.0))
        for name, offset, long_name in (("elevation_min", -50.0, "Minimum"), ("elevation_max", 50.0, "Maximum")):
            variable(f"{main}_{name.split('_')[1]}" if positive == "down" else name,
                     {"long_name": f"{long_name} water depth relative to LAT", "units": "m", "positive": positive},
                     values(offset))
        variable("stdev", {"long_name": "Standard deviation of water depth in the cell", "units": "m"},
                 np.where(np.isfinite(z), 1.5, EMODNET_FILL if fill != "nan" else np.nan).astype(np.float32))
        variable("value_count", {"long_name": "Number of values used for interpolation over the cell"},
                 np.where(np.isfinite(z), 3, 0).astype(np.int32), dtype="i4")
        variable("interpolation_flag", {"long_name": "Interpolation flag (1: extrapolated cell)"},
                 np.zeros(z.shape, dtype=np.int8), dtype="i1")


def _bounds(centres: np.ndarray, first_edge: float | None = None) -> np.ndarray:
    mids = 0.5 * (centres[1:] + centres[:-1])
    lo = np.concatenate([[centres[0] - (mids[0] - centres[0]) if first_edge is None else first_edge], mids])
    hi = np.concatenate([mids, [centres[-1] + (centres[-1] - mids[-1])]])
    return np.stack([lo, hi], axis=1)


def write_woa(path: str | Path, kind: str, months, depth_m, lat_deg, lon_deg, values, *, title: str,
              mean_offset: float = 0.0, sd_values=None) -> None:
    """Write one WOA variable file.

    Parameters
    ----------
    kind : {"t", "s"}
        Temperature (``t_an``, degC) or salinity (``s_an``, practical salinity).
    months : sequence of int
        The month of each time step (1..12); WOA's own monthly files have one.
    depth_m, lat_deg, lon_deg : array_like
        Levels and cell centres (WOA's 0.25-deg grid has centres at k/4 + 1/8 deg).
    values : array_like, shape (time, depth, lat, lon)
        NaN where the cell has no water (written as the fill value).
    mean_offset : float
        ``{kind}_mn`` (the statistical mean WOA also ships) is written as ``values`` plus this,
        so that a reader that picks it instead of ``{kind}_an`` is caught.
    sd_values : array_like, optional
        ``{kind}_sd``, the standard deviation WOA ships beside the means (same shape; NaN: none).
    """
    import netCDF4

    months = [int(m) for m in months]
    depth = np.asarray(depth_m, dtype=float)
    lat = np.asarray(lat_deg, dtype=float)
    lon = np.asarray(lon_deg, dtype=float)
    data = np.asarray(values, dtype=float)
    if kind == "t":
        std, units, name = "sea_water_temperature", "degrees_celsius", "sea_water_temperature"
    elif kind == "s":
        std, units, name = "sea_water_salinity", "1", "sea_water_salinity"
    else:
        raise ValueError(f"kind must be 't' or 's', got {kind!r}")
    with netCDF4.Dataset(path, "w", format="NETCDF4_CLASSIC") as nc:
        nc.setncatts({"Conventions": "CF-1.6, ACDD-1.3", "title": title,
                      "summary": "Synthetic fields in the layout of the World Ocean Atlas 2023 monthly "
                                 "0.25-degree files, written by tools/make_sample_data.py",
                      "institution": "tmakit (synthetic sample data, not World Ocean Atlas data)",
                      "geospatial_lat_resolution": "0.25 degrees",
                      "geospatial_lon_resolution": "0.25 degrees"})
        for dim, size in (("time", len(months)), ("nbounds", 2), ("depth", depth.size),
                          ("lat", lat.size), ("lon", lon.size)):
            nc.createDimension(dim, size)
        crs = nc.createVariable("crs", "i4")
        crs.setncatts(_CRS)
        for axis_name, centres, unit, axis in (("lat", lat, "degrees_north", "Y"),
                                               ("lon", lon, "degrees_east", "X")):
            v = nc.createVariable(axis_name, "f4", (axis_name,))
            v.setncatts({"standard_name": "latitude" if axis == "Y" else "longitude",
                         "long_name": "latitude" if axis == "Y" else "longitude",
                         "units": unit, "axis": axis, "bounds": f"{axis_name}_bnds"})
            v[:] = centres
            b = nc.createVariable(f"{axis_name}_bnds", "f4", (axis_name, "nbounds"))
            b.setncatts({"comment": f"{axis_name} bounds"})
            b[:, :] = np.stack([centres - 0.125, centres + 0.125], axis=1)
        v = nc.createVariable("depth", "f4", ("depth",))
        v.setncatts({"standard_name": "depth", "bounds": "depth_bnds", "positive": "down",
                     "units": "meters", "axis": "Z"})
        v[:] = depth
        b = nc.createVariable("depth_bnds", "f4", ("depth", "nbounds"))
        b.setncatts({"comment": "depth bounds"})
        b[:, :] = _bounds(depth, first_edge=0.0)
        v = nc.createVariable("time", "f4", ("time",))
        v.setncatts({"standard_name": "time", "long_name": "time", "units": WOA_TIME_UNITS, "axis": "T",
                     "climatology": "climatology_bounds"})
        v[:] = [395.5 + m for m in months]
        b = nc.createVariable("climatology_bounds", "f4", ("time", "nbounds"))
        b.setncatts({"comment": "This variable defines the bounds of the climatological time period for "
                                "each time"})
        b[:, :] = [[m - 1.0, 804.0 + m] for m in months]
        for suffix, offset, long_name in (
                ("an", 0.0, f"Objectively analyzed mean fields for {name} at standard depth levels."),
                ("mn", mean_offset, f"Average of all unflagged interpolated values at each standard depth "
                                    f"level for {name} in each grid-square which contain at least one "
                                    f"measurement.")):
            v = nc.createVariable(f"{kind}_{suffix}", "f4", ("time", "depth", "lat", "lon"), zlib=True,
                                  complevel=9, shuffle=True, fill_value=WOA_FILL)
            v.setncatts({"standard_name": std, "long_name": long_name,
                         "cell_methods": "area: mean depth: mean time: mean within years time: mean over years",
                         "grid_mapping": "crs", "units": units})
            field = data + offset
            v[:, :, :, :] = np.where(np.isfinite(field), field, WOA_FILL).astype(np.float32)
        if sd_values is not None:
            v = nc.createVariable(f"{kind}_sd", "f4", ("time", "depth", "lat", "lon"), zlib=True,
                                  complevel=9, shuffle=True, fill_value=WOA_FILL)
            v.setncatts({"standard_name": std,
                         "long_name": f"The standard deviation about the statistical mean of {name} in "
                                      f"each grid-square at each standard depth level.",
                         "cell_methods": "area: mean depth: mean time: mean within years time: "
                                         "standard_deviation over years",
                         "grid_mapping": "crs", "units": units})
            sd = np.asarray(sd_values, dtype=float)
            v[:, :, :, :] = np.where(np.isfinite(sd), sd, WOA_FILL).astype(np.float32)


#: Sea-Bird's bad_flag: a missing or bad value, and the ``flag`` of a scan Loop Edit marks bad.
SEABIRD_BAD_FLAG = -9.990e-29
#: The .cnv columns these files can hold: Sea-Bird's short name -> (its long name and unit, the
#: format of its values); ``{lat}`` is the latitude depth was computed at.
SEABIRD_COLUMNS = {
    "prDM": ("Pressure, Digiquartz [db]", "{:11.3f}"),
    "depSM": ("Depth [salt water, m], lat = {lat:.2f}", "{:11.3f}"),
    "t090C": ("Temperature [ITS-90, deg C]", "{:11.4f}"),
    "t068C": ("Temperature [IPTS-68, deg C]", "{:11.4f}"),
    "sal00": ("Salinity, Practical [PSU]", "{:11.4f}"),
    "timeS": ("Time, Elapsed [seconds]", "{:11.3f}"),
    "flag": (" 0.000e+00", "{:11.3e}"),  # Sea-Bird writes "flag:  0.000e+00"
}


def _nmea_position(value_deg: float, hemispheres: str, width: int) -> str:
    hemisphere = hemispheres[0] if value_deg >= 0.0 else hemispheres[1]
    degrees, minutes = divmod(round(abs(value_deg) * 60.0, 2), 60.0)  # "43 00.00 N"
    return f"{int(degrees):0{width}d} {minutes:05.2f} {hemisphere}"


def write_cnv(path: str | Path, columns: dict, *, latitude_deg: float, longitude_deg: float,
              start: datetime.datetime, interval: str, station: str, bin_size_m: float | None = None,
              names: dict[str, str] | None = None) -> Path:
    """Write a CTD cast in Sea-Bird's ``.cnv`` layout (ASCII, Windows line ends).

    Parameters
    ----------
    columns : dict
        Sea-Bird short name (a key of `SEABIRD_COLUMNS`) -> values, one per scan, in column order;
        `SEABIRD_BAD_FLAG` is written as Sea-Bird writes it. No rows: the header alone.
    latitude_deg, longitude_deg : float
        The NMEA position of the header (and the latitude of ``depSM``'s name line).
    start : datetime
        The time of the first scan (UTC).
    interval : str
        Sea-Bird's ``# interval`` value: ``"seconds: 0.25"`` for scans, ``"meters: 5"`` when binned.
    station : str
        The ``** Station:`` line.
    bin_size_m : float, optional
        Write the ``binavg_*`` lines of a file binned by depth.
    names : dict, optional
        Short name -> the name written in its ``# name`` line instead (a file with another column).
    """
    path = Path(path)
    names = names or {}
    data = {name: np.asarray(values, dtype=float) for name, values in columns.items()}
    rows = len(next(iter(data.values()))) if data else 0
    stamp = start.strftime("%b %d %Y %H:%M:%S")
    lines = ["* Sea-Bird SBE 9 Data File:",
             f"* FileName = C:\\SBE\\data\\{path.stem}.hex",
             "* Software Version Seasave V 7.26.7.107",
             "* Temperature SN = 0000",
             "* Conductivity SN = 0000",
             f"* System UpLoad Time = {stamp}",
             f"* NMEA Latitude = {_nmea_position(latitude_deg, 'NS', 2)}",
             f"* NMEA Longitude = {_nmea_position(longitude_deg, 'EW', 3)}",
             f"* NMEA UTC (Time) = {stamp}",
             "* Store Lat/Lon Data = Append to Every Scan",
             "** Ship: synthetic (tmakit sample data, not a real cast)",
             f"** Station: {station}",
             f"* System UTC = {stamp}",
             f"# nquan = {len(data)}",
             f"# nvalues = {rows}",
             "# units = specified"]
    for k, name in enumerate(data):
        long_name = SEABIRD_COLUMNS[name][0].format(lat=latitude_deg)
        lines.append(f"# name {k} = {names.get(name, name)}: {long_name}")
    for k, (name, values) in enumerate(data.items()):
        good = values[values != SEABIRD_BAD_FLAG]
        if name == "flag" or not good.size:
            lines.append(f"# span {k} = {0.0:.4e}, {0.0:.4e}")
        else:
            fmt = SEABIRD_COLUMNS[name][1]
            lines.append(f"# span {k} = {fmt.format(good.min())}, {fmt.format(good.max())}")
    lines += [f"# interval = {interval}",
              f"# start_time = {stamp} [System UTC, first data scan.]",
              f"# bad_flag = {SEABIRD_BAD_FLAG:.3e}",
              f"# datcnv_date = {stamp}, 7.26.7.129",
              f"# datcnv_in = C:\\SBE\\data\\{path.stem}.hex C:\\SBE\\data\\{path.stem}.XMLCON",
              "# datcnv_skipover = 0"]
    if bin_size_m is not None:
        lines += [f"# binavg_date = {stamp}, 7.26.7.129",
                  "# binavg_bintype = meters",
                  f"# binavg_binsize = {bin_size_m:g}",
                  "# binavg_excl_bad_scans = yes",
                  "# binavg_skipover = 0",
                  "# binavg_surface_bin = no, min = 0.000, max = 0.000, value = 0.000"]
    lines += ["# file_type = ascii", "*END*"]
    formats = [SEABIRD_COLUMNS[name][1] for name in data]
    for i in range(rows):
        lines.append("".join(f"{SEABIRD_BAD_FLAG:11.3e}" if values[i] == SEABIRD_BAD_FLAG else fmt.format(values[i])
                             for fmt, values in zip(formats, data.values())))
    with open(path, "w", encoding="ascii", newline="\r\n") as fh:
        fh.write("\n".join(lines) + "\n")
    return path
