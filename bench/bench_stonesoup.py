"""Stone Soup beside tmakit's particle filter: the one comparison, accuracy and speed.

    make bench, or: python -m bench.bench_stonesoup [--runs R] [--seeds S ...] [--particles N ...]
    [--multiples M ...] [--name NAME]

writes ``docs/results/NAME.json`` (default ``stonesoup``) and ``docs/results/NAME.png``, quoted by
docs/stonesoup.md. Stone Soup is the ``stonesoup`` extra (1.9.1, pinned), in this environment;
``make bench`` installs it.

Accuracy: Iglesis & de Montella's manoeuvring-observer scenario on the ``munk-1000`` grid (a 5 m
ship, 50 Hz, the observer turning at 13-17 min), ``R`` runs of simulated bearings and levels for
each seed, each run tracked by

- tmakit's regularized particle filter (``tracker.track(method="rpf")``: Epanechnikov kernel,
  N_eff < N/3, bearings and SPL, sigma_l = 10 dB) with ``N`` particles (each N given), and
- Stone Soup's SIR particle filter (its ``ParticlePredictor`` with a constant-velocity model of
  the same velocity spread per cycle, its ``ParticleUpdater`` with ``ESSResampler`` at N/3 and
  its ``MCMCRegulariser``) given tmakit's measurement model (the plugin,
  ``stonesoup.plugins.tmakit``, the same sigma_l in total) through the detections of the same
  measurement file, from priors of the same law, at each multiple ``M`` of ``N`` particles.

Reported: the final position error of each (median over the runs of each seed and of all), the
ratio to tmakit's, the time per run, and the runs in which Stone Soup's cloud collapsed (fewer
distinct particles than state dimensions: its regulariser's covariance is singular and it raises;
such a run counts as its largest error). Stone Soup needs more particles for the same error; the
ratio at each multiple, seed by seed, is what the Stone Soup test's particle multiple rests on
(tests/tracker/stonesoup/test_stonesoup.py).

Speed: particle-steps per second of Stone Soup's particle filter on bearings alone (its own
``Cartesian2DToBearing``; ``ParticlePredictor``, ``ParticleUpdater`` with a
``MultinomialResampler`` inside ``ESSResampler`` at N/3, and the ``MCMCRegulariser``, which Stone
Soup's updater calls only after a resampling, as the paper's algorithm does), N = 5000, the
first 30 cycles of ``idm-static`` (it is slow), from tmakit's prior particles; tmakit's filter on
the same bearings in the same run (``bench.bench_rpf.bench_tmakit``: one filter over the 151
cycles and over the first 31, batched 40 runs on 1 and 2 threads), the ratios, and both filters'
resampling fractions over the cycles timed. Stone Soup's predict + update only are timed.
"""

from __future__ import annotations

import argparse
import math
import time
from datetime import datetime, timedelta
from pathlib import Path

import numpy as np

from bench.bench_rpf import _scenario, bench_tmakit
from bench.harness import RESULTS_DIR, Session, median

#: The scenario and grid of the accuracy comparison.
SCENARIO, AREA, CLASS, BAND = "idm-maneuvering", "munk-1000", "ship", "F50"
#: sigma_l of both filters' level likelihood in total, dB (the paper's filter).
LEVEL_SIGMA_DB = 10.0
#: Stone Soup's filter is timed on the first cycles of idm-static only (it is slow).
SPEED_STEPS = 30


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
    """Stone Soup's SIR particle filter with tmakit's model over the cycles of ``m``: the states, and
    the cycle at which its cloud collapsed (None: it did not; the states then end before it)."""
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.plugins.tmakit import detections_from_measurements
    from stonesoup.predictor.particle import ParticlePredictor
    from stonesoup.regulariser.particle import MCMCRegulariser
    from stonesoup.resampler.particle import ESSResampler
    from stonesoup.types.array import StateVectors
    from stonesoup.types.hypothesis import SingleHypothesis
    from stonesoup.types.state import ParticleState
    from stonesoup.updater.particle import ParticleUpdater

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
    for k, (when, detections) in enumerate(cycles):
        prediction = predictor.predict(state, timestamp=when)  # (dt 0 at the first: its parent is the prior)
        if detections:
            try:
                state = updater.update(SingleHypothesis(prediction, next(iter(detections))))
            except np.linalg.LinAlgError:
                # the cloud collapsed onto fewer distinct particles than the state has dimensions:
                # the regulariser's kernel covariance is singular and Stone Soup stops
                return out, k
        else:
            state = prediction
        out.append(state)
    return out, None


