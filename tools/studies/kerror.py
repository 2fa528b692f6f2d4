"""Tracking with the K error model a sensitivity study measured, against the one number.

On the built-in ``shelf-break`` area a sensitivity study (``tmakit sensitivity shelf-break``)
draws members: the same area with its relief, water and bottom perturbed, each member's K the
sea's. Here the sea is one of those members: each Monte Carlo run draws a member and simulates
the target's levels with that member's K (the K error then has the study's structure: an offset
the member keeps along range, a residual that changes along it), the other errors as usual (the
target's speed and P0 drawn from its class, eq. 11 levels, eq. 2 bearings). The members are
split in `FOLDS` groups; for each, the K error model is measured on the others
(`acoustics.sensitivity.errormodel`) and its share of the runs' seas is drawn from it: the
trackers are judged on seas their error model was not measured on. The same measurements are tracked with the nominal
tables and:

- ``model``: the study's model (offset and residual per class, band and bearing, the residual's
  correlation length, the offset's correlation between bands; `tracker.levels` integrates the
  offset out along the track);
- ``scalar``: the class's one number, the study's rms of K's error over members, bands, bearings
  and ranges, as the offset (with the tables' own residual beside it, as for any area file);
- ``bot``: the particle filter on the bearings alone, the reference neither should fall behind.

Trackers: the ML analysis (``ml``) and the particle filter with bearings and SPL (``rpf``). The
members' seas are grids computed where the observer starts and read from the observer wherever it
is (the simulator's K at the target's bearing and range from the observer): the trackers read the
nominal tables the same way (`acoustics.grid.face.Tables.as_everywhere`), so no error grows with
the observer's distance from the origin.

``tmakit experiment kerror shelf-tv --grid G --study S --out DIR [--runs N]`` writes
``kerror_rmse.csv`` (``t_min``, ``METHOD_SD_rmse_m``), ``kerror.json`` and ``kerror_rmse.png``
(all or none).
"""

from __future__ import annotations

import json
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.grid.dataset import with_k_error_model
from acoustics.grid.face import Tables
from acoustics.grid.kerror import MODEL_VARS
from acoustics.grid.opentables import open_tables
from acoustics.sensitivity.errormodel import k_error_model
from acoustics.sensitivity.face import Study
from acoustics.sensitivity.files import open_study
from acoustics.sensitivity.summaries import k_error_by_class, summarize
from envdata.errors import InputError
from envdata.files import atomic_paths
from tools.studies.calibration import class_draws
from tools.studies.trackerrors import FILTER_PARTICLES, LEVEL_SD_DB, ml_track, rpf_config, rpf_track
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch

SCENARIO = "shelf-tv"
REPORT_MIN = (5, 10, 20, 30)
#: The stated sds are checked from this minute on, min.
LATE_MIN = 10.0
#: Time bins in which each tracker is compared with the bearings-only filter, min.
TIME_BINS_MIN = (0, 5, 10, 15, 20, 25, 30)
METHODS = ("ml", "rpf")
SDS = ("model", "scalar")


def member_tables(nominal: Tables, study: Study, member: int) -> Tables:
    """The sea of one member: the nominal grid with the member's K (the truth the runs simulate)."""
    ds = nominal.dataset
    dims = ds["k_db"].dims
    canonical = ("class", "band", "bearing", "range") if study.bearing_deg is not None else ("class", "band", "range")
    k = np.transpose(study.member_k_db(member), [canonical.index(d) for d in dims])
    ds = ds.assign(k_db=(dims, k, ds["k_db"].attrs))
    ds = ds.drop_vars([n for n in ("k_error_sd_db", *MODEL_VARS) if n in ds.data_vars])
    return open_tables(ds, name=f"{nominal.source} (member {member})")


#: The members' groups: each one's seas tracked with the model of the others.
FOLDS = 4


def _subset(study: Study, members) -> Study:
    """The study with only the given members."""
    idx = np.asarray(members, dtype=int)
    return replace(study, dataset=study.dataset.isel(member=idx), k_db=study.k_db[idx],
                   parameters={k: v[idx] for k, v in study.parameters.items()})


def _scalar_model(nominal: Tables, value_db: float):
    """A model dataset that is the one number as the offset everywhere, no residual of its own."""
    model = k_error_model_like(nominal)
    return model.assign(k_offset_sd_db=model["k_offset_sd_db"] * 0.0 + value_db,
                        k_residual_sd_db=model["k_residual_sd_db"] * 0.0,
                        k_residual_length_m=model["k_residual_length_m"] * 0.0 + 1000.0,
                        k_offset_band_correlation=model["k_offset_band_correlation"] * 0.0 + 1.0)


