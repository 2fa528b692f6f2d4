"""docs/uncertainty.md (and the study pages that show the same blocks): how each study's trackers'
stated sds hold against the truth after its first 10 minutes."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import (
    RANGE_CELL_HEAD,
    calibration_head,
    calibration_row,
    calibration_rows,
    caption,
    load_result,
    markdown_table,
    range_cell,
)
from bench.docfigures.depth import filter_span, model_span

PAGE = "docs/uncertainty.md"

#: Figures the page's prose quotes (the rest are its blocks): (result file, keys, how it prints).
QUOTES = (
    ("ab-ml36.json", ("workloads", "ml_cycle_3_classes_240_bearings_ms", "after_over_before"),
     "takes {:.2f} times the time it took"),
    ("ab-ml36.json", ("workloads", "rpf_one_filter_bearings_msteps_per_s", "after_over_before"),
     "throughput on bearings is {:.2f} times"),
    ("level-errors.json", ("figures", "rpf_level_errors_cost_ratio", "value"), "{:.2f}x\nthe white likelihood's time"),
    ("depth-diagnosis.json", (model_span("shelf-slope-nps", "0.0015", "coverage_90", 100.0),),
     "in {0[0]:.0f}-{0[1]:.0f} % of the slope run's cycles"),
    ("depth-diagnosis.json", (filter_span("shelf-slope-nps", "bearings_only", "coverage_90", 100.0),),
     "the bearings-only filter holds {0[0]:.0f}-{0[1]:.0f} %"),
    ("kerror-check.json", ("classes", "TV", "all", "jump", "residual", "rms_misfit_db2"),
     "residual's RMS misfit {:.1f} against"),
    ("kerror-check.json", ("classes", "TV", "same_regime", "jump", "residual", "jump_db"),
     "a jump of {:.1f} dB over"),
    ("kerror-check.json", ("classes", "TV", "same_regime", "jump", "residual", "jump_length_m"),
     "dB over\n{:.0f} m fits"),
)

SHELF = (("ml_bearing", "ML analysis, bearing-dependent grid"),
         ("rpf_bearing", "particle filter, bearing-dependent grid"),
         ("bot_bearing", "bearings-only filter"),
         ("ml_isotropic", "ML analysis, origin's column (the shortcut)"),
         ("rpf_isotropic", "particle filter, origin's column (the shortcut)"))
KERROR = (("ml_model", "ML analysis, the study's model"), ("ml_scalar", "ML analysis, one number"),
          ("rpf_model", "particle filter, the study's model"), ("rpf_scalar", "particle filter, one number"),
          ("bot", "bearings-only filter"))
FOLLOW = tuple((f"{m}_{t}_bellhop", f"{label}, {where}") for m, label in
               (("ml", "ML analysis"), ("rpf", "particle filter"), ("bot", "bearings-only filter"))
               for t, where in (("origin", "origin table"), ("atlas-10km", "10 km atlas"), ("atlas-5km", "5 km atlas")))
IDM = {"bot": "bearings only", "spl": "bearings + SPL", "spl_vp": "bearings + SPL, variance-preserving",
       "spl_sl": "bearings + SPL, source-level state"}


def _study(root: Path, file: str, names, head: str = "tracker") -> str:
    """One study's calibration table from its result file."""
    d = load_result(root, file)
    return markdown_table(calibration_rows(d["calibration_after_late_min"], names, head)) + "\n" + caption(d, file)


def calibration_shelf(root: Path) -> str:
    return _study(root, "shelf/shelf.json", SHELF)


def calibration_kerror(root: Path) -> str:
    return _study(root, "kerror/kerror.json", KERROR)


def calibration_follow(root: Path) -> str:
    return _study(root, "atlas-tracking/follow.json", FOLLOW, "tracker, tables (BELLHOP's levels)")


def _several(root: Path, head: str, files: dict, label) -> str:
    """One calibration table over several result files (name -> file): a row per file and entry of
    its ``calibration_after_late_min``, labelled ``label(name, key)``; the files' captions below."""
    rows, captions = calibration_head(head), []
    for name, file in files.items():
        d = load_result(root, file)
        rows += [calibration_row(label(name, key), c) for key, c in d["calibration_after_late_min"].items()]
        captions.append(caption(d, file))
    return markdown_table(rows) + "\n" + "".join(captions)


def calibration_gm(root: Path) -> str:
    return _several(root, "scenario, cycles after 10 min",
                    {f: f"{f}/summary.json" for f in ("gm-tv-30km", "gm-tv-110km", "gm-nps")},
                    lambda name, part: f"{name}, {part.replace('_', ' ')}")


