"""docs/locate.md: the paper's numbers (Schmidt et al.) against tmakit's, both steering rules."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import load_result, markdown_table

PAGE = "docs/locate.md"


def _pair(xy, digits: int = 4) -> str:
    return f"({xy[0]:.{digits}f}, {xy[1]:.{digits}f})"


def locate(root: Path) -> str:
    d = load_result(root, "locate.json")
    p, rules = d["paper_eq23"], d["rules"]
    a, b = rules["eq23"], rules["eq17"]

    def both(fmt, get) -> tuple[str, str]:
        return fmt.format(get(a)), fmt.format(get(b))

    rows = [("quantity", "paper", "eq23", "eq17"), ("---", "---", "---", "---"),
            ("second bearing α₂", "", *both("{:.3f}°", lambda r: r["bearing_deg"][1])),
            ("u (eq. 11) / \\|P\\| (eq. 10)", "", *both("{}", lambda r: f"{r['u']:.3f} / {r['determinant']:.4f}")),
            ("d13, eq. 25", f"{p['d13_eq25']:.4f}", *both("{:.4f}", lambda r: r["d13_eq25"])),
            ("d13, exact", "", f"{a['d13']:.4f} ({a['d13']:.5f})", f"{b['d13']:.4f}"),
            ("d24, exact", f"{p['d24']:.4f}", *both("{:.4f}", lambda r: r["d24"])),
            ("d24, eq. 26", "", *both("{:.4f}", lambda r: r["d24_eq26"])),
            ("d24, eq. 27", f"{p['d24_eq27']:.4f}", *both("{:.4f}", lambda r: r["d24_eq27"])),
            ("d24/d13, exact", f"({p['d24']:.4f}/{p['d13_eq25']:.4f} = {p['d24'] / p['d13_eq25']:.3f})",
             *both("{:.3f}", lambda r: r["ratio"])),
            ("d24/d13, eq. 28", "", *both("{:.3f}", lambda r: r["ratio_eq28"])),
            ("area, shoelace", p["area"], *both("{:.4f}", lambda r: r["area"])),
            ("area, d13·d24/2", "", *both("{:.4f}", lambda r: r["area_diagonals"])),
            (f"mean of {a['monte_carlo']['trials']} trials (eq. 29)", _pair(p["mc_mean"]),
             *both("{}", lambda r: _pair(r["monte_carlo"]["mean"]))),
            ("expected mean (10⁶ trials)", "", *both("{}", lambda r: _pair(r["expectation"]["mean"]))),
            ("trials inside the quadrilateral", p["inside"],
             *both("{:.0f} %", lambda r: 100 * r["monte_carlo"]["inside_fraction"]))]
    return markdown_table(rows)


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"locate": locate}

#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("locate.json", ("rules", "eq23", "d24"), "d24 exact: {:.4f} against"),
    ("locate.json", ("rules", "eq23", "d24_eq27"), "is {:.4f}; the paper's"),
    ("locate.json", ("rules", "eq23", "area_diagonals"), "is d13·d24/2 ({:.4f})"),
    ("locate.json", ("rules", "eq23", "diagonals_angle_deg"), "cross at\nabout {:.0f}°"),
    ("locate.json", ("rules", "eq23", "area"), "its true area is {:.4f}"),
    ("locate.json", ("rules", "eq23", "monte_carlo", "mean"), "ours " + "({0[0]:.4f}, {0[1]:.4f})"),
    ("locate.json", ("rules", "eq23", "monte_carlo", "standard_error"),
     "one standard error of a 1000-trial mean ({0[0]:.3f} in x, {0[1]:.3f} in y)"),
    ("locate.json", ("rules", "eq23", "expectation", "bias"),
     "biased away from the observer by\n({0[0]:.3f}, {0[1]:.3f})"),
    ("locate.json", ("rules", "eq23", "expectation", "standard_error"), "standard error about {0[1]:.4f}"),
)
