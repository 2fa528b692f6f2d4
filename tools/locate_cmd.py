"""``tmakit locate``: a stationary target from bearings, and ``tmakit locate plan``: a route.

    tmakit locate --bearings CSV [--method lsq|crossing|mean] [--d-alpha-deg 1] [--plot PNG]
    tmakit locate plan --target-x-m X --target-y-m Y [--speed-mps 5] [--leg-s 600] [--legs 10]
                       [--rule eq23|eq17] [--out CSV] [--plot PNG]

The science is in `tracker.locate` (Schmidt et al.); this module parses, calls and reports.
"""

from __future__ import annotations

import argparse
import dataclasses
import math

from envdata.files import atomic_paths
from tools.outputs import Kind, check_output_file
from tools.report import Report
from tracker.errors import LocateError
from tracker.locate.choices import DEFAULT_MAX_U, CourseRule, FixMethod, Side

DEFAULT_TRIALS_WITH_PLOT = 1000


def register(subparsers, common: argparse.ArgumentParser) -> None:
    """Add the ``locate`` command (with its ``plan`` action) to the main parser."""
    p = subparsers.add_parser(
        "locate", parents=[common],
        help="stationary target from bearings (Schmidt et al.); 'locate plan' plans a route",
        description="Estimate a stationary target's position from bearings taken at known "
                    "observer positions, with the conditioning number u (eq. 11) and the "
                    "error region for a bearing error bound D_alpha (eqs. 25-28). "
                    "'tmakit locate plan ...' plans the observer's route (eq. 17 or 23).")
    p.add_argument("--bearings", metavar="CSV",
                   help="bearings CSV: t_s, obs_x_m, obs_y_m, bearing_deg (extra columns ignored)")
    p.add_argument("--method", choices=[m.value for m in FixMethod], default=FixMethod.LSQ.value,
                   help="crossing: last two bearings (eqs. 6-8); lsq: least squares over all; "
                        "mean: mean of consecutive pairwise fixes (eq. 29); default lsq")
    _add_region_options(p)
    p.add_argument("--max-u", type=float, default=DEFAULT_MAX_U,
                   help="largest conditioning number u accepted (default %(default)g)")
    p.set_defaults(func=run_locate)

    actions = p.add_subparsers(dest="locate_action", metavar="ACTION")
    q = actions.add_parser(
        "plan", parents=[common], help="plan the observer's route (eq. 17 or algorithm 23)",
        description="Plan the observer's route for K legs toward a target guess: each leg "
                    "perpendicular to the current bearing (eq17) or to the anticipated next "
                    "bearing (eq23, the paper's modified algorithm). Prints the route with "
                    "u and 1/|P| per pair and the first pair's error region.")
    q.add_argument("--target-x-m", type=float, required=True, help="target guess, east, m")
    q.add_argument("--target-y-m", type=float, required=True, help="target guess, north, m")
    q.add_argument("--start-x-m", type=float, default=0.0, help="first bearing point, m (0)")
    q.add_argument("--start-y-m", type=float, default=0.0, help="first bearing point, m (0)")
    q.add_argument("--speed-mps", type=float, default=5.0, help="observer speed, m/s (5)")
    q.add_argument("--leg-s", type=float, default=600.0,
                   help="time between bearings, s (600; leg VT = speed * time)")
    q.add_argument("--legs", type=int, default=10, help="number of legs K (10)")
    q.add_argument("--rule", choices=[r.value for r in CourseRule],
                   default=CourseRule.EQ23.value,
                   help="eq17: perpendicular to the current bearing; eq23: perpendicular to the "
                        "anticipated next bearing (default)")
    q.add_argument("--first-leg", choices=[r.value for r in CourseRule], default=None,
                   help="rule for the first leg only (default: --rule); the paper's text uses "
                        "eq17 for it, its Fig. 8 numbers come from eq23 with R1 known")
    q.add_argument("--side", choices=[s.value for s in Side], default=Side.PORT.value,
                   help="keep the target to port (course = bearing + 90, default) or starboard")
    q.add_argument("--min-range-m", type=float, default=None,
                   help="eq23 stops closing and circles below this range (default VT/sqrt 2)")
    q.add_argument("--simulate", action="store_true",
                   help="add uniform bearing errors within +-D_alpha and steer on the fixes "
                        "(use --seed for a repeatable run)")
    _add_region_options(q)
    q.add_argument("--out", metavar="CSV", help="write the route as CSV (bearings CSV columns "
                                                "plus course_deg, speed_mps, range_m, u, ...)")
    q.set_defaults(func=run_plan)


