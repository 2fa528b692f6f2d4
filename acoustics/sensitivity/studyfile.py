"""A sensitivity study as files: run it (resumable), summarise it, write its outputs all or none.

The study file (study and summaries merged), the K(r) spread plot (and with ``tl`` the sd map)
and the area copy with the measured ``k_error_sd_db`` are written together: all of them, or,
if one cannot be written, none. Finished members are kept in ``.NAME.partial-HASH/`` beside the
study file while members remain to be computed, so an interrupted study resumes; once every
member is in, the folder goes, whether the outputs could be written or not.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

import envdata
from acoustics.bellhop.exe import find_bellhop
from acoustics.builder.gridfile import remove_cache, resume_dir
from acoustics.sensitivity import writeback
from acoustics.sensitivity.face import study_face
from acoustics.sensitivity.files import write_study
from acoustics.sensitivity.perturbspec import default_perturbations
from acoustics.sensitivity.spec import RECIPROCITY_MIN_DEPTH_M, StudySpec
from acoustics.sensitivity.study import StudyStats, run_study
from acoustics.sensitivity.summaries import k_error_by_class, summarize
from envdata.files import atomic_paths


def _over_bearings(values: xr.DataArray, rms: bool = False) -> float:
    """One number of a (class, band) summary: itself, or over the bearings of a bearing-dependent
    study (rms for sds and rms errors, mean otherwise; bearings without K left out)."""
    v = np.asarray(values.values, dtype=float).ravel()
    v = v[np.isfinite(v)]
    if v.size == 0:
        return float("nan")
    return float(np.sqrt(np.mean(v ** 2))) if rms else float(np.mean(v))


def output_files(out: Path, *, plot: Path | None = None, tl: bool = False,
                 write_k_error: Path | None = None, into: Path | None = None,
                 bearing_dependent: bool = False) -> dict[str, str]:
    """The files a study writes: ``{"study": ..., "plot": ..., "spread": ..., "sd_map": ...,
    "area_with_k_error": ..., "grid_with_k_error": ...}``.

    With ``plot`` the K spread per class and band (for a bearing-dependent area the polar map
    of the sd of K, and ``STEM-spread.png`` K's spread along the bearing where it moves most);
    with ``tl`` also ``STEM-sd-map.png``, the sd of TL over depth and range.
    """
    files = {"study": str(out)}
    if plot is not None:
        files["plot"] = str(plot)
        if bearing_dependent:
            files["spread"] = str(Path(plot).with_name(f"{Path(plot).stem}-spread.png"))
        if tl:
            files["sd_map"] = str(Path(plot).with_name(f"{Path(plot).stem}-sd-map.png"))
    if write_k_error is not None:
        files["area_with_k_error"] = str(write_k_error)
    if into is not None:
        files["grid_with_k_error"] = str(into)
    return files


def run_study_file(area_name: str, *, members: int, perturbations=None, seed: int = 0,
                   scheduler: str | None = None, workers: int = 1, out: Path | None = None,
                   tl: bool = False, plot: Path | None = None, write_k_error: Path | None = None,
                   ranges_km: tuple[float, ...] = (5.0, 10.0, 20.0, 50.0, 100.0),
                   range_min_km: float | None = None,
                   range_max_km: float | None = None,
                   reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M,
                   progress: bool = False, into: Path | None = None) -> dict:
    """Run a study, write its files and return what was done.

    ``perturbations`` (a list of `Perturbation`; default the area's defaults); ``ranges_km`` where
    the range error is evaluated, km.

    ``out`` defaults to ``AREA-sensitivity.nc``; the keys of the result are what
    ``tmakit sensitivity`` reports (``files``, ``k``, ``range_error``, ``k_error_sd_db``, ...).
    ``into`` names a grid of the same area to write the measured ``k_error_sd_db(class, band[,
    bearing], range)`` into (checked before the study runs, replaced with the other outputs).
    """
    if workers < 1:
        raise envdata.InputError(f"workers: must be >= 1, got {workers}")
    area_file = envdata.area_path(area_name)
    area = envdata.load_area(area_name)
    perturbations = list(perturbations) if perturbations else default_perturbations(area)
    eval_ranges = [float(r) * 1000.0 for r in ranges_km]
    if not eval_ranges or not all(np.isfinite(r) and r > 0 for r in eval_ranges):
        raise envdata.InputError(f"evaluation ranges: need positive ranges, got {list(ranges_km)} km")
    spec = StudySpec(area=area, perturbations=tuple(perturbations), members=members, seed=seed, tl=tl,
                          reciprocity_min_depth_m=reciprocity_min_depth_m)  # validates before any output
    out = out if out is not None else Path(f"{area.name}-sensitivity.nc")
    into_tables = None
    if into is not None:  # a grid that cannot take the result is refused before the members run
        from acoustics.sensitivity.intogrid import check_into_grid

        into_tables = check_into_grid(into, area)
    digest = spec.digest(find_bellhop().sha256)
    cache_dir = resume_dir(out, digest)
    stats = StudyStats()
    ds = run_study(area, perturbations, members=members, seed=seed, tl=tl, scheduler=scheduler,
                        workers=workers, cache_dir=cache_dir, progress=progress, stats=stats,
                        reciprocity_min_depth_m=reciprocity_min_depth_m)
    study = study_face(ds, str(out))
    summary = summarize(study, eval_ranges_m=eval_ranges,
                             range_min_m=None if range_min_km is None else range_min_km * 1000.0,
                             range_max_m=None if range_max_km is None else range_max_km * 1000.0)
    merged = xr.merge([ds, summary], combine_attrs="override")
    measured = k_error_by_class(summary)
    radial = area.is_bearing_dependent
    files = output_files(out, plot=plot, tl=tl, write_k_error=write_k_error, into=into, bearing_dependent=radial)
    into_grid = None
    if into_tables is not None:
        from acoustics.sensitivity.intogrid import k_error_grid

        into_grid = k_error_grid(into_tables, summary, study, Path(out).name)
    try:
        with atomic_paths([Path(p) for p in files.values()]) as temps:
            tmp = dict(zip(files, temps))
            write_study(merged, tmp["study"], atomic=False)
            if "plot" in files:
                from acoustics.sensitivity import plot as plots

                if radial:
                    bearing = plots.spread_bearing_deg(summary)
                    plots.plot_polar_sd(study, summary, tmp["plot"], atomic=False)
                    plots.plot_spread_along(study, bearing, tmp["spread"], atomic=False)
                    if "sd_map" in files:
                        j = int(np.argmin(np.abs(study.bearing_deg - bearing)))
                        plots.plot_sd_map(study.along(j), tmp["sd_map"], atomic=False)
                else:
                    plots.plot_spread(study, tmp["plot"], atomic=False)
                    if "sd_map" in files:
                        plots.plot_sd_map(study, tmp["sd_map"], atomic=False)
            if into_grid is not None:
                from acoustics.sensitivity.intogrid import write_k_error_grid

                write_k_error_grid(into_grid, tmp["grid_with_k_error"], atomic=False)
            if "area_with_k_error" in files:
                writeback.write_k_error(area_file, measured, tmp["area_with_k_error"], atomic=False)
    finally:
        remove_cache(cache_dir)  # every member is in: nothing left to resume
    per_cb = {}
    for cls_name in summary["class"].values:
        for band in summary["band"].values:
            sel = {"class": cls_name, "band": band}
            per_cb[f"{cls_name}/{band}"] = {
                "bias_db_median": round(float(np.nanmedian(summary["k_bias_db"].sel(sel))), 3),
                "sd_db_median": round(float(np.nanmedian(summary["k_sd_db"].sel(sel))), 3),
                "rms_error_db": round(_over_bearings(summary["k_rms_error_db"].sel(sel), rms=True), 3),
                "offset_sd_db": round(_over_bearings(summary["k_offset_sd_db"].sel(sel), rms=True), 3),
                "residual_rms_db": round(_over_bearings(summary["k_residual_rms_db"].sel(sel), rms=True), 3),
                "constant_fraction": round(_over_bearings(summary["k_constant_fraction"].sel(sel)), 3)}
    ranging = {}
    for c in summary["class"].values:
        # a bearing-dependent study: the rms over bearings (per bearing in the study file)
        bias = summary["range_bias_m"].sel({"class": c})
        rms = summary["range_rms_m"].sel({"class": c})
        if "bearing" in rms.dims:
            bias = bias.mean("bearing", skipna=True)
            rms = np.sqrt((rms ** 2).mean("bearing", skipna=True))
        bias, rms = bias.values, rms.values
        ranging[str(c)] = {f"{r / 1000:g}": {"bias_m": round(float(bias[i]), 1), "rms_m": round(float(rms[i]), 1)}
                           for i, r in enumerate(summary["eval_range"].values)}
    drivers = {}
    for ic, cls_name in enumerate(summary["class"].values):
        corr = summary["k_offset_correlation"].values[ic]
        order = [j for j in np.argsort(-np.abs(np.nan_to_num(corr))) if np.isfinite(corr[j])][:3]
        drivers[str(cls_name)] = {str(summary["parameter"].values[j]): round(float(corr[j]), 2) for j in order}
    by_bearing = {}
    if radial:
        for c in summary["class"].values:
            sd = summary["k_sd_db"].sel({"class": c})
            by_bearing[str(c)] = {f"{b:g}": round(float(np.nanmedian(sd.sel(bearing=b))), 3)
                                  if np.isfinite(sd.sel(bearing=b)).any() else None
                                  for b in summary["bearing"].values}
    return {"files": files, "offset_drivers": drivers, "k_sd_db_median_by_bearing": by_bearing,
            "area": area.name, "members": members, "seed": seed,
            "perturbations": [p.describe() for p in perturbations],
            "k_method": ds.attrs["k_method"], "members_reused": stats.members_reused,
            "workers": stats.workers, "bellhop_seconds": round(stats.bellhop_seconds, 3),
            "wall_seconds": round(stats.wall_seconds, 3),
            "k_error_sd_db": {k: round(v, 3) for k, v in measured.items()},
            "k_error_sd_db_area_file": {c.name: c.k_error_sd_db for c in area.classes},
            "k": per_cb, "range_error": ranging,
            "window_km": [summary.attrs["summary_range_min_m"] / 1000.0,
                          summary.attrs["summary_range_max_m"] / 1000.0]}
