"""docs/depth.md: the depth study (errors, estimates, the intervals' widths against the prior's,
hypothesis weights, level residuals, the tables against BELLHOP from the target)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import RANGE_CELL_HEAD, caption, load_result, markdown_table, percent, range_cell

PAGE = "docs/depth.md"


_DEPTH_ESTIMATES = (("ml_posterior", "ML analysis: posterior over its hypotheses' tracks"),
                    ("rpf_bank", "bank of particle filters at the ML's hypotheses"),
                    ("known_motion_true_track", "the motion known: posterior along the true track"))
#: The position-error table's columns, those the file holds (the depth-state filter's
#: ``rpf_unknown`` is in files made before it was retired).
_ERROR_KEYS = ("rpf_class", "rpf_true", "rpf_unknown", "rpf_bank", "ml_class", "ml_true", "ml_unknown")


def depth_errors(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    pooled = d["median_rms_error_pooled_m"]
    keys = tuple(k for k in _ERROR_KEYS if k in pooled)
    rows = [("scenario", "true depth, m", *keys), ("---",) * (2 + len(keys))]
    for sc, by_z in d["median_rms_error_m"].items():
        for z, v in by_z.items():
            rows.append((f"`{sc}`", z, *(f"{v[k]:.0f}" for k in keys)))
    rows.append(("all", "all", *(f"**{pooled[k]:.0f}**" for k in keys)))
    ratio = d["ratio_unknown_to_true_pooled"]
    by_sc = d["ratio_unknown_to_true_by_scenario"]
    text = "; ".join(f"{k} {ratio[k]:.2f} (" + ", ".join(f"{sc} {v[k]:.2f}" for sc, v in by_sc.items()) + ")"
                     for k in ratio)
    scale = d.get("track_range_scale_ln_rms")
    scale_text = ("" if scale is None else " How far in range scale each tracker's final estimate carried back is "
                  "off, RMS of ln(range / true range) over the runs: "
                  + ", ".join(f"{k} {scale[k]:.2f}" for k in keys if k in scale) + ".")
    nearest = d.get("ratio_nearest_hypothesis_to_true_pooled")
    nearest_text = ("" if not nearest else " Each method at the depth hypothesis nearest to the true depth (the best "
                    "any weighing of its hypotheses could pick) over the true depth: "
                    + ", ".join(f"{k} {v:.2f}" for k, v in nearest.items()) + ".")
    other = d.get("ratio_other_track_rule_to_true_pooled")
    other_text = ("" if not other else " Each weighed method with the other rule for the track it reports ("
                  + ", ".join(f"{m} by {r}" for m, r in d["track_rule"].items()) + " above): "
                  + ", ".join(f"{k} {v:.2f}" for k, v in other.items()) + ".")
    return (markdown_table(rows)
            + f"\nPosition error with the depth unknown over that given the true depth, medians over "
            f"all runs (by scenario): {text}; target <= {d['target_ratio']:g}.{other_text}{nearest_text}"
            f"{scale_text}\n\n"
            + caption(d, "depth/depth.json"))


def depth_estimates(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    zs = [f"{z:g}" for z in d["true_depths_m"]]
    scs = d["scenarios"]
    rows = [("depth from", "covered, all runs", *(f"covered, {sc}" for sc in scs), *(f"{z} m" for z in zs),
             "median width", "surface-or-submerged call wrong (surface / submerged targets)"),
            ("---",) * (4 + len(scs) + len(zs))]
    for key, label in _DEPTH_ESTIMATES:
        e = d["depth_estimates"].get(key)
        if e is None:
            continue
        c = e["surface_call"]
        rows.append((label, f"**{100 * e['all']['coverage_90']:.0f} %**",
                     *(f"{100 * e['by_scenario'][sc]['coverage_90']:.0f} %" for sc in scs),
                     *(f"{100 * e['by_true_depth'][z]['coverage_90']:.0f} %" for z in zs),
                     f"{e['all']['median_width_m']:.0f} m",
                     f"{100 * c['error_rate']:.1f} % of {c['runs']} ({100 * c['error_rate_surface_targets']:.0f} % / "
                     f"{100 * c['error_rate_submerged_targets']:.0f} %)"))
    return (markdown_table(rows) + f"\nThe 90 % interval of the final depth covers the truth in that share of runs "
            f"(target >= {100 * d['target_coverage']:.0f} %); {d['runs']} runs per scenario and depth, levels from "
            f"{d['truth']}.\n\n" + caption(d, "depth/depth.json"))


def depth_widths(root: Path) -> str:
    """The final 90 % intervals' median width by true depth against the prior's own interval."""
    d = load_result(root, "depth/depth.json")
    zs = [f"{z:g}" for z in d["true_depths_m"]]
    lo, hi = d["prior_interval_m"]
    rows = [("depth from", *(f"{z} m" for z in zs), "all"), ("---",) * (2 + len(zs))]
    for key, label in _DEPTH_ESTIMATES:
        e = d["depth_estimates"].get(key)
        if e is None:
            continue
        cells = [e["by_true_depth"][z] for z in zs] + [e["all"]]
        rows.append((label, *(f"{c['median_width_m']:.0f} m ({c['median_width_over_prior']:.2f})" for c in cells)))
    return (markdown_table(rows) + "\nThe final 90 % interval's width, median over the runs at each true depth (in "
            f"brackets over the prior's own 90 % interval, {lo:.1f}-{hi:.0f} m: {hi - lo:.0f} m wide, what a posterior "
            "that learnt nothing from the levels states).\n\n" + caption(d, "depth/depth.json"))


def depth_mismatch(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    m = d["level_residual_at_true_depth_db"]
    zs = [f"{z:g}" for z in d["true_depths_m"]]
    rows = [("scenario", *(f"{z} m" for z in zs)), ("---",) * (1 + len(zs))]
    for sc, by_z in m.items():
        rows.append((f"`{sc}`", *(f"{by_z[z]['along_track_sd_db']:.1f} ({by_z[z]['band_offset_sd_db']:.1f})"
                                  for z in zs)))
    return (markdown_table(rows)
            + "\nThe levels less P0 + K + G, K the tables' at the true depth along the true track, "
            "each run's mean taken off: sd along the track, median over runs and bands (in brackets the sd of "
            "the bands' offsets from the run's common one), dB; eq. 11's error included.\n\n"
            + caption(d, "depth/depth.json"))


def depth_check(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    c = d["tables_vs_bellhop_from_target_db"]
    zs = list(c["geometries"][0]["by_depth_m"])
    rows = [("observer (x, y), km", "bearing", *(f"{z} m" for z in zs), "median"), ("---",) * (3 + len(zs))]
    for g in c["geometries"]:
        by = g["by_depth_m"]
        rows.append((f"({g['observer_x_m'] / 1e3:g}, {g['observer_y_m'] / 1e3:g})", f"{g['bearing_deg']:g} deg",
                     *(f"{by[z]['common_sd_db']:.1f} / {by[z]['band_own_sd_db']:.1f}" for z in zs),
                     f"**{g['median_common_sd_db']:.1f} / {g['median_band_own_sd_db']:.1f}**"))
    f = c["fit"]
    return (markdown_table(rows)
            + "\nK from BELLHOP run from the target less the tables' K read from the observer, targets "
            f"at {c['ranges_km'][0]:g}-{c['ranges_km'][1]:g} km every km on one bearing: the sd along range of the "
            "part common to the bands / of each band's own, dB. The likelihood's fine errors from it: "
            f"{f['fine_sd_db']:.1f} / {f['fine_band_sd_db']:.1f} dB where the tables were computed, growing by "
            f"{f['fine_growth_db_per_km']:.1f} / {f['fine_band_growth_db_per_km']:.2f} dB per km of the observer's "
            "distance from there (sd^2 = sd_0^2 + (g d)^2, least squares); the bands' offsets (their sd over the "
            f"bands, median {f['band_sd_db']:.2f} dB at the origin) by {f['band_growth_db_per_km']:.2f} dB per km, "
            "added to the class's 1 dB; the offset common to the bands (each depth's mean less the origin's on the "
            f"same bearing, RMS over the depths) by {f['offset_growth_db_per_km']:.2f} dB per km, added to the "
            "class's P0 and dK." + _check_correlation(c) + "\n\n" + caption(d, "depth/depth.json"))


def _check_correlation(c: dict) -> str:
    """The common part's correlation from one range to the next, at the origin and away from it
    (files made before the check recorded it: nothing)."""
    at = {True: [], False: []}
    for g in c["geometries"]:
        if "median_common_lag1_correlation" in g:
            at[g["distance_km"] == 0.0].append(g["median_common_lag1_correlation"])
    if not (at[True] and at[False]):
        return ""
    span = c["ranges_km"]
    return (f" The part common to the bands is correlated from one km to the next by {min(at[True]):.1f} to "
            f"{max(at[True]):.1f} at the origin and {min(at[False]):.1f} to {max(at[False]):.1f} away from it "
            f"(medians over the depths; targets {span[0]:g}-{span[1]:g} km): away from where they were "
            "computed the tables are off slowly along range.")


def depth_weights(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    w = d["hypothesis_weights_mean"]["ml"]
    hyps = list(next(iter(next(iter(w.values())).values())))
    rows = [("scenario", "true depth, m", *(f"{float(h):.0f} m" for h in hyps)), ("---",) * (2 + len(hyps))]
    for sc, by_z in w.items():
        for z, v in by_z.items():
            rows.append((f"`{sc}`", z, *(f"{v[h]:.2f}" for h in hyps)))
    return (markdown_table(rows) + "\nThe ML analysis's depth hypotheses' final weights, mean over runs.\n\n"
            + caption(d, "depth/depth.json"))


_DIAGNOSIS_MODELS = (("levels", "the study's levels"), ("levels_k_smoothed", "K smoothed"),
                     ("bearings_only", "bearings only"),
                     ("bearings_only_sd_floor", "bearings only, their sd at least {floor:g} deg"))


def depth_diagnosis(root: Path) -> str:
    d = load_result(root, "depth-diagnosis.json")
    f = d["figures"]
    floor = d["bearing_sd_floor_deg"]
    rows = [("scenario", "true depth, m", *(f"{label.format(floor=floor)}: {RANGE_CELL_HEAD}"
                                            for _, label in _DIAGNOSIS_MODELS)),
            ("---",) * (2 + len(_DIAGNOSIS_MODELS))]
    for sc, by_z in d["by_case"].items():
        for z, v in by_z.items():
            rows.append((f"`{sc}`", z, *(range_cell(v[m]["coverage_90"], v[m]["abs_z_median"],
                                                    v[m]["rms_error_median_m"]) for m, _ in _DIAGNOSIS_MODELS)))
    rows.append(("all", "all", *("**" + range_cell(*(f[f"{m}_{k}"]["value"] for k in (
        "coverage_90_pooled", "abs_z_median_pooled", "rms_error_median_pooled_m"))).replace(" %", " %**", 1)
        for m, _ in _DIAGNOSIS_MODELS)))
    pc = d["posterior_case"]
    runs = pc["runs"]
    text = ("\nThe filter given the true depth, the study's runs; RMSE: the median over runs of the RMS position "
            "error after 5 min. On `{}` at {:g} m, runs {}: the filter's own model puts the true path "
            "{} log units below the best constant-velocity path it finds (first range {} km against the true "
            "{:.2f} km); the levels' spread across the bands along the true path, RMS {} dB.\n\n").format(
        pc["scenario"], pc["true_depth_m"], ", ".join(str(r["run"]) for r in runs),
        ", ".join(f"{r['truth_below_best']:.0f}" for r in runs),
        ", ".join(f"{r['best_first_range_m'] / 1000:.1f}" for r in runs), runs[0]["true_first_range_m"] / 1000,
        ", ".join(f"{r['band_spread_at_truth_db']:.2f}" for r in runs))
    return markdown_table(rows) + text + caption(d, "depth-diagnosis.json")


def depth_model_posterior(root: Path) -> str:
    d = load_result(root, "depth-diagnosis.json")
    sigmas = [f"{a:g}" for a in d["model_sigma_a_mps2"]]
    rows = [("scenario", "true depth, m", *(f"sigma_a {a} m/s^2: 90 % holds / median \\|error\\| / sd / "
                                            "log evidence against the paper's" for a in sigmas)),
            ("---",) * (2 + len(sigmas))]
    for sc, by_z in d["model_posterior"].items():
        for z, v in by_z.items():
            rows.append((f"`{sc}`", z, *(f"{100 * v[a]['coverage_90']:.0f} % / {v[a]['abs_z_median']:.2f} / "
                                         f"{v[a]['log_evidence_vs_paper_median']:+.1f}" for a in sigmas)))
    f = d["figures"]
    rows.append(("all", "all", *(f"**{100 * f[f'model_posterior_coverage_90_mean_sigma_a_{a}']['value']:.0f} %**"
                                 for a in sigmas)))
    text = ("\nThe filter's model's posterior of the range on the bearings alone, without sampling "
            "(`tracker.rpf.gaussiansum`), the first {} runs of each case, the filter's prior and sigma_theta; "
            "the log evidence: how much more probable the run's bearings are under that acceleration sd "
            "than under the paper's, median over runs.\n\n").format(d["model_runs"])
    return markdown_table(rows) + text + caption(d, "depth-diagnosis.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"depth-errors": depth_errors, "depth-estimates": depth_estimates, "depth-widths": depth_widths,
          "depth-weights": depth_weights, "depth-mismatch": depth_mismatch, "depth-check": depth_check,
          "depth-diagnosis": depth_diagnosis, "depth-model-posterior": depth_model_posterior}


def model_span(scenario: str | None, sigma_a: str, key: str, scale: float = 1.0):
    """The least and greatest of a model-posterior figure over the true depths of ``scenario``
    (every scenario if None) at acceleration sd ``sigma_a``."""
    def span(d: dict) -> tuple[float, float]:
        cases = d["model_posterior"]
        v = [scale * by_z[z][sigma_a][key] for sc, by_z in cases.items() if scenario in (None, sc) for z in by_z]
        return min(v), max(v)
    return span


def filter_span(scenario: str, model: str, key: str, scale: float = 1.0):
    """The least and greatest of a filter's figure (`by_case`) over the true depths of ``scenario``."""
    def span(d: dict) -> tuple[float, float]:
        v = [scale * m[model][key] for m in d["by_case"][scenario].values()]
        return min(v), max(v)
    return span


