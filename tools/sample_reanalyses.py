"""Write netCDF files in the layouts of ocean reanalyses (sample and test data).

The layouts (names, dtypes, attributes, packing, time axes) are those the products are
downloaded in, so that tmakit's climatology reader is exercised on them; the values are whatever
the caller gives. Every file says in its title and ``institution`` that its values are
synthetic, not the product's.

- Copernicus Marine (GLORYS12, MEDSEA, IBI; `write_cmems`): ``thetao`` (potential temperature,
  ``degrees_C``) and ``so`` (practical salinity, units ``1e-3``) on (time, depth, latitude,
  longitude), float32 with ``_FillValue`` (or, as the older MOTU downloads, int16 packed with
  ``scale_factor``/``add_offset``), float32 ``latitude``/``longitude``, ``depth`` positive down,
  ``time`` in "hours since 1950-01-01" (gregorian). MEDSEA ships temperature and salinity as two
  datasets: write each alone. Other kinds on request: ``bigthetao`` (Conservative Temperature),
  ``absso`` (Absolute Salinity, g kg-1), in-situ temperature, kelvin.
- HYCOM GOFS 3.1 (`write_hycom`): ``water_temp`` (in-situ, degC) and ``salinity`` (psu) on (time,
  depth, lat, lon), int16 packed (scale 0.001, offset 20, ``_FillValue`` -30000), double
  ``lat``/``lon`` (longitudes 0..360), ``time`` in "hours since 2000-01-01 00:00:00".
"""

from __future__ import annotations

import datetime
from pathlib import Path

import numpy as np

#: GLORYS12's first depth levels, m (50 levels to 5728 m; the first 33 reach 1062 m).
GLORYS_LEVELS_M = np.array([0.494, 1.541, 2.646, 3.819, 5.078, 6.441, 7.93, 9.573, 11.405, 13.467, 15.81,
                            18.496, 21.599, 25.211, 29.445, 34.434, 40.344, 47.374, 55.764, 65.807, 77.854,
                            92.326, 109.729, 130.666, 155.851, 186.126, 222.475, 266.04, 318.127, 380.213,
                            453.938, 541.089, 643.567, 763.333, 902.339, 1062.44, 1245.291, 1452.251,
                            1684.284, 1941.893, 2225.078, 2533.336, 2865.703, 3220.82, 3597.032, 3992.484,
                            4405.224, 4833.291, 5274.784, 5727.917], dtype=float)
CMEMS_FILL = np.float32(9.96921e36)
CMEMS_TIME_UNITS = "hours since 1950-01-01"
HYCOM_TIME_UNITS = "hours since 2000-01-01 00:00:00"
HYCOM_FILL = np.int16(-30000)

#: kind -> (default name, standard_name, long_name, units)
_TEMPERATURE = {"potential": ("thetao", "sea_water_potential_temperature", "Temperature", "degrees_C"),
                "conservative": ("bigthetao", "sea_water_conservative_temperature", "Conservative Temperature",
                                 "degrees_C"),
                "in-situ": ("to", "sea_water_temperature", "In-situ temperature", "degrees_C")}
_SALINITY = {"practical": ("so", "sea_water_salinity", "Salinity", "1e-3"),
             "absolute": ("absso", "sea_water_absolute_salinity", "Absolute Salinity", "g kg-1")}


def _times(times, units: str) -> np.ndarray:
    import cftime

    return np.asarray(cftime.date2num(list(times), units, calendar="gregorian"), dtype=float)


def _packed(nc, name: str, dims, values: np.ndarray, *, scale: float, offset: float, fill: np.int16,
            attrs: dict) -> None:
    v = nc.createVariable(name, "i2", dims, zlib=True, complevel=4, fill_value=fill)
    v.setncatts({**attrs, "scale_factor": np.float32(scale), "add_offset": np.float32(offset)})
    v.set_auto_maskandscale(False)
    packed = np.round((values - offset) / scale)
    v[...] = np.where(np.isfinite(values), packed, fill).astype(np.int16)


