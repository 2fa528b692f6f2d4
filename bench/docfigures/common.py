"""What every page's tables share: reading a result file and one of its figures, the caption naming
the file and how it was made, and the Markdown table."""

from __future__ import annotations

import json
from pathlib import Path


def load_result(root: Path, name: str) -> dict:
    return json.loads((root / "docs" / "results" / name).read_text())


def figure(data: dict, name: str) -> float:
    figures = data.get("figures") or data.get("results")
    return figures[name]["value"]


def percent(share: float) -> float:
    """A share (0-1) in per cent: the key step of a quoted figure printed with ``%``."""
    return 100.0 * share


def caption(data: dict, file: str) -> str:
    prov = data["provenance"]
    when = f"commit {prov.get('commit') or '?'}, {str(prov.get('date') or '?')[:10]}"
    load = prov.get("load_average") or {}
    before = load.get("before")
    before = before[0] if isinstance(before, list) else before
    pending = "; to be made again after the sea-surface change" if prov.get("rerun_pending") else ""
    shown = f", load average {before:g} at the start" if isinstance(before, (int, float)) else ""
    return f"*From `docs/results/{file}` (`{prov['command']}`; {when}{shown}{pending}).*\n"


def made_at(data: dict, file: str) -> str:
    """A result file named with the commit, date and load average it was made at."""
    prov = data["provenance"]
    load = (prov.get("load_average") or {}).get("before")
    load = load[0] if isinstance(load, list) else load
    shown = f", load average {load:g}" if isinstance(load, (int, float)) else ""
    pending = ", to be made again after the sea-surface change" if prov.get("rerun_pending") else ""
    when = f"commit {prov.get('commit') or '?'}, {str(prov.get('date') or '?')[:10]}"
    return f"`docs/results/{file}` ({when}{shown}{pending})"


def markdown_table(rows) -> str:
    return "".join("| " + " | ".join(row) + " |\n" for row in rows)


def rmse_rows(d: dict, names, heads: tuple[str, str], fmt: str, scale: float) -> list[tuple]:
    """A tracker study's position RMSE at 5, 10, 20 and 30 min and its mean after 5 min, a row per
    (key, label) of ``names``, each value divided by ``scale`` and printed with ``fmt``."""
    rows = [(heads[0], "5 min", "10 min", "20 min", "30 min", heads[1]), ("---",) * 6]
    for key, label in names:
        r = d["rmse_m"][key]
        rows.append((label, *(fmt.format(r[t] / scale) for t in ("5", "10", "20", "30")),
                     fmt.format(d["mean_rmse_after_5min_m"][key] / scale)))
    return rows


def calibration_rows(calibration: dict, names, head: str = "tracker") -> list[tuple]:
    """How a study's trackers' stated sds hold against the truth (``calibration_after_late_min``
    of its result file, `tools.studies.calibration`): per (key, label) of ``names``, the 90 %
    interval's coverage of range, course and speed, and range's median |error| / sd and mean
    (error / sd)^2 (calibrated: 90 %, 0.67, 1)."""
    return calibration_head(head) + [calibration_row(label, calibration[key]) for key, label in names]


def calibration_head(head: str) -> list[tuple]:
    """The head of a calibration table (`calibration_rows`)."""
    return [(head, "range: 90 % interval holds the truth", "median \\|error\\| / sd", "mean (error / sd)^2",
             "course: 90 % holds", "speed: 90 % holds"), ("---",) * 6]


def calibration_row(label: str, c: dict) -> tuple:
    """One tracker's row of a calibration table from its ``{range, course, speed}`` figures."""
    r = c["range"]
    return (label, f"{100 * r['coverage_90']:.0f} %", f"{r['median_abs_z']:.2f}", _nees(r["mean_sq_z"]),
            f"{100 * c['course']['coverage_90']:.0f} %", f"{100 * c['speed']['coverage_90']:.0f} %")


def range_cell(coverage: float, abs_z_median: float, rms_m: float) -> str:
    """One filter's range figures in one cell: the 90 % interval's coverage, the median
    |error| / sd and an RMS error, "90 % / 0.67 / 1.23 km"."""
    return f"{100 * coverage:.0f} % / {abs_z_median:.2f} / {rms_m / 1000:.2f} km"


RANGE_CELL_HEAD = "90 % holds / median \\|error\\| / sd / RMSE"


def _nees(value: float) -> str:
    """A mean squared normalised error as a page prints it (large ones in powers of ten)."""
    return f"{value:.2f}" if value < 100 else f"{value:.1e}"