#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("depth-diagnosis.json", (model_span("shelf-slope-nps", "0.0015", "coverage_90", 100.0),),
     "the truth in {0[0]:.0f}-{0[1]:.0f} % of cycles and"),
    ("depth-diagnosis.json", (filter_span("shelf-slope-nps", "bearings_only", "coverage_90", 100.0),),
     "the bearings-only filter in {0[0]:.0f}-{0[1]:.0f} % (the table before)"),
    ("depth-diagnosis.json", (model_span("shelf-slope-nps", "0.0003", "abs_z_median"),),
     "sd of {0[0]:.2f}-{0[1]:.2f} at 3e-4"),
    ("depth-diagnosis.json", (model_span(None, "0.0003", "log_evidence_vs_paper_median"),),
     "at 3e-4, {0[0]:+.1f} to {0[1]:+.1f})"),
    ("depth/depth.json", ("n_particles",), "the class's P0, {:d} particles"),
    ("depth/depth.json", ("prior_interval_m", 0), "its own 90 % interval over 2-300 m is {:.1f}-"),
    ("depth/depth.json", ("prior_interval_m", 1), "-{:.0f} m. What is left"),
    ("kerror-check.json", ("classes", "TV", "all", "residual_sd_db_at_origin"), "residual along the path ({:.2f} dB"),
    ("kerror-check.json", ("classes", "TV", "all", "residual_growth_db_per_km"), "the residual by {:.2f} dB/km"),
    ("kerror-check.json", ("classes", "TV", "all", "offset_growth_db_per_km"), "the offset by {:.2f} dB/km"),
    ("depth.json", ("figures", "depth_likelihood_cpu_s_no_range_scale", "value"), "takes {:.3f} s of CPU without"),
    ("depth.json", ("figures", "depth_likelihood_cpu_s_range_scale", "value"), "and {:.3f} s with it"),
    ("depth.json", ("figures", "depth_likelihood_range_scale_cost_ratio", "value"), "a ratio of {:.1f}"),
    ("depth.json", ("figures", "track_depth_posterior_cpu_s_whole_water_column", "value"), "it costs {:.1f} s of CPU"),
    ("depth.json", ("figures", "track_depth_posterior_depths", "value"), "({:d} depths: NPS"),
    ("depth.json", ("figures", "rpf_depth_state_throughput_ratio", "value"), "ran at {:.2f} of the fixed-depth"),
    *(("depth/depth.json", ("depth_estimates", key, "all", "coverage_90", percent), fmt) for key, fmt in (
        ("ml_posterior", "covers the truth in {:.0f} %"),
        ("rpf_bank", "the bank's in {:.0f} %"), ("known_motion_true_track", "(the motion known) in {:.0f} %"))),
    ("depth/depth.json", ("depth_estimates", "ml_posterior", "by_true_depth", "6", "coverage_90", percent),
     "in {:.0f} % (ML"),
    ("depth/depth.json", ("depth_estimates", "rpf_bank", "by_true_depth", "6", "coverage_90", percent),
     "{:.0f} % (bank)"),
    ("depth/depth.json", ("depth_estimates", "rpf_bank", "surface_call", "error_rate", percent),
     "{:.1f} % for the bank"),
    ("depth/depth.json", ("depth_estimates", "ml_posterior", "all", "median_width_m"),
     "the ML analysis's median {:.0f} m over"),
    ("depth/depth.json", ("ratio_unknown_to_true_pooled", "rpf_bank"), "at {:.2f}x the filter given the true depth"),
    ("depth/depth.json", ("ratio_unknown_to_true_pooled", "ml_unknown"), "the ML analysis at {:.2f}x"),
    ("depth/depth.json", ("ratio_nearest_hypothesis_to_true_pooled", "rpf"), "the bank would be at {:.2f}x"),
    ("depth/depth.json", ("ratio_other_track_rule_to_true_pooled", "rpf_bank_by_weight"), "the bank is at {:.2f}x"),
    ("depth/depth.json", ("median_rms_error_pooled_m", "rpf_bank"), "median error, {:.0f} m"),
    ("depth/depth.json", ("median_rms_error_pooled_m", "rpf_class"), "class's depth, {:.0f} m"),
    ("depth/depth.json", ("median_rms_error_pooled_m", "rpf_true"), "the true depth, {:.0f} m"),
    ("depth/depth.json", ("range_calibration_after_late_min", "rpf_bank", "coverage_90", percent),
     "the bank's {:.0f} %"),
    *(("depth.json", ("figures", f"reciprocity_error_median_abs_db_at_{z}m", "value"), fmt)
      for z, fmt in (("5", "{:.2f} dB at 5 m"), ("10", "{:.2f} at 10 m"), ("20", "{:.2f} at 20 m"),
                     ("50", "{:.2f} at 50 m"), ("150", "{:.2f} at 150 m"), ("200", "{:.2f} at 200 m"))),
)
