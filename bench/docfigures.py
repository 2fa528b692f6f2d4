"""The tables in README and docs/ that quote a result file, generated from it: the one script.

A page holds each such table between two markers naming it,

    <!-- docfigures grids -->
    | figure | measured | target |
    ...
    <!-- /docfigures -->

and ``TABLES`` says which result file each name is made from and how. ``python -m
bench.docfigures`` rewrites every block from its file; ``--check`` changes nothing and exits 1
naming each block whose committed text differs from what its file gives (the test
tests/test_docfigures.py runs it in ``make test``). A table's caption names its file; a file
marked ``rerun_pending`` (bench.record) is quoted as it is, with the mark.

Figures quoted in prose are checked, not written: ``QUOTES`` lists, per page, the result file,
the figure's place in it and how the page prints it, and ``--check`` names each whose printed
value the page no longer holds (a prose sentence is the author's; the check keeps it honest).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Callable
from pathlib import Path

from bench.docfigures_planning import TABLES as PLANNING_TABLES
from bench.harness import REPO

PAGES = ("README.md", "docs/*.md")
BLOCK = re.compile(r"(<!-- docfigures (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /docfigures -->)", re.S)


def _load(root: Path, name: str) -> dict:
    return json.loads((root / "docs" / "results" / name).read_text())


def _fig(data: dict, name: str) -> float:
    figures = data.get("figures") or data.get("results")
    return figures[name]["value"]


def _source(data: dict, file: str) -> str:
    prov = data["provenance"]
    when = f"commit {prov.get('commit') or '?'}, {str(prov.get('date') or '?')[:10]}"
    load = prov.get("load_average") or {}
    before = load.get("before")
    before = before[0] if isinstance(before, list) else before
    pending = "; to be made again after the sea-surface change" if prov.get("rerun_pending") else ""
    shown = f", load average {before:g} at the start" if isinstance(before, (int, float)) else ""
    return f"*From `docs/results/{file}` (`{prov['command']}`; {when}{shown}{pending}).*\n"


def grids(root: Path) -> str:
    d = _load(root, "grids.json")
    w1, w2 = _fig(d, "ocean_deep_build_1_worker"), _fig(d, "ocean_deep_build_2_workers")
    raw = _fig(d, "ocean_deep_raw_bellhop_sum")
    naive = _fig(d, "naive_loop_estimate")
    rows = [
        ("figure", "measured", "target"), ("---", "---", "---"),
        (f"`grids build`, 2 workers ({_fig(d, 'ocean_deep_runs')} BELLHOP runs)", f"{w2:.1f} s", "< 60 s"),
        ("`grids build`, 1 worker, over the sum of the raw BELLHOP runs on the same .env files",
         f"{_fig(d, 'overhead_build_over_raw_bellhop'):.2f} ({w1:.1f} s / {raw:.1f} s)", "<= 1.10"),
        ("the command's fixed cost (start-up, writing the 12 MB netCDF), the same on any number of workers",
         f"{_fig(d, 'ocean_deep_fixed_cost_w1_minus_raw'):.1f} s", ""),
        ("2 workers vs 1", f"{_fig(d, 'parallel_speedup_2_vs_1_workers'):.2f}x", ">= 1.7"),
        ("peak memory (largest process)", f"{_fig(d, 'ocean_deep_peak_rss'):.0f} MiB", "< 1 GiB"),
        ("the naive loop (classes x bands x 7 frequencies at BELLHOP's automatic beam count), estimated from "
         f"BELLHOP's measured cost per beam and receiver ({_fig(d, 'bellhop_cost_per_beam_receiver'):.2f} ns; a "
         f"real automatic-beam run took {_fig(d, 'cost_model_check_auto_beam_run'):.2f} x the model's prediction)",
         f"about {naive:.0f} s ({naive / 60:.0f} min), {_fig(d, 'speedup_over_naive_loop'):.0f}x slower",
         '"well over ten minutes"'),
    ]
    return _table(rows) + "\n" + _source(d, "grids.json")


def accuracy(root: Path) -> str:
    d = _load(root, "accuracy.json")

    def pair(key: str, digits: int = 2) -> tuple[str, str]:
        return (f"{_fig(d, key + '_median'):#.{digits}g} dB", f"{_fig(d, key + '_p95'):#.{digits}g} dB")

    beams = (250, 500, 1000, 3000)
    rec = [k for k in (d.get("figures") or d["results"]) if k.startswith("k_error_reciprocity_")
           and k.endswith("_median")]
    rows = [("shortcut", "median abs. error", "95th percentile"), ("---", "---", "---"),
            ("all of the default settings together", *pair("k_error_default_grid_vs_full")),
            ("fixed fan of 1500 beams (vs up to 72 000)", *pair("k_error_fixed_beam_fan_vs_full")),
            ("one run per band, other frequencies through absorption (a near-surface class's run: its "
             "surface pattern averaged over the band)", *pair("k_error_frequency_shortcut_vs_full")),
            (" / ".join(str(b) for b in beams) + " beams",
             " / ".join(f"{_fig(d, f'k_error_{b}_beams_vs_full_median'):#.2g}" for b in beams) + " dB",
             " / ".join(f"{_fig(d, f'k_error_{b}_beams_vs_full_p95'):#.2g}" for b in beams) + " dB")]
    for key in rec:
        cls_name, depth = key.removeprefix("k_error_reciprocity_").removesuffix("_median").split("_")
        what = f"{cls_name} at {depth.removesuffix('m')} m"
        rows.append((f"reciprocity (source at the observer), {what}", *pair(key.removesuffix("_median"))))
    table = [k for k in (d.get("figures") or d["results"]) if k.startswith("k_error_observer_table_semicoherent_")
             and k.endswith("_median")]
    for key in table:
        cls_name, depth = key.removeprefix("k_error_observer_table_semicoherent_").removesuffix("_median").split("_")
        inc = key.replace("_semicoherent_", "_incoherent_").removesuffix("_median")
        base = key.removesuffix("_median")
        rows.append((f"the table from the observer (arrivals and the surface's image at the target), {cls_name} at "
                     f"{depth.removesuffix('m')} m, against its own runs; incoherent beams in brackets",
                     f"{_fig(d, base + '_median'):#.2g} dB ({_fig(d, inc + '_median'):#.2g} dB)",
                     f"{_fig(d, base + '_p95'):#.2g} dB ({_fig(d, inc + '_p95'):#.2g} dB)"))
    tl = "tl_field_error_default_vs_full_NPS_FB1"
    rows.append(("the whole TL field (NPS, FB1, where TL < 120 dB) with the default settings", *pair(tl)))
    return _table(rows) + "\n" + _source(d, "accuracy.json")


def startup(root: Path) -> str:
    d = _load(root, "startup.json")
    figures = d["figures"]
    rows = [("command", "median, s", "target"), ("---", "---", "---")]
    for key, value in figures.items():
        if key.startswith("tmakit_") and key.endswith("_help"):
            command = "tmakit --help" if key == "tmakit_help" else \
                f"tmakit {key.removeprefix('tmakit_').removesuffix('_help')} --help"
            rows.append((f"`{command}`", f"{value['value']:.2f}", f"< {d['target_s']:g}"))
    heavy = ", ".join(d["import_profile"]["heavy_imported"]) or "none of numpy, xarray, pandas, matplotlib"
    rows.append(("imports before the parser runs (`-X importtime`)",
                 f"{d['import_profile']['total_ms']:.0f} ms; {heavy}", ""))
    return _table(rows) + "\n" + _source(d, "startup.json")


def manoeuvres(root: Path) -> str:
    d = _load(root, "maneuver.json")
    rows = [("tests", "course, 5-20 min", "speed", "range", "course, 25-40 min", "speed", "range",
             "turn declared after (mean, max)", "missed", "declared where none"), ("---",) * 10]
    for label, name in (("paper", "paper (eqs. 26-29)"), ("default", "default")):
        def f(key: str, label: str = label) -> float:
            return _fig(d, f"gm_{label}_{key}")

        rows.append((name, f"{f('tack1_course_rms'):.2f} deg", f"{f('tack1_speed_rms'):.2f} m/s",
                     f"{f('tack1_range_rms'):.0f} m", f"{f('tack2_course_rms'):.2f} deg",
                     f"{f('tack2_speed_rms'):.2f} m/s", f"{f('tack2_range_rms'):.0f} m",
                     f"{f('turn_delay_mean'):.0f} s, {f('turn_delay_max'):.0f} s", f"{f('turn_missed_runs'):d}",
                     f"{f('false_per_run'):.2g} per run"))
    ratios = [_fig(d, k) for k in (d.get("figures") or {}) if k.startswith("gm_default_over_paper_")]
    return (_table(rows) + f"\nDefault over paper: {min(ratios):.4f}-{max(ratios):.4f} on the six figures; "
            f"the study took {_fig(d, 'gm_default_seconds'):.0f} s with the default tests, "
            f"{_fig(d, 'gm_paper_seconds'):.0f} s with the paper's.\n\n" + _source(d, "maneuver.json"))


def stonesoup(root: Path) -> str:
    d = _load(root, "stonesoup.json")
    summ = d["summary"]
    rpf = summ["rpf"]
    rows = [("filter", "particles", f"final position error, median of {len(d['runs'])} runs", "over tmakit's",
             "time per run (median)"), ("---",) * 5,
            ("tmakit track --method rpf", f"{rpf['particles']}", f"{rpf['final_error_median_m']:.0f} m", "1",
             f"{rpf['seconds_median']:.3f} s")]
    for s in summ["stonesoup"]:
        rows.append(("Stone Soup SIR + MCMC regulariser, tmakit's model", f"{s['particles']}",
                     f"{s['final_error_median_m']:.0f} m", f"{s['over_rpf']:.2f}x", f"{s['seconds_median']:.2f} s"))
    return _table(rows) + "\n" + _source(d, "stonesoup.json")


#: The G&M experiments of docs/gm.md: (result folder, what the paper gives for the true class).
GM_RUNS = (("gm-tv-30km", "5-7 deg, 1.0-1.5 m/s, 2-3 km"), ("gm-tv-110km", "5-30 deg, sV = 1.0 m/s, <= 20 %"),
           ("gm-nps", "Figs. 12-14"))


def gm_experiments(root: Path) -> str:
    rows = [("scenario, runs", "hypothesis", "course RMS", "speed RMS", "range RMS", "paper"), ("---",) * 6]
    sources = []
    for folder, paper in GM_RUNS:
        d = _load(root, f"{folder}/summary.json")
        true = d["true_class"]
        for name in [true] + [c for c in d["classes"] if c != true]:
            s = d["steady_state"][name]
            cells = (f"{s['course_rms_deg']:.1f} deg", f"{s['speed_rms_mps']:.2f} m/s",
                     f"{s['range_rms_m'] / 1000:.2f} km ({100 * s['range_rms_rel']:.0f} %)")
            if name == true:
                rows.append((f"{folder}, {d['runs']}", f"**{name} (true)**", *(f"**{c}**" for c in cells), paper))
            else:
                rows.append((f"{folder}, {d['runs']}", name, *cells, "larger than true class"))
        sources.append(_source(d, f"{folder}/summary.json"))
    return _table(rows) + "\n" + "".join(sources)


def shelf_rmse(root: Path) -> str:
    d = _load(root, "shelf/shelf.json")
    names = (("ml_bearing", "ML (G&M), bearing-dependent"), ("ml_isotropic", "ML (G&M), origin's column, flat"),
             ("rpf_bearing", "particle filter, bearing-dependent"),
             ("rpf_isotropic", "particle filter, origin's column, flat"))
    rows = _rmse_rows(d, names, ("tracker, grid", "5-30 min"), "{:.0f}", 1.0)
    return _table(rows) + "\n" + _source(d, "shelf/shelf.json")


def _rmse_rows(d: dict, names, heads: tuple[str, str], fmt: str, scale: float) -> list[tuple]:
    """A tracker study's position RMSE at 5, 10, 20 and 30 min and its mean after 5 min, a row per
    (key, label) of ``names``, each value divided by ``scale`` and printed with ``fmt``."""
    rows = [(heads[0], "5 min", "10 min", "20 min", "30 min", heads[1]), ("---",) * 6]
    for key, label in names:
        r = d["rmse_m"][key]
        rows.append((label, *(fmt.format(r[t] / scale) for t in ("5", "10", "20", "30")),
                     fmt.format(d["mean_rmse_after_5min_m"][key] / scale)))
    return rows


def shelf_dk(root: Path) -> str:
    d = _load(root, "shelf/shelf.json")
    where = {"0": "0 deg (up the slope to the shelf)", "90": "90 deg (along the slope)",
             "150": "150 deg (down the slope, where the transport starts)",
             "180": "180 deg (down the slope to the basin)"}
    rows = [("bearing", "5 km", "10 km", "15 km", "20 km"), ("---",) * 5]
    for b, label in where.items():
        rows.append((label, *(f"{d['k_difference_db'][b][r]:+.1f}" for r in ("5", "10", "15", "20"))))
    return _table(rows) + "\n" + _source(d, "shelf/shelf.json")


FOLLOW_TABLES = (("origin", "origin"), ("atlas-10km", "atlas, 10 km"), ("atlas-5km", "atlas, 5 km"))


def follow_rmse(root: Path) -> str:
    d = _load(root, "atlas-tracking/follow.json")
    m = d["mean_rmse_after_10min_m"]
    rows = [("tables", "ML, BELLHOP levels", "PF, BELLHOP levels", "ML, the atlas's own levels",
             "PF, the atlas's own levels", "ML with the paper's tests, BELLHOP levels"), ("---",) * 6]
    for key, label in FOLLOW_TABLES:
        rows.append((label, *(f"{m[f'{t}_{key}_{lv}']:.0f}" for t, lv in
                              (("ml", "bellhop"), ("rpf", "bellhop"), ("ml", "tables"), ("rpf", "tables"),
                               ("ml-paper", "bellhop")))))
    lv = d["level_bellhop_minus_atlas5km_db"]
    return (_table(rows) + "\nAlong the path, BELLHOP's FB1 level less the 5 km atlas's: "
            f"median {lv['median']:+.1f} dB, "
            f"sd {lv['sd']:.1f} dB, 95th percentile of the absolute difference {lv['p95_abs']:.1f} dB.\n\n"
            + _source(d, "atlas-tracking/follow.json"))


def _follow_bins_table(by_table: dict, cell) -> str:
    """A follow-study table: a row per table of `FOLLOW_TABLES`, a column per time bin of
    ``by_table`` (table -> bin -> value), each cell ``cell(value)``."""
    bins = list(next(iter(by_table.values())))
    rows = [("tables", *(f"{b} min" for b in bins)), ("---",) * (1 + len(bins))]
    rows += [(label, *(cell(by_table[key][b]) for b in bins)) for key, label in FOLLOW_TABLES]
    return _table(rows)


def follow_kerror(root: Path) -> str:
    d = _load(root, "atlas-tracking/follow.json")
    table = _follow_bins_table(d["bellhop_minus_tables_k_db"], lambda v: f"{v['rms_db']:.1f} ({v['mean_db']:+.1f})")
    return (table + "\nBELLHOP's K along the true path less the tables' K there, every band: RMS over the "
            "cycles and bands of each time bin (in brackets the mean), dB.\n\n"
            + _source(d, "atlas-tracking/follow.json"))


def follow_level_range(root: Path) -> str:
    d = _load(root, "atlas-tracking/follow.json")
    ranges = _follow_bins_table(d["ml_level_range_bellhop"], lambda v: (
        f"{v['ln_error_median']:+.2f} / {v['ln_error_rms']:.2f} / {v['sd_over_range_median']:.2f}"))
    slopes = _follow_bins_table(d["tables_k_slope_db"], lambda v: f"{v:.1f}")
    return (ranges + "\nThe ML analysis's level range (eq. 20) on BELLHOP's levels, default tests: median and "
            "RMS of ln(level range / true range), then the median of eq. 21's sd over the true range, over the "
            "runs and cycles of each time bin.\n\n" + slopes
            + "\nEach table's K near the true range along the path, (K(0.8 r) - K(1.25 r)) / log10(1.25 / 0.8): "
            "dB per decade of range, median over the cycles and bands of each time bin (20 for spherical "
            "spreading, near 0 where K is flat: a level says little about range there).\n\n"
            + _source(d, "atlas-tracking/follow.json"))


def follow_blend_ratio(root: Path) -> str:
    d = _load(root, "atlas-tracking/blend.json")
    r = d["after_10min_over_origin"]
    names = [f"atlas-{sp} {w}" for sp in ("10km", "5km") for w in d["ratios"]]
    rows = [("tables, weights", "ML over origin (90 % interval)", "PF over origin (90 % interval)"), ("---",) * 3]
    for name in names:
        shown = name.replace("atlas-", "atlas ").replace("km", " km").replace("water-", "water, ratio ")
        rows.append((shown, *(f"{r[f'{m} {name}']['ratio']:.2f} ({r[f'{m} {name}']['p05']:.2f}-"
                              f"{r[f'{m} {name}']['p95']:.2f})" for m in ("ml", "rpf"))))
    n = d["runs_per_seed"] * len(d["seeds"])
    return (_table(rows) + f"\nRMS over 10-40 min of the position RMSE over the {n} runs of both seeds pooled, over "
            "the origin table's on the same runs; the interval from the runs resampled alike for both tables.\n\n"
            + _source(d, "atlas-tracking/blend.json"))


def follow_blend(root: Path) -> str:
    d = _load(root, "atlas-tracking/blend.json")
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
    return (_table(rows) + f"\nPosition RMSE over {d['runs_per_seed']} runs per seed, RMS over 10-40 min, m (the "
            "last column over 0-40 min, a value per seed); BELLHOP's levels along the true paths; the "
            f"default ratio is {d['default_ratio']:g}.\n\n" + _source(d, "atlas-tracking/blend.json"))


def atlas_trackers_speed(root: Path) -> str:
    d = _load(root, "atlas-trackers.json")
    m = d["median_s"]
    rows = [("figure", "one grid", "atlas", f"ratio (target {d['target_ratio']:g})"), ("---",) * 4,
            (f"ML cycle, {d['ml_rows']} class rows", f"{d['ml_cycle_ms']['grid']:.1f} ms",
             f"{d['ml_cycle_ms']['atlas']:.1f} ms", f"{d['ratio_ml_atlas_over_grid']:.2f}"),
            (f"particle filter, a batch of 20 runs x {d['rpf_particles']} particles", f"{m['rpf20_grid']:.2f} s",
             f"{m['rpf20_atlas']:.2f} s", f"{d['ratio_rpf20_atlas_over_grid']:.2f}"),
            (f"particle filter, one run x {d['rpf_particles']} particles", f"{1e3 * m['rpf_grid']:.0f} ms",
             f"{1e3 * m['rpf_atlas']:.0f} ms", f"{d['ratio_rpf_atlas_over_grid']:.2f}")]
    return (_table(rows) + f"\nThe {d['scenario']} scenario, {d['cycles']} cycles, the 5 km atlas against one of its "
            f"tables, {d['repeats']} interleaved repeats, medians.\n\n" + _source(d, "atlas-trackers.json"))


def follow_manoeuvres(root: Path) -> str:
    d = _load(root, "atlas-tracking/follow.json")
    m = d["ml_manoeuvres_declared"]
    rows = [("tables", "BELLHOP levels, default", "paper", "atlas's levels, default", "paper"), ("---",) * 5]
    for key, label in FOLLOW_TABLES:
        rows.append((label, *(f"{m[f'{t}_{key}_{lv}']['mean_manoeuvres']:.1f}" for t, lv in
                              (("ml", "bellhop"), ("ml-paper", "bellhop"), ("ml", "tables"), ("ml-paper", "tables")))))
    return _table(rows) + "\n" + _source(d, "atlas-tracking/follow.json")


def kerror_sd(root: Path) -> str:
    d = _load(root, "kerror/sensitivity.json")
    depth = {"NPS": 200, "SW": 6, "TV": 8}
    rows = [("class", "measured `k_error_sd_db` (area file)", "median sd of K by bearing, dB (0 / 90 / 180 / 300 deg)",
             "drives the constant offset"), ("---",) * 4]
    for c, sd in d["k_error_sd_db"].items():
        by = d["k_sd_db_median_by_bearing"][c]
        drivers = sorted(d["offset_drivers"][c].items(), key=lambda kv: -abs(kv[1]))[:2]
        rows.append((f"{c} ({depth.get(c, '?')} m)", f"{sd:.2f} ({d['k_error_sd_db_area_file'][c]:g})",
                     " / ".join(f"{by[b]:.2f}" for b in ("0", "90", "180", "300")),
                     ", ".join(f"{k.replace('_', ' ')} ({v:+.2f})" for k, v in drivers)))
    return _table(rows) + "\n" + _source(d, "kerror/sensitivity.json")


def kerror_rmse(root: Path) -> str:
    d = _load(root, "kerror/kerror.json")
    names = (("rpf_map", "particle filter, sd by bearing and range"), ("rpf_scalar", "particle filter, one number"),
             ("ml_map", "ML analysis, sd by bearing and range"), ("ml_scalar", "ML analysis, one number"))
    rows = _rmse_rows(d, names, ("position RMSE, km", "mean after 5 min"), "{:.2f}", 1000.0)
    return _table(rows) + "\n" + _source(d, "kerror/kerror.json")


def _pm(s: dict, key: str = "p90_db") -> str:
    return f"{s['median_db']:.2f} / {s[key]:.2f} / {s['mean_db']:+.2f}"


def surface(root: Path) -> str:
    d = _load(root, "surface.json")
    c = d["cases"]
    rows = [("case", "semicoherent (the default): median / p90 / mean, dB", "incoherent beams",
             "bound (median / mean)"), ("---", "---", "---", "---")]
    pairs = [
        ("image-source solution, flat grid, 6 m source, 100-300 Hz", "image flat 100-300 Hz", "0.1 median"),
        ("Munk channel, flat grid TL beyond 5 km, 6 m, 100 Hz tone", "munk flat TL beyond 5 km, 100 Hz tone",
         "1.5 / 1"),
        ("the same, 89-112 Hz", "munk flat TL beyond 5 km, 89-112 Hz", ""),
        ("Munk, table from the 100 m observer, 6 m target, beyond 30 km, 89-112 Hz",
         "munk from the observer, 6 m to 100 m beyond 30 km, 89-112 Hz", "3.5 / 1.5"),
        ("the same, 100 Hz tone", "munk from the observer, 6 m to 100 m beyond 30 km, 100 Hz tone", ""),
        ("200 m shelf, flat grid, 5 m source, 250 Hz, 2-20 km", "shelf 5 m 250 Hz, 2-20 km", "1 / (p90 2.5)"),
    ]
    for label, key, bound in pairs:
        rows.append((label, _pm(c[f"{key}, semicoherent"]), _pm(c[f"{key}, incoherent"]), bound))
    k = c["image from the observer 100-300 Hz, semicoherent"]["k"]
    rows.append(("image-source solution, table from the 100 m observer, K of the 6 m target", _pm(k), "", "0.1 median"))
    for mode in ("semicoherent", "incoherent"):
        rec = c[f"reciprocity ocean-deep K to 40 km, {mode}"]
        worst = max(rec.values(), key=lambda x: x["median_db"])
        c[f"_rec_{mode}"] = worst
    rows.append(("ocean-deep, K of SW and TV from the observer against the targets' own runs (worst class and band)",
                 _pm(c["_rec_semicoherent"]), _pm(c["_rec_incoherent"]), "0.5 median"))
    return _table(rows) + "\n" + _source(d, "surface.json")


def surface_cost(root: Path) -> str:
    d = _load(root, "surface-cost.json")
    rows = [("build (2 workers)", "incoherent", "semicoherent (the default)", "wall ratio", "BELLHOP ratio"),
            ("---", "---", "---", "---", "---")]
    for name, b in d["builds"].items():
        rows.append((name, f"{b['wall_incoherent_s']:.1f} s ({b['runs_incoherent']} runs)",
                     f"{b['wall_semicoherent_s']:.1f} s ({b['runs_semicoherent']} runs)",
                     f"{b['wall_ratio']:.2f}x", f"{b['bellhop_ratio']:.2f}x"))
    return _table(rows) + "\n" + _source(d, "surface-cost.json")


def radials(root: Path) -> str:
    d = _load(root, "radials.json")

    def f(key: str) -> float:
        return _fig(d, key)

    rows = [("figure", f"shelf-break, 12 radials x 3 bands to 30 km ({f('shelf_break_runs'):d} runs)",
             f"36 radials x 3 bands to 50 km ({f('wide_36_radials_runs'):d} runs)", "target"),
            ("---", "---", "---", "---"),
            ("`grids build`, 2 workers", f"{f('shelf_break_build_2_workers_median'):.1f} s",
             f"{f('wide_36_radials_build_2_workers'):.1f} s", ""),
            ("over half the sum of the raw BELLHOP runs", f"{f('shelf_break_2_workers_over_half_raw'):.2f}",
             f"{f('wide_36_radials_2_workers_over_half_raw'):.2f}", "<= 1.10"),
            ("the raw runs two at a time, over half their sum (what the machine allows)",
             f"{f('shelf_break_raw_two_at_a_time_over_half_raw'):.2f}",
             f"{f('wide_36_radials_raw_two_at_a_time_over_half_raw'):.2f}", ""),
            ("2 workers vs 1", f"{f('shelf_break_speedup_2_vs_1'):.2f}x", "", ">= 1.8x"),
            ("the command's fixed cost (1 worker less the raw sum)",
             f"{f('shelf_break_fixed_cost_w1_minus_raw'):.1f} s", "", ""),
            ("peak memory (largest process)", "", f"{f('wide_36_radials_peak_rss'):.0f} MiB", "< 1 GiB"),
            ("K with the default 25 m ray step against 5 m, median / 95th percentile",
             f"{f('step_25m_vs_5m_k_median_abs_diff'):.2f} / {f('step_25m_vs_5m_k_p95_abs_diff'):.2f} dB", "", "")]
    return _table(rows) + "\n" + _source(d, "radials.json")


def grids_check(root: Path) -> str:
    d = _load(root, "grids-check.json")
    rows = [("area", "doubled", "K moves: median (worst class and band), dB", "converged"),
            ("---", "---", "---", "---")]
    for area, result in d["areas"].items():
        for v in result["variants"]:
            rows.append((area, v["change"], f"{v['median_db']:.2f} ({v['worst_db']:.2f} {v['worst']})",
                         "yes" if v["converged"] else "no"))
    return _table(rows) + "\n" + _source(d, "grids-check.json")


def _whole(case: dict) -> dict:
    """(class, band) -> the comparison's row over all bearings of a models-study case."""
    return {(r["class"], r["band"]): r for r in case["rows"] if r["bearing_deg"] is None}


