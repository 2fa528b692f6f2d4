"""``tmakit track --grid FILE --measurements CSV --out CSV [--method ml|rpf|rpf-bot]``."""

from __future__ import annotations

import argparse
import math

from envdata.errors import InputError
from envdata.files import atomic_paths
from tools.outputs import Kind, check_output_file
from tools.report import Report
from tracker.methods import Method


def register(subparsers, common: argparse.ArgumentParser) -> None:
    p = subparsers.add_parser(
        "track", parents=[common], help="track a target from a measurement CSV",
        description="Estimate course, speed and range every cycle for every class hypothesis: "
                    "ml (Grinenkov & Mashoshin), rpf / rpf-bot (particle filters).")
    p.add_argument("--grid", required=True, metavar="FILE",
                   help="propagation grid (netCDF) or atlas (Zarr store: the tables follow the observer)")
    p.add_argument("--month", type=int, metavar="M", help="the atlas's month (needed when it has several)")
    p.add_argument("--measurements", required=True, metavar="CSV", help="measurement CSV")
    p.add_argument("--out", required=True, metavar="CSV", help="track CSV to write")
    p.add_argument("--method", choices=[m.value for m in Method], default=Method.ML.value,
                   help="tracker (default ml)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the particle filters")
    p.add_argument("--class", dest="cls_name", metavar="NAME", help="only this class hypothesis")
    p.add_argument("--band", metavar="NAME", help="only this band's levels")
    p.add_argument("--plot", metavar="PNG",
                   help="also draw the observer's path, the bearing fan and each hypothesis's track with its "
                        "uncertainty ellipses over the area (and the errors against --truth)")
    p.add_argument("--truth", metavar="CSV", help="truth CSV (simulate's truth.csv) drawn on --plot")
    p.add_argument("--target-depth", default="class", metavar="unknown|class|METRES",
                   help="the target's depth: its class's (default, where the tables are "
                        "computed), a depth in metres, or unknown (estimated with the motion)")
    p.add_argument("--range-prior", metavar="NEAR,FAR", type=_range_prior,
                   help="the particle filters' prior range, km: every factor of range between the two "
                        "equally likely (default 1 km to the grid's last range)")
    p.add_argument("--force", action="store_true",
                   help="replace --out (and --plot) even if it is not a track CSV (a PNG)")
    p.set_defaults(func=run_track)


def _range_prior(text: str) -> tuple[float, float]:
    """``NEAR,FAR`` in km -> (near, far) in m; what is wrong with it otherwise."""
    try:
        near, far = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give two ranges in km, NEAR,FAR (e.g. 2,25)") from None
    return 1000.0 * near, 1000.0 * far


def run_track(args) -> Report:
    import numpy as np

    from acoustics.grid.opentables import open_tables
    from tracker.measurements import read_measurements
    from tracker.track import track
    from tracker.trackfile import write_track
    from tracker.truthfile import read_truth

    check_output_file(args.out, Kind.TRACK_CSV, force=args.force)
    if args.plot is not None:
        check_output_file(args.plot, Kind.PNG, force=args.force)
    elif args.truth is not None:
        raise InputError("--truth is drawn on the picture: give --plot PNG too")
    tables = open_tables(args.grid, month=args.month)
    m = read_measurements(args.measurements, list(tables.band_names), origin=tables.area.origin)
    truth = read_truth(args.truth) if args.truth is not None else None
    df = track(tables, m, method=args.method, rng=np.random.default_rng(args.seed),
               cls_name=args.cls_name, band=args.band, target_depth=args.target_depth,
               range_prior_m=args.range_prior)
    if args.plot is None:
        write_track(args.out, df)
    else:  # the track and its picture: both or neither
        from acoustics.plots.figures import save_figure
        from tracker.trackplot import track_figure

        fig = track_figure(df, m, tables, truth=truth, grid_path=args.grid)
        with atomic_paths([args.out, args.plot]) as (csv_tmp, png_tmp):
            write_track(csv_tmp, df, atomic=False)
            save_figure(fig, png_tmp, atomic=False)
    last = df.groupby("class").tail(1)
    lines = [f"tracked {len(m)} cycles ({args.method}); wrote {args.out}"
             + (f" and {args.plot}" if args.plot else "")]
    data = {"out": args.out, "plot": args.plot, "method": args.method, "cycles": len(m), "final": {}}
    if tables.follows_observer:
        lines.append(f"  the tables followed the observer through the atlas {args.grid}")
        data["follows_observer"] = True
    offset = tables.observer_offset(m.obs_x_m, m.obs_y_m)
    if offset is not None:
        lines.append(f"  observer up to {offset.distance_m / 1000:.2f} km from the grid's origin "
                     f"({offset.origin_lat_deg:g} N, {offset.origin_lon_deg:g} E): its "
                     f"bearing-dependent tables are computed from there")
        data["observer_max_distance_from_origin_m"] = offset.distance_m
    for _, r in last.iterrows():
        depth = (f", depth {r.depth_m:.0f} m" + (f" (sd {r.depth_sd_m:.0f} m)"
                                                  if np.isfinite(r.depth_sd_m) else "")
                 if np.isfinite(r.depth_m) else "")
        lines.append(f"  {r['class']}: range {r.range_m / 1000:.2f} km{_pm(r.range_sd_m / 1000, '.2f', 'km')}, "
                     f"course {r.course_deg:.1f} deg{_pm(r.course_sd_deg, '.1f', 'deg')}, speed "
                     f"{r.speed_mps:.2f} m/s{_pm(r.speed_sd_mps, '.2f', 'm/s')} (tack {r.tack}){depth}")
        data["final"][r["class"]] = {k: float(r[k]) for k in ("range_m", "course_deg", "speed_mps", "range_sd_m",
                                                               "course_sd_deg", "speed_sd_mps", "depth_m",
                                                               "depth_sd_m")}
    for choice in df.attrs.get("depth", []):
        posterior = (f"depth {choice.median_m:.0f} m, 90 % in {choice.interval_m[0]:.0f}-"
                     f"{choice.interval_m[1]:.0f} m, P(<= 15 m) {choice.surface_probability:.2f}, "
                     f"P(>= 40 m) {choice.submerged_probability:.2f}")
        vs_class = ("" if choice.log_lr_class_depth is None else
                    f", {choice.log_lr_class_depth:.1f} over its table depth")
        lines.append(f"  {choice.cls_name}: most likely depth {choice.depth_m:.0f} m of "
                     f"{len(choice.depths_m)} hypotheses (ln likelihood ratio "
                     f"{choice.log_lr_next:.1f} over the next{vs_class}); {posterior}")
        lines.append("    weights: " + ", ".join(f"{z:g} m {w:.2f}" for z, w in zip(choice.depths_m, choice.weights)))
        data.setdefault("depth", {})[choice.cls_name] = {
            "depth_m": choice.depth_m, "depths_m": list(choice.depths_m), "weights": list(choice.weights),
            "log_likelihood": list(choice.log_likelihood),
            "log_lr_next": choice.log_lr_next if math.isfinite(choice.log_lr_next) else None,
            "log_lr_class_depth": choice.log_lr_class_depth, "median_m": choice.median_m,
            "interval_m": list(choice.interval_m), "surface_probability": choice.surface_probability,
            "submerged_probability": choice.submerged_probability}
    return Report("\n".join(lines), data)


def _pm(sd: float, fmt: str, unit: str) -> str:
    """The 90 % interval's half-width beside an estimate (1.645 sd: docs/uncertainty.md), or none."""
    return f" +- {1.6448536 * sd:{fmt}} {unit} (90 %)" if math.isfinite(sd) else ""
