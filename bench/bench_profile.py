"""Where a table build's time goes: BELLHOP per run type, files, the arrivals' reduction, the
tables' assembly, the resume folder, the dataset or store, and what is left (scheduling, waiting).

``python -m bench.bench_profile [--repeats N] [--workers W]`` writes ``docs/results/build-profile.json``.
Two builds, interleaved, ``--repeats`` times, each in a fresh interpreter as a command runs it
(``process_s`` is its whole time, start-up included; the imports alone are measured apart, as a
fresh interpreter importing what ``grids build`` and ``atlas build`` import); with ``--before DIR``
the same builds of another checkout (the code before a change) in the same turns:

- the shelf-break grid file (12 radials x 3 bands to 30 km, its resume folder, the netCDF), as
  ``tmakit grids build shelf-break`` makes it;
- ocean-deep's flat grid file (10 runs from the class depths to 120 km), the fixed cost's case;
- one atlas table of shelf-break-atlas (its first position and month, the atlas's own depth
  axis), as ``tmakit atlas build`` makes it: the plan (the data boxes read once), the store's
  template, the table's radials and runs, its chunks and ``done`` flag.

The builder's functions are timed where they are called (each wrapped in this process for the
profile), summed over threads: BELLHOP's process time by run type (field runs, the surface's
arrivals runs); the files around it (writing the inputs, the run folder, starting the process);
reading the .shd and .arr files; the arrivals' reduction (``surfaceimage.image_tl_db``); the
resume folder's writes; the assembly of each radial's bands into the tables (the consumer's time
between finished runs); planning (radials sampled, runs written); the dataset and its netCDF, or
the store's template and the table's chunks. "other" is the build's wall time less the sum: the
executor's scheduling and waiting, negative where the worker's work overlaps the assembly.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections import defaultdict
from pathlib import Path

from bench.harness import REPO, Session, command_naming

#: The categories, in the order the table shows them.
CATEGORIES = ("bellhop field runs", "bellhop arrivals runs", "run files and process start", "reading .shd",
              "reading .arr", "arrivals reduction", "resume folder writes", "tables assembly",
              "planning (radials, runs)", "dataset or store")
STARTUP = ("import tools.cli, acoustics.builder.gridfile, acoustics.builder.atlas, acoustics.builder.radial")


class Profile:
    """Seconds per category, summed over threads."""

    def __init__(self):
        self.seconds: dict[str, float] = defaultdict(float)
        self.counts: dict[str, int] = defaultdict(int)
        self._lock = threading.Lock()

    def add(self, category: str, seconds: float, count: int = 1) -> None:
        with self._lock:
            self.seconds[category] += seconds
            self.counts[category] += count

    def timed(self, category: str, fn):
        def wrapper(*args, **kwargs):
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                self.add(category, time.perf_counter() - start)
        return wrapper


@contextlib.contextmanager
def instrumented(profile: Profile):
    """The builder's functions wrapped to feed ``profile``; put back on leaving."""
    from acoustics.bellhop import runner
    from acoustics.builder import atlas, executor, flat, gridfile, radial, runs
    from acoustics.grid import dataset

    saved = []

    def patch(obj, name, new):
        saved.append((obj, name, getattr(obj, name)))
        setattr(obj, name, new)

    def timed(obj, name, category):  # a function the checkout has (the code moves between releases)
        if hasattr(obj, name):
            patch(obj, name, profile.timed(category, getattr(obj, name)))

    patch(runner, "read_shd", profile.timed("reading .shd", runner.read_shd))
    patch(runner, "read_arr", profile.timed("reading .arr", runner.read_arr))
    patch(runs, "image_tl_db", profile.timed("arrivals reduction", runs.image_tl_db))
    run_env = runs.run_env

    def timed_run_env(*args, **kwargs):
        before = dict(profile.seconds)
        start = time.perf_counter()
        result = run_env(*args, **kwargs)
        wall = time.perf_counter() - start
        kind = "bellhop arrivals runs" if result.arrivals is not None else "bellhop field runs"
        profile.add(kind, result.seconds)
        # reading is timed by its own wrapper (other threads' reads may land between: small)
        read = sum(profile.seconds.get(k, 0.0) - before.get(k, 0.0) for k in ("reading .shd", "reading .arr"))
        profile.add("run files and process start", max(wall - result.seconds - read, 0.0))
        return result

    patch(runs, "run_env", timed_run_env)
    patch(executor.ResultCache, "save", profile.timed("resume folder writes", executor.ResultCache.save))
    iter_runs = radial.iter_runs

    def timed_iter_runs(*args, **kwargs):
        it = iter_runs(*args, **kwargs)
        while True:
            try:
                item = next(it)
            except StopIteration:
                return
            start = time.perf_counter()
            yield item
            profile.add("tables assembly", time.perf_counter() - start)

    patch(radial, "iter_runs", timed_iter_runs)
    if hasattr(flat, "iter_runs"):
        patch(flat, "iter_runs", timed_iter_runs)
    for module in (radial, atlas):
        patch(module, "area_radials", profile.timed("planning (radials, runs)", module.area_radials))
    for name in ("plan_radial_runs", "plan_radial_image_runs"):
        patch(radial, name, profile.timed("planning (radials, runs)", getattr(radial, name)))
    timed(flat, "plan_runs", "planning (radials, runs)")
    timed(flat, "flat_dataset", "dataset or store")
    patch(atlas, "plan_atlas", profile.timed("planning (radials, runs)", atlas.plan_atlas))
    timed(radial, "radial_dataset", "dataset or store")
    # the builders that import their dataset function where they call it look it up here
    timed(dataset, "flat_dataset", "dataset or store")
    timed(dataset, "radial_dataset", "dataset or store")
    patch(gridfile, "write_grid", profile.timed("dataset or store", gridfile.write_grid))
    for name in ("_template", "write_table", "set_done"):
        timed(atlas, name, "dataset or store")
    try:
        yield profile
    finally:
        for obj, name, old in reversed(saved):
            setattr(obj, name, old)


