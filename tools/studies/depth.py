"""A submarine off its class's table depth: what the trackers make of its depth, and what an
unknown depth costs them, over several true depths, on levels the tables did not make.

The class NPS has its tables at 200 m in the built-in ``shelf-break`` area. Two scenarios:
``shelf-nps`` (the observer running west along the slope, the submarine 12 km to the south-
south-east) and ``shelf-slope-nps`` (the observer crossing the slope southward, the submarine to
the south-west; its tables stay those of the origin). For each true depth of `TRUE_DEPTHS_M`
the levels of every band are simulated with BELLHOP along each cycle's true target-to-observer
path (``tmakit simulate --truth bellhop``, `acoustics.builder.truthk`; ``truth="tables"`` reads
them from the grid's depth axis instead), with a P0 and a dK drawn per run (the class's sds),
eq. 11's level errors and eq. 2's bearing errors. The same measurements are tracked by

- the particle filter (bearings and the levels of every band, the class's P0, 2000 particles,
  the variance-preserving regularization, a range prior around the first range with 25 % sd,
  the offset common to a run as the source-level offset state) given the class's depth, given
  the true depth (``Tables.at_target_depth``), and as a bank of filters, one at each of the
  ML analysis's depth hypotheses, weighed as the ML analysis weighs its hypotheses (the method
  ``tmakit track --method rpf --target-depth unknown`` runs, here with these settings); the
  filter with the depth as a state was retired (its own depth interval covered the truth in 7 %
  of runs, its position error 1.82x the filter given the true depth: docs/depth.md);
- the ML motion analysis (all bands) given the class's depth, the true depth, and over depth
  hypotheses (``tracker.mltma.depths``).

With a depth weighed over hypotheses (the ML analysis, the bank) each cycle's position is that
of the hypothesis of the largest weight (the ML analysis, as ``tmakit track`` reports it), or of
the largest weight times the bearings' fit along its track (the bank; `TRACK_RULE`, the other
rule's figures kept beside), the weight after that cycle along each hypothesis's final estimate
carried back: a study's shortcut (the final estimate is not known at that cycle) for the
position error; the depth's figures are those after the last cycle, where it is what the
tracker has.

Per run: the RMS position error over 5 min to the end; with the depth unknown, the final
depth posterior's median, 90 % interval and its surface (<= 15 m) and submerged (>= 40 m)
masses. For the ML analysis the posterior is `tracker.depth.bank.depth_posterior` (each
hypothesis's final estimate carried back over the run); for the particle filter the bank's
posterior. The
hypotheses' final weights are kept per run (``w_<depth>``). What the levels themselves allow,
whatever a tracker makes of the motion: the posterior along the true track (``known_motion``),
and the levels' residual about the tables' K at the true depth along it
(``level_residual_at_true_depth_db``); how far in range scale each tracker's final estimate
carried back is off (``track_range_scale_ln_rms``: what the depth likelihood's range-scale
integral allows for, `tracker.depth.likelihood.RANGE_SCALE_SD`); each weighed method's track at the
hypothesis nearest to the true depth (variant ``nearest``: the best any weighing of its
hypotheses could pick; ``ratio_nearest_hypothesis_to_true_pooled``). The summary: medians of
the position errors and their ratios, the 90 % intervals' coverage of the truth (target
>= 85 %) and widths, the surface-or-submerged call's error rate.
"""

from __future__ import annotations

