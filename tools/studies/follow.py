"""Following the observer through an atlas, on levels the tables did not make (docs/atlas-tracking.md).

An observer crosses the shelf-break slope (scenario ``shelf-cross``); the measurements are
simulated with K from BELLHOP along each cycle's true target-to-observer geodesic
(``acoustics.builder.truthk``: no reciprocity, no grid, no interpolation), and, for reference,
from the 5 km atlas's own tables; each run's target drawn from its class
(`tools.studies.calibration.class_draws`: speed on five nodes, P0 and dK). Each set is tracked by
the ML analysis (true class; with the manoeuvre tests of ``tracker.mltma.maneuver`` as now, and
as the paper writes them), the particle filter (bearings and SPL, the levels' lasting errors
integrated out, `tracker.levels`) and the filter on bearings alone, with three sets of tables:

- ``origin``: the built-in shelf-break grid, centred where the observer starts;
- ``atlas-10km``, ``atlas-5km``: the area's atlas (``shelf-break-atlas``) at two spacings,
  the tables following the observer.

Position RMSE against time over the runs, the manoeuvres the ML analysis declares (the target
never manoeuvres), the truth's levels against the tables' along the path, and each tracker's
stated sds against the truth after `LATE_MIN` (`tools.studies.calibration`).
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.builder.atlas import build_atlas_file
from acoustics.builder.gridfile import build_grid_file
from acoustics.builder.truthk import BellhopTruth
from acoustics.grid.formats import RESULT_FORMAT
from acoustics.grid.opentables import open_tables
from envdata.areafile import load_area
from envdata.files import atomic_paths
from tools.studies.calibration import class_draws
from tools.studies.trackerrors import FILTER_PARTICLES, LEVEL_SD_DB, ml_errors, ml_track, rpf_config, rpf_track
from tracker.mltma import MLParams
from tracker.scenario import load_scenario
from tracker.simulate import TruePaths, simulate_batch, tables_k

AREA, ATLAS_AREA, SCENARIO = "shelf-break", "shelf-break-atlas", "shelf-cross"
SPACINGS_KM = (10.0, 5.0)
TABLES = ("origin", "atlas-10km", "atlas-5km")
TRUTHS = ("bellhop", "tables")
REPORT_MIN = (10, 20, 30, 40)
#: The position errors are compared from this minute on (before it the ML analysis ranges on
#: the levels alone), min.
LATE_MIN = 10.0
#: The time bins of the tables' K along the path (its error, its slope) and of the ML analysis's
#: level ranges against the truth, min.
TIME_BINS_MIN = (0, 5, 10, 15, 20, 30, 40)
#: K's slope near the true range is read between these multiples of it (`k_slope_by_time`).
K_SLOPE_FACTORS = (0.8, 1.25)


def _by_time_bin(minutes, summary) -> dict:
    """``summary(cycles)`` for each bin of `TIME_BINS_MIN`, ``cycles`` the bin's mask over ``minutes``."""
    return {f"{lo}-{hi}": summary((minutes >= lo) & (minutes < hi))
            for lo, hi in zip(TIME_BINS_MIN[:-1], TIME_BINS_MIN[1:])}


def level_range_by_time(record: dict, range_m, minutes) -> dict:
    """The ML analysis's level range (eq. 20) and its sd (eq. 21) against the true range, per time
    bin of `TIME_BINS_MIN` over runs and cycles: the median and the RMS of ln(r_level / r) and the
    median of sd / r (a level range whose sd is honest has |ln error| about sd / r)."""
    ln_err = np.log(record["r_level_m"] / range_m)
    rel_sd = record["r_level_sd_m"] / range_m
    return _by_time_bin(minutes, lambda c: {
        "ln_error_median": round(float(np.nanmedian(ln_err[:, c])), 3),
        "ln_error_rms": round(float(np.sqrt(np.nanmean(ln_err[:, c] ** 2))), 3),
        "sd_over_range_median": round(float(np.nanmedian(rel_sd[:, c])), 3)})