def run(*, particles: int, stonesoup_particles: tuple[int, ...], runs: int, seed: int,
        grid_path: Path | None = None) -> dict:
    """The comparison: per run, tmakit's filter's final position error and time at ``particles``,
    and Stone Soup's at each of ``stonesoup_particles``, all on the same measurements and each
    from the same prior (Stone Soup's its own draw of the same law at its particle count)."""
    from stonesoup.plugins.tmakit import track_frame

    import acoustics
    from tools.studies.idm_scenarios import get_scenario
    from tracker import rpf
    from tracker.rpf.prior import initial_particles
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
            states, collapsed = stonesoup_track(m, tables, prior, sigma_a_mps2=cfg.sigma_a_mps2,
                                                bearing_sd_deg=cfg.bearing_sigma_deg, rng=rng_ss)
            seconds = time.perf_counter() - start
            if collapsed is not None:  # a run lost: no final error (the summary counts it as the worst)
                row["stonesoup"][n] = {"final_error_m": None, "collapsed_at_cycle": collapsed,
                                       "seconds": round(seconds, 3)}
                continue
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
    with its ratio to tmakit's and the runs whose cloud collapsed (counted as its largest errors)."""
    rows = out["runs"]
    rpf_err = median([r["rpf_final_error_m"] for r in rows])
    res = {"rpf": {"particles": out["particles"], "final_error_median_m": rpf_err,
                   "seconds_median": median([r["rpf_seconds"] for r in rows])}, "stonesoup": []}
    for n in out["stonesoup_particles"]:
        # a run whose cloud collapsed counts as the worst: the median is None if half of them did
        errs = [r["stonesoup"][n]["final_error_m"] for r in rows]
        err = median([math.inf if e is None else e for e in errs])
        err = err if math.isfinite(err) else None
        res["stonesoup"].append({"particles": n, "multiple": n / out["particles"], "final_error_median_m": err,
                                 "over_rpf": None if err is None else err / rpf_err,
                                 "collapsed_runs": sum(e is None for e in errs),
                                 "seconds_median": median([r["stonesoup"][n]["seconds"] for r in rows])})
    return res