def write_cmems(path: str | Path, times, depth_m, lat_deg, lon_deg, *, title: str, temperature=None,
                salinity=None, temperature_kind: str = "potential", salinity_kind: str = "practical",
                temperature_units: str = "degrees_C", names: dict[str, str] | None = None,
                packed: bool = False, standard_names: bool = True) -> Path:
    """Write a Copernicus Marine physics file (GLORYS12 / MEDSEA layout).

    Parameters
    ----------
    times : sequence of datetime.datetime
        One per time step (monthly means are stamped mid-month, daily ones at 12:00... as given).
    depth_m, lat_deg, lon_deg : array_like
        Levels (m, positive down) and cell centres, deg.
    temperature, salinity : array_like, shape (time, depth, lat, lon), optional
        Values in the kind's units (``temperature_units``; Absolute Salinity in g/kg); NaN where the
        cell has no water. Either may be left out (MEDSEA's split datasets).
    temperature_kind : {"potential", "conservative", "in-situ"}
    salinity_kind : {"practical", "absolute"}
    temperature_units : str
        "degrees_C" as Copernicus writes it, or "K" (values then in kelvin).
    names : dict, optional
        "temperature"/"salinity" -> a variable name other than the kind's usual one.
    packed : bool
        int16 with ``scale_factor``/``add_offset`` (the older MOTU downloads) instead of float32.
    standard_names : bool
        False leaves the ``standard_name`` attributes out (a file another tool rewrote).
    """
    import netCDF4

    depth = np.asarray(depth_m, dtype=float)
    lat = np.asarray(lat_deg, dtype=float)
    lon = np.asarray(lon_deg, dtype=float)
    names = names or {}
    with netCDF4.Dataset(path, "w", format="NETCDF4") as nc:
        nc.setncatts({"Conventions": "CF-1.0", "title": f"{title} (synthetic values, not Copernicus Marine data)",
                      "institution": "tmakit (synthetic sample data in the layout of Copernicus Marine "
                                     "physics reanalyses; the values are made up)",
                      "source": "tools/sample_reanalyses.py", "references": "http://marine.copernicus.eu",
                      "product_user_manual": "not applicable: synthetic"})
        for dim, size in (("time", len(times)), ("depth", depth.size), ("latitude", lat.size),
                          ("longitude", lon.size)):
            nc.createDimension(dim, size)
        v = nc.createVariable("time", "f8", ("time",))
        v.setncatts({"standard_name": "time", "long_name": "Time (hours since 1950-01-01)",
                     "units": CMEMS_TIME_UNITS, "calendar": "gregorian", "axis": "T"})
        v[:] = _times(times, CMEMS_TIME_UNITS)
        v = nc.createVariable("depth", "f4", ("depth",))
        v.setncatts({"standard_name": "depth", "long_name": "Depth", "units": "m", "positive": "down",
                     "axis": "Z", "unit_long": "Meters"})
        v[:] = depth
        for name, centres, axis in (("latitude", lat, "Y"), ("longitude", lon, "X")):
            v = nc.createVariable(name, "f4", (name,))
            v.setncatts({"standard_name": name, "long_name": name.capitalize(),
                         "units": "degrees_north" if axis == "Y" else "degrees_east", "axis": axis,
                         "step": np.float32(np.median(np.diff(centres)) if centres.size > 1 else 0.0)})
            v[:] = centres
        dims = ("time", "depth", "latitude", "longitude")
        for role, values, table, kind in (("temperature", temperature, _TEMPERATURE, temperature_kind),
                                          ("salinity", salinity, _SALINITY, salinity_kind)):
            if values is None:
                continue
            default, std, long_name, units = table[kind]
            if role == "temperature":
                units = temperature_units
            attrs = {"long_name": long_name, "units": units, "cell_methods": "area: mean",
                     "unit_long": "Degrees Celsius" if units == "degrees_C" else units}
            if standard_names:
                attrs["standard_name"] = std
            data = np.asarray(values, dtype=float)
            name = names.get(role, default)
            if packed:
                offset = 21.0 if role == "temperature" and units == "degrees_C" else (
                    290.0 if role == "temperature" else 20.0)
                _packed(nc, name, dims, data, scale=0.000732444, offset=offset, fill=np.int16(-32767),
                        attrs=attrs)
            else:
                v = nc.createVariable(name, "f4", dims, zlib=True, complevel=4, fill_value=CMEMS_FILL)
                v.setncatts(attrs)
                v[...] = np.where(np.isfinite(data), data, CMEMS_FILL).astype(np.float32)
    return Path(path)


