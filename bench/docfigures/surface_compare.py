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
