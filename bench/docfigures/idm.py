"""docs/idm.md: the particle filter's speed and memory (bench/bench_rpf.py)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, figure, load_result, markdown_table

PAGE = "docs/idm.md"


def rpf_speed(root: Path) -> str:
    d = load_result(root, "rpf.json")

    def f(key: str) -> float:
        return figure(d, key)

    rows = [("figure", "measured", "target"), ("---",) * 3,
            ("one filter, 151 cycles / the first 31 cycles",
             f"{f('rpf_one_filter_n5000'):.1f} / {f('rpf_one_filter_n5000_first_31_cycles'):.1f} M particle-steps/s",
             ""),
            ("batched, 40 runs, 1 thread / 2 threads",
             f"{f('rpf_batched_40_runs_n5000'):.1f} / {f('rpf_batched_40_runs_n5000_2_threads'):.1f} M "
             f"particle-steps/s ({f('speedup_2_threads_vs_1_batched'):.2f}x)", ""),
            ("numpy reference, one filter / batched",
             f"{f('rpf_numpy_reference_one_filter_n5000'):.1f} / {f('rpf_numpy_reference_batched_40_runs_n5000'):.1f}"
             f" M particle-steps/s (the kernel {f('speedup_kernel_vs_numpy_one_filter'):.1f}x / "
             f"{f('speedup_kernel_vs_numpy_batched'):.1f}x)", ""),
            ("the `idm-static` study, 1000 runs x 151 cycles x 5000, bearings only and bearings + SPL, 2 worker "
             "processes", f"{f('idm_static_1000runs_151cycles_n5000_bot_and_spl_wall'):.0f} s wall "
             f"({f('idm_static_1000runs_rate'):.1f} M particle-steps/s), "
             f"{f('idm_static_1000runs_peak_memory_largest_process'):.2f} GiB peak per process", "3 min, 4 GiB"),
            ("the kernel's first call in a process (numba's cache loaded)",
             f"{f('rpf_kernel_first_call_incl_compile_or_cache_load'):.1f} s", "")]
    return (markdown_table(rows) + "\nThe share of cycles that resampled over the 151: the compiled kernel "
            f"{f('rpf_kernel_resampled_fraction_151_cycles'):.3f}, the numpy reference "
            f"{f('rpf_numpy_resampled_fraction_151_cycles'):.3f}; the kernel's over the first 31 cycles "
            f"{f('rpf_kernel_resampled_fraction_31_cycles'):.2f}.\n\n" + caption(d, "rpf.json"))


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"rpf-speed": rpf_speed}

#: Figures the page quotes in prose: none checked yet. The page's prose figures (the filters'
#: errors against the paper's, the CRLB's crossings) are its studies' and are being made again
#: with the level model's change; each is to be listed here as the page is rewritten.
QUOTES: tuple = ()
