"""Stone Soup's particle filter on a tmakit scenario with tmakit's tables, beside ``tmakit track
--method rpf`` on the same measurements (docs/stonesoup.md).

``python -m bench.bench_stonesoup [--particles N] [--stonesoup-particles N ...] [--runs R] [--seed S]
[--name NAME]`` writes
``docs/results/NAME.json`` (default ``stonesoup``) with the harness's provenance and
``docs/results/NAME.png``: Iglesis & de Montella's manoeuvring-observer scenario on the
``munk-1000`` grid (a 5 m ship, 50 Hz, the observer turning at 13-17 min), ``R`` runs of
simulated bearings and levels, each tracked by

- tmakit's regularized particle filter (``tracker.track(method="rpf")``: Epanechnikov kernel,
  N_eff < N/3, bearings and SPL, sigma_l = 10 dB), and
- Stone Soup's SIR particle filter (its ``ParticlePredictor`` with a constant-velocity model of
  the same acceleration sd, its ``ParticleUpdater`` with ``ESSResampler`` at N/3 and its
  ``MCMCRegulariser``) given tmakit's measurement model (``tracker.stonesoup.model``, the same
  sigma_l in total) through the detections of the same measurement file
  (``tracker.stonesoup.convert``), from the same prior particles.

Reported: the final position error of each (median over runs), the ratio, the time of each;
Stone Soup at several particle counts, as it needs more than tmakit's filter for the same error
(docs/stonesoup.md).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

#: The scenario and grid of the comparison.
SCENARIO, AREA, CLASS, BAND = "idm-maneuvering", "munk-1000", "ship", "F50"
#: sigma_l of both filters' level likelihood in total, dB (the paper's filter).
LEVEL_SIGMA_DB = 10.0


def measurements_of(sc, tables, rng):
    """One run of the scenario's bearings and levels as a tmakit Measurements (and the truth)."""
    from tools.studies.idm import simulate
    from tracker.measurements import Measurements

    ic, ib = tables.class_index(CLASS), tables.band_index(BAND)
    profile = tables.level_profile(ic, ib, sc.obs_depth_m)
    bearing, level = simulate(sc, profile, 1, rng)
    t = sc.t_s
    obs = sc.observer_state(t)
    n = t.size
    m = Measurements(source=SCENARIO, t_s=t, obs_x_m=obs[:, 0], obs_y_m=obs[:, 1],
                     obs_depth_m=np.full(n, sc.obs_depth_m), bearing_deg=np.degrees(bearing[0]) % 360.0,
                     bearing_sigma_deg=np.full(n, np.nan), band_names=(BAND,), level_db=level[0][:, None],
                     snr_db=np.full((n, 1), np.nan))
    return m, sc.target_state(t)


def stonesoup_track(m, tables, prior_xy_v, *, sigma_a_mps2: float, bearing_sd_deg: float, rng):
    """Stone Soup's SIR particle filter with tmakit's model over the cycles of ``m``; the states."""
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.predictor.particle import ParticlePredictor
    from stonesoup.regulariser.particle import MCMCRegulariser
    from stonesoup.resampler.particle import ESSResampler
    from stonesoup.types.array import StateVectors
    from stonesoup.types.hypothesis import SingleHypothesis
    from stonesoup.types.state import ParticleState
    from stonesoup.updater.particle import ParticleUpdater

    from tracker.stonesoup.convert import detections_from_measurements

    cls = tables.classes[tables.class_index(CLASS)]
    # the same sigma_l in total as tmakit's filter: the model adds the class's sds
    level_sd = math.sqrt(max(LEVEL_SIGMA_DB ** 2 - cls.noise_sd_db ** 2 - cls.k_error_sd_db ** 2, 0.0))
    # tmakit's motion noise is a white acceleration held over a cycle (velocity variance
    # sigma_a^2 dt^2); Stone Soup's constant velocity is a continuous white acceleration of
    # spectral density q (velocity variance q dt): the same velocity spread over a cycle at q = sigma_a^2 dt
    dt = float(np.median(np.diff(m.t_s)))
    q = sigma_a_mps2 ** 2 * dt
    transition = CombinedLinearGaussianTransitionModel([ConstantVelocity(q), ConstantVelocity(q)])
    n = prior_xy_v.shape[1]
    predictor = ParticlePredictor(transition)
    updater = ParticleUpdater(measurement_model=None, resampler=ESSResampler(threshold=n / 3.0),
                              regulariser=MCMCRegulariser(transition_model=transition))
    cycles = detections_from_measurements(m, tables, CLASS, bearing_sd_deg=bearing_sd_deg, level_sd_db=level_sd)
    state = ParticleState(StateVectors(prior_xy_v), log_weight=np.full(n, -math.log(n)), timestamp=cycles[0][0])
    np.random.seed(int(rng.integers(2 ** 31)))  # Stone Soup draws from numpy's global generator
    out = []
    for when, detections in cycles:
        prediction = predictor.predict(state, timestamp=when)  # (dt 0 at the first: its parent is the prior)
        if detections:
            state = updater.update(SingleHypothesis(prediction, next(iter(detections))))
        else:
            state = prediction
        out.append(state)
    return out


