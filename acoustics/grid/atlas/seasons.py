"""Detection ranges of a class at every position and month of an atlas: the planner's "which season
is worst here" (``tmakit plan months``, ``tmakit atlas plot --what pd``).

At each position and month the P_D map of the table there (``acoustics.grid.pdmap``, on the
atlas's radials) gives, per P_D level, the range on every bearing; a position's range is the
median over its bearings, with a bearing where P_D never reaches the level counted as 0 m and one
where it passes the table's last range as beyond it. When more than half of the bearings pass the
table's end the median is "beyond the table" too, and no range is given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.grid.atlas.store import AtlasStore
from acoustics.grid.detectionsigma import SigmaOverride
from acoustics.grid.pdmap import ANY_BAND, PDMap, pd_map
from acoustics.pd import PD_LEVELS
from envdata.errors import InputError


@dataclass(frozen=True, slots=True, kw_only=True)
class PositionRange:
    """The detection range of one P_D level at one position and month, over its bearings.

    Attributes
    ----------
    origin : int
        The position's index in the atlas.
    lat_deg, lon_deg : float
    month : int
    level : float
        The P_D level.
    median_m, min_m, max_m : float
        Over the bearings, m: the median (NaN when it is beyond the table), and the least and
        largest range given on a bearing (NaN when none is).
    bearings_beyond : int
        Bearings where P_D still reaches the level at the table's last range.
    bearings_never : int
        Bearings where P_D never reaches it.
    bearings : int
    median_beyond_table : bool
        More than half of the bearings pass the table's end.
    """

    origin: int
    lat_deg: float
    lon_deg: float
    month: int
    level: float
    median_m: float
    min_m: float
    max_m: float
    bearings_beyond: int
    bearings_never: int
    bearings: int
    median_beyond_table: bool


def check_choice(store: AtlasStore, cls_name: str | None, band: str | None, months) -> tuple[str, str, list[int]]:
    """The class (default: the first), band or "any" (the default) and months (default: all)
    asked of an atlas; InputError naming the atlas's choices otherwise."""
    cls_name = store.class_names[0] if cls_name is None else cls_name
    if cls_name not in store.class_names:
        raise InputError(f"{store.path}: class {cls_name!r} is not in the atlas ({', '.join(store.class_names)})")
    _first_built(store)
    row = ANY_BAND if band is None else band
    if row != ANY_BAND and row not in store.band_names:
        raise InputError(f"{store.path}: band {band!r} is not in the atlas ({', '.join(store.band_names)}, "
                         f"or {ANY_BAND})")
    months = [int(m) for m in store.months] if months is None else [int(m) for m in months]
    for m in months:
        store.month_index(m)
    return cls_name, row, months


def _first_built(store: AtlasStore) -> int:
    built = np.flatnonzero(store.done.any(axis=0))
    if not built.size:
        raise InputError(f"{store.path}: no table of the atlas is built; tmakit atlas build {store.area.name} "
                         f"builds them")
    return int(built[0])


def position_maps(store: AtlasStore, cls_name: str, month: int, *, override: SigmaOverride | None = None
                  ) -> dict[int, PDMap]:
    """The P_D map of a class on the radials of every built position of a month, by position."""
    m = store.month_index(month)
    return {o: pd_map(store.sel(month=month, origin=o), cls_name, store.bearing_deg, override=override)
            for o in range(store.lat_deg.size) if store.done[m, o]}


def position_ranges(store: AtlasStore, month: int, maps: dict[int, PDMap], row: str) -> list[PositionRange]:
    """Each position's detection range per P_D level (module docstring), from its P_D map."""
    out = []
    for o, pm in maps.items():
        i = pm.row(row)
        for level in PD_LEVELS:
            ranges = pm.ranges_m[level][i]
            past = pm.beyond[level][i]
            never = ~past & np.isnan(ranges)
            counted = np.where(past, np.inf, np.where(never, 0.0, ranges))
            median = float(np.median(counted))
            given = ranges[np.isfinite(ranges)]
            out.append(PositionRange(origin=o, lat_deg=float(store.lat_deg[o]), lon_deg=float(store.lon_deg[o]),
                                     month=int(month), level=level,
                                     median_m=median if np.isfinite(median) else np.nan,
                                     min_m=float(given.min()) if given.size else np.nan,
                                     max_m=float(given.max()) if given.size else np.nan,
                                     bearings_beyond=int(past.sum()), bearings_never=int(never.sum()),
                                     bearings=int(ranges.size), median_beyond_table=not np.isfinite(median)))
    return out


def season_table(store: AtlasStore, cls_name: str, row: str, months, *, override: SigmaOverride | None = None
                 ) -> list[PositionRange]:
    """`position_ranges` of every month asked, month after month."""
    out = []
    for month in months:
        out += position_ranges(store, month, position_maps(store, cls_name, month, override=override), row)
    return out


__all__ = ["PositionRange", "check_choice", "position_maps", "position_ranges", "season_table"]
