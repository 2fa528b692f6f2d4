"""How the commands say P_D results in their summaries (``grids plot|build|show``, ``atlas plot``,
``plan``): the detection ranges per level over the bearings, "beyond the table" never as a range,
and where the range axis falls short."""

from __future__ import annotations

import math


def km_span(values_m) -> str:
    """``12.3-18.0 km`` (or one value) over the finite values; ``-`` when none is."""
    found = [v / 1000.0 for v in values_m if v is not None and math.isfinite(v)]
    if not found:
        return "-"
    lo, hi = min(found), max(found)
    return f"{hi:.1f} km" if hi - lo < 0.05 else f"{lo:.1f}-{hi:.1f} km"


def pd_lines(pd_maps: dict, row: str, indent: str = "  ") -> list[str]:
    """One line per class: the ranges where P_D falls through each level, over the bearings, and
    the bearings where it passes the table's last range."""
    lines = []
    for cls_name, pm in pd_maps.items():
        i = pm.row(row)
        spans = " / ".join(km_span(pm.ranges_m[level][i]) for level in pm.ranges_m)
        levels = " / ".join(f"{level:g}" for level in pm.ranges_m)
        line = f"{indent}{cls_name} {row}: P_D {levels} out to {spans}"
        past = int(pm.beyond[min(pm.ranges_m)][i].sum())
        if past:
            line += (f"; P_D >= {min(pm.ranges_m):g} still at the table's last range "
                     f"({pm.range_m[-1] / 1000:g} km) on {past} of {pm.bearing_deg.size} bearing(s): beyond the table")
        lines.append(line)
    return lines


def reach_lines(reach: list, indent: str = "  ") -> list[str]:
    """Per class and band where detection passes the table's end: how far the axis would have to go."""
    lines = []
    for r in reach:
        if r.inside:
            continue
        need = ("" if r.needed_m is None else
                f"; the range axis would have to reach about {r.needed_m / 1000:,.0f} km (K's tail: "
                f"{r.spreading_db_per_decade:.1f} dB per decade of range and absorption)")
        lines.append(f"{indent}{r.cls_name} {r.band}: P_D {r.edge_pd:.2f} at the table's last range "
                     f"({r.range_max_m / 1000:g} km) on {r.bearings_beyond} of {r.bearings} bearing(s), above 0.1"
                     + need)
    if not lines:
        lines.append(f"{indent}every class's P_D falls below 0.1 inside the table, in every band")
    return lines


def reach_data(reach: list) -> list[dict]:
    """`reach_lines`' facts as JSON."""
    return [{"class": r.cls_name, "band": r.band, "range_max_m": r.range_max_m, "pd_at_table_end": round(r.edge_pd, 4),
             "bearings_beyond_table": r.bearings_beyond, "bearings": r.bearings, "inside": r.inside,
             "range_needed_m": None if r.needed_m is None else round(r.needed_m, -2),
             "tail_spreading_db_per_decade": None if r.spreading_db_per_decade is None
             else round(r.spreading_db_per_decade, 2)} for r in reach]
