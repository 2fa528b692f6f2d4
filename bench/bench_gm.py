"""Benchmarks of the ML tracker (Grinenkov & Mashoshin): cycle latency and the experiment.

Run: ``make bench`` or ``python -m bench.bench_gm [GRID]`` (default: the ocean-deep grid in
out/bench/, built or reused first). Prints `name: value unit` lines.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from bench.harness import Session, bench_grid

session = Session("gm")


def main() -> None:
    import acoustics
    from tools.studies.gm import run
    from tracker.mltma import MLTracker
    from tracker.scenario import load_scenario
    from tracker.simulate import simulate

    out = Path(__file__).resolve().parents[1] / "out" / "bench"
    if len(sys.argv) > 1:
        path = Path(sys.argv[1])
    else:
        path = Path(bench_grid("ocean-deep"))
    grid = acoustics.open_tables(path)
    # one 40-min tack (the scenario's first, made 2400 s long): the last cycles carry 220-240
    # bearings on the tack, as the latency figure asks
    sc = load_scenario("gm-tv-30km")
    sc = dataclasses.replace(sc, target_tacks=(
        dataclasses.replace(sc.target_tacks[0], duration_s=2400.0),))
    m, _ = simulate(sc, grid, np.random.default_rng(0))
    trk = MLTracker(grid, capacity=len(m))
    vx, vy = m.obs_velocity_mps()
    lat = []
    for i in range(len(m)):
        t0 = time.perf_counter()
        trk.update_from(m, i, obs_vel=(vx[i], vy[i]))
        lat.append(time.perf_counter() - t0)
    lat_ms = 1000.0 * np.median(lat[-20:])       # 220-240 bearings on the tack
    session.say("ml_cycle_latency_3_classes_240_bearings", float(lat_ms), "ms (median of the last 20 cycles)")
    session.say("ml_class_cycles_per_second", 3.0 / (lat_ms / 1000.0), "1/s")
    t0 = time.perf_counter()
    run("gm-tv-30km", grid_path=path, n=11, out_dir=out / "gm-experiment", workers=2)
    session.say("gm_experiment_1331_runs_2_workers", time.perf_counter() - t0, "s")


if __name__ == "__main__":
    main()
    session.write()
