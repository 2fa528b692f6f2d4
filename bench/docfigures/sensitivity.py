"""docs/sensitivity.md: the sensitivity studies (sets, range errors, speed), reciprocity, the K error
maps and the tracking with them."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, figure, load_result, made_at, markdown_table, percent, rmse_rows

PAGE = "docs/sensitivity.md"


#: The sensitivity command's studies of ocean-deep that docs/sensitivity.md quotes: set -> its label.
SENSITIVITY_SETS = {"profile": "profile measured well", "bottom": "bottom only", "default": "the default set (both)"}


def _range_span(values: list[float], digits: int, unit: str) -> str:
    lo, hi = min(values), max(values)
    return f"{lo:.{digits}f} {unit}".strip() if round(lo, digits) == round(hi, digits) else \
        f"{lo:.{digits}f}-{hi:.{digits}f} {unit}".strip()


def sensitivity_sets(root: Path) -> str:
    rows = [("perturbation set", "NPS (200 m)", "SW (6 m)", "TV (8 m)", "constant share", "median sd of dK(r)"),
            ("---",) * 6,
            ("paper (constant offset, profile measured well)", "2.0 dB", "1.5 dB", "1.5 dB", "100 % (assumed)", "–")]
    sources = []
    for name, label in SENSITIVITY_SETS.items():
        file = f"sensitivity/ocean-deep-{name}.json"
        d = load_result(root, file)
        specs = ", ".join(f"`{p}`" for p in d["perturbations"]) if name != "default" else ""
        sd = d["k_error_sd_db"]
        share = [100.0 * v["constant_fraction"] for v in d["k"].values()]
        spread = [v["sd_db_median"] for v in d["k"].values()]
        share_text = "< 1 %" if max(share) < 1.0 else _range_span(share, 0, "%")
        rows.append((f"{label}: {specs}" if specs else label, *(f"{sd[c]:.2f} dB" for c in ("NPS", "SW", "TV")),
                     share_text, _range_span(spread, 2 if max(spread) < 1 else 1, "dB")))
        sources.append(made_at(d, file))
    return markdown_table(rows) + "\n*From " + "; ".join(sources) + " (each by the command above, through "\
        "`python -m bench.record`).*\n"


def sensitivity_ranges(root: Path) -> str:
    rows = [("set", "class", "5 km", "10 km", "20 km", "50 km", "100 km"), ("---",) * 7]
    for name, label in SENSITIVITY_SETS.items():
        d = load_result(root, f"sensitivity/ocean-deep-{name}.json")
        for cls_name in ("NPS", "SW"):
            err = d["range_error"][cls_name]
            km = [err[r]["rms_m"] / 1000.0 for r in ("5", "10", "20", "50", "100")]
            rows.append((label, cls_name, *(f"{x:.2f} km" if x < 10.0 else f"{x:.1f} km" for x in km)))
    return markdown_table(rows) + "\n" + "*From the same files.*\n"


def sensitivity_speed(root: Path) -> str:
    d = load_result(root, "sensitivity.json")
    w1, w2 = figure(d, "study_1_worker_wall"), figure(d, "study_2_workers_wall")
    rows = [("figure", "measured", "target"), ("---",) * 3,
            ("2 workers vs 1 (median of the side-by-side pairs)",
             f"{figure(d, 'speedup_2_vs_1_workers'):.2f}x ({w1:.1f} s -> {w2:.1f} s)", ">= 1.7x"),
            ("overhead, 1 worker: wall / sum of BELLHOP - 1",
             f"{figure(d, 'overhead_1_worker_wall_over_bellhop_sum'):.1f} %", "<= 10 %"),
            ("overhead, 2 workers: 2 x wall / sum of BELLHOP - 1",
             f"{figure(d, 'overhead_2_workers_wall_x2_over_bellhop_sum'):.1f} %", "<= 10 %"),
            ("results with 1 and 2 workers",
             "identical (bitwise)" if figure(d, "results_identical_1_vs_2_workers") else "NOT identical", "identical")]
    return markdown_table(rows) + "\n" + caption(d, "sensitivity.json")


def reciprocity(root: Path) -> str:
    sens, acc = load_result(root, "sensitivity.json"), load_result(root, "accuracy.json")
    rows = [("class (depth)", "how its K is computed", "against its own runs: median", "p95"), ("---",) * 4]
    for key in (k for k in (sens.get("figures") or sens["results"]) if k.startswith("reciprocity_vs_direct_")
                and k.endswith("_median")):
        cls_name, depth = key.removeprefix("reciprocity_vs_direct_").removesuffix("_median").split("_")
        rows.append((f"{cls_name} ({depth.removesuffix('m')} m)", "by reciprocity (source at the observer)",
                     f"{figure(sens, key):.2f} dB", f"{figure(sens, key.replace('_median', '_p95')):.2f} dB"))
    for key in (k for k in (acc.get("figures") or acc["results"])
                if k.startswith("k_error_observer_table_semicoherent_") and k.endswith("_median")):
        cls_name, depth = key.removeprefix("k_error_observer_table_semicoherent_").removesuffix("_median").split("_")
        inc = key.replace("_semicoherent_", "_incoherent_")
        rows.append((f"{cls_name} ({depth.removesuffix('m')} m)",
                     "directly here; from the observer in a bearing-dependent grid or an atlas (incoherent beams "
                     "in brackets)", f"{figure(acc, key):.2f} dB ({figure(acc, inc):.2f} dB)",
                     f"{figure(acc, key.replace('_median', '_p95')):.2f} dB "
                     f"({figure(acc, inc.replace('_median', '_p95')):.2f} dB)"))
    return markdown_table(rows) + "\n" + caption(sens, "sensitivity.json") + caption(acc, "accuracy.json")


def kerror_sd(root: Path) -> str:
    d = load_result(root, "kerror/sensitivity.json")
    depth = {"NPS": 200, "SW": 6, "TV": 8}
    rows = [("class", "measured `k_error_sd_db` (area file)", "median sd of K by bearing, dB (0 / 90 / 180 / 300 deg)",
             "drives the constant offset"), ("---",) * 4]
    for c, sd in d["k_error_sd_db"].items():
        by = d["k_sd_db_median_by_bearing"][c]
        drivers = sorted(d["offset_drivers"][c].items(), key=lambda kv: -abs(kv[1]))[:2]
        rows.append((f"{c} ({depth.get(c, '?')} m)", f"{sd:.2f} ({d['k_error_sd_db_area_file'][c]:g})",
                     " / ".join(f"{by[b]:.2f}" for b in ("0", "90", "180", "300")),
                     ", ".join(f"{k.replace('_', ' ')} ({v:+.2f})" for k, v in drivers)))
    return markdown_table(rows) + "\n" + caption(d, "kerror/sensitivity.json")


def kerror_rmse(root: Path) -> str:
    d = load_result(root, "kerror/kerror.json")
    names = (("rpf_model", "particle filter, the study's model"), ("rpf_scalar", "particle filter, one number"),
             ("ml_model", "ML analysis, the study's model"), ("ml_scalar", "ML analysis, one number"),
             ("bot", "bearings-only filter (the same prior)"))
    rows = rmse_rows(d, names, ("position RMSE, km", "mean after 5 min"), "{:.2f}", 1000.0)
    return markdown_table(rows) + "\n" + caption(d, "kerror/kerror.json")


def kerror_bins(root: Path) -> str:
    """Each tracker's RMSE by 5-minute bin beside the bearings-only filter's, km."""
    d = load_result(root, "kerror/kerror.json")
    by = d["rmse_by_time_bin_m"]
    bins = list(by["bot"])
    rows = [("position RMSE, km, by minutes", *bins), ("---",) * (1 + len(bins))]
    worse = d["worse_than_bearings_only_bins"]
    for key in ("rpf_model", "rpf_scalar", "ml_model", "ml_scalar", "bot"):
        rows.append((key.replace("_", ", "), *(f"**{by[key][b] / 1000:.2f}**" if b in worse.get(key, ())
                                               else f"{by[key][b] / 1000:.2f}" for b in bins)))
    return (markdown_table(rows) + "\n*In bold: a bin where the tracker is further off than the bearings-only "
            "filter.*\n\n" + caption(d, "kerror/kerror.json"))


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"sensitivity-sets": sensitivity_sets, "sensitivity-ranges": sensitivity_ranges,
          "sensitivity-speed": sensitivity_speed, "reciprocity": reciprocity, "kerror-sd": kerror_sd,
          "kerror-rmse": kerror_rmse, "kerror-bins": kerror_bins}


def _ships_span(d: dict) -> tuple[float, float]:
    """The ships' (SW, TV) constant-offset sd, dB: their least and greatest."""
    v = [d["figures"][f"k_error_sd_db_{c}"]["value"] for c in ("SW", "TV")]
    return min(v), max(v)


