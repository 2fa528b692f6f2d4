"""Benchmarks of the unknown target depth: the particle filter's cost, and the reciprocity error
of a flat grid's observer-centred TL near the surface.

    make bench, or: python -m bench.bench_depth

Prints one line per figure, ``name: value unit``, all measured in this one run, and writes
docs/results/depth.json:

- particle-cycles per CPU second of the compiled filter with the depth fixed (K(r) profiles,
  ``tracker.rpf.run_batch``) and with the depth a state (K from (depth, range) slabs,
  ``tracker.rpf.depthbatch.run_batch_depth``), side by side on the same measurements (scenario
  ``shelf-nps`` on the built-in shelf-break grid: 12 radials x 251 depths x 300 ranges; 20 runs
  x 2000 particles x 181 cycles, bearings and FB1 levels, one thread), 7 repeats interleaved
  (fixed, depth, depth, fixed, ...), medians, and their ratio (target >= 0.5); timed in the
  process's CPU time, which other users' load on the shared machine changes least, with the
  wall-clock ratio beside it;
- the depth likelihood after the last cycle along one shelf-nps track over the depth study's
  span, with and without the range-scale integral (`tracker.depthlevels.RANGE_SCALE_SD`), 7
  repeats interleaved, medians of CPU time, and their ratio; and the depth posterior as
  ``tmakit track --target-depth unknown`` takes it along one track (every few cycles) over the
  class's whole span (CPU seconds, median of 3);
- K of a class by reciprocity (``tl_obs_db``: source at the observer) less K from the direct runs
  (source at the class depth), median |dB| over range, for classes at 5 to 200 m in the tiny
  Munk test area (observer at 100 m).
"""

from __future__ import annotations

import time

import numpy as np

from bench.harness import REPO, Session, median

session = Session("depth")

RUNS, PARTICLES, REPEATS = 20, 2000, 7
RECIPROCITY_DEPTHS_M = (5.0, 10.0, 20.0, 50.0, 150.0, 200.0)


def throughput() -> None:
    import acoustics
    import envdata
    from envdata.classes import SourceLevelModel
    from tools.studies.depth import DEPTH_SPAN_M, _rpf_config
    from tracker.rpf import run_batch
    from tracker.rpf.depthbatch import DepthConfig, run_batch_depth
    from tracker.rpf.track import cycle_profiles
    from tracker.scenario import load_scenario
    from tracker.simulate import simulate_batch

    grid = REPO / "docs" / "results" / "depth" / "grids" / "shelf-break-bellhop.nc"
    if not grid.exists():
        acoustics.build_grid_file(envdata.load_area("shelf-break"), grid, workers=2)
    tables = acoustics.open_tables(grid)
    sc = load_scenario("shelf-nps")
    ic = tables.class_index(sc.target_class)
    sim = simulate_batch(sc, tables, np.random.default_rng(0), dk_db=np.zeros(RUNS))
    cfg = _rpf_config(tables, sim, ic, PARTICLES)
    obs = np.stack([sim.obs_x_m, sim.obs_y_m, np.gradient(sim.obs_x_m, sim.t_s),
                    np.gradient(sim.obs_y_m, sim.t_s)], axis=-1)
    bearing = np.radians(sim.bearing_deg)
    level = sim.level_db[:, :, 0]
    cls = tables.classes[ic]
    common = dict(t_s=sim.t_s, obs_state=obs, bearing_rad_meas=bearing, level_db_meas=level,
                  cfg=cfg, source_level_model=SourceLevelModel.P0, p0_db=cls.noise_mean_db)
    # one bearing's profiles for every run (the fixed-depth filter's cost does not depend on it)
    profiles = cycle_profiles(tables, ic, 0, np.full(sim.t_s.size, sim.obs_depth_m), sim.bearing_deg[0])
    target_k = tables.target_depth_k(ic, 0)
    depth = DepthConfig(depth_min_m=DEPTH_SPAN_M[0], depth_max_m=DEPTH_SPAN_M[1])

    def fixed(seed):
        return run_batch(k_profiles=profiles, rng=np.random.default_rng(seed), **common)

    def unknown(seed):
        return run_batch_depth(target_k=target_k, cycle_bearing_deg=sim.bearing_deg[0], depth=depth,
                               rng=np.random.default_rng(seed), **common)

    fixed(0), unknown(0)  # compile (or load the cache) outside the timing
    work = RUNS * PARTICLES * sim.t_s.size
    cpu = {"fixed": [], "unknown": []}
    wall = {"fixed": [], "unknown": []}
    pair = (("fixed", fixed), ("unknown", unknown))
    for rep in range(REPEATS):
        for name, fn in pair if rep % 2 == 0 else pair[::-1]:  # drift in the load falls on both
            wall0, cpu0 = time.perf_counter(), time.process_time()
            fn(rep + 1)
            cpu[name].append(work / (time.process_time() - cpu0))
            wall[name].append(work / (time.perf_counter() - wall0))
    session.say("rpf_fixed_depth_particle_cycles_per_s", median(cpu["fixed"]), "1/s", runs=cpu["fixed"])
    session.say("rpf_depth_state_particle_cycles_per_s", median(cpu["unknown"]), "1/s", runs=cpu["unknown"])
    ratios = [u / f for u, f in zip(cpu["unknown"], cpu["fixed"])]
    session.say("rpf_depth_state_throughput_ratio", median(ratios), "", runs=ratios)
    wall_ratios = [u / f for u, f in zip(wall["unknown"], wall["fixed"])]
    session.say("rpf_depth_state_throughput_ratio_wall", median(wall_ratios), "", runs=wall_ratios)


