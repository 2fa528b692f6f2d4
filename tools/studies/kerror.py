"""Tracking with the K error a sensitivity study measured: per bearing and range, or one number.

On the built-in ``shelf-break`` area, a sensitivity study (``tmakit sensitivity shelf-break
--into GRID``) leaves in the grid ``k_error_sd_db(class, band, bearing, range)``: the rms over
its members of K - K_nominal. Here the sea is one of those members: each Monte Carlo run draws a
member and simulates the target's levels with that member's K (the K error then follows the
study's spread: small where the members agree, large where they do not), the other errors as
usual (eq. 11 levels, bearings, the source's P0). The same measurements are tracked with the
nominal tables twice:

- ``map``: the grid's sd at each measurement's bearing and range (the ML analysis's eq. 21
  nodes at the row's bearing and level range; the particle filter's level likelihood with
  sigma_l^2 = 1.1^2 + sd(r)^2 at each particle's range along the cycle's bearing);
- ``scalar``: the class's one measured number (the study's ``k_error_sd_db`` of the class, rms
  over members, bands, bearings and ranges) everywhere, as a constant map and as
  sigma_l = hypot(1.1, number), as the trackers did before.

``tmakit experiment kerror shelf-tv --grid G --study S --out DIR [--runs N]`` writes
``kerror_rmse.csv`` (``t_min``, ``METHOD_SD_rmse_m``), ``kerror.json`` and ``kerror_rmse.png``
(all or none).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.grid.dataset import with_k_error_sd
from acoustics.grid.face import Tables
from acoustics.grid.opentables import open_tables
from acoustics.sensitivity.face import Study
from acoustics.sensitivity.files import open_study
from acoustics.sensitivity.summaries import k_error_by_class, summarize
from envdata.errors import InputError
from envdata.files import atomic_paths
from tools.studies.trackerrors import LEVEL_SD_DB, ml_errors, rpf_errors
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch

SCENARIO = "shelf-tv"
REPORT_MIN = (5, 10, 20, 30)
METHODS = ("ml", "rpf")
SDS = ("map", "scalar")


def member_tables(nominal: Tables, study: Study, member: int) -> Tables:
    """The sea of one member: the nominal grid with the member's K (the truth the runs simulate)."""
    dims = nominal.dataset["k_db"].dims
    canonical = ("class", "band", "bearing", "range") if study.bearing_deg is not None else ("class", "band", "range")
    k = np.transpose(study.member_k_db(member), [canonical.index(d) for d in dims])
    ds = nominal.dataset.assign(k_db=(dims, k, nominal.dataset["k_db"].attrs))
    if "k_error_sd_db" in ds:
        ds = ds.drop_vars("k_error_sd_db")
    return open_tables(ds, name=f"{nominal.source} (member {member})")


