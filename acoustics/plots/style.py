"""What the figures of a bearing-dependent grid share: the grid's area and name, the options
check, labels, land and depth contours.

Bearings are clockwise from true north at the origin; between radials the figures show what the
trackers use, values linear in bearing (``acoustics.grid.lookup``).
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.grid.face import Tables
from envdata.errors import InputError

#: Depth contours drawn where the water reaches them, m.
CONTOUR_LEVELS_M = (100.0, 200.0, 500.0, 1000.0, 2000.0, 3000.0, 4000.0, 5000.0)
#: Land: where a radial has met the coast (the grid holds nothing there).
LAND_COLOR = "#c8b28a"
#: The observer at the origin.
ORIGIN_STYLE = dict(marker="*", color="crimson", mec="k", mew=0.5, ls="none")
DPI = 110
DEG = "\N{DEGREE SIGN}"


def check_plot_options(tables: Tables, *, cls_name: str | None = None, band: str | None = None,
                       bearing_deg: float | None = None) -> None:
    """Refuse a class or band the grid does not have, or a bearing that is not in [0, 360) deg.

    Raises
    ------
    InputError
        Naming the grid file, the option and its value.
    """
    src = tables.source
    classes, bands = tables.class_names, tables.band_names
    if cls_name is not None and cls_name not in classes:
        raise InputError(f"{src}: class {cls_name!r} is not a class of the grid ({', '.join(classes)})")
    if band is not None and band not in bands:
        raise InputError(f"{src}: band {band!r} is not a band of the grid ({', '.join(bands)})")
    if bearing_deg is not None:
        if not (math.isfinite(bearing_deg) and 0.0 <= bearing_deg < 360.0):
            raise InputError(f"{src}: bearing {bearing_deg:g} deg: must be in [0, 360) deg, "
                             f"clockwise from true north")


def band_label(tables: Tables, band: str) -> str:
    """``FB1 (100-300 Hz)``, or ``F1 (250 Hz)`` for one frequency."""
    b = tables.bands[tables.band_index(band)]
    return f"{band} ({b.low_hz:g} Hz)" if b.low_hz == b.high_hz else f"{band} ({b.low_hz:g}-{b.high_hz:g} Hz)"


def class_label(tables: Tables, cls_name: str) -> str:
    """``NPS (at 200 m)``: the class and the depth its tables are for."""
    return f"{cls_name} (at {tables.classes[tables.class_index(cls_name)].depth_m:g} m)"


def origin_label(tables) -> str:
    """``43.000°N 5.000°E``: the origin of bearing-dependent tables."""
    return f"{tables.origin_lat_deg:.3f}{DEG}N {tables.origin_lon_deg:.3f}{DEG}E"


def contour_levels(depth_m: np.ndarray) -> list[float]:
    """The `CONTOUR_LEVELS_M` the water in ``depth_m`` crosses."""
    d = np.asarray(depth_m, dtype=float)
    if not np.isfinite(d).any():
        return []
    lo, hi = float(np.nanmin(d)), float(np.nanmax(d))
    return [z for z in CONTOUR_LEVELS_M if lo < z < hi]


def label_depth(z: float) -> str:
    return f"{z:g} m"