import dataclasses
import json
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.builder.gridfile import build_grid_file
from envdata.areafile import load_area
from envdata.classes import SourceLevelModel
from envdata.files import atomic_paths
from tools.studies.calibration import Z90
from tools.studies.depth_setup import (  # noqa: F401  (the study's settings, named here too)
    AREA,
    CALIBRATION_MIN,
    DEPTH_SPAN_M,
    KNOWN,
    LATE_MIN,
    METHODS,
    SCENARIO,
    SCENARIOS,
    TARGET_COVERAGE,
    TARGET_RATIO,
    TRACK_RULE,
    TRUE_DEPTHS_M,
    UNKNOWN,
    VARIANTS,
)
from tools.studies.depth_summary import _mismatch_summary, _summary, _text
from tools.studies.depthcheck import table_check
from tools.studies.trackerrors import LEVEL_SD_DB, rpf_config, run_configs
from tracker.depth.bank import (
    TRACK_RULES,
    bearing_fit,
    depth_hypotheses_m,
    depth_posterior,
    hypothesis_weights,
    owners,
    picked_hypothesis,
)
from tracker.depth.likelihood import TrackDepthLikelihood, line_back
from tracker.depth.posterior import (
    DepthPosterior,
    depth_grid_m,
    posterior,
)
from tracker.levels import LevelErrors
from tracker.mltma import MLBatch
from tracker.rpf import RpfConfig, run_batch
from tracker.rpf.track import cycle_profiles
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch


def _rpf_config(tables, sim, ic: int, n_particles: int) -> RpfConfig:
    """The shelf study's settings (class speed statistics, a range prior around the first range
    with 25 % sd, the variance-preserving regularization), sigma_l eq. 11's error: the errors
    that last along a run are integrated out (`tracker.levels`, `_rpf`)."""
    return rpf_config(tables, sim, ic, n_particles, LEVEL_SD_DB)


def _observer(sim) -> np.ndarray:
    return np.stack([sim.obs_x_m, sim.obs_y_m, np.gradient(sim.obs_x_m, sim.t_s),
                     np.gradient(sim.obs_y_m, sim.t_s)], axis=-1)


def _rpf(tables, sim, ic: int, variant: str, true_depth_m: float, rng, n_particles: int, prior_seed):
    """Positions and velocities and the stated range sd (E, T, 5): the filter on the levels of
    every band, their lasting errors integrated out (`tracker.levels.LevelErrors.of_tables`);
    each run's range prior drawn about its first range from ``prior_seed``
    (`tools.studies.trackerrors.prior_centres_m`)."""
    e, t = sim.bearing_deg.shape
    obs = _observer(sim)
    configs = run_configs(_rpf_config(tables, sim, ic, n_particles), sim, prior_seed)
    target = tables.classes[ic]
    view = tables.at_target_depth(true_depth_m) if variant == "true" else tables
    n_bands = len(tables.bands)
    errors = LevelErrors.of_tables(view, ic, source_sd_db=target.noise_sd_db)
    away = view.distance_from_origin_m(sim.obs_x_m, sim.obs_y_m)
    pos = np.empty((e, t, 5))
    for run in range(e):
        profiles = [cycle_profiles(view, ic, b, np.full(t, sim.obs_depth_m), sim.bearing_deg[run])
                    for b in range(n_bands)]
        res = run_batch(k_profiles=profiles, t_s=sim.t_s, obs_state=obs,
                        bearing_rad_meas=np.radians(sim.bearing_deg[run])[None],
                        bearing_sd_rad=np.radians(sim.bearing_sigma_deg[run])[None],
                        level_db_meas=sim.level_db[run][None], cfg=configs[run], rng=rng,
                        source_level_model=SourceLevelModel.P0, p0_db=target.noise_mean_db, summaries=True,
                        level_errors=errors, displacement_m=away)
        pos[run, :, :4] = res.mean[0][:, :4] + obs
        pos[run, :, 4] = res.extra["sd"][0][:, 0]
    return pos


def _ml_positions(tables, sim, ic: int) -> np.ndarray:
    """Positions and velocities of the ML analysis and its stated range sd, every run and cycle,
    (E, T, 5)."""
    e, t = sim.bearing_deg.shape
    batch = MLBatch(tables, np.full(e, ic), t)
    vx = np.gradient(sim.obs_x_m, sim.t_s)
    vy = np.gradient(sim.obs_y_m, sim.t_s)
    pos = np.full((e, t, 5), np.nan)
    for i in range(t):
        out = batch.update(sim.t_s[i], sim.obs_x_m[i], sim.obs_y_m[i], vx[i], vy[i],
                           sim.bearing_deg[:, i], sim.bearing_sigma_deg[:, i], sim.level_db[:, i, :],
                           sim.snr_db[:, i, :], obs_depth_m=sim.obs_depth_m)
        course = np.radians(out["course_deg"])
        pos[:, i] = np.stack([out["x_m"], out["y_m"], out["speed_mps"] * np.sin(course),
                              out["speed_mps"] * np.cos(course), out["range_sd_m"]], axis=-1)
    return pos


