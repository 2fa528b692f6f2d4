"""Stone Soup's particle filter on a tmakit scenario with tmakit's tables, beside ``tmakit track
--method rpf`` on the same measurements (docs/stonesoup.md).

``python -m tools.stonesoup.example [--particles N] [--runs R] [--seed S] [--name NAME]`` writes
``docs/results/NAME.json`` (default ``stonesoup``) with the harness's provenance and
``docs/results/NAME.png``: Iglesis & de Montella's manoeuvring-observer scenario on the
``munk-1000`` grid (a 5 m ship, 50 Hz, the observer turning at 13-17 min), ``R`` runs of
simulated bearings and levels, each tracked by

- tmakit's regularized particle filter (``tracker.track(method="rpf")``: Epanechnikov kernel,
  N_eff < N/3, bearings and SPL, sigma_l = 10 dB), and
- Stone Soup's SIR particle filter (its ``ParticlePredictor`` with a constant-velocity model of
  the same acceleration sd, its ``ParticleUpdater`` with ``ESSResampler`` at N/3 and its
  ``MCMCRegulariser``) given tmakit's measurement model (``tools.stonesoup.model``, the same
  sigma_l in total) through the detections of the same measurement file
  (``tools.stonesoup.convert``), from the same prior particles.

Reported: the final position error of each (median over runs), the ratio, the wall time of each.
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

    from tools.stonesoup.convert import detections_from_measurements

    cls = tables.classes[tables.class_index(CLASS)]
    # the same sigma_l in total as tmakit's filter: the model adds the class's sds
    level_sd = math.sqrt(max(LEVEL_SIGMA_DB ** 2 - cls.noise_sd_db ** 2 - cls.k_error_sd_db ** 2, 0.0))
    q = sigma_a_mps2 ** 2
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
        prediction = predictor.predict(state, timestamp=when) if when > state.timestamp else state
        if detections:
            state = updater.update(SingleHypothesis(prediction, next(iter(detections))))
        else:
            state = prediction
        out.append(state)
    return out


def run(*, particles: int, runs: int, seed: int, grid_path: Path | None = None) -> dict:
    """The comparison: per run, each filter's final position error and time."""
    import acoustics
    from tools.stonesoup.convert import track_frame
    from tools.studies.idm_scenarios import get_scenario
    from tracker import rpf
    from tracker.rpf.prior import initial_particles
    from tracker.track import track

    tables = acoustics.open_tables(grid_path) if grid_path else acoustics.build_grid_file(
        AREA, Path("out") / "stonesoup" / f"{AREA}-bellhop.nc", workers=2).file
    tables = acoustics.open_tables(tables) if not hasattr(tables, "k_at") else tables
    sc = get_scenario(SCENARIO)
    cfg = rpf.RpfConfig(n_particles=particles, level_sigma_db=LEVEL_SIGMA_DB)
    seeds = np.random.SeedSequence(seed).spawn(runs)
    rows = []
    for i, s in enumerate(seeds):
        rng_data, rng_tmakit, rng_ss = (np.random.default_rng(x) for x in s.spawn(3))
        m, truth = measurements_of(sc, tables, rng_data)
        start = time.perf_counter()
        df = track(tables, m, method="rpf", rng=rng_tmakit, rpf_config=cfg, cls_name=CLASS)
        t_tmakit = time.perf_counter() - start
        # the same prior as tmakit's filter: its initial particles, relative -> absolute (x, vx, y, vy)
        obs0 = sc.observer_state(m.t_s[:1])[0]
        rel = initial_particles(math.radians(m.bearing_deg[0]), obs0[2:4], cfg, 1, rng_ss)[:, 0]
        prior = np.vstack([rel[0] + obs0[0], rel[2] + obs0[2], rel[1] + obs0[1], rel[3] + obs0[3]])
        start = time.perf_counter()
        states = stonesoup_track(m, tables, prior, sigma_a_mps2=cfg.sigma_a_mps2,
                                 bearing_sd_deg=cfg.bearing_sigma_deg, rng=rng_ss)
        t_ss = time.perf_counter() - start
        ss = track_frame(states, m, CLASS)
        last = truth[-1]
        rows.append({"run": i,
                     "rpf_final_error_m": float(math.hypot(df["x_m"].iloc[-1] - last[0], df["y_m"].iloc[-1] - last[1])),
                     "stonesoup_final_error_m": float(math.hypot(ss["x_m"].iloc[-1] - last[0],
                                                                 ss["y_m"].iloc[-1] - last[1])),
                     "rpf_seconds": round(t_tmakit, 3), "stonesoup_seconds": round(t_ss, 3),
                     "_tracks": (df, ss, truth, m)})
    return {"scenario": SCENARIO, "grid": str(getattr(tables, "source", "")), "particles": particles,
            "runs": rows}


def _plot(path: Path, rows: list[dict]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    df, ss, truth, m = rows[0]["_tracks"]
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    ax.plot(truth[:, 0] / 1e3, truth[:, 1] / 1e3, "k-", lw=2, label="target (truth)")
    ax.plot(m.obs_x_m / 1e3, m.obs_y_m / 1e3, "k--", lw=1, label="observer")
    ax.plot(df["x_m"] / 1e3, df["y_m"] / 1e3, "C0-", label="tmakit track --method rpf")
    ax.plot(ss["x_m"] / 1e3, ss["y_m"] / 1e3, "C3-", label="Stone Soup particle filter, tmakit's model")
    ax.set_xlabel("east, km")
    ax.set_ylabel("north, km")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"{SCENARIO} on {AREA}: run 0")
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    tmp.replace(path)


def main(argv=None) -> int:
    from bench.harness import RESULTS_DIR, Session, median

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--particles", type=int, default=5000)
    p.add_argument("--runs", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--grid", type=Path, help="the munk-1000 grid (default: built into out/stonesoup/)")
    p.add_argument("--name", default="stonesoup")
    args = p.parse_args(argv)
    session = Session(args.name)
    out = run(particles=args.particles, runs=args.runs, seed=args.seed, grid_path=args.grid)
    rows = out["runs"]
    _plot(RESULTS_DIR / f"{args.name}.png", rows)
    rpf_err = median([r["rpf_final_error_m"] for r in rows])
    ss_err = median([r["stonesoup_final_error_m"] for r in rows])
    session.say("rpf_final_error_median", rpf_err, "m")
    session.say("stonesoup_final_error_median", ss_err, "m")
    session.say("stonesoup_over_rpf", ss_err / rpf_err, "x")
    session.say("rpf_seconds_median", median([r["rpf_seconds"] for r in rows]), "s")
    session.say("stonesoup_seconds_median", median([r["stonesoup_seconds"] for r in rows]), "s")
    session.write(scenario=out["scenario"], particles=out["particles"],
                  runs=[{k: v for k, v in r.items() if not k.startswith("_")} for r in rows])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
