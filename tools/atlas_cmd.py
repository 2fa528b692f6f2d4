"""``tmakit atlas build|show|plot|sample``: tables for many observer positions and months."""

from __future__ import annotations

import os
from pathlib import Path

from envdata.errors import InputError
from tools.outputs import Kind, check_output_file
from tools.report import Report, want_progress


def register(sub, common) -> None:
    p = sub.add_parser("atlas", parents=[common], help="build, show, plot and sample atlases (many positions "
                                                       "and months of bearing-dependent tables)")
    asub = p.add_subparsers(dest="atlas_command", metavar="ACTION", required=True)

    b = asub.add_parser("build", parents=[common], help="build (or bring up to date) the atlas of an area")
    b.add_argument("area", metavar="AREA", help="area TOML with [origin], [bearings] and [atlas]")
    b.add_argument("--out", type=Path, required=True, metavar="NAME.zarr", help="the Zarr store to write")
    b.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="tables computed at once on this machine (default: the number of cores; ignored "
                        "with --scheduler)")
    b.add_argument("--scheduler", metavar="ADDR", help="run on this Dask distributed scheduler (tcp://HOST:PORT); "
                                                       "the store must be on a file system its workers share")
    b.add_argument("--force", action="store_true", help="replace --out whatever it is, and recompute every table")
    b.set_defaults(func=run_build)

    s = asub.add_parser("show", parents=[common], help="summarise an atlas")
    s.add_argument("store", type=Path, metavar="NAME.zarr")
    s.set_defaults(func=run_show)

    pl = asub.add_parser("plot", parents=[common], help="the coverage map over the bathymetry")
    pl.add_argument("store", type=Path, metavar="NAME.zarr")
    pl.add_argument("--out", type=Path, required=True, metavar="PNG",
                    help="the map; with --what pd also STEM.nc beside it (CF netCDF on lat/lon for a GIS)")
    pl.add_argument("--what", choices=["detection", "k", "pd"], default="detection",
                    help="median detection range of the class at each position (default), its K at --range-km, "
                         "or (pd) the probability of detection: each position's P_D map, its 0.9 / 0.5 / 0.1 "
                         "ranges, beyond the table marked")
    pl.add_argument("--class", dest="cls_name", help="class (default: the first)")
    pl.add_argument("--band", help="band (default: any band for detection and pd, the first for k)")
    pl.add_argument("--month", type=int, help="month (default: the atlas's first)")
    pl.add_argument("--range-km", type=float, help="range of K, km (default: the middle of the range axis)")
    pl.add_argument("--sigma-db", type=float, metavar="DB",
                    help="with --what pd: the level's sd in place of the class's source-level sd and K's error "
                         "sd, dB (> 0)")
    pl.add_argument("--force", action="store_true", help="replace --out even if it is not a PNG")
    pl.set_defaults(func=run_plot)

    sa = asub.add_parser("sample", parents=[common], help="K and TL at observer positions between the positions")
    sa.add_argument("store", type=Path, metavar="NAME.zarr")
    sa.add_argument("--points", type=Path, required=True, metavar="CSV",
                    help="columns obs_lat_deg, obs_lon_deg, month, class, band, bearing_deg, range_m [, depth_m]")
    sa.add_argument("--out", type=Path, required=True, metavar="CSV", help="the rows with k_db and tl_db added")
    sa.add_argument("--weights", choices=("water", "bilinear"), default="water",
                    help="between positions: bilinear weights tempered by how alike each position's water depth "
                         "is to the observer's (default), or the bilinear weights alone")
    sa.add_argument("--force", action="store_true", help="replace --out even if it is not a CSV")
    sa.set_defaults(func=run_sample)


def _check_store_out(out: Path, force: bool) -> None:
    from acoustics.grid.atlas.format import is_atlas_store
    from tools.outputs import check_output_dir

    try:
        str(out).encode("utf-8")
    except UnicodeEncodeError:
        raise InputError(f"{os.fsencode(out).decode('utf-8', 'backslashreplace')}: output path is not valid "
                         f"UTF-8") from None
    if (out.exists() or out.is_symlink()) and not force:
        if not out.is_dir():
            raise InputError(f"{out}: exists and is not a tmakit atlas (a file); --force replaces it")
        if not is_atlas_store(out):
            raise InputError(f"{out}: exists and is not a tmakit atlas; --force replaces it")
    check_output_dir(out.parent if str(out.parent) else Path("."))


def run_build(args) -> Report:
    import envdata
    from acoustics.builder.atlas import build_atlas_file
    from acoustics.builder.executor import check_scheduler_address

    if args.scheduler is not None:
        check_scheduler_address(args.scheduler)
    elif args.workers < 1:
        raise InputError(f"--workers: must be >= 1, got {args.workers}")
    area = envdata.load_area(args.area)
    _check_store_out(args.out, args.force)
    info = build_atlas_file(area, args.out, workers=args.workers, scheduler=args.scheduler, force=args.force,
                            progress=want_progress(args))
    dims = ", ".join(f"{k} {v}" for k, v in info["dims"].items())
    summary = (f"wrote {info['file']}: atlas of area {info['area']} ({dims})\n"
               f"  tables: {info['tables']} ({info['tables_built']} built, {info['tables_reused']} up to date); "
               f"positions left out: {len(info['left_out'])}\n"
               f"  BELLHOP runs: {info['runs']}, {info['bellhop_seconds']:.1f} s of BELLHOP, "
               f"{info['wall_seconds']:.1f} s wall")
    return Report(summary, info)


