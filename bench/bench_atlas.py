"""Benchmarks of atlases (README "Atlases").

Run with ``python -m bench.bench_atlas [--repeats N]``; writes ``docs/results/atlas.json``. The
area is the atlas tests' (tests/data/atlas-test.toml, its climatology written by the data build
``python -m tests.fixtures.sample_data --monthly``).

- Speed: an atlas of the test area (the shelf-break relief, 2 months x 6 positions = 12 tables)
  with tables of 12 radials x 3 bands to 10 km (36 BELLHOP runs, BELLHOP's own beam count, a
  25 m ray step as the built-in shelf-break area: about 5 s of BELLHOP a table), built with
  ``--force`` on a Dask LocalCluster on 127.0.0.1 of 1 and of 2 worker processes (one thread
  each; the cluster started before the build's clock), in turn, ``--repeats`` times; each
  build's own sum of BELLHOP process times is the raw serial time of its runs. Targets: 2
  workers within 1.05 x half that raw time; 2 workers vs 1 >= 1.9x. Why these tables: what the
  ratios measure is a table's work outside BELLHOP (sampling its radials, writing the .env
  files, reading the .shd files, the region write; about 0.1 s) and the build's fixed cost
  against its BELLHOP time. The tests' tables (4 radials, one band, 300 beams: 12 runs of 20-50
  ms) made that share 15-20 % and measured the benchmark; a real table (README's budget: 36
  radials x 3 bands to 50 km, 108 runs of 0.78 s, 84 s) makes it 0.1 %; these tables, 2-3 %,
  are the smallest whose share is of the order of the 5 % the target allows, and the 12 of
  them build in about a minute.
- Memory: the peak resident size of the building process (``atlas build`` in a child process, 2
  worker threads; BELLHOP's own processes are not counted) on the tests' atlas (4 km lattice, 40
  tables) and on one about 4x larger (a 2 km lattice): flat, < 1 GiB.
- The store: open, one table slab read, ``values_at`` of 10 000 points, size against float32 raw.
- Cost per table against the number of TL depths (the atlas's own depth axis).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.harness import REPO as ROOT
from bench.harness import Session

#: The atlas tests' area, as data (the tests read it too).
ATLAS_TOML = ROOT / "tests" / "data" / "atlas-test.toml"

CHILD = """
import json, resource, sys
import envdata
from acoustics.builder.atlas import build_atlas_file
area = envdata.load_area({area!r})
if {cluster!r}:
    from distributed import LocalCluster
    with LocalCluster(n_workers={workers}, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as cluster:
        info = build_atlas_file(area, {out!r}, scheduler=cluster.scheduler_address, force=True)
else:
    info = build_atlas_file(area, {out!r}, workers={workers}, force=True)
info["peak_rss_mib"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({{k: info[k] for k in ("tables", "runs", "bellhop_seconds", "wall_seconds", "peak_rss_mib",
                                        "raw_bytes", "positions", "workers")}}))
"""

#: The speed benchmark's tables: 12 radials x 3 bands (the built-in shelf-break area's), 100 m
#: range cells to 10 km, BELLHOP's own beam count and a 25 m ray step (module docstring).
SPEED_BANDS = """[[bands]]
name = "FB1"
low_hz = 100.0
high_hz = 300.0

[[bands]]
name = "FB2"
low_hz = 300.0
high_hz = 1000.0

[[bands]]
name = "FB3"
low_hz = 1000.0
high_hz = 3000.0
"""


def write_atlas_area(folder: Path, *, spacing_km: float) -> Path:
    """The atlas tests' area in ``folder`` with this lattice spacing, its climatology and relief
    beside it (written by the data build, a command of the tests' fixtures)."""
    if not (folder / "woa_monthly_t.nc").exists():
        subprocess.run([sys.executable, "-m", "tests.fixtures.sample_data", "--monthly", str(folder)],
                       cwd=ROOT, check=True)
    path = folder / "atlas-test.toml"
    path.write_text(ATLAS_TOML.read_text().replace("spacing_km = 8.0", f"spacing_km = {spacing_km}"))
    return path


def area_file(folder: Path, spacing_km: float, step_deg: float = 30.0, depth_step_m: float = 50.0) -> Path:
    path = write_atlas_area(folder, spacing_km=spacing_km)
    text = path.read_text().replace("step_deg = 90.0", f"step_deg = {step_deg}")
    text = text.replace("depth_step_m = 50.0\n\n[water]", f"depth_step_m = {depth_step_m}\n\n[water]")
    path.write_text(text)
    return path


def speed_area_file(folder: Path) -> Path:
    """The speed benchmark's area: the test area with the tables of ``SPEED_BANDS``."""
    path = area_file(folder, spacing_km=8.0)
    text = path.read_text()
    one_band = text[text.index("[[bands]]"):text.index("[[classes]]")]
    text = text.replace(one_band, SPEED_BANDS + "\n").replace("range_step_m = 200.0", "range_step_m = 100.0")
    path.write_text(text.replace("n_beams = 300\nstep_m = 50.0", "step_m = 25.0"))
    return path


def build(area: Path, out: Path, workers: int, cluster: bool = False) -> dict:
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", CHILD.format(area=str(area), out=str(out), workers=workers,
                                                              cluster=cluster)],
                          capture_output=True, text=True, check=True, cwd=ROOT)
    info = json.loads(done.stdout.strip().splitlines()[-1])
    info["process_seconds"] = time.perf_counter() - start
    return info


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    session = Session("atlas")
    results: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        area = speed_area_file(tmp / "speed")
        one, two = [], []
        load = [os.getloadavg()]  # per build, beside the session's before and after
        for i in range(args.repeats):
            order = (1, 2) if i % 2 == 0 else (2, 1)
            for workers in order:
                info = build(area, tmp / f"w{workers}.zarr", workers, cluster=True)
                load.append(os.getloadavg())
                (one if workers == 1 else two).append(info)
                print(f"repeat {i + 1}: {workers} worker(s): {info['wall_seconds']:.2f} s, BELLHOP "
                      f"{info['bellhop_seconds']:.2f} s, {info['runs']} runs", flush=True)
        w1 = statistics.median(x["wall_seconds"] for x in one)
        w2 = statistics.median(x["wall_seconds"] for x in two)
        raw = statistics.median(x["bellhop_seconds"] for x in one)
        ratio_half = statistics.median(b["wall_seconds"] / (0.5 * a["bellhop_seconds"]) for a, b in zip(one, two))
        # what the machine allowed: 2 workers over half their own BELLHOP sum (on a shared machine
        # each run of two at once takes longer than alone; this ratio is the build's own cost)
        own = statistics.median(b["wall_seconds"] / (0.5 * b["bellhop_seconds"]) for b in two)
        speedup = statistics.median(a["wall_seconds"] / b["wall_seconds"] for a, b in zip(one, two))
        results["speed"] = {
            "tables": one[0]["tables"], "runs": one[0]["runs"], "positions": one[0]["positions"],
            "build_1_worker_s": round(w1, 2), "build_2_workers_s": round(w2, 2),
            "raw_serial_bellhop_s": round(raw, 2), "per_run_ms": round(1000 * raw / one[0]["runs"], 1),
            "two_workers_over_half_raw": round(ratio_half, 3), "target_two_workers_over_half_raw": 1.05,
            "bellhop_2_workers_s": round(statistics.median(x["bellhop_seconds"] for x in two), 2),
            "two_workers_over_half_their_own_bellhop": round(own, 3),
            "two_vs_one_worker": round(speedup, 3), "target_two_vs_one": 1.9,
            "process_seconds_2_workers": round(statistics.median(x["process_seconds"] for x in two), 2),
            "workers": "Dask LocalCluster on 127.0.0.1, worker processes of one thread",
            "bands": 3, "radials": 12, "range_max_m": 10000.0,
            "repeats": args.repeats, "load_average_1_min_per_build": [round(x[0], 2) for x in load],
            "load_average_1_min_median": round(statistics.median(x[0] for x in load), 2)}
        print(json.dumps(results["speed"]), flush=True)
        small = area_file(tmp / "small", spacing_km=4.0)  # memory: the tests' tables, threads
        small_info = build(small, tmp / "small.zarr", 2)
        big_area = area_file(tmp / "big", spacing_km=2.0)
        big = build(big_area, tmp / "big.zarr", 2)
        results["memory"] = {"small_tables": small_info["tables"],
                             "small_peak_rss_mib": round(small_info["peak_rss_mib"], 1),
                             "large_tables": big["tables"], "large_peak_rss_mib": round(big["peak_rss_mib"], 1),
                             "target_mib": 1024}
        print(json.dumps(results["memory"]), flush=True)

        from acoustics.grid.atlas.sample import values_at
        from acoustics.grid.atlas.store import open_store

        store = tmp / "big.zarr"
        t = time.perf_counter()
        atlas = open_store(store)
        open_s = time.perf_counter() - t
        slab_times = []
        for o in range(min(20, atlas.lat_deg.size)):
            t = time.perf_counter()
            atlas.slab(1, o)
            slab_times.append(time.perf_counter() - t)
        rng = np.random.default_rng(1)
        rows = atlas.row_col
        lat = atlas.lat_deg[rows[:, 0] <= 1]
        n = 10_000
        plat = rng.uniform(lat.min(), lat.max(), n)
        plon = rng.uniform(atlas.lon_deg.min(), atlas.lon_deg.max() - 1e-6, n)
        t = time.perf_counter()
        values_at(atlas, lat_deg=plat, lon_deg=plon, month=rng.choice([2, 8], n), cls_name="TV", band_name="FB2",
                  bearing_deg=rng.uniform(0, 360, n), range_m=rng.uniform(200, 10000, n))
        sample_s = time.perf_counter() - t
        size = sum(f.stat().st_size for f in store.rglob("*") if f.is_file())
        results["store"] = {"tables": int(atlas.done.size), "open_s": round(open_s, 4),
                            "slab_read_ms_median": round(1000 * statistics.median(slab_times), 2),
                            "sample_10000_points_s": round(sample_s, 3), "store_bytes": size,
                            "raw_float32_bytes": int(big["raw_bytes"]),
                            "store_over_raw": round(size / big["raw_bytes"], 3),
                            "targets": {"open_s": 1.0, "slab_read_ms": 50.0, "sample_s": 2.0}}
        print(json.dumps(results["store"]), flush=True)
        depth_cost = []
        for step in (100.0, 25.0, 10.0):
            a = area_file(tmp / f"d{int(step)}", spacing_km=8.0, depth_step_m=step)
            info = build(a, tmp / f"d{int(step)}.zarr", 1)
            depths = int(open_store(tmp / f"d{int(step)}.zarr").depth_m.size)
            depth_cost.append({"depth_step_m": step, "depths": depths, "tables": info["tables"],
                               "bellhop_s_per_table": round(info["bellhop_seconds"] / info["tables"], 3)})
        results["cost_per_table_vs_depths"] = depth_cost
        print(json.dumps(depth_cost), flush=True)
    session.write(**results)
    print(json.dumps(results["speed"], indent=1))


if __name__ == "__main__":
    main()
