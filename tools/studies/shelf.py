"""Tracking in a range-dependent area: the bearing-dependent grid against the usual shortcut.

A target is simulated in the built-in ``shelf-break`` area, its levels computed by BELLHOP along
each cycle's true target-to-observer path (``truth="bellhop"``, `acoustics.builder.truthk`: no
table, the observer moving away from where the grid was computed) or read from the
bearing-dependent grid (``truth="tables"``, the sea as the tables know it). Each run's target is
drawn from its class (`tools.studies.calibration.class_draws`: speed, P0, and the dK of eq. 31
once per run, as G&M's section 4). The same measurements are then tracked twice, by the same
trackers:

- with the bearing-dependent grid;
- with an isotropic grid built from the origin's own sound-speed profile and water depth, as
  if the whole area were that one column over a flat bottom (the usual shortcut:
  `origin_area`).

The trackers: the ML motion analysis of Grinenkov & Mashoshin (``ml``, the true class
hypothesis), the particle filter with bearings and SPL of Iglesis & de Montella with the levels'
lasting errors integrated out (``rpf``, `tracker.levels`), and the filter on bearings alone
(``bot``, the reference neither should fall behind). The position error of each is averaged over
the runs (RMSE against time), and its stated sds are checked against the truth: the coverage of
the 90 % intervals of range, course and speed after `LATE_MIN` (`tools.studies.calibration`).
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.builder.gridfile import build_grid_file
from acoustics.grid.formats import RESULT_FORMAT
from envdata.area import Area, Water
from envdata.areafile import load_area
from envdata.files import atomic_paths
from envdata.radials import area_radials
from envdata.ssp import SoundSpeedProfile
from tools.studies.calibration import class_draws
from tools.studies.trackerrors import FILTER_PARTICLES, LEVEL_SD_DB, ml_track, rpf_config, rpf_track
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch

AREA = "shelf-break"
SCENARIO = "shelf-tv"
GRIDS = ("bearing", "isotropic")
METHODS = ("ml", "rpf", "bot")
TRUTHS = ("bellhop", "tables")
#: The stated sds are checked from this minute on, min.
LATE_MIN = 10.0
#: Times (min after the first cycle) at which the summary gives the RMSE.
REPORT_MIN = (5, 10, 20, 30)
#: Where the summary compares the two grids' K(r) of the target's class in the first band.
K_BEARINGS_DEG = (0.0, 90.0, 150.0, 180.0)
K_RANGES_M = (5000.0, 10000.0, 15000.0, 20000.0)


def origin_area(area: Area) -> Area:
    """The usual shortcut: ``area`` as one column over a flat bottom, the origin's own.

    The water depth is the bottom at the origin, the sound-speed profile the section's column
    nearest the origin cut at that depth (linear in depth), and the radials go: a grid without
    bearings.
    """
    radial = area_radials(area)[0]
    depth = float(np.interp(0.0, radial.range_m, radial.bottom_depth_m))
    column = radial.speed_mps[:, int(np.argmin(np.abs(radial.ssp_range_m)))]
    z = radial.ssp_depth_m
    keep = z < depth
    ssp = SoundSpeedProfile(depth_m=tuple(float(v) for v in np.append(z[keep], depth)),
                            speed_mps=tuple(float(v) for v in np.append(
                                np.round(column[keep], 3), round(float(np.interp(depth, z, column)), 3))),
                            kind="table")
    doc = dataclasses.replace(area, water=Water(depth_m=depth, ssp=ssp), origin=None, bearings=None,
                              name=f"{area.name}-origin",
                              description=f"{area.name} as its origin's column over a flat bottom "
                                          f"({depth:.0f} m): the usual shortcut").to_dict()
    from envdata.areafile import parse_area

    return parse_area(doc, f"{area.name}-origin")


def run(*, runs: int, out_dir: str | Path, seed: int = 0, workers: int = 2, n_particles: int = FILTER_PARTICLES,
        progress: bool = False, truth: str = "bellhop", area: Area | None = None) -> dict:
    """The study: build (or reuse) both grids in ``out_dir/grids``, simulate ``runs`` runs (levels
    from ``truth``: BELLHOP along the true paths, its runs kept in ``out_dir/grids/truth-runs``, or
    the bearing-dependent grid), track them with both; write ``shelf_rmse.csv``, ``shelf.json`` and
    ``shelf_rmse.png`` (all or none) and return the summary. ``area``: the built-in shelf-break
    area with other settings (benchmarks that vary how its tables are made); by default as built in."""
    if truth not in TRUTHS:
        raise ValueError(f"truth must be one of {', '.join(TRUTHS)}, got {truth!r}")
    start = time.perf_counter()
    out = Path(out_dir)
    area = load_area(AREA) if area is None else area
    if area.name != AREA:
        raise ValueError(f"the shelf study's area is {AREA!r}, got {area.name!r}")
    grids = {"bearing": build_grid_file(area, out / "grids" / f"{AREA}-bellhop.nc", workers=workers,
                                        progress=progress).file,
             "isotropic": build_grid_file(origin_area(area), out / "grids" / f"{AREA}-origin-bellhop.nc",
                                          workers=workers, progress=progress).file}
    from acoustics.grid.opentables import open_tables

    tables = {name: open_tables(path) for name, path in grids.items()}
    sc = load_scenario(SCENARIO)
    sea = tables["bearing"]
    cls_index = sea.class_index(sc.target_class)
    band = 0  # FB1, the band heard farthest
    rng = np.random.default_rng(seed)
    provider = None
    if truth == "bellhop":
        from acoustics.builder.truthk import BellhopTruth

        provider = BellhopTruth(area, cache_dir=out / "grids" / "truth-runs", workers=workers)
    t0 = time.perf_counter()
    sim = simulate_batch(sc, sea, rng, **class_draws(sc, sea.classes[cls_index], runs, rng), k_provider=provider)
    truth_seconds = time.perf_counter() - t0
    minutes = (sim.t_s - sim.t_s[0]) / 60.0
    late = minutes >= LATE_MIN
    errors, calibration = {}, {}
    for name, tab in tables.items():
        ic = tab.class_index(sc.target_class)
        tracked = {"ml": ml_track(tab, sim, ic),
                   "rpf": rpf_track(tab, sim, ic, band, np.random.default_rng([seed, GRIDS.index(name)]), n_particles,
                                    config=rpf_config(tab, sim, ic, n_particles, LEVEL_SD_DB),
                                    level_errors="tables", prior_seed=seed),
                   "bot": rpf_track(tab, sim, ic, band, np.random.default_rng([seed, GRIDS.index(name), 9]),
                                    n_particles, bearings_only=True, prior_seed=seed)}
        for method, tr in tracked.items():
            errors[(method, name)] = tr.position_error_m(sim)
            calibration[f"{method}_{name}"] = tr.calibration(sim, late)
    frame = pd.DataFrame({"t_min": minutes})
    for (method, grid), err in errors.items():
        frame[f"{method}_{grid}_rmse_m"] = np.sqrt(np.nanmean(err ** 2, axis=0))
    summary = {"scenario": sc.name, "area": AREA, "runs": runs, "seed": seed, "n_particles": n_particles,
               "band": sea.band_names[band], "class": sc.target_class, "truth": truth,
               "truth_runs": None if provider is None else provider.stats.runs,
               "truth_runs_cached": None if provider is None else provider.stats.cached,
               "truth_seconds": round(truth_seconds, 1), "late_min": LATE_MIN,
               "origin_depth_m": float(tables["isotropic"].area.water.depth_m),
               "grids": {k: str(v) for k, v in grids.items()},
               "rmse_m": {f"{method}_{grid}": {f"{m:g}": float(np.interp(m, minutes,
                                                                         frame[f"{method}_{grid}_rmse_m"]))
                                               for m in REPORT_MIN}
                          for method in METHODS for grid in GRIDS},
               "mean_rmse_after_5min_m": {f"{method}_{grid}": float(np.sqrt(np.nanmean(
                   errors[(method, grid)][:, minutes >= 5.0] ** 2))) for method in METHODS for grid in GRIDS},
               "calibration_after_late_min": calibration,
               "k_difference_db": _k_difference(tables, cls_index, band),
               "seconds": round(time.perf_counter() - start, 1)}
    files = [out / "shelf_rmse.csv", out / "shelf.json", out / "shelf_rmse.png"]
    from tools.studies.shelf_plot import rmse_figure

    fig = rmse_figure(frame, summary)
    from acoustics.plots.figures import save_figure

    with atomic_paths(files) as (csv_tmp, json_tmp, png_tmp):
        frame.to_csv(csv_tmp, index=False, float_format="%.6g")
        json_tmp.write_text(json.dumps({"tmakit_format": RESULT_FORMAT, **summary}, indent=1) + "\n")
        save_figure(fig, png_tmp, atomic=False)
    summary["files"] = [str(f) for f in files]
    summary["summary"] = _text(summary)
    return summary


def _k_difference(tables: dict, cls_index: int, band: int) -> dict:
    """K(r) of the bearing-dependent grid less the shortcut's, dB, at `K_BEARINGS_DEG` x
    `K_RANGES_M` ({bearing: {range km: dB}}; None where the grid has no K, beyond land)."""
    out = {}
    flat = tables["isotropic"].k_at(cls_index, np.array(K_RANGES_M))[:, band]
    for bearing in K_BEARINGS_DEG:
        k = tables["bearing"].k_at(cls_index, np.array(K_RANGES_M), bearing_deg=bearing)[:, band]
        out[f"{bearing:g}"] = {f"{r / 1000:g}": (None if not np.isfinite(d) else round(float(d), 2))
                               for r, d in zip(K_RANGES_M, k - flat)}
    return out


def _text(summary: dict) -> str:
    lines = [f"shelf study: {summary['runs']} runs of {summary['scenario']} in {summary['area']} "
             f"(class {summary['class']}, SPL band {summary['band']}, levels from {summary['truth']}); "
             f"position RMSE, m, at "
             + ", ".join(f"{m} min" for m in REPORT_MIN) + ":"]
    for key, by_min in summary["rmse_m"].items():
        lines.append(f"  {key:>14}: " + "  ".join(f"{v:8.0f}" for v in by_min.values())
                     + f"   (mean after 5 min {summary['mean_rmse_after_5min_m'][key]:.0f} m)")
    lines.append(f"  the isotropic grid is the origin's column over a flat bottom of "
                 f"{summary['origin_depth_m']:.0f} m")
    lines.append(f"90 % range interval's coverage of the truth after {summary['late_min']:g} min "
                 f"(calibrated: 0.90; median |error| / sd, calibrated 0.67):")
    for key, c in summary["calibration_after_late_min"].items():
        lines.append(f"  {key:>14}: {c['range']['coverage_90']:.2f} ({c['range']['median_abs_z']:.2f})")
    return "\n".join(lines)