def _per_class(values: list[str], classes: list[str]) -> str:
    """One value when every class has it, else each with its class."""
    if len(set(values)) == 1:
        return values[0]
    return ", ".join(f"{v} ({c})" for v, c in zip(values, classes))


def _cut(case: dict) -> str:
    bearings = sorted({r["bearing_deg"] for r in case["rows"] if r["bearing_deg"] is not None})
    base = case["area"].split("-fb")[0].removesuffix("-crossover")
    bands = "/".join(b[0] for b in case["bands"])
    where = (f", radial{'s' if len(bearings) > 1 else ''} {'/'.join(f'{b:g}' for b in bearings)} deg"
             if bearings else "")
    return f"{base} {bands}{where} to {case['range_max_m'] / 1000:g} km"


def models_areas(root: Path) -> str:
    d = _load(root, "models-areas.json")
    rows = [("area, band, cut", "\\|dTL\\| median / p90", "\\|dK\\| median / p90, NPS (200 m)", "SW (6 m)",
             "TV (8 m)", "rms dK, NPS / SW / TV", "RAM runs, run time", "BELLHOP runs, run time"),
            ("---",) * 8]
    for case in d["cases"]:
        whole = _whole(case)
        classes = list(dict.fromkeys(c for c, _ in whole))
        band = case["bands"][0][0]
        tl = [f"{whole[(c, band)]['tl_median_db']:.2f} / {whole[(c, band)]['tl_p90_db']:.2f} dB" for c in classes]
        k = [f"{whole[(c, band)]['k_median_db']:.2f} / {whole[(c, band)]['k_p90_db']:.2f} dB" for c in classes]
        rms = " / ".join(f"{whole[(c, band)]['k_rms_db']:.2f}" for c in classes) + " dB"
        ram, bh = case["ram"], case["bellhop"]
        rows.append((_cut(case), _per_class(tl, classes), *k, rms,
                     f"{ram['runs']}, {ram['run_seconds']:.0f} s ({ram['wall_s']:.0f} s wall)",
                     f"{bh['runs']}, {_secs(bh['run_seconds'])} s ({case.get('bellhop_mode', 'incoherent')}, "
                     f"{case.get('bellhop_beams', '?')} beams)"))
    return _table(rows) + "\n" + _source(d, "models-areas.json")


