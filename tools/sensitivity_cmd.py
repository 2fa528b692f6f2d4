"""``tmakit sensitivity``: how much K(r) moves when the environment is not what the tables assumed.

    tmakit sensitivity AREA --members N [--perturb SPEC]... [--seed S] [--scheduler ADDR]
                       [--workers N] [--out FILE] [--tl] [--plot PNG] [--write-k-error TOML] [--into GRID]

The science is in ``acoustics.sensitivity`` (perturbations in ``acoustics.sensitivity.perturb``);
this module parses, calls and reports.
"""

from __future__ import annotations

import logging
import math
import os
from pathlib import Path

from envdata.errors import InputError
from tools.outputs import Kind, check_output_file
from tools.report import Report, want_progress

#: ``acoustics.builder.plan.RECIPROCITY_MIN_DEPTH_M`` as the help shows it (the module imports
#: xarray; tests/tools/test_startup.py checks the two agree). The option's default is None: the
#: library's own value.
RECIPROCITY_MIN_DEPTH_M_SHOWN = 50.0


def register(sub, common) -> None:
    p = sub.add_parser(
        "sensitivity", parents=[common], help="environmental sensitivity study of K(r) (ensemble)",
        description="Run an ensemble of perturbed environments (sound-speed profile, bottom, water "
                    "depth, source and observer depths) through BELLHOP, on this machine or on a "
                    "Dask cluster, and summarise how K(r) moves: bias, sd, constant-offset share, "
                    "and the range error of level-based ranging (Grinenkov & Mashoshin eq. 20).")
    p.add_argument("area", metavar="AREA", help="built-in area name or TOML path")
    p.add_argument("--members", type=int, default=16, help="ensemble size (default %(default)s)")
    p.add_argument("--perturb", action="append", metavar="SPEC", default=None,
                   help="KIND:KEY=VALUE,... or a TOML file of [[perturb]] tables; repeatable "
                        "(default: the set in docs/sensitivity.md)")
    p.add_argument("--seed", type=int, default=0, help="member m draws from default_rng([seed, m])")
    p.add_argument("--scheduler", metavar="ADDR", help="run the members on this Dask distributed scheduler "
                                                        "(default: threads on this machine)")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="members computed at once on this machine (default: the number of cores; "
                        "ignored with --scheduler)")
    p.add_argument("--out", type=Path, help="study netCDF to write (default: AREA-sensitivity.nc)")
    p.add_argument("--tl", action="store_true",
                   help="full grid per member; keep tl_db(member, class, band, depth, range)")
    p.add_argument("--plot", type=Path, metavar="PNG",
                   help="spread of K(r) per class and band; with --tl also PNG-sd-map.png")
    p.add_argument("--write-k-error", type=Path, metavar="TOML",
                   help="write a copy of the area file with the measured k_error_sd_db per class")
    p.add_argument("--into", type=Path, metavar="GRID",
                   help="write the measured k_error_sd_db(class, band[, bearing], range) into this grid of "
                        "the same area (the trackers then use it)")
    p.add_argument("--ranges-km", default="5,10,20,50,100",
                   help="true ranges for the level-ranging error, km (default %(default)s)")
    p.add_argument("--range-min-km", type=float, help="summary window start, km (default: first range)")
    p.add_argument("--range-max-km", type=float, help="summary window end, km (default: last range)")
    p.add_argument("--reciprocity-min-depth-m", type=float, default=None, metavar="M",
                   help="classes at least this deep get K by reciprocity (default: the grids' "
                        f"threshold, {RECIPROCITY_MIN_DEPTH_M_SHOWN:g} m)")
    p.add_argument("--force", action="store_true",
                   help="replace outputs even if they are not tmakit's kind of file")
    p.set_defaults(func=run_sensitivity)


def _quiet_dask(verbose: int) -> None:
    """Dask's own loggers log at INFO into our stderr handler; keep them to warnings unless -vv."""
    import distributed  # noqa: F401  (its import configures the 'distributed' loggers)

    if verbose < 2:
        logging.getLogger("distributed").setLevel(logging.WARNING)


