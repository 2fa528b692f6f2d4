"""The Monte Carlo study of Grinenkov & Mashoshin section 4 (eqs. 32-34).

An n x n x n design (the paper: 11 x 11 x 11 = 1331 runs) over the true speed, the true noise
P0 and the transfer-characteristic error dK, each at n nodes over +- 2 sd of the class's
distribution, weighted by the normal densities of eqs. 32-34. Section 4 draws the speed and
noise of every repetition "according to the PDFs of the object's class", and g_V(V_n),
g_P0(P0_m) of eqs. 32-34 are the class PDFs at the actual values; so by default
(``center="class"``) the first target tack's speed and noise are set to the class means plus
the node offsets, and later tacks keep the scenario's changes from the first (the transport's
+2 m/s and +4 dB). ``center="scenario"`` adds the offsets to the scenario's own values instead
(the scenario's tack then sits 1 sd below the class mean for the transport). All runs and all
class hypotheses go through one batched tracker (rows = runs x classes), cycle by cycle; runs
are split into chunks of `CHUNK_RUNS` runs over worker processes (same seed, same numbers,
whatever the number of workers).
"""

from __future__ import annotations

import json
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.grid.formats import RESULT_FORMAT
from envdata.files import atomic_path
from tracker.mltma import MLBatch, MLParams, wrap180
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch

#: Runs per chunk (one worker task, one random stream); 1331 runs make 14 chunks.
CHUNK_RUNS = 100


def design(cls, n: int):
    """Offsets (dv, dp0, dk) and weights of the n^3 design (eqs. 32-34)."""
    u = np.linspace(-2.0, 2.0, n) if n > 1 else np.zeros(1)
    w = np.exp(-0.5 * u ** 2)
    dv, dp, dk = np.meshgrid(u * cls.speed_sd_mps, u * cls.noise_sd_db, u * cls.k_error_sd_db,
                             indexing="ij")
    ww = w[:, None, None] * w[None, :, None] * w[None, None, :]
    return dv.ravel(), dp.ravel(), dk.ravel(), ww.ravel()


def weighted_rms(sq: dict, w) -> tuple[dict, dict]:
    """Weighted RMS over runs of squared errors (C, E, T) (eqs. 32-34) and the runs counted.

    Eqs. 32-34 count time from the moment of detection, so every run has an estimate at every
    t_i. Here the time axis is the scenario's and a run may have no estimate yet at a cycle
    (the submarine before any band is detected: no level range and no earlier range). Such
    (run, cycle) pairs are left out of both sums of eqs. 32-34 (the weights are renormalised
    over the runs that have an estimate); the count of runs that entered is returned beside the
    RMS (NaN where no run has an estimate).

    Parameters
    ----------
    sq : dict of str to ndarray, shape (C, E, T)
        Squared errors, NaN where the run has no estimate.
    w : array_like, shape (E,)
        Design weights g_V g_P0 g_dK of the runs.

    Returns
    -------
    rms, runs : dict of str to ndarray, shape (C, T)
    """
    w = np.asarray(w, dtype=float)
    rms, runs = {}, {}
    for key, v in sq.items():
        ok = np.isfinite(v)
        num = np.einsum("e,cet->ct", w, np.where(ok, v, 0.0))
        den = np.einsum("e,cet->ct", w, ok.astype(float))
        with np.errstate(invalid="ignore", divide="ignore"):
            rms[key] = np.where(den > 0, np.sqrt(num / np.where(den > 0, den, 1.0)), np.nan)
        runs[key] = ok.sum(axis=1)
    return rms, runs


def center_offsets(sc, cls, center: str) -> tuple[float, float]:
    """Speed and noise shifts (m/s, dB) added to every run's offsets for a design centre.

    ``"class"``: the first target tack gets the class means mV, mP0 (eqs. 32-34, section 4);
    ``"scenario"``: the scenario's values are the centre (no shift).
    """
    if center == "scenario":
        return 0.0, 0.0
    if center != "class":
        raise ValueError(f"center must be 'class' or 'scenario', got {center!r}")
    tk = sc.target_tacks[0]
    return cls.speed_mean_mps - tk.speed_mps, cls.noise_mean_db - tk.noise_db