def _secs(x: float) -> str:
    return f"{x:.2g}" if x < 10.0 else f"{x:.0f}"


def ram_crossover(root: Path) -> str:
    d = _load(root, "ram-crossover.json")
    rows = [("band", "\\|dTL\\| median / p90", "\\|dK\\| median, NPS / SW / TV", "rms dK, NPS / SW / TV"),
            ("---",) * 4]
    for case in d["cases"]:
        whole = _whole(case)
        classes = list(dict.fromkeys(c for c, _ in whole))
        for name, low, high in case["bands"]:
            tl = [f"{whole[(c, name)]['tl_median_db']:.2f} / {whole[(c, name)]['tl_p90_db']:.2f} dB" for c in classes]
            rows.append((f"{low:.0f}-{high:.0f} Hz", _per_class(tl, classes),
                         " / ".join(f"{whole[(c, name)]['k_median_db']:.2f}" for c in classes) + " dB",
                         " / ".join(f"{whole[(c, name)]['k_rms_db']:.2f}" for c in classes) + " dB"))
    return _table(rows) + "\n" + _source(d, "ram-crossover.json")


def surface_compare(root: Path) -> str:
    d = _load(root, "surface-compare.json")
    rows = [("area", "class", "FB1 / FB2 / FB3 (or the band): \\|dK\\| median (p90), signed median dK, dB"),
            ("---",) * 3]
    for area, entry in d["areas"].items():
        by = entry["by_class_band"]
        classes = list(dict.fromkeys(k.split()[0] for k in by))
        for cls_name in classes:
            cells = [f"{v['k_median_db']:.2f} ({v['k_p90_db']:.2f}), {v['k_signed_median_db']:+.2f}"
                     for k, v in by.items() if k.split()[0] == cls_name]
            rows.append((area, cls_name, " / ".join(cells)))
    return _table(rows) + "\n" + _source(d, "surface-compare.json")


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
        d = _load(root, file)
        specs = ", ".join(f"`{p}`" for p in d["perturbations"]) if name != "default" else ""
        sd = d["k_error_sd_db"]
        share = [100.0 * v["constant_fraction"] for v in d["k"].values()]
        spread = [v["sd_db_median"] for v in d["k"].values()]
        share_text = "< 1 %" if max(share) < 1.0 else _range_span(share, 0, "%")
        rows.append((f"{label}: {specs}" if specs else label, *(f"{sd[c]:.2f} dB" for c in ("NPS", "SW", "TV")),
                     share_text, _range_span(spread, 2 if max(spread) < 1 else 1, "dB")))
        sources.append(_made(d, file))
    return _table(rows) + "\n*From " + "; ".join(sources) + " (each by the command above, through "\
        "`python -m bench.record`).*\n"


