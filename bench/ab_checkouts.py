"""The same workloads on two checkouts of tmakit, interleaved: is one slower than the other?

    python -m bench.ab_checkouts BEFORE_DIR AFTER_DIR [--repeats 3] [--name ab-refactor] [--atlas STORE]

Each workload runs in a fresh process with the checkout first on the import path and the same Python
and BELLHOP (this venv's), alternately A B, B A, A B, ... so that drift in the machine's load falls
on both; the figure is the median over the repeats and the ratio after / before of those medians.
Workloads: the ``grids build`` of ocean-deep and of shelf-break on 2 workers (wall time of the
command), a small ``atlas build`` (the built-in atlas area with 4 radials) on 2 workers, on an atlas
both sides read (``--atlas``: the simulator and the ML analysis, then the particle filter, asking
the tables where the observer is every cycle, and ``atlas sample`` of 10 000 points), one cycle of
the ML tracker with 3 class hypotheses and 220-240 bearings on the tack (as bench_gm.py, on the
Urick grid: no BELLHOP in it), the compiled particle filter's throughput on bearings (one filter,
as bench_rpf.py), and ``tmakit --help`` (the start-up every command pays).
The workloads' code runs on either side of the studies' move to tools/ (it falls back to the old
module paths). Written to docs/results/NAME.json by the harness. Not part of ``make bench``: it
compares a change with its parent.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from bench.harness import command_naming, git_state, load_average, provenance, write_result

GRIDS_BUILD = """
import subprocess, sys, time, tempfile, os
out = os.path.join(tempfile.mkdtemp(), "g.nc")
t = time.perf_counter()
subprocess.run([sys.executable, "-m", "tools.cli", "grids", "build", "{area}", "--out", out,
                "--workers", "2"], check=True, capture_output=True)
print(time.perf_counter() - t)
"""

# the built-in atlas area with 4 radials (its 6 positions, 1 month): a small atlas build
ATLAS_BUILD = """
import os, subprocess, sys, tempfile, time
from pathlib import Path
import envdata
src = Path(envdata.area_path("shelf-break-atlas"))
text = src.read_text().replace("step_deg = 30.0", "step_deg = 90.0").replace('"data/', f'"{src.parent}/data/')
folder = Path(tempfile.mkdtemp())
(folder / "a.toml").write_text(text)
t = time.perf_counter()
subprocess.run([sys.executable, "-m", "tools.cli", "atlas", "build", str(folder / "a.toml"), "--out",
                str(folder / "a.zarr"), "--workers", "2"], check=True, capture_output=True)
print(time.perf_counter() - t)
"""
# the follow study's crossing of the slope on an atlas both sides read ($TMAKIT_AB_ATLAS, built once):
# the simulator and a tracker asking the tables where the observer is every cycle
ATLAS_TRACK = """
import os, time, numpy as np
from acoustics.grid.opentables import open_tables
from tracker.scenario import load_scenario
from tracker.simulate import simulate
from tracker.track import track
t = time.perf_counter()
tables = open_tables(os.environ["TMAKIT_AB_ATLAS"])
m, _ = simulate(load_scenario("shelf-cross"), tables, np.random.default_rng(0))
if "{method}" == "rpf":
    track(tables, m, method="rpf", rng=np.random.default_rng(1))  # compiled once
    t = time.perf_counter()
track(tables, m, method="{method}", rng=np.random.default_rng(1))
print(time.perf_counter() - t)
"""
# tmakit atlas sample on 10 000 points of that atlas
ATLAS_SAMPLE = """
import os, subprocess, sys, tempfile, time
import numpy as np
from pathlib import Path
store = os.environ["TMAKIT_AB_ATLAS"]
rng = np.random.default_rng(1)
folder = Path(tempfile.mkdtemp())
rows = ["obs_lat_deg,obs_lon_deg,month,class,band,bearing_deg,range_m"]
rows += [f"{la:.5f},{lo:.5f},0,TV,FB2,{b:.1f},{r:.0f}" for la, lo, b, r in zip(
    rng.uniform(42.88, 43.02, 10000), rng.uniform(4.95, 5.03, 10000), rng.uniform(0, 360, 10000),
    rng.uniform(200, 19000, 10000))]