def _add_region_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--d-alpha-deg", type=float, default=1.0,
                   help="bearing error bound D_alpha for the error region, deg (1)")
    p.add_argument("--trials", type=int, default=None,
                   help=f"Monte Carlo trials with uniform bearing errors (default "
                        f"{DEFAULT_TRIALS_WITH_PLOT} with --plot, else none)")
    p.add_argument("--seed", type=int, default=None, help="random seed for the Monte Carlo")
    p.add_argument("--plot", metavar="PNG", help="draw the analogues of the paper's figures")
    p.add_argument("--force", action="store_true",
                   help="replace --out/--plot even if they are not tmakit's kind of file")


def _trials(args) -> int:
    n = args.trials if args.trials is not None else (DEFAULT_TRIALS_WITH_PLOT if args.plot else 0)
    if n < 0 or n > 10_000_000:
        raise LocateError(f"--trials: must be in [0, 10000000], got {n}")
    return n


def _check_d_alpha(args) -> None:
    if not (math.isfinite(args.d_alpha_deg) and 0.0 < args.d_alpha_deg < 45.0):
        raise LocateError(f"--d-alpha-deg: the bearing error bound must be in (0, 45) deg, "
                          f"got {args.d_alpha_deg} deg")


def _region_data(region) -> dict | None:
    if region is None:
        return None
    from tracker.locate.regions import ErrorRegion

    if isinstance(region, ErrorRegion):
        return {"kind": "quadrilateral", "vertices_m": region.vertices_m.tolist(),
                "d13_m": region.d13_m, "d13_eq25_m": region.d13_eq25_m, "d24_m": region.d24_m,
                "d24_eq26_m": region.d24_eq26_m, "d24_eq27_m": region.d24_eq27_m,
                "ratio": region.ratio, "ratio_eq28": region.ratio_eq28,
                "area_m2": region.area_m2, "area_diagonals_m2": region.area_diagonals_m2,
                "d_alpha_deg": region.d_alpha_deg, "delta_deg": region.delta_deg,
                "baseline_m": region.baseline_m}
    return {"kind": "polygon", "vertices_m": region.vertices_m.tolist(),
            "area_m2": region.area_m2, "diameter_m": region.diameter_m,
            "d_alpha_deg": region.d_alpha_deg}


def _region_lines(region, note: str) -> list[str]:
    from tracker.locate.regions import ErrorRegion

    if isinstance(region, ErrorRegion):
        verts = " ".join(f"({x:.1f}, {y:.1f})" for x, y in region.vertices_m)
        return [
            f"error region, D_alpha = {region.d_alpha_deg:g} deg ({note}; bearings differ by "
            f"{abs(region.delta_deg):.4g} deg, baseline {region.baseline_m:.1f} m):",
            f"  d13 = {region.d13_m:.1f} m (eq. 25: {region.d13_eq25_m:.1f} m)",
            f"  d24 = {region.d24_m:.1f} m (eq. 26: {region.d24_eq26_m:.1f} m, "
            f"eq. 27: {region.d24_eq27_m:.1f} m)",
            f"  d24/d13 = {region.ratio:.4g} (eq. 28: {region.ratio_eq28:.4g})",
            f"  area = {region.area_m2:.4g} m^2 (d13*d24/2 = {region.area_diagonals_m2:.4g} m^2)",
            f"  vertices 1-4 (x, y), m: {verts}",
        ]
    verts = " ".join(f"({x:.1f}, {y:.1f})" for x, y in region.vertices_m)
    return [f"error region, D_alpha = {region.d_alpha_deg:g} deg ({note}): "
            f"{len(region.vertices_m)} vertices, area = {region.area_m2:.4g} m^2, "
            f"diameter = {region.diameter_m:.1f} m",
            f"  vertices (x, y), m: {verts}"]


