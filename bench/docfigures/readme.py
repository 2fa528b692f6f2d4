"""README.md: the grid build's speed and accuracy, the command line's start-up, the radials' build; the
figures its prose quotes (the G&M experiment, the atlas, icechunk, the particle filter and Stone Soup)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, figure, load_result, markdown_table, percent

PAGE = "README.md"


def grids(root: Path) -> str:
    d = load_result(root, "grids.json")
    w1, w2 = figure(d, "ocean_deep_build_1_worker"), figure(d, "ocean_deep_build_2_workers")
    raw = figure(d, "ocean_deep_raw_bellhop_sum")
    naive = figure(d, "naive_loop_estimate")
    rows = [
        ("figure", "measured", "target"), ("---", "---", "---"),
        (f"`grids build`, 2 workers ({figure(d, 'ocean_deep_runs')} BELLHOP runs)", f"{w2:.1f} s", "< 60 s"),
        ("`grids build`, 1 worker, over the sum of the raw BELLHOP runs on the same .env files",
         f"{figure(d, 'overhead_build_over_raw_bellhop'):.2f} ({w1:.1f} s / {raw:.1f} s)", "<= 1.10"),
        ("the command's fixed cost (start-up, writing the 12 MB netCDF), the same on any number of workers: "
         "1 worker less the raw sum", f"{figure(d, 'ocean_deep_fixed_cost_w1_minus_raw'):.1f} s", ""),
        *([("the same from one process: the 1-worker command's wall time less its own BELLHOP runs' "
            "(free of the load's drift between the command and the raw runs)",
            f"{figure(d, 'ocean_deep_fixed_cost_w1_own'):.1f} s", "< 1 s")]
          if "ocean_deep_fixed_cost_w1_own" in d["figures"] else []),
        ("2 workers vs 1", f"{figure(d, 'parallel_speedup_2_vs_1_workers'):.2f}x", ">= 1.7"),
        ("peak memory (largest process)", f"{figure(d, 'ocean_deep_peak_rss'):.0f} MiB", "< 1 GiB"),
        ("the naive loop (classes x bands x 7 frequencies at BELLHOP's automatic beam count), estimated from "
         f"BELLHOP's measured cost per beam and receiver ({figure(d, 'bellhop_cost_per_beam_receiver'):.2f} ns; a "
         f"real automatic-beam run took {figure(d, 'cost_model_check_auto_beam_run'):.2f} x the model's prediction)",
         f"about {naive:.0f} s ({naive / 60:.0f} min), {figure(d, 'speedup_over_naive_loop'):.0f}x slower",
         '"well over ten minutes"'),
    ]
    return markdown_table(rows) + "\n" + caption(d, "grids.json")


def accuracy(root: Path) -> str:
    d = load_result(root, "accuracy.json")

    def pair(key: str, digits: int = 2) -> tuple[str, str]:
        return (f"{figure(d, key + '_median'):#.{digits}g} dB", f"{figure(d, key + '_p95'):#.{digits}g} dB")

    beams = (250, 500, 1000, 3000)
    rec = [k for k in (d.get("figures") or d["results"]) if k.startswith("k_error_reciprocity_")
           and k.endswith("_median")]
    rows = [("shortcut", "median abs. error", "95th percentile"), ("---", "---", "---"),
            ("all of the default settings together", *pair("k_error_default_grid_vs_full")),
            ("fixed fan of 1500 beams (vs up to 72 000)", *pair("k_error_fixed_beam_fan_vs_full")),
            ("one run per band, other frequencies through absorption (a near-surface class's run: its "
             "surface pattern averaged over the band)", *pair("k_error_frequency_shortcut_vs_full")),
            (" / ".join(str(b) for b in beams) + " beams",
             " / ".join(f"{figure(d, f'k_error_{b}_beams_vs_full_median'):#.2g}" for b in beams) + " dB",
             " / ".join(f"{figure(d, f'k_error_{b}_beams_vs_full_p95'):#.2g}" for b in beams) + " dB")]
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
                     f"{figure(d, base + '_median'):#.2g} dB ({figure(d, inc + '_median'):#.2g} dB)",
                     f"{figure(d, base + '_p95'):#.2g} dB ({figure(d, inc + '_p95'):#.2g} dB)"))
    tl = "tl_field_error_default_vs_full_NPS_FB1"
    rows.append(("the whole TL field (NPS, FB1, where TL < 120 dB) with the default settings", *pair(tl)))
    return markdown_table(rows) + "\n" + caption(d, "accuracy.json")


def startup(root: Path) -> str:
    d = load_result(root, "startup.json")
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
    return markdown_table(rows) + "\n" + caption(d, "startup.json")


def radials(root: Path) -> str:
    d = load_result(root, "radials.json")

    def f(key: str) -> float:
        return figure(d, key)

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
            ("field and arrivals runs per radial: their mean BELLHOP time, one run alone", "",
             f"{f('wide_36_radials_field_run_mean_s'):.2f} s / {f('wide_36_radials_arrivals_run_mean_s'):.2f} s", "")]
    if "step_25m_vs_5m_k_median_abs_diff" in d["figures"]:   # not with --no-convergence
        rows.append(("K with the default 25 m ray step against 5 m, median / 95th percentile",
                     f"{f('step_25m_vs_5m_k_median_abs_diff'):.2f} / {f('step_25m_vs_5m_k_p95_abs_diff'):.2f} dB",
                     "", ""))
    return markdown_table(rows) + "\n" + caption(d, "radials.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"grids": grids, "accuracy": accuracy, "startup": startup, "radials": radials}

def _load_span(file: str, before: str, after: str) -> tuple:
    """The quotes of a file's load average at the start and at the end (their 1-minute values)."""
    return tuple((file, ("provenance", "load_average", when, 0), fmt) for when, fmt in (("before", before),
                                                                                       ("after", after)))


