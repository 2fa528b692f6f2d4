"""Run every benchmark of this package (``bench_*.py``), one after the other, each in its own process.

Each prints one line per figure, ``name: value unit``, and writes its result file. ``python -m
bench.run grids startup`` runs only bench_grids and bench_startup.
"""

from __future__ import annotations

import subprocess
import sys

from bench.harness import REPO


def main(argv: list[str]) -> int:
    names = sorted(p.stem for p in (REPO / "bench").glob("bench_*.py"))
    if argv:
        names = [n for n in names if n.removeprefix("bench_") in argv]
    status = 0
    for name in names:
        print(f"# {name}", flush=True)
        status |= subprocess.run([sys.executable, "-m", f"bench.{name}"], cwd=REPO).returncode
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
