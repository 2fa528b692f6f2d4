"""docs/stonesoup.md: Stone Soup's particle filter beside tmakit's, how well and how fast
(bench/bench_stonesoup.py)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, figure, load_result, markdown_table

PAGE = "docs/stonesoup.md"


def stonesoup(root: Path) -> str:
    d = load_result(root, "stonesoup.json")
    entries = d["accuracy"]["by_particles"]
    first = entries[0]
    seeds = [str(s) for s in first["seeds"]]
    rows = [("filter", "particles", f"final position error, median of {first['pooled']['runs']} runs ({len(seeds)} "
             f"seeds x {first['runs_per_seed']})", "over tmakit's: all runs (seed " + ", ".join(seeds) + ")",
             "time per run (median)"), ("---",) * 5]
    for a in entries:
        rpf = a["pooled"]["rpf"]
        rows.append(("**tmakit track --method rpf**", f"{rpf['particles']}",
                     f"{rpf['final_error_median_m']:.0f} m", "1", f"{rpf['seconds_median']:.3f} s"))
        for s in a["pooled"]["stonesoup"]:
            per = ", ".join(_ratio(x["over_rpf"]) for sd in seeds for x in a["by_seed"][sd]["stonesoup"]
                            if x["particles"] == s["particles"])
            lost = s.get("collapsed_runs", 0)
            error = ("more than half collapsed" if s["final_error_median_m"] is None
                     else f"{s['final_error_median_m']:.0f} m")
            if lost:
                error += f" ({lost} run{'s' if lost > 1 else ''} collapsed)"
            rows.append(("Stone Soup SIR + MCMC regulariser, tmakit's model", f"{s['particles']} "
                         f"({s['multiple']:g}x)", error,
                         f"{_ratio(s['over_rpf'])} ({per})", f"{s['seconds_median']:.2f} s"))
    return (markdown_table(rows) + "\nA run whose Stone Soup cloud collapsed (fewer distinct particles than the state "
            "has dimensions: its regulariser's kernel covariance is singular and it stops) counts as its largest "
            "error.\n\n" + caption(d, "stonesoup.json"))


def _ratio(value) -> str:
    return "-" if value is None else f"{value:.2f}x"


def stonesoup_speed(root: Path) -> str:
    d = load_result(root, "stonesoup.json")

    def f(key: str) -> float:
        return figure(d, key)

    rows = [("figure", "measured", "target"), ("---",) * 3,
            ("Stone Soup's particle filter, the first 30 cycles", f"{f('stonesoup_particle_filter_n5000'):.2f} M "
             "particle-steps/s", ""),
            ("tmakit's filter, one run: 151 cycles / the first 31",
             f"{f('rpf_one_filter_n5000'):.1f} / {f('rpf_one_filter_n5000_first_31_cycles'):.1f} M particle-steps/s",
             ""),
            ("tmakit's filter, batched 40 runs: 1 thread / 2 threads",
             f"{f('rpf_batched_40_runs_n5000'):.1f} / {f('rpf_batched_40_runs_n5000_2_threads'):.1f} M "
             "particle-steps/s", ""),
            ("one filter against Stone Soup", f"**{f('speedup_one_filter_vs_stonesoup'):.0f}x** "
             f"({f('speedup_one_filter_same_cycles_vs_stonesoup'):.0f}x on the same first cycles)", ">= 10x"),
            ("batched against Stone Soup, 1 thread / 2 threads", f"**{f('speedup_batched_vs_stonesoup'):.0f}x / "
             f"{f('speedup_batched_2_threads_vs_stonesoup'):.0f}x**", ">= 50x"),
            ("share of the timed cycles that resampled, Stone Soup / tmakit",
             f"{f('stonesoup_resampled_fraction_first_30_cycles'):.2f} / "
             f"{f('rpf_resampled_fraction_first_31_cycles'):.2f}", "")]
    return markdown_table(rows) + "\n" + caption(d, "stonesoup.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"stonesoup": stonesoup, "stonesoup-speed": stonesoup_speed}

#: Figures the page quotes in prose: none outside its two tables (the prose's 8x and 2x are the
#: test's particle multiple and bound, which tests/tracker/stonesoup/test_stonesoup.py checks
#: against the file).
QUOTES: tuple = ()
