"""The ML analysis's manoeuvre tests before and after (tracker.mltma.maneuver): the G&M study of
gm-tv-30km (27 runs; its figures must not get worse) run with the paper's tests and with the
present ones, side by side; written to docs/results/maneuver.json.

    python bench/bench_maneuver.py OCEAN_DEEP_GRID.nc
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

from acoustics.grid.formats import RESULT_FORMAT
from tools.studies import gm
from tracker.mltma import MLParams

OUT = Path(__file__).resolve().parents[1] / "docs" / "results" / "maneuver.json"


def main(grid: str) -> dict:
    result = {"tmakit_format": RESULT_FORMAT, "scenario": "gm-tv-30km", "runs": 27}
    for label, params in (("paper", MLParams(maneuver_curved=False, level_vs_k=False)), ("now", MLParams())):
        with tempfile.TemporaryDirectory() as tmp:
            start = time.perf_counter()
            res = gm.run("gm-tv-30km", grid_path=grid, n=3, out_dir=tmp, seed=0, workers=2, params=params)
            result[label] = {"steady_state": res["steady_state"], "seconds": round(time.perf_counter() - start, 1)}
    OUT.write_text(json.dumps(result, indent=1) + "\n")
    return result


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1]), indent=1))