def _polar(sim, pos):
    """Range and bearing from the observer of positions (..., T, 2+)."""
    x = pos[..., 0] - sim.obs_x_m
    y = pos[..., 1] - sim.obs_y_m
    return np.hypot(x, y), np.mod(np.degrees(np.arctan2(x, y)), 360.0)


def _carried_back(sim, pos):
    """Range and bearing of the final estimates (..., T, 4) carried back over the run
    (`tracker.depth.likelihood.line_back`), (..., T) each."""
    x, y = line_back(sim.t_s, pos[..., 0], pos[..., 1], pos[..., 2], pos[..., 3])
    return _polar(sim, np.stack([x, y], axis=-1))


def _ml(tables, sim, ic: int, variant: str, true_depth_m: float, like, hypotheses):
    """ML positions (E, T, 2) and, with the depth unknown, the final posterior (E, D) and its
    hypotheses' final weights (E, H). ``hypotheses`` holds the positions at each depth
    hypothesis (H, E, T, 4), computed by the first call that needs them (the class's depth is
    one of them)."""
    z = depth_hypotheses_m(DEPTH_SPAN_M, tables.classes[ic].depth_m)
    own = np.flatnonzero(np.isclose(z, tables.classes[ic].depth_m))
    if variant == "class" and own.size:
        return _ml_hypotheses(tables, sim, ic, z, hypotheses)[own[0]], None, None
    if variant != "unknown":
        view = tables.at_target_depth(true_depth_m) if variant == "true" else tables
        return _ml_positions(view, sim, ic), None, None
    return _weighed(sim, _ml_hypotheses(tables, sim, ic, z, hypotheses), z, like)


def _ml_hypotheses(tables, sim, ic: int, z, hypotheses) -> np.ndarray:
    if "ml" not in hypotheses:
        hypotheses["ml"] = np.array([_ml_positions(tables.at_target_depth(float(h)), sim, ic) for h in z])
    return hypotheses["ml"]


def _rpf_bank(tables, sim, ic: int, like, seed, n_particles: int, hypotheses, prior_seed):
    """The bank of particle filters at the depth hypotheses, each given its depth as the
    variant "true" is, weighed as the ML analysis's hypotheses are (`_weighed`); their positions
    (H, E, T, 4) kept in ``hypotheses["rpf"]``."""
    z = depth_hypotheses_m(DEPTH_SPAN_M, tables.classes[ic].depth_m)
    pos_z = np.array([_rpf(tables, sim, ic, "true", float(h), np.random.default_rng([*seed, h_i]), n_particles,
                           prior_seed) for h_i, h in enumerate(z)])
    hypotheses["rpf"] = pos_z
    return _weighed(sim, pos_z, z, like)


def _nearest_rows(sim, hypotheses, z, z_true: float, late, base) -> list:
    """Rows of variant "nearest": each method's track at the hypothesis nearest to the true depth
    (`tracker.mltma.depths.owners`), the best any weighing of those hypotheses could pick."""
    h = int(owners(np.array([z_true]), z)[0])
    return [_position_rows(sim, pos_z[h], late, {**base, "method": method, "variant": "nearest"})
            for method, pos_z in hypotheses.items()]


