"""What integrating the levels' lasting errors out costs the particle filter.

    python -m bench.bench_level_errors [--repeats 7]

The compiled filter on the same measurements with the paper's white level likelihood and with
the errors of `tracker.levels` integrated out per particle (`tracker.rpf.kernel.levelerrors`: an
offset and a residual along the path, one band; what ``tmakit track --method rpf`` runs), side by
side: the shelf-nps submarine on the built-in shelf-break grid (20 runs x 2000 particles x 181
cycles, bearings and FB1 levels, one thread), repeats interleaved (white, errors, errors, white,
...), particle-cycles per CPU second (the process's CPU time, which other users' load changes
least), medians and their ratio. Writes docs/results/level-errors.json.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bench.harness import REPO, Session, median

RUNS, PARTICLES = 20, 2000


def throughput(session: Session, repeats: int) -> None:
    import acoustics
    import envdata
    from envdata.classes import SourceLevelModel
    from tools.studies.trackerrors import LEVEL_SD_DB, rpf_config
    from tracker.levels import LevelErrors
    from tracker.rpf import run_batch
    from tracker.rpf.track import cycle_profiles
    from tracker.scenario import load_scenario
    from tracker.simulate import simulate_batch

    grid = REPO / "docs" / "results" / "depth" / "grids" / "shelf-break-bellhop.nc"
    if not grid.exists():
        acoustics.build_grid_file(envdata.load_area("shelf-break"), grid, workers=2)
    tables = acoustics.open_tables(grid)
    sc = load_scenario("shelf-nps")
    ic = tables.class_index(sc.target_class)
    cls = tables.classes[ic]
    sim = simulate_batch(sc, tables, np.random.default_rng(0), dk_db=np.zeros(RUNS))
    obs = np.stack([sim.obs_x_m, sim.obs_y_m, np.gradient(sim.obs_x_m, sim.t_s),
                    np.gradient(sim.obs_y_m, sim.t_s)], axis=-1)
    profiles = cycle_profiles(tables, ic, 0, np.full(sim.t_s.size, sim.obs_depth_m), sim.bearing_deg[0])
    errors = LevelErrors.of_tables(tables, ic, [0], source_sd_db=cls.noise_sd_db)
    away = tables.distance_from_origin_m(sim.obs_x_m, sim.obs_y_m)
    common = dict(t_s=sim.t_s, obs_state=obs, bearing_rad_meas=np.radians(sim.bearing_deg),
                  level_db_meas=sim.level_db[:, :, 0], k_profiles=profiles,
                  source_level_model=SourceLevelModel.P0, p0_db=cls.noise_mean_db, p0_sd_db=cls.noise_sd_db)
    cfg_white = rpf_config(tables, sim, ic, PARTICLES)
    cfg_errors = rpf_config(tables, sim, ic, PARTICLES, LEVEL_SD_DB)

    def white(seed):
        return run_batch(cfg=cfg_white, rng=np.random.default_rng(seed), **common)

    def integrated(seed):
        return run_batch(cfg=cfg_errors, rng=np.random.default_rng(seed), level_errors=errors,
                         displacement_m=away, **common)

    white(0), integrated(0)  # compile (or load the cache) outside the timing
    work = RUNS * PARTICLES * sim.t_s.size
    cpu = {"white": [], "errors": []}
    pair = (("white", white), ("errors", integrated))
    for rep in range(repeats):
        for name, fn in pair if rep % 2 == 0 else pair[::-1]:   # drift in the load falls on both
            c0 = time.process_time()
            fn(rep + 1)
            cpu[name].append(work / (time.process_time() - c0))
    session.say("rpf_white_particle_cycles_per_cpu_s", median(cpu["white"]), "1/s", runs=cpu["white"])
    session.say("rpf_level_errors_particle_cycles_per_cpu_s", median(cpu["errors"]), "1/s", runs=cpu["errors"])
    ratios = [w / e for w, e in zip(cpu["white"], cpu["errors"])]
    session.say("rpf_level_errors_cost_ratio", median(ratios), "(white throughput / with the errors)", runs=ratios)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    s = Session("level-errors")
    throughput(s, args.repeats)
    s.write()
