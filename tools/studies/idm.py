"""Monte Carlo study of Iglesis & de Montella sec. 5: RMSE of BOT and BOT+SPL and the BOT CRLB.

``run("idm-static", runs=1000, out_dir=...)`` simulates the scenario's bearings (sd 1.5 deg)
and SPLs (sd 4 dB; SL of eq. 12 minus the grid's TL, eq. 16), filters every run with the RPF
bearings-only ("rpf-bot") and with bearings and SPL ("rpf", sigma_l = 10 dB in the filter) on
the same measurements, and writes the position RMSE against time with the BOT CRLB (zero
process noise) as CSV and PNG (analogues of Figs. 3, 5 and 7), plus Table 1 for the static
observer. Runs go in chunks of ``CHUNK_RUNS`` (arrays (4, runs, N)), each chunk with its own
seed from ``numpy.random.SeedSequence(seed).spawn``, so the result does not depend on the
number of worker processes.
"""

from __future__ import annotations

import json
import logging
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.grid.face import Tables
from acoustics.grid.formats import RESULT_FORMAT
from envdata.classes import ross_source_level_db
from envdata.files import atomic_path
from tools.studies.idm_columns import COLUMN
from tools.studies.idm_scenarios import IdmScenario, get_scenario
from tracker import rpf
from tracker.crlb import bot_crlb, bot_spl_crlb, prior_covariance
from tracker.scenario import ScenarioError

log = logging.getLogger(__name__)

AREA = "munk-1000"
CLASS = "ship"
BAND = "F50"
CHUNK_RUNS = 20
#: sd of the source-level offset prior of the "rpf-sl" filter (beyond the paper), dB.
SL_OFFSET_PRIOR_SD_DB = 6.0
#: sigma_l of the filters' SPL likelihood in the paper, dB (its data have 4 dB).
PAPER_LEVEL_SIGMA_DB = 10.0
#: The particles' stated sds are checked from this minute on, min.
LATE_MIN = 10.0


def methods_for(scenario: IdmScenario) -> tuple[str, ...]:
    """Filters compared in a scenario: the paper's BOT and BOT+SPL, BOT+SPL with the
    variance-preserving regularization ("rpf-vp", beyond the paper), and the joint SL offset
    where the scenario has one."""
    base = ("rpf-bot", "rpf", "rpf-vp")
    return base + ("rpf-sl",) if scenario.sl_offset_db != 0.0 else base


def check_level_sigma(level_sigma_db: float) -> None:
    """ScenarioError unless the filters' sigma_l is a positive number of dB."""
    if not (math.isfinite(level_sigma_db) and level_sigma_db > 0):
        raise ScenarioError(f"level sigma_l: must be a positive number of dB, got "
                            f"{level_sigma_db:g}")


def _config(method: str, n_particles: int, level_sigma_db: float) -> rpf.RpfConfig:
    cfg = rpf.RpfConfig(n_particles=n_particles, level_sigma_db=level_sigma_db)
    if method == "rpf-vp":
        cfg = replace(cfg, shrink=True)
    if method == "rpf-sl":
        cfg = replace(cfg, sl_offset_sd_db=SL_OFFSET_PRIOR_SD_DB, shrink=True)
    return cfg


def simulate(scenario: IdmScenario, k_profile, runs: int, rng: np.random.Generator
             ) -> tuple[np.ndarray, np.ndarray]:
    """Measured bearings (rad, [0, 2 pi)) and SPLs (dB) of ``runs`` runs, shape (runs, K).

    Bearing = eq. 9 + N(0, sd); SPL = SL(v) + offset + K(r) + N(0, sd) (eqs. 12, 15-16).
    """
    t = scenario.t_s
    rel = scenario.target_state(t) - scenario.observer_state(t)
    tgt = scenario.target_state(t)
    true_b = rpf.bearing_rad(rel[:, 0], rel[:, 1])
    true_l = (ross_source_level_db(np.hypot(tgt[:, 2], tgt[:, 3])) + scenario.sl_offset_db
              + k_profile(np.hypot(rel[:, 0], rel[:, 1])))
    b = true_b[None] + math.radians(scenario.bearing_sd_deg) * rng.standard_normal((runs, t.size))
    lv = true_l[None] + scenario.level_sd_db * rng.standard_normal((runs, t.size))
    return np.mod(b, 2.0 * math.pi), lv


