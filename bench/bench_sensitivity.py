"""Benchmarks of the environmental sensitivity studies (issue 6).

Prints one line per figure, ``name: value unit``; the ratios are measured side by side in this
one run. A 16-member study of ``ocean-deep`` with the default perturbations on 1 and then 2
local worker threads (target: at least 1.7x), the overhead of the executor over the sum of
BELLHOP run times (target: at most 10 %), the measured K error per class and band, and the
accuracy of K by reciprocity against the direct K. Takes about three minutes on 2 idle cores.
"""

from __future__ import annotations

import os
import time

import numpy as np

import envdata
from acoustics import sensitivity as sens
from acoustics.sensitivity.perturb import default_perturbations

MEMBERS = 16


def say(name: str, value, unit: str = "") -> None:
    text = f"{value:.4g}" if isinstance(value, float) else str(value)
    print(f"{name}: {text} {unit}".rstrip(), flush=True)


def study(area, workers: int):
    stats = sens.StudyStats()
    start = time.perf_counter()
    ds = sens.run_study(area, default_perturbations(area), members=MEMBERS, seed=0, workers=workers, stats=stats)
    return ds, stats, time.perf_counter() - start


def main() -> None:
    area = envdata.load_area(envdata.DEFAULT_AREA)
    say("cores", os.cpu_count() or 1)
    say("load_average_1min_at_start", os.getloadavg()[0])

    # -- reciprocity vs direct K on the nominal area ---------------------------------------------
    direct, t_direct = sens.compute_k(area, reciprocity_min_depth_m=1e9)
    recip, t_recip = sens.compute_k(area, reciprocity_min_depth_m=0.0)
    for ic, cls in enumerate(area.classes):
        d = np.abs(recip[ic] - direct[ic]).ravel()
        say(f"reciprocity_vs_direct_{cls.name}_{cls.depth_m:g}m_median", float(np.median(d)), "dB")
        say(f"reciprocity_vs_direct_{cls.name}_{cls.depth_m:g}m_p95", float(np.percentile(d, 95)), "dB")
    say("k_bellhop_seconds_direct_all_classes", t_direct, "s")
    say("k_bellhop_seconds_reciprocity_all_classes", t_recip, "s")

    # -- 1 worker vs 2 workers, same study -----------------------------------------------------------
    ds1, st1, wall1 = study(area, 1)
    ds2, st2, wall2 = study(area, 2)
    same = bool(np.array_equal(ds1["k_db"].values, ds2["k_db"].values))
    say("study_members", MEMBERS)
    say("study_1_worker_wall", wall1, "s")
    say("study_1_worker_bellhop_sum", st1.bellhop_seconds, "s")
    say("study_2_workers_wall", wall2, "s")
    say("study_2_workers_bellhop_sum", st2.bellhop_seconds, "s")
    say("speedup_2_vs_1_workers", wall1 / wall2, "x")
    say("overhead_1_worker_wall_over_bellhop_sum", 100.0 * (wall1 / st1.bellhop_seconds - 1.0), "%")
    say("overhead_2_workers_wall_x2_over_bellhop_sum", 100.0 * (2.0 * wall2 / st2.bellhop_seconds - 1.0), "%")
    say("results_identical_1_vs_2_workers", same)
    say("load_average_1min_at_end", os.getloadavg()[0])

    # -- what the study measures -------------------------------------------------------------------
    summary = sens.summarize(ds2)
    for cls_name in summary["class"].values:
        for band in summary["band"].values:
            sel = {"class": cls_name, "band": band}
            say(f"k_rms_error_{cls_name}_{band}", float(summary["k_rms_error_db"].sel(sel)), "dB")
            say(f"k_offset_sd_{cls_name}_{band}", float(summary["k_offset_sd_db"].sel(sel)), "dB")
            say(f"k_constant_fraction_{cls_name}_{band}", float(summary["k_constant_fraction"].sel(sel)))
        say(f"k_error_sd_measured_{cls_name}", float(summary["k_error_sd_db"].sel({"class": cls_name})), "dB")


if __name__ == "__main__":
    main()