def _members_ships_span(d: dict) -> tuple[float, float]:
    """The ships' (SW, TV) constant-offset sd the kerror study's members measured, dB."""
    v = [d["k_error_sd_db"][c] for c in ("SW", "TV")]
    return min(v), max(v)


#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("kerror/sensitivity.json", (_members_ships_span,), "give the ships {0[0]:.1f}-{0[1]:.1f} dB"),
    *(("sensitivity-shelf.json", keys, fmt) for keys, fmt in (
        (("provenance", "commit"), "commit\n{},"),
        (("figures", "repeats", "value"), "{:d} interleaved repeats"),
        (("figures", "study_1_worker_wall", "value"), "take {:.0f} s on 1 worker"),
        (("figures", "overhead_1_worker_wall_over_bellhop_sum", "value", percent), "{:.1f} % over their BELLHOP time"),
        (("figures", "study_2_workers_wall", "value"), "{:.0f} s, "),
        (("figures", "overhead_2_workers_wall_over_half_bellhop_sum", "value", percent),
         "{:.1f} % over half their BELLHOP time"),
        (("figures", "speedup_2_vs_1_workers", "value"), "is {:.2f}x (target 1.8x"),
        (("figures", "study_1_worker_bellhop_sum", "value"), "BELLHOP time was {:.0f} s"),
        (("figures", "study_2_workers_bellhop_sum", "value"), "and {:.0f} s with two at once"),
        ((_ships_span,), "in that run was {0[0]:.1f}-{0[1]:.1f} dB"),
        (("figures", "k_error_sd_db_NPS", "value"), "the submarine's {:.1f} dB"),
    )),
)