def _made(data: dict, file: str) -> str:
    """A result file named with the commit, date and load average it was made at."""
    prov = data["provenance"]
    load = (prov.get("load_average") or {}).get("before")
    load = load[0] if isinstance(load, list) else load
    shown = f", load average {load:g}" if isinstance(load, (int, float)) else ""
    pending = ", to be made again after the sea-surface change" if prov.get("rerun_pending") else ""
    when = f"commit {prov.get('commit') or '?'}, {str(prov.get('date') or '?')[:10]}"
    return f"`docs/results/{file}` ({when}{shown}{pending})"


def sensitivity_ranges(root: Path) -> str:
    rows = [("set", "class", "5 km", "10 km", "20 km", "50 km", "100 km"), ("---",) * 7]
    for name, label in SENSITIVITY_SETS.items():
        d = _load(root, f"sensitivity/ocean-deep-{name}.json")
        for cls_name in ("NPS", "SW"):
            err = d["range_error"][cls_name]
            km = [err[r]["rms_m"] / 1000.0 for r in ("5", "10", "20", "50", "100")]
            rows.append((label, cls_name, *(f"{x:.2f} km" if x < 10.0 else f"{x:.1f} km" for x in km)))
    return _table(rows) + "\n" + "*From the same files.*\n"


def sensitivity_speed(root: Path) -> str:
    d = _load(root, "sensitivity.json")
    w1, w2 = _fig(d, "study_1_worker_wall"), _fig(d, "study_2_workers_wall")
    rows = [("figure", "measured", "target"), ("---",) * 3,
            ("2 workers vs 1 (median of the side-by-side pairs)",
             f"{_fig(d, 'speedup_2_vs_1_workers'):.2f}x ({w1:.1f} s -> {w2:.1f} s)", ">= 1.7x"),
            ("overhead, 1 worker: wall / sum of BELLHOP - 1",
             f"{_fig(d, 'overhead_1_worker_wall_over_bellhop_sum'):.1f} %", "<= 10 %"),
            ("overhead, 2 workers: 2 x wall / sum of BELLHOP - 1",
             f"{_fig(d, 'overhead_2_workers_wall_x2_over_bellhop_sum'):.1f} %", "<= 10 %"),
            ("results with 1 and 2 workers",
             "identical (bitwise)" if _fig(d, "results_identical_1_vs_2_workers") else "NOT identical", "identical")]
    return _table(rows) + "\n" + _source(d, "sensitivity.json")


