"""``tmakit grids build|show|plot|compare``: propagation tables for an area."""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path

from acoustics.plots.what import What
from tools.outputs import Kind, check_output_file
from tools.pdtext import pd_lines, reach_data, reach_lines
from tools.report import Report, want_progress

#: The values of ``acoustics.Model`` (the builders' enum, which imports xarray: the parser lists
#: them without it; tests/tools/test_startup.py checks they are the enum's).
MODELS = ("bellhop", "urick", "ram", "auto")


def register(sub, common) -> None:
    p = sub.add_parser("grids", parents=[common], help="build, show and plot propagation grids")
    gsub = p.add_subparsers(dest="grids_command", metavar="ACTION", required=True)

    b = gsub.add_parser("build", parents=[common], help="build the grid file of an area")
    b.add_argument("area", metavar="AREA", help="built-in area name or TOML path")
    b.add_argument("--out", type=Path, help="grid file to write (default: AREA-MODEL.nc)")
    b.add_argument("--model", choices=MODELS, default="bellhop",
                   help="bellhop (default), urick, ram (the parabolic equation; bands from coherent "
                        "runs) or auto (RAM below the crossover frequency, BELLHOP above)")
    b.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="BELLHOP or RAM runs at once on this machine (default: the number of cores; "
                        "ignored with --scheduler)")
    b.add_argument("--scheduler", metavar="ADDR", help="run on this Dask distributed scheduler")
    b.add_argument("--force", action="store_true",
                   help="rebuild even if the file is up to date; replace --out even if it is not a grid")
    b.set_defaults(func=run_build)

    ck = gsub.add_parser("check", parents=[common], help="how far K moves when the beams, the ray step and "
                         "the frequencies per band are doubled, on a sample of radials, without building "
                         "the grid; and the settings a build uses")
    ck.add_argument("area", metavar="AREA", help="built-in area name or TOML path")
    ck.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                    help="BELLHOP runs at once (default: the number of cores)")
    ck.set_defaults(func=run_check)

    s = gsub.add_parser("show", parents=[common], help="summarise a grid file")
    s.add_argument("file", type=Path, metavar="FILE")
    s.set_defaults(func=run_show)

    pl = gsub.add_parser("plot", parents=[common], help="plot TL fields and K(r) curves; for a "
                         "bearing-dependent grid also the map around the origin and the bottom")
    pl.add_argument("file", type=Path, metavar="FILE")
    pl.add_argument("--out", type=Path, required=True, metavar="PNG",
                    help="the plot; for a bearing-dependent grid the map, with STEM-bottom.png (and "
                         "STEM-section.png with --bearing) written beside it")
    pl.add_argument("--class", dest="cls_name",
                    help="class whose TL field (or section) to draw, the only class on the map "
                         "(default: the first; every class on the map)")
    pl.add_argument("--band", help="band of the K(r) or P_D map, the section and the depth figure "
                                   "(default: the first; any band for P_D: --band any)")
    pl.add_argument("--what", choices=[w.value for w in What],
                    help="the map: K(r) in --band (k, the default) or the detection range per band, "
                         "each class at its mean level (detection), bearing-dependent grids; (pd) the "
                         "probability of detection P_D = Phi(SE / sigma) in --band or any band with its "
                         "0.9 / 0.5 / 0.1 ranges, as a map with STEM.nc beside it (CF netCDF on lat/lon "
                         "for a GIS), or against range on a flat grid; or "
                         "(depth) only PNG: K of --class in --band against target depth and range, "
                         "on the radial nearest to --bearing (default: the first) or a flat grid "
                         "built with a class's depth_range_m")
    pl.add_argument("--sigma-db", type=float, metavar="DB",
                    help="with --what pd: the level's sd in place of the class's source-level sd and K's "
                         "error sd, dB (> 0)")
    pl.add_argument("--sonar", metavar="NAME|FILE",
                    help="with --what detection or pd: listen with this sonar (a built-in one, e.g. "
                         "omni-buoy, or a sonar TOML file: its [sonar] and optional [noise]) in place of "
                         "the area's; K is the grid's")
    pl.add_argument("--bearing", type=float, metavar="DEG",
                    help="also write STEM-section.png: TL over depth and range on the radial nearest "
                         "to this bearing, deg in [0, 360) (bearing-dependent grids); with --what "
                         "depth the radial drawn")
    pl.add_argument("--bathymetry", type=Path, metavar="FILE",
                    help="bathymetry file for the map's latitude-longitude panel (default: the file the "
                         "grid records, if found by its name and sha256)")
    pl.add_argument("--force", action="store_true", help="replace the outputs even if they are not PNGs")
    pl.set_defaults(func=run_plot)

    c = gsub.add_parser("compare", parents=[common], help="how far two grids of one area are apart: "
                        "median and 90th percentile of |dTL| and |dK| by class, band (and bearing)")
    c.add_argument("file_a", type=Path, metavar="A", help="the first grid (differences are B - A)")
    c.add_argument("file_b", type=Path, metavar="B", help="the second grid, of the same area and axes")
    c.add_argument("--plot", type=Path, metavar="PNG", help="also draw the difference field B - A")
    c.add_argument("--force", action="store_true", help="replace --plot even if it is not a PNG")
    c.set_defaults(func=run_compare)


