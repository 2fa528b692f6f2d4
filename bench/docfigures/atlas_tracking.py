"""docs/atlas-tracking.md: the follow study, the atlas blend and the trackers' speed on an atlas."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, load_result, markdown_table, percent

PAGE = "docs/atlas-tracking.md"


FOLLOW_TABLES = (("origin", "origin"), ("atlas-10km", "atlas, 10 km"), ("atlas-5km", "atlas, 5 km"))


def follow_rmse(root: Path) -> str:
    d = load_result(root, "atlas-tracking/follow.json")
    m = d["mean_rmse_after_10min_m"]
    rows = [("tables", "ML, BELLHOP levels", "PF, BELLHOP levels", "ML, the atlas's own levels",
             "PF, the atlas's own levels", "ML with the paper's tests, BELLHOP levels"), ("---",) * 6]
    for key, label in FOLLOW_TABLES:
        rows.append((label, *(f"{m[f'{t}_{key}_{lv}']:.0f}" for t, lv in
                              (("ml", "bellhop"), ("rpf", "bellhop"), ("ml", "tables"), ("rpf", "tables"),
                               ("ml-paper", "bellhop")))))
    lv = d["level_bellhop_minus_atlas5km_db"]
    return (markdown_table(rows) + "\nAlong the path, BELLHOP's FB1 level less the 5 km atlas's: "
            f"median {lv['median']:+.1f} dB, "
            f"sd {lv['sd']:.1f} dB, 95th percentile of the absolute difference {lv['p95_abs']:.1f} dB.\n\n"
            + caption(d, "atlas-tracking/follow.json"))


def _follow_bins_table(by_table: dict, cell) -> str:
    """A follow-study table: a row per table of `FOLLOW_TABLES`, a column per time bin of
    ``by_table`` (table -> bin -> value), each cell ``cell(value)``."""
    bins = list(next(iter(by_table.values())))
    rows = [("tables", *(f"{b} min" for b in bins)), ("---",) * (1 + len(bins))]
    rows += [(label, *(cell(by_table[key][b]) for b in bins)) for key, label in FOLLOW_TABLES]
    return markdown_table(rows)


def follow_kerror(root: Path) -> str:
    d = load_result(root, "atlas-tracking/follow.json")
    table = _follow_bins_table(d["bellhop_minus_tables_k_db"], lambda v: f"{v['rms_db']:.1f} ({v['mean_db']:+.1f})")
    return (table + "\nBELLHOP's K along the true path less the tables' K there, every band: RMS over the "
            "cycles and bands of each time bin (in brackets the mean), dB.\n\n"
            + caption(d, "atlas-tracking/follow.json"))


def follow_level_range(root: Path) -> str:
    d = load_result(root, "atlas-tracking/follow.json")
    ranges = _follow_bins_table(d["ml_level_range_bellhop"], lambda v: (
        f"{v['ln_error_median']:+.2f} / {v['ln_error_rms']:.2f} / {v['sd_over_range_median']:.2f}"))
    slopes = _follow_bins_table(d["tables_k_slope_db"], lambda v: f"{v:.1f}")
    return (ranges + "\nThe ML analysis's level range (eq. 20) on BELLHOP's levels, default tests: median and "
            "RMS of ln(level range / true range), then the median of eq. 21's sd over the true range, over the "
            "runs and cycles of each time bin.\n\n" + slopes
            + "\nEach table's K near the true range along the path, (K(0.8 r) - K(1.25 r)) / log10(1.25 / 0.8): "
            "dB per decade of range, median over the cycles and bands of each time bin (20 for spherical "
            "spreading, near 0 where K is flat: a level says little about range there).\n\n"
            + caption(d, "atlas-tracking/follow.json"))


def follow_over_origin(root: Path) -> str:
    d = load_result(root, "atlas-tracking/follow.json")
    r = d["after_10min_over_origin_bellhop"]
    rows = [("tables", "ML analysis over the origin table (90 % interval)",
             "particle filter over the origin table (90 % interval)"), ("---",) * 3]
    for name in ("atlas-10km", "atlas-5km"):
        rows.append((name.replace("atlas-", "atlas ").replace("km", " km"),
                     *(f"{r[f'{m} {name}']['ratio']:.2f} ({r[f'{m} {name}']['p05']:.2f}-{r[f'{m} {name}']['p95']:.2f})"
                       for m in ("ml", "rpf"))))
    return (markdown_table(rows)
            + f"\nRMS over {d['late_min']:g}-40 min of the position RMSE over the {d['runs']} runs (BELLHOP's "
            "levels), over the origin table's on the same runs; the interval from the runs resampled alike for "
            "both tables.\n\n" + caption(d, "atlas-tracking/follow.json"))


def follow_blend_ratio(root: Path) -> str:
    d = load_result(root, "atlas-tracking/blend.json")
    r = d["after_10min_over_origin"]
    names = [f"atlas-{sp} {w}" for sp in ("10km", "5km") for w in d["ratios"]]
    rows = [("tables, weights", "ML over origin (90 % interval)", "PF over origin (90 % interval)"), ("---",) * 3]
    for name in names:
        shown = name.replace("atlas-", "atlas ").replace("km", " km").replace("water-", "water, ratio ")
        rows.append((shown, *(f"{r[f'{m} {name}']['ratio']:.2f} ({r[f'{m} {name}']['p05']:.2f}-"
                              f"{r[f'{m} {name}']['p95']:.2f})" for m in ("ml", "rpf"))))
    n = d["runs_per_seed"] * len(d["seeds"])
    return (markdown_table(rows)
            + f"\nRMS over 10-40 min of the position RMSE over the {n} runs of both seeds pooled, over "
            "the origin table's on the same runs; the interval from the runs resampled alike for both tables.\n\n"
            + caption(d, "atlas-tracking/blend.json"))


def follow_blend(root: Path) -> str:
    d = load_result(root, "atlas-tracking/blend.json")
    seeds = [str(v) for v in d["seeds"]]
    sc = d["scores"]
    names = ["origin"] + [f"atlas-{sp} {r}" for sp in ("10km", "5km") for r in d["ratios"]]
    heads = [f"{m}, seed {sd}" for m in ("ML", "PF") for sd in seeds]
    rows = [("tables, weights", *heads, "ML whole run"), ("---",) * (2 + len(heads))]
    for name in names:
        shown = name.replace("atlas-", "atlas ").replace("km", " km").replace("water-", "water, ratio ")
        rows.append((shown, *(f"{sc[f'{m} {name}'][sd]['rmse_after_10min_m']:.0f}" for m in ("ml", "rpf")
                              for sd in seeds),
                     " / ".join(f"{sc[f'ml {name}'][sd]['rmse_whole_run_m']:.0f}" for sd in seeds)))
    return (markdown_table(rows)
            + f"\nPosition RMSE over {d['runs_per_seed']} runs per seed, RMS over 10-40 min, m (the "
            "last column over 0-40 min, a value per seed); BELLHOP's levels along the true paths; the "
            f"default ratio is {d['default_ratio']:g}.\n\n" + caption(d, "atlas-tracking/blend.json"))


def atlas_trackers_speed(root: Path) -> str:
    d = load_result(root, "atlas-trackers.json")
    m = d["median_s"]
    rows = [("figure", "one grid", "atlas", f"ratio (target {d['target_ratio']:g})"), ("---",) * 4,
            (f"ML cycle, {d['ml_rows']} class rows", f"{d['ml_cycle_ms']['grid']:.1f} ms",
             f"{d['ml_cycle_ms']['atlas']:.1f} ms", f"{d['ratio_ml_atlas_over_grid']:.2f}"),
            (f"particle filter, a batch of 20 runs x {d['rpf_particles']} particles", f"{m['rpf20_grid']:.2f} s",
             f"{m['rpf20_atlas']:.2f} s", f"{d['ratio_rpf20_atlas_over_grid']:.2f}"),
            (f"particle filter, one run x {d['rpf_particles']} particles", f"{1e3 * m['rpf_grid']:.0f} ms",
             f"{1e3 * m['rpf_atlas']:.0f} ms", f"{d['ratio_rpf_atlas_over_grid']:.2f}")]
    return (markdown_table(rows)
            + f"\nThe {d['scenario']} scenario, {d['cycles']} cycles, the 5 km atlas against one of its "
            f"tables, {d['repeats']} interleaved repeats, medians.\n\n" + caption(d, "atlas-trackers.json"))


def follow_manoeuvres(root: Path) -> str:
    d = load_result(root, "atlas-tracking/follow.json")
    m = d["ml_manoeuvres_declared"]
    rows = [("tables", "BELLHOP levels, default", "paper", "atlas's levels, default", "paper"), ("---",) * 5]
    for key, label in FOLLOW_TABLES:
        rows.append((label, *(f"{m[f'{t}_{key}_{lv}']['mean_manoeuvres']:.1f}" for t, lv in
                              (("ml", "bellhop"), ("ml-paper", "bellhop"), ("ml", "tables"), ("ml-paper", "tables")))))
    return markdown_table(rows) + "\n" + caption(d, "atlas-tracking/follow.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"follow-rmse": follow_rmse, "follow-kerror": follow_kerror, "follow-manoeuvres": follow_manoeuvres,
          "follow-blend": follow_blend, "follow-level-range": follow_level_range,
          "follow-blend-ratio": follow_blend_ratio,
          "follow-over-origin": follow_over_origin, "atlas-trackers-speed": atlas_trackers_speed}

#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("atlas-tracking/follow.json", ("mean_rmse_after_10min_m", "bot_origin_bellhop"), "with the same prior ({:.0f} m)"),
    ("atlas-tracking/follow.json", ("calibration_after_late_min", "bot_origin_bellhop", "range", "coverage_90",
                                    percent), "to {:.0f} %\n  of cycles held"),
    ("truth-bellhop.json", ("first", "seconds"), "{:.1f} s on 2 workers"),
    ("truth-bellhop.json", ("cached", "seconds"), "{:.1f} s again from the run"),
)
