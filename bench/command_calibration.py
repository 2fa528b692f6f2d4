"""Whether the sds that ``tmakit track --method rpf|rpf-vp|rpf-bot`` writes hold the truth: the
command's particle filters, with the settings the command gives them
(`tracker.rpf.track.command_config`), on runs whose levels BELLHOP made along each true path.

    python -m bench.command_calibration [--shelf docs/results/shelf] [--depth docs/results/depth]

Sets of runs, each a study's own (its seeds, grid and BELLHOP truth, read from the study's output
folder, built there if missing). The command's settings were chosen on the first three ("tuned":
true in the file); the others were not looked at while choosing them ("tuned": false):

- the shelf study's transport (``shelf-tv``: a TV class target 20 km off, its speed, P0 and dK
  drawn from the class), runs 1-``--shelf-runs`` (tuned) and the rest of its 100 (held out);
- the depth study's submarine at its tables' depth (``shelf-nps`` and ``shelf-slope-nps`` at
  200 m, 12 runs each: `bench.depth_diagnosis.simulate`; tuned), and at 60 m with the tables at
  60 m, as ``--target-depth 60`` gives them (held out).

Each run's measurements go through `tracker.rpf.track.track_measurements` as the command sends
them (the true class's hypothesis, the first band's levels, seed = the run's index). Reported per
set and method: the share of cycles after 10 min whose 90 % range interval (range +- 1.645
range_sd) holds the true range, the median |error| / sd, and the median over runs of the RMS
position error after 5 min. Writes docs/results/command-calibration.json.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from bench.harness import REPO, Session

METHODS = ("rpf", "rpf-vp", "rpf-bot")
CALIBRATION_MIN = 10.0
LATE_MIN = 5.0


def shelf_runs(folder: Path, runs: int, workers: int):
    """The shelf study's tables, its simulated runs (all of them: the draws depend on the count)
    and the class name."""
    from acoustics.builder.gridfile import build_grid_file
    from acoustics.builder.truthk import BellhopTruth
    from acoustics.grid.opentables import open_tables
    from envdata.areafile import load_area
    from tools.studies.calibration import class_draws
    from tools.studies.shelf import AREA, SCENARIO
    from tracker.scenario import load_scenario
    from tracker.simulate import simulate_batch

    area = load_area(AREA)
    tables = open_tables(build_grid_file(area, folder / "grids" / f"{AREA}-bellhop.nc", workers=workers).file)
    sc = load_scenario(SCENARIO)
    ic = tables.class_index(sc.target_class)
    rng = np.random.default_rng(0)  # the study's seed
    sim = simulate_batch(sc, tables, rng, **class_draws(sc, tables.classes[ic], runs, rng),
                         k_provider=BellhopTruth(area, cache_dir=folder / "grids" / "truth-runs", workers=workers))
    return tables, sim, sc.target_class


def score(tables, sim, cls_name: str, method: str, runs) -> dict:
    """The command's filter on the runs ``runs`` (indices): coverage, median |z|, median RMSE."""
    from tracker.rpf.track import track_measurements
    from tracker.simulate import measurements_of

    minutes = (sim.t_s - sim.t_s[0]) / 60.0
    inside, z_all, rms = [], [], []
    runs = list(runs)
    for run in runs:
        df = track_measurements(tables, measurements_of(sim, run), method=method,
                                rng=np.random.default_rng(run), cls_name=cls_name)
        rows = np.searchsorted(sim.t_s, df["t_s"].to_numpy())
        t_min = minutes[rows]
        with np.errstate(invalid="ignore", divide="ignore"):
            z = np.abs(df["range_m"].to_numpy() - sim.range_m[run, rows]) / df["range_sd_m"].to_numpy()
        z = z[(t_min >= CALIBRATION_MIN) & np.isfinite(z)]
        inside.append(z <= 1.645)
        z_all.append(z)
        err = np.hypot(df["x_m"].to_numpy() - sim.x_m[run, rows], df["y_m"].to_numpy() - sim.y_m[run, rows])
        rms.append(float(np.sqrt(np.nanmean(err[t_min >= LATE_MIN] ** 2))))
    return {"coverage_90": float(np.mean(np.concatenate(inside))),
            "abs_z_median": float(np.median(np.concatenate(z_all))),
            "rms_error_median_m": float(np.median(rms)), "runs": len(runs)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.command_calibration", description=__doc__.split("\n\n")[0])
    parser.add_argument("--shelf", default=str(REPO / "docs" / "results" / "shelf"),
                        help="the shelf study's output folder (its grids/ and truth runs are reused)")
    parser.add_argument("--depth", default=str(REPO / "docs" / "results" / "depth"),
                        help="the depth study's output folder")
    parser.add_argument("--shelf-runs", type=int, default=30, help="runs of the shelf study's 100 tracked")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)

    from acoustics.builder.gridfile import build_grid_file
    from acoustics.builder.truthk import BellhopTruth
    from acoustics.grid.opentables import open_tables
    from bench.depth_diagnosis import simulate
    from envdata.areafile import load_area
    from tools.studies.depth_setup import AREA as DEPTH_AREA

    session = Session("command-calibration")
    sets = {}  # name: (tables, runs, class, run indices, tuned)
    tables, sim, cls = shelf_runs(Path(args.shelf), 100, args.workers)
    sets["shelf-tv"] = (tables, sim, cls, range(args.shelf_runs), True)
    sets[f"shelf-tv, runs {args.shelf_runs + 1}-100"] = (tables, sim, cls, range(args.shelf_runs, 100), False)
    depth = Path(args.depth)
    area = load_area(DEPTH_AREA)
    grid = build_grid_file(area, depth / "grids" / f"{DEPTH_AREA}-bellhop.nc", workers=args.workers).file
    d_tables = open_tables(grid)
    provider = BellhopTruth(area, cache_dir=depth / "grids" / "truth-runs", workers=args.workers)
    for true_depth, tuned in ((200.0, True), (60.0, False)):
        for scenario in ("shelf-nps", "shelf-slope-nps"):
            d_sim, ic, _ = simulate(d_tables, provider, scenario, true_depth, 12)
            # the tables at the true depth, as --target-depth METRES gives them
            view = d_tables if true_depth == d_tables.classes[ic].depth_m else d_tables.at_target_depth(true_depth)
            sets[f"{scenario} at {true_depth:g} m"] = (view, d_sim, d_tables.classes[ic].name, range(12), tuned)
    results = {}
    for name, (tab, s, cls_name, runs, tuned) in sets.items():
        first = list(runs)
        results[name] = {"tuned": tuned, "true_first_range_m": float(np.median(s.range_m[first, 0])),
                         "true_speed_mps": float(np.median(s.speed_mps[first, 0]))}
        for method in METHODS:
            got = score(tab, s, cls_name, method, runs)
            results[name][method] = got
            session.say(f"{name} {method} coverage_90", got["coverage_90"])
    from tracker.rpf.track import COMMAND_BANDWIDTH_SCALE, COMMAND_PARTICLES, NEAR_RANGE_M

    session.write(methods=list(METHODS), sets=results,
                  settings={"range_prior": "log-uniform", "near_range_m": NEAR_RANGE_M, "far_range": "the grid's last",
                            "particles": COMMAND_PARTICLES, "bandwidth_scale": COMMAND_BANDWIDTH_SCALE,
                            "speed": "class"})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