def reciprocity(root: Path) -> str:
    sens, acc = _load(root, "sensitivity.json"), _load(root, "accuracy.json")
    rows = [("class (depth)", "how its K is computed", "against its own runs: median", "p95"), ("---",) * 4]
    for key in (k for k in (sens.get("figures") or sens["results"]) if k.startswith("reciprocity_vs_direct_")
                and k.endswith("_median")):
        cls_name, depth = key.removeprefix("reciprocity_vs_direct_").removesuffix("_median").split("_")
        rows.append((f"{cls_name} ({depth.removesuffix('m')} m)", "by reciprocity (source at the observer)",
                     f"{_fig(sens, key):.2f} dB", f"{_fig(sens, key.replace('_median', '_p95')):.2f} dB"))
    for key in (k for k in (acc.get("figures") or acc["results"])
                if k.startswith("k_error_observer_table_semicoherent_") and k.endswith("_median")):
        cls_name, depth = key.removeprefix("k_error_observer_table_semicoherent_").removesuffix("_median").split("_")
        inc = key.replace("_semicoherent_", "_incoherent_")
        rows.append((f"{cls_name} ({depth.removesuffix('m')} m)",
                     "directly here; from the observer in a bearing-dependent grid or an atlas (incoherent beams "
                     "in brackets)", f"{_fig(acc, key):.2f} dB ({_fig(acc, inc):.2f} dB)",
                     f"{_fig(acc, key.replace('_median', '_p95')):.2f} dB "
                     f"({_fig(acc, inc.replace('_median', '_p95')):.2f} dB)"))
    return _table(rows) + "\n" + _source(sens, "sensitivity.json") + _source(acc, "accuracy.json")