def _plot(path: Path, first: dict, pooled: dict[int, dict]) -> None:
    """Run 0 of the first seed at the largest N (the tracks), and each N's median final error
    against Stone Soup's particle count."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    row = first["runs"][0]
    df, truth, m = row["_truth"]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11.0, 4.8))
    ax.plot(truth[:, 0] / 1e3, truth[:, 1] / 1e3, "k-", lw=2, label="target (truth)")
    ax.plot(m.obs_x_m / 1e3, m.obs_y_m / 1e3, "k--", lw=1, label="observer")
    ax.plot(df["x_m"] / 1e3, df["y_m"] / 1e3, "C0-", label=f"tmakit track --method rpf, N = {first['particles']}")
    for j, (n, ss) in enumerate(row["_tracks"].items()):
        ax.plot(ss["x_m"] / 1e3, ss["y_m"] / 1e3, f"C{j + 1}-", lw=1,
                label=f"Stone Soup SIR + MCMC, tmakit's model, N = {n}")
    ax.set_xlabel("east, km")
    ax.set_ylabel("north, km")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=7)
    ax.set_title(f"{SCENARIO} on {AREA}: run 0 of the first seed")
    for j, (n, summ) in enumerate(pooled.items()):
        ns = [s["particles"] for s in summ["stonesoup"]]
        ax2.plot(ns, [s["final_error_median_m"] for s in summ["stonesoup"]], "o-", color=f"C{2 * j + 1}",
                 label=f"Stone Soup with tmakit's model (tmakit's N = {n})")
        ax2.axhline(summ["rpf"]["final_error_median_m"], color=f"C{2 * j}", label=f"tmakit rpf, N = {n}")
        ax2.axhline(2 * summ["rpf"]["final_error_median_m"], color=f"C{2 * j}", ls=":", label=f"2x tmakit rpf, N = {n}")
    ax2.set_xscale("log")
    ax2.set_xlabel("Stone Soup particles")
    ax2.set_ylabel(f"final position error, m (median of {summ['runs']} runs)")
    ax2.legend(loc="best", fontsize=7)
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=100)
    plt.close(fig)
    tmp.replace(path)


def accuracy(session: Session, *, particles: int, multiples: tuple[int, ...], runs: int,
             seeds: tuple[int, ...], grid_path: Path | None) -> tuple[dict, dict]:
    """The accuracy comparison at tmakit's ``particles`` over every seed: each seed's summary and all
    runs pooled (the file's entry), and the first seed's runs (for the figure)."""
    counts = tuple(particles * k for k in multiples)
    outs = {seed: run(particles=particles, stonesoup_particles=counts, runs=runs, seed=seed, grid_path=grid_path)
            for seed in seeds}
    pooled = summary({"particles": particles, "stonesoup_particles": counts,
                      "runs": [r for out in outs.values() for r in out["runs"]]})
    pooled["runs"] = runs * len(seeds)
    by_seed = {str(seed): summary(out) for seed, out in outs.items()}
    at = f"n{particles}_"
    session.say(f"{at}rpf_final_error_median", pooled["rpf"]["final_error_median_m"], "m")
    session.say(f"{at}rpf_seconds_median", pooled["rpf"]["seconds_median"], "s")
    for s in pooled["stonesoup"]:
        n = s["particles"]
        session.say(f"{at}stonesoup_{n}_collapsed_runs", s["collapsed_runs"])
        if s["final_error_median_m"] is not None:
            session.say(f"{at}stonesoup_{n}_final_error_median", s["final_error_median_m"], "m")
            session.say(f"{at}stonesoup_{n}_over_rpf", s["over_rpf"], "x")
        for seed, summ in by_seed.items():
            ratio = next(x["over_rpf"] for x in summ["stonesoup"] if x["particles"] == n)
            if ratio is not None:
                session.say(f"{at}stonesoup_{n}_over_rpf_seed_{seed}", ratio, "x")
        session.say(f"{at}stonesoup_{n}_seconds_median", s["seconds_median"], "s")
    entry = {"particles": particles, "multiples": list(multiples), "seeds": list(seeds), "runs_per_seed": runs,
             "pooled": pooled, "by_seed": by_seed,
             "runs": {str(seed): [{k: v for k, v in r.items() if not k.startswith("_")} for r in out["runs"]]
                      for seed, out in outs.items()}}
    return entry, outs[seeds[0]]


def stonesoup_bearings_rate(n: int = 5000, steps: int = SPEED_STEPS) -> tuple[float, float]:
    """Particle-steps per second of Stone Soup's particle filter on idm-static's bearings alone
    (the module docstring), and the share of its timed cycles that resampled."""
    from stonesoup.models.measurement.nonlinear import Cartesian2DToBearing
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.predictor.particle import ParticlePredictor
    from stonesoup.regulariser.particle import MCMCRegulariser
    from stonesoup.resampler.particle import ESSResampler, MultinomialResampler
    from stonesoup.types.array import StateVectors
    from stonesoup.types.detection import Detection
    from stonesoup.types.hypothesis import SingleHypothesis
    from stonesoup.types.state import ParticleState
    from stonesoup.updater.particle import ParticleUpdater

    from tracker import rpf

    _, t, obs, b = _scenario()
    cfg = rpf.RpfConfig(n_particles=n)
    init = rpf.initial_particles(b[0], obs[0, 2:], cfg, 1, np.random.default_rng(3))[:, 0]
    dt = float(t[1] - t[0])
    # ConstantVelocity's noise_diff_coeff q = sigma_a^2: the continuous white-noise model (position
    # variance q dt^3/3 against tmakit's sigma_a^2 dt^4/4), a different noise size at the same cost
    q = cfg.sigma_a_mps2 ** 2
    trans = CombinedLinearGaussianTransitionModel([ConstantVelocity(q), ConstantVelocity(q)])
    # Stone Soup's bearing is atan2(y, x) (counter-clockwise from east): on the mapping (y, x) it is
    # tmakit's atan2(x, y)
    meas = Cartesian2DToBearing(ndim_state=4, mapping=(2, 0),
                                noise_covar=np.array([[math.radians(cfg.bearing_sigma_deg) ** 2]]))
    updater = ParticleUpdater(meas, resampler=ESSResampler(threshold=n / 3, resampler=MultinomialResampler()),
                              regulariser=MCMCRegulariser(transition_model=trans))
    predictor = ParticlePredictor(trans)
    t0 = datetime(2024, 1, 1)
    # tmakit's particles are relative (x, y, vx, vy); Stone Soup's absolute (x, vx, y, vy)
    prior = ParticleState(StateVectors(np.stack([init[0] + obs[0, 0], init[2] + obs[0, 2], init[1] + obs[0, 1],
                                                 init[3] + obs[0, 3]])),
                          weight=np.full(n, 1.0 / n), timestamp=t0)
    np.random.seed(3)  # Stone Soup draws from numpy's global generator
    resampled, elapsed = 0, 0.0
    for k in range(1, steps + 1):
        ts = t0 + timedelta(seconds=dt * k)
        start = time.perf_counter()
        pred = predictor.predict(prior, timestamp=ts)
        det = Detection(np.array([[b[k]]]), timestamp=ts, measurement_model=meas)
        prior = updater.update(SingleHypothesis(pred, det))
        elapsed += time.perf_counter() - start
        # after a resampling the weights are equal again (checked outside the timing)
        w = np.asarray(prior.weight, dtype=float)
        resampled += bool(np.allclose(w, 1.0 / n, rtol=1e-6, atol=0))
    return steps * n / elapsed, resampled / steps


def speed(session: Session) -> None:
    """Stone Soup's filter and tmakit's on the same bearings, side by side (the module docstring)."""
    bench_tmakit(1, cycles=5)  # warm-up (imports, numba's compile or cache load), not timed
    stonesoup_bearings_rate(n=500, steps=2)  # warm-up (Stone Soup's imports), not timed
    one, _ = bench_tmakit(1, repeat=3)
    one_31, rpf_resampled = bench_tmakit(1, cycles=SPEED_STEPS + 1, repeat=3)
    batched, _ = bench_tmakit(40, repeat=2)
    threaded, _ = bench_tmakit(40, threads=2, repeat=2)
    ss, ss_resampled = stonesoup_bearings_rate()
    session.say("stonesoup_particle_filter_n5000", ss / 1e6, "M particle-steps/s")
    session.say("stonesoup_resampled_fraction_first_30_cycles", ss_resampled)
    session.say("rpf_one_filter_n5000", one / 1e6, "M particle-steps/s")
    session.say("rpf_one_filter_n5000_first_31_cycles", one_31 / 1e6, "M particle-steps/s")
    session.say("rpf_resampled_fraction_first_31_cycles", rpf_resampled)
    session.say("rpf_batched_40_runs_n5000", batched / 1e6, "M particle-steps/s")
    session.say("rpf_batched_40_runs_n5000_2_threads", threaded / 1e6, "M particle-steps/s")
    session.say("speedup_one_filter_vs_stonesoup", one / ss, "x")
    session.say("speedup_one_filter_same_cycles_vs_stonesoup", one_31 / ss, "x")
    session.say("speedup_batched_vs_stonesoup", batched / ss, "x")
    session.say("speedup_batched_2_threads_vs_stonesoup", threaded / ss, "x")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--particles", type=int, nargs="+", default=[2000, 5000],
                   help="tmakit's filter: each N (5000 the paper's; 2000 the Stone Soup test's)")
    p.add_argument("--multiples", type=int, nargs="+", default=[1, 2, 4, 8],
                   help="Stone Soup's particles, as multiples of each --particles")
    p.add_argument("--runs", type=int, default=32, help="runs per seed")
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    p.add_argument("--grid", type=Path, help="the munk-1000 grid (default: built into out/stonesoup/)")
    p.add_argument("--name", default="stonesoup")
    args = p.parse_args(argv)
    session = Session(args.name)
    speed(session)
    entries, first = [], None
    for n in args.particles:
        entry, first = accuracy(session, particles=n, multiples=tuple(args.multiples), runs=args.runs,
                                seeds=tuple(args.seeds), grid_path=args.grid)
        entries.append(entry)
    _plot(RESULTS_DIR / f"{args.name}.png", first, {e["particles"]: e["pooled"] for e in entries})
    session.write(extra_versions=_stonesoup_version(),
                  accuracy={"scenario": SCENARIO, "area": AREA, "level_sigma_db": LEVEL_SIGMA_DB,
                            "by_particles": entries})
    return 0


def _stonesoup_version() -> dict:
    from importlib import metadata

    return {"stonesoup": metadata.version("stonesoup")}


if __name__ == "__main__":
    raise SystemExit(main())
