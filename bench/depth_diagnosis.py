"""Why the particle filter's range intervals miss the truth on the depth study (docs/depth.md,
"Stated range sds"): the filter given the true depth, on the study's own runs, with three level
models side by side, and its model's posterior at the truth against its best path.

    python -m bench.depth_diagnosis [--cache docs/results/depth] [--runs 12] [--posterior-runs 3]

For each scenario and true depth of the depth study (the same runs: its seeds, its BELLHOP truth,
its grid, read from ``--cache``, the study's output folder, built there if missing) the filter
given the true depth (`tools.studies.depth`'s settings, with the paper's acceleration sd alone:
the diagnosis is of that sd, the studies' filters now share out three) runs

- ``levels``: as in the study (every band's level, the errors that last integrated out);
- ``levels_k_smoothed``: K averaged over a range uncertainty r' ~ N(r, max(`SMOOTH_FLOOR_M`,
  `SMOOTH_FRACTION` r)) (`tracker.depth.kstructure`) and the spread of K there (the median over
  the profile's 3-25 km) added to the level's own sd: a model that does not trust the tables'
  short ripple;
- ``bearings_only``: the same filter without levels (on the slope run the observer keeps one
  course: the range is the range and speed priors');
- ``bearings_only_sd_floor``: the same with the filter's bearing sd at least
  `BEARING_SD_FLOOR_DEG` (the measured sds go down to 0.05 deg): whether the bearings' likelihood,
  a tube narrower than the cloud can fill, is what narrows the cloud.

Reported: the share of cycles after 10 min whose 90 % range interval holds the truth, the median
|error| / sd, the median over runs of the RMS position error after 5 min.

Then the filter's model's own posterior on the bearings, without sampling
(`tracker.rpf.gaussiansum`, a Gaussian sum of EKFs), for the first ``--model-runs`` runs of every
case, with the paper's acceleration sd and the smaller ones of `MODEL_SIGMA_A_MPS2`: its range
interval's coverage, and how much more probable the bearings are under each (the log evidence
against the paper's, median over runs). Where the sum misses as the bearings-only filter does,
the miss is the model's, not the sampler's.

Then, for the first ``--posterior-runs`` runs of `POSTERIOR_CASE`, the filter's own model's log
posterior (bearings, the levels' exact marginal, the filter's range and speed priors) along
constant-velocity paths: at the true path and at the best path found by profiling the first
range (the other three parameters optimised at each), and along the true path the spread of the
levels' residual across the bands (the class's model has the bands' errors fully correlated:
only the measurement's own 1.1 dB separates them). Writes docs/results/depth-diagnosis.json.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from bench.harness import REPO, Session

SMOOTH_FRACTION = 0.05
SMOOTH_FLOOR_M = 200.0
#: The ranges over which a profile's K spread is summarised, m.
SPREAD_SPAN_M = (3000.0, 25000.0)
POSTERIOR_CASE = ("shelf-slope-nps", 6.0)
#: The first ranges profiled, relative to the true first range, m.
PROFILE_SPAN_M = (-6000.0, 8000.0, 500.0)
MODELS = ("levels", "levels_k_smoothed", "bearings_only", "bearings_only_sd_floor")
BEARING_SD_FLOOR_DEG = 0.5
#: The acceleration sds whose model posterior on the bearings is computed, m/s^2 (the paper's first).
MODEL_SIGMA_A_MPS2 = (1.5e-3, 3e-4, 1e-4)
#: The Gaussian sum's nodes over first range, course and speed (`tracker.rpf.gaussiansum`).
MODEL_GRID = (25, 21, 15)


def _smoothed(profile, cache: dict):
    """The profile with K averaged over the range uncertainty, and the sd of K's spread there."""
    from acoustics.grid.levelprofile import LevelProfile
    from tracker.depth.kstructure import RangeSmoothing, smoothed_k

    key = id(profile)
    if key not in cache:
        k = np.asarray(profile.k_db, dtype=float)
        mean, var = smoothed_k(k, profile.range_m, RangeSmoothing(fraction=SMOOTH_FRACTION, floor_m=SMOOTH_FLOOR_M))
        span = (profile.range_m >= SPREAD_SPAN_M[0]) & (profile.range_m <= SPREAD_SPAN_M[1]) & np.isfinite(var)
        cache[key] = (LevelProfile(range_m=profile.range_m, k_db=np.where(np.isfinite(mean), mean, k),
                                   k_sd_db=profile.k_sd_db),
                      float(np.sqrt(np.median(var[span]))), profile)  # the original kept: ids stay unique
    return cache[key][:2]


