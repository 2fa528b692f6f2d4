"""Benchmark of a sensitivity study on a bearing-dependent area (issue 19).

A 16-member study of the built-in ``shelf-break`` area (12 radials x 3 bands to 30 km, the
default perturbations of an area with data: relief, water, bottom, depths) on 1 and then 2
local worker threads, interleaved and repeated (``--repeats``, default 3; medians). Targets: 2
workers at least 1.8x faster than 1; the wall time on 1 worker at most 10 % over the members'
BELLHOP time. Prints one line per figure and writes docs/results/sensitivity-shelf.json.
"""

from __future__ import annotations

import argparse
import os

import numpy as np

import envdata
from acoustics import sensitivity as sens
from bench.bench_sensitivity import MEMBERS, study
from bench.harness import Session, median

session = Session("sensitivity-shelf")



def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    area = envdata.load_area("shelf-break")
    session.say("cores", os.cpu_count() or 1)
    walls = {1: [], 2: []}
    bellhop = {1: [], 2: []}
    first = {}
    for _ in range(args.repeats):
        for workers in (1, 2):
            ds, stats, wall = study(area, workers)
            walls[workers].append(wall)
            bellhop[workers].append(stats.bellhop_seconds)
            first.setdefault(workers, ds)
    same = bool(np.array_equal(first[1]["k_db"].values, first[2]["k_db"].values, equal_nan=True))
    session.say("study_members", MEMBERS)
    session.say("repeats", args.repeats)
    session.say("runs_per_member", len(area.bearings.bearing_deg) * len(area.bands))
    session.say("study_1_worker_wall", median(walls[1]), "s (median)", runs=walls[1])
    session.say("study_1_worker_bellhop_sum", median(bellhop[1]), "s (median)", runs=bellhop[1])
    session.say("study_2_workers_wall", median(walls[2]), "s (median)", runs=walls[2])
    session.say("study_2_workers_bellhop_sum", median(bellhop[2]), "s (median)", runs=bellhop[2])
    session.say("speedup_2_vs_1_workers", median([a / b for a, b in zip(walls[1], walls[2])]), "x (median of pairs)")
    session.say("overhead_1_worker_wall_over_bellhop_sum",
        median([w / b - 1.0 for w, b in zip(walls[1], bellhop[1])]), "(median; target <= 0.10)")
    session.say("overhead_2_workers_wall_over_half_bellhop_sum",
        median([w / (0.5 * b) - 1.0 for w, b in zip(walls[2], bellhop[2])]), "(median; target <= 0.10)")
    session.say("results_identical_on_1_and_2_workers", same)
    summary = sens.summarize(sens.study_face(first[2]), eval_ranges_m=[5000.0, 10000.0, 20000.0])
    for cls_name, value in sens.k_error_by_class(summary).items():
        session.say(f"k_error_sd_db_{cls_name}", value, "dB")
    sd = summary["k_sd_db"]
    for b in summary["bearing"].values:
        session.say(f"k_sd_db_median_bearing_{b:g}", float(np.nanmedian(sd.sel(bearing=b))), "dB (all classes, bands)")
    session.write(area="shelf-break", members=MEMBERS)


if __name__ == "__main__":
    main()