#: The paper's manoeuvre tests (eqs. 26-29 as written): the experiment reproduces the paper.
PAPER_PARAMS = MLParams(maneuver_curved=False, level_vs_k=False)


def run_chunk(grid_path: str, scenario: str, dv, dp, dk, seed, params=None):
    """Simulate and track one chunk of runs: squared errors and estimates (C, E, T) of course,
    speed, range, the simulation, the tack each row declared at each cycle (C, E, T), and each
    estimate's error over the sd the tracker stated (C, E, T) of course, speed and range."""
    from acoustics import open_tables

    tables = open_tables(grid_path)
    sc = load_scenario(scenario)
    rng = np.random.default_rng(seed)
    sim = simulate_batch(sc, tables, rng, dv_mps=dv, dp0_db=dp, dk_db=dk)
    e, t = sim.bearing_deg.shape
    n_cls = len(tables.classes)
    ci = np.repeat(np.arange(n_cls)[None, :], e, axis=0).ravel()   # rows: run-major
    batch = MLBatch(tables, ci, t, params)
    vx = np.gradient(sim.obs_x_m, sim.t_s)
    vy = np.gradient(sim.obs_y_m, sim.t_s)
    err = {k: np.zeros((n_cls, e, t)) for k in ("course", "speed", "range")}
    est = {k: np.zeros((n_cls, e, t)) for k in ("course", "speed", "range")}
    tacks = np.zeros((n_cls, e, t), dtype=int)
    z = {k: np.zeros((n_cls, e, t)) for k in ("course", "speed", "range")}
    for i in range(t):
        rep = lambda a, i=i: np.repeat(a[:, i], n_cls, axis=0)  # noqa: E731
        out = batch.update(sim.t_s[i], sim.obs_x_m[i], sim.obs_y_m[i], vx[i], vy[i],
                           rep(sim.bearing_deg), rep(sim.bearing_sigma_deg),
                           np.repeat(sim.level_db[:, i, :], n_cls, axis=0),
                           np.repeat(sim.snr_db[:, i, :], n_cls, axis=0),
                           obs_depth_m=sim.obs_depth_m)
        k = out["course_deg"].reshape(e, n_cls).T
        v = out["speed_mps"].reshape(e, n_cls).T
        r = out["range_m"].reshape(e, n_cls).T
        est["course"][:, :, i], est["speed"][:, :, i], est["range"][:, :, i] = k, v, r
        err["course"][:, :, i] = wrap180(k - sim.course_deg[None, :, i]) ** 2
        err["speed"][:, :, i] = (v - sim.speed_mps[None, :, i]) ** 2
        err["range"][:, :, i] = (r - sim.range_m[None, :, i]) ** 2
        tacks[:, :, i] = out["tack"].reshape(e, n_cls).T
        with np.errstate(invalid="ignore", divide="ignore"):
            z["course"][:, :, i] = wrap180(k - sim.course_deg[None, :, i]) / out["course_sd_deg"].reshape(e, n_cls).T
            z["speed"][:, :, i] = (v - sim.speed_mps[None, :, i]) / out["speed_sd_mps"].reshape(e, n_cls).T
            z["range"][:, :, i] = (r - sim.range_m[None, :, i]) / out["range_sd_m"].reshape(e, n_cls).T
    return err, est, sim, tacks, z


