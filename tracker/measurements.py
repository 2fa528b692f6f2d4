"""Measurement CSV: one row per sonar cycle (docs/formats.md "Measurement CSV").

Columns: ``t_s, obs_x_m, obs_y_m, obs_depth_m, bearing_deg`` (required), ``bearing_sigma_deg``
(optional) and, per band NAME of the grid, ``level_db_NAME`` (blank when the band is not
detected) and optional ``snr_db_NAME`` (10 lg q, the power SNR of eq. 11 after the array).
An observer given by ``obs_lat_deg, obs_lon_deg`` (WGS84) instead of ``obs_x_m, obs_y_m`` is put in
the local plane of the grid's area (azimuthal equidistant about its ``[origin]``); with both,
``obs_x_m, obs_y_m`` are used. Extra columns are ignored. A blank bearing is allowed (the trackers
skip that cycle and say so once); every other required value must be a finite number.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from envdata.files import atomic_path, read_csv_text
from envdata.limits import MAX_POSITION_M, MAX_TIME_S
from tracker.errors import MeasurementFileError

REQUIRED_COLUMNS = ("t_s", "obs_x_m", "obs_y_m", "obs_depth_m", "bearing_deg")
LEVEL_PREFIX = "level_db_"
SNR_PREFIX = "snr_db_"
_UNITS = {"t_s": "s", "obs_x_m": "m", "obs_y_m": "m", "obs_depth_m": "m", "bearing_deg": "deg",
          "bearing_sigma_deg": "deg", "obs_lat_deg": "deg", "obs_lon_deg": "deg"}
#: The observer's position as latitude and longitude, instead of obs_x_m, obs_y_m.
LAT_LON_COLUMNS = ("obs_lat_deg", "obs_lon_deg")
_LAT_LON_BOUNDS = {"obs_lat_deg": (-90.0, 90.0), "obs_lon_deg": (-180.0, 360.0)}
#: Plausible bounds of a band level and a band SNR, dB (a value outside is a unit mistake).
LEVEL_RANGE_DB = (-50.0, 300.0)
SNR_RANGE_DB = (-100.0, 200.0)
#: Deepest observer accepted, m.
MAX_DEPTH_M = 12000.0


@dataclass(frozen=True, slots=True, kw_only=True)
class Measurements:
    """Bearings and band levels of one target over the sonar cycles.

    Attributes
    ----------
    source : str
        File name (or another label), used in messages.
    t_s : ndarray, shape (n,)
        Cycle times, s, strictly increasing.
    obs_x_m, obs_y_m, obs_depth_m : ndarray, shape (n,)
        Observer position east, north and depth, m.
    bearing_deg : ndarray, shape (n,)
        Bearing to the target, deg clockwise from north in [0, 360); NaN where missing.
    bearing_sigma_deg : ndarray, shape (n,)
        Bearing error sd (eq. 2), deg; NaN where the column is absent or blank.
    band_names : tuple of str
        Bands that have a ``level_db_NAME`` column, in grid order.
    level_db : ndarray, shape (n, n_bands)
        Band levels, dB re 1 uPa; NaN when the band is not detected.
    snr_db : ndarray, shape (n, n_bands)
        Band power SNR 10 lg q, dB; NaN when absent or blank.
    """

    source: str
    t_s: np.ndarray
    obs_x_m: np.ndarray
    obs_y_m: np.ndarray
    obs_depth_m: np.ndarray
    bearing_deg: np.ndarray
    bearing_sigma_deg: np.ndarray
    band_names: tuple[str, ...]
    level_db: np.ndarray
    snr_db: np.ndarray

    def __post_init__(self) -> None:
        n = None
        for name in ("t_s", "obs_x_m", "obs_y_m", "obs_depth_m", "bearing_deg",
                     "bearing_sigma_deg"):
            value = np.array(getattr(self, name), dtype=float, ndmin=1)
            if value.ndim != 1:
                raise MeasurementFileError(f"{self.source}: {name} must be one-dimensional, "
                                           f"got shape {value.shape}")
            n = len(value) if n is None else n
            if len(value) != n:
                raise MeasurementFileError(f"{self.source}: {name} has {len(value)} values, "
                                           f"t_s has {n}")
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        object.__setattr__(self, "band_names", tuple(self.band_names))
        for name in ("level_db", "snr_db"):
            value = np.array(getattr(self, name), dtype=float, ndmin=2)
            if value.size == 0:
                value = value.reshape(n, len(self.band_names))
            if value.shape != (n, len(self.band_names)):
                raise MeasurementFileError(f"{self.source}: {name} has shape {value.shape}, "
                                           f"expected ({n}, {len(self.band_names)})")
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        for name in ("t_s", "obs_x_m", "obs_y_m", "obs_depth_m"):
            value = getattr(self, name)
            bad = np.flatnonzero(~np.isfinite(value))
            if bad.size:
                i = int(bad[0])
                raise MeasurementFileError(f"{self.source}: row {i + 1}, column {name}: "
                                           f"{value[i]} {_UNITS[name]} is not a finite number")
        check_bounds(self.source, t_s=self.t_s, obs_x_m=self.obs_x_m, obs_y_m=self.obs_y_m)
        bad = np.flatnonzero(np.diff(self.t_s) <= 0.0)
        if bad.size:
            i = int(bad[0]) + 1
            raise MeasurementFileError(f"{self.source}: row {i + 1}, column t_s: {self.t_s[i]} s "
                                       f"is not after the previous row's {self.t_s[i - 1]} s")

    def __len__(self) -> int:
        return len(self.t_s)

    def obs_velocity_mps(self) -> tuple[np.ndarray, np.ndarray]:
        """Observer velocity east and north, m/s, from the positions.

        Central differences inside, one-sided at the ends (``numpy.gradient`` over t_s). A
        single cycle gives zero velocity.
        """
        if len(self.t_s) < 2:
            return np.zeros(len(self.t_s)), np.zeros(len(self.t_s))
        return (np.gradient(self.obs_x_m, self.t_s, edge_order=1),
                np.gradient(self.obs_y_m, self.t_s, edge_order=1))

    def band_index(self, name: str) -> int:
        return self.band_names.index(name)

    def take(self, rows) -> Measurements:
        """The measurements of the given rows (a slice or index array)."""
        return Measurements(source=self.source, t_s=self.t_s[rows], obs_x_m=self.obs_x_m[rows],
                            obs_y_m=self.obs_y_m[rows], obs_depth_m=self.obs_depth_m[rows],
                            bearing_deg=self.bearing_deg[rows],
                            bearing_sigma_deg=self.bearing_sigma_deg[rows],
                            band_names=self.band_names, level_db=self.level_db[rows],
                            snr_db=self.snr_db[rows])

    def with_bands(self, names) -> Measurements:
        """The measurements with the levels and SNR of the named bands only, in that order."""
        j = [self.band_index(n) for n in names]
        return replace(self, band_names=tuple(names), level_db=self.level_db[:, j], snr_db=self.snr_db[:, j])

    def to_frame(self):
        """The measurements as a pandas DataFrame with the columns of the measurement CSV."""
        import pandas as pd

        cols = {name: getattr(self, name) for name in REQUIRED_COLUMNS}
        cols["bearing_sigma_deg"] = self.bearing_sigma_deg
        for j, band in enumerate(self.band_names):
            cols[LEVEL_PREFIX + band] = self.level_db[:, j]
        for j, band in enumerate(self.band_names):
            cols[SNR_PREFIX + band] = self.snr_db[:, j]
        return pd.DataFrame(cols)


def check_bounds(source: str, *, t_s, obs_x_m, obs_y_m) -> None:
    """Refuse times beyond 100 years and positions beyond 20 000 km (unit or typing mistakes).

    Raises
    ------
    MeasurementFileError
        Naming the file, the row (1-based), the column and the value.
    """
    for name, values, limit, text in (("t_s", t_s, MAX_TIME_S, "beyond 100 years"),
                                      ("obs_x_m", obs_x_m, MAX_POSITION_M, "beyond 20000 km"),
                                      ("obs_y_m", obs_y_m, MAX_POSITION_M, "beyond 20000 km")):
        bad = np.flatnonzero(~(np.abs(np.asarray(values, dtype=float)) <= limit))
        if bad.size:
            i = int(bad[0])
            raise MeasurementFileError(f"{source}: row {i + 1}, column {name}: {values[i]:g} "
                                       f"{_UNITS[name]} is {text}")


def parse_number(cell: str, where: str, unit: str, *, blank_ok: bool = False) -> float:
    """One CSV cell as a finite number; blank (or NaN) gives NaN when ``blank_ok``.

    ``where`` names file, row and column for the MeasurementFileError message.
    """
    cell = cell.strip()
    if not cell:
        if blank_ok:
            return math.nan
        raise MeasurementFileError(f"{where}: blank value; expected a number in {unit}")
    try:
        value = float(cell)
    except ValueError:
        raise MeasurementFileError(f"{where}: {cell!r} is not a number ({unit})") from None
    if not math.isfinite(value):
        if blank_ok and math.isnan(value):
            return math.nan
        raise MeasurementFileError(f"{where}: {cell} {unit} is not a finite number")
    return value


def read_measurements(path: str | os.PathLike, grid_band_names: Sequence[str] | None = None,
                      origin=None) -> Measurements:
    """Read and validate a measurement CSV.

    Parameters
    ----------
    path : path-like
        The CSV file (header required; extra columns ignored).
    grid_band_names : sequence of str, optional
        Band names of the grid the measurements will be used with. A ``level_db_NAME`` or
        ``snr_db_NAME`` column whose NAME is not among them is an error; the level columns are
        returned in this order. Without it, the bands are taken in file order.
    origin : envdata.geometry.Origin, optional
        The grid area's ``[origin]``: where ``obs_lat_deg, obs_lon_deg`` are put in the plane.
        Without it, a file with latitudes and longitudes and no ``obs_x_m, obs_y_m`` is refused.

    Returns
    -------
    Measurements

    Raises
    ------
    MeasurementFileError
        Unreadable, empty or binary file; a missing required column; a band the grid lacks;
        a row with the wrong number of fields; a non-numeric or non-finite value; a bearing
        outside [0, 360) deg, a bearing sd <= 0, a negative depth, a level or SNR out of its
        plausible range; a time not after the previous row's. One line naming the file, row,
        column and value.
    """
    src = str(path)
    text = read_csv_text(path, "measurement CSV", MeasurementFileError)
    reader = csv.reader(io.StringIO(text))
    header = None
    for row in reader:
        if any(cell.strip() for cell in row):
            header = [cell.strip() for cell in row]
            break
    if header is None:
        raise MeasurementFileError(f"{src}: empty file; expected a header with "
                                   f"{', '.join(REQUIRED_COLUMNS)}")
    dupes = sorted({h for h in header if h and header.count(h) > 1})
    if dupes:
        raise MeasurementFileError(f"{src}: column {dupes[0]!r} appears more than once")
    lat_lon = all(c in header for c in LAT_LON_COLUMNS) and not ("obs_x_m" in header and "obs_y_m" in header)
    if lat_lon and origin is None:
        raise MeasurementFileError(f"{src}: columns obs_lat_deg, obs_lon_deg: the grid has no [origin] to put "
                                   f"them in its plane; give obs_x_m, obs_y_m (m east and north)")
    needed = [c for c in REQUIRED_COLUMNS if not (lat_lon and c in ("obs_x_m", "obs_y_m"))]
    if lat_lon:
        needed[1:1] = list(LAT_LON_COLUMNS)
    missing = [name for name in needed if name not in header]
    if missing:
        raise MeasurementFileError(f"{src}: missing required column {missing[0]!r} (required: "
                                   f"{', '.join(REQUIRED_COLUMNS)})")
    level_bands = [h[len(LEVEL_PREFIX):] for h in header if h.startswith(LEVEL_PREFIX)]
    snr_bands = [h[len(SNR_PREFIX):] for h in header if h.startswith(SNR_PREFIX)]
    if grid_band_names is not None:
        grid_band_names = [str(b) for b in grid_band_names]
        for prefix, bands in ((LEVEL_PREFIX, level_bands), (SNR_PREFIX, snr_bands)):
            for band in bands:
                if band not in grid_band_names:
                    raise MeasurementFileError(
                        f"{src}: column {prefix + band!r}: band {band!r} is not a band of the "
                        f"grid ({', '.join(grid_band_names) or 'none'})")
        band_names = tuple(b for b in grid_band_names if b in level_bands)
    else:
        band_names = tuple(level_bands)
    for band in snr_bands:
        if band not in band_names:
            raise MeasurementFileError(f"{src}: column {SNR_PREFIX + band!r} has no matching "
                                       f"{LEVEL_PREFIX + band!r} column")
    index = {name: header.index(name) for name in needed}
    sigma_col = header.index("bearing_sigma_deg") if "bearing_sigma_deg" in header else None
    level_cols = [header.index(LEVEL_PREFIX + b) for b in band_names]
    snr_cols = [header.index(SNR_PREFIX + b) if SNR_PREFIX + b in header else None
                for b in band_names]

    values: dict[str, list[float]] = {name: [] for name in needed}
    sigma: list[float] = []
    levels: list[list[float]] = []
    snrs: list[list[float]] = []
    n_row = 0

    def number(cell: str, where: str, column: str, unit: str, *, blank_ok: bool) -> float:
        return parse_number(cell, f"{src}: {where}, column {column}", unit, blank_ok=blank_ok)

    def decibels(cell: str, where: str, column: str, bounds: tuple[float, float], unit: str) -> float:
        """A level or SNR cell: blank (NaN), or a number of dB within ``bounds``."""
        v = number(cell, where, column, "dB", blank_ok=True)
        if not math.isnan(v) and not bounds[0] <= v <= bounds[1]:
            raise MeasurementFileError(f"{src}: {where}, column {column}: {v:g} dB is outside "
                                       f"[{bounds[0]:g}, {bounds[1]:g}] {unit}")
        return v

    for row in reader:
        if not any(cell.strip() for cell in row):
            continue
        n_row += 1
        where = f"row {n_row} (line {reader.line_num})"
        if len(row) != len(header):
            raise MeasurementFileError(f"{src}: {where}: has {len(row)} fields, the header has "
                                       f"{len(header)}")
        for name, col in index.items():
            value = number(row[col], where, name, _UNITS[name], blank_ok=name == "bearing_deg")
            if name == "bearing_deg" and not math.isnan(value) and not 0.0 <= value < 360.0:
                raise MeasurementFileError(f"{src}: {where}, column bearing_deg: {value:g} deg "
                                           f"is outside [0, 360) deg")
            if name in _LAT_LON_BOUNDS and not _LAT_LON_BOUNDS[name][0] <= value <= _LAT_LON_BOUNDS[name][1]:
                lo, hi = _LAT_LON_BOUNDS[name]
                raise MeasurementFileError(f"{src}: {where}, column {name}: {value:g} deg is outside "
                                           f"[{lo:g}, {hi:g}] deg")
            if name == "obs_depth_m" and not 0.0 <= value <= MAX_DEPTH_M:
                raise MeasurementFileError(f"{src}: {where}, column obs_depth_m: {value:g} m is "
                                           f"outside [0, {MAX_DEPTH_M:g}] m")
            if name == "t_s" and values["t_s"] and value <= values["t_s"][-1]:
                raise MeasurementFileError(f"{src}: {where}, column t_s: {value:g} s is not after "
                                           f"the previous row's {values['t_s'][-1]:g} s")
            values[name].append(value)
        s = math.nan
        if sigma_col is not None:
            s = number(row[sigma_col], where, "bearing_sigma_deg", "deg", blank_ok=True)
            if not math.isnan(s) and not 0.0 < s <= 180.0:
                raise MeasurementFileError(f"{src}: {where}, column bearing_sigma_deg: {s:g} deg "
                                           f"is outside (0, 180] deg")
        sigma.append(s)
        lv, sn = [], []
        for band, lc, sc in zip(band_names, level_cols, snr_cols):
            lv.append(decibels(row[lc], where, LEVEL_PREFIX + band, LEVEL_RANGE_DB, "dB re 1 uPa"))
            sn.append(math.nan if sc is None else decibels(row[sc], where, SNR_PREFIX + band, SNR_RANGE_DB, "dB"))
        levels.append(lv)
        snrs.append(sn)
    if n_row == 0:
        raise MeasurementFileError(f"{src}: no data rows after the header; expected one row "
                                   f"per cycle")
    nb = len(band_names)
    if lat_lon:
        from envdata.geometry import lat_lon_to_local_plane

        x, y = lat_lon_to_local_plane(origin.lat_deg, origin.lon_deg, values.pop("obs_lat_deg"),
                                      values.pop("obs_lon_deg"))
        values["obs_x_m"], values["obs_y_m"] = list(np.atleast_1d(x)), list(np.atleast_1d(y))
    return Measurements(source=src, **{k: np.array(v) for k, v in values.items()},
                        bearing_sigma_deg=np.array(sigma), band_names=band_names,
                        level_db=np.array(levels, dtype=float).reshape(n_row, nb),
                        snr_db=np.array(snrs, dtype=float).reshape(n_row, nb))


def write_measurements(path: str | os.PathLike, m: Measurements, *, atomic: bool = True) -> None:
    """Write measurements as a measurement CSV (blanks for NaN).

    With ``atomic`` (the default) through a temporary file renamed on success; without, straight
    to ``path`` (for a caller that renames several files together).
    """
    df = m.to_frame()
    if not atomic:
        df.to_csv(path, index=False, na_rep="", float_format="%.10g")
        return
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False, na_rep="", float_format="%.10g")