def track(tables, sim, ic: int, view, model: str, rng, n_particles: int) -> np.ndarray:
    """Positions, velocities and the stated range sd (E, T, 5) of the filter under ``model``."""
    from envdata.classes import SourceLevelModel
    from tools.studies.depth import _observer
    from tools.studies.trackerrors import LEVEL_SD_DB, rpf_config
    from tracker.levels import LevelErrors
    from tracker.rpf import run_batch
    from tracker.rpf.track import cycle_profiles

    e, t = sim.bearing_deg.shape
    obs = _observer(sim)
    target = tables.classes[ic]
    errors = LevelErrors.of_tables(view, ic, source_sd_db=target.noise_sd_db)
    away = view.distance_from_origin_m(sim.obs_x_m, sim.obs_y_m)
    cache: dict = {}
    floor = BEARING_SD_FLOOR_DEG if model == "bearings_only_sd_floor" else 0.0
    pos = np.empty((e, t, 5))
    for run in range(e):
        profiles, spread = [], []
        for b in range(len(tables.bands)):
            raw = cycle_profiles(view, ic, b, np.full(t, sim.obs_depth_m), sim.bearing_deg[run])
            if model == "levels_k_smoothed":
                pairs = [_smoothed(p, cache) for p in raw]
                raw = [p for p, _ in pairs]
                spread += [s for _, s in pairs]
            profiles.append(raw)
        sigma = float(np.hypot(LEVEL_SD_DB, np.median(spread))) if spread else LEVEL_SD_DB
        levels = sim.level_db[run][None]
        res = run_batch(k_profiles=profiles, t_s=sim.t_s, obs_state=obs,
                        bearing_rad_meas=np.radians(sim.bearing_deg[run])[None],
                        bearing_sd_rad=np.radians(np.maximum(sim.bearing_sigma_deg[run], floor))[None],
                        level_db_meas=np.full(levels.shape, np.nan) if model.startswith("bearings_only") else levels,
                        cfg=replace(rpf_config(tables, sim, ic, n_particles, sigma), sigma_a_mix_mps2=()), rng=rng,
                        source_level_model=SourceLevelModel.P0, p0_db=target.noise_mean_db, summaries=True,
                        level_errors=errors, displacement_m=away)
        pos[run, :, :4] = res.mean[0][:, :4] + obs
        pos[run, :, 4] = res.extra["sd"][0][:, 0]
    return pos


def simulate(tables, provider, scenario: str, true_depth_m: float, runs: int, seed: int = 0):
    """The depth study's runs of one scenario and true depth (`tools.studies.depth.simulate_runs`
    with the study's seeds), the class index and the seed key."""
    from tools.studies.depth import simulate_runs
    from tools.studies.depth_setup import SCENARIOS, TRUE_DEPTHS_M
    from tracker.scenario import load_scenario

    key = (seed, SCENARIOS.index(scenario), TRUE_DEPTHS_M.index(true_depth_m))
    sc = load_scenario(scenario)
    return simulate_runs(tables, sc, true_depth_m, runs, key, provider), tables.class_index(sc.target_class), key


