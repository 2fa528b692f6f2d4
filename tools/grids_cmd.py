"""``tmakit grids build|show|plot``: propagation tables for an area."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

import acoustics
import envdata
from acoustics.build import build_grid_file
from acoustics.radialstyle import What, check_plot_options
from tools.outputs import Kind, check_output_file
from tools.report import Report, want_progress


def register(sub, common) -> None:
    p = sub.add_parser("grids", parents=[common], help="build, show and plot propagation grids")
    gsub = p.add_subparsers(dest="grids_command", metavar="ACTION", required=True)

    b = gsub.add_parser("build", parents=[common], help="build the grid file of an area")
    b.add_argument("area", metavar="AREA", help="built-in area name or TOML path")
    b.add_argument("--out", type=Path, help="grid file to write (default: AREA-MODEL.nc)")
    b.add_argument("--model", choices=[m.value for m in acoustics.Model], default="bellhop")
    b.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="BELLHOP runs at once on this machine (default: the number of cores; "
                        "ignored with --scheduler)")
    b.add_argument("--scheduler", metavar="ADDR", help="run on this Dask distributed scheduler")
    b.add_argument("--force", action="store_true",
                   help="rebuild even if the file is up to date; replace --out even if it is not a grid")
    b.set_defaults(func=run_build)

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
    pl.add_argument("--band", help="band of the K(r) map and the section (bearing-dependent grids; "
                                   "default: the first)")
    pl.add_argument("--what", choices=[w.value for w in What],
                    help="the map: K(r) in --band (k, the default) or the detection range per band, "
                         "each class at its mean level (detection); bearing-dependent grids")
    pl.add_argument("--bearing", type=float, metavar="DEG",
                    help="also write STEM-section.png: TL over depth and range on the radial nearest "
                         "to this bearing, deg in [0, 360) (bearing-dependent grids)")
    pl.add_argument("--bathymetry", type=Path, metavar="FILE",
                    help="bathymetry file for the map's latitude-longitude panel (default: the file the "
                         "grid records, if found by its name and sha256)")
    pl.add_argument("--force", action="store_true", help="replace the outputs even if they are not PNGs")
    pl.set_defaults(func=run_plot)


def run_build(args) -> Report:
    area = envdata.load_area(args.area)
    out = args.out if args.out is not None else Path(f"{area.name}-{args.model}.nc")
    check_output_file(out, Kind.NETCDF, force=args.force)
    info = build_grid_file(area, out, model=args.model, workers=args.workers,
                           scheduler=args.scheduler, force=args.force, progress=want_progress(args))
    if info["up_to_date"]:
        summary = f"{info['file']}: up to date for area {info['area']} ({info['model']}); --force rebuilds"
    else:
        dims = ", ".join(f"{k} {v}" for k, v in info["dims"].items())
        summary = (f"wrote {info['file']}: area {info['area']}, model {info['model']} ({dims})\n"
                   f"  BELLHOP runs: {info['runs']} ({info['runs_reused']} reused), "
                   f"{info['bellhop_seconds']:.1f} s of BELLHOP, {info['wall_seconds']:.1f} s wall")
    return Report(summary, info)


def run_show(args) -> Report:
    ds = acoustics.open_grid(args.file)
    ranges_km = [r for r in (1, 5, 10, 30, 60, 110) if r * 1000 <= float(ds["range"].max())]
    lines = [f"{args.file}: area {ds.attrs['area']}, model {ds.attrs['model']}, "
             f"observer at {ds.attrs['observer_depth_m']:g} m",
             "  dims: " + ", ".join(f"{k} {v}" for k, v in ds.sizes.items()),
             f"  range {float(ds['range'][0]):g}-{float(ds['range'][-1]):g} m, "
             f"depth {float(ds['depth'][0]):g}-{float(ds['depth'][-1]):g} m",
             f"  created {ds.attrs.get('created', '?')}, source_hash {ds.attrs['source_hash'][:16]}...",
             f"  BELLHOP: {ds.attrs.get('bellhop_version', '-')}"]
    by_bearing = "bearing" in ds.dims
    if by_bearing:
        bottom = ds["bottom_depth_m"].values
        lines.append(f"  origin {ds.attrs['origin_lat_deg']:g} N, {ds.attrs['origin_lon_deg']:g} E; "
                     f"{ds.sizes['bearing']} radials; bottom {np.nanmin(bottom):.0f}-{np.nanmax(bottom):.0f} m; "
                     f"{np.mean(np.isnan(bottom)):.0%} of the range cells beyond land")
        lines.append("  K(r) dB at " + ", ".join(f"{r} km" for r in ranges_km)
                     + " (BELLHOP median over bearings / Urick; - where no bearing has K):")
    else:
        lines.append("  K(r) dB at " + ", ".join(f"{r} km" for r in ranges_km) + " (BELLHOP / Urick):")
    k_table = {}
    at_m = [r * 1000.0 for r in ranges_km]  # np.interp: xarray's .interp needs scipy
    for cls_name in ds["class"].values:
        for band in ds["band"].values:
            sel = {"class": cls_name, "band": band}
            k = ds["k_db"].sel(sel).values
            if by_bearing:  # (bearing, range): the median over the radials that have K there
                along = np.stack([np.interp(at_m, ds["range"].values, row) for row in k])
                finite = np.isfinite(along).any(axis=0)
                kb = np.full(len(at_m), np.nan)
                kb[finite] = np.nanmedian(along[:, finite], axis=0)
            else:
                kb = np.interp(at_m, ds["range"].values, k)
            ku = np.interp(at_m, ds["range"].values, ds["k_urick_db"].sel(sel).values)
            k_table[f"{cls_name}/{band}"] = {"k_db": [None if not np.isfinite(v) else round(float(v), 2) for v in kb],
                                             "k_urick_db": ku.round(2).tolist()}
            lines.append(f"    {cls_name:>5} {band:>5}: " + "  ".join(
                f"{'-' if not np.isfinite(a) else f'{a:.1f}':>7}/{b:6.1f}" for a, b in zip(kb, ku)))
    data = {"file": str(args.file), "attrs": {k: (v.item() if isinstance(v, np.generic) else v)
                                              for k, v in ds.attrs.items() if k != "area_json"},
            "dims": {k: int(v) for k, v in ds.sizes.items()},
            "classes": [str(c) for c in ds["class"].values], "bands": [str(b) for b in ds["band"].values],
            "ranges_km": ranges_km, "k": k_table}
    return Report("\n".join(lines), data)


def run_plot(args) -> Report:
    from acoustics.plot import plot_grid

    check_output_file(args.out, Kind.PNG, force=args.force)
    ds = acoustics.open_grid(args.file)
    if "bearing" in ds.dims:
        return _plot_bearing_grid(args, ds)
    for option, value in (("--bearing", args.bearing), ("--band", args.band), ("--what", args.what),
                          ("--bathymetry", args.bathymetry)):
        if value is not None:
            raise envdata.InputError(f"{args.file}: {option} is for a bearing-dependent grid; this grid has "
                                     f"no bearings (its area has no [origin]), its TL is the same along "
                                     f"every bearing")
    if args.cls_name is not None and args.cls_name not in ds["class"].values:
        raise envdata.InputError(f"{args.file}: --class {args.cls_name!r} is not a class of the grid "
                                 f"({', '.join(map(str, ds['class'].values))})")
    plot_grid(ds, args.out, cls_name=args.cls_name)
    return Report(f"wrote {args.out}", {"file": str(args.out)})


def _plot_bearing_grid(args, ds) -> Report:
    """The map, the bottom and the section of a bearing-dependent grid (acoustics.radialplots)."""
    from acoustics.gridbathymetry import find_bathymetry, load_around_origin
    from acoustics.radialplots import bearing_plot_paths, plot_bearing_grid

    check_plot_options(ds, cls_name=args.cls_name, band=args.band, bearing_deg=args.bearing)
    paths = bearing_plot_paths(args.out, section=args.bearing is not None)
    for path in paths.values():
        check_output_file(path, Kind.PNG, force=args.force)
    choice = find_bathymetry(ds, given=args.bathymetry, grid_path=args.file)
    bathymetry, note = None, ""
    if choice is not None:
        lat0, lon0 = float(ds.attrs["origin_lat_deg"]), float(ds.attrs["origin_lon_deg"])
        bathymetry = load_around_origin(choice, lat0, lon0, float(ds["range"].values[-1]))
        note = (f"{choice.how}; sha256 as the grid records" if choice.matches
                else "given; not the file the grid was built from (sha256 differs)")
    what = What(args.what or What.K)
    written = plot_bearing_grid(ds, args.out, what=what, cls_name=args.cls_name, band=args.band,
                                bearing_deg=args.bearing, bathymetry=bathymetry, bathymetry_note=note)
    lines = [f"wrote {path} ({key})" for key, path in written.items()]
    if choice is not None:
        lines.append(f"  bathymetry {choice.path} ({note})")
    else:
        lines.append("  no bathymetry file at hand: the map has no latitude-longitude panel "
                     "(--bathymetry FILE adds it)")
    data = {"files": {key: str(path) for key, path in written.items()}, "what": str(what),
            "bathymetry": None if choice is None else {"file": str(choice.path), "found": choice.how,
                                                       "matches_grid": choice.matches}}
    return Report("\n".join(lines), data)
