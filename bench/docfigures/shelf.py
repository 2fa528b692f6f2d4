"""docs/shelf.md: tracking over the shelf break, and the bearing-dependent K against the flat one."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, load_result, markdown_table, rmse_rows

PAGE = "docs/shelf.md"


def shelf_rmse(root: Path) -> str:
    d = load_result(root, "shelf/shelf.json")
    names = (("ml_bearing", "ML (G&M), bearing-dependent"), ("ml_isotropic", "ML (G&M), origin's column, flat"),
             ("rpf_bearing", "particle filter, bearing-dependent"),
             ("rpf_isotropic", "particle filter, origin's column, flat"),
             ("bot_bearing", "bearings-only filter (the same prior)"))
    rows = rmse_rows(d, names, ("tracker, grid", "5-30 min"), "{:.0f}", 1.0)
    return markdown_table(rows) + "\n" + caption(d, "shelf/shelf.json")


def shelf_dk(root: Path) -> str:
    d = load_result(root, "shelf/shelf.json")
    where = {"0": "0 deg (up the slope to the shelf)", "90": "90 deg (along the slope)",
             "150": "150 deg (down the slope, where the transport starts)",
             "180": "180 deg (down the slope to the basin)"}
    rows = [("bearing", "5 km", "10 km", "15 km", "20 km"), ("---",) * 5]
    for b, label in where.items():
        rows.append((label, *(f"{d['k_difference_db'][b][r]:+.1f}" for r in ("5", "10", "15", "20"))))
    return markdown_table(rows) + "\n" + caption(d, "shelf/shelf.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"shelf-rmse": shelf_rmse, "shelf-dk": shelf_dk}


def _tens(x: float) -> int:
    """Seconds rounded to ten, as "about 40 s"."""
    return int(round(x, -1))


#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("shelf/shelf.json", ("seconds", _tens), "It takes about {:d} s on\n2 cores"),
)
