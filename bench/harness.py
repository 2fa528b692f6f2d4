"""The one harness every benchmark uses: repeats and medians, workloads interleaved, the load
average before and after, and the result file with its provenance.

A benchmark is a module of this package, run from the repository's root as
``python -m bench.NAME [options]`` (``make bench`` runs them all, ``bench/run.py``). It opens a
`Session`, measures, `say`s each figure and `write`s once:

    session = Session("grids")                    # the load average now
    times = session.interleave({"one": build_1, "two": build_2}, repeats=3)
    session.say("build_1_worker", median(times["one"]), "s (median)", runs=times["one"])
    session.write()                               # docs/results/grids.json

The file holds ``provenance`` (the command that made it, the commit and whether the tree was
clean, the date, the load average before and after, the machine's cores and memory, and the
versions of the packages and the BELLHOP that matter) and ``figures`` (each with its value,
unit and the repeats behind it), and whatever else the benchmark adds (``write(**context)``).
The machines are shared: read ratios measured side by side, not absolute times.
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Mapping
from importlib import metadata
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
RESULTS_DIR = REPO / "docs" / "results"
#: The distributions whose versions a result file records (those installed).
PACKAGES = ("numpy", "xarray", "pandas", "netCDF4", "numba", "zarr", "dask", "distributed", "pyproj",
            "easypyram", "matplotlib")


def median(values) -> float:
    return float(statistics.median(values))


def load_average() -> list[float]:
    """The 1, 5 and 15-minute load averages, rounded to 0.01."""
    return [round(x, 2) for x in os.getloadavg()]


def git_state() -> tuple[str | None, bool | None]:
    """The short commit of the checkout and whether its tracked files are as committed, the result
    files apart: a benchmark that follows another in one checkout (``make bench``) finds the first
    one's file written in docs/results, which changes no code it measures."""
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, capture_output=True,
                                text=True, timeout=10).stdout.strip() or None
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".",
                                ":(exclude)docs/results"], cwd=REPO,
                               capture_output=True, text=True, timeout=30).stdout.strip()
    except OSError:
        return None, None
    return commit, commit is not None and not dirty


def machine() -> dict:
    """Cores and memory of this machine."""
    try:
        memory_gib = round(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2 ** 30, 1)
    except (ValueError, OSError, AttributeError):
        memory_gib = None
    return {"cores": os.cpu_count(), "memory_gib": memory_gib}


def versions(extra: Mapping[str, str] | None = None) -> dict:
    """Python, tmakit, the packages of `PACKAGES` that are installed and the BELLHOP in use."""
    out = {"python": sys.version.split()[0]}
    for name in ("tmakit", *PACKAGES):
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            pass
    try:
        from acoustics.bellhop.exe import find_bellhop

        out["bellhop"] = find_bellhop().version
    except Exception as exc:  # noqa: BLE001 - a benchmark without BELLHOP still records the rest
        out["bellhop"] = f"not found ({type(exc).__name__})"
    out.update(extra or {})
    return out


def command_line() -> str:
    """How this process was started, as one would type it from the repository's root."""
    main = sys.modules.get("__main__")
    spec = getattr(main, "__spec__", None)
    args = ["python", "-m", spec.name] if spec is not None else ["python", *sys.argv[:1]]
    return shlex.join([*args, *sys.argv[1:]])


def command_naming(module: str, argv, names: Mapping[str, str]) -> str:
    """``python -m module ARGS`` (``argv``, default this process's) with each machine path among
    the arguments shown by its name in ``names`` (a checkout: BEFORE, AFTER; its commit is in the
    result file)."""
    args = sys.argv[1:] if argv is None else argv
    return shlex.join(["python", "-m", module, *(names.get(a, a) for a in args)])


def portable(command: str) -> str:
    """``command`` as one types it from the repository's root on any machine: the checkout's own
    path and an interpreter's absolute path (a venv's ``.../bin/python``) taken out."""
    command = re.sub(r"(?<![\w.-])/\S*/bin/python[0-9.]*(?=\s|$)", "python", command)
    return command.replace(str(REPO) + "/", "")


def portable_path(path) -> str:
    """A file's path as a result file may name it on any machine: relative to the repository when
    inside it, relative to the environment (``VENV/...``) when inside the running Python's prefix
    (a venv outside the checkout), else its name alone."""
    p = Path(path)
    if not p.is_absolute():
        return str(p)
    for root, shown in ((REPO, ""), (Path(sys.prefix), "VENV/")):
        if p.is_relative_to(root):
            return shown + str(p.relative_to(root))
    return p.name


