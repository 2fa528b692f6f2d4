"""``atlas sample``: the atlas's K and TL at observer positions given in a CSV.

Input columns ``obs_lat_deg, obs_lon_deg, month, class, band, bearing_deg, range_m`` and
optionally ``depth_m`` (the target's, m; empty: the class's); the output is the input rows, in
their order, with ``k_db`` and ``tl_db`` added (``AtlasTables.values_at``; docs/formats.md).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.grid.atlas import AtlasTables
from envdata.errors import InputError
from envdata.files import check_input_file

POINT_COLUMNS = ("obs_lat_deg", "obs_lon_deg", "month", "class", "band", "bearing_deg", "range_m")
#: Most rows a points file may have.
MAX_POINTS = 10_000_000


def read_points(path: str | Path) -> pd.DataFrame:
    """Read and check a points CSV (see the module docstring).

    Raises
    ------
    InputError
        Not a regular file or not CSV, a column missing, a value not a number or out of range;
        the message names the file, the column and the row (1 = the first data row).

    Returns
    -------
    DataFrame
        The file's text, column by column (written back as it was); the numeric columns parsed
        into ``.attrs[column]`` (float arrays, NaN for an empty ``depth_m``).
    """
    path = check_input_file(path, "points file", InputError)
    try:
        df = pd.read_csv(path, dtype=str, keep_default_na=False)
    except (ValueError, UnicodeDecodeError, pd.errors.ParserError) as exc:
        raise InputError(f"{path}: not a readable CSV ({type(exc).__name__}: {str(exc).splitlines()[0][:100]})") \
            from None
    missing = [c for c in POINT_COLUMNS if c not in df.columns]
    if missing:
        raise InputError(f"{path}: missing column {missing[0]!r} (need {', '.join(POINT_COLUMNS)})")
    if len(df) > MAX_POINTS:
        raise InputError(f"{path}: {len(df)} rows, more than {MAX_POINTS}")
    for col, lo, hi in (("obs_lat_deg", -90.0, 90.0), ("obs_lon_deg", -180.0, 360.0), ("month", 0, 12),
                        ("bearing_deg", -360.0, 720.0), ("range_m", 0.0, 1e7), ("depth_m", 0.0, 12000.0)):
        if col not in df.columns:
            continue
        text = df[col].str.strip()
        values = pd.to_numeric(text, errors="coerce").to_numpy(dtype=float)
        allowed_nan = (col == "depth_m") & (text == "").to_numpy()  # an empty depth: the class's
        bad = ~((values >= lo) & (values <= hi)) & ~allowed_nan
        if col == "month":
            bad |= np.isfinite(values) & (values != np.round(values))
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"{path}: row {i + 1}, column {col}: {df[col].iloc[i]!r} is not a number in "
                             f"[{lo:g}, {hi:g}]")
        df.attrs[col] = values  # the numbers; the columns keep the file's text for the output
    for col in ("class", "band"):
        empty = (df[col].str.strip() == "").to_numpy()
        if empty.any():
            raise InputError(f"{path}: row {int(np.argmax(empty)) + 1}, column {col}: empty")
    return df


def sample_atlas(atlas: AtlasTables, points: pd.DataFrame, source: str = "points") -> pd.DataFrame:
    """The points with ``k_db`` and ``tl_db`` added, dB (``AtlasTables.values_at``).

    Raises
    ------
    InputError
        A point outside the positions' hull, or of a month, class or band the atlas lacks; the
        message names the row (1 = the first data row).
    """
    num = points.attrs
    try:
        k, tl = atlas.values_at(lat_deg=num["obs_lat_deg"], lon_deg=num["obs_lon_deg"],
                                month=num["month"].astype(int), cls_name=points["class"].str.strip().to_numpy(object),
                                band_name=points["band"].str.strip().to_numpy(object),
                                bearing_deg=np.mod(num["bearing_deg"], 360.0), range_m=num["range_m"],
                                depth_m=num.get("depth_m"))
    except InputError as exc:
        text = str(exc)
        if text.startswith("observer "):  # "observer 12: ..." -> the file's row 13
            head, _, rest = text.partition(":")
            text = f"row {int(head.split()[1]) + 1}:{rest}"
        raise InputError(f"{source}: {text}") from None
    out = points.copy()
    out.attrs = {}
    out["k_db"] = k
    out["tl_db"] = tl
    return out
