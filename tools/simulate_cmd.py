"""``tmakit simulate SCENARIO --grid FILE --out DIR [--seed N]`` (Grinenkov & Mashoshin sec. 4)."""

from __future__ import annotations

import argparse

from tools.outputs import Kind, check_output_dir, check_output_file
from tools.report import Report


def register(subparsers, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "simulate", parents=[common], help="simulate bearings and band levels of a scenario",
        description="Simulate a scenario (built-in name or TOML file) on a propagation grid: "
                    "writes DIR/measurements.csv and DIR/truth.csv.")
    p.add_argument("scenario", help="built-in scenario (gm-nps, gm-tv-110km, gm-tv-30km) or TOML")
    p.add_argument("--grid", required=True, metavar="FILE",
                   help="propagation grid (netCDF) or atlas (Zarr store: the tables follow the observer)")
    p.add_argument("--month", type=int, metavar="M", help="the atlas's month (needed when it has several)")
    p.add_argument("--truth", choices=("tables", "bellhop"), default="tables",
                   help="where the true levels come from: the tables (default), or BELLHOP along each "
                        "cycle's target-to-observer geodesic in the area's own water and bottom")
    p.add_argument("--workers", type=int, default=2, metavar="N", help="BELLHOP workers for --truth bellhop")
    p.add_argument("--scheduler", metavar="ADDR", help="a trusted Dask scheduler for --truth bellhop")
    p.add_argument("--out", required=True, metavar="DIR", help="output directory")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--force", action="store_true",
                   help="replace existing files in DIR even if they are not tmakit's CSVs")
    p.set_defaults(func=run_simulate)


def run_simulate(args) -> Report:
    import numpy as np

    from acoustics.grid.opentables import open_tables
    from tracker.scenario import load_scenario
    from tracker.simulate import simulate, write_simulation

    out = check_output_dir(args.out)
    check_output_file(out / "measurements.csv", Kind.MEASUREMENT_CSV, force=args.force)
    check_output_file(out / "truth.csv", Kind.TRUTH_CSV, force=args.force)
    sc = load_scenario(args.scenario)
    tables = open_tables(args.grid, month=args.month)
    provider = None
    if args.truth == "bellhop":
        from acoustics.builder.truthk import BellhopTruth

        provider = BellhopTruth.beside(tables.area, args.grid, cache_dir=out / ".truth-runs", workers=args.workers,
                                scheduler=args.scheduler)
    m, truth = simulate(sc, tables, np.random.default_rng(args.seed), k_provider=provider)
    files = write_simulation(args.out, m, truth)
    det = np.isfinite(m.level_db).mean(axis=0)
    summary = (f"simulated {sc.name}: {len(m)} cycles of {sc.cycle_s:g} s, class "
               f"{sc.target_class}; detected fraction per band "
               + ", ".join(f"{b} {f:.2f}" for b, f in zip(m.band_names, det))
               + f"\n  wrote {files['measurements']}, {files['truth']}")
    if provider is not None:
        summary += (f"\n  levels from {provider.stats.runs} BELLHOP runs along the true geodesics "
                    f"({provider.stats.cached} from the cache in {out / '.truth-runs'}), not from the tables")
    data = {"scenario": sc.name, "cycles": len(m), **files, "truth": args.truth,
            "detected_fraction": dict(zip(m.band_names, det.tolist()))}
    offset = tables.observer_offset(m.obs_x_m, m.obs_y_m)
    if offset is not None:
        summary += (f"\n  observer up to {offset.distance_m / 1000:.2f} km from the grid's origin "
                    f"({offset.origin_lat_deg:g} N, {offset.origin_lon_deg:g} E)")
        data["observer_max_distance_from_origin_m"] = offset.distance_m
    return Report(summary, data)