def manoeuvre_detection(tacks, true_tack, t_s, weights) -> list[dict]:
    """How quickly the tracker declares the target's real manoeuvres, and what else it declares.

    Parameters
    ----------
    tacks : ndarray of int, shape (E, T)
        The tack each run's row declared at each cycle (one class hypothesis).
    true_tack : ndarray of int, shape (T,)
        The scenario's tack at each cycle.
    t_s : ndarray, shape (T,)
    weights : ndarray, shape (E,)
        Design weights of the runs (eqs. 32-34).

    Returns
    -------
    list of dict
        One per stretch between real manoeuvres: ``from_s`` (its start: 0 or the manoeuvre's
        first cycle), and for a manoeuvre ``delay_s`` (weighted mean, median and max over the runs
        that declared one: the time of the first new tack from ``from_s`` on, less ``from_s``),
        ``missed_runs``; for every stretch ``false_per_run`` (the weighted mean number of further
        tacks declared in it).
    """
    starts = [0] + [int(i) for i in np.flatnonzero(np.diff(true_tack) > 0) + 1]
    ends = starts[1:] + [t_s.size]
    w = np.asarray(weights, dtype=float)
    out = []
    for j, (a, b) in enumerate(zip(starts, ends)):
        before = tacks[:, a - 1] if a > 0 else np.ones(len(tacks), dtype=int)
        new = tacks[:, b - 1] - before                                  # tacks declared in [a, b)
        item = {"from_s": float(t_s[a] - t_s[0])}
        if j > 0:
            hit = new > 0
            first = np.argmax(tacks[:, a:b] > before[:, None], axis=1)
            delay = t_s[a + first] - t_s[a]
            item["delay_s"] = ({"mean": float(np.average(delay[hit], weights=w[hit])),
                                "median": float(np.median(delay[hit])), "max": float(delay[hit].max())}
                               if hit.any() else None)
            item["missed_runs"] = int((~hit).sum())
            new = np.maximum(new - 1, 0)
        item["false_per_run"] = float(np.average(new, weights=w))
        out.append(item)
    return out


