"""``atlas sample``: the atlas's K and TL where asked, at observer positions given in a CSV.

Input columns ``obs_lat_deg, obs_lon_deg, month, class, band, bearing_deg, range_m`` and
optionally ``depth_m`` (the target's, m; empty: the class's); the output is the input rows, in
their order, with ``k_db`` and ``tl_db`` added (`values_at`; docs/formats.md). Between positions
each surrounding position's table is read at the same bearing and range from the observer and
the values weighted in dB (``acoustics.grid.atlas.weights``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.errors import ObserverPositionError
from acoustics.grid.atlas.store import AtlasStore
from acoustics.grid.lookup import axis_cells, bearing_weights
from acoustics.kcurve import spectral_term_db
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


def sample_store(store: AtlasStore, points: pd.DataFrame, source: str = "points") -> pd.DataFrame:
    """The points with ``k_db`` and ``tl_db`` added, dB (`values_at`).

    Raises
    ------
    InputError
        A point outside the positions' hull, or of a month, class or band the atlas lacks; the
        message names the row (1 = the first data row).
    """
    num = points.attrs
    try:
        k, tl = values_at(store, lat_deg=num["obs_lat_deg"], lon_deg=num["obs_lon_deg"],
                                month=num["month"].astype(int), cls_name=points["class"].str.strip().to_numpy(object),
                                band_name=points["band"].str.strip().to_numpy(object),
                                bearing_deg=np.mod(num["bearing_deg"], 360.0), range_m=num["range_m"],
                                depth_m=num.get("depth_m"))
    except ObserverPositionError as exc:  # the point's index -> the file's row, from 1
        raise InputError(f"{source}: row {exc.index + 1}: {exc.reason}") from None
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None
    out = points.copy()
    out.attrs = {}
    out["k_db"] = k
    out["tl_db"] = tl
    return out


def values_at(store: AtlasStore, *, lat_deg, lon_deg, month, cls_name, band_name, bearing_deg, range_m,
              depth_m=None) -> tuple[np.ndarray, np.ndarray]:
    """K and TL for observers at positions, targets at bearings and ranges from them, dB.

    Parameters
    ----------
    lat_deg, lon_deg : array_like, shape (P,)
        Observer positions, deg.
    month : array_like of int, shape (P,)
    cls_name, band_name : array_like of str, shape (P,)
    bearing_deg, range_m : array_like, shape (P,)
        Where the target is from the observer, deg clockwise from north, m.
    depth_m : array_like, shape (P,), optional
        The target's depth, m; NaN or None: the class's. K is then S - TL at that depth.

    Returns
    -------
    k_db, tl_db : ndarray, shape (P,)
        Each surrounding position's table read at the same bearing and range (linear between
        radials and in range, linear in depth), weighted in dB; NaN below the bottom or
        beyond land at any of them.
    """
    lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
    n = lat.size
    month = np.broadcast_to(np.asarray(month), (n,))
    cls_arr = np.broadcast_to(np.asarray(cls_name, dtype=object), (n,))
    band_arr = np.broadcast_to(np.asarray(band_name, dtype=object), (n,))
    bearing = np.broadcast_to(np.asarray(bearing_deg, dtype=float), (n,))
    rng = np.broadcast_to(np.asarray(range_m, dtype=float), (n,))
    classes = {c.name: i for i, c in enumerate(store.area.classes)}
    bands = {b.name: i for i, b in enumerate(store.area.bands)}
    for what, arr, names in (("class", cls_arr, classes), ("band", band_arr, bands)):
        bad = [i for i, v in enumerate(arr) if v not in names]
        if bad:
            raise ObserverPositionError(bad[0], f"{what} {arr[bad[0]]!r} is not in the atlas ({', '.join(names)})")
    ci = np.array([classes[v] for v in cls_arr], dtype=int)
    bi = np.array([bands[v] for v in band_arr], dtype=int)
    mi = np.array([store.month_index(int(v)) for v in month], dtype=int) if n else np.zeros(0, int)
    cdepth = np.array([c.depth_m for c in store.area.classes])[ci]
    depth = cdepth if depth_m is None else np.where(np.isfinite(np.broadcast_to(
        np.asarray(depth_m, dtype=float), (n,))), np.asarray(depth_m, dtype=float), cdepth)
    own_k = depth_m is None or ~np.isfinite(np.broadcast_to(np.asarray(depth_m, dtype=float), (n,)))
    own_k = np.broadcast_to(own_k, (n,))
    idx, w = store.weights(lat, np.asarray(lon_deg, dtype=float))
    for p, q in zip(*np.nonzero(w > 0)):
        if not store.done[mi[p], idx[p, q]]:
            store.check_table(mi[p], idx[p, q])
    # every (month, origin) slab needed, read once
    needed = sorted({(int(mi[p]), int(idx[p, q])) for p, q in zip(*np.nonzero(w > 0))})
    slot = {key: s for s, key in enumerate(needed)}
    if needed:
        tls, ks = zip(*[store.slab(m, o)[:2] for m, o in needed])
        tl_all, k_all = np.stack(tls), np.stack(ks)  # (S, C, B, N, Z, R), (S, C, B, N, R)
    j0, j1, wb = bearing_weights(store.bearing_deg, bearing)
    r0, r1, wr = axis_cells(store.range_m, rng)
    z0, z1, wz = axis_cells(store.depth_m, depth)
    k_out = np.zeros(n)
    tl_out = np.zeros(n)
    spectral = np.array([[spectral_term_db(c, b) for b in store.area.bands] for c in store.area.classes])
    for q in range(w.shape[1]):
        s = np.array([slot.get((int(mi[p]), int(idx[p, q])), 0) for p in range(n)], dtype=int)
        use = w[:, q] > 0

        def k_of(j, r, s=s):
            return k_all[s, ci, bi, j, r]

        def tl_of(j, z, r, s=s):
            return tl_all[s, ci, bi, j, z, r].astype(float)

        def at_range(fn, *a):
            return (1 - wr) * fn(*a, r0) + wr * fn(*a, r1)

        k_q = (1 - wb) * at_range(k_of, j0) + wb * at_range(k_of, j1) if needed else np.zeros(n)
        tl_q = np.zeros(n)
        if needed:
            for j, wj in ((j0, 1 - wb), (j1, wb)):
                tl_q += wj * ((1 - wz) * at_range(tl_of, j, z0) + wz * at_range(tl_of, j, z1))
        k_q = np.where(own_k, k_q, spectral[ci, bi] - tl_q)
        k_out += np.where(use, w[:, q] * np.where(use, k_q, 0.0), 0.0)
        tl_out += np.where(use, w[:, q] * np.where(use, tl_q, 0.0), 0.0)
        # a NaN at any position with weight makes the result NaN
        k_out = np.where(use & ~np.isfinite(k_q), np.nan, k_out)
        tl_out = np.where(use & ~np.isfinite(tl_q), np.nan, tl_out)
    return k_out, tl_out