def _chunk(args) -> dict[str, np.ndarray]:
    """One chunk of runs: simulate, filter with every method, return position errors (m) and each
    estimate's error over the sd its particles state (range, course, speed)."""
    scenario, range_m, k_db, runs, seed_seq, n_particles, level_sigma_db = args
    from acoustics.grid.levelprofile import LevelProfile

    profile = LevelProfile(range_m=range_m, k_db=k_db)
    rng = np.random.default_rng(seed_seq)
    t = scenario.t_s
    obs = scenario.observer_state(t)
    rel = scenario.target_state(t) - obs
    bearings, levels = simulate(scenario, profile, runs, rng)
    out = {}
    for method in methods_for(scenario):
        res = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=bearings,
                            level_db_meas=None if method == "rpf-bot" else levels,
                            k_profiles=[profile] * t.size,
                            cfg=_config(method, n_particles, level_sigma_db), rng=rng, summaries=True)
        out[method] = np.hypot(res.mean[:, :, 0] - rel[None, :, 0],
                               res.mean[:, :, 1] - rel[None, :, 1])
        out[method + ":resampled"] = res.resampled.mean(axis=1)
        out[method + ":z"] = _z_scores(res, rel, obs)
    return out


def _z_scores(res, rel, obs) -> np.ndarray:
    """Range, course and speed error over the sd the particles state, (3, runs, K)."""
    from tools.studies.calibration import wrap_deg

    mean, sd = res.mean, res.extra["sd"]
    tvx, tvy = mean[..., 2] + obs[None, :, 2], mean[..., 3] + obs[None, :, 3]
    true_v = rel[:, 2:4] + obs[:, 2:4]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.stack([
            (np.hypot(mean[..., 0], mean[..., 1]) - np.hypot(rel[None, :, 0], rel[None, :, 1])) / sd[..., 0],
            wrap_deg(np.degrees(np.arctan2(tvx, tvy) - np.arctan2(true_v[None, :, 0], true_v[None, :, 1])))
            / sd[..., 1],
            (np.hypot(tvx, tvy) - np.hypot(true_v[None, :, 0], true_v[None, :, 1])) / sd[..., 2]])


def _calibration(z: np.ndarray, late) -> dict:
    """Coverage of the 90 % intervals, median |z| and mean z^2 of range, course and speed after
    the late cycles (`tools.studies.calibration`), from the z scores (3, runs, K)."""
    from tools.studies.calibration import interval_calibration

    return {name: interval_calibration(z[j][:, late], 1.0)
            for j, name in enumerate(("range", "course", "speed"))}


def _phases(sc: IdmScenario, t_s: np.ndarray) -> dict[str, np.ndarray]:
    """The cycles after LATE_MIN split at the observer's turn: "before_turn" (range unobserved
    by the bearings, the prior's range sets it) and "after_turn" (the turn done); empty for a
    scenario without a turn."""
    if sc.turn is None:
        return {}
    t_min = t_s / 60.0
    return {"before_turn": (t_min >= LATE_MIN) & (t_s < sc.turn[0]), "after_turn": t_s >= sc.turn[1]}


def _truth_in_prior(sc: IdmScenario, n_particles: int) -> float:
    """The true initial range less the filters' prior range mean, in prior sds (the paper's
    target starts 2.5 sd nearer than the prior says: where the bearings leave range unobserved,
    an honest filter's interval misses it about as often as the prior's would)."""
    cfg = rpf.RpfConfig(n_particles=n_particles)
    return round((math.hypot(sc.target_x_m, sc.target_y_m) - cfg.range_mean_m) / cfg.range_sd_m, 3)


