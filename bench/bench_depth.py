"""Benchmarks of the unknown target depth: the depth posterior's cost, and the reciprocity error
of a flat grid's observer-centred TL near the surface.

    make bench, or: python -m bench.bench_depth

Prints one line per figure, ``name: value unit``, all measured in this one run, and writes
docs/results/depth.json:

- the depth likelihood after the last cycle along one shelf-nps track over the depth study's
  span, with and without the range-scale integral (`tracker.depth.likelihood.RANGE_SCALE_SD`), 7
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

REPEATS = 7
RECIPROCITY_DEPTHS_M = (5.0, 10.0, 20.0, 50.0, 150.0, 200.0)


def posterior_cost() -> None:
    import acoustics
    from tools.studies.depth import DEPTH_SPAN_M
    from tracker.depth.bank import posterior_along_tracks
    from tracker.depth.likelihood import TrackDepthLikelihood
    from tracker.depth.posterior import depth_grid_m
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
    posterior_cost()
    reciprocity()
    session.write()