def run(*, particles: int, stonesoup_particles: tuple[int, ...], runs: int, seed: int,
        grid_path: Path | None = None) -> dict:
    """The comparison: per run, tmakit's filter's final position error and time at ``particles``,
    and Stone Soup's at each of ``stonesoup_particles``, all on the same measurements and each
    from the same prior (Stone Soup's its own draw of the same law at its particle count)."""
    import acoustics
    from tools.studies.idm_scenarios import get_scenario
    from tracker import rpf
    from tracker.rpf.prior import initial_particles
    from tracker.stonesoup.convert import track_frame
    from tracker.track import track

    if grid_path is None:  # the paper's grid, built once (about 3 s)
        grid_path = Path("out") / "stonesoup" / f"{AREA}-bellhop.nc"
        if not grid_path.exists():
            import envdata

            grid_path.parent.mkdir(parents=True, exist_ok=True)
            acoustics.write_grid(acoustics.build_grid(envdata.load_area(AREA), workers=2), grid_path)
    tables = acoustics.open_tables(grid_path)
    sc = get_scenario(SCENARIO)
    cfg = rpf.RpfConfig(n_particles=particles, level_sigma_db=LEVEL_SIGMA_DB)
    rows = []
    for i, s in enumerate(np.random.SeedSequence(seed).spawn(runs)):
        rng_data, rng_tmakit, rng_ss = (np.random.default_rng(x) for x in s.spawn(3))
        m, truth = measurements_of(sc, tables, rng_data)
        last = truth[-1]
        start = time.perf_counter()
        df = track(tables, m, method="rpf", rng=rng_tmakit, rpf_config=cfg, cls_name=CLASS)
        err = math.hypot(df["x_m"].iloc[-1] - last[0], df["y_m"].iloc[-1] - last[1])
        row = {"run": i, "rpf_final_error_m": float(err),
               "rpf_seconds": round(time.perf_counter() - start, 3), "stonesoup": {}}
        obs0 = sc.observer_state(m.t_s[:1])[0]
        for n in stonesoup_particles:
            # the prior of tmakit's filter (its initial particles, relative) as absolute (x, vx, y, vy)
            rel = initial_particles(math.radians(m.bearing_deg[0]), obs0[2:4],
                                    rpf.RpfConfig(n_particles=n, level_sigma_db=LEVEL_SIGMA_DB), 1, rng_ss)[:, 0]
            prior = np.vstack([rel[0] + obs0[0], rel[2] + obs0[2], rel[1] + obs0[1], rel[3] + obs0[3]])
            start = time.perf_counter()
            states = stonesoup_track(m, tables, prior, sigma_a_mps2=cfg.sigma_a_mps2,
                                     bearing_sd_deg=cfg.bearing_sigma_deg, rng=rng_ss)
            seconds = time.perf_counter() - start
            ss = track_frame(states, m, CLASS)
            row["stonesoup"][n] = {"final_error_m": float(math.hypot(ss["x_m"].iloc[-1] - last[0],
                                                                      ss["y_m"].iloc[-1] - last[1])),
                                   "seconds": round(seconds, 3)}
            if i == 0:
                row.setdefault("_tracks", {})[n] = ss
        row["_truth"] = (df, truth, m)
        rows.append(row)
    return {"scenario": SCENARIO, "area": AREA, "particles": particles,
            "stonesoup_particles": list(stonesoup_particles), "runs": rows}


