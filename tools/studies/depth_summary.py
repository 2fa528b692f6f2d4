"""The depth study's summary (`tools.studies.depth`): position errors and their ratios, the
stated range sds against the truth, the depth intervals' coverage and width against the prior's,
the surface-or-submerged call, per scenario and true depth."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from tools.studies.depth_setup import (
    AREA,
    DEPTH_SPAN_M,
    KNOWN,
    LATE_MIN,
    METHODS,
    TARGET_COVERAGE,
    TARGET_RATIO,
    TRACK_RULE,
    UNKNOWN,
)
from tracker.depth.posterior import PRIOR_LOG_OFFSET_M, SUBMERGED_MIN_M, SURFACE_MAX_M


def _mismatch_summary(parts) -> dict:
    """Per scenario and true depth: the median over runs and bands of the residual's sd along
    the track, and the sd of the bands' offsets from the run's common one, dB."""
    d = pd.concat(parts, ignore_index=True)
    out = {}
    for (sc, z), g in d.groupby(["scenario", "true_depth_m"]):
        out.setdefault(sc, {})[f"{z:g}"] = {"along_track_sd_db": round(float(g["along_track_sd_db"].median()), 2),
                                             "band_offset_sd_db": round(float(np.nanstd(g["band_offset_db"])), 2)}
    return out


def _call_error(d: pd.DataFrame) -> dict:
    """The surface-or-submerged call (surface where the posterior's mass at most 15 m deep
    exceeds its mass at least 40 m deep) on the runs whose truth is one or the other."""
    judged = d[(d["true_depth_m"] <= SURFACE_MAX_M) | (d["true_depth_m"] >= SUBMERGED_MIN_M)]
    called_surface = judged["p_surface"] > judged["p_submerged"]
    wrong = called_surface != (judged["true_depth_m"] <= SURFACE_MAX_M)
    surface = judged["true_depth_m"] <= SURFACE_MAX_M
    return {"runs": int(len(judged)), "error_rate": float(wrong.mean()) if len(judged) else None,
            "error_rate_surface_targets": float(wrong[surface].mean()) if surface.any() else None,
            "error_rate_submerged_targets": float(wrong[~surface].mean()) if (~surface).any() else None}


def _depth_stats(d: pd.DataFrame) -> dict:
    cover = (d["lo_m"] <= d["true_depth_m"]) & (d["true_depth_m"] <= d["hi_m"])
    lo, hi = _prior_interval()
    width = d["hi_m"] - d["lo_m"]
    return {"coverage_90": float(cover.mean()), "median_width_m": float(width.median()),
            "median_width_over_prior": round(float(width.median() / (hi - lo)), 3),
            "median_depth_m": float(d["depth_m"].median()),
            "median_abs_error_m": float((d["depth_m"] - d["true_depth_m"]).abs().median())}


def _summary(frame: pd.DataFrame, tables, ic: int, *, runs, seed, n_particles, truth, grid, provider) -> dict:
    pos = frame[frame["method"] != KNOWN].drop_duplicates(["scenario", "true_depth_m", "run", "method", "variant"])
    med = pos.groupby(["scenario", "true_depth_m", "method", "variant"])["rms_error_m"].median()
    errors = {}
    for (sc, z, method, variant), v in med.items():
        errors.setdefault(sc, {}).setdefault(f"{z:g}", {})[f"{method}_{variant}"] = round(float(v), 1)
    pooled = pos.groupby(["method", "variant"])["rms_error_m"].median()
    unknown = [(m, u) for m in METHODS for u in UNKNOWN[m]]
    ratios = {f"{m}_{u}": float(pooled[(m, u)] / pooled[(m, "true")]) for m, u in unknown}
    nearest = {m: round(float(pooled[(m, "nearest")] / pooled[(m, "true")]), 3)
               for m in METHODS if (m, "nearest") in pooled.index}
    other_rule = {f"{m}_{v}": round(float(pooled[(m, v)] / pooled[(m, "true")]), 3)
                  for m, v in pooled.index if "_by_" in v}
    per_combo_ratio = {}
    for sc, by_z in errors.items():
        for z, v in by_z.items():
            per_combo_ratio.setdefault(sc, {})[z] = {f"{m}_{u}": round(v[f"{m}_{u}"] / v[f"{m}_true"], 3)
                                                     for m, u in unknown}
    # the ratio of the medians over each scenario's runs (all depths)
    by_sc = pos.groupby(["scenario", "method", "variant"])["rms_error_m"].median()
    ratio_by_scenario = {sc: {f"{m}_{u}": round(float(by_sc[(sc, m, u)] / by_sc[(sc, m, "true")]), 3)
                              for m, u in unknown} for sc in errors}
    depth = frame[frame["variant"].isin(["unknown", "bank"])]
    estimators = {}
    for (method, variant, source), d in depth.groupby(["method", "variant", "depth_from"]):
        key = f"{method}_bank" if variant == "bank" else f"{method}_{source}"
        estimators[key] = {"all": _depth_stats(d), "surface_call": _call_error(d),
                           "by_true_depth": {f"{z:g}": _depth_stats(g) for z, g in d.groupby("true_depth_m")},
                           "by_scenario": {sc: _depth_stats(g) for sc, g in d.groupby("scenario")}}
    wcols = [c for c in frame.columns if c.startswith("w_")]
    weights = {}
    for (method, variant, sc, z), g in depth[depth["depth_from"] == "posterior"].groupby(
            ["method", "variant", "scenario", "true_depth_m"]):
        key = f"{method}_bank" if variant == "bank" else method
        weights.setdefault(key, {}).setdefault(sc, {})[f"{z:g}"] = {c[2:]: round(float(g[c].mean()), 3)
                                                                    for c in wcols}
    cls = tables.classes[ic]
    out = {"area": AREA, "scenarios": sorted(frame["scenario"].unique().tolist()), "runs": runs, "seed": seed,
           "n_particles": n_particles, "truth": truth, "class": cls.name, "class_depth_m": float(cls.depth_m),
           "true_depths_m": sorted(float(z) for z in frame["true_depth_m"].unique()),
           "depth_span_m": list(DEPTH_SPAN_M), "grid": str(grid),
           "median_rms_error_m": errors, "median_rms_error_pooled_m": {f"{m}_{v}": round(float(x), 1)
                                                                      for (m, v), x in pooled.items()},
           "ratio_unknown_to_true_pooled": ratios, "ratio_unknown_to_true": per_combo_ratio,
           "ratio_nearest_hypothesis_to_true_pooled": nearest,
           "track_rule": TRACK_RULE, "ratio_other_track_rule_to_true_pooled": other_rule,
           "ratio_unknown_to_true_by_scenario": ratio_by_scenario,
           "target_ratio": TARGET_RATIO, "target_coverage": TARGET_COVERAGE, "depth_estimates": estimators,
           "hypothesis_weights_mean": weights,
           "track_range_scale_ln_rms": _scale_rms(pos),
           "range_calibration_after_late_min": _range_calibration(pos),
           "prior_interval_m": [round(v, 2) for v in _prior_interval()],
           "late_min": LATE_MIN}
    if provider is not None:
        out["truth_runs"] = int(provider.stats.runs)
        out["truth_runs_cached"] = int(provider.stats.cached)
    return out


def _range_calibration(pos: pd.DataFrame) -> dict:
    """Per method and variant, every run pooled (each counts its late cycles alike): the 90 %
    range interval's coverage and the median over runs of the median |error| / sd."""
    g = pos.groupby(["method", "variant"])
    return {f"{m}_{v}": {"coverage_90": round(float(d["range_cover_90"].mean()), 4),
                         "median_abs_z": round(float(d["range_abs_z_median"].median()), 3)} for (m, v), d in g}


