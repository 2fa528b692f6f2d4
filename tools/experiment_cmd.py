"""``tmakit experiment gm|idm|shelf SCENARIO [--runs N] --out DIR [--seed N] [--workers N]
[--level-sigma-db DB] [--manoeuvre-tests paper|default]``."""

from __future__ import annotations

import argparse
from pathlib import Path

from envdata.errors import InputError
from envdata.limits import check_memory
from tools.outputs import check_output_dir
from tools.report import Report, want_progress


def register(subparsers, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "experiment", parents=[common], help="the papers' Monte Carlo studies",
        description="gm: the 11 x 11 x 11 design of Grinenkov & Mashoshin (eqs. 32-34); "
                    "idm: the Iglesis & de Montella scenarios; shelf: tracking in the shelf-break "
                    "area with its bearing-dependent grid and with the origin's column over a "
                    "flat bottom (docs/shelf.md); depth: a submarine off its class's table depth, "
                    "tracked with the class's depth, the true depth and the depth unknown (docs/depth.md); "
                    "follow: an atlas following the observer against one grid (docs/atlas-tracking.md); "
                    "kerror: tracking with the K error a sensitivity study measured (docs/sensitivity.md).")
    p.add_argument("study", choices=("gm", "idm", "shelf", "depth", "follow", "kerror"))
    p.add_argument("scenario", help="scenario name or TOML file")
    p.add_argument("--runs", type=int, default=None,
                   help="gm: number of runs n^3 (default 1331 = 11^3); idm: runs (1000); "
                        "shelf: runs (100); depth: runs (24); follow: runs (10); kerror: runs (48)")
    p.add_argument("--grid", metavar="FILE",
                   help="propagation grid of the scenario's area (idm: built from munk-1000 if not given; "
                        "kerror: the area's bearing-dependent grid)")
    p.add_argument("--study", dest="sensitivity_study", metavar="FILE",
                   help="kerror: the sensitivity study file (tmakit sensitivity)")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--level-sigma-db", type=float, default=None, metavar="DB",
                   help="idm: sigma_l of the filters' SPL likelihood (default the paper's 10 dB; "
                        "the data have 4 dB)")
    p.add_argument("--truth", choices=("bellhop", "tables"), default=None,
                   help="shelf, depth: the levels from BELLHOP along the true paths (the default) or "
                        "from the study's own grid")
    p.add_argument("--manoeuvre-tests", choices=("paper", "default"), default=None,
                   help="gm: the ML analysis's manoeuvre tests, the paper's eqs. 26-29 as written "
                        "(the default of the experiment) or those of tmakit track")
    p.set_defaults(func=run_experiment)


#: Most Monte Carlo runs a study takes (a larger number is a typing mistake).
MAX_RUNS = 1_000_000


def _check_runs(runs: int, cycles: int, bytes_per_run_cycle: float, what: str) -> None:
    """Refuse a run count out of range, or one whose arrays would not fit the machine."""
    if not 1 <= runs <= MAX_RUNS:
        raise InputError(f"--runs: must be in [1, {MAX_RUNS}], got {runs}")
    check_memory(runs * cycles * bytes_per_run_cycle, f"{what}: {runs} runs of {cycles} cycles")


def _self_built_study_runs(args, study, default_runs: int, bytes_per_run_cycle: float, builds: str) -> int:
    """The runs of a study that builds its own tables (depth, follow, shelf), after refusing the
    options it does not take and another scenario than its own."""
    from tracker.scenario import load_scenario

    if args.level_sigma_db is not None or args.grid is not None:
        raise InputError(f"--level-sigma-db, --grid: the {args.study} study builds {builds}")
    if args.manoeuvre_tests is not None:
        raise InputError(f"--manoeuvre-tests: only the gm study has it, not {args.study}")
    if args.truth is not None and args.study not in ("shelf", "depth"):
        raise InputError(f"--truth: only the shelf and depth studies have it, not {args.study}")
    if args.scenario != study.SCENARIO:
        raise InputError(f"{args.study}: the study is written for scenario {study.SCENARIO!r}, got "
                         f"{args.scenario!r}")
    runs = default_runs if args.runs is None else args.runs
    _check_runs(runs, load_scenario(study.SCENARIO).times_s().size, bytes_per_run_cycle, args.study)
    return runs


#: The studies that build their own tables and report a summary: their default runs, the memory
#: a run needs per cycle (bytes) and what they build, for `_self_built_study_runs`' checks.
_SELF_BUILT = {"depth": (24, 8.0 * 60, "its own grid"), "shelf": (100, 8.0 * 40, "its own two grids")}