def summary(out: dict) -> dict:
    """Medians over the runs: tmakit's final error and time, and Stone Soup's at each particle count
    with its ratio to tmakit's."""
    from bench.harness import median

    rows = out["runs"]
    rpf_err = median([r["rpf_final_error_m"] for r in rows])
    res = {"rpf": {"particles": out["particles"], "final_error_median_m": rpf_err,
                   "seconds_median": median([r["rpf_seconds"] for r in rows])}, "stonesoup": []}
    for n in out["stonesoup_particles"]:
        err = median([r["stonesoup"][n]["final_error_m"] for r in rows])
        res["stonesoup"].append({"particles": n, "final_error_median_m": err, "over_rpf": err / rpf_err,
                                 "seconds_median": median([r["stonesoup"][n]["seconds"] for r in rows])})
    return res


def _plot(path: Path, out: dict, summ: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    row = out["runs"][0]
    df, truth, m = row["_truth"]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11.0, 4.8))
    ax.plot(truth[:, 0] / 1e3, truth[:, 1] / 1e3, "k-", lw=2, label="target (truth)")
    ax.plot(m.obs_x_m / 1e3, m.obs_y_m / 1e3, "k--", lw=1, label="observer")
    ax.plot(df["x_m"] / 1e3, df["y_m"] / 1e3, "C0-", label=f"tmakit track --method rpf, N = {out['particles']}")
    for j, (n, ss) in enumerate(row["_tracks"].items()):
        ax.plot(ss["x_m"] / 1e3, ss["y_m"] / 1e3, f"C{j + 1}-", lw=1,
                label=f"Stone Soup SIR + MCMC, tmakit's model, N = {n}")
    ax.set_xlabel("east, km")
    ax.set_ylabel("north, km")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=7)
    ax.set_title(f"{SCENARIO} on {AREA}: run 0")
    ns = [s["particles"] for s in summ["stonesoup"]]
    ax2.plot(ns, [s["final_error_median_m"] for s in summ["stonesoup"]], "o-", color="C3",
             label="Stone Soup with tmakit's model")
    ax2.axhline(summ["rpf"]["final_error_median_m"], color="C0",
                label=f"tmakit rpf, N = {summ['rpf']['particles']}")
    ax2.axhline(2 * summ["rpf"]["final_error_median_m"], color="C0", ls=":", label="2x tmakit rpf")
    ax2.set_xscale("log")
    ax2.set_xlabel("Stone Soup particles")
    ax2.set_ylabel(f"final position error, m (median of {len(out['runs'])} runs)")
    ax2.legend(loc="best", fontsize=8)
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=100)
    plt.close(fig)
    tmp.replace(path)


def main(argv=None) -> int:
    from bench.harness import RESULTS_DIR, Session

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--particles", type=int, default=5000, help="tmakit's filter (the paper's N)")
    p.add_argument("--stonesoup-particles", type=int, nargs="+", default=[5000, 10000, 20000, 40000])
    p.add_argument("--runs", type=int, default=32)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--grid", type=Path, help="the munk-1000 grid (default: built into out/stonesoup/)")
    p.add_argument("--name", default="stonesoup")
    args = p.parse_args(argv)
    session = Session(args.name)
    out = run(particles=args.particles, stonesoup_particles=tuple(args.stonesoup_particles), runs=args.runs,
              seed=args.seed, grid_path=args.grid)
    summ = summary(out)
    _plot(RESULTS_DIR / f"{args.name}.png", out, summ)
    session.say("rpf_final_error_median", summ["rpf"]["final_error_median_m"], "m")
    session.say("rpf_seconds_median", summ["rpf"]["seconds_median"], "s")
    for s in summ["stonesoup"]:
        session.say(f"stonesoup_{s['particles']}_final_error_median", s["final_error_median_m"], "m")
        session.say(f"stonesoup_{s['particles']}_over_rpf", s["over_rpf"], "x")
        session.say(f"stonesoup_{s['particles']}_seconds_median", s["seconds_median"], "s")
    session.write(scenario=out["scenario"], area=out["area"], summary=summ,
                  runs=[{k: v for k, v in r.items() if not k.startswith("_")} for r in out["runs"]])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