def _fmt(value: float, spec: str) -> str:
    return format(value, spec) if math.isfinite(value) else "-"


def _mc_data(summary) -> dict | None:
    return None if summary is None else dataclasses.asdict(summary)


def _mc_line(data: dict | None) -> list[str]:
    if data is None or not data["fixes"]:
        return []
    inside = ("" if data["inside_fraction"] is None
              else f"; {100.0 * data['inside_fraction']:.1f} % inside the error region")
    return [f"Monte Carlo, {data['trials']} trials of uniform bearing errors: mean fix (eq. 29) "
            f"x = {data['mean_x_m']:.1f} m, y = {data['mean_y_m']:.1f} m{inside}"]


def run_locate(args) -> Report:
    """``tmakit locate --bearings CSV``: fix, conditioning and error region."""
    if not args.bearings:
        raise LocateError("locate: give --bearings CSV to locate a target, or use "
                          "'tmakit locate plan ...' to plan a route")
    _check_d_alpha(args)
    n_trials = _trials(args)
    if args.plot:
        check_output_file(args.plot, Kind.PNG, force=args.force)
    import numpy as np

    from tracker.locate.bearings import read_bearings_csv
    from tracker.locate.study import locate_study

    bearings = read_bearings_csv(args.bearings)

    study = locate_study(bearings, method=args.method, max_u=args.max_u, d_alpha_deg=args.d_alpha_deg,
                         n_trials=n_trials, rng=np.random.default_rng(args.seed))
    result, region, region_note, region_problem = (study.result, study.region, study.region_note,
                                                   study.region_problem)
    mc = study.monte_carlo
    n = len(bearings)
    if args.plot:
        from acoustics.plots.figures import save_figure
        from tracker.locate.plot import locate_figure

        save_figure(locate_figure(bearings, result, region, mc), args.plot)

    mc_data = _mc_data(study.monte_carlo_summary)
    data = {
        "bearings": str(args.bearings), "method": result.method.value, "n_bearings": n,
        "x_m": result.x_m, "y_m": result.y_m, "u": result.u, "determinant": result.determinant,
        "max_u": args.max_u, "residual_rms_deg": result.residual_rms_deg,
        "pairs_used": len(result.pair_rows), "pairs_skipped": result.pairs_skipped,
        "region": _region_data(region), "region_problem": region_problem,
        "monte_carlo": mc_data, "plot": args.plot,
    }
    det_note = {FixMethod.CROSSING: "|P| (eq. 10)", FixMethod.LSQ: "sqrt(det P^T P)",
                FixMethod.MEAN: "smallest pair |P| (eq. 10)"}[result.method]
    lines = [
        f"{args.bearings}: {n} bearings, method {result.method.value}",
        f"estimate: x = {result.x_m:.1f} m, y = {result.y_m:.1f} m",
        f"conditioning number u = {result.u:.4g} (eq. 11), {det_note} = "
        f"{result.determinant:.4g}; bearing residual rms {result.residual_rms_deg:.3g} deg",
    ]
    if result.method is FixMethod.MEAN:
        lines.append(f"pairs used {len(result.pair_rows)}, left out {result.pairs_skipped}")
    if region is not None:
        lines += _region_lines(region, region_note)
    else:
        lines.append(f"error region, D_alpha = {args.d_alpha_deg:g} deg: none ({region_problem})")
    lines += _mc_line(mc_data)
    if args.plot:
        lines.append(f"plot: {args.plot}")
    return Report("\n".join(lines), data)