def _find_grid(grid):
    import acoustics

    if grid is None:
        raise ScenarioError(f"the idm experiment needs the {AREA} grid: build it with "
                            f"'tmakit grids build {AREA}' and give its file")
    if isinstance(grid, Tables):
        return grid, grid.source
    return acoustics.open_tables(grid), str(grid)


def run(scenario: str, *, runs: int, out_dir: Path, seed: int, progress: bool = False,
        workers: int | None = None, grid=None, n_particles: int = 5000,
        level_sigma_db: float = PAPER_LEVEL_SIGMA_DB) -> dict:
    """Run one scenario's Monte Carlo study and write its CSV, PNG and JSON.

    Parameters
    ----------
    scenario : str
        ``idm-maneuvering``, ``idm-parallel``, ``idm-static`` or ``idm-static-sl-offset``.
    runs : int
        Monte Carlo runs (the paper: 1000).
    out_dir : Path
        Output directory: ``SCENARIO_rmse.csv``, ``SCENARIO_rmse.png``, ``SCENARIO.json`` and,
        for the static observer, ``table1.csv``.
    seed : int
        Seed of everything random; same seed, same numbers (whatever ``workers``).
    progress : bool
        Progress bar on stderr.
    workers : int, optional
        Worker processes (default: the CPU count).
    grid : path or Tables
        The munk-1000 grid (the tracker reads grids; it never runs BELLHOP).
    n_particles : int
        N (5000).
    level_sigma_db : float
        sigma_l of the SPL likelihood in the filters (eq. 33), dB: the paper's 10 dB against
        its 4 dB measurement noise; the data's value (``scenario.level_sd_db``) is the
        matched filter (beyond the paper, docs/idm.md).

    Returns
    -------
    dict
        "summary" (text) and JSON-able figures: RMSE at the report times, the paper's values,
        files written, elapsed time.
    """
    sc = get_scenario(scenario)
    if int(runs) != runs or runs < 1:
        raise ScenarioError(f"runs: must be a positive integer, got {runs}")
    check_level_sigma(level_sigma_db)
    out_dir = Path(out_dir)
    tables, grid_name = _find_grid(grid)
    ic, ib = tables.class_index(CLASS), tables.band_index(BAND)
    source_depth_m = tables.classes[ic].depth_m
    if abs(source_depth_m - sc.target_depth_m) > 1e-6:
        raise ScenarioError(f"{grid_name}: class {CLASS!r} radiates at {source_depth_m:g} m, "
                            f"the scenario's target is at {sc.target_depth_m:g} m")
    profile = tables.level_profile(ic, ib, sc.obs_depth_m)
    t = sc.t_s
    n_chunks = math.ceil(runs / CHUNK_RUNS)
    seeds = np.random.SeedSequence(seed).spawn(n_chunks)
    sizes = [min(CHUNK_RUNS, runs - i * CHUNK_RUNS) for i in range(n_chunks)]
    jobs = [(sc, profile.range_m, profile.k_db, sizes[i], seeds[i], n_particles, level_sigma_db)
            for i in range(n_chunks)]
    workers = max(1, min(workers or os.cpu_count() or 1, n_chunks))
    start = time.perf_counter()
    results = []
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=runs, desc=scenario, unit="run")
    if workers == 1:
        for job in jobs:
            results.append(_chunk(job))
            if bar:
                bar.update(job[3])
    else:
        import multiprocessing as mp

        with ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context("fork")) as pool:
            for job, res in zip(jobs, pool.map(_chunk, jobs)):
                results.append(res)
                if bar:
                    bar.update(job[3])
    if bar:
        bar.close()
    elapsed = time.perf_counter() - start
    methods = methods_for(sc)
    err = {m: np.concatenate([r[m] for r in results]) for m in methods}
    resampled = {m: float(np.mean(np.concatenate([r[m + ":resampled"] for r in results])))
                 for m in methods}
    late = t / 60.0 >= LATE_MIN
    z_all = {m: np.concatenate([r[m + ":z"] for r in results], axis=1) for m in methods}
    calibration = {_col(m): _calibration(z_all[m], late) for m in methods}
    by_phase = {phase: {_col(m): _calibration(z_all[m], keep) for m in methods}
                for phase, keep in _phases(sc, t).items()}

    obs = sc.observer_state(t)
    rel = sc.target_state(t) - obs
    cfg = rpf.RpfConfig(n_particles=n_particles)
    p0 = prior_covariance(float(rpf.bearing_rad(rel[0, 0], rel[0, 1])),
                          range_mean_m=cfg.range_mean_m, range_sd_m=cfg.range_sd_m,
                          bearing_sd_rad=math.radians(cfg.bearing_sigma_deg),
                          speed_mean_mps=cfg.speed_mean_mps, speed_sd_mps=cfg.speed_sd_mps,
                          course_sd_rad=math.radians(cfg.course_sd_deg))
    crlb = bot_crlb(t, rel, bearing_sd_rad=math.radians(sc.bearing_sd_deg), p0=p0)
    # the same bound with the levels (data's sd, Ross SL known): how much the SPL can give
    crlb_spl = bot_spl_crlb(t, rel, obs[:, 2:4],
                            bearing_sd_rad=math.radians(sc.bearing_sd_deg),
                            level_sd_db=sc.level_sd_db, k_profile=profile, p0=p0)
    frame = pd.DataFrame({"t_s": t, "t_min": t / 60.0})
    for m in methods:
        frame[f"rmse_{_col(m)}_m"] = np.sqrt(np.mean(err[m] ** 2, axis=0))
        frame[f"median_{_col(m)}_m"] = np.median(err[m], axis=0)
    frame["crlb_bot_m"] = crlb
    frame["crlb_spl_m"] = crlb_spl

    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = out_dir / f"{scenario}_rmse.csv"
    png_path = out_dir / f"{scenario}_rmse.png"
    json_path = out_dir / f"{scenario}.json"
    with atomic_path(csv_path) as tmp:
        frame.to_csv(tmp, index=False, float_format="%.6g")
    from acoustics.plots.figures import save_figure
    from tools.studies.idm_plot import DPI, rmse_figure

    save_figure(rmse_figure(frame, sc, methods, runs=runs), png_path, dpi=DPI)

    at = {}
    for tm in sc.report_times_min:
        row = frame.iloc[int(np.argmin(np.abs(frame["t_min"] - tm)))]
        at[f"{tm:g}"] = {f"rmse_{_col(m)}_m": float(row[f"rmse_{_col(m)}_m"]) for m in methods}
        at[f"{tm:g}"]["crlb_bot_m"] = float(row["crlb_bot_m"])
        at[f"{tm:g}"]["crlb_spl_m"] = float(row["crlb_spl_m"])
    minima = {}
    for m in methods:
        col = frame[f"rmse_{_col(m)}_m"]
        i = int(np.argmin(col.values[1:])) + 1  # the first cycle is the prior
        minima[_col(m)] = {"t_min": float(frame["t_min"].iloc[i]), "rmse_m": float(col.iloc[i])}
    files = {"csv": str(csv_path), "png": str(png_path), "json": str(json_path)}
    table_rows = None
    if sc.name == "idm-static":
        table_rows = _table1(frame, sc)
        t1 = out_dir / "table1.csv"
        with atomic_path(t1) as tmp:
            pd.DataFrame(table_rows).to_csv(tmp, index=False, float_format="%.6g")
        files["table1"] = str(t1)
    particle_steps = runs * t.size * n_particles * len(methods)
    data = {
        "scenario": sc.name, "title": sc.title, "runs": runs, "seed": seed,
        "n_particles": n_particles, "level_sigma_db": level_sigma_db,
        "cycles": int(t.size), "methods": list(methods),
        "grid": grid_name, "at": at, "minimum": minima, "paper": sc.paper,
        "final": {f"rmse_{_col(m)}_m": float(frame[f"rmse_{_col(m)}_m"].iloc[-1])
                  for m in methods} | {"crlb_bot_m": float(crlb[-1]),
                                       "crlb_spl_m": float(crlb_spl[-1])},
        "resampled_fraction": resampled, "late_min": LATE_MIN, "calibration_after_late_min": calibration,
        "calibration_by_phase": by_phase, "truth_range_in_prior_sd": _truth_in_prior(sc, n_particles),
        "table1": table_rows, "files": files,
        "elapsed_s": elapsed, "workers": workers,
        "particle_steps_per_s": particle_steps / elapsed,
    }
    with atomic_path(json_path) as tmp:
        tmp.write_text(json.dumps({"tmakit_format": RESULT_FORMAT, **data}, indent=2))
    data["summary"] = _summary(data, sc, methods)
    return data