def run_build(args) -> Report:
    import acoustics
    import envdata
    from acoustics.builder.gridfile import build_grid_file

    area = envdata.load_area(args.area)
    out = args.out if args.out is not None else Path(f"{area.name}-{args.model}.nc")
    check_output_file(out, Kind.NETCDF, force=args.force)
    info = build_grid_file(area, out, model=args.model, workers=args.workers,
                           scheduler=args.scheduler, force=args.force, progress=want_progress(args))
    if info.up_to_date:
        summary = f"{info.file}: up to date for area {info.area} ({info.model}); --force rebuilds"
    else:
        dims = ", ".join(f"{k} {v}" for k, v in info.dims.items())
        summary = (f"wrote {info.file}: area {info.area}, model {info.model} ({dims})\n"
                   f"  runs: {info.runs} ({info.runs_reused} reused), "
                   f"{info.bellhop_seconds:.1f} s of BELLHOP, {info.ram_seconds:.1f} s of RAM, "
                   f"{info.wall_seconds:.1f} s wall")
    summary += "".join(f"\nnote: {note}" for note in info.notes)
    data = grid_file_data(info)
    # imported once the runs are started: xarray comes beside them (acoustics.builder.preload)
    from acoustics.grid.pdmap import table_reach

    reach = table_reach(acoustics.open_tables(info.dataset if info.dataset is not None else out))
    summary += "\nwhere P_D falls below 0.1 (the class at its mean level):\n" + "\n".join(reach_lines(reach))
    data["reach"] = reach_data(reach)
    return Report(summary, data)


def run_check(args) -> Report:
    import envdata
    from acoustics.builder.check import CONVERGED_DB, check_area

    if args.workers < 1:
        raise envdata.InputError(f"--workers: must be >= 1, got {args.workers}")
    area = envdata.load_area(args.area)
    result = check_area(area, workers=args.workers, progress=want_progress(args))
    settings = ", ".join(f"{k} {v}" for k, v in result.settings.items() if v is not None)
    lines = [f"area {result.area}: K on {result.sample} ({result.baseline_seconds:.1f} s of BELLHOP)",
             f"  the build runs with: {settings}"]
    for v in result.variants:
        verdict = "converged" if v.converged else f"NOT converged (median > {CONVERGED_DB:g} dB)"
        lines.append(f"  {v.change}: K moves {v.median_db:.2f} dB median, {v.worst_db:.2f} dB at worst "
                     f"({v.worst}); {verdict}")
    data = dataclasses.asdict(result)
    data["converged"] = result.converged
    return Report("\n".join(lines), data)


def grid_file_data(info) -> dict:
    """A ``GridFileResult`` as the JSON report gives it."""
    data = dataclasses.asdict(dataclasses.replace(info, dataset=None))  # the grid itself is the file
    del data["dataset"]
    data.update(file=str(info.file), model=str(info.model),
                bellhop_seconds=round(info.bellhop_seconds, 3), ram_seconds=round(info.ram_seconds, 3),
                wall_seconds=round(info.wall_seconds, 3))
    if info.up_to_date:
        del data["dims"]
    return data


def run_show(args) -> Report:
    import numpy as np

    import acoustics
    from acoustics.grid.summary import grid_summary

    s = grid_summary(acoustics.open_tables(args.file))
    lines = [f"{args.file}: area {s.area}, model {s.model}, observer at {s.observer_depth_m:g} m",
             "  dims: " + ", ".join(f"{k} {v}" for k, v in s.sizes.items()),
             f"  range {s.range_m[0]:g}-{s.range_m[1]:g} m, depth {s.depth_m[0]:g}-{s.depth_m[1]:g} m",
             f"  created {s.attrs.get('created', '?')}, source_hash {s.attrs['source_hash'][:16]}...",
             f"  BELLHOP: {s.attrs.get('bellhop_version', '-')}"]
    g = s.geometry
    if g:
        lines.append(f"  origin {g['origin_lat_deg']:g} N, {g['origin_lon_deg']:g} E; {g['radials']} radials; "
                     f"bottom {g['bottom_min_m']:.0f}-{g['bottom_max_m']:.0f} m; "
                     f"{g['beyond_land_fraction']:.0%} of the range cells beyond land")
        lines.append("  K(r) dB at " + ", ".join(f"{r} km" for r in s.ranges_km)
                     + f" ({s.model} {g['k_typical']} / Urick; - where no bearing has K):")
    else:
        lines.append("  K(r) dB at " + ", ".join(f"{r} km" for r in s.ranges_km) + f" ({s.model} / Urick):")
    k_table = {}
    for row in s.k:
        k_table[f"{row.cls_name}/{row.band}"] = {
            "k_db": [None if not np.isfinite(v) else round(v, 2) for v in row.k_db],
            "k_urick_db": [round(v, 2) for v in row.k_urick_db]}
        lines.append(f"    {row.cls_name:>5} {row.band:>5}: " + "  ".join(
            f"{'-' if not np.isfinite(a) else f'{a:.1f}':>7}/{b:6.1f}" for a, b in zip(row.k_db, row.k_urick_db)))
    data = {"file": str(args.file), "attrs": s.attrs, "dims": s.sizes,
            "classes": sorted({r.cls_name for r in s.k}, key=[r.cls_name for r in s.k].index),
            "bands": sorted({r.band for r in s.k}, key=[r.band for r in s.k].index),
            "ranges_km": list(s.ranges_km), "k": k_table}
    return Report("\n".join(lines), data)


