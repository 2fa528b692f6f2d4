"""Start-up of the command line: ``tmakit --help`` and ``tmakit COMMAND --help`` (target < 0.5 s,
the median of 5), and what the interpreter imports before argparse runs (``python -X importtime``).

Each command's help runs in a fresh process, the commands in turns (forwards, then backwards),
``--repeats`` times; the figure is the median wall time of each. The import profile is that of
``import tools.cli`` and building the parser: the total, the slowest top-level imports, and
whether numpy, xarray, pandas or matplotlib were among them (they must not be: a command imports
what it needs when it runs). Written to docs/results/startup.json.

    python -m bench.bench_startup [--repeats 5]
"""

from __future__ import annotations

import argparse
import subprocess
import sys

from bench.harness import REPO, Session, median

COMMANDS = ("", "doctor", "areas", "grids", "atlas", "sensitivity", "simulate", "track", "experiment", "locate",
            "demo")
HEAVY = ("numpy", "xarray", "pandas", "matplotlib", "numba", "scipy", "dask", "zarr", "netCDF4", "pyproj")
TARGET_S = 0.5


def _help(command: str) -> None:
    subprocess.run([sys.executable, "-m", "tools.cli", *([command] if command else []), "--help"], cwd=REPO,
                   check=True, capture_output=True)


def import_profile() -> dict:
    """``-X importtime`` of the parser's start-up: total, the ten slowest packages, heavy ones."""
    done = subprocess.run([sys.executable, "-X", "importtime", "-c",
                           "from tools.cli import build_parser; build_parser()"],
                          cwd=REPO, check=True, capture_output=True, text=True)
    rows = []
    for line in done.stderr.splitlines():
        if not line.startswith("import time:") or "|" not in line or "cumulative" in line:
            continue
        _, cumulative, name = line.removeprefix("import time:").split("|")
        rows.append((name.rstrip(), int(cumulative)))
    top = [(n.strip(), us) for n, us in rows if not n.startswith("  ")]  # imported by the parser itself
    return {"total_ms": round(sum(us for _, us in top) / 1000.0, 1),
            "slowest_ms": {n: round(us / 1000.0, 1) for n, us in sorted(top, key=lambda r: -r[1])[:10]},
            "heavy_imported": sorted({n.strip().split(".")[0] for n, _ in rows} & set(HEAVY))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    session = Session("startup")
    times = session.interleave({c or "tmakit": (lambda c=c: _help(c)) for c in COMMANDS}, args.repeats)
    for name, runs in times.items():
        label = "tmakit_help" if name == "tmakit" else f"tmakit_{name}_help"
        session.say(label, median(runs), f"s (median of {args.repeats}; target < {TARGET_S:g})", runs=runs)
    worst = max(median(r) for r in times.values())
    session.say("slowest_help", worst, "s")
    profile = import_profile()
    session.say("parser_imports_total", profile["total_ms"], "ms (-X importtime)")
    session.say("parser_imports_heavy", ", ".join(profile["heavy_imported"]) or "none")
    session.write(repeats=args.repeats, target_s=TARGET_S, import_profile=profile)


if __name__ == "__main__":
    main()