def _col(method: str) -> str:
    return COLUMN[method]


def _table1(frame: pd.DataFrame, sc: IdmScenario) -> list[dict]:
    rows = []
    for tm in (36.0, 63.0, 150.0):
        row = frame.iloc[int(np.argmin(np.abs(frame["t_min"] - tm)))]
        key = f"{tm:g}min_m"
        rows.append({"t_min": tm, "bot_m": float(row["rmse_bot_m"]),
                     "paper_bot_m": sc.paper[f"bot_{key}"], "spl_m": float(row["rmse_spl_m"]),
                     "paper_spl_m": sc.paper[f"spl_{key}"], "crlb_bot_m": float(row["crlb_bot_m"]),
                     "crlb_spl_m": float(row["crlb_spl_m"])})
    return rows


def _summary(data: dict, sc: IdmScenario, methods) -> str:
    names = {"rpf-bot": "BOT", "rpf": "BOT+SPL", "rpf-vp": "BOT+SPL, VP kernel",
             "rpf-sl": "BOT+SPL, VP, SL offset"}
    lines = [f"{sc.name}: {sc.title}",
             f"{data['runs']} runs x {data['cycles']} cycles x {data['n_particles']} particles, "
             f"seed {data['seed']}, {data['workers']} workers, {data['elapsed_s']:.1f} s "
             f"({data['particle_steps_per_s'] / 1e6:.2f} M particle-steps/s); grid {data['grid']}; "
             f"filters' sigma_l {data['level_sigma_db']:g} dB",
             "position RMSE, m:"]
    head = (f"  {'t_min':>6} " + " ".join(f"{names[m]:>18}" for m in methods)
            + f" {'BOT CRLB':>10} {'SPL CRLB':>10}")
    lines.append(head)
    for tm, vals in data["at"].items():
        lines.append(f"  {float(tm):>6g} " + " ".join(
            f"{vals[f'rmse_{_col(m)}_m']:>18.0f}" for m in methods)
            + f" {vals['crlb_bot_m']:>10.0f} {vals['crlb_spl_m']:>10.0f}")
    for m in methods:
        mn = data["minimum"][_col(m)]
        lines.append(f"  minimum {names[m]}: {mn['rmse_m']:.0f} m at {mn['t_min']:g} min")
    parts = {f"after {data['late_min']:g} min": data["calibration_after_late_min"]}
    parts |= {phase.replace("_", " "): c for phase, c in data["calibration_by_phase"].items()}
    lines.append(f"range's 90 % interval holds the truth (the true start {data['truth_range_in_prior_sd']:+.1f} "
                 "prior sds from the prior's range):")
    for label, cal in parts.items():
        lines.append(f"  {label:>12}: " + ", ".join(
            f"{names[m]} {100 * cal[_col(m)]['range']['coverage_90']:.0f} %" for m in methods))
    if data["paper"]:
        lines.append("paper: " + ", ".join(f"{k} = {v:g}" for k, v in data["paper"].items()))
    lines.append("files: " + ", ".join(data["files"].values()))
    return "\n".join(lines)