def calibration_idm(root: Path) -> str:
    return _several(root, "scenario, filter", {s: f"idm/{s}.json" for s in ("idm-static", "idm-maneuvering")},
                    lambda name, key: f"{name}, {IDM.get(key, key)}")


def calibration_idm_phases(root: Path) -> str:
    """The manoeuvring observer's cycles after 10 min split at its turn (13-17 min)."""
    d = load_result(root, "idm/idm-maneuvering.json")
    rows = calibration_head("filter, cycles")
    for phase, label in (("before_turn", "before the turn (10-12 min)"), ("after_turn", "after the turn (17-30 min)")):
        rows += [calibration_row(f"{IDM.get(key, key)}, {label}", c)
                 for key, c in d["calibration_by_phase"][phase].items()]
    return markdown_table(rows) + "\n" + caption(d, "idm/idm-maneuvering.json")


def calibration_depth(root: Path) -> str:
    d = load_result(root, "depth/depth.json")
    rows = [("tracker, depth", "range: 90 % interval holds the truth", "median \\|error\\| / sd"), ("---",) * 3]
    rows += [(key.replace("_", ", "), f"{100 * c['coverage_90']:.0f} %", f"{c['median_abs_z']:.2f}")
             for key, c in d["range_calibration_after_late_min"].items()]
    return markdown_table(rows) + "\n" + caption(d, "depth/depth.json")


def kerror_check(root: Path) -> str:
    d = load_result(root, "kerror-check.json")
    rows = [("fit, surface ship (TV, 8 m)", "residual at the origin", "its growth", "the offset's growth",
             "the residual's correlation length", "as a jump and a slope: the residual's, the offset's",
             "each band's own: at the origin, its growth"),
            ("---",) * 7]

    def jump(j: dict) -> str:
        if j["jump_db"] < 0.05:
            return f"no jump, {j['growth_db_per_km']:.2f} dB/km"
        return f"{j['jump_db']:.1f} dB over {j['jump_length_m']:.0f} m, then {j['growth_db_per_km']:.2f} dB/km"

    for part, label in (("all", "every line (the model's)"),
                        ("same_regime", "without an observer moved onto the shelf")):
        f = d["classes"]["TV"][part]
        rows.append((label, f"{f['residual_sd_db_at_origin']:.2f} dB", f"{f['residual_growth_db_per_km']:.2f} dB/km",
                     f"{f['offset_growth_db_per_km']:.2f} dB/km", f"{f['residual_length_m']:.0f} m",
                     f"{jump(f['jump']['residual'])}; {jump(f['jump']['offset'])}",
                     f"{f['band_own_sd_db_at_origin']:.2f} dB (correlation between bands "
                     f"{f['residual_band_correlation_at_origin']:.2f}), {f['band_own_growth_db_per_km']:.2f} dB/km"))
    return markdown_table(rows) + "\n" + caption(d, "kerror-check.json")


def command_calibration(root: Path) -> str:
    d = load_result(root, "command-calibration.json")
    methods = d["methods"]
    rows = [("runs (BELLHOP's levels)", "settings chosen on them", "true first range, median",
             *(f"`{m}`: {RANGE_CELL_HEAD}" for m in methods)), ("---",) * (3 + len(methods))]
    for name, v in d["sets"].items():
        rows.append((f"`{name}`, {v[methods[0]]['runs']} runs", "yes" if v["tuned"] else "no (held out)",
                     f"{v['true_first_range_m'] / 1000:.1f} km",
                     *(range_cell(v[m]["coverage_90"], v[m]["abs_z_median"], v[m]["rms_error_median_m"])
                       for m in methods)))
    p = d["settings"]
    return (markdown_table(rows) + f"\nThe command's settings: range prior log-uniform from "
            f"{p['near_range_m'] / 1000:g} km to the grid's last range, {p['particles']:,} particles sharing out "
            f"three acceleration sds, {p['bandwidth_scale']:g} of the paper's bandwidth, speed the class's mean "
            "and sd; RMSE: the median over runs of the RMS position error after 5 min.\n\n"
            + caption(d, "command-calibration.json"))


TABLES = {"kerror-check": kerror_check, "calibration-shelf": calibration_shelf,
          "calibration-kerror": calibration_kerror, "calibration-follow": calibration_follow,
          "calibration-gm": calibration_gm, "calibration-idm": calibration_idm,
          "calibration-idm-phases": calibration_idm_phases,
          "calibration-depth": calibration_depth, "command-calibration": command_calibration}