def run(scenario: str, *, grid_path, n: int = 11, out_dir, seed: int = 0, workers: int = 1,
        progress: bool = False, params: MLParams | None = None, center: str = "class",
        chunk_runs: int = CHUNK_RUNS) -> dict:
    """Run the n^3 experiment of a scenario; write rms.csv, summary.json and plots into out_dir.

    ``center``: ``"class"`` (default, the paper's eqs. 32-34) or ``"scenario"``, see
    `center_offsets`. ``params`` default to `PAPER_PARAMS`: the experiment reproduces the paper's
    algorithm, manoeuvre tests included (``tmakit track`` takes the robust ones by default).
    ``progress`` shows a tqdm bar of finished runs on stderr. Runs go in chunks of
    ``chunk_runs``, each with its own random stream; the workers share them out.
    """
    from acoustics import open_tables

    t_start = time.perf_counter()
    params = PAPER_PARAMS if params is None else params
    grid = open_tables(grid_path)
    sc = load_scenario(scenario)
    classes = grid.classes
    true_cls = next(c for c in classes if c.name == sc.target_class)
    dv, dp, dk, w = design(true_cls, n)
    shift_v, shift_p = center_offsets(sc, true_cls, center)
    dv, dp = dv + shift_v, dp + shift_p
    n_runs = len(dv)
    # chunks of a fixed size, each with its own seed spawned from ``seed``: the numbers do not
    # depend on the number of workers
    if int(chunk_runs) != chunk_runs or chunk_runs < 1:
        raise ValueError(f"chunk_runs must be a positive integer, got {chunk_runs}")
    chunks = [np.arange(i, min(i + chunk_runs, n_runs)) for i in range(0, n_runs, chunk_runs)]
    seeds = np.random.SeedSequence(seed).spawn(len(chunks))
    args = [(str(grid_path), scenario, dv[c], dp[c], dk[c], seeds[j], params)
            for j, c in enumerate(chunks)]
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n_runs, desc=f"gm {sc.name}", unit="run")
    results = [None] * len(args)
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            futures = {pool.submit(run_chunk, *a): j for j, a in enumerate(args)}
            for fut in as_completed(futures):
                j = futures[fut]
                results[j] = fut.result()
                if bar:
                    bar.update(len(chunks[j]))
    else:
        for j, a in enumerate(args):
            results[j] = run_chunk(*a)
            if bar:
                bar.update(len(chunks[j]))
    if bar:
        bar.close()
    sq = {k: np.concatenate([r[0][k] for r in results], axis=1) for k in ("course", "speed", "range")}
    sim0 = results[0][2]
    t_s = sim0.t_s
    rms, runs = weighted_rms(sq, w)                                       # eqs. 32-34
    names = [c.name for c in classes]
    rows = []
    for ci, name in enumerate(names):
        for i, t in enumerate(t_s):
            rows.append({"t_s": t, "class": name, "course_rms_deg": rms["course"][ci, i],
                         "speed_rms_mps": rms["speed"][ci, i], "range_rms_m": rms["range"][ci, i],
                         "course_runs": int(runs["course"][ci, i]),
                         "speed_runs": int(runs["speed"][ci, i]),
                         "range_runs": int(runs["range"][ci, i]),
                         "range_true_m": float(np.average(
                             np.concatenate([r[2].range_m for r in results])[:, i], weights=w))})
    df = pd.DataFrame(rows)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with atomic_path(out / "rms.csv") as tmp:
        df.to_csv(tmp, index=False, float_format="%.6g")
    steady = _steady(df, t_s)
    later = _later_tacks(df, t_s, sim0.tack)
    ic = names.index(sc.target_class)
    tacks = np.concatenate([r[3][ic] for r in results], axis=0)
    detection = manoeuvre_detection(tacks, sim0.tack, t_s, w)
    zs = {k: np.concatenate([r[4][k][ic] for r in results], axis=0) for k in ("course", "speed", "range")}
    calibration = weighted_calibration(zs, w, t_s, sim0.tack)
    elapsed = time.perf_counter() - t_start
    summary = {"scenario": sc.name, "true_class": sc.target_class, "runs": n_runs,
               "center": center,
               "cycles": len(t_s), "classes": names, "elapsed_s": elapsed,
               "steady_state": steady, "later_tacks": later, "manoeuvres": detection,
               "calibration_after_late_min": calibration, "late_min": LATE_MIN,
               "rms_csv": str(out / "rms.csv")}
    try:
        from tools.studies.gm_plot import plot_experiment

        # the one-run plot shows the design's centre (class mean speed and noise, dK = 0)
        centre = int(np.argmax(w))
        j = next(j for j, c in enumerate(chunks) if centre in c)
        summary["plots"] = plot_experiment(df, results[j][:3], sc, names, out,
                                           run=int(np.flatnonzero(chunks[j] == centre)[0]))
    except ImportError:  # pragma: no cover - matplotlib is a dependency
        summary["plots"] = []
    with atomic_path(out / "summary.json") as tmp:
        tmp.write_text(json.dumps({"tmakit_format": RESULT_FORMAT, **summary}, indent=1, default=float))
    lines = [f"experiment gm {sc.name}: {n_runs} runs x {len(names)} classes x {len(t_s)} cycles "
             f"in {elapsed:.1f} s"]
    for name in names:
        s = steady[name]
        lines.append(f"  {name}: steady RMS (5-20 min) course {s['course_rms_deg']:.1f} deg, "
                     f"speed {s['speed_rms_mps']:.2f} m/s, range {s['range_rms_m'] / 1000:.2f} km "
                     f"({100 * s['range_rms_rel']:.0f}%)")
    for k, item in enumerate(later, start=2):
        s = item[sc.target_class]
        lines.append(f"  {sc.target_class}, tack {k} ({item['from_s'] / 60 + 5:g}-{item['to_s'] / 60:g} min): course "
                     f"{s['course_rms_deg']:.1f} deg, speed {s['speed_rms_mps']:.2f} m/s, range "
                     f"{s['range_rms_m'] / 1000:.2f} km")
    for item in detection[1:]:
        d = item["delay_s"]
        lines.append(f"  {sc.target_class}: manoeuvre at {item['from_s'] / 60:g} min declared after "
                     + (f"{d['mean']:.0f} s (median {d['median']:.0f}, max {d['max']:.0f})" if d else "-")
                     + f", missed in {item['missed_runs']} runs")
    lines.append(f"  {sc.target_class}: manoeuvres declared where there was none, per run: "
                 f"{sum(item['false_per_run'] for item in detection):.2f}")
    cov = calibration["all"].get("range", {})
    lines.append(f"  {sc.target_class}: 90 % range interval covers the truth in "
                 f"{100 * cov.get('coverage_90', float('nan')):.0f} % of cycles after {LATE_MIN:g} min "
                 f"(median |error| / sd {cov.get('median_abs_z', float('nan')):.2f}; calibrated: 90 %, 0.67)")
    summary["summary"] = "\n".join(lines)
    return summary


