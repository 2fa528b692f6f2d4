"""The ML analysis's manoeuvre tests before and after (tracker.mltma.maneuver): the G&M study of
gm-tv-30km (27 runs; its figures must not get worse) run with the paper's tests and with the
present ones, side by side; written to docs/results/maneuver.json.

    python -m bench.bench_maneuver [OCEAN_DEEP_GRID.nc]   (default: built or reused in out/bench/)
"""

from __future__ import annotations

import json
import sys
import tempfile
import time

from acoustics.grid.formats import RESULT_FORMAT
from bench.harness import Session, bench_grid
from tools.studies import gm
from tracker.mltma import MLParams


def main(grid: str) -> dict:
    session = Session("maneuver")
    result = {"tmakit_format": RESULT_FORMAT, "scenario": "gm-tv-30km", "runs": 27}
    for label, params in (("paper", MLParams(maneuver_curved=False, level_vs_k=False)), ("now", MLParams())):
        with tempfile.TemporaryDirectory() as tmp:
            start = time.perf_counter()
            res = gm.run("gm-tv-30km", grid_path=grid, n=3, out_dir=tmp, seed=0, workers=2, params=params)
            result[label] = {"steady_state": res["steady_state"], "seconds": round(time.perf_counter() - start, 1)}
    session.write(**result)
    return result


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1] if len(sys.argv) > 1 else bench_grid("ocean-deep")), indent=1))