def atlas_table_area():
    """shelf-break-atlas with its first position alone and its first month: one table."""
    import envdata
    from acoustics.builder.atlas import plan_atlas

    area = envdata.load_area("shelf-break-atlas")
    plan = plan_atlas(area)
    spec = dataclasses.replace(area.atlas, lat_deg=None, lon_deg=None, spacing_km=None,
                               positions=((float(plan.lat_deg[0]), float(plan.lon_deg[0])),),
                               months=area.atlas.months)
    return dataclasses.replace(area, atlas=spec)


def build_grid_file(folder: Path, workers: int, area: str = "shelf-break") -> tuple[Profile, float, int]:
    from acoustics.builder.gridfile import build_grid_file as build

    profile = Profile()
    with instrumented(profile):
        start = time.perf_counter()
        result = build(area, folder / f"{area}.nc", workers=workers, force=True)
        wall = time.perf_counter() - start
    return profile, wall, result.runs


def build_flat_grid_file(folder: Path, workers: int) -> tuple[Profile, float, int]:
    return build_grid_file(folder, workers, "ocean-deep")


def build_atlas_table(folder: Path, workers: int) -> tuple[Profile, float, int]:
    from acoustics.builder.atlas import build_atlas_file

    area = atlas_table_area()
    profile = Profile()
    with instrumented(profile):
        start = time.perf_counter()
        result = build_atlas_file(area, folder / "table.zarr", workers=workers, force=True)
        wall = time.perf_counter() - start
    return profile, wall, result["runs"]


BUILDS = {"shelf-break grid": build_grid_file, "atlas table": build_atlas_table,
          "ocean-deep grid": build_flat_grid_file}

#: What a fresh interpreter runs for one build: this file's functions on the checkout it starts in.
ONE = """
import importlib.util, json, sys, tempfile, time
from pathlib import Path
start = time.perf_counter()
spec = importlib.util.spec_from_file_location("profile_one", {path!r})
mod = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mod)
with tempfile.TemporaryDirectory() as tmp:
    profile, wall, runs = mod.BUILDS[{build!r}](Path(tmp), {workers})
    if {keep!r} and (Path(tmp) / "shelf-break.nc").exists():
        (Path(tmp) / "shelf-break.nc").replace({keep!r})
print(json.dumps({{"wall": wall, "process": time.perf_counter() - start, "runs": runs,
                  "seconds": dict(profile.seconds), "counts": dict(profile.counts)}}))
"""