#: The stated sds are checked from this minute on, min (DESIGN.md "K's error and stated
#: uncertainty": every study after its first 10 minutes).
LATE_MIN = 10.0


def weighted_calibration(z: dict, weights, t_s, true_tack) -> dict:
    """The true class's stated sds against the truth after `LATE_MIN`, each run weighted by its
    design weight (eqs. 32-34: the class's distribution), over the whole run and per true tack:
    the weighted share of cycles whose |error| / sd is within 1.645 (the 90 % interval's
    coverage), the weighted median |error| / sd and the weighted mean of its square.

    Parameters
    ----------
    z : dict of str to ndarray, shape (E, T)
        Error over stated sd of course, speed and range (NaN: no estimate).
    weights : ndarray, shape (E,)
    t_s : ndarray, shape (T,)
    true_tack : ndarray of int, shape (T,)
    """
    from tools.studies.calibration import Z90

    late = (np.asarray(t_s) - t_s[0]) / 60.0 >= LATE_MIN
    parts = {"all": late, **{f"tack_{k}": late & (np.asarray(true_tack) == k) for k in np.unique(true_tack)}}
    out = {}
    for name, cycles in parts.items():
        item = {}
        for key, v in z.items():
            a = np.abs(v[:, cycles])
            ww = np.broadcast_to(np.asarray(weights, dtype=float)[:, None], a.shape)
            ok = np.isfinite(a)
            if not ok.any():
                continue
            a, ww = a[ok], ww[ok]
            order = np.argsort(a)
            cum = np.cumsum(ww[order]) / ww.sum()
            item[key] = {"coverage_90": round(float(np.sum(ww * (a <= Z90)) / ww.sum()), 4),
                         "median_abs_z": round(float(a[order][np.searchsorted(cum, 0.5)]), 3),
                         "mean_sq_z": round(float(np.sum(ww * a * a) / ww.sum()), 3)}
        out[name] = item
    return out


def _later_tacks(df: pd.DataFrame, t_s, true_tack) -> list[dict]:
    """Mean RMS per class over each later tack, from 5 min after its start to its end (the
    second tack of gm-tv-30km: 25-40 min)."""
    starts = np.flatnonzero(np.diff(true_tack) > 0) + 1
    ends = list(starts[1:]) + [len(t_s)]
    out = []
    for a, b in zip(starts, ends):
        lo, hi = t_s[a] + 300.0, t_s[b - 1]
        item = {"from_s": float(t_s[a] - t_s[0]), "to_s": float(hi - t_s[0])}
        for name, d in df.groupby("class"):
            sel = d[(d.t_s >= lo) & (d.t_s <= hi)]
            item[name] = {"course_rms_deg": float(sel.course_rms_deg.mean()),
                          "speed_rms_mps": float(sel.speed_rms_mps.mean()),
                          "range_rms_m": float(sel.range_rms_m.mean()),
                          "range_rms_rel": float((sel.range_rms_m / sel.range_true_m).mean())}
        out.append(item)
    return out


def _steady(df: pd.DataFrame, t_s) -> dict:
    """Mean RMS over 5-20 min after detection (the first tack's steady state) per class."""
    out = {}
    for name, d in df.groupby("class"):
        sel = d[(d.t_s >= 300.0) & (d.t_s <= 1200.0)]
        out[name] = {"course_rms_deg": float(sel.course_rms_deg.mean()),
                     "speed_rms_mps": float(sel.speed_rms_mps.mean()),
                     "range_rms_m": float(sel.range_rms_m.mean()),
                     "range_rms_rel": float((sel.range_rms_m / sel.range_true_m).mean())}
    return out
