"""``tmakit plan track|months``: detection planning from the tables (docs/planning.md).

``plan track``: the cumulative probability that the sonar has detected a target by each time
along a scenario's or a CSV's track, and the expected time of the first detection.
``plan months``: an atlas's detection range at every position and month, side by side.
"""

from __future__ import annotations

from pathlib import Path

from envdata.errors import InputError
from tools.outputs import Kind, check_output_file
from tools.report import Report


def register(sub, common) -> None:
    p = sub.add_parser("plan", parents=[common], help="detection planning: P_D along a track, an atlas's "
                                                      "detection ranges month by month")
    psub = p.add_subparsers(dest="plan_command", metavar="ACTION", required=True)

    t = psub.add_parser("track", parents=[common], help="the cumulative probability of detection along a track "
                        "(one look per integration time) and the expected time of the first detection")
    t.add_argument("--grid", required=True, metavar="FILE", help="grid (netCDF) or atlas (Zarr store)")
    source = t.add_mutually_exclusive_group(required=True)
    source.add_argument("--scenario", metavar="S", help="built-in scenario or TOML: its observer and target "
                                                        "tracks, without noise")
    source.add_argument("--track", type=Path, metavar="CSV",
                        help="t_s and the target as range_m, bearing_deg from the observer or x_m, y_m; optional "
                             "obs_x_m, obs_y_m (else the observer at the origin), obs_depth_m, class (a truth, "
                             "track or route CSV)")
    t.add_argument("--class", dest="cls_name",
                   help="the target's class (default: the scenario's, or the CSV's one class)")
    t.add_argument("--month", type=int, metavar="M", help="the atlas's month (needed when it has several)")
    t.add_argument("--sigma-db", type=float, metavar="DB",
                   help="the persistent sd of the level, dB (> 0), in place of the class's source-level sd and "
                        "K's error sd")
    t.add_argument("--look-sd-db", type=float, metavar="DB",
                   help="an sd drawn anew at every look, independently, dB (>= 0; the tables' model has none)")
    t.add_argument("--sonar", metavar="NAME|FILE",
                   help="listen with this sonar (built-in, e.g. omni-buoy, or a sonar TOML file) in place "
                        "of the area's")
    t.add_argument("--out", type=Path, required=True, metavar="CSV", help="P_D and the cumulative P_D at every look")
    t.add_argument("--plot", type=Path, metavar="PNG", help="also draw them against time")
    t.add_argument("--force", action="store_true", help="replace --out and --plot even if they are not tmakit's")
    t.set_defaults(func=run_track)

    m = psub.add_parser("months", parents=[common], help="an atlas's detection range per position and month, "
                        "side by side")
    m.add_argument("store", type=Path, metavar="NAME.zarr")
    m.add_argument("--class", dest="cls_name", help="class (default: the first)")
    m.add_argument("--band", help="band, or any (the default)")
    m.add_argument("--months", type=int, nargs="+", metavar="M", help="months (default: every month of the atlas)")
    m.add_argument("--sigma-db", type=float, metavar="DB",
                   help="the level's sd in place of the class's source-level sd and K's error sd, dB (> 0)")
    m.add_argument("--out", type=Path, required=True, metavar="CSV",
                   help="a row per position, month and P_D level: the median range over the radials and more")
    m.add_argument("--plot", type=Path, metavar="PNG", help="also draw the months side by side")
    m.add_argument("--force", action="store_true", help="replace --out and --plot even if they are not tmakit's")
    m.set_defaults(func=run_months)


def _outputs(args) -> list[Path]:
    out = check_output_file(args.out, Kind.CSV, force=args.force)
    paths = [out]
    if args.plot is not None:
        paths.append(check_output_file(args.plot, Kind.PNG, force=args.force))
        if paths[1].resolve() == out.resolve():
            raise InputError(f"{out}: --out and --plot name the same file")
    return paths


def _write(outputs: list[Path], table, figure) -> None:
    """The CSV and (``figure()``, when given) the PNG: both or, on any failure, neither."""
    from acoustics.plots.figures import save_figure
    from envdata.files import atomic_paths

    fig = figure() if figure is not None else None
    with atomic_paths(outputs) as temps:
        table.to_csv(temps[0], index=False, float_format="%.6g")
        if fig is not None:
            save_figure(fig, temps[1], atomic=False)