def run(*, grid: str | Path, study: str | Path, out_dir: str | Path, runs: int = 48, seed: int = 0,
        n_particles: int = 2000) -> dict:
    """The study (see the module); returns its summary and writes its three files."""
    start = time.perf_counter()
    out = Path(out_dir)
    with_map = open_tables(grid)
    if not with_map.has_k_error_map:
        raise InputError(f"{grid}: the grid has no k_error_sd_db; run tmakit sensitivity ... --into {grid}")
    study_k = open_study(study)
    summary_k = summarize(study_k)
    sc = load_scenario(SCENARIO)
    ic = with_map.class_index(sc.target_class)
    band = 0  # FB1, the band heard farthest
    scalar_db = k_error_by_class(summary_k)[sc.target_class]
    scalar = open_tables(with_k_error_sd(with_map.dataset, np.where(np.isfinite(with_map.k_grid_db), scalar_db, np.nan),
                                         f"one number, {scalar_db:.2f} dB"), name=f"{grid} (one number)")
    rng = np.random.default_rng(seed)
    members = rng.integers(0, study_k.members, runs)
    errors = {(m, s): [] for m in METHODS for s in SDS}
    minutes = None
    for member in np.unique(members):
        n = int(np.sum(members == member))
        truth = member_tables(with_map, study_k, int(member))
        # the level error is the member's K itself: no extra dK drawn
        sim = simulate_batch(sc, truth, rng, dk_db=np.zeros(n))
        minutes = (sim.t_s - sim.t_s[0]) / 60.0
        for name, tables, sigma in (("map", with_map, LEVEL_SD_DB),
                                    ("scalar", scalar, float(np.hypot(LEVEL_SD_DB, scalar_db)))):
            errors[("ml", name)].append(ml_errors(tables, sim, ic)[0])
            # the scalar filter's sigma_l already holds the K error: its grid gives it no map
            filter_tables = tables if name == "map" else open_grid_without_map(with_map)
            errors[("rpf", name)].append(rpf_errors(filter_tables, sim, ic, band,
                                                    np.random.default_rng([seed, int(member), SDS.index(name)]),
                                                    n_particles, level_sigma_db=sigma, at_observer=False))
    errors = {k: np.concatenate(v) for k, v in errors.items()}
    frame = pd.DataFrame({"t_min": minutes})
    for (method, name), err in errors.items():
        frame[f"{method}_{name}_rmse_m"] = np.sqrt(np.nanmean(err ** 2, axis=0))
    sd_along = {f"{b:g}": round(float(np.nanmedian(with_map.k_error_sd_profile_db(ic, band, b))), 2)
                for b in with_map.bearing_axis_deg}
    summary = {"scenario": sc.name, "area": with_map.area.name, "runs": runs, "seed": seed,
               "n_particles": n_particles, "class": sc.target_class, "band": with_map.band_names[band],
               "study": str(study), "grid": str(grid), "study_members": study_k.members,
               "members_drawn": np.bincount(members, minlength=study_k.members).tolist(),
               "scalar_k_error_sd_db": round(scalar_db, 3), "level_sd_db": LEVEL_SD_DB,
               "k_error_sd_db_median_by_bearing": sd_along,
               "rmse_m": {f"{m}_{s}": {f"{t:g}": float(np.interp(t, minutes, frame[f"{m}_{s}_rmse_m"]))
                                       for t in REPORT_MIN} for m in METHODS for s in SDS},
               "mean_rmse_after_5min_m": {f"{m}_{s}": float(np.sqrt(np.nanmean(errors[(m, s)][:, minutes >= 5.0] ** 2)))
                                          for m in METHODS for s in SDS},
               "seconds": round(time.perf_counter() - start, 1)}
    files = [out / "kerror_rmse.csv", out / "kerror.json", out / "kerror_rmse.png"]
    fig = _figure(frame, summary)
    from acoustics.plots.figures import save_figure

    out.mkdir(parents=True, exist_ok=True)
    with atomic_paths(files) as (csv_tmp, json_tmp, png_tmp):
        frame.to_csv(csv_tmp, index=False, float_format="%.6g")
        json_tmp.write_text(json.dumps(summary, indent=1) + "\n")
        save_figure(fig, png_tmp, atomic=False)
    return summary


def open_grid_without_map(tables: Tables) -> Tables:
    """The same grid without ``k_error_sd_db`` (the classes' one number, already in sigma_l)."""
    return open_tables(tables.dataset.drop_vars("k_error_sd_db"), name=f"{tables.source} (no map)")


def _figure(frame: pd.DataFrame, summary: dict):
    from acoustics.plots.figures import new_figure

    fig = new_figure(figsize=(7.5, 4.2))
    ax = fig.subplots()
    styles = {"map": "-", "scalar": "--"}
    colors = {"ml": "tab:blue", "rpf": "tab:red"}
    for m in METHODS:
        for s in SDS:
            ax.plot(frame["t_min"], frame[f"{m}_{s}_rmse_m"] / 1000.0, styles[s], color=colors[m],
                    label=f"{m}, K error sd {'by bearing and range' if s == 'map' else 'one number'}")
    ax.set_xlabel("time, min")
    ax.set_ylabel("position RMSE, km")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"{summary['scenario']} in {summary['area']}: {summary['runs']} runs, each in the sea of a "
                 f"member of a {summary['study_members']}-member study", fontsize=9)
    fig.tight_layout()
    return fig