def posterior_cost() -> None:
    import acoustics
    from tools.studies.depth import DEPTH_SPAN_M
    from tracker.depthlevels import TrackDepthLikelihood
    from tracker.depthpost import depth_grid_m
    from tracker.mltma.depths import posterior_along_tracks
    from tracker.scenario import load_scenario
    from tracker.simulate import measurements_of, simulate_batch, truth_of

    tables = acoustics.open_tables(REPO / "docs" / "results" / "depth" / "grids" / "shelf-break-bellhop.nc")
    sc = load_scenario("shelf-nps")
    ic = tables.class_index(sc.target_class)
    sim = simulate_batch(sc, tables, np.random.default_rng(0), dk_db=np.zeros(1))
    t = sim.t_s
    m = measurements_of(sim, 0, "shelf-nps")
    track = truth_of(sim, sc, 0)
    x, y = track["x_m"].to_numpy() - m.obs_x_m, track["y_m"].to_numpy() - m.obs_y_m
    r, b = np.hypot(x, y), np.degrees(np.arctan2(x, y)) % 360.0
    z = depth_grid_m(tables.depth_m, DEPTH_SPAN_M)
    likes = {"plain": TrackDepthLikelihood(tables, ic, tables.band_names, DEPTH_SPAN_M, range_scale_sd=0.0),
             "scaled": TrackDepthLikelihood(tables, ic, tables.band_names, DEPTH_SPAN_M)}

    def once(like):
        like(z, t, r, b, m.level_db, m.snr_db, m.obs_x_m, m.obs_y_m)

    for like in likes.values():
        once(like)
    cpu = {k: [] for k in likes}
    names = list(likes)
    for rep in range(REPEATS):
        for name in names if rep % 2 == 0 else names[::-1]:
            cpu0 = time.process_time()
            once(likes[name])
            cpu[name].append(time.process_time() - cpu0)
    session.say("depth_likelihood_cpu_s_no_range_scale", median(cpu["plain"]), "s", runs=cpu["plain"])
    session.say("depth_likelihood_cpu_s_range_scale", median(cpu["scaled"]), "s", runs=cpu["scaled"])
    ratios = [a / b for a, b in zip(cpu["scaled"], cpu["plain"])]
    session.say("depth_likelihood_range_scale_cost_ratio", median(ratios), "", runs=ratios)
    # as tmakit track --target-depth unknown takes it for one track: every few cycles, the class's
    # span (NPS has no depth_range_m here: the whole water column the tables hold)
    span = tables.target_depth_span_m(ic)
    runs = []
    for _ in range(3):
        cpu0 = time.process_time()
        posterior_along_tracks(tables, ic, m, [track], np.array([0.5 * sum(span)]), span)
        runs.append(time.process_time() - cpu0)
    session.say("track_depth_posterior_cpu_s_whole_water_column", median(runs), "s", runs=runs)
    session.say("track_depth_posterior_depths", int(depth_grid_m(tables.depth_m, span).size))
    session.say("track_depth_posterior_cycles", int(t.size))


def reciprocity() -> None:
    import acoustics
    import envdata

    doc = envdata.load_area(REPO / "tests" / "data" / "tiny-munk.toml").to_dict()
    base = doc["classes"][0]
    # a depth_range_m makes the build add tl_obs_db (the runs from the observer depth)
    doc["classes"] = [{**base, "name": f"D{int(z)}", "depth_m": z, "depth_range_m": [5.0, 200.0]}
                      for z in RECIPROCITY_DEPTHS_M]
    t = acoustics.open_tables(acoustics.build_grid(envdata.parse_area(doc, "reciprocity"), workers=2))
    for ic, cls in enumerate(t.classes):
        diff = t.at_target_depth(cls.depth_m).k_grid_db[ic] - t.k_grid_db[ic]   # (M, R)
        session.say(f"reciprocity_error_median_abs_db_at_{cls.depth_m:g}m", float(np.median(np.abs(diff))), "dB")


if __name__ == "__main__":
    throughput()
    posterior_cost()
    reciprocity()
    session.write()
