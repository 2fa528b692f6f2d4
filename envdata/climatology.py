"""Climatologies in the World Ocean Atlas layout: ``t_an``, ``s_an`` on (time, depth, lat, lon).

WOA's netCDF files hold the objectively analysed in-situ temperature ``t_an`` (degC) and
practical salinity ``s_an`` on standard depth levels (``depth``, m, positive down) at cell
centres (``lat``, ``lon``), float32 with a large ``_FillValue`` below the sea floor and on land.
Their ``time`` axis ("months since 1955-01-01") is left undecoded. WOA ships one file per
variable and month (``woa23_decav_t08_04.nc`` and ``..._s08_04.nc``: one time step, 57 levels to
1500 m for a month, deeper for the annual and seasonal fields); a file may also hold both
variables, and 12 time steps of which ``[water] month`` picks one. Variables are found by name
(``t_an``, ``s_an``) or by CF ``standard_name`` (``sea_water_temperature``,
``sea_water_salinity`` or ``sea_water_practical_salinity``).

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

from envdata.datafiles import ClimatologySource, DataFile
from envdata.errors import AreaError
from envdata.geogrid import (METRE_UNITS, LatLonAxes, bilinear_corners, distance_m, find_variable,
                             open_dataset, units_of)
from envdata.limits import check_memory

TEMPERATURE_NAMES = ("t_an",)
SALINITY_NAMES = ("s_an",)
TEMPERATURE_STANDARD_NAMES = ("sea_water_temperature",)  # in-situ
SALINITY_STANDARD_NAMES = ("sea_water_salinity", "sea_water_practical_salinity")
#: Other CF quantities a climatology may hold; refused with a message (tmakit reads in-situ T
#: and practical S, as WOA gives them).
OTHER_KINDS = {"sea_water_potential_temperature": "potential temperature",
               "sea_water_conservative_temperature": "Conservative Temperature",
               "sea_water_absolute_salinity": "Absolute Salinity",
               "sea_water_preformed_salinity": "preformed salinity"}
TEMPERATURE_UNITS = ("degrees_celsius", "degree_celsius", "degrees_c", "degree_c", "degc", "deg_c",
                     "celsius", "degreec", "degreesc")
SALINITY_UNITS = ("", "1", "psu", "pss-78", "pss78", "pss", "0.001", "1e-3", "unitless")
#: Cells beyond the box of the positions loaded on each side (bilinear neighbours and the
#: nearest valid column for positions among land cells).
MARGIN_CELLS = 3
#: Values beyond this are a fill value the file did not declare.
MAX_ABS_VALUE = 1.0e5


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
            self.temperature = _Variable.open(source.temperature, "temperature", TEMPERATURE_NAMES,
                                              TEMPERATURE_STANDARD_NAMES, TEMPERATURE_UNITS, source.month,
                                              self._open)
            self.salinity = _Variable.open(source.salinity, "salinity", SALINITY_NAMES,
                                           SALINITY_STANDARD_NAMES, SALINITY_UNITS, source.month, self._open)
            _check_same_grid(self.temperature, self.salinity)
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

    def load_box(self, lat_deg, lon_deg) -> TsField:
        """Load T and S around the positions (a margin of `MARGIN_CELLS` cells), filled down.

        Raises
        ------
        AreaError
            A position outside the files' cells, or T or S outside the sea's range.
        """
        lat = np.asarray(lat_deg, dtype=float)
        inside = self.axes.contains(lat, lon_deg)
        if not np.all(inside):
            i = int(np.argmin(inside))
            raise AreaError(f"{self.path}: position {lat.ravel()[i]:.5f} N "
                            f"{np.asarray(lon_deg, dtype=float).ravel()[i]:.5f} E is outside the "
                            f"climatology ({self.axes.describe()})")
        lat_slice, lon_slice, lat_flip, lon_flip = self.axes.box(lat, lon_deg, MARGIN_CELLS)
        t = self.temperature.load(lat_slice, lon_slice, lat_flip, lon_flip)
        s = self.salinity.load(lat_slice, lon_slice, lat_flip, lon_flip)
        for name, field, lo, hi, var in (("temperature", t, -2.5, 40.0, self.temperature),
                                         ("salinity", s, 0.0, 42.0, self.salinity)):
            bad = np.isfinite(field) & ((field < lo) | (field > hi))
            if bad.any():
                raise AreaError(f"{var.path}: {var.name!r} holds {name} {field[bad][0]:g} outside "
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
        return TsField(path=self.path, depth_m=self.depth_m.copy(), lat_deg=lat_axis.copy(),
                       lon_deg=lon_axis.copy(), temperature_c=fill_down(t), salinity_psu=fill_down(s),
                       axes=self.axes)


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


@dataclass(eq=False)
class _Variable:
    """One climatology variable in one file: where it is and how to cut it."""

    path: Path
    name: str
    var: object
    axes: LatLonAxes
    depth_dim: str
    depth_values: np.ndarray  # as stored, m positive down
    time_dim: str | None
    time_index: int | None

    @property
    def depth_sorted(self) -> np.ndarray:
        return np.sort(self.depth_values)

    @classmethod
    def open(cls, file: DataFile, what: str, names, standard_names, units, month, opened: list) -> "_Variable":
        path = file.resolved()
        ds = open_dataset(path, f"{what} climatology file")
        opened.append(ds)
        try:
            name = find_variable(ds, path, what, names, standard_names)
        except AreaError:
            name = next((str(n) for n, v in ds.data_vars.items() if v.attrs.get("standard_name") in OTHER_KINDS),
                        None)
            if name is None:
                raise
        std = ds[name].attrs.get("standard_name")
        if std in OTHER_KINDS:
            raise AreaError(f"{path}: {name!r} holds {OTHER_KINDS[std]} ({std}); tmakit reads in-situ "
                            f"temperature and practical salinity, as the World Ocean Atlas gives them")
        var = ds[name]
        unit = units_of(var)
        if unit.lower().replace(" ", "_") not in units:
            raise AreaError(f"{path}: variable {name!r} ({what}) has units {unit!r}; need "
                            f"{'degrees_celsius' if what == 'temperature' else 'practical salinity (1 or psu)'}")
        axes = LatLonAxes.of(ds, name, path)
        others = [str(d) for d in var.dims if str(d) not in (axes.lat_dim, axes.lon_dim)]
        depth_dim = next((d for d in others if _is_depth(ds, d)), None)
        if depth_dim is None:
            raise AreaError(f"{path}: variable {name!r} has no depth axis among its dimensions "
                            f"({', '.join(map(str, var.dims))})")
        depth = _depth_values(ds, depth_dim, path)
        rest = [d for d in others if d != depth_dim]
        if len(rest) > 1:
            raise AreaError(f"{path}: variable {name!r} has dimensions ({', '.join(map(str, var.dims))}); "
                            f"need (time, depth, lat, lon)")
        time_dim = rest[0] if rest else None
        steps = int(var.sizes[time_dim]) if time_dim else 1
        if steps == 12:
            if month is None:
                raise AreaError(f"{path}: {name!r} has 12 time steps (months); give [water] month = 1..12")
            index = month - 1
        elif steps == 1:
            index = 0 if time_dim else None
        else:
            raise AreaError(f"{path}: {name!r} has {steps} time steps; need 1 (used as it is) or 12 "
                            f"(one per month, picked by [water] month)")
        return cls(path=path, name=name, var=var, axes=axes, depth_dim=depth_dim, depth_values=depth,
                   time_dim=time_dim, time_index=index)

    def load(self, lat_slice: slice, lon_slice: slice, lat_flip: bool, lon_flip: bool) -> np.ndarray:
        """(Z, ny, nx) values of the box, levels increasing, axes increasing; NaN for no value."""
        ny, nx = lat_slice.stop - lat_slice.start, lon_slice.stop - lon_slice.start
        check_memory(4.0 * 8 * self.depth_values.size * ny * nx,
                     f"{self.path}: the {self.depth_values.size} x {ny} x {nx} climatology cells the radials cross")
        sel = {self.axes.lat_dim: lat_slice, self.axes.lon_dim: lon_slice}
        if self.time_dim is not None:
            sel[self.time_dim] = self.time_index
        block = self.var.isel(sel).transpose(self.depth_dim, self.axes.lat_dim, self.axes.lon_dim)
        values = np.asarray(block.values, dtype=float)
        values[~(np.abs(values) <= MAX_ABS_VALUE)] = np.nan
        order = np.argsort(self.depth_values)
        values = values[order]
        if lat_flip:
            values = values[:, ::-1, :]
        if lon_flip:
            values = values[:, :, ::-1]
        return values


def _is_depth(ds, dim: str) -> bool:
    if dim not in ds.variables:
        return dim.lower() == "depth"
    attrs = ds[dim].attrs
    return (dim.lower() in ("depth", "z", "lev", "level") or attrs.get("standard_name") == "depth"
            or attrs.get("axis") == "Z" or "positive" in attrs)


def _depth_values(ds, dim: str, path: Path) -> np.ndarray:
    if dim not in ds.variables:
        raise AreaError(f"{path}: the depth dimension {dim!r} has no coordinate variable")
    coord = ds[dim]
    unit = units_of(coord)
    if unit not in METRE_UNITS:
        raise AreaError(f"{path}: depth coordinate {dim!r} must be in metres, got units {unit!r}")
    values = np.asarray(coord.values, dtype=float)
    if str(coord.attrs.get("positive", "down")).strip().lower() == "up":
        values = -values
    if values.ndim != 1 or values.size < 1 or not np.all(np.isfinite(values)) or values.min() < 0.0:
        raise AreaError(f"{path}: depth coordinate {dim!r} must be finite depths >= 0 m")
    step = np.diff(np.sort(values))
    if np.any(step <= 0):
        raise AreaError(f"{path}: depth coordinate {dim!r} has repeated levels")
    return values


def _check_same_grid(a: _Variable, b: _Variable) -> None:
    if a.path == b.path:
        return
    for what, x, y in (("depth levels", a.depth_sorted, b.depth_sorted),
                       ("latitudes", a.axes.lat_sorted, b.axes.lat_sorted),
                       ("longitudes", a.axes.lon_sorted, b.axes.lon_sorted)):
        if x.shape != y.shape or not np.allclose(x, y, rtol=0, atol=1e-6):
            raise AreaError(f"{b.path}: its {what} differ from those of the temperature file {a.path}; "
                            f"the two files must be on one grid")
