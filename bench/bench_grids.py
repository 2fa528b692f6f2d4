"""Speed and memory of the propagation grids of the default area, and the naive loop they replace.

Run with ``make bench`` (or ``python -m bench.bench_grids``). Prints one line per figure, ``name:
value unit``, and writes docs/results/grids.json. ``grids build`` on 1 and 2 workers and the raw
BELLHOP runs on the same .env files are interleaved and repeated; the figures are medians
(ratios: medians of the side-by-side pairs). What the build's shortcuts cost in accuracy is
bench_accuracy.py. Takes about five minutes on 2 cores.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
from pathlib import Path

import envdata
from acoustics.bellhop.exe import find_bellhop
from acoustics.builder.plan import plan_runs, receiver_depths_m
from acoustics.kcurve import band_frequencies_hz
from bench.harness import Session, cli_with_rusage, median, raw_bellhop_seconds

session = Session("grids")

REPO = Path(__file__).resolve().parents[1]
REPEATS = 3  # timings interleaved and repeated; the figures are medians




def main() -> None:
    exe = find_bellhop().path
    area = envdata.load_area(envdata.DEFAULT_AREA)
    ncores = os.cpu_count() or 1
    session.say("cores", ncores)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "g.nc"
        # -- speed and memory of the default area ----------------------------------------------
        runs = plan_runs(area)
        w1, w2, raws, rss, own = [], [], [], [], []
        for _ in range(REPEATS):  # interleaved, so that a change of load hits all three alike
            wall1, rss1, report1 = cli_with_rusage(["grids", "build", area.name, "--out", str(out), "--workers",
                                                    "1", "--force"])
            own.append(wall1 - report1["bellhop_seconds"])
            wall2, rss2, _ = cli_with_rusage(["grids", "build", area.name, "--out", str(out), "--workers", "2",
                                              "--force"])
            w1.append(wall1)
            w2.append(wall2)
            raws.append(raw_bellhop_seconds(runs, exe))
            rss.append(max(rss1, rss2))
        wall1, wall2, raw = median(w1), median(w2), median(raws)
        session.say("repeats", REPEATS)
        session.say("ocean_deep_runs", len(runs), "BELLHOP runs")
        session.say("ocean_deep_build_1_worker", wall1, "s (median)", runs=w1)
        session.say("ocean_deep_build_2_workers", wall2, "s (median)", runs=w2)
        session.say("ocean_deep_raw_bellhop_sum", raw, "s (median)", runs=raws)
        session.say("overhead_build_over_raw_bellhop", median([a / b for a, b in zip(w1, raws)]),
            "ratio, median of pairs (target <= 1.10)")
        session.say("parallel_speedup_2_vs_1_workers", median([a / b for a, b in zip(w1, w2)]),
            "x, median of pairs (target >= 1.7)")
        session.say("ocean_deep_peak_rss", max(rss), "MiB (target < 1024)")
        # the command's fixed cost (start-up, writing the netCDF), the same on any number of workers
        session.say("ocean_deep_fixed_cost_w1_minus_raw", median([a - b for a, b in zip(w1, raws)]), "s")
        # the same from one process: the 1-worker command's wall time less its own BELLHOP runs'
        # (one at a time), free of the load's drift between the command and the raw runs
        session.say("ocean_deep_fixed_cost_w1_own", median(own), "s (median; target < 1)", runs=own)

    # -- the naive loop: classes x bands x frequencies at BELLHOP's automatic beam count ----------
    receivers = receiver_depths_m(area).size * area.grid.range_m().size
    ns_per = raw / (sum(r.n_beams for r in runs) * receivers) * 1e9
    session.say("bellhop_cost_per_beam_receiver", ns_per, "ns")
    c0 = area.water.ssp.speed_mps[0]

    def auto_beams(f):  # BELLHOP's choice for NBeams = 0 (angleMod): 0.3 r_max f / c0, at least 300
        return max(int(0.3 * area.grid.range_max_m * f / c0), 300)

    naive_beams = sum(auto_beams(f) for _ in area.classes for b in area.bands
                      for f in band_frequencies_hz(b, area.propagation.freqs_per_band))
    naive_s = naive_beams * receivers * ns_per * 1e-9
    # check the cost model on one real automatic-beam run (FB1 centre, the NPS depth)
    auto_area = dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, n_beams=0))
    probe = [r for r in plan_runs(auto_area) if r.source_depth_m == 200.0][0]
    probe_s = raw_bellhop_seconds([probe], exe)
    predicted = auto_beams(probe.freq_hz) * receivers * ns_per * 1e-9
    session.say("cost_model_check_auto_beam_run", probe_s / predicted, "measured/predicted")
    naive_runs = len(area.classes) * len(area.bands) * area.propagation.freqs_per_band
    session.say("naive_loop_estimate", naive_s, f"s ({naive_runs} runs at automatic beam counts)")
    session.say("speedup_over_naive_loop", naive_s / wall2, "x")


if __name__ == "__main__":
    main()
    session.write()
