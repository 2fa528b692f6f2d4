"""``tmakit demo``: the main job on the built-in default area, and the map of a bearing-dependent
area (the built-in shelf break)."""

from __future__ import annotations

import os
from pathlib import Path

from tools.grids_cmd import grid_file_data
from tools.outputs import Kind, check_output_dir, check_output_file
from tools.pdtext import reach_data, reach_lines
from tools.report import Report, want_progress

#: The built-in area whose bearing-dependent grid the demo maps.
MAP_AREA = "shelf-break"
#: Its figures, each written as MAP_AREA-NAME.png (the P_D map, any band, with MAP_AREA-pd.nc beside
#: it: the same on latitude and longitude for a GIS).
MAP_FIGURES = ("k", "detection", "pd", "bottom")
#: The sonar its detection and P_D maps listen with (envdata/sonars/): the area's own, Grinenkov &
#: Mashoshin's 42 dB array in open-ocean noise, hears every class far beyond the 30 km tables
#: (docs/planning.md), a map that would show only the tables' edge.
MAP_SONAR = "omni-buoy"


def register(sub, common) -> None:
    p = sub.add_parser("demo", parents=[common],
                       help=f"build and plot the default area's grids, and map the {MAP_AREA} area")
    p.add_argument("--out", type=Path, default=Path("out/demo"), metavar="DIR")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    p.add_argument("--force", action="store_true",
                   help="replace files in DIR even if they are not tmakit's kind of file")
    p.set_defaults(func=run)


def run(args) -> Report:
    import acoustics
    import envdata
    from acoustics.builder.gridfile import build_grid_file
    from acoustics.grid.pdmap import table_reach
    from envdata.receiver import load_receiver

    check_output_dir(args.out)
    grid_path = args.out / f"{envdata.DEFAULT_AREA}-bellhop.nc"
    check_output_file(grid_path, Kind.NETCDF, force=args.force)
    area = envdata.load_area(envdata.DEFAULT_AREA)
    for cls in area.classes:
        check_output_file(args.out / f"{envdata.DEFAULT_AREA}-{cls.name}.png", Kind.PNG, force=args.force)
    map_grid = args.out / f"{MAP_AREA}-bellhop.nc"
    check_output_file(map_grid, Kind.NETCDF, force=args.force)
    map_pngs = {what: args.out / f"{MAP_AREA}-{what}.png" for what in MAP_FIGURES}
    for png in map_pngs.values():
        check_output_file(png, Kind.PNG, force=args.force)
    map_pngs["pd-netcdf"] = check_output_file(args.out / f"{MAP_AREA}-pd.nc", Kind.NETCDF, force=args.force)
    args.out.mkdir(parents=True, exist_ok=True)
    info = build_grid_file(envdata.DEFAULT_AREA, grid_path, workers=args.workers,
                           progress=want_progress(args))
    # matplotlib: imported only by the commands that draw
    from acoustics.plots.gridplots import PlotRequest, plot_grid
    from acoustics.plots.radialplots import plot_map_set

    tables = acoustics.open_tables(grid_path)
    plots = []
    for cls_name in tables.class_names:
        png = args.out / f"{envdata.DEFAULT_AREA}-{cls_name}.png"
        plot_grid(tables, png, PlotRequest(cls_name=cls_name))
        plots.append(str(png))
    map_info = build_grid_file(MAP_AREA, map_grid, workers=args.workers, progress=want_progress(args))
    map_tables = acoustics.open_tables(map_grid).with_receiver(load_receiver(MAP_SONAR))
    plot_map_set(map_tables, map_pngs, grid_path=map_grid)
    plots.extend(str(p) for p in map_pngs.values())
    reach = table_reach(map_tables)
    state = "up to date" if info.up_to_date else f"built in {info.wall_seconds:.1f} s"
    map_state = "up to date" if map_info.up_to_date else f"built in {map_info.wall_seconds:.1f} s"
    summary = (f"demo: area {envdata.DEFAULT_AREA}: grid {grid_path} ({state})\n"
               f"      area {MAP_AREA}: grid {map_grid} ({map_state})\n"
               + "\n".join(f"  plot {p}" for p in plots)
               + f"\n  maps heard by {map_tables.sonar_label()}"
               + f"\n  where P_D falls below 0.1 on {MAP_AREA}'s tables:\n" + "\n".join(reach_lines(reach, "    ")))
    return Report(summary, {"grid": grid_file_data(info), "map_grid": grid_file_data(map_info), "plots": plots,
                            "map_sonar": MAP_SONAR, "map_reach": reach_data(reach)})