def models_bench(root: Path) -> str:
    d = _load(root, "models.json")
    runs = _fig(d, "ram_runs")
    rows = [("figure", "value"), ("---", "---"),
            (f"RAM runs ({runs // 21} radials x 21 frequencies)", f"{runs}"),
            ("BELLHOP build, 2 workers",
             f"{_fig(d, 'bellhop_w2_wall'):.2f} s, peak {_fig(d, 'bellhop_w2_peak_rss'):.0f} MiB"),
            ("RAM build, 1 worker",
             f"{_fig(d, 'ram_w1_wall'):.1f} s ({_fig(d, 'ram_run_seconds_sum_w1'):.1f} s of runs), "
             f"peak {_fig(d, 'ram_w1_peak_rss'):.0f} MiB"),
            ("RAM build, 2 workers", f"{_fig(d, 'ram_w2_wall'):.1f} s, peak {_fig(d, 'ram_w2_peak_rss'):.0f} MiB"),
            ("RAM on 2 workers over BELLHOP on 2 workers", f"{_fig(d, 'ram_w2_over_bellhop_w2'):.2g}x"),
            ("RAM, 2 workers against 1", f"{_fig(d, 'ram_speedup_2_vs_1'):.2f}x (target >= 1.8x)")]
    return _table(rows) + "\n" + _source(d, "models.json")


_DEPTH_ESTIMATES = (("ml_posterior", "ML analysis: posterior over its hypotheses' tracks"),
                    ("rpf_bank", "bank of particle filters at the ML's hypotheses"),
                    ("rpf_particles", "particle filter, depth a state: the particles (mean +- 1.645 sd)"),
                    ("rpf_track", "particle filter, depth a state: posterior along its track"),
                    ("known_motion_true_track", "the motion known: posterior along the true track"))


def depth_errors(root: Path) -> str:
    d = _load(root, "depth/depth.json")
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
    return (_table(rows) + f"\nPosition error with the depth unknown over that given the true depth, medians over "
            f"all runs (by scenario): {text}; target <= {d['target_ratio']:g}.{other_text}{nearest_text}"
            f"{scale_text}\n\n"
            + _source(d, "depth/depth.json"))


def depth_estimates(root: Path) -> str:
    d = _load(root, "depth/depth.json")
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
    return (_table(rows) + f"\nThe 90 % interval of the final depth covers the truth in that share of runs "
            f"(target >= {100 * d['target_coverage']:.0f} %); {d['runs']} runs per scenario and depth, levels from "
            f"{d['truth']}.\n\n" + _source(d, "depth/depth.json"))


def depth_mismatch(root: Path) -> str:
    d = _load(root, "depth/depth.json")
    m = d["level_residual_at_true_depth_db"]
    zs = [f"{z:g}" for z in d["true_depths_m"]]
    rows = [("scenario", *(f"{z} m" for z in zs)), ("---",) * (1 + len(zs))]
    for sc, by_z in m.items():
        rows.append((f"`{sc}`", *(f"{by_z[z]['along_track_sd_db']:.1f} ({by_z[z]['band_offset_sd_db']:.1f})"
                                  for z in zs)))
    return (_table(rows) + "\nThe levels less P0 + K + G, K the tables' at the true depth along the true track, "
            "each run's mean taken off: sd along the track, median over runs and bands (in brackets the sd of "
            "the bands' offsets from the run's common one), dB; eq. 11's error included.\n\n"
            + _source(d, "depth/depth.json"))


