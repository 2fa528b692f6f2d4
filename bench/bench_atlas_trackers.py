"""Trackers on an atlas against the same trackers on one grid, side by side (issue target: within
1.3x): the ML analysis's cycle and the particle filter's throughput on the shelf-cross scenario,
tables following the observer through the 5 km shelf-break atlas against that atlas's table at
one position (the same axes); the filter on one run and on a batch of 20 runs (the K profiles of
a cycle serve the whole batch). 7 interleaved repeats, medians, the load average beside them;
each repeat opens the tables anew (no view kept from the last). Written to docs/results/atlas-trackers.json.

    python -m bench.bench_atlas_trackers [ATLAS.zarr]   (default: the follow study's 5 km atlas)
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from acoustics.grid.atlas.follow import follow
from acoustics.grid.atlas.store import open_store
from acoustics.grid.formats import RESULT_FORMAT
from bench.harness import REPO as ROOT
from bench.harness import Session, portable_path
from envdata.classes import SourceLevelModel
from tracker.mltma import MLBatch
from tracker.rpf import RpfConfig, run_batch
from tracker.rpf.track import cycle_profiles
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch

ATLAS = ROOT / "docs" / "results" / "atlas-tracking" / "grids" / "atlas-5km.zarr"
REPEATS = 7  # a single filter run is ~20 ms: 7 interleaved repeats for a steady median
N_PARTICLES = 5000


def _tables(path: Path, which: str):
    atlas = open_store(path)
    month = int(atlas.months[0])
    return follow(atlas, month) if which == "atlas" else atlas.sel(month=month, origin=int(atlas.lat_deg.size // 2))


def _ml_seconds(tables, sim) -> float:
    e, t = sim.bearing_deg.shape
    batch = MLBatch(tables, np.arange(len(tables.classes)), t)
    vx, vy = np.gradient(sim.obs_x_m, sim.t_s), np.gradient(sim.obs_y_m, sim.t_s)
    start = time.perf_counter()
    for i in range(t):
        batch.update(sim.t_s[i], sim.obs_x_m[i], sim.obs_y_m[i], vx[i], vy[i], sim.bearing_deg[0, i],
                     sim.bearing_sigma_deg[0, i], sim.level_db[0, i], sim.snr_db[0, i], obs_depth_m=sim.obs_depth_m)
    return (time.perf_counter() - start) / t


def _rpf_seconds(tables, sim, ic: int, runs: int) -> float:
    t = sim.t_s.size
    obs = np.stack([sim.obs_x_m, sim.obs_y_m, np.gradient(sim.obs_x_m, sim.t_s),
                    np.gradient(sim.obs_y_m, sim.t_s)], axis=-1)
    cfg = RpfConfig(n_particles=N_PARTICLES)
    start = time.perf_counter()
    profiles = cycle_profiles(tables, ic, 0, np.full(t, sim.obs_depth_m), sim.bearing_deg[0], sim.obs_x_m,
                              sim.obs_y_m)
    bearings = np.radians(np.repeat(sim.bearing_deg[:1], runs, 0))
    run_batch(t_s=sim.t_s, obs_state=obs, bearing_rad_meas=bearings,
              level_db_meas=np.repeat(sim.level_db[:1, :, 0], runs, 0), k_profiles=profiles, cfg=cfg,
              rng=np.random.default_rng(1),
              source_level_model=SourceLevelModel.P0, p0_db=tables.classes[ic].noise_mean_db, p0_sd_db=2.5)
    return time.perf_counter() - start


def main(path: Path) -> dict:
    sc = load_scenario("shelf-cross")
    base = _tables(path, "grid")
    ic = base.class_index(sc.target_class)
    sim = simulate_batch(sc, _tables(path, "atlas"), np.random.default_rng(0), dk_db=[0.0])
    _rpf_seconds(base, sim, ic, 1)  # compile the kernel once, outside the timings
    session = Session("atlas-trackers")
    times = {k: [] for k in ("ml_grid", "ml_atlas", "rpf_grid", "rpf_atlas", "rpf20_grid", "rpf20_atlas")}
    # each workload's own time (the tables opened anew are not timed), grid and atlas in turns
    workloads = {f"{kind}_{which}": (lambda kind=kind, which=which: times[f"{kind}_{which}"].append(
        _ml_seconds(_tables(path, which), sim) if kind == "ml"
        else _rpf_seconds(_tables(path, which), sim, ic, 1 if kind == "rpf" else 20)))
        for kind in ("ml", "rpf", "rpf20") for which in ("grid", "atlas")}
    session.interleave(workloads, REPEATS)
    med = {k: float(np.median(v)) for k, v in times.items()}
    result = {"tmakit_format": RESULT_FORMAT, "atlas": portable_path(path), "scenario": sc.name,
              "cycles": int(sim.t_s.size),
              "ml_rows": len(base.classes), "rpf_particles": N_PARTICLES, "repeats": REPEATS, "times_s": times,
              "median_s": med, "ml_cycle_ms": {"grid": 1e3 * med["ml_grid"], "atlas": 1e3 * med["ml_atlas"]},
              "ratio_ml_atlas_over_grid": med["ml_atlas"] / med["ml_grid"],
              "ratio_rpf_atlas_over_grid": med["rpf_atlas"] / med["rpf_grid"],
              "ratio_rpf20_atlas_over_grid": med["rpf20_atlas"] / med["rpf20_grid"], "target_ratio": 1.3}
    session.write(**result)
    return result


if __name__ == "__main__":
    print(json.dumps(main(Path(sys.argv[1]) if len(sys.argv) > 1 else ATLAS), indent=1))
