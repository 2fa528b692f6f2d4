"""Truth CSV: where the target really was (written by the simulator; docs/formats.md "Truth CSV").

``read_truth`` reads one back (a user's own truth too) for comparing a track with it: it needs
``t_s``, ``x_m`` and ``y_m`` (times increasing, positions within reach); other columns are
ignored.
"""

from __future__ import annotations

import csv
import io
import os
from dataclasses import dataclass

import numpy as np

from envdata.files import read_csv_text
from envdata.limits import check_position, check_time
from tracker.errors import MeasurementFileError

REQUIRED = ("t_s", "x_m", "y_m")


@dataclass(frozen=True, slots=True, kw_only=True)
class Truth:
    """The target's true positions: times, s; x east and y north of the origin, m."""

    source: str
    t_s: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray

    def at(self, t_s) -> tuple[np.ndarray, np.ndarray]:
        """Position at given times, m, linear between rows (NaN outside the file's times)."""
        t = np.asarray(t_s, dtype=float)
        inside = (t >= self.t_s[0]) & (t <= self.t_s[-1])
        x = np.where(inside, np.interp(t, self.t_s, self.x_m), np.nan)
        y = np.where(inside, np.interp(t, self.t_s, self.y_m), np.nan)
        return x, y


def read_truth(path: str | os.PathLike) -> Truth:
    """Read a truth CSV.

    Raises
    ------
    MeasurementFileError
        Not a regular text file, no header or a missing column, a value that is not a finite
        number, a time not after the previous row's, a position beyond 20 000 km. One line
        naming the file, row and column.
    """
    src = str(path)
    text = read_csv_text(path, "truth CSV", MeasurementFileError)
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise MeasurementFileError(f"{src}: empty truth CSV (no header row)")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise MeasurementFileError(f"{src}: line 1: the header needs a {missing[0]} column, got "
                                   f"{', '.join(header)}")
    if len(rows) < 2:
        raise MeasurementFileError(f"{src}: no rows after the header")
    cols = {c: header.index(c) for c in REQUIRED}
    values = {c: np.empty(len(rows) - 1) for c in REQUIRED}
    for i, row in enumerate(rows[1:], start=2):
        for c, j in cols.items():
            where = f"{src}: row {i - 1}, column {c}"
            cell = row[j].strip() if j < len(row) else ""
            try:
                v = float(cell)
            except ValueError:
                raise MeasurementFileError(f"{where}: {cell!r} is not a number") from None
            if not np.isfinite(v):
                raise MeasurementFileError(f"{where}: {cell} is not a finite number")
            (check_time if c == "t_s" else check_position)(v, where)
            values[c][i - 2] = v
    t = values["t_s"]
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        k = int(back[0]) + 2
        raise MeasurementFileError(f"{src}: row {k}, column t_s: {t[k - 1]:g} s is not after the "
                                   f"previous row's {t[k - 2]:g} s")
    return Truth(source=src, t_s=t, x_m=values["x_m"], y_m=values["y_m"])