def depth_check(root: Path) -> str:
    d = _load(root, "depth/depth.json")
    c = d["tables_vs_bellhop_from_target_db"]
    zs = list(c["geometries"][0]["by_depth_m"])
    rows = [("observer (x, y), km", "bearing", *(f"{z} m" for z in zs), "median"), ("---",) * (3 + len(zs))]
    for g in c["geometries"]:
        by = g["by_depth_m"]
        rows.append((f"({g['observer_x_m'] / 1e3:g}, {g['observer_y_m'] / 1e3:g})", f"{g['bearing_deg']:g} deg",
                     *(f"{by[z]['common_sd_db']:.1f} / {by[z]['band_own_sd_db']:.1f}" for z in zs),
                     f"**{g['median_common_sd_db']:.1f} / {g['median_band_own_sd_db']:.1f}**"))
    f = c["fit"]
    return (_table(rows) + "\nK from BELLHOP run from the target less the tables' K read from the observer, targets "
            f"at {c['ranges_km'][0]:g}-{c['ranges_km'][1]:g} km every km on one bearing: the sd along range of the "
            "part common to the bands / of each band's own, dB. The likelihood's fine errors from it: "
            f"{f['fine_sd_db']:.1f} / {f['fine_band_sd_db']:.1f} dB where the tables were computed, growing by "
            f"{f['fine_growth_db_per_km']:.1f} / {f['fine_band_growth_db_per_km']:.2f} dB per km of the observer's "
            "distance from there (sd^2 = sd_0^2 + (g d)^2, least squares); the bands' offsets (their sd over the "
            f"bands, median {f['band_sd_db']:.2f} dB at the origin) by {f['band_growth_db_per_km']:.2f} dB per km, "
            "added to the class's 1 dB; the offset common to the bands (each depth's mean less the origin's on the "
            f"same bearing, RMS over the depths) by {f['offset_growth_db_per_km']:.2f} dB per km, added to the "
            "class's P0 and dK." + _check_correlation(c) + "\n\n" + _source(d, "depth/depth.json"))


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
    d = _load(root, "depth/depth.json")
    w = d["hypothesis_weights_mean"]["ml"]
    hyps = list(next(iter(next(iter(w.values())).values())))
    rows = [("scenario", "true depth, m", *(f"{float(h):.0f} m" for h in hyps)), ("---",) * (2 + len(hyps))]
    for sc, by_z in w.items():
        for z, v in by_z.items():
            rows.append((f"`{sc}`", z, *(f"{v[h]:.2f}" for h in hyps)))
    return (_table(rows) + "\nThe ML analysis's depth hypotheses' final weights, mean over runs.\n\n"
            + _source(d, "depth/depth.json"))


#: The Nx2D benchmark's configurations: name in the file -> (route, workers).
NX2D_ROUTES = {"2d_workers1": ("2-D per radial", 1), "2d_workers2": ("2-D per radial", 2),
               "nx2d_workers1": ("Nx2D", 1), "nx2d_workers2": ("Nx2D", 2), "nx2d_workers2_groups2": ("Nx2D", 2),
               "nx2d_cells_workers2_groups2": ("Nx2D, bottom on the file's cells", 2)}


def nx2d_times(root: Path) -> str:
    d = _load(root, "nx2d.json")
    rows = [("area", "route", "workers", "runs per frequency", "BELLHOP runs", "wall, s", "BELLHOP processes, s (sum)",
             "the repeats (wall, s)"), ("---",) * 8]
    for area, a in d["areas"].items():
        label = "flat" if area.endswith("-flat") else area
        fastest = min(t["wall_s"]["median"] for t in a["times_s"].values())
        for name, t in a["times_s"].items():
            route, workers = NX2D_ROUTES[name]
            if name == "nx2d_cells_workers2_groups2":
                route = f"Nx2D, bottom on {a['box_cells']['bathymetry_step_m']:.0f} m nodes"
            runs = int(t["runs"]["median"])
            if name.startswith("2d"):
                per = f"{a['bearings']} (1 radial each)"
                extra = runs - a["runs_2d"]
                shown = f"{runs} ({a['runs_2d']} fields, {extra} arrivals)" if extra else f"{runs}"
            else:
                groups = runs // a["frequencies"]
                per = f"{groups} ({a['bearings'] // groups} bearings{' each' if groups > 1 else ''})"
                shown = f"{runs}"
            wall = f"{t['wall_s']['median']:.1f}"
            rows.append((label, route, f"{workers}", per, shown,
                         f"**{wall}**" if t["wall_s"]["median"] == fastest else wall,
                         f"{t['bellhop_s']['median']:.1f}", ", ".join(f"{w:.1f}" for w in t["wall_s"]["runs"])))
    return _table(rows) + "\n" + _source(d, "nx2d.json")


def nx2d_bearings(root: Path) -> str:
    d = _load(root, "nx2d.json")
    a = d["areas"]["shelf-break"]
    step = a["box_cells"]["bathymetry_step_m"]
    rows = [("bearing, deg", "cells", "median, dB", "p90, dB", "max, dB", "median signed (Nx2D - 2-D), dB",
             f"bottom on {step:.0f} m nodes: median / p90, dB"), ("---",) * 7]
    for r, c in zip(a["agreement"]["per_bearing"], a["agreement_cells"]["per_bearing"]):
        rows.append((f"{r['bearing_deg']:g}", f"{r['cells']}", f"{r['median_db']:.3f}", f"{r['p90_db']:.2f}",
                     f"{r['max_db']:.1f}", f"{r['bias_db']:+.4f}", f"{c['median_db']:.2f} / {c['p90_db']:.2f}"))
    return _table(rows) + "\n" + _source(d, "nx2d.json")


def nx2d_attribution(root: Path) -> str:
    d = _load(root, "nx2d.json")
    att = d["areas"]["shelf-break"]["attribution"]
    bearings = att["bearings_deg"]
    rows = [("2-D run of the radial with ...", *(f"{b:g} deg: median / p90, dB" if i == 0 else f"{b:g} deg"
                                                 for i, b in enumerate(bearings))), ("---",) * (1 + len(bearings))]
    for key, label in (("as_built", "its own bottom and sound speed (as built)"),
                       ("facet_bottom", "BELLHOP3D's triangulated bottom"),
                       ("facet_bottom_box_speed", "the triangulated bottom and the box's sound speed")):
        rows.append((label, *(f"{r['median_db']:.3f} / {r['p90_db']:.2f}" for r in att[key])))
    return _table(rows) + "\n" + _source(d, "nx2d.json")