def run_plan(args) -> Report:
    """``tmakit locate plan``: the route for K legs, its conditioning and error region."""
    _check_d_alpha(args)
    n_trials = _trials(args)
    outputs = []
    if args.out:
        outputs.append(check_output_file(args.out, Kind.ROUTE_CSV, force=args.force))
    if args.plot:
        outputs.append(check_output_file(args.plot, Kind.PNG, force=args.force))
    import numpy as np

    from tracker.locate.study import plan_study

    plan = plan_study(target_x_m=args.target_x_m, target_y_m=args.target_y_m, start_x_m=args.start_x_m,
                      start_y_m=args.start_y_m, speed_mps=args.speed_mps, leg_s=args.leg_s,
                      n_legs=args.legs, rule=args.rule, side=args.side, min_range_m=args.min_range_m,
                      first_leg_rule=args.first_leg, d_alpha_deg=args.d_alpha_deg,
                      simulate=bool(args.simulate), n_trials=n_trials,
                      rng=np.random.default_rng(args.seed))
    route, region, region_problem, frame = plan.route, plan.region, plan.region_problem, plan.table

    fig = None
    if args.plot:
        from tracker.locate.plot import plan_figure

        fig = plan_figure(route, region, plan.monte_carlo)
    with atomic_paths(outputs) as temps:  # the route and its plot: both or neither
        temps = list(temps)
        if args.out:
            frame.to_csv(temps.pop(0), index=False, float_format="%.12g", na_rep="")
        if fig is not None:
            from acoustics.plots.figures import save_figure

            save_figure(fig, temps.pop(0), atomic=False)

    mc_data = _mc_data(plan.monte_carlo_summary)
    rows = frame.replace({math.nan: None}).to_dict(orient="records")
    data = {
        "target_x_m": args.target_x_m, "target_y_m": args.target_y_m, "rule": route.rule.value,
        "first_leg_rule": route.first_leg_rule.value,
        "side": route.side.value, "legs": len(route.course_deg), "speed_mps": route.speed_mps,
        "leg_s": route.leg_s, "leg_m": route.leg_m, "min_range_m": route.min_range_m,
        "simulated": bool(args.simulate), "route": rows, "u_first": float(route.u[0]),
        "u_last": float(route.u[-1]), "region": _region_data(region),
        "region_problem": region_problem, "monte_carlo": mc_data, "out": args.out,
        "plot": args.plot,
    }
    lines = [
        f"route, rule {route.rule.value} (first leg {route.first_leg_rule.value}), target to "
        f"{route.side.value}: {len(route.course_deg)} "
        f"leg{'s' if len(route.course_deg) > 1 else ''} of {route.leg_m:.1f} m "
        f"({route.speed_mps:g} m/s for {route.leg_s:g} s), "
        f"target guess ({args.target_x_m:g}, {args.target_y_m:g}) m"
        + (f", bearings with errors within +-{args.d_alpha_deg:g} deg" if args.simulate else ""),
        f"{'n':>3} {'t_s':>9} {'obs_x_m':>10} {'obs_y_m':>10} {'bearing':>8} {'course':>7} "
        f"{'range_m':>10} {'u':>8} {'1/|P|':>8} {'d13_m':>9} {'d24_m':>9}",
    ]
    for k, row in enumerate(frame.itertuples(index=False), start=1):
        inv_det = 1.0 / abs(row.determinant) if row.determinant else math.nan
        lines.append(
            f"{k:>3} {row.t_s:>9.0f} {row.obs_x_m:>10.1f} {row.obs_y_m:>10.1f} "
            f"{row.bearing_deg:>8.2f} {_fmt(row.course_deg, '.2f'):>7} {row.range_m:>10.1f} "
            f"{_fmt(row.u, '.3f'):>8} {_fmt(inv_det, '.3f'):>8} {_fmt(row.d13_m, '.1f'):>9} "
            f"{_fmt(row.d24_m, '.1f'):>9}")
    if region is not None:
        lines += _region_lines(region, "first pair of the planned route")
    else:
        lines.append(f"error region, D_alpha = {args.d_alpha_deg:g} deg: none ({region_problem})")
    lines += _mc_line(mc_data)
    if args.out:
        lines.append(f"route: {args.out}")
    if args.plot:
        lines.append(f"plot: {args.plot}")
    return Report("\n".join(lines), data)