def one_build(checkout: Path, build: str, workers: int, keep: str = "") -> dict:
    """One build in a fresh interpreter started in ``checkout`` (its code first on the path), as a
    command runs it: start-up (imports, numba's cache) included in ``process``; the grid file
    kept as ``keep`` when given."""
    code = ONE.format(path=str(Path(__file__).resolve()), build=build, workers=workers, keep=keep)
    out = subprocess.run([sys.executable, "-c", code], cwd=checkout, check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def compare_grids(a: Path, b: Path) -> dict:
    """The largest |difference| of the two shelf-break grids' TL and K where both are finite, and
    whether their NaN cells are the same, dB."""
    import numpy as np
    import xarray as xr

    out = {}
    with xr.open_dataset(a) as ga, xr.open_dataset(b) as gb:
        for name in ("tl_db", "k_db"):
            x, y = ga[name].values, gb[name].values
            both = np.isfinite(x) & np.isfinite(y)
            out[f"{name} max |difference|"] = float(np.max(np.abs(x - y)[both]))
            out[f"{name} same NaN cells"] = bool(np.array_equal(np.isfinite(x), np.isfinite(y)))
    return out


def summary(done: list[dict]) -> dict:
    """Medians over the repeats: wall times, each category, and the rest of the wall time."""
    seconds = {cat: round(statistics.median(d["seconds"].get(cat, 0.0) for d in done), 3) for cat in CATEGORIES}
    seconds["other (scheduling, waiting)"] = round(statistics.median(
        d["wall"] - sum(d["seconds"].get(c, 0.0) for c in CATEGORIES) for d in done), 3)
    return {"wall_s": round(statistics.median(d["wall"] for d in done), 3),
            "process_s": round(statistics.median(d["process"] for d in done), 3),
            "walls_s": [round(d["wall"], 3) for d in done], "runs": done[0]["runs"],
            "bellhop_runs": {k: done[0]["counts"].get(k, 0) for k in ("bellhop field runs", "bellhop arrivals runs")},
            "seconds": seconds}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--before", type=Path, help="a checkout of the code before a change (git archive "
                        "COMMIT | tar -x -C DIR), profiled side by side")
    parser.add_argument("--before-commit", default=None, help="the commit --before holds, for the record")
    args = parser.parse_args(argv)
    # the checkout before is a machine path: the command names it BEFORE (its commit is in the file)
    named = {} if args.before is None else {str(args.before): "BEFORE"}
    session = Session("build-profile", command=command_naming("bench.bench_profile", argv, named))
    sides = {"now": REPO, **({"before": args.before.resolve()} if args.before else {})}
    for checkout in sides.values():  # warm: numba's caches, the data files in the page cache
        one_build(checkout, "atlas table", args.workers)
    done: dict[tuple[str, str], list[dict]] = {(s, b): [] for s in sides for b in BUILDS}
    kept = Path(tempfile.mkdtemp(prefix="tmakit-profile-"))
    session.interleave({f"{s} {b}": (lambda s=s, b=b: done[(s, b)].append(
        one_build(sides[s], b, args.workers, str(kept / f"{s}.nc"))))
        for s, b in done}, args.repeats)
    same = compare_grids(kept / "now.nc", kept / "before.nc") if args.before else None
    shutil.rmtree(kept, ignore_errors=True)
    startup = {s: [] for s in sides}
    for _ in range(args.repeats):
        for s, checkout in sides.items():
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", STARTUP], cwd=checkout, check=True)
            startup[s].append(time.perf_counter() - start)
    out = {}
    for side in sides:
        out[side] = {"startup_s": round(statistics.median(startup[side]), 3),
                     "builds": {b: summary(done[(side, b)]) for b in BUILDS}}
        for b, res in out[side]["builds"].items():
            session.say(f"{side}: {b} wall", res["wall_s"], "s (median)", runs=res["walls_s"])
            for cat, value in res["seconds"].items():
                session.say(f"{side}: {b}: {cat}", value, "s")
        session.say(f"{side}: start-up (imports of a build command)", out[side]["startup_s"], "s",
                    runs=startup[side])
    if same is not None:
        for name, value in same.items():
            session.say(f"now against before: {name}", value, "" if isinstance(value, bool) else "dB")
    session.write(repeats=args.repeats, workers=args.workers, before_commit=args.before_commit, profiles=out,
                  now_against_before=same)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