def _position_rows(sim, pos, late, base) -> pd.DataFrame:
    """Rows of positions (E, T, 5) without a depth of their own: the RMS position error over the
    ``late`` cycles, the range scale (`_range_scale`), and how the stated range sd holds from
    `CALIBRATION_MIN` on: the share of cycles whose 90 % range interval covers the truth and the
    median |error| / sd."""
    err = np.hypot(pos[..., 0] - sim.x_m, pos[..., 1] - sim.y_m)
    r, _ = _polar(sim, pos)
    checked = (sim.t_s - sim.t_s[0]) / 60.0 >= CALIBRATION_MIN
    with np.errstate(invalid="ignore", divide="ignore"):
        z = np.abs(r - sim.range_m)[:, checked] / pos[..., 4][:, checked]
        cover = np.nanmean(np.where(np.isfinite(z), z <= Z90, np.nan), axis=1)
        z_med = np.nanmedian(z, axis=1)
    return pd.DataFrame({**base, "depth_from": "", "rms_error_m": np.sqrt(np.nanmean(err[:, late] ** 2, axis=1)),
                         "range_scale_ln": _range_scale(sim, pos, late), "range_cover_90": cover,
                         "range_abs_z_median": z_med})


def _weighed(sim, pos_z, z, like):
    """Each cycle's position among the hypotheses' (H, E, T, 4) by each rule of `TRACK_RULES`,
    {rule: (E, T, 4)}; the final posterior (E, D) and the hypotheses' final weights (E, H). The
    weights are each hypothesis's posterior mass along the final estimates carried back
    (`tracker.depth.bank.depth_posterior`)."""
    r, b = _carried_back(sim, pos_z)
    post, own = depth_posterior(like, z, DEPTH_SPAN_M, sim.t_s, r, b, sim.level_db, sim.snr_db,
                                sim.obs_x_m, sim.obs_y_m)                                   # weight (E, T, D)
    w = hypothesis_weights(post, own, z.size)                                               # (E, T, H)
    fit = bearing_fit(sim.bearing_deg, b)                                                   # (E, T, H)
    picked = {rule: np.take_along_axis(pos_z, picked_hypothesis(w, fit, rule)[None, ..., None], axis=0)[0]
              for rule in TRACK_RULES}
    return picked, post.at_cycle(post.weight[:, -1]), w[:, -1]


def _range_scale(sim, pos, late) -> np.ndarray:
    """Per run, ln of the final estimate's range carried back (what a depth posterior along a
    tracker's track reads) over the true range, the median over the ``late`` cycles."""
    r_track, _ = _carried_back(sim, pos)
    r_true, _ = _polar(sim, np.stack([sim.x_m, sim.y_m], axis=-1))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.nanmedian(np.log(r_track[:, late] / r_true[:, late]), axis=1)


def _track_posterior(sim, pos, like, polar=None) -> DepthPosterior:
    """`tracker.depth.errors`'s posterior after the last cycle along positions (E, T, 2+) (or a
    given range and bearing)."""
    z = depth_grid_m(like.tables.depth_m, DEPTH_SPAN_M)
    r, b = _polar(sim, pos) if polar is None else polar
    ll = like(z, sim.t_s, r, b, sim.level_db, sim.snr_db, sim.obs_x_m, sim.obs_y_m)[..., -1]        # (D, E)
    return posterior(z, ll.T, DEPTH_SPAN_M)


def _k_mismatch(sim, like, z_true: float, scenario: str) -> pd.DataFrame:
    """The levels less P0 + K + G with K the tables' at the true depth (averaged as the depth
    likelihood reads it) along the true track, each run's mean taken off: the tables' K error
    along the path with eq. 11's error, per band (rows: runs x bands)."""
    r, b = _polar(sim, np.stack([sim.x_m, sim.y_m], axis=-1))
    k = np.stack([m.at(np.asarray(z_true), r, b) for m in like._mean], axis=-1)          # (E, T, M)
    resid = sim.level_db - (like._base_db + k)
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        run_mean = np.nanmean(resid, axis=(1, 2), keepdims=True)
        band_mean = np.nanmean(resid - run_mean, axis=1)                                 # (E, M)
        along = np.nanstd(resid - run_mean - band_mean[:, None, :], axis=1)              # (E, M)
    return pd.DataFrame({"scenario": scenario, "true_depth_m": z_true,
                         "band": np.tile(np.arange(k.shape[-1]), k.shape[0]),
                         "band_offset_db": band_mean.ravel(), "along_track_sd_db": along.ravel()})