def provenance(*, command: str | None = None, load_before: list[float] | None = None,
               extra_versions: Mapping[str, str] | None = None,
               git: tuple[str | None, bool | None] | None = None) -> dict:
    """What makes a result file traceable (see the module docstring); ``git`` is the checkout's
    state when the measurement began (default: now)."""
    commit, clean = git if git is not None else git_state()
    return {"command": portable(command or command_line()), "commit": commit, "tree_clean": clean,
            "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "load_average": {"before": load_before, "after": load_average()},
            "machine": machine(), "versions": versions(extra_versions)}


def write_result(name: str, data: Mapping, *, provenance_data: Mapping) -> Path:
    """``docs/results/NAME.json`` (NAME may hold a folder): ``provenance`` then ``data``,
    written atomically."""
    path = RESULTS_DIR / f"{name}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps({"provenance": dict(provenance_data), **data}, indent=1, default=str) + "\n")
    tmp.replace(path)
    print(f"# wrote {path.relative_to(REPO)}", flush=True)
    return path


class Session:
    """One benchmark run: its figures, the load average when it began, and its result file."""

    def __init__(self, name: str, *, command: str | None = None):
        self.name = name
        self.command = command
        self.load_before = load_average()
        self.git = git_state()  # the code measured, before anything is written
        self.figures: dict[str, dict] = {}

    def say(self, name: str, value, unit: str = "", *, runs=None) -> None:
        """Print one figure, ``name: value unit``, and keep it; ``runs`` are the repeats a
        median came from."""
        text = f"{value:.4g}" if isinstance(value, float) else str(value)
        print(f"{name}: {text} {unit}".rstrip(), flush=True)
        entry = {"value": value, "unit": unit}
        if runs is not None:
            entry["runs"] = [round(float(r), 4) for r in runs]
        self.figures[name] = entry

    def interleave(self, workloads: Mapping[str, Callable[[], object]], repeats: int) -> dict[str, list[float]]:
        """Wall times, s, of each workload ``repeats`` times, in turns A B C, C B A, A B C, ...
        so that a change of the machine's load falls on all alike."""
        names = list(workloads)
        times = {n: [] for n in names}
        for rep in range(repeats):
            for n in names if rep % 2 == 0 else names[::-1]:
                start = time.perf_counter()
                workloads[n]()
                times[n].append(time.perf_counter() - start)
        return times

    def repeat(self, fn: Callable[[], object], repeats: int) -> list[float]:
        """Wall times, s, of ``repeats`` calls of ``fn``."""
        return self.interleave({"one": fn}, repeats)["one"]

    def write(self, *, extra_versions: Mapping[str, str] | None = None, **context) -> Path:
        """docs/results/NAME.json: the provenance, ``context`` and the figures said."""
        data = {**context, **({"figures": self.figures} if self.figures else {})}
        return write_result(self.name, data, provenance_data=provenance(
            command=self.command, load_before=self.load_before, extra_versions=extra_versions, git=self.git))


def bench_grid(area: str) -> str:
    """The built-in area's BELLHOP grid in out/bench/, built or reused (for a benchmark run with
    no grid given, as ``make bench`` runs them)."""
    from acoustics.builder.gridfile import build_grid_file

    return str(build_grid_file(area, REPO / "out" / "bench" / f"{area}-bellhop.nc", workers=2).file)


def raw_bellhop_each(runs, exe) -> list[float]:
    """The wall time of bellhop.exe itself on each run's files (the .env and the files beside it,
    such as a source pattern's .sbp), one at a time, s."""
    out = []
    for run in runs:
        with tempfile.TemporaryDirectory() as tmp:
            (Path(tmp) / "raw.env").write_text(run.env)
            for suffix, text in run.files:
                (Path(tmp) / f"raw.{suffix}").write_text(text)
            start = time.perf_counter()
            subprocess.run([str(exe), "raw"], cwd=tmp, check=True, capture_output=True)
            out.append(time.perf_counter() - start)
    return out


def raw_bellhop_seconds(runs, exe) -> float:
    """Sum of the wall times of bellhop.exe itself on the runs' files, one at a time: what a
    build's BELLHOP time is measured against."""
    return sum(raw_bellhop_each(runs, exe))


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