def _ranges_km(text: str) -> tuple[float, ...]:
    """--ranges-km as numbers, km."""
    try:
        values = tuple(float(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise InputError(f"--ranges-km: expected comma-separated numbers, got {text!r}") from None
    if not values or any(not (math.isfinite(v) and v > 0) for v in values):
        raise InputError(f"--ranges-km: need positive ranges, got {text!r}")
    return values


def run_sensitivity(args) -> Report:
    import envdata
    from acoustics import sensitivity as sens

    out = args.out if args.out is not None else Path(f"{envdata.load_area(args.area).name}-sensitivity.nc")
    kinds = {"study": Kind.NETCDF, "plot": Kind.PNG, "sd_map": Kind.PNG, "spread": Kind.PNG,
             "area_with_k_error": Kind.AREA_TOML, "grid_with_k_error": Kind.NETCDF}
    radial = envdata.load_area(args.area).is_bearing_dependent
    for name, path in sens.output_files(out, plot=args.plot, tl=args.tl, write_k_error=args.write_k_error,
                                        into=args.into, bearing_dependent=radial).items():
        check_output_file(path, kinds[name], force=args.force)
    if args.scheduler is not None:
        _quiet_dask(getattr(args, "verbose", 0) or 0)
    for flag, value, ok, bound in (("--members", args.members, 1 <= args.members <= 100_000, "in [1, 100000]"),
                                   ("--seed", args.seed, 0 <= args.seed < 2 ** 63, "in [0, 2^63)"),
                                   ("--workers", args.workers, args.workers >= 1, ">= 1")):
        if not ok:
            raise InputError(f"{flag}: must be {bound}, got {value}")
    ranges_km = _ranges_km(args.ranges_km)
    reciprocity_min_depth_m = (sens.RECIPROCITY_MIN_DEPTH_M if args.reciprocity_min_depth_m is None
                               else args.reciprocity_min_depth_m)
    perturbations = ([p for text in args.perturb for p in sens.parse_spec(text, f"--perturb {text.strip()}")]
                     if args.perturb else None)
    info = sens.run_study_file(args.area, members=args.members, perturbations=perturbations, seed=args.seed,
                          scheduler=args.scheduler, workers=args.workers, out=out, tl=args.tl,
                          plot=args.plot, write_k_error=args.write_k_error, ranges_km=ranges_km,
                          range_min_km=args.range_min_km, range_max_km=args.range_max_km,
                          reciprocity_min_depth_m=reciprocity_min_depth_m, progress=want_progress(args),
                          into=args.into)
    lines = [f"wrote {info['files']['study']}: area {info['area']}, {info['members']} members "
             f"(seed {info['seed']}, {info['members_reused']} reused), {info['workers']} workers, "
             f"{info['bellhop_seconds']:.1f} s of BELLHOP, {info['wall_seconds']:.1f} s wall",
             "  perturbations: " + "; ".join(info["perturbations"]),
             f"  K(r) vs nominal over {info['window_km'][0]:g}-{info['window_km'][1]:g} km "
             "(median bias / median sd / rms, constant-offset sd, residual, constant share):"]
    for key, v in info["k"].items():
        lines.append(f"    {key:>10}: {v['bias_db_median']:+6.2f} / {v['sd_db_median']:5.2f} / "
                     f"{v['rms_error_db']:5.2f} dB, offset sd {v['offset_sd_db']:5.2f} dB, residual "
                     f"{v['residual_rms_db']:5.2f} dB, constant {100 * v['constant_fraction']:3.0f} %")
    lines.append("  measured k_error_sd_db (area file): " + ", ".join(
        f"{c} {v:.2f} ({info['k_error_sd_db_area_file'][c]:g}) dB" for c, v in info["k_error_sd_db"].items()))
    for c, by_bearing in info["k_sd_db_median_by_bearing"].items():
        lines.append(f"    median sd of K by bearing, {c}: " + ", ".join(
            f"{b} deg {v:.2f}" if v is not None else f"{b} deg -" for b, v in by_bearing.items()) + " dB")
    lines.append("  parameters most correlated with the constant offset:")
    for c, top in info["offset_drivers"].items():
        lines.append(f"    {c:>5}: " + ", ".join(f"{k} {v:+.2f}" for k, v in top.items()))
    lines.append("  level-ranging (eq. 20) rms error with nominal tables:")
    for c, by_range in info["range_error"].items():
        lines.append(f"    {c:>5}: " + "  ".join(f"{r} km {v['rms_m'] / 1000:.2f} km" for r, v in by_range.items()))
    for name, path in info["files"].items():
        if name != "study":
            lines.append(f"  wrote {path}")
    return Report("\n".join(lines), info)
