"""What a benchmark measured: printed as ``name: value unit`` lines, written to docs/results/NAME.json;
and `cli_with_rusage`, the way the benchmarks time a ``tmakit`` command.

Each ``bench_NAME.py`` calls `say` for every figure and `write` once at the end; the JSON file
holds the figures with their units, the machine's cores, its load average at the start and the
end (the machines are shared: read a ratio measured side by side, not an absolute time), the
commit and the date. The docs quote these files.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
RESULTS_DIR = REPO / "docs" / "results"

_figures: dict[str, dict] = {}
_load_at_start = os.getloadavg()[0]


def _git(*args: str) -> str | None:
    try:
        return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True, timeout=10).stdout.strip()
    except OSError:
        return None


# the code measured: the commit and whether tracked files differed from it, when the benchmark
# started (a benchmark that writes result files into the tree leaves it changed at its end)
_commit = _git("rev-parse", "--short", "HEAD") or None
_status = _git("status", "--porcelain", "--untracked-files=no")
_tree_clean = None if _status is None else _status == ""


def say(name: str, value, unit: str = "", *, runs: list[float] | None = None) -> None:
    """Print one figure and keep it for `write`; ``runs`` are the repeats a median came from."""
    text = f"{value:.4g}" if isinstance(value, float) else str(value)
    print(f"{name}: {text} {unit}".rstrip(), flush=True)
    entry = {"value": value, "unit": unit}
    if runs is not None:
        entry["runs"] = [round(float(r), 4) for r in runs]
    _figures[name] = entry


def median(values) -> float:
    return float(statistics.median(values))


def write(name: str, **context) -> Path:
    """Write the figures said so far to docs/results/NAME.json (atomically) and return its path."""
    data = {"bench": f"bench/bench_{name}.py",
            "command": " ".join(["python", f"bench/bench_{name}.py", *sys.argv[1:]]), "commit": _commit,
            "tree_clean": _tree_clean,
            "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "cores": os.cpu_count(), "memory_gib": _memory_gib(), "versions": _versions(),
            "load_average_at_start": round(_load_at_start, 2),
            "load_average_at_end": round(os.getloadavg()[0], 2), **context, "results": _figures}
    RESULTS_DIR.mkdir(parents=True, exist_ok=True)
    path = RESULTS_DIR / f"{name}.json"
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=1, default=str) + "\n")
    tmp.replace(path)
    print(f"# wrote {path.relative_to(REPO)}", flush=True)
    return path


def _memory_gib() -> float | None:
    """The machine's memory, GiB (None where /proc/meminfo is not there)."""
    try:
        kib = next(int(line.split()[1]) for line in Path("/proc/meminfo").read_text().splitlines()
                   if line.startswith("MemTotal:"))
    except (OSError, StopIteration, ValueError):
        return None
    return round(kib / 2 ** 20, 1)


def _versions() -> dict:
    """Python's and the numerical packages' versions."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": sys.version.split()[0]}
    for pkg in ("numpy", "numba", "xarray", "aubellhop"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            pass
    return out


def cli_with_rusage(args: list[str]) -> tuple[float, float, dict]:
    """Run ``tmakit ARGS --json`` in a child process: wall time (s), peak resident size of the
    largest process it waited for (MiB), and its JSON report."""
    start = time.perf_counter()
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen([sys.executable, "-m", "tools.cli", *args, "--json"], cwd=REPO,
                                stdout=out, stderr=err, text=True)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        out.seek(0)
        err.seek(0)
        if status != 0:
            raise SystemExit(f"bench: tmakit {' '.join(args)} failed: {err.read()}")
        return wall, usage.ru_maxrss / 1024.0, json.loads(out.read())