def k_error_model_like(nominal: Tables):
    """An empty model dataset (zeros) on the nominal grid's class, band (and bearing) axes."""
    import xarray as xr

    ds = nominal.dataset
    radial = "bearing" in ds.dims
    coords = {"class": ds["class"].values, "band": ds["band"].values,
              **({"bearing": ds["bearing"].values} if radial else {})}
    shape = tuple(ds.sizes[d] for d in MODEL_VARS["k_offset_sd_db"][radial])
    return xr.Dataset({name: (dims[radial], np.zeros(shape if len(dims[radial]) > 1 else (ds.sizes["class"],)))
                       for name, dims in MODEL_VARS.items()}, coords=coords)


def run(*, grid: str | Path, study: str | Path, out_dir: str | Path, runs: int = 48, seed: int = 0,
        n_particles: int = FILTER_PARTICLES) -> dict:
    """The study (see the module); returns its summary and writes its three files."""
    start = time.perf_counter()
    out = Path(out_dir)
    nominal = open_tables(grid)
    if nominal.bearing_axis_deg is None:
        raise InputError(f"{grid}: the kerror study needs the bearing-dependent grid of {SCENARIO!r}'s area")
    base = open_tables(nominal.dataset.drop_vars([n for n in ("k_error_sd_db", *MODEL_VARS)
                                                  if n in nominal.dataset.data_vars]), name=str(grid))
    study_k = open_study(study)
    if study_k.members < 4:
        raise InputError(f"{study}: the kerror study splits the members in {FOLDS} groups: it needs at least 4, "
                         f"got {study_k.members}")
    sc = load_scenario(SCENARIO)
    ic = base.class_index(sc.target_class)
    band = 0  # FB1, the band heard farthest
    groups = [np.arange(g, study_k.members, FOLDS) for g in range(FOLDS)]
    folds = [(np.setdiff1d(np.arange(study_k.members), seas), seas) for seas in groups]
    per_fold = [runs // FOLDS + (1 if g < runs % FOLDS else 0) for g in range(FOLDS)]
    rng = np.random.default_rng(seed)
    errors = {(m, s): [] for m in METHODS for s in SDS}
    errors[("bot", "-")] = []
    tracked_cal = {}
    scalars, drawn = [], np.zeros(study_k.members, dtype=int)
    minutes = None
    for fold, (fit, seas) in enumerate(folds):
        fitted = _subset(study_k, fit)
        scalar_db = k_error_by_class(summarize(fitted))[sc.target_class]
        scalars.append(scalar_db)
        fitted_model = with_k_error_model(base.dataset, k_error_model(fitted), f"members {fit.tolist()}")
        one_number = with_k_error_model(base.dataset, _scalar_model(base, scalar_db), "one number")
        tables = {"model": open_tables(fitted_model, name=f"{grid} (model of members {fit.tolist()})").as_everywhere(),
                  "scalar": open_tables(one_number, name=f"{grid} (one number)").as_everywhere()}
        members = seas[rng.integers(0, seas.size, per_fold[fold])]
        for member in np.unique(members):
            n = int(np.sum(members == member))
            drawn[member] += n
            truth = member_tables(base, study_k, int(member)).as_everywhere()
            draws = class_draws(sc, truth.classes[ic], n, rng)
            draws["dk_db"] = np.zeros(n)  # the K error is the member's K itself
            sim = simulate_batch(sc, truth, rng, **draws)
            minutes = (sim.t_s - sim.t_s[0]) / 60.0
            late = minutes >= LATE_MIN
            for name, tab in tables.items():
                gen = np.random.default_rng([seed, int(member), SDS.index(name)])
                runs_of = {"ml": ml_track(tab, sim, ic),
                           "rpf": rpf_track(tab, sim, ic, band, gen, n_particles,
                                            config=rpf_config(tab, sim, ic, n_particles, LEVEL_SD_DB),
                                            level_errors="tables", at_observer=False, prior_seed=int(member))}
                for method, tr in runs_of.items():
                    errors[(method, name)].append(tr.position_error_m(sim))
                    tracked_cal.setdefault((method, name), []).append((tr, sim, late))
            bot = rpf_track(tables["model"], sim, ic, band, np.random.default_rng([seed, int(member), 9]), n_particles,
                            bearings_only=True, at_observer=False, prior_seed=int(member))
            errors[("bot", "-")].append(bot.position_error_m(sim))
            tracked_cal.setdefault(("bot", "-"), []).append((bot, sim, late))
    errors = {k: np.concatenate(v) for k, v in errors.items()}
    keys = [f"{m}_{s}" for m in METHODS for s in SDS] + ["bot"]
    by_key = dict(zip(keys, [errors[(m, s)] for m in METHODS for s in SDS] + [errors[("bot", "-")]]))
    frame = pd.DataFrame({"t_min": minutes})
    for key, err in by_key.items():
        frame[f"{key}_rmse_m"] = np.sqrt(np.nanmean(err ** 2, axis=0))
    calibration = {f"{m}_{s}" if s != "-" else m: _pooled_calibration(parts) for (m, s), parts in tracked_cal.items()}
    bins = {key: {f"{lo}-{hi}": _rms(err[:, (minutes >= lo) & (minutes < hi)])
                  for lo, hi in zip(TIME_BINS_MIN[:-1], TIME_BINS_MIN[1:])} for key, err in by_key.items()}
    summary = {"scenario": sc.name, "area": base.area.name, "runs": runs, "seed": seed, "n_particles": n_particles,
               "class": sc.target_class, "band": base.band_names[band], "study": str(study), "grid": str(grid),
               "study_members": study_k.members, "folds": [seas.tolist() for _, seas in folds],
               "members_drawn": drawn.tolist(), "scalar_k_error_sd_db_by_fold": [round(v, 3) for v in scalars],
               "level_sd_db": LEVEL_SD_DB, "late_min": LATE_MIN,
               "model_by_fold": [_model_summary(k_error_model(_subset(study_k, fit)), ic, band) for fit, _ in folds],
               "rmse_m": {key: {f"{t:g}": float(np.interp(t, minutes, frame[f"{key}_rmse_m"])) for t in REPORT_MIN}
                          for key in keys},
               "mean_rmse_after_5min_m": {key: _rms(err[:, minutes >= 5.0]) for key, err in by_key.items()},
               "rmse_by_time_bin_m": bins,
               "worse_than_bearings_only_bins": {key: [b for b, v in bins[key].items() if v > bins["bot"][b]]
                                                 for key in keys if key != "bot"},
               "calibration_after_late_min": calibration,
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


def _rms(err) -> float:
    return float(np.sqrt(np.nanmean(np.asarray(err, dtype=float) ** 2)))


def _pooled_calibration(parts) -> dict:
    """The calibration of every batch of runs pooled: the estimates' errors and sds concatenated."""
    from tools.studies.calibration import interval_calibration, wrap_deg

    def stack(f):
        return np.concatenate([f(tr, sim)[:, late] for tr, sim, late in parts], axis=0)

    return {"range": interval_calibration(stack(lambda tr, sim: tr.range_m - sim.range_m),
                                          stack(lambda tr, sim: tr.range_sd_m)),
            "course": interval_calibration(stack(lambda tr, sim: wrap_deg(tr.course_deg - sim.course_deg)),
                                           stack(lambda tr, sim: tr.course_sd_deg)),
            "speed": interval_calibration(stack(lambda tr, sim: tr.speed_mps - sim.speed_mps),
                                          stack(lambda tr, sim: tr.speed_sd_mps))}


def _model_summary(model, ic: int, band: int) -> dict:
    """One fold's model of the target's class in the band, medians over the bearings."""
    def med(name):
        v = np.asarray(model[name].isel({"class": ic}).values, dtype=float)
        v = v[band] if v.ndim >= 1 and name in ("k_offset_sd_db", "k_residual_sd_db") else v
        return round(float(np.nanmedian(v)), 3)

    return {name: med(name) for name in MODEL_VARS}


def _figure(frame: pd.DataFrame, summary: dict):
    from acoustics.plots.figures import new_figure

    fig = new_figure(figsize=(7.5, 4.2))
    ax = fig.subplots()
    styles = {"model": "-", "scalar": "--"}
    colors = {"ml": "tab:blue", "rpf": "tab:red"}
    for m in METHODS:
        for s in SDS:
            ax.plot(frame["t_min"], frame[f"{m}_{s}_rmse_m"] / 1000.0, styles[s], color=colors[m],
                    label=f"{m}, K error {'model by band and bearing' if s == 'model' else 'one number'}")
    ax.plot(frame["t_min"], frame["bot_rmse_m"] / 1000.0, ":", color="tab:gray", label="bearings only")
    ax.set_xlabel("time, min")
    ax.set_ylabel("position RMSE, km")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"{summary['scenario']} in {summary['area']}: {summary['runs']} runs, each in the sea of a "
                 f"member of a {summary['study_members']}-member study", fontsize=9)
    fig.tight_layout()
    return fig
