"""Benchmarks of the environmental sensitivity studies (issue 6).

Prints one line per figure, ``name: value unit``; the ratios are measured side by side in this
one run. A 16-member study of ``ocean-deep`` with the default perturbations on 1 and then 2
local worker threads (target: at least 1.7x), the overhead of the executor over the sum of
BELLHOP run times (target: at most 10 %), the measured K error per class and band, and the
accuracy of K by reciprocity against the direct K for the classes it serves (those beyond the
surface's reach: a near-surface class always runs directly, with the surface at its end). The
studies on 1 and 2 workers are interleaved and repeated (``--repeats``, default 3); the figures are medians. Writes
docs/results/sensitivity.json. Takes about ten minutes on 2 idle cores.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

import acoustics
import envdata
from acoustics import sensitivity as sens
from acoustics.builder.plan import near_surface
from acoustics.sensitivity.perturbspec import default_perturbations
from bench.harness import Session, median

session = Session("sensitivity")

MEMBERS = 16


def study(area, workers: int):
    """A study of the area's default perturbations on ``workers``: dataset, stats, wall time, s."""
    stats = sens.StudyStats()
    start = time.perf_counter()
    ds = sens.run_study(area, default_perturbations(area), members=MEMBERS, seed=0, workers=workers, stats=stats)
    return ds, stats, time.perf_counter() - start


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    area = envdata.load_area(envdata.DEFAULT_AREA)
    session.say("cores", os.cpu_count() or 1)

    # -- reciprocity vs direct K on the nominal area ---------------------------------------------
    s_direct, s_recip = acoustics.BuildStats(), acoustics.BuildStats()
    direct = acoustics.build_k(area, reciprocity_min_depth_m=math.inf, stats=s_direct).values
    recip = acoustics.build_k(area, reciprocity_min_depth_m=0.0, stats=s_recip).values
    t_direct, t_recip = s_direct.bellhop_seconds, s_recip.bellhop_seconds
    for ic, cls in enumerate(area.classes):
        if near_surface(area, cls):  # always direct (the surface at its end): bench_accuracy measures
            continue                 # its K from a table from the observer
        d = np.abs(recip[ic] - direct[ic]).ravel()
        session.say(f"reciprocity_vs_direct_{cls.name}_{cls.depth_m:g}m_median", float(np.median(d)), "dB")
        session.say(f"reciprocity_vs_direct_{cls.name}_{cls.depth_m:g}m_p95", float(np.percentile(d, 95)), "dB")
    session.say("k_bellhop_seconds_direct_all_classes", t_direct, "s")
    session.say("k_bellhop_seconds_reciprocity_all_classes", t_recip, "s")

    # -- 1 worker vs 2 workers, same study -----------------------------------------------------------
    walls = {1: [], 2: []}
    bellhop = {1: [], 2: []}
    same = True
    for _ in range(args.repeats):  # interleaved: a load change hits both alike
        for workers in (1, 2):
            ds, st, wall = study(area, workers)
            walls[workers].append(wall)
            bellhop[workers].append(st.bellhop_seconds)
            if workers == 1:
                ds1 = ds
            else:
                ds2 = ds
                same = same and bool(np.array_equal(ds1["k_db"].values, ds2["k_db"].values))
    wall1, wall2 = median(walls[1]), median(walls[2])
    session.say("study_members", MEMBERS)
    session.say("repeats", args.repeats)
    session.say("study_1_worker_wall", wall1, "s (median)", runs=walls[1])
    session.say("study_1_worker_bellhop_sum", median(bellhop[1]), "s (median)", runs=bellhop[1])
    session.say("study_2_workers_wall", wall2, "s (median)", runs=walls[2])
    session.say("study_2_workers_bellhop_sum", median(bellhop[2]), "s (median)", runs=bellhop[2])
    session.say("speedup_2_vs_1_workers", median([a / b for a, b in zip(walls[1], walls[2])]), "x (median of pairs)")
    session.say("overhead_1_worker_wall_over_bellhop_sum",
        median([100.0 * (w / b - 1.0) for w, b in zip(walls[1], bellhop[1])]), "%")
    session.say("overhead_2_workers_wall_x2_over_bellhop_sum",
        median([100.0 * (2.0 * w / b - 1.0) for w, b in zip(walls[2], bellhop[2])]), "%")
    session.say("results_identical_1_vs_2_workers", same)

    # -- what the study measures -------------------------------------------------------------------
    summary = sens.summarize(sens.study_face(ds2))
    for cls_name in summary["class"].values:
        for band in summary["band"].values:
            sel = {"class": cls_name, "band": band}
            session.say(f"k_rms_error_{cls_name}_{band}", float(summary["k_rms_error_db"].sel(sel)), "dB")
            session.say(f"k_offset_sd_{cls_name}_{band}", float(summary["k_offset_sd_db"].sel(sel)), "dB")
            session.say(f"k_constant_fraction_{cls_name}_{band}", float(summary["k_constant_fraction"].sel(sel)))
        session.say(f"k_error_sd_measured_{cls_name}", float(summary["k_error_sd_db"].sel({"class": cls_name})), "dB")


if __name__ == "__main__":
    main()
    session.write()