def write_hycom(path: str | Path, times, depth_m, lat_deg, lon_deg, *, title: str, temperature,
                salinity) -> Path:
    """Write a HYCOM GOFS 3.1 file (in-situ ``water_temp``, ``salinity``; int16 packed; lon 0..360).

    ``temperature`` (in-situ, degC) and ``salinity`` (psu) have shape (time, depth, lat, lon), NaN
    where there is no water; ``lon_deg`` in 0..360 as HYCOM's global grid stores them.
    """
    import netCDF4

    depth = np.asarray(depth_m, dtype=float)
    lat = np.asarray(lat_deg, dtype=float)
    lon = np.asarray(lon_deg, dtype=float)
    with netCDF4.Dataset(path, "w", format="NETCDF4_CLASSIC") as nc:
        nc.setncatts({"Conventions": "CF-1.0", "title": f"{title} (synthetic values, not HYCOM data)",
                      "institution": "tmakit (synthetic sample data in the layout of HYCOM GOFS 3.1; the "
                                     "values are made up)",
                      "source": "tools/sample_reanalyses.py", "experiment": "93.0"})
        for dim, size in (("time", len(times)), ("depth", depth.size), ("lat", lat.size), ("lon", lon.size)):
            nc.createDimension(dim, size)
        v = nc.createVariable("time", "f8", ("time",))
        v.setncatts({"long_name": "Valid Time", "units": HYCOM_TIME_UNITS, "time_origin": "2000-01-01 00:00:00",
                     "calendar": "gregorian", "axis": "T"})
        v[:] = _times(times, HYCOM_TIME_UNITS)
        v = nc.createVariable("depth", "f8", ("depth",))
        v.setncatts({"long_name": "Depth", "standard_name": "depth", "units": "m", "positive": "down",
                     "axis": "Z"})
        v[:] = depth
        for name, centres, axis in (("lat", lat, "Y"), ("lon", lon, "X")):
            v = nc.createVariable(name, "f8", (name,))
            v.setncatts({"long_name": "Latitude" if axis == "Y" else "Longitude",
                         "standard_name": "latitude" if axis == "Y" else "longitude",
                         "units": "degrees_north" if axis == "Y" else "degrees_east", "axis": axis})
            v[:] = centres
        dims = ("time", "depth", "lat", "lon")
        _packed(nc, "water_temp", dims, np.asarray(temperature, dtype=float), scale=0.001, offset=20.0,
                fill=HYCOM_FILL, attrs={"long_name": "Water Temperature", "standard_name": "sea_water_temperature",
                                        "units": "degC", "NAVO_code": np.int32(15)})
        _packed(nc, "salinity", dims, np.asarray(salinity, dtype=float), scale=0.001, offset=20.0,
                fill=HYCOM_FILL, attrs={"long_name": "Salinity", "standard_name": "sea_water_salinity",
                                        "units": "psu", "NAVO_code": np.int32(16)})
    return Path(path)


def monthly_times(first: datetime.date, count: int) -> list[datetime.datetime]:
    """Mid-month stamps of ``count`` months from ``first``'s month (as monthly means are stamped)."""
    out = []
    year, month = first.year, first.month
    for _ in range(count):
        out.append(datetime.datetime(year, month, 16, 12, 0, 0) if month != 2 else datetime.datetime(year, 2, 15))
        year, month = (year + 1, 1) if month == 12 else (year, month + 1)
    return out
