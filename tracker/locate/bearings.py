"""Bearings of one stationary target taken at known observer positions: the input and its CSV.

The bearings CSV has the columns ``t_s, obs_x_m, obs_y_m, bearing_deg`` (docs/formats.md): times in
seconds, increasing; observer positions east and north in metres; bearings in degrees clockwise
from north in [0, 360). Both the file reader and the dataclass check their values.
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass

import numpy as np

from envdata.files import read_csv_text
from envdata.limits import MAX_POSITION_M, MAX_TIME_S
from tracker.errors import LocateError, MeasurementFileError
from tracker.measurements import parse_number

BEARING_COLUMNS = ("t_s", "obs_x_m", "obs_y_m", "bearing_deg")
_UNITS = {"t_s": "s", "obs_x_m": "m", "obs_y_m": "m", "bearing_deg": "deg"}


@dataclass(frozen=True, slots=True, kw_only=True)
class Bearings:
    """Bearings of one stationary target taken at known observer positions.

    Attributes
    ----------
    t_s : ndarray
        Time of each bearing, s (increasing).
    obs_x_m, obs_y_m : ndarray
        Observer position east and north, m.
    bearing_deg : ndarray
        Bearing to the target, degrees clockwise from north in [0, 360).
    source : str
        Where the bearings came from (a file name), used in error messages.
    """

    t_s: np.ndarray
    obs_x_m: np.ndarray
    obs_y_m: np.ndarray
    bearing_deg: np.ndarray
    source: str = "bearings"

    def __post_init__(self) -> None:
        arrays = {}
        for name in BEARING_COLUMNS:
            value = np.array(getattr(self, name), dtype=float, ndmin=1)
            if value.ndim != 1:
                raise LocateError(f"{self.source}: {name} must be one-dimensional, "
                                  f"got shape {value.shape}")
            value.setflags(write=False)
            arrays[name] = value
            object.__setattr__(self, name, value)
        sizes = {len(a) for a in arrays.values()}
        if len(sizes) != 1:
            raise LocateError(f"{self.source}: t_s, obs_x_m, obs_y_m and bearing_deg differ in "
                              f"length: {', '.join(str(len(a)) for a in arrays.values())}")
        for name, value in arrays.items():
            bad = np.flatnonzero(~np.isfinite(value))
            if bad.size:
                i = int(bad[0])
                raise LocateError(f"{self.source}: column {name}, row {i + 1}: "
                                  f"{value[i]} {_UNITS[name]} is not a finite number")
        for name, limit, text in (("t_s", MAX_TIME_S, "beyond 100 years"),
                                  ("obs_x_m", MAX_POSITION_M, "beyond 20000 km"),
                                  ("obs_y_m", MAX_POSITION_M, "beyond 20000 km")):
            bad = np.flatnonzero(~(np.abs(arrays[name]) <= limit))
            if bad.size:
                i = int(bad[0])
                raise LocateError(f"{self.source}: column {name}, row {i + 1}: "
                                  f"{arrays[name][i]:g} {_UNITS[name]} is {text}")
        bad = np.flatnonzero((arrays["bearing_deg"] < 0.0) | (arrays["bearing_deg"] >= 360.0))
        if bad.size:
            i = int(bad[0])
            raise LocateError(f"{self.source}: column bearing_deg, row {i + 1}: "
                              f"{arrays['bearing_deg'][i]} deg is outside [0, 360) deg")
        bad = np.flatnonzero(np.diff(arrays["t_s"]) <= 0.0)
        if bad.size:
            i = int(bad[0]) + 1
            raise LocateError(f"{self.source}: column t_s, row {i + 1}: {arrays['t_s'][i]} s is "
                              f"not after the previous row's {arrays['t_s'][i - 1]} s")

    def __len__(self) -> int:
        return len(self.bearing_deg)

    @classmethod
    def from_arrays(cls, obs_x_m, obs_y_m, bearing_deg, *, t_s=None,
                    source: str = "bearings") -> Bearings:
        """Bearings from arrays; times default to 0, 1, 2, ... s."""
        n = len(np.atleast_1d(bearing_deg))
        t = np.arange(n, dtype=float) if t_s is None else t_s
        return cls(t_s=t, obs_x_m=obs_x_m, obs_y_m=obs_y_m, bearing_deg=bearing_deg, source=source)

    def to_frame(self):
        """The bearings as a pandas DataFrame with the columns of the bearings CSV."""
        import pandas as pd

        return pd.DataFrame({name: getattr(self, name) for name in BEARING_COLUMNS})


def read_bearings_csv(path: str | os.PathLike) -> Bearings:
    """Read and validate a bearings CSV.

    The file needs a header with the columns ``t_s, obs_x_m, obs_y_m, bearing_deg`` (any
    order; extra columns such as those of the measurement CSV are ignored) and one row per
    bearing, ordered by time.

    Parameters
    ----------
    path : path-like
        The CSV file.

    Returns
    -------
    Bearings
        The validated bearings; ``source`` is the file name.

    Raises
    ------
    MeasurementFileError
        Unreadable, empty or binary file; missing column; a row with too few or too many
        fields; a blank, non-numeric or non-finite value; a bearing outside [0, 360) deg; a
        time not after the previous row's. The message names the file, the row (1-based data
        row and the file's line number), the column and the value with its unit.
    """
    src = str(path)
    text = read_csv_text(path, "bearings file", MeasurementFileError)
    if not text.strip():
        raise MeasurementFileError(f"{src}: the file is empty; expected a header with columns "
                                   f"{', '.join(BEARING_COLUMNS)}")
    reader = csv.reader(io.StringIO(text, newline=""), skipinitialspace=True)
    header: list[str] = []
    for row in reader:
        if any(cell.strip() for cell in row):
            header = [cell.strip() for cell in row]
            break
    missing = [name for name in BEARING_COLUMNS if name not in header]
    if missing:
        raise MeasurementFileError(f"{src}: missing column {missing[0]!r} (the header has "
                                   f"{', '.join(repr(h) for h in header)}); required: "
                                   f"{', '.join(BEARING_COLUMNS)}")
    index = {name: header.index(name) for name in BEARING_COLUMNS}
    values: dict[str, list[float]] = {name: [] for name in BEARING_COLUMNS}
    n_row = 0
    for row in reader:
        if not any(cell.strip() for cell in row):
            continue  # blank line
        n_row += 1
        where = f"row {n_row} (line {reader.line_num})"
        if len(row) != len(header):
            raise MeasurementFileError(f"{src}: {where}: has {len(row)} fields, the header has "
                                       f"{len(header)}")
        for name, col in index.items():
            cell = row[col].strip()
            value = parse_number(cell, f"{src}: {where}, column {name}", _UNITS[name])
            if name == "bearing_deg" and not 0.0 <= value < 360.0:
                raise MeasurementFileError(f"{src}: {where}, column bearing_deg: {cell} deg is "
                                           f"outside [0, 360) deg")
            if name == "t_s" and values["t_s"] and value <= values["t_s"][-1]:
                raise MeasurementFileError(f"{src}: {where}, column t_s: {cell} s is not after "
                                           f"the previous row's {values['t_s'][-1]:g} s")
            values[name].append(value)
    if n_row == 0:
        raise MeasurementFileError(f"{src}: no data rows after the header; expected one row "
                                   f"per bearing")
    return Bearings(**{name: np.array(v) for name, v in values.items()}, source=src)