def _first_path(sim, sc, ic: int, scale: float = 1.0) -> TruePaths:
    """The first run's true path (the runs share it), its ranges multiplied by ``scale``."""
    return TruePaths(ic=ic, obs_x_m=sim.obs_x_m, obs_y_m=sim.obs_y_m, obs_depth_m=sim.obs_depth_m,
                     x_m=sim.x_m[:1], y_m=sim.y_m[:1], range_m=scale * sim.range_m[:1],
                     bearing_deg=sim.bearing_true_deg[:1], target_depth_m=sc.target_depth_m)


def k_slope_by_time(sim, sc, ic: int, tables: dict) -> dict:
    """How much each table's K says about range near the true one: (K(0.8 r) - K(1.25 r)) /
    log10(1.25 / 0.8) along the true path (`K_SLOPE_FACTORS`), the tables where the observer is,
    at the true bearing, every band; per time bin of `TIME_BINS_MIN`, the median over the cycles
    and bands, dB per decade of range (20 for spherical spreading; near 0 where K is flat)."""
    minutes = (sim.t_s - sim.t_s[0]) / 60.0
    near, far = K_SLOPE_FACTORS
    out = {}
    for name, tab in tables.items():
        k = tables_k(tab)
        slope = (k(_first_path(sim, sc, ic, near))[0] - k(_first_path(sim, sc, ic, far))[0]) / np.log10(far / near)
        out[name] = _by_time_bin(minutes, lambda c, slope=slope: round(float(np.nanmedian(slope[c])), 2))
    return out


def k_error_by_time(sim, sc, ic: int, truth, tables: dict) -> dict:
    """BELLHOP's K along the true path (the runs share it) less each table's K there, every band:
    per time bin of `TIME_BINS_MIN`, the mean and the RMS over cycles and bands, dB."""
    paths = _first_path(sim, sc, ic)
    k_truth = truth(paths)[0]                                                       # (T, M)
    minutes = (sim.t_s - sim.t_s[0]) / 60.0
    out = {}
    for name, tab in tables.items():
        d = k_truth - tables_k(tab)(paths)[0]                                       # (T, M)
        out[name] = _by_time_bin(minutes, lambda c, d=d: {"mean_db": round(float(np.nanmean(d[c])), 2),
                                                          "rms_db": round(float(np.sqrt(np.nanmean(d[c] ** 2))), 2)})
    return out


def _rms(values) -> float:
    """The RMS of an RMSE over time (NaN where no run has an estimate left out)."""
    return float(np.sqrt(np.nanmean(np.asarray(values, dtype=float) ** 2)))