def run_show(args) -> Report:
    from acoustics.grid.atlas.store import open_store

    store = open_store(args.store)
    size = sum(f.stat().st_size for f in Path(args.store).rglob("*") if f.is_file())
    info = {"file": str(args.store), "area": store.area.name, "months": store.months.tolist(),
            "positions": int(store.lat_deg.size), "classes": list(store.class_names), "bands": list(store.band_names),
            "bearings": int(store.bearing_deg.size), "depths": int(store.depth_m.size),
            "ranges": int(store.range_m.size), "range_max_m": float(store.range_m[-1]),
            "tables_done": int(store.done.sum()), "tables": int(store.done.size), "left_out": store.left_out,
            "store_bytes": size, "tmakit_format": store.attrs.get("tmakit_format")}
    lines = [f"{args.store}: atlas of area {store.area.name} (tmakit format {info['tmakit_format']})",
             f"  months {', '.join(map(str, info['months']))}; {info['positions']} positions; classes "
             f"{', '.join(info['classes'])}; bands {', '.join(info['bands'])}",
             f"  {info['bearings']} radials x {info['depths']} depths x {info['ranges']} ranges to "
             f"{info['range_max_m'] / 1000:g} km; {size / 2**20:.1f} MiB on disk",
             f"  tables complete: {info['tables_done']} of {info['tables']}"]
    if store.left_out:
        lines.append(f"  left out ({len(store.left_out)}):")
        lines += [f"    {p['lat_deg']:.4f} N {p['lon_deg']:.4f} E: {p['reason']}" for p in store.left_out]
    return Report("\n".join(lines), info)


def run_plot(args) -> Report:
    from acoustics.grid.atlas.store import open_store
    from acoustics.plots.atlasmap import coverage_figure
    from acoustics.plots.figures import save_figure

    out = check_output_file(args.out, Kind.PNG, force=args.force)
    if args.what == "pd":
        return _plot_pd(args, out)
    if args.sigma_db is not None:
        raise InputError("--sigma-db is for the probability of detection (--what pd)")
    if args.range_km is not None and not (args.range_km > 0 and args.range_km < 1e5):
        raise InputError(f"--range-km: must be > 0 km, got {args.range_km}")
    store = open_store(args.store)
    fig, values = coverage_figure(store, what=args.what, cls_name=args.cls_name, band=args.band, month=args.month,
                                  range_m=None if args.range_km is None else 1000.0 * args.range_km)
    save_figure(fig, out)
    return Report(f"wrote {out}: coverage map of {store.area.name} ({args.what})",
                  {"file": str(out), "values": [None if v != v else float(v) for v in values]})


def _plot_pd(args, out: Path) -> Report:
    """``atlas plot --what pd``: the map PNG and its netCDF, all or none, and each position's ranges."""
    from acoustics.grid.atlas.seasons import check_choice, position_maps, position_ranges
    from acoustics.grid.atlas.store import open_store
    from acoustics.grid.detectionsigma import SigmaOverride
    from acoustics.grid.pdfile import atlas_pd_dataset
    from acoustics.grid.pdmap import pd_summary
    from acoustics.plots.atlaspd import atlas_pd_figure
    from acoustics.plots.radialplots import write_figures
    from tools.pdtext import pd_lines

    if args.range_km is not None:
        raise InputError("--range-km is for the K map (--what k)")
    netcdf = out.with_name(f"{out.stem}.nc")
    if netcdf == out:
        raise InputError(f"{out}: the map's PNG needs a name of its own (say {out.stem}.png): its netCDF goes "
                         f"beside it as {out.name}")
    check_output_file(netcdf, Kind.NETCDF, force=args.force)
    sigma = None if args.sigma_db is None else SigmaOverride(sigma_db=args.sigma_db)
    store = open_store(args.store)
    month = int(store.months[0]) if args.month is None else args.month
    cls_name, row, _ = check_choice(store, args.cls_name, args.band, [month])
    maps = position_maps(store, cls_name, month, override=sigma)
    rows = position_ranges(store, month, maps, row)
    fig = atlas_pd_figure(store, month=month, cls_name=cls_name, row=row, maps=maps, rows=rows, override=sigma)
    write_figures({out: fig}, datasets={netcdf: atlas_pd_dataset(store, month, cls_name, row, override=sigma)})
    lines = [f"wrote {out} (map) and {netcdf} (netcdf): P_D of {cls_name}, {row}, month {month} of "
             f"{store.area.name}"]
    positions = []
    for o, pm in maps.items():
        lines += pd_lines({f"position {o} ({store.lat_deg[o]:.4f} N {store.lon_deg[o]:.4f} E): {cls_name}": pm}, row)
        positions.append({"origin": o, "lat_deg": float(store.lat_deg[o]), "lon_deg": float(store.lon_deg[o]),
                          **pd_summary(pm)})
    data = {"files": {"map": str(out), "netcdf": str(netcdf)}, "what": "pd", "month": month, "class": cls_name,
            "band": row, "positions": positions,
            "median_range_m": [_position_row(r) for r in rows]}
    return Report("\n".join(lines), data)


def _position_row(r) -> dict:
    """A ``PositionRange`` as JSON (NaN as None)."""
    import dataclasses
    import math

    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in dataclasses.asdict(r).items()}


def run_sample(args) -> Report:
    from acoustics.grid.atlas.sample import read_points, sample_store
    from acoustics.grid.atlas.store import open_store
    from envdata.files import atomic_path

    out = check_output_file(args.out, Kind.CSV, force=args.force)
    points = read_points(args.points)
    store = open_store(args.store)
    if args.weights == "bilinear":
        store.water_depth_ratio = None
    result = sample_store(store, points, str(args.points))
    with atomic_path(out) as tmp:
        result.to_csv(tmp, index=False, float_format="%.4f")
    return Report(f"wrote {out}: {len(result)} rows with k_db and tl_db from {args.store}",
                  {"file": str(out), "rows": len(result)})
