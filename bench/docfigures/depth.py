"""docs/depth.md: the depth study (errors, estimates, hypothesis weights, level residuals, the tables
against BELLHOP from the target)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, load_result, markdown_table

PAGE = "docs/depth.md"


_DEPTH_ESTIMATES = (("ml_posterior", "ML analysis: posterior over its hypotheses' tracks"),
                    ("rpf_bank", "bank of particle filters at the ML's hypotheses"),
                    ("rpf_particles", "particle filter, depth a state: the particles (mean +- 1.645 sd)"),
                    ("rpf_track", "particle filter, depth a state: posterior along its track"),
                    ("known_motion_true_track", "the motion known: posterior along the true track"))


def depth_errors(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    keys = ("rpf_class", "rpf_true", "rpf_unknown", "rpf_bank", "ml_class", "ml_true", "ml_unknown")
    rows = [("scenario", "true depth, m", *keys), ("---",) * (2 + len(keys))]
    for sc, by_z in d["median_rms_error_m"].items():
        for z, v in by_z.items():
            rows.append((f"`{sc}`", z, *(f"{v[k]:.0f}" for k in keys)))
    pooled = d["median_rms_error_pooled_m"]
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


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"depth-errors": depth_errors, "depth-estimates": depth_estimates, "depth-weights": depth_weights,
          "depth-mismatch": depth_mismatch, "depth-check": depth_check}

#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("depth.json", ("figures", "rpf_depth_state_throughput_ratio", "value"), "a ratio\nof **{:.2f}**"),
    ("depth.json", ("figures", "depth_likelihood_range_scale_cost_ratio", "value"), "a ratio of {:.1f}"),
    ("depth.json", ("figures", "track_depth_posterior_cpu_s_whole_water_column", "value"), "it costs {:.1f} s of CPU"),
    ("depth/depth.json", ("depth_estimates", "ml_posterior", "all", "median_width_m"),
     "the ML analysis's median {:.0f} m over"),
)