#: name -> the function that makes its block from the result files under a root.
TABLES: dict[str, Callable[[Path], str]] = {"grids": grids, "accuracy": accuracy, "startup": startup,
                                             "surface": surface, "surface-cost": surface_cost,
                                             "grids-check": grids_check, "models-areas": models_areas,
                                             "ram-crossover": ram_crossover, "surface-compare": surface_compare,
                                             "sensitivity-sets": sensitivity_sets,
                                             "sensitivity-ranges": sensitivity_ranges,
                                             "sensitivity-speed": sensitivity_speed, "reciprocity": reciprocity,
                                             "models-bench": models_bench, "manoeuvres": manoeuvres,
                                             "radials": radials, "stonesoup": stonesoup,
                                             "gm-experiments": gm_experiments,
                                             "shelf-rmse": shelf_rmse, "shelf-dk": shelf_dk,
                                             "depth-errors": depth_errors, "depth-estimates": depth_estimates,
                                             "depth-weights": depth_weights, "depth-mismatch": depth_mismatch,
                                             "depth-check": depth_check,
                                             "follow-rmse": follow_rmse, "follow-kerror": follow_kerror,
                                             "follow-manoeuvres": follow_manoeuvres, "follow-blend": follow_blend,
                                             "follow-level-range": follow_level_range,
                                             "follow-blend-ratio": follow_blend_ratio,
                                             "atlas-trackers-speed": atlas_trackers_speed,
                                             "kerror-sd": kerror_sd, "kerror-rmse": kerror_rmse,
                                             "nx2d-times": nx2d_times, "nx2d-bearings": nx2d_bearings,
                                             "nx2d-attribution": nx2d_attribution}
TABLES.update(PLANNING_TABLES)

#: Figures quoted in prose: (page, result file, the figure's keys in it, how the page prints it).
QUOTES: tuple[tuple[str, str, tuple[str, ...], str], ...] = (
    ("docs/depth.md", "depth.json", ("figures", "rpf_depth_state_throughput_ratio", "value"), "a ratio\nof **{:.2f}**"),
    ("docs/depth.md", "depth.json", ("figures", "depth_likelihood_range_scale_cost_ratio", "value"),
     "a ratio of {:.1f}"),
    ("docs/depth.md", "depth.json", ("figures", "track_depth_posterior_cpu_s_whole_water_column", "value"),
     "it costs {:.1f} s of CPU"),
    ("docs/atlas-tracking.md", "truth-bellhop.json", ("first", "seconds"), "{:.1f} s on 2 workers"),
    ("docs/atlas-tracking.md", "truth-bellhop.json", ("cached", "seconds"), "{:.1f} s again from the run"),
    *(("README.md", "gm-tv-30km/summary.json", ("steady_state", "TV", key), fmt) for key, fmt in (
        ("course_rms_deg", "| {:.1f} deg /"), ("speed_rms_mps", "/ {:.2f} m/s /"))),
    *(("README.md", "atlas.json", ("speed", key), fmt) for key, fmt in (
        ("tables", "{:d} tables"), ("runs", "({:d} runs"), ("per_run_ms", "{:.0f} ms each"),
        ("build_2_workers_s", "took {:.1f} s on 2 workers"), ("raw_serial_bellhop_s", "against {:.1f} s of raw"),
        ("two_workers_over_half_raw", "{:.2f} x half of it"), ("two_vs_one_worker", "{:.2f}x faster than 1 worker"),
        ("bellhop_2_workers_s", "({:.1f} s summed"), ("two_workers_over_half_their_own_bellhop", "{:.3f} x half"))),
    *(("README.md", "atlas.json", ("memory", key), fmt) for key, fmt in (
        ("small_peak_rss_mib", "{:.0f} MiB for"), ("small_tables", "for {:d} tables"),
        ("large_peak_rss_mib", "{:.0f} MiB for"), ("large_tables", "for {:d} (flat"))),
    *(("README.md", "atlas.json", ("store", key), fmt) for key, fmt in (
        ("open_s", "open {:.2f} s"), ("slab_read_ms_median", "slab read {:.1f} ms"),
        ("sample_10000_points_s", "sampled in {:.2f} s"), ("store_over_raw", "the store is {:.2f} of its raw"))),
    ("README.md", "icechunk.json", ("median_seconds_per_table", "icechunk"), "cost {:.3f} s"),
    ("README.md", "icechunk.json", ("median_seconds_per_table", "zarr"), "against {:.3f} s for the atlas's"),
    ("README.md", "icechunk.json", ("icechunk_over_zarr",), "({:.2f}x)"),
)


def stale_quotes(root: Path) -> list[str]:
    """The `QUOTES` whose printed value the page no longer holds, as ``page: file key (printed)``."""
    out, texts = [], {}
    for page, file, keys, fmt in QUOTES:
        text = texts.setdefault(page, (root / page).read_text())
        value = _load(root, file)
        for key in keys:
            value = value[key]
        printed = fmt.format(value)
        if " ".join(printed.split()) not in " ".join(text.split()):  # line breaks in prose are free
            out.append(f"{page}: {file} {'.'.join(keys)} ({printed!r})")
    return out


def _table(rows) -> str:
    return "".join("| " + " | ".join(row) + " |\n" for row in rows)


def pages(root: Path) -> list[Path]:
    return [p for pattern in PAGES for p in sorted(root.glob(pattern))]


def render(text: str, root: Path, where: str) -> tuple[str, list[str]]:
    """The page with every block made anew, and the names of the blocks that changed."""
    changed = []

    def one(m: re.Match) -> str:
        name = m["name"]
        if name not in TABLES:
            raise SystemExit(f"{where}: unknown docfigures block {name!r} (known: {', '.join(TABLES)})")
        body = TABLES[name](root)
        if body != m["body"]:
            changed.append(name)
        return m.group(1) + body + m.group(4)

    return BLOCK.sub(one, text), changed


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if a page differs")
    parser.add_argument("--root", type=Path, default=REPO, help="the checkout whose pages and results to use")
    args = parser.parse_args(argv)
    stale = []
    for page in pages(args.root):
        text = page.read_text()
        new, changed = render(text, args.root, str(page))
        stale += [f"{page.relative_to(args.root)}: {name}" for name in changed]
        if changed and not args.check:
            page.write_text(new)
    for line in stale:
        print(("differs from its result file: " if args.check else "rewrote ") + line)
    quotes = stale_quotes(args.root)
    for line in quotes:  # prose is the author's to rewrite: named, never changed
        print(f"quoted in prose, not what its result file gives: {line}")
    return 1 if (stale and args.check) or quotes else 0


if __name__ == "__main__":
    sys.exit(main())
