"""``tmakit demo``: the main job on the built-in default area."""

from __future__ import annotations

import os
from pathlib import Path

import acoustics
import envdata
from acoustics.build import build_grid_file
from acoustics.plot import plot_grid
from tools.outputs import Kind, check_output_dir, check_output_file
from tools.report import Report, want_progress


def register(sub, common) -> None:
    p = sub.add_parser("demo", parents=[common], help="build and plot the default area's grids")
    p.add_argument("--out", type=Path, default=Path("out/demo"), metavar="DIR")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    p.add_argument("--force", action="store_true",
                   help="replace files in DIR even if they are not tmakit's kind of file")
    p.set_defaults(func=run)


def run(args) -> Report:
    check_output_dir(args.out)
    grid_path = args.out / f"{envdata.DEFAULT_AREA}-bellhop.nc"
    check_output_file(grid_path, Kind.NETCDF, force=args.force)
    area = envdata.load_area(envdata.DEFAULT_AREA)
    for cls in area.classes:
        check_output_file(args.out / f"{envdata.DEFAULT_AREA}-{cls.name}.png", Kind.PNG, force=args.force)
    args.out.mkdir(parents=True, exist_ok=True)
    info = build_grid_file(envdata.DEFAULT_AREA, grid_path, workers=args.workers,
                           progress=want_progress(args))
    ds = acoustics.open_grid(grid_path)
    plots = []
    for cls_name in ds["class"].values:
        png = args.out / f"{envdata.DEFAULT_AREA}-{cls_name}.png"
        plot_grid(ds, png, cls_name=str(cls_name))
        plots.append(str(png))
    state = "up to date" if info["up_to_date"] else f"built in {info['wall_seconds']:.1f} s"
    summary = (f"demo: area {envdata.DEFAULT_AREA}: grid {grid_path} ({state})\n"
               + "\n".join(f"  plot {p}" for p in plots))
    return Report(summary, {"grid": info, "plots": plots})
