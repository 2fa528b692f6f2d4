"""docs/nx2d.md: the Nx2D benchmark's times, agreement by bearing and its attribution (the page does
not hold these blocks yet; they are made from nx2d.json all the same)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, load_result, markdown_table

PAGE = "docs/nx2d.md"


#: The Nx2D benchmark's configurations: name in the file -> (route, workers).
NX2D_ROUTES = {"2d_workers1": ("2-D per radial", 1), "2d_workers2": ("2-D per radial", 2),
               "nx2d_workers1": ("Nx2D", 1), "nx2d_workers2": ("Nx2D", 2), "nx2d_workers2_groups2": ("Nx2D", 2),
               "nx2d_cells_workers2_groups2": ("Nx2D, bottom on the file's cells", 2)}


def nx2d_times(root: Path) -> str:
    d = load_result(root, "nx2d.json")
    rows = [("area", "route", "workers", "runs per frequency", "BELLHOP runs", "wall, s", "BELLHOP processes, s (sum)",
             "the repeats (wall, s)"), ("---",) * 8]
    for area, a in d["areas"].items():
        label = "flat" if area.endswith("-flat") else area
        fastest = min(t["wall_s"]["median"] for t in a["times_s"].values())
        for name, t in a["times_s"].items():
            route, workers = NX2D_ROUTES[name]
            if name == "nx2d_cells_workers2_groups2":
                route = f"Nx2D, bottom on {a['box_cells']['bathymetry_step_m']:.0f} m nodes"
            runs = int(t["runs"]["median"])
            if name.startswith("2d"):
                per = f"{a['bearings']} (1 radial each)"
                extra = runs - a["runs_2d"]
                shown = f"{runs} ({a['runs_2d']} fields, {extra} arrivals)" if extra else f"{runs}"
            else:
                groups = runs // a["frequencies"]
                per = f"{groups} ({a['bearings'] // groups} bearings{' each' if groups > 1 else ''})"
                shown = f"{runs}"
            wall = f"{t['wall_s']['median']:.1f}"
            rows.append((label, route, f"{workers}", per, shown,
                         f"**{wall}**" if t["wall_s"]["median"] == fastest else wall,
                         f"{t['bellhop_s']['median']:.1f}", ", ".join(f"{w:.1f}" for w in t["wall_s"]["runs"])))
    return markdown_table(rows) + "\n" + caption(d, "nx2d.json")


def nx2d_bearings(root: Path) -> str:
    d = load_result(root, "nx2d.json")
    a = d["areas"]["shelf-break"]
    step = a["box_cells"]["bathymetry_step_m"]
    rows = [("bearing, deg", "cells", "median, dB", "p90, dB", "max, dB", "median signed (Nx2D - 2-D), dB",
             f"bottom on {step:.0f} m nodes: median / p90, dB"), ("---",) * 7]
    for r, c in zip(a["agreement"]["per_bearing"], a["agreement_cells"]["per_bearing"]):
        rows.append((f"{r['bearing_deg']:g}", f"{r['cells']}", f"{r['median_db']:.3f}", f"{r['p90_db']:.2f}",
                     f"{r['max_db']:.1f}", f"{r['bias_db']:+.4f}", f"{c['median_db']:.2f} / {c['p90_db']:.2f}"))
    return markdown_table(rows) + "\n" + caption(d, "nx2d.json")


def nx2d_attribution(root: Path) -> str:
    d = load_result(root, "nx2d.json")
    att = d["areas"]["shelf-break"]["attribution"]
    bearings = att["bearings_deg"]
    rows = [("2-D run of the radial with ...", *(f"{b:g} deg: median / p90, dB" if i == 0 else f"{b:g} deg"
                                                 for i, b in enumerate(bearings))), ("---",) * (1 + len(bearings))]
    for key, label in (("as_built", "its own bottom and sound speed (as built)"),
                       ("facet_bottom", "BELLHOP3D's triangulated bottom"),
                       ("facet_bottom_box_speed", "the triangulated bottom and the box's sound speed")):
        rows.append((label, *(f"{r['median_db']:.3f} / {r['p90_db']:.2f}" for r in att[key])))
    return markdown_table(rows) + "\n" + caption(d, "nx2d.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"nx2d-times": nx2d_times, "nx2d-bearings": nx2d_bearings, "nx2d-attribution": nx2d_attribution}

_SB = ("areas", "shelf-break", "times_s")
_FLAT = ("areas", "shelf-break-flat", "times_s")


def _nanometres(x: float) -> float:
    return x * 1e9


def _cross_stretch(x: float) -> str:
    """The stretch across the radials less 1, as the page prints it (3.7e-6)."""
    mantissa, exponent = f"{x - 1.0:.1e}".split("e")
    return f"{mantissa}e{int(exponent)}"


#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("nx2d.json", ("geometry", "aeqd_max_offset_m", _nanometres), "**{:.1f} nm**"),
    ("nx2d.json", ("geometry", "aeqd_max_offset_m"), "({:.1e} m)"),
    ("nx2d.json", ("geometry", "flat_earth_max_offset_m"), "**{:.0f} m** off at 30 km"),
    ("nx2d.json", ("geometry", "aeqd_cross_radial_scale", _cross_stretch), "= 1 + {} at 30 km"),
    ("nx2d.json", (*_SB, "nx2d_workers1", "sample_s", "median"), "box took {:.2f} s"),
    ("nx2d.json", (*_SB, "nx2d_workers1", "write_s", "median"), "writing its inputs {:.2f} s"),
    ("nx2d.json", (*_SB, "nx2d_workers2_groups2", "write_s", "median"), "6 runs take {:.2f} s to write"),
    ("nx2d.json", (*_FLAT, "nx2d_workers1", "bellhop_s", "median"), "took {:.1f} s (flat)"),
    ("nx2d.json", (*_SB, "nx2d_workers1", "bellhop_s", "median"), "and {:.1f} s (shelf-break)"),
    ("nx2d.json", (*_FLAT, "2d_workers1", "bellhop_s", "median"), "against {:.1f} s"),
    ("nx2d.json", (*_SB, "2d_workers1", "bellhop_s", "median"), "and {:.1f} s for the 2-D build"),
)