def _depth_rows(post: DepthPosterior) -> dict:
    """Per run: median, 5 % and 95 % quantiles, surface and submerged masses."""
    surf, sub = post.surface_probability()
    return {"depth_m": post.quantile(0.5), "lo_m": post.quantile(0.05), "hi_m": post.quantile(0.95),
            "p_surface": surf, "p_submerged": sub}


def _weight_rows(w: np.ndarray, z) -> dict:
    """Per run, each depth hypothesis's final weight, columns ``w_<depth>``."""
    return {f"w_{h:g}": w[:, j] for j, h in enumerate(z)}


def simulate_runs(tables, scenario, true_depth_m: float, runs: int, seed_key, provider):
    """The study's ``runs`` runs of one scenario (a `tracker.scenario.Scenario`) with its target at
    ``true_depth_m``: P0 and dK drawn per run from the class, the stream seeded by ``seed_key``
    (the study's: (seed, scenario index, depth index)), levels from ``provider`` (None: the
    tables)."""
    cls = tables.classes[tables.class_index(scenario.target_class)]
    rng = np.random.default_rng(list(seed_key))
    return simulate_batch(dataclasses.replace(scenario, target_depth_m=float(true_depth_m)), tables, rng,
                          dp0_db=rng.normal(0.0, cls.noise_sd_db, runs),
                          dk_db=rng.normal(0.0, cls.k_error_sd_db, runs), k_provider=provider)


def _truth_provider(truth: str, out: Path, workers: int):
    if truth == "tables":
        return None
    from acoustics.builder.truthk import BellhopTruth

    return BellhopTruth(load_area(AREA), cache_dir=out / "grids" / "truth-runs", workers=workers)