def run_track(args) -> Report:
    from acoustics.grid.detectionsigma import SigmaOverride
    from acoustics.grid.opentables import open_tables
    from envdata.receiver import load_receiver
    from tracker.pdtrack import ASSUMPTIONS, read_track_path, scenario_path, track_pd, track_pd_figure
    from tracker.scenario import load_scenario

    outputs = _outputs(args)
    override = SigmaOverride(sigma_db=args.sigma_db, look_sd_db=args.look_sd_db)
    path = scenario_path(load_scenario(args.scenario)) if args.scenario else read_track_path(args.track, args.cls_name)
    cls_name = args.cls_name or path.cls_name
    tables = open_tables(args.grid, month=args.month)
    if args.sonar is not None:
        tables = tables.with_receiver(load_receiver(args.sonar))
    if cls_name is None:
        raise InputError(f"{path.source}: the track names no class; say which with --class "
                         f"({', '.join(tables.class_names)})")
    if cls_name not in tables.class_names:
        raise InputError(f"{args.grid}: class {cls_name!r} is not a class of the grid "
                         f"({', '.join(tables.class_names)})")
    result = track_pd(tables, path, cls_name, override=override)
    table = result.table()
    _write(outputs, table, (lambda: track_pd_figure(result)) if args.plot else None)
    first = result.first["any"]
    mean = first["mean_s_given_detected"]
    lines = [f"wrote {outputs[0]}" + (f" and {outputs[1]}" if args.plot else "")
             + f": {len(table)} looks of {result.look_s:g} s along {path.source}, class {cls_name}",
             f"  P(detected by the end), any band: {first['p_detected_by_end']:.3f}; "
             + (f"first detection, given one: {mean:.0f} s on average" if mean is not None else "no detection expected")
             + (f"; P_cum reaches 0.5 at {first['median_s']:g} s" if first["median_s"] is not None else "")]
    for row in (*result.rows[:-1], "any_shared"):
        f = result.first[row]
        said = "any band, one offset shared by the bands" if row == "any_shared" else row
        lines.append(f"    {said}: P(detected by the end) {f['p_detected_by_end']:.3f}"
                     + (f", P_cum 0.5 at {f['median_s']:g} s" if f["median_s"] is not None else ""))
    if not path.observer_given and args.track is not None:
        lines.append("  note: the file gives no observer position (obs_x_m, obs_y_m): the observer is at the origin")
    lines.append("  sigma: " + result.sigma_source)
    lines.append("  " + tables.sonar_label())
    data = {"files": {"csv": str(outputs[0]), **({"plot": str(outputs[1])} if args.plot else {})}, "class": cls_name,
            "looks": len(table), "look_s": result.look_s, "sigma": result.sigma_source,
            "observer_given": path.observer_given, "first_detection": result.first, "assumptions": list(ASSUMPTIONS),
            "sonar": tables.sonar_name}
    return Report("\n".join(lines), data)


def run_months(args) -> Report:
    import dataclasses

    import pandas as pd

    from acoustics.grid.atlas.seasons import check_choice, season_table
    from acoustics.grid.atlas.store import open_store
    from acoustics.grid.detectionsigma import SigmaOverride
    from acoustics.plots.atlaspd import seasons_figure

    outputs = _outputs(args)
    override = None if args.sigma_db is None else SigmaOverride(sigma_db=args.sigma_db)
    store = open_store(args.store)
    cls_name, row, months = check_choice(store, args.cls_name, args.band, args.months)
    rows = season_table(store, cls_name, row, months, override=override)
    table = pd.DataFrame([dataclasses.asdict(r) for r in rows])
    table.insert(4, "class", cls_name)
    table.insert(5, "band", row)
    _write(outputs, table, (lambda: seasons_figure(store, rows, cls_name=cls_name, row=row, months=months))
           if args.plot else None)
    lines = [f"wrote {outputs[0]}" + (f" and {outputs[1]}" if args.plot else "")
             + f": {cls_name}, {row}, months {', '.join(map(str, months))} of {store.area.name}",
             "  median range where P_D = 0.5, km, per position (beyond: past the table's "
             f"{store.range_m[-1] / 1000:g} km):"]
    by_origin: dict[int, list[str]] = {}
    for r in rows:
        if r.level == 0.5:
            by_origin.setdefault(r.origin, []).append(
                f"{r.month}: {'beyond' if r.median_beyond_table else f'{r.median_m / 1000:.1f}'}")
    lines += [f"    position {o} ({store.lat_deg[o]:.4f} N {store.lon_deg[o]:.4f} E): " + ", ".join(v)
              for o, v in by_origin.items()]
    data = {"files": {"csv": str(outputs[0]), **({"plot": str(outputs[1])} if args.plot else {})}, "class": cls_name,
            "band": row, "months": months, "rows": table.astype(object).where(table.notna(), None).to_dict("records")}
    return Report("\n".join(lines), data)