(folder / "p.csv").write_text(chr(10).join(rows) + chr(10))
t = time.perf_counter()
subprocess.run([sys.executable, "-m", "tools.cli", "atlas", "sample", store, "--points", str(folder / "p.csv"),
                "--out", str(folder / "o.csv")], check=True, capture_output=True)
print(time.perf_counter() - t)
"""

#: Each snippet prints one number (seconds, or particle-steps per second) and runs in the
#: checkout's directory with the checkout first on sys.path.
WORKLOADS = {
    **{f"grids_build_{area.replace('-', '_')}_2_workers_s": (GRIDS_BUILD.format(area=area), "lower")
       for area in ("ocean-deep", "shelf-break")},
    "ml_cycle_3_classes_240_bearings_ms": ("""
import dataclasses, time, numpy as np, envdata, acoustics
from tracker.mltma import MLTracker
from tracker.scenario import load_scenario
from tracker.simulate import simulate
grid = acoustics.build_grid(envdata.load_area("ocean-deep"), model="urick")
try:
    from acoustics.grid.opentables import open_tables
    grid = open_tables(grid)
except (ImportError, TypeError):  # before the one way in took a dataset
    try:
        from acoustics.grid.tables import as_tables
        grid = as_tables(grid)
    except ImportError:  # the checkout before the typed face takes the dataset
        pass
sc = load_scenario("gm-tv-30km")
sc = dataclasses.replace(sc, target_tacks=(dataclasses.replace(sc.target_tacks[0], duration_s=2400.0),))
m, _ = simulate(sc, grid, np.random.default_rng(0))
trk = MLTracker(grid, capacity=len(m))
vx, vy = m.obs_velocity_mps()
lat = []
for i in range(len(m)):
    t0 = time.perf_counter()
    trk.update_from(m, i, obs_vel=(vx[i], vy[i]))
    lat.append(time.perf_counter() - t0)
print(1000.0 * float(np.median(lat[-20:])))
""", "lower"),
    "rpf_one_filter_bearings_msteps_per_s": ("""
import math, time, numpy as np
from tracker import rpf
try:
    from tools.studies.idm_scenarios import get_scenario
except ImportError:  # a checkout before the studies moved to tools/
    from tracker.studies.idm_scenarios import get_scenario
sc = get_scenario("idm-static")  # as bench_rpf._scenario
t = sc.t_s
obs = sc.observer_state(t)
rel = sc.target_state(t) - obs
b = rpf.bearing_rad(rel[:, 0], rel[:, 1]) + math.radians(1.5) * np.random.default_rng(1).standard_normal(t.size)
cfg = rpf.RpfConfig(n_particles=5000)
rpf.run_batch(t_s=t[:5], obs_state=obs[:5], bearing_rad_meas=b[None, :5], level_db_meas=None,
              k_profiles=None, cfg=cfg, rng=np.random.default_rng(0))  # compile
best = 0.0
for i in range(3):
    s = time.perf_counter()
    rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b[None], level_db_meas=None,
                  k_profiles=None, cfg=cfg, rng=np.random.default_rng(2 + i))
    best = max(best, t.size * 5000 / (time.perf_counter() - s))
print(best / 1e6)
""", "higher"),
    "atlas_build_6_tables_2_workers_s": (ATLAS_BUILD, "lower"),
    "atlas_simulate_and_track_ml_s": (ATLAS_TRACK.format(method="ml"), "lower"),
    "atlas_track_rpf_s": (ATLAS_TRACK.format(method="rpf"), "lower"),
    "atlas_sample_10000_points_s": (ATLAS_SAMPLE, "lower"),
    **{f"rpf_{kind}_shelf_nps_mpc_per_cpu_s": ("""
import os, time, numpy as np, acoustics
from envdata.classes import SourceLevelModel
from tracker.rpf import RpfConfig, run_batch
from tracker.rpf.track import cycle_profiles
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch
open_ = getattr(acoustics, "open_tables", None) or acoustics.open_grid  # before the one way in
tables = open_(os.environ["TMAKIT_AB_SHELF_GRID"])  # the shelf-nps filter of the depth study
sc = load_scenario("shelf-nps")
ic = tables.class_index(sc.target_class)
sim = simulate_batch(sc, tables, np.random.default_rng(0), dk_db=np.zeros(20))
cls = tables.classes[ic]
r0 = float(np.mean(sim.range_m[:, 0]))
cfg = RpfConfig(n_particles=2000, bearing_sigma_deg=float(np.median(sim.bearing_sigma_deg)), level_sigma_db=1.5,
                range_mean_m=r0, range_sd_m=0.25 * r0, speed_mean_mps=cls.speed_mean_mps,
                speed_sd_mps=cls.speed_sd_mps, shrink=True, sl_offset_sd_db=float(np.hypot(2.5, 2.0)))
