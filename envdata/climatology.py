"""Climatologies and ocean reanalyses: T and S on (time, depth, lat, lon).

The World Ocean Atlas' netCDF files hold the objectively analysed in-situ temperature ``t_an``
(degC) and practical salinity ``s_an`` on standard depth levels (``depth``, m, positive down) at
cell centres (``lat``, ``lon``), float32 with a large ``_FillValue`` below the sea floor and on
land, and beside them their statistics, among which the standard deviations ``t_sd`` and ``s_sd``
(read here where present, for sensitivity studies). Their ``time`` axis ("months since
1955-01-01") cannot be decoded. WOA ships one file per variable and month
(``woa23_decav_t08_04.nc`` and ``..._s08_04.nc``: one time step, 57 levels to 1500 m for a month,
deeper for the annual and seasonal fields); a file may also hold both variables, and 12 time
steps of which ``[water] month`` picks one.

Ocean reanalyses and models (Copernicus Marine's GLORYS12 and MEDSEA, HYCOM, NEMO) use other
names and quantities: ``thetao`` (potential temperature), ``so`` (practical salinity),
``water_temp``/``salinity`` (HYCOM, in-situ), on ``latitude``/``longitude``, often with a decodable
time axis. Variables are found by a given name (``[water] temperature_variable`` /
``salinity_variable``), else by the common names (``envdata.climvariable``'s `TEMPERATURE_NAMES`,
`SALINITY_NAMES`), else by CF ``standard_name`` (in-situ first where several kinds are there). What a variable holds is
told by its ``standard_name``, else its name (``thetao`` is potential temperature), else its
``long_name`` ("potential", "conservative", "absolute"), else in-situ temperature and practical
salinity. Potential and Conservative Temperature and Absolute Salinity are converted to in-situ
temperature and practical salinity with TEOS-10 at each cell's pressure and position
(``envdata.seawater.in_situ_ts``) before anything else; temperatures in kelvin are converted to
degC.

Time: a file with one time step is used as it is. With more, ``[water] month`` picks: where the
time axis decodes (CF "... since ..." units), the steps that fall in that calendar month
(several: their mean); where it does not (WOA), the month-th of 12 steps.

Each column (one lat/lon cell) is filled down: where it stops above the sea floor its deepest
valid T and S continue down (and, should its top levels be missing, its shallowest valid values
continue up). Across columns, T and S are interpolated bilinearly in latitude and longitude with
the weights of the valid (wet) columns renormalised; a position with no valid column around it
takes the nearest valid one.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from envdata.climvariable import ClimVariable, check_same_grid
from envdata.datafiles import ClimatologySource
from envdata.errors import AreaError
from envdata.geogrid import (
    LatLonAxes,
    bilinear_corners,
    distance_m,
    units_of,
)
from envdata.seawater import SalinityKind, TemperatureKind, in_situ_ts

#: Where the temperature and salinity of sea water lie, in their units after conversion.
TEMPERATURE_RANGE_C = (-2.5, 40.0)
SALINITY_RANGE = (0.0, 42.0)
#: Cells beyond the box of the positions loaded on each side (bilinear neighbours and the
#: nearest valid column for positions among land cells).
MARGIN_CELLS = 3


@dataclass(frozen=True, eq=False)
class TsField:
    """A box of a climatology in memory: T and S filled down each column, on increasing axes."""

    path: Path
    depth_m: np.ndarray  # (Z,) increasing levels
    lat_deg: np.ndarray  # (ny,)
    lon_deg: np.ndarray  # (nx,) in the file's longitude convention
    temperature_c: np.ndarray  # (Z, ny, nx), in-situ, filled down; NaN in columns with no data
    salinity_psu: np.ndarray  # (Z, ny, nx), practical salinity, filled down likewise
    axes: LatLonAxes
    #: (Z, ny, nx) standard deviations of T (degC) and S where the file has them (WOA's t_sd,
    #: s_sd), filled down like T and S; NaN in wet columns without them; None: not in the file.
    temperature_sd_c: np.ndarray | None = None
    salinity_sd_psu: np.ndarray | None = None

    @property
    def valid(self) -> np.ndarray:
        """(ny, nx) True where a column has T and S (a wet cell)."""
        return np.isfinite(self.temperature_c[0]) & np.isfinite(self.salinity_psu[0])

    def columns_at(self, lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
        """T and S columns at positions, interpolated bilinearly across the valid columns.

        Parameters
        ----------
        lat_deg, lon_deg : array_like, shape (M,)

        Returns
        -------
        temperature_c, salinity_psu : ndarray, shape (Z, M)
            At the file's levels ``depth_m``. The four columns around a position are weighted
            bilinearly; the weights of those without data are dropped and the rest renormalised;
            with none valid around it the position takes the nearest valid column.

        Raises
        ------
        AreaError
            No valid column at all in the loaded box.
        """
        lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
        lon = self.axes.file_lon(np.atleast_1d(lon_deg))
        valid = self.valid
        if not valid.any():
            raise AreaError(f"{self.path}: no water (no valid temperature and salinity) in the "
                            f"cells around {lat[0]:.4f} N {lon[0]:.4f} E")
        iy, ix, w = bilinear_corners(self.lat_deg, self.lon_deg, lat, lon)
        w = np.where(valid[iy, ix], w, 0.0)
        total = w.sum(axis=1)
        for m in np.flatnonzero(total <= 0.0):  # nothing valid around it: the nearest valid column
            vy, vx = np.nonzero(valid)
            d = distance_m(lat[m], lon[m], self.lat_deg[vy], self.lon_deg[vx])
            k = int(np.argmin(d))
            iy[m], ix[m], w[m] = vy[k], vx[k], [1.0, 0.0, 0.0, 0.0]
        w = w / w.sum(axis=1, keepdims=True)

        def mix(field: np.ndarray) -> np.ndarray:
            cols = field[:, iy, ix]  # (Z, M, 4)
            return np.sum(np.where(w > 0, cols, 0.0) * w, axis=2)

        return mix(self.temperature_c), mix(self.salinity_psu)


class ClimatologyFiles:
    """An open climatology (one file, or WOA's temperature and salinity pair), read lazily.

    Use as a context manager.

    Raises
    ------
    AreaError
        A file missing or not netCDF, a variable missing, of the wrong kind or units, a time axis
        that is neither 1 nor 12 steps (or 12 without a month), or two files on different grids.
    """

    def __init__(self, source: ClimatologySource):
        self.source = source
        self._open: list = []
        try:
            self.temperature = ClimVariable.open(source.temperature, "temperature", source.month, self._open,
                                              given=source.temperature_variable)
            self.salinity = ClimVariable.open(source.salinity, "salinity", source.month, self._open,
                                           given=source.salinity_variable)
            check_same_grid(self.temperature, self.salinity)
        except BaseException:
            self.close()
            raise
        self.axes = self.temperature.axes
        self.path = self.temperature.path

    def __enter__(self) -> "ClimatologyFiles":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        for ds in self._open:
            ds.close()
        self._open.clear()

    @property
    def depth_m(self) -> np.ndarray:
        """The file's depth levels, m, increasing."""
        return self.temperature.depth_sorted

    def describe(self) -> str:
        paths = sorted({str(self.temperature.path), str(self.salinity.path)})
        return f"{' and '.join(paths)} ({self.axes.describe()})"

    @property
    def has_sd(self) -> bool:
        """Whether both files carry standard deviations beside the means (WOA's t_sd, s_sd)."""
        return self.temperature.sd_var is not None and self.salinity.sd_var is not None

    @property
    def has_months(self) -> bool:
        """Whether the files hold several months, one of which ``[water] month`` picked."""
        return all(v.time_dim is not None and int(v.var.sizes[v.time_dim]) > 1
                   for v in (self.temperature, self.salinity))

    @property
    def temperature_kind(self) -> TemperatureKind:
        """What the file's temperature is (converted to in-situ on loading)."""
        return self.temperature.kind

    @property
    def salinity_kind(self) -> SalinityKind:
        """What the file's salinity is (converted to practical on loading)."""
        return self.salinity.kind

    def load_box(self, lat_deg, lon_deg) -> TsField:
        """Load T and S around the positions (a margin of `MARGIN_CELLS` cells), filled down.

        Raises
        ------
        AreaError
            A position outside the files' cells, or T or S outside the sea's range.
        """
        lat_slice, lon_slice, lat_flip, lon_flip = self.axes.box_inside(self.path, lat_deg, lon_deg, MARGIN_CELLS,
                                                                        "the climatology")
        box = (lat_slice, lon_slice, lat_flip, lon_flip)
        t = self.temperature.load(*box)
        s = self.salinity.load(*box)
        for field, lo_hi, var in ((t, TEMPERATURE_RANGE_C, self.temperature), (s, SALINITY_RANGE, self.salinity)):
            lo, hi = lo_hi
            bad = np.isfinite(field) & ((field < lo) | (field > hi))
            if bad.any():
                raise AreaError(f"{var.path}: {var.name!r} holds {var.what} {field[bad][0]:g} outside "
                                f"[{lo:g}, {hi:g}] (units {units_of(var.var)!r})")
        # a column counts only where it has both T and S
        wet = np.isfinite(t) & np.isfinite(s)
        t = np.where(wet, t, np.nan)
        s = np.where(wet, s, np.nan)
        lat_axis = self.axes.lat_deg[lat_slice]
        lon_axis = self.axes.lon_deg[lon_slice]
        if lat_flip:
            lat_axis = lat_axis[::-1]
        if lon_flip:
            lon_axis = lon_axis[::-1]
        depth = self.depth_m
        t, s = in_situ_ts(t, s, depth[:, None, None], lat_axis[None, :, None], lon_axis[None, None, :],
                          temperature_kind=self.temperature.kind, salinity_kind=self.salinity.kind)
        sds = []
        for var in (self.temperature, self.salinity):
            sd = var.load_sd(*box)
            if sd is not None:
                bad = np.isfinite(sd) & wet & ~(sd >= 0.0)
                if bad.any():
                    raise AreaError(f"{var.path}: {var.sd_name!r} holds a standard deviation {sd[bad][0]:g} < 0 "
                                    f"(units {units_of(var.sd_var)!r})")
                sd = fill_down(np.where(wet, sd, np.nan))
            sds.append(sd)
        return TsField(path=self.path, depth_m=depth.copy(), lat_deg=lat_axis.copy(),
                       lon_deg=lon_axis.copy(), temperature_c=fill_down(t), salinity_psu=fill_down(s),
                       axes=self.axes, temperature_sd_c=sds[0], salinity_sd_psu=sds[1])


def open_climatology(source: ClimatologySource) -> ClimatologyFiles:
    """Open a climatology lazily (see `ClimatologyFiles`)."""
    return ClimatologyFiles(source)


def fill_down(field: np.ndarray) -> np.ndarray:
    """Fill each column's gaps: the last valid value above continues down (the deepest valid
    value to the last level); top levels with nothing above take the shallowest valid value.

    Parameters
    ----------
    field : ndarray, shape (Z, ...)
        Levels first; NaN where the file has no value.

    Returns
    -------
    ndarray, same shape
        No NaN in columns with at least one value; all-NaN columns stay NaN.
    """
    valid = np.isfinite(field)
    levels = np.arange(field.shape[0]).reshape((-1,) + (1,) * (field.ndim - 1))
    last = np.maximum.accumulate(np.where(valid, levels, -1), axis=0)
    first = np.argmax(valid, axis=0)[None, ...]
    index = np.where(last >= 0, last, first)
    out = np.take_along_axis(field, np.broadcast_to(index, field.shape).copy(), axis=0)
    return np.where(valid.any(axis=0)[None, ...], out, np.nan)