class PathPosterior:
    """The filter's model's log posterior along constant-velocity paths of one run: (first range,
    first bearing, course, speed) from the observer's first position."""

    def __init__(self, tables, sim, ic: int, view, run: int):
        from tools.studies.trackerrors import LEVEL_SD_DB, rpf_config
        from tracker.levels import LevelErrors
        from tracker.rpf.track import cycle_profiles

        self.sim, self.run, self.cls = sim, run, tables.classes[ic]
        self.errors = LevelErrors.of_tables(view, ic, source_sd_db=self.cls.noise_sd_db)
        self.cfg = rpf_config(tables, sim, ic, 2, LEVEL_SD_DB)  # its priors only
        self.level_var = LEVEL_SD_DB ** 2
        self.t = sim.t_s - sim.t_s[0]
        self.away = view.distance_from_origin_m(sim.obs_x_m, sim.obs_y_m)
        depth = np.full(self.t.size, sim.obs_depth_m)
        self.profiles = [cycle_profiles(view, ic, b, depth, sim.bearing_deg[run]) for b in range(len(tables.bands))]

    def truth(self) -> tuple:
        s, r = self.sim, self.run
        return (float(s.range_m[r, 0]), float(s.bearing_true_deg[r, 0]), float(s.course_deg[r, 0]),
                float(s.speed_mps[r, 0]))

    def residual(self, q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Relative x, y (T,) and the levels less P0 and K along path ``q`` (T, M)."""
        s = self.sim
        r0, b0, course, speed = q
        x = s.obs_x_m[0] + r0 * np.sin(np.radians(b0)) + speed * np.sin(np.radians(course)) * self.t
        y = s.obs_y_m[0] + r0 * np.cos(np.radians(b0)) + speed * np.cos(np.radians(course)) * self.t
        rx, ry = x - s.obs_x_m, y - s.obs_y_m
        rng_m = np.hypot(rx, ry)
        k = np.stack([np.array([p(r) for p, r in zip(band, rng_m)]) for band in self.profiles], axis=-1)
        return rx, ry, s.level_db[self.run] - self.cls.noise_mean_db - k

    def log_posterior(self, q) -> float:
        from tracker.levels import log_marginal, path_steps_m

        s, cfg = self.sim, self.cfg
        rx, ry, resid = self.residual(q)
        bearing = np.degrees(np.arctan2(rx, ry)) % 360.0
        miss = (s.bearing_deg[self.run] - bearing + 180.0) % 360.0 - 180.0
        ok = np.isfinite(miss)
        ln_b = -0.5 * np.sum((miss[ok] / s.bearing_sigma_deg[self.run][ok]) ** 2)
        ln_l = log_marginal(resid, np.full(resid.shape, self.level_var), self.errors, t_s=self.t,
                            step_m=path_steps_m(rx, ry), displacement_m=self.away)[-1]
        ln_p = (-0.5 * ((q[0] - cfg.range_mean_m) / cfg.range_sd_m) ** 2
                - 0.5 * ((q[3] - self.cls.speed_mean_mps) / self.cls.speed_sd_mps) ** 2)
        return float(ln_b + ln_l + ln_p)

    def best(self) -> tuple[float, tuple]:
        """The best path over the profiled first ranges (the other parameters optimised from the
        true path's, scaled)."""
        from scipy.optimize import minimize

        truth = self.truth()
        best = (-np.inf, truth)
        for r0 in truth[0] + np.arange(*PROFILE_SPAN_M):
            if r0 < 1000.0:
                continue
            start = (truth[1], truth[2], truth[3] * r0 / truth[0])
            res = minimize(lambda p, r0=r0: -self.log_posterior((r0, *p)), start, method="Nelder-Mead",
                           options={"xatol": 1e-4, "fatol": 1e-3, "maxiter": 3000})
            if -res.fun > best[0]:
                best = (-float(res.fun), (float(r0), *map(float, res.x)))
        return best


def model_posterior(tables, sim, ic: int, runs: int, sigma_a_mps2: float) -> dict:
    """The filter's model's posterior of the range on the bearings of the first ``runs`` runs
    (`tracker.rpf.gaussiansum.bearings_posterior`, the filter's prior and sigma_theta): the share
    of cycles after `LATE_MIN` whose 90 % interval holds the truth, the median |error| / sd, and
    each run's log evidence of its bearings."""
    from tools.studies.depth import _observer
    from tools.studies.depth_setup import LATE_MIN
    from tools.studies.trackerrors import rpf_config
    from tracker.rpf.gaussiansum import bearings_posterior

    cfg = replace(rpf_config(tables, sim, ic, 2), sigma_a_mps2=sigma_a_mps2, sigma_a_mix_mps2=())
    obs = _observer(sim)
    late = (sim.t_s - sim.t_s[0]) / 60.0 >= LATE_MIN
    z, evidence = [], []
    for run in range(runs):
        got = bearings_posterior(sim.t_s, obs, np.radians(sim.bearing_deg[run]), np.radians(sim.bearing_sigma_deg[run]),
                                 cfg, grid=MODEL_GRID)
        z.append(((got.range_mean_m - sim.range_m[run]) / got.range_sd_m)[late])
        evidence.append(got.log_evidence)
    z = np.concatenate(z)
    return {"coverage_90": float(np.mean(np.abs(z) <= 1.645)), "abs_z_median": float(np.median(np.abs(z))),
            "log_evidence": evidence}


def coverage_rows(sim, pos) -> dict:
    from tools.studies.depth import _position_rows
    from tools.studies.depth_setup import LATE_MIN

    late = (sim.t_s - sim.t_s[0]) / 60.0 >= LATE_MIN
    rows = _position_rows(sim, pos, late, {})
    return {"coverage_90": float(rows.range_cover_90.mean()), "abs_z_median": float(rows.range_abs_z_median.median()),
            "rms_error_median_m": float(rows.rms_error_m.median()), "_rows": rows}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.depth_diagnosis", description=__doc__.split("\n\n")[0])
    parser.add_argument("--cache", default=str(REPO / "docs" / "results" / "depth"),
                        help="the depth study's output folder (its grids/ and truth runs are reused)")
    parser.add_argument("--runs", type=int, default=12, help="runs per scenario and true depth (the study's 12)")
    parser.add_argument("--posterior-runs", type=int, default=3)
    parser.add_argument("--model-runs", type=int, default=4,
                        help="runs per case whose model posterior is computed (a few seconds each per acceleration sd)")
    parser.add_argument("--particles", type=int, default=2000, help="the study's 2000")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)

    import pandas as pd

    from acoustics.builder.gridfile import build_grid_file
    from acoustics.builder.truthk import BellhopTruth
    from acoustics.grid.opentables import open_tables
    from envdata.areafile import load_area
    from tools.studies.depth_setup import AREA, SCENARIOS, TRUE_DEPTHS_M

    session = Session("depth-diagnosis")
    cache = Path(args.cache)
    grid = build_grid_file(load_area(AREA), cache / "grids" / f"{AREA}-bellhop.nc", workers=args.workers).file
    tables = open_tables(grid)
    provider = BellhopTruth(load_area(AREA), cache_dir=cache / "grids" / "truth-runs", workers=args.workers)
    by_case: dict = {}
    pooled: dict = {m: [] for m in MODELS}
    model_posteriors: dict = {}
    for scenario in SCENARIOS:
        for z in TRUE_DEPTHS_M:
            sim, ic, seed = simulate(tables, provider, scenario, z, args.runs)
            view = tables.at_target_depth(z)
            for m_i, model in enumerate(MODELS):
                # the study's stream for the filter given the true depth (variant index 1)
                rng = np.random.default_rng([*seed, 1] if model == "levels" else [*seed, 1, m_i])
                got = coverage_rows(sim, track(tables, sim, ic, view, model, rng, args.particles))
                pooled[model].append(got.pop("_rows"))
                by_case.setdefault(scenario, {}).setdefault(f"{z:g}", {})[model] = got
                print(f"{scenario} {z:g} m {model}: {got}", flush=True)
            # the filter's model's own posterior on the same runs' bearings
            row = {f"{a:g}": model_posterior(tables, sim, ic, min(args.model_runs, args.runs), a)
                   for a in MODEL_SIGMA_A_MPS2}
            paper = row[f"{MODEL_SIGMA_A_MPS2[0]:g}"]["log_evidence"]
            for got in row.values():
                got["log_evidence_vs_paper_median"] = float(np.median(np.subtract(got["log_evidence"], paper)))
            model_posteriors.setdefault(scenario, {})[f"{z:g}"] = row
            said = (f"{a}: {g['coverage_90']:.2f} / {g['abs_z_median']:.2f} / {g['log_evidence_vs_paper_median']:+.1f}"
                    for a, g in row.items())
            print(f"{scenario} {z:g} m model posterior: " + ", ".join(said), flush=True)
    for a in MODEL_SIGMA_A_MPS2:
        key = f"{a:g}"
        cells = [row[key] for by_z in model_posteriors.values() for row in by_z.values()]
        cover = float(np.mean([c["coverage_90"] for c in cells]))
        session.say(f"model_posterior_coverage_90_mean_sigma_a_{key}", cover)
    for model, parts in pooled.items():
        f = pd.concat(parts)
        session.say(f"{model}_coverage_90_pooled", float(f.range_cover_90.mean()))
        session.say(f"{model}_abs_z_median_pooled", float(f.range_abs_z_median.median()))
        session.say(f"{model}_rms_error_median_pooled_m", float(f.rms_error_m.median()), "m")

    scenario, z = POSTERIOR_CASE
    sim, ic, _ = simulate(tables, provider, scenario, z, args.runs)
    view = tables.at_target_depth(z)
    posterior = []
    for run in range(args.posterior_runs):
        post = PathPosterior(tables, sim, ic, view, run)
        at_truth = post.log_posterior(post.truth())
        best, q = post.best()
        _, _, resid = post.residual(post.truth())
        band_spread = float(np.sqrt(np.nanmean(np.nanvar(resid, axis=1))))
        posterior.append({"run": run, "true_first_range_m": post.truth()[0], "log_posterior_truth": at_truth,
                          "log_posterior_best": best, "best_first_range_m": q[0],
                          "truth_below_best": best - at_truth, "band_spread_at_truth_db": band_spread})
        print(posterior[-1], flush=True)
    session.say("posterior_truth_below_best_median", float(np.median([p["truth_below_best"] for p in posterior])))
    session.say("band_spread_at_truth_db_median", float(np.median([p["band_spread_at_truth_db"] for p in posterior])),
                "dB")
    session.write(models=list(MODELS), smooth_fraction=SMOOTH_FRACTION, smooth_floor_m=SMOOTH_FLOOR_M,
                  bearing_sd_floor_deg=BEARING_SD_FLOOR_DEG,
                  runs=args.runs, particles=args.particles, by_case=by_case,
                  model_sigma_a_mps2=list(MODEL_SIGMA_A_MPS2), model_grid=list(MODEL_GRID), model_runs=args.model_runs,
                  model_posterior=model_posteriors,
                  posterior_case={"scenario": scenario, "true_depth_m": z, "runs": posterior})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