obs = np.stack([sim.obs_x_m, sim.obs_y_m, np.gradient(sim.obs_x_m, sim.t_s),
                np.gradient(sim.obs_y_m, sim.t_s)], axis=-1)
common = dict(t_s=sim.t_s, obs_state=obs, bearing_rad_meas=np.radians(sim.bearing_deg),
              level_db_meas=sim.level_db[:, :, 0], cfg=cfg, source_level_model=SourceLevelModel.P0,
              p0_db=cls.noise_mean_db)
profiles = cycle_profiles(tables, ic, 0, np.full(sim.t_s.size, sim.obs_depth_m), sim.bearing_deg[0])
def go(seed):
    run_batch(k_profiles=profiles, rng=np.random.default_rng(seed), **common)
go(0)  # compile (or load the cache) outside the timing
best = 0.0
for i in range(3):
    c = time.process_time()
    go(1 + i)
    best = max(best, 20 * 2000 * sim.t_s.size / (time.process_time() - c))
print(best / 1e6)
""", "higher") for kind in ("fixed_depth",)},
    "tmakit_help_s": ("""
import subprocess, sys, time
t = time.perf_counter()
subprocess.run([sys.executable, "-m", "tools.cli", "--help"], check=True, capture_output=True)
print(time.perf_counter() - t)
""", "lower"),
}


def run_one(checkout: Path, snippet: str) -> float:
    env = dict(os.environ, PYTHONPATH=str(checkout))
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as fh:
        fh.write(snippet)
    try:
        done = subprocess.run([sys.executable, fh.name], cwd=checkout, env=env, capture_output=True,
                              text=True, check=True)
    finally:
        os.unlink(fh.name)
    return float(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--name", default="ab-refactor", help="docs/results/NAME.json (default %(default)s)")
    parser.add_argument("--only", action="append", choices=sorted(WORKLOADS), help="only this workload")
    parser.add_argument("--atlas", type=Path, help="the atlas store of the built-in atlas area the atlas "
                                                   "workloads read (tmakit atlas build shelf-break-atlas)")
    args = parser.parse_args(argv)
    if args.atlas is not None:
        os.environ["TMAKIT_AB_ATLAS"] = str(args.atlas.resolve())
    load_before, git = load_average(), git_state()
    sides = {"before": args.before.resolve(), "after": args.after.resolve()}
    result = {"repeats": args.repeats, "checkouts": {k: _describe(v) for k, v in sides.items()}, "workloads": {}}
    for name, (snippet, better) in WORKLOADS.items():
        if args.only and name not in args.only or "TMAKIT_AB_ATLAS" in snippet and args.atlas is None:
            continue
        values = {"before": [], "after": []}
        for i in range(args.repeats):
            order = ("before", "after") if i % 2 == 0 else ("after", "before")
            for side in order:
                values[side].append(run_one(sides[side], snippet))
        med = {side: statistics.median(v) for side, v in values.items()}
        ratio = med["after"] / med["before"]
        result["workloads"][name] = {"values": values, "median": med, "after_over_before": ratio,
                                     "better": better}
        print(f"{name}: before {med['before']:.4g}, after {med['after']:.4g}, after/before {ratio:.3f}",
              flush=True)
    # the two checkouts are machine paths: the command names them BEFORE and AFTER, their commits
    # are the result's "checkouts"
    command = command_naming("bench.ab_checkouts", argv, {str(args.before): "BEFORE", str(args.after): "AFTER"})
    write_result(args.name, result, provenance_data=provenance(command=command, load_before=load_before, git=git))
    return 0


def _describe(checkout: Path) -> str:
    done = subprocess.run(["git", "-C", str(checkout), "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True)
    return done.stdout.strip() or str(checkout)


if __name__ == "__main__":
    sys.exit(main())
