"""``simulate --truth bellhop`` of a 60-minute, 20-s-cycle scenario on 2 workers (issue target:
under 5 minutes): the shelf-cross scenario stretched to 60 minutes on the shelf-break grid, the
command timed from start to end, once without a cache and once with it. Written to
docs/results/truth-bellhop.json.

    python -m bench.bench_truth [SHELF_BREAK_GRID.nc]   (default: built or reused in out/bench/)
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from acoustics.grid.formats import RESULT_FORMAT
from bench.harness import REPO as ROOT
from bench.harness import Session, bench_grid, portable
from envdata.areafile import area_path


def main(grid: str) -> dict:
    session = Session("truth-bellhop")
    text = (ROOT / "envdata" / "scenarios" / "shelf-cross.toml").read_text()
    text = text.replace("duration_s = 2400.0", "duration_s = 3600.0").replace('name = "shelf-cross"',
                                                                              'name = "shelf-cross-60min"')
    text = text.replace("speed_mps = 4.5", "speed_mps = 3.0")  # 10.8 km in 60 min: inside the area
    result = {"tmakit_format": RESULT_FORMAT, "grid": portable(grid), "workers": 2,
              "area": str(area_path("shelf-break").relative_to(ROOT))}
    with tempfile.TemporaryDirectory() as tmp:
        sc = Path(tmp) / "sc.toml"
        sc.write_text(text)
        for label in ("first", "cached"):
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "tools.cli", "simulate", str(sc), "--grid", grid, "--out",
                                   str(Path(tmp) / "out"), "--truth", "bellhop", "--workers", "2", "--json",
                                   "--force"], capture_output=True, text=True, cwd=ROOT)
            ok = done.returncode == 0
            report = json.loads(done.stdout.strip().splitlines()[-1]) if ok else {"error": done.stderr}
            result[label] = {"seconds": round(time.perf_counter() - start, 1), "cycles": report.get("cycles"),
                             "returncode": done.returncode}
    result["target_s"] = 300.0
    session.write(**result)
    return result


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1] if len(sys.argv) > 1 else bench_grid("shelf-break")), indent=1))