def run_plot(args) -> Report:
    import acoustics
    from acoustics.grid.detectionsigma import SigmaOverride
    from acoustics.grid.pdmap import pd_summary
    from acoustics.plots.gridplots import PlotRequest, plot_grid, plot_paths
    from envdata.errors import InputError
    from envdata.receiver import load_receiver

    sigma = None if args.sigma_db is None else SigmaOverride(sigma_db=args.sigma_db)
    tables = acoustics.open_tables(args.file)
    if args.sonar is not None:
        if args.what not in (What.DETECTION.value, What.PD.value):
            raise InputError("--sonar: only with --what detection or --what pd (K does not depend on the sonar)")
        tables = tables.with_receiver(load_receiver(args.sonar))
    request = PlotRequest(cls_name=args.cls_name, band=args.band,
                          what=None if args.what is None else What(args.what), bearing_deg=args.bearing,
                          bathymetry=args.bathymetry, grid_path=args.file, sigma=sigma)
    for key, path in plot_paths(tables, args.out, request).items():
        check_output_file(path, Kind.NETCDF if key == "netcdf" else Kind.PNG, force=args.force)
    plots = plot_grid(tables, args.out, request)
    lines = [f"wrote {path} ({key})" for key, path in plots.files.items()]
    data = {"files": {key: str(path) for key, path in plots.files.items()}}
    if plots.what == What.PD:
        lines += pd_lines(plots.pd_maps, plots.pd_row)
        bearings = tables.bearing_axis_deg is not None
        data.update(what=str(plots.what), band=plots.pd_row,
                    pd={c: pd_summary(pm, with_bearings=bearings) for c, pm in plots.pd_maps.items()})
    if plots.what in (What.K, What.DETECTION, What.PD) and "map" in plots.files:  # say which bathymetry file
        data["what"] = str(plots.what)
        choice = plots.bathymetry
        if choice is not None:
            lines.append(f"  bathymetry {choice.path} ({plots.notes[0]})")
        else:
            lines.append("  no bathymetry file at hand: the map has no latitude-longitude panel "
                         "(--bathymetry FILE adds it)")
        data["bathymetry"] = None if choice is None else {"file": str(choice.path), "found": choice.how,
                                                          "matches_grid": choice.matches}
    elif plots.what == What.DEPTH:
        lines = [f"wrote {args.out} (K against target depth and range)"]
        data = {"file": str(args.out), "what": str(plots.what)}
    elif plots.what == What.PD:
        pass
    else:
        lines = [f"wrote {args.out}"]
        data = {"file": str(args.out)}
    if tables.sonar_name is not None:
        lines.append(f"  {tables.sonar_label()}")
        data["sonar"] = tables.sonar_name
    return Report("\n".join(lines), data)


def run_compare(args) -> Report:
    import acoustics
    from acoustics.grid.compare import compare_grids

    if args.plot is not None:
        check_output_file(args.plot, Kind.PNG, force=args.force)
    comparison = compare_grids(acoustics.open_tables(args.file_a), acoustics.open_tables(args.file_b))
    data = comparison.to_dict()
    lines = [f"{args.file_b} ({comparison.model_b}) against {args.file_a} ({comparison.model_a}), "
             f"area {comparison.area}: |dTL| and |dK|, median / 90th percentile, dB",
             f"  {'class':>6} {'band':>6} {'bearing':>8}  {'|dTL|':>13}  {'|dK|':>13}  {'dTL signed':>10}  "
             f"{'cells':>9}  {'one-sided':>9}"]
    for row in comparison.rows:
        bearing = "all" if row.bearing_deg is None else f"{row.bearing_deg:g}"
        lines.append(f"  {row.cls_name:>6} {row.band:>6} {bearing:>8}  {_pair(row.tl_median_db, row.tl_p90_db):>13}  "
                     f"{_pair(row.k_median_db, row.k_p90_db):>13}  {_num(row.tl_signed_median_db):>10}  "
                     f"{row.tl_cells:>9}  {row.tl_one_sided:>9}")
    if args.plot is not None:
        from acoustics.plots.compareplot import plot_comparison

        plot_comparison(comparison, args.plot)
        lines.append(f"wrote {args.plot}")
        data["plot"] = str(args.plot)
    return Report("\n".join(lines), data)


def _num(x: float) -> str:
    return "-" if not math.isfinite(x) else f"{x:+.2f}"


def _pair(median: float, p90: float) -> str:
    return "-" if not math.isfinite(median) else f"{median:.2f} / {p90:.2f}"