def run(*, runs: int, out_dir: str | Path, seed: int = 0, workers: int = 2, n_particles: int = 2000,
        truth: str = "bellhop", scenarios=SCENARIOS, true_depths_m=TRUE_DEPTHS_M,
        progress: bool = False) -> dict:
    """The study: build (or reuse) the shelf-break grid in ``out_dir/grids``, simulate ``runs``
    runs of each scenario at each true depth, track them six ways; write ``depth_runs.csv``,
    ``depth.json`` and ``depth.png`` (all or none) and return the summary."""
    if truth not in ("bellhop", "tables"):
        raise ValueError(f"truth must be 'bellhop' or 'tables', got {truth!r}")
    start = time.perf_counter()
    out = Path(out_dir)
    grid = build_grid_file(load_area(AREA), out / "grids" / f"{AREA}-bellhop.nc", workers=workers,
                           progress=progress).file
    from acoustics.grid.opentables import open_tables

    tables = open_tables(grid)
    provider = _truth_provider(truth, out, workers)
    rows, mismatch = [], []
    for s_i, name in enumerate(scenarios):
        sc0 = load_scenario(name)
        ic = tables.class_index(sc0.target_class)
        cls = tables.classes[ic]
        like = TrackDepthLikelihood(tables, ic, tables.band_names, DEPTH_SPAN_M)
        for z_i, z_true in enumerate(true_depths_m):
            sim = simulate_runs(tables, sc0, z_true, runs, (seed, s_i, z_i), provider)
            late = (sim.t_s - sim.t_s[0]) / 60.0 >= LATE_MIN
            base = {"scenario": name, "true_depth_m": float(z_true), "run": np.arange(runs)}
            hypotheses = {}
            hyp_z = depth_hypotheses_m(DEPTH_SPAN_M, cls.depth_m)
            for method in METHODS:
                for v_i, variant in enumerate(VARIANTS[:2] + UNKNOWN[method]):
                    depth_info = {}
                    if method == "rpf" and variant == "bank":
                        pos, final, w = _rpf_bank(tables, sim, ic, like, (seed, s_i, z_i, v_i), n_particles,
                                                  hypotheses, (seed, s_i, z_i))
                        depth_info = {"posterior": {**_depth_rows(final), **_weight_rows(w, hyp_z)}}
                    elif method == "rpf":
                        pos = _rpf(tables, sim, ic, variant, z_true, np.random.default_rng([seed, s_i, z_i, v_i]),
                                   n_particles, (seed, s_i, z_i))
                    else:
                        pos, final, w = _ml(tables, sim, ic, variant, z_true, like, hypotheses)
                        if final is not None:
                            depth_info = {"posterior": {**_depth_rows(final), **_weight_rows(w, hyp_z)}}
                    others = {}
                    if isinstance(pos, dict):  # picked among the depth hypotheses by each rule
                        others = {f"{variant}_by_{rule}": p for rule, p in pos.items() if rule != TRACK_RULE[method]}
                        pos = pos[TRACK_RULE[method]]
                    rows += [_position_rows(sim, p, late, {**base, "method": method, "variant": v})
                             for v, p in others.items()]
                    own = _position_rows(sim, pos, late, {**base, "method": method, "variant": variant})
                    if not depth_info:
                        rows.append(own)
                    for source, d in depth_info.items():
                        rows.append(own.assign(depth_from=source, **d))
            rows += _nearest_rows(sim, hypotheses, hyp_z, float(z_true), late, base)
            # the levels' own say with the motion known: the posterior along the true track
            true_pos = np.stack([sim.x_m, sim.y_m], axis=-1)
            rows.append(pd.DataFrame({**base, "method": KNOWN, "variant": "unknown", "depth_from": "true_track",
                                      "rms_error_m": 0.0, **_depth_rows(_track_posterior(sim, true_pos, like))}))
            mismatch.append(_k_mismatch(sim, like, z_true, name))
    frame = pd.concat(rows, ignore_index=True)
    summary = _summary(frame, tables, ic, runs=runs, seed=seed, n_particles=n_particles, truth=truth,
                       grid=grid, provider=provider)
    summary["level_residual_at_true_depth_db"] = _mismatch_summary(mismatch)
    if provider is not None:
        summary["tables_vs_bellhop_from_target_db"] = table_check(tables, provider, ic, DEPTH_SPAN_M)
    summary["seconds"] = round(time.perf_counter() - start, 1)
    files = [out / "depth_runs.csv", out / "depth.json", out / "depth.png"]
    from acoustics.plots.figures import save_figure
    from tools.studies.depth_plot import depth_figure

    fig = depth_figure(frame, summary)
    with atomic_paths(files) as (csv_tmp, json_tmp, png_tmp):
        frame.to_csv(csv_tmp, index=False, float_format="%.6g")
        json_tmp.write_text(json.dumps(summary, indent=1) + "\n")
        save_figure(fig, png_tmp, atomic=False)
    summary["files"] = [str(f) for f in files]
    summary["summary"] = _text(summary)
    return summary


def main(argv=None) -> int:
    import argparse

    parser = argparse.ArgumentParser(prog="python -m tools.studies.depth",
                                     description="The depth study (docs/depth.md): several true depths on "
                                                 "shelf-nps and shelf-slope-nps, tracked with the class's depth, "
                                                 "the true depth and the depth unknown.")
    parser.add_argument("--runs", type=int, default=6, help="runs per scenario and true depth (default 6)")
    parser.add_argument("--out", required=True, help="output directory (its grids/ is reused)")
    parser.add_argument("--truth", choices=("bellhop", "tables"), default="bellhop",
                        help="levels from BELLHOP along each cycle's path, or from the tables' depth axis")
    parser.add_argument("--depths", default=",".join(f"{z:g}" for z in TRUE_DEPTHS_M),
                        help="true depths, m, comma-separated")
    parser.add_argument("--scenarios", default=",".join(SCENARIOS), help="scenarios, comma-separated")
    parser.add_argument("--particles", type=int, default=2000, help="particles of each filter (default 2000)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    a = parser.parse_args(argv)
    res = run(runs=a.runs, out_dir=a.out, seed=a.seed, workers=a.workers, n_particles=a.particles, truth=a.truth,
              scenarios=tuple(a.scenarios.split(",")), true_depths_m=tuple(float(v) for v in a.depths.split(",")))
    print(res["summary"])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