def run_experiment(args) -> Report:
    if args.workers < 1:
        raise InputError(f"--workers: must be >= 1, got {args.workers}")
    check_output_dir(args.out)
    if args.study != "kerror" and args.sensitivity_study is not None:
        raise InputError(f"--study: only the kerror study reads a sensitivity study, not {args.study}")
    if args.study == "kerror":
        return _run_kerror(args)
    if args.study in _SELF_BUILT:
        import importlib

        study = importlib.import_module(f"tools.studies.{args.study}")
        runs = _self_built_study_runs(args, study, *_SELF_BUILT[args.study])
        res = study.run(runs=runs, out_dir=args.out, seed=args.seed, workers=args.workers,
                        progress=want_progress(args), truth=args.truth or "bellhop")
        return Report(res["summary"], res)
    if args.study == "follow":
        from tools.studies import follow

        runs = _self_built_study_runs(args, follow, 10, 8.0 * 80, "its own grid and atlases")
        res = follow.run(runs=runs, out_dir=args.out, seed=args.seed, workers=args.workers)
        text = (f"follow study: {runs} runs of {res['scenario']}; mean position RMSE after 10 min, m:\n" +
                "\n".join(f"  {k:>28}: {v:8.0f}" for k, v in res["mean_rmse_after_10min_m"].items()))
        return Report(text, res)
    if args.study == "idm":
        from tools.studies import idm as idm_experiment

        if args.manoeuvre_tests is not None:
            raise InputError("--manoeuvre-tests: only the gm study has it, not idm")
        if args.level_sigma_db is not None:  # before a grid is built
            idm_experiment.check_level_sigma(args.level_sigma_db)
        runs = 1000 if args.runs is None else args.runs
        # per run and cycle: measurements, and each filter's estimates (the chunks bound the rest)
        _check_runs(runs, idm_experiment.get_scenario(args.scenario).t_s.size, 8.0 * 40, "idm")
        grid = args.grid
        if grid is None:  # build (or reuse) the appendix environment's grid beside the results
            from acoustics.builder.gridfile import build_grid_file as build_file

            grid = build_file(idm_experiment.AREA, Path(args.out) / f"{idm_experiment.AREA}.nc",
                              workers=args.workers, progress=want_progress(args)).file
        res = idm_experiment.run(args.scenario, runs=runs,
                                 out_dir=Path(args.out), seed=args.seed, progress=want_progress(args),
                                 workers=args.workers, grid=grid,
                                 level_sigma_db=(idm_experiment.PAPER_LEVEL_SIGMA_DB
                                                 if args.level_sigma_db is None
                                                 else args.level_sigma_db))
        return Report(res.get("summary", ""), res)
    from tools.studies import gm as gm_experiment

    if args.level_sigma_db is not None:
        raise InputError("--level-sigma-db: only the idm study has it (the gm tracker takes "
                         "its level sd from the SNR, eq. 11)")

    runs = 1331 if args.runs is None else args.runs
    n = round(runs ** (1.0 / 3.0))
    if runs < 1 or n ** 3 != runs:
        raise InputError(f"--runs: must be a cube n^3 (e.g. 27, 125, 1331), got {runs}")
    from tracker.scenario import load_scenario

    # per run and cycle: squared errors and estimates of course, speed and range per class
    _check_runs(runs, load_scenario(args.scenario).times_s().size, 8.0 * 6 * 3 * 4, "gm")
    if args.grid is None:
        raise InputError("--grid: the gm experiment needs the propagation grid of the "
                         "scenario's area (tmakit grids build ocean-deep)")
    from tracker.mltma import MLParams

    params = MLParams() if args.manoeuvre_tests == "default" else gm_experiment.PAPER_PARAMS
    res = gm_experiment.run(args.scenario, grid_path=args.grid, n=n, out_dir=args.out,
                            seed=args.seed, workers=args.workers, progress=want_progress(args),
                            params=params)
    res["manoeuvre_tests"] = args.manoeuvre_tests or "paper"
    return Report(res["summary"], res)


def _run_kerror(args) -> Report:
    from tools.studies import kerror

    if args.level_sigma_db is not None:
        raise InputError("--level-sigma-db: the kerror study takes sigma_l from eq. 11 and the K error")
    if args.grid is None or args.sensitivity_study is None:
        raise InputError("--grid, --study: the kerror study needs the area's bearing-dependent grid and a "
                         "sensitivity study's file (tmakit sensitivity shelf-break --out STUDY)")
    if args.scenario != kerror.SCENARIO:
        raise InputError(f"kerror: the study is written for scenario {kerror.SCENARIO!r}, got {args.scenario!r}")
    from tracker.scenario import load_scenario

    runs = 48 if args.runs is None else args.runs
    _check_runs(runs, load_scenario(kerror.SCENARIO).times_s().size, 8.0 * 40, "kerror")
    res = kerror.run(grid=args.grid, study=args.sensitivity_study, out_dir=args.out, runs=runs, seed=args.seed)
    text = (f"kerror study: {runs} runs of {res['scenario']}; mean position RMSE after 5 min, m:\n" +
            "\n".join(f"  {k:>12}: {v:8.0f}" for k, v in res["mean_rmse_after_5min_m"].items()))
    return Report(text, res)