def _prior_interval() -> tuple[float, float]:
    """The depth prior's own 90 % interval over `DEPTH_SPAN_M` (uniform in ln(z + 1 m),
    `tracker.depth.posterior`), m: what a posterior that learnt nothing states."""
    z0 = PRIOR_LOG_OFFSET_M
    lo, hi = (math.log(v + z0) for v in DEPTH_SPAN_M)
    return tuple(math.exp(lo + q * (hi - lo)) - z0 for q in (0.05, 0.95))


def _scale_rms(pos: pd.DataFrame) -> dict:
    """Per tracker (method_variant), the RMS over all runs of `_range_scale`: how far in range
    scale the tracks a depth posterior reads are off (`tracker.depth.likelihood`'s range-scale sd)."""
    g = pos.groupby(["method", "variant"])["range_scale_ln"]
    return {f"{m}_{v}": round(float(np.sqrt(np.nanmean(x ** 2))), 3) for (m, v), x in g}


def _text(summary: dict) -> str:
    lines = [f"depth study: {summary['runs']} runs of {', '.join(summary['scenarios'])} in {summary['area']} at "
             f"{', '.join(f'{z:g}' for z in summary['true_depths_m'])} m (class {summary['class']} tables at "
             f"{summary['class_depth_m']:g} m; levels from {summary['truth']}); median RMS position error after "
             f"{summary['late_min']:g} min, all runs, m:"]
    for key, v in summary["median_rms_error_pooled_m"].items():
        lines.append(f"  {key:>12}: {v:8.0f}")
    for m, ratio in summary["ratio_unknown_to_true_pooled"].items():
        lines.append(f"  {m}: position error / given the true depth = {ratio:.2f} (target <= {TARGET_RATIO})")
    for key, est in summary["depth_estimates"].items():
        a, c = est["all"], est["surface_call"]
        lines.append(f"  depth from {key}: 90 % interval covers the truth in {100 * a['coverage_90']:.0f} % of "
                     f"runs (target >= {100 * TARGET_COVERAGE:.0f} %), median width {a['median_width_m']:.0f} m; "
                     f"surface-or-submerged call wrong in {100 * (c['error_rate'] or 0):.1f} % of {c['runs']} runs")
    return "\n".join(lines)