def _shown(path: Path) -> str:
    """A table's path as the result file records it: relative to where the study ran, if inside."""
    try:
        return str(Path(path).resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def build_tables(out: Path, workers: int) -> dict[str, Path]:
    """The origin grid and the two atlases in ``out`` (reused when up to date)."""
    files = {"origin": build_grid_file(load_area(AREA), out / f"{AREA}-bellhop.nc", workers=workers).file}
    atlas_area = load_area(ATLAS_AREA)
    for spacing in SPACINGS_KM:
        area = dataclasses.replace(atlas_area, atlas=dataclasses.replace(atlas_area.atlas, spacing_km=spacing))
        path = out / f"atlas-{spacing:g}km.zarr"
        build_atlas_file(area, path, workers=workers)
        files[f"atlas-{spacing:g}km"] = path
    return {k: Path(v) for k, v in files.items()}


def run(*, runs: int, out_dir: str | Path, seed: int = 0, workers: int = 2,
        n_particles: int = FILTER_PARTICLES) -> dict:
    """The study: write ``follow_rmse.csv``, ``follow.json`` and ``follow_rmse.png`` (all or none)."""
    start = time.perf_counter()
    out = Path(out_dir)
    paths = build_tables(out / "grids", workers)
    tables = {name: open_tables(path) for name, path in paths.items()}
    sc = load_scenario(SCENARIO)
    ic = tables["origin"].class_index(sc.target_class)
    band = 0  # FB1, the band heard farthest
    truth = BellhopTruth(load_area(AREA), cache_dir=out / "grids" / "truth-runs", workers=workers)
    t0 = time.perf_counter()
    draws = class_draws(sc, tables["origin"].classes[ic], runs, np.random.default_rng([seed, 2]))
    sims = {"bellhop": simulate_batch(sc, tables["origin"], np.random.default_rng([seed, 0]), **draws,
                                      k_provider=truth)}
    truth_seconds = time.perf_counter() - t0
    sims["tables"] = simulate_batch(sc, tables["atlas-5km"], np.random.default_rng([seed, 0]), **draws)
    minutes = (sims["bellhop"].t_s - sims["bellhop"].t_s[0]) / 60.0
    frame = pd.DataFrame({"t_min": minutes})
    rmse, tacks, level_ranges, calibration, late_errors = {}, {}, {}, {}, {}
    late = minutes >= LATE_MIN
    for truth_name, sim in sims.items():
        for name, tab in tables.items():
            for label, params in (("ml", MLParams()), ("ml-paper", MLParams(maneuver_curved=False,
                                                                              level_vs_k=False))):
                record = {} if (label, truth_name) == ("ml", "bellhop") else None
                tr = ml_track(tab, sim, ic, params, record=record)
                err, tk = tr.position_error_m(sim), tr.tacks
                late_errors[(label, name, truth_name)] = err[:, late]
                if record is not None:
                    level_ranges[name] = level_range_by_time(record, sim.range_m, minutes)
                frame[f"{label}_{name}_{truth_name}_rmse_m"] = np.sqrt(np.nanmean(err ** 2, axis=0))
                tacks[f"{label}_{name}_{truth_name}"] = {"mean_manoeuvres": float(np.mean(tk - 1)),
                                                         "runs_with_any": int(np.sum(tk > 1))}
                calibration[f"{label}_{name}_{truth_name}"] = tr.calibration(sim, late)
            for label, kw in (("rpf", {"config": rpf_config(tab, sim, ic, n_particles, LEVEL_SD_DB),
                                       "level_errors": "tables"}),
                              ("bot", {"bearings_only": True})):
                tr = rpf_track(tab, sim, ic, band, np.random.default_rng([seed, 1]), n_particles, prior_seed=seed,
                               **kw)
                err = tr.position_error_m(sim)
                late_errors[(label, name, truth_name)] = err[:, late]
                frame[f"{label}_{name}_{truth_name}_rmse_m"] = np.sqrt(np.nanmean(err ** 2, axis=0))
                calibration[f"{label}_{name}_{truth_name}"] = tr.calibration(sim, late)
    for col in frame.columns[1:]:
        rmse[col.removesuffix("_rmse_m")] = {f"{m:g}": float(np.interp(m, minutes, frame[col])) for m in REPORT_MIN}
    # each atlas's error after 10 min over the origin table's on the same runs, with its interval
    over_origin = {f"{label} {name}": ratio_to_reference(late_errors[(label, name, "bellhop")],
                                                         late_errors[(label, "origin", "bellhop")],
                                                         np.random.default_rng([seed, 9]))
                   for label in ("ml", "rpf") for name in tables if name != "origin"}
    diff = sims["bellhop"].level_true_db[0, :, band] - sims["tables"].level_true_db[0, :, band]
    k_error = k_error_by_time(sims["bellhop"], sc, ic, truth, tables)
    k_slope = k_slope_by_time(sims["bellhop"], sc, ic, tables)
    obs_travel = float(np.hypot(np.ptp(sims["bellhop"].obs_x_m), np.ptp(sims["bellhop"].obs_y_m)))
    summary = {"scenario": sc.name, "runs": runs, "seed": seed, "n_particles": n_particles, "class": sc.target_class,
               "band": tables["origin"].band_names[band], "observer_travel_m": obs_travel,
               "tables": {k: _shown(v) for k, v in paths.items()},
               "truth_runs": truth.stats.runs, "truth_runs_cached": truth.stats.cached,
               "truth_seconds": round(truth_seconds, 1),
               "level_bellhop_minus_atlas5km_db": {"median": float(np.nanmedian(diff)),
                                                   "sd": float(np.nanstd(diff)),
                                                   "p95_abs": float(np.nanpercentile(np.abs(diff), 95))},
               "bellhop_minus_tables_k_db": k_error, "tables_k_slope_db": k_slope,
               "ml_level_range_bellhop": level_ranges,
               "rmse_m": rmse, "mean_rmse_after_10min_m": {
                   col.removesuffix("_rmse_m"): _rms(frame[col].to_numpy()[minutes >= LATE_MIN])
                   for col in frame.columns[1:]},
               "after_10min_over_origin_bellhop": over_origin,
               "ml_manoeuvres_declared": tacks, "late_min": LATE_MIN,
               "calibration_after_late_min": calibration, "seconds": round(time.perf_counter() - start, 1)}
    files = [out / "follow_rmse.csv", out / "follow.json", out / "follow_rmse.png"]
    fig = _figure(frame, summary)
    from acoustics.plots.figures import save_figure

    with atomic_paths(files) as (csv_tmp, json_tmp, png_tmp):
        frame.to_csv(csv_tmp, index=False, float_format="%.6g")
        json_tmp.write_text(json.dumps({"tmakit_format": RESULT_FORMAT, **summary}, indent=1) + "\n")
        save_figure(fig, png_tmp, atomic=False)
    summary["files"] = [str(f) for f in files]
    return summary


def blend_trial(*, runs: int, seeds, ratios, out_dir: str | Path, workers: int = 2,
                n_particles: int = FILTER_PARTICLES) -> dict:
    """How the atlas's blend between positions serves the trackers (docs/atlas-tracking.md): on
    BELLHOP's levels along the true paths, for each seed a batch of ``runs`` runs tracked by the
    ML analysis (default tests) and the particle filter with the origin table and with each atlas
    whose positions are weighted with each water-depth ratio of ``ratios`` (None: bilinear alone;
    ``AtlasStore.water_depth_ratio``). Per tracker, table and seed: the RMS over t >= 10 min of
    the RMSE over runs (as ``follow.json``'s ``mean_rmse_after_10min_m``) and the median over
    runs of each run's mean error after 10 min, and the RMS of the RMSE over the whole run
    (the first 10 min, when the ML analysis ranges on the levels alone, included); per tracker and
    atlas, the first of these over the seeds' runs pooled, over the origin table's on the same
    runs, with its interval (`ratio_to_reference`); per atlas and ratio, BELLHOP's K along the path
    less the tables' (`k_error_by_time`). Grids and atlases as
    `run` builds them in ``out_dir``."""
    from acoustics.grid.atlas.weights import WATER_DEPTH_RATIO

    paths = build_tables(Path(out_dir) / "grids", workers)
    sc = load_scenario(SCENARIO)
    origin = open_tables(paths["origin"])
    ic = origin.class_index(sc.target_class)
    truth = BellhopTruth(load_area(AREA), cache_dir=Path(out_dir) / "grids" / "truth-runs", workers=workers)
    label = {r: "bilinear" if r is None else f"water-{r:g}" for r in ratios}
    # each atlas opened once per ratio (the seeds' observer paths are the same: its weights and
    # slabs, kept by the face, serve every seed)
    tables = {"origin": origin}
    for ratio in ratios:
        for spacing in SPACINGS_KM:
            name = f"atlas-{spacing:g}km"
            tab = open_tables(paths[name])
            tab.store.water_depth_ratio = ratio
            tables[f"{name} {label[ratio]}"] = tab
    scores, k_error, pooled = {}, {}, {}
    for seed in seeds:
        draws = class_draws(sc, origin.classes[ic], runs, np.random.default_rng([seed, 2]))
        sim = simulate_batch(sc, origin, np.random.default_rng([seed, 0]), **draws, k_provider=truth)
        late = (sim.t_s - sim.t_s[0]) / 60.0 >= LATE_MIN
        for name, tab in tables.items():
            errs = {"ml": ml_errors(tab, sim, ic, MLParams())[0],
                    "rpf": rpf_track(tab, sim, ic, 0, np.random.default_rng([seed, 1]), n_particles,
                                     config=rpf_config(tab, sim, ic, n_particles, LEVEL_SD_DB),
                                     level_errors="tables", prior_seed=seed).position_error_m(sim)}
            for method, err in errs.items():
                pooled.setdefault(f"{method} {name}", []).append(err[:, late])
                rmse = np.sqrt(np.nanmean(err ** 2, axis=0))
                scores.setdefault(f"{method} {name}", {})[str(seed)] = {
                    "rmse_after_10min_m": round(_rms(rmse[late]), 1),
                    "median_run_mean_after_10min_m": round(float(np.median(np.nanmean(err[:, late], axis=1))), 1),
                    "rmse_whole_run_m": round(_rms(rmse), 1)}
        if seed == seeds[0]:
            k_error = k_error_by_time(sim, sc, ic, truth, tables)
    pooled = {key: np.concatenate(v) for key, v in pooled.items()}
    over_origin = {key: ratio_to_reference(err, pooled[f"{key.split()[0]} origin"], np.random.default_rng([0, 9]))
                   for key, err in pooled.items() if not key.endswith(" origin")}
    return {"scenario": sc.name, "runs_per_seed": runs, "seeds": list(seeds), "n_particles": n_particles,
            "default_ratio": WATER_DEPTH_RATIO, "ratios": [label[r] for r in ratios], "scores": scores,
            "after_10min_over_origin": over_origin, "bellhop_minus_tables_k_db": k_error}


#: Resamples of the runs for the interval of `ratio_to_reference`.
BOOTSTRAP = 2000


def ratio_to_reference(err, reference, rng: np.random.Generator) -> dict:
    """The RMS over time of one tracker's RMSE over runs, over the same runs' with other tables
    (``err``, ``reference``: (E, T) errors of the same runs and cycles), and its 90 % interval
    over the runs resampled alike for both (`BOOTSTRAP` times): ``ratio``, ``p05``, ``p95``."""
    def ratio(rows):
        def late(e):
            return _rms(np.sqrt(np.nanmean(e[rows] ** 2, axis=0)))
        return late(err) / late(reference)

    e = len(err)
    boot = [ratio(rng.integers(0, e, e)) for _ in range(BOOTSTRAP)]
    return {"ratio": round(ratio(np.arange(e)), 4), "p05": round(float(np.percentile(boot, 5)), 4),
            "p95": round(float(np.percentile(boot, 95)), 4)}


def _figure(frame: pd.DataFrame, summary: dict):
    from acoustics.plots.figures import new_figure

    fig = new_figure(figsize=(11, 7.5), layout="constrained")
    axes = fig.subplots(2, 2, sharex=True)
    styles = {"origin": ("tab:red", "-"), "atlas-10km": ("tab:blue", "--"), "atlas-5km": ("tab:green", "-")}
    for row, truth in enumerate(TRUTHS):
        for col, method in enumerate(("ml", "rpf")):
            ax = axes[row, col]
            for name in TABLES:
                color, ls = styles[name]
                ax.plot(frame.t_min, frame[f"{method}_{name}_{truth}_rmse_m"], color=color, ls=ls, label=name)
            ax.set_yscale("log")
            ax.grid(alpha=0.3, which="both")
            source = "BELLHOP along the true paths" if truth == "bellhop" else "the 5 km atlas"
            ax.set_title(f"{method}: levels from {source}", fontsize=9)
            ax.set_ylabel("position RMSE, m")
            ax.legend(fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("time, min")
    fig.suptitle(f"{summary['scenario']}: {summary['runs']} runs, observer "
                 f"{summary['observer_travel_m'] / 1000:.1f} km across the slope, class {summary['class']}",
                 fontsize=10)
    return fig


__all__ = ["blend_trial", "run"]