def _km(x: float) -> float:
    return x / 1000.0


def _ml_bins_behind_bearings_only(d: dict) -> str:
    """In which five-minute bins the ML analysis is further off than the bearings-only filter, as
    README says it: "every five-minute bin, with the model and with the one number" when in all."""
    worse = d["worse_than_bearings_only_bins"]
    n_bins = len(d["rmse_by_time_bin_m"]["bot"])
    if all(len(worse[k]) == n_bins for k in ("ml_model", "ml_scalar")):
        return "every five-minute bin, with the model and with the one number"
    return f"{len(worse['ml_model'])} of {n_bins} bins with the model, {len(worse['ml_scalar'])} with the one number"


#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("radials.json", ("figures", "western_med_bellhop_cpu_hours", "value"), "about {:,.0f}\nCPU hours of BELLHOP"),
    ("radials.json", ("figures", "western_med_build_cpu_hours", "value"), "and {:,.0f} with the builder's"),
    ("bottom.json", ("wide_36_radials", "every sample", "western_med_bellhop_cpu_hours"),
     "area: {:,.0f} CPU hours of BELLHOP since"),
    ("bottom.json", ("wide_36_radials", "1 m", "western_med_bellhop_cpu_hours"), "would take\n{:,.0f} CPU hours"),
    ("bottom.json", ("wide_36_radials", "1 m, step 50 m", "western_med_bellhop_cpu_hours"),
     "and {:,.0f} with the ray step at 50 m"),
    ("kerror/kerror.json", ("mean_rmse_after_5min_m", "rpf_model", _km),
     "closer than the one measured number\ndoes ({:.2f}"),
    ("kerror/kerror.json", ("mean_rmse_after_5min_m", "rpf_scalar", _km), "against {:.2f} km after 5 min"),
    ("kerror/kerror.json", ("calibration_after_late_min", "rpf_model", "range", "coverage_90", percent),
     "hold the truth in {:.0f} % of cycles"),
    ("kerror/kerror.json", ("calibration_after_late_min", "rpf_scalar", "range", "coverage_90", percent),
     "({:.0f} % with the one\nnumber)"),
    ("kerror/kerror.json", ("calibration_after_late_min", "ml_model", "range", "coverage_90", percent),
     "its intervals hold the truth in {:.0f} %"),
    ("kerror/kerror.json", (_ml_bins_behind_bearings_only,), "further off than the bearings-only\nfilter in {}"),
    *(("gm-tv-30km/summary.json", ("steady_state", "TV", key), fmt) for key, fmt in (
        ("course_rms_deg", "| {:.1f} deg /"), ("speed_rms_mps", "/ {:.2f} m/s /"))),
    *(("atlas.json", ("speed", key), fmt) for key, fmt in (
        ("tables", "{:d} tables"), ("runs", "({:d} runs"), ("per_run_ms", "{:.0f} ms each"),
        ("build_2_workers_s", "took {:.1f} s on 2 workers"), ("raw_serial_bellhop_s", "against {:.1f} s of raw"),
        ("two_workers_over_half_raw", "{:.2f} x half of it"), ("two_vs_one_worker", "{:.2f}x faster than 1 worker"),
        ("bellhop_2_workers_s", "({:.1f} s summed"), ("two_workers_over_half_their_own_bellhop", "{:.3f} x half"))),
    *(("atlas.json", ("memory", key), fmt) for key, fmt in (
        ("small_peak_rss_mib", "{:.0f} MiB for"), ("small_tables", "for {:d} tables"),
        ("large_peak_rss_mib", "{:.0f} MiB for"), ("large_tables", "for {:d} (flat"))),
    *(("atlas.json", ("store", key), fmt) for key, fmt in (
        ("open_s", "open {:.2f} s"), ("slab_read_ms_median", "slab read {:.1f} ms"),
        ("sample_10000_points_s", "sampled in {:.2f} s"), ("store_over_raw", "the store is {:.2f} of its raw"))),
    ("icechunk.json", ("median_seconds_per_table", "icechunk"), "cost {:.3f} s"),
    ("icechunk.json", ("median_seconds_per_table", "zarr"), "against {:.3f} s for the atlas's"),
    ("icechunk.json", ("icechunk_over_zarr",), "({:.2f}x)"),
    *(("rpf.json", ("figures", key, "value"), fmt) for key, fmt in (
        ("idm_static_1000runs_151cycles_n5000_bot_and_spl_wall", "bearings + SPL) {:.0f} s at"),
        ("idm_static_1000runs_peak_memory_largest_process", "{:.2f} GiB peak"))),
    *_load_span("rpf.json", "measured at load average {:.1f}-", "-{:.1f});"),
    *(("stonesoup.json", ("figures", key, "value"), fmt) for key, fmt in (
        ("speedup_one_filter_vs_stonesoup", "side by side in one run: {:.0f}x for one filter"),
        ("speedup_batched_vs_stonesoup", "{:.0f}x batched on one thread"),
        ("speedup_batched_2_threads_vs_stonesoup", "and {:.0f}x on two"))),
    *_load_span("stonesoup.json", "at load average {:.1f}-", "-{:.1f}; Stone Soup's own rate"),
    *(("gm.json", ("figures", key, "value"), fmt) for key, fmt in (
        ("ml_cycle_latency_3_classes_240_bearings", "3 class hypotheses and 240 bearings {:.1f} ms"),
        ("gm_experiment_1331_runs_2_workers", "the 1331-run G&M experiment {:.0f} s"))),
    *_load_span("gm.json", "at load average {:.1f}-", "-{:.1f}\non the 2 cores"),
    *(("sensitivity.json", ("figures", key, "value"), fmt) for key, fmt in (
        ("speedup_2_vs_1_workers", "is {:.2f}x faster on 2 local workers"), ("repeats", "{:d} interleaved\nrepeats"),
        ("overhead_1_worker_wall_over_bellhop_sum", "{:.1f} % overhead over\nthe BELLHOP time on 1 worker"),
        ("overhead_2_workers_wall_x2_over_bellhop_sum", "and {:.1f} % on 2"))),
    *_load_span("sensitivity.json", "at load average {:.1f}-", "-{:.1f}; 3 interleaved"),
)
