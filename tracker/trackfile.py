"""Track CSV: the trackers' output, one row per cycle per class hypothesis (docs/formats.md "Track CSV")."""

from __future__ import annotations

import os

import numpy as np
import pandas as pd

from envdata.files import atomic_path

TRACK_COLUMNS = ("t_s", "class", "x_m", "y_m", "range_m", "bearing_deg", "course_deg", "speed_mps",
                 "range_sd_m", "course_sd_deg", "speed_sd_mps", "tack", "method", "depth_m",
                 "depth_sd_m")
#: Columns a track CSV of an earlier version may lack (read as blank): the target's depth, m,
#: and its sd (blank where the depth was assumed, not estimated).
OPTIONAL_COLUMNS = ("depth_m", "depth_sd_m")
_TEXT_COLUMNS = ("class", "method")


def check_track(df: pd.DataFrame, where: str = "track") -> pd.DataFrame:
    """Check a track table has exactly the columns of TRACK_COLUMNS; return them in order.

    Raises
    ------
    ValueError
        A missing column or a non-numeric column that should hold numbers. These are
        programming errors of a tracker, not bad user input.
    """
    missing = [c for c in TRACK_COLUMNS if c not in df.columns]
    if missing:
        raise ValueError(f"{where}: track table lacks column {missing[0]!r} "
                         f"(needs {', '.join(TRACK_COLUMNS)})")
    out = df.loc[:, list(TRACK_COLUMNS)].copy()
    for col in TRACK_COLUMNS:
        if col in _TEXT_COLUMNS:
            out[col] = out[col].astype(str)
        elif col == "tack":
            out[col] = out[col].astype(int)
        elif not np.issubdtype(out[col].dtype, np.number):
            raise ValueError(f"{where}: track column {col!r} must be numeric, got {out[col].dtype}")
    return out


def write_track(path: str | os.PathLike, df: pd.DataFrame, *, atomic: bool = True) -> None:
    """Write a track CSV after checking its columns (TRACK_COLUMNS order): through a temporary
    file, or straight to ``path`` for a caller that renames several files together."""
    out = check_track(df, str(path))
    if not atomic:
        out.to_csv(path, index=False, na_rep="", float_format="%.9g")
        return
    with atomic_path(path) as tmp:
        out.to_csv(tmp, index=False, na_rep="", float_format="%.9g")


def read_track(path: str | os.PathLike) -> pd.DataFrame:
    """Read a track CSV written by write_track."""
    df = pd.read_csv(path, keep_default_na=True, dtype={"class": str, "method": str})
    for col in OPTIONAL_COLUMNS:
        if col not in df.columns:
            df[col] = np.nan
    return check_track(df, str(path))
