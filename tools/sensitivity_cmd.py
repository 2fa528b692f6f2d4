"""``tmakit sensitivity``: how much K(r) moves when the environment is not what the tables assumed.

    tmakit sensitivity AREA --members N [--perturb SPEC]... [--seed S] [--scheduler ADDR]
                       [--workers N] [--out FILE] [--tl] [--plot PNG] [--write-k-error TOML]

The science is in ``acoustics.sensitivity`` (perturbations in ``acoustics.sensitivity.perturb``);
this module parses, calls and reports.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path

import numpy as np
import xarray as xr

import envdata
from acoustics import sensitivity as sens
from acoustics.bellhop.exe import find_bellhop
from acoustics.build import remove_cache, resume_dir
from acoustics.sensitivity.perturb import default_perturbations, parse_spec
from tools.report import Report, want_progress


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
    p.add_argument("--ranges-km", default="5,10,20,50,100",
                   help="true ranges for the level-ranging error, km (default %(default)s)")
    p.add_argument("--range-min-km", type=float, help="summary window start, km (default: first range)")
    p.add_argument("--range-max-km", type=float, help="summary window end, km (default: last range)")
    p.add_argument("--reciprocity-min-depth-m", type=float, default=sens.RECIPROCITY_MIN_DEPTH_M,
                   help="classes at least this deep get K by reciprocity (default %(default)g m)")
    p.set_defaults(func=run_sensitivity)


def _ranges_m(text: str) -> list[float]:
    try:
        values = [float(v) * 1000.0 for v in text.split(",") if v.strip()]
    except ValueError:
        raise envdata.InputError(f"--ranges-km: expected comma-separated numbers, got {text!r}") from None
    if not values or any(not (np.isfinite(v) and v > 0) for v in values):
        raise envdata.InputError(f"--ranges-km: need positive ranges, got {text!r}")
    return values


def run_study_file(area_name: str, *, members: int, perturb: list[str] | None = None, seed: int = 0,
                   scheduler: str | None = None, workers: int = 1, out: Path | None = None,
                   tl: bool = False, plot: Path | None = None, write_k_error: Path | None = None,
                   ranges_km: str = "5,10,20,50,100", range_min_km: float | None = None,
                   range_max_km: float | None = None,
                   reciprocity_min_depth_m: float = sens.RECIPROCITY_MIN_DEPTH_M,
                   progress: bool = False) -> dict:
    """Run a study from the command-line options, write its files and return what was done."""
    if workers < 1:
        raise envdata.InputError(f"--workers: must be >= 1, got {workers}")
    area_file = envdata.area_path(area_name)
    area = envdata.load_area(area_name)
    perturbations = ([p for text in perturb for p in parse_spec(text)] if perturb
                     else default_perturbations(area))
    eval_ranges = _ranges_m(ranges_km)
    spec = sens.StudySpec(area=area, perturbations=tuple(perturbations), members=members, seed=seed, tl=tl,
                          reciprocity_min_depth_m=reciprocity_min_depth_m)  # validates before any output
    out = out if out is not None else Path(f"{area.name}-sensitivity.nc")
    digest = spec.digest(find_bellhop().sha256)
    cache_dir = resume_dir(out, digest)
    stats = sens.StudyStats()
    ds = sens.run_study(area, perturbations, members=members, seed=seed, tl=tl, scheduler=scheduler,
                        workers=workers, cache_dir=cache_dir, progress=progress, stats=stats,
                        reciprocity_min_depth_m=reciprocity_min_depth_m)
    summary = sens.summarize(ds, eval_ranges_m=eval_ranges,
                             range_min_m=None if range_min_km is None else range_min_km * 1000.0,
                             range_max_m=None if range_max_km is None else range_max_km * 1000.0)
    merged = xr.merge([ds, summary], combine_attrs="override")
    sens.write_study(merged, out)
    files = {"study": str(out)}
    if plot is not None:
        from acoustics.sensitivity.plot import plot_sd_map, plot_spread

        plot_spread(ds, plot)
        files["plot"] = str(plot)
        if tl:
            sd_map = plot.with_name(f"{plot.stem}-sd-map.png")
            plot_sd_map(ds, sd_map)
            files["sd_map"] = str(sd_map)
    measured = sens.k_error_by_class(summary)
    if write_k_error is not None:
        sens.write_k_error(area_file, measured, write_k_error)
        files["area_with_k_error"] = str(write_k_error)
    remove_cache(cache_dir)
    per_cb = {}
    for cls_name in summary["class"].values:
        for band in summary["band"].values:
            sel = {"class": cls_name, "band": band}
            per_cb[f"{cls_name}/{band}"] = {
                "bias_db_median": round(float(np.median(summary["k_bias_db"].sel(sel))), 3),
                "sd_db_median": round(float(np.median(summary["k_sd_db"].sel(sel))), 3),
                "rms_error_db": round(float(summary["k_rms_error_db"].sel(sel)), 3),
                "offset_sd_db": round(float(summary["k_offset_sd_db"].sel(sel)), 3),
                "residual_rms_db": round(float(summary["k_residual_rms_db"].sel(sel)), 3),
                "constant_fraction": round(float(summary["k_constant_fraction"].sel(sel)), 3)}
    ranging = {}
    for c in summary["class"].values:
        bias = summary["range_bias_m"].sel({"class": c}).values
        rms = summary["range_rms_m"].sel({"class": c}).values
        ranging[str(c)] = {f"{r / 1000:g}": {"bias_m": round(float(bias[i]), 1), "rms_m": round(float(rms[i]), 1)}
                           for i, r in enumerate(summary["eval_range"].values)}
    drivers = {}
    for ic, cls_name in enumerate(summary["class"].values):
        corr = summary["k_offset_correlation"].values[ic]
        order = [j for j in np.argsort(-np.abs(np.nan_to_num(corr))) if np.isfinite(corr[j])][:3]
        drivers[str(cls_name)] = {str(summary["parameter"].values[j]): round(float(corr[j]), 2) for j in order}
    return {"files": files, "offset_drivers": drivers, "area": area.name, "members": members, "seed": seed,
            "perturbations": [p.describe() for p in perturbations],
            "k_method": ds.attrs["k_method"], "members_reused": stats.members_reused,
            "workers": stats.workers, "bellhop_seconds": round(stats.bellhop_seconds, 3),
            "wall_seconds": round(stats.wall_seconds, 3),
            "k_error_sd_db": {k: round(v, 3) for k, v in measured.items()},
            "k_error_sd_db_area_file": {c.name: c.k_error_sd_db for c in area.classes},
            "k": per_cb, "range_error": ranging,
            "window_km": [summary.attrs["summary_range_min_m"] / 1000.0,
                          summary.attrs["summary_range_max_m"] / 1000.0]}


def _quiet_dask(verbose: int) -> None:
    """Dask's own loggers log at INFO into our stderr handler; keep them to warnings unless -vv."""
    import distributed  # noqa: F401  (its import configures the 'distributed' loggers)

    if verbose < 2:
        logging.getLogger("distributed").setLevel(logging.WARNING)


def run_sensitivity(args) -> Report:
    if args.scheduler is not None:
        _quiet_dask(getattr(args, "verbose", 0) or 0)
    info = run_study_file(args.area, members=args.members, perturb=args.perturb, seed=args.seed,
                          scheduler=args.scheduler, workers=args.workers, out=args.out, tl=args.tl,
                          plot=args.plot, write_k_error=args.write_k_error, ranges_km=args.ranges_km,
                          range_min_km=args.range_min_km, range_max_km=args.range_max_km,
                          reciprocity_min_depth_m=args.reciprocity_min_depth_m, progress=want_progress(args))
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
