"""The ML analysis's manoeuvre tests, the paper's (`tools.studies.gm.PAPER_PARAMS`) and the
default ones (`tracker.mltma.MLParams()`), on what each must do; written to
docs/results/maneuver.json:

- quick on a real turn: the Grinenkov & Mashoshin study of gm-tv-30km (the transport turns and
  speeds up at 20 min), both sets of tests on the same runs: the true class's RMS on each tack
  and the delay with which the turn is declared;
- quiet on a straight target: the follow study (docs/atlas-tracking.md; BELLHOP's levels along
  the true path, a target that never manoeuvres), rerun into docs/results/atlas-tracking/: the
  manoeuvres the ML analysis declares per run and its position RMSE.

    python -m bench.bench_maneuver [OCEAN_DEEP_GRID.nc] [--runs 1331] [--follow-runs 10]

Without a grid, the ocean-deep grid is built or reused in out/bench/. The follow study builds
its grid and atlases into docs/results/atlas-tracking/grids/ (reused).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time

from bench.harness import REPO, Session, bench_grid, command_line, provenance
from tools.studies import follow, gm
from tracker.mltma import MLParams

SCENARIO = "gm-tv-30km"
TESTS = {"paper": gm.PAPER_PARAMS, "default": MLParams()}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("grid", nargs="?", help="the ocean-deep grid (default: built or reused in out/bench/)")
    ap.add_argument("--runs", type=int, default=1331, help="gm runs, a cube (default 1331)")
    ap.add_argument("--follow-runs", type=int, default=10)
    args = ap.parse_args(argv)
    session = Session("maneuver")
    grid = args.grid or bench_grid("ocean-deep")
    n = round(args.runs ** (1.0 / 3.0))
    gm_out = {}
    for label, params in TESTS.items():
        with tempfile.TemporaryDirectory() as tmp:
            start = time.perf_counter()
            res = gm.run(SCENARIO, grid_path=grid, n=n, out_dir=tmp, seed=0, workers=2, params=params)
        gm_out[label] = res
        true = res["true_class"]
        for tack, figures in (("tack1", res["steady_state"][true]), ("tack2", res["later_tacks"][0][true])):
            session.say(f"gm_{label}_{tack}_course_rms", figures["course_rms_deg"], "deg")
            session.say(f"gm_{label}_{tack}_speed_rms", figures["speed_rms_mps"], "m/s")
            session.say(f"gm_{label}_{tack}_range_rms", figures["range_rms_m"], "m")
        turn = res["manoeuvres"][1]
        session.say(f"gm_{label}_turn_delay_mean", turn["delay_s"]["mean"] if turn["delay_s"] else float("nan"), "s")
        session.say(f"gm_{label}_turn_delay_max", turn["delay_s"]["max"] if turn["delay_s"] else float("nan"), "s")
        session.say(f"gm_{label}_turn_missed_runs", turn["missed_runs"], "runs")
        session.say(f"gm_{label}_false_per_run", sum(item["false_per_run"] for item in res["manoeuvres"]), "per run")
        session.say(f"gm_{label}_seconds", round(time.perf_counter() - start, 1), "s")
    for tack in ("tack1", "tack2"):
        for key in ("course_rms", "speed_rms", "range_rms"):
            ratio = (session.figures[f"gm_default_{tack}_{key}"]["value"]
                     / session.figures[f"gm_paper_{tack}_{key}"]["value"])
            session.say(f"gm_default_over_paper_{tack}_{key}", round(ratio, 4), "")
    out = REPO / "docs" / "results" / "atlas-tracking"
    start = time.perf_counter()
    res = follow.run(runs=args.follow_runs, out_dir=out, seed=0, workers=2)
    for name in follow.TABLES:
        for label in ("ml", "ml-paper"):
            key = f"{label}_{name}_bellhop"
            session.say(f"follow_{key}_manoeuvres_per_run", res["ml_manoeuvres_declared"][key]["mean_manoeuvres"],
                        "per run")
            session.say(f"follow_{key}_mean_rmse_after_10min", round(res["mean_rmse_after_10min_m"][key]), "m")
    session.say("follow_seconds", round(time.perf_counter() - start, 1), "s")
    # the study's own file gets this run's provenance (it quotes figures the pages cite)
    path = out / "follow.json"
    data = json.loads(path.read_text())
    data.pop("provenance", None)
    path.write_text(json.dumps({"provenance": provenance(command=command_line(), load_before=session.load_before,
                                                         git=session.git), **data}, indent=1) + "\n")
    session.write(scenario=SCENARIO, gm_runs=n ** 3, follow_runs=args.follow_runs,
                  follow_result=str((out / "follow.json").relative_to(REPO)),
                  gm_later_tacks={k: v["later_tacks"] for k, v in gm_out.items()},
                  gm_manoeuvres={k: v["manoeuvres"] for k, v in gm_out.items()})


if __name__ == "__main__":
    main()
