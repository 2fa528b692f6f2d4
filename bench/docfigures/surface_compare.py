"""docs/surface-compare.md: K before and after the sea-surface change, by area, class and band."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, load_result, markdown_table

PAGE = "docs/surface-compare.md"


def surface_compare(root: Path) -> str:
    d = load_result(root, "surface-compare.json")
    rows = [("area", "class", "FB1 / FB2 / FB3 (or the band): \\|dK\\| median (p90), signed median dK, dB"),
            ("---",) * 3]
    for area, entry in d["areas"].items():
        by = entry["by_class_band"]
        classes = list(dict.fromkeys(k.split()[0] for k in by))
        for cls_name in classes:
            cells = [f"{v['k_median_db']:.2f} ({v['k_p90_db']:.2f}), {v['k_signed_median_db']:+.2f}"
                     for k, v in by.items() if k.split()[0] == cls_name]
            rows.append((area, cls_name, " / ".join(cells)))
    return markdown_table(rows) + "\n" + caption(d, "surface-compare.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"surface-compare": surface_compare}


def _quieter(x: float) -> float:
    """A signed dK as the prose says it: how much quieter (dB, positive)."""
    return -x


def _k(area: str, key: str, what: str = "k_signed_median_db") -> tuple:
    return ("areas", area, "by_class_band", key, what)


#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = tuple(("surface-compare.json", keys, fmt) for keys, fmt in (
    ((*_k("ocean-deep", "SW FB1"), _quieter), "SW is {:.1f} dB quieter (median"),
    ((*_k("ocean-deep", "TV FB1"), _quieter), "is {:.1f} dB quieter. In FB2"),
    (_k("ocean-deep", "SW FB2"), "heard louder, by {:.1f} and"),
    (_k("ocean-deep", "TV FB2"), "and {:.1f} dB. In FB3"),
    ((*_k("ocean-deep", "SW FB3"), abs), "In FB3 SW moves {:.1f} dB"),
    ((*_k("shelf-break", "SW FB1"), _quieter), "SW {:.1f} dB quieter than before"),
    ((*_k("shelf-break", "TV FB1"), _quieter), "TV {:.1f} dB;\nby range"),
    (_k("shelf-break-atlas", "SW FB1"), "SW {:.1f} dB and"),
    (_k("shelf-break-atlas", "TV FB1"), "TV {:.1f} dB in FB1"),
    ((*_k("munk-1000", "ship F50"), _quieter), "K would be {:.1f} dB lower"),
))
