"""Measurement simulator of Grinenkov & Mashoshin section 4 (cycle steps 1-6).

Each cycle: true positions and bearing; band levels W_k = P0 + K_k(r) + dK + H (eqs. 12, 31;
dK drawn once per run); band SNR 10 lg q = W_k - H - (N_k - DI) from the area's sea noise N_k
in the band and the array's directivity index; a band is detected when the indicator SNR
Q = q sqrt(df T) reaches the detection threshold, else its level is blank; level errors with
the sd of eq. 11; bearing error with the sd of eq. 2 from the highest detected band.

Batched over runs (leading axis E) for the Monte Carlo experiment; ``simulate`` is one run.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.detection import indicator_snr
from acoustics.errors import ObserverPositionError
from acoustics.grid.face import Tables
from envdata.errors import InputError
from envdata.files import atomic_paths
from envdata.limits import check_memory
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements, write_measurements
from tracker.ranging import bearing_sd_deg, level_sd_db
from tracker.scenario import Scenario, ScenarioError, observer_track, tack_path

#: A target within this of its class's depth is heard with the class's K as built, m.
TARGET_DEPTH_TOLERANCE_M = 0.01
TRUTH_COLUMNS = ("t_s", "x_m", "y_m", "depth_m", "course_deg", "speed_mps", "class", "noise_db",
                 "tack")


@dataclass(frozen=True, slots=True, kw_only=True)
class SimBatch:
    """E simulated runs of one scenario on a common time axis (arrays (E, T) or (E, T, M))."""

    t_s: np.ndarray
    obs_x_m: np.ndarray            # (T,)
    obs_y_m: np.ndarray
    obs_depth_m: float
    x_m: np.ndarray                # (E, T) target truth
    y_m: np.ndarray
    course_deg: np.ndarray
    speed_mps: np.ndarray
    noise_db: np.ndarray
    tack: np.ndarray               # (T,)
    range_m: np.ndarray
    bearing_true_deg: np.ndarray
    bearing_deg: np.ndarray        # measured
    bearing_sigma_deg: np.ndarray
    level_true_db: np.ndarray      # (E, T, M)
    level_db: np.ndarray           # measured, NaN when not detected
    snr_db: np.ndarray
    band_names: tuple[str, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class TruePaths:
    """Where the target is from the observer every cycle: what a K provider is asked.

    Arrays (T,) for the observer, (E, T) for the runs' targets; plane coordinates of the
    area's origin, m; bearings deg clockwise from north at the observer.
    """

    ic: int
    obs_x_m: np.ndarray
    obs_y_m: np.ndarray
    obs_depth_m: float
    x_m: np.ndarray
    y_m: np.ndarray
    range_m: np.ndarray
    bearing_deg: np.ndarray
    target_depth_m: float


def tables_k(tables: Tables):
    """The K provider of the tables: K of the class at the target's bearing and range, from the
    tables where the observer is each cycle (``Tables.at_observer``), with the target at
    its own depth (``Tables.at_target_depth``) when it is off its class's; (E, T, M), dB."""

    def k_of(p: TruePaths) -> np.ndarray:
        cls = tables.classes[p.ic]
        other_depth = abs(p.target_depth_m - cls.depth_m) > TARGET_DEPTH_TOLERANCE_M
        views = [tables.at_observer(x, y) for x, y in zip(p.obs_x_m, p.obs_y_m)]
        if all(v is views[0] for v in views):  # one set of tables for the whole path
            views = views[:1]
        k = np.empty(p.range_m.shape + (len(tables.bands),))
        for j, view in enumerate(views):
            heard = view.at_target_depth(p.target_depth_m) if other_depth else view
            cycles = slice(None) if len(views) == 1 else slice(j, j + 1)
            k[:, cycles] = heard.k_at(p.ic, p.range_m[:, cycles], p.obs_depth_m,
                                      bearing_deg=p.bearing_deg[:, cycles])
        return k

    return k_of


def simulate_batch(sc: Scenario, tables: Tables, rng: np.random.Generator, *,
                   dv_mps=0.0, dp0_db=0.0, dk_db=None, k_provider=None) -> SimBatch:
    """Simulate E runs of a scenario.

    Parameters
    ----------
    sc : Scenario
    tables : Tables
        Propagation grid of the scenario's area; its K(r) of the scenario's class at the
        scenario's observer depth (`acoustics.grid.face.Tables.k_db`) is the "actual" transfer
        characteristic, linear in range and held at the ends of the range axis. A target at
        another depth than its class's (``[target] depth_m``) is heard with K at its own depth,
        from the tables' depth axis (`acoustics.grid.face.Tables.at_target_depth`).
    rng : numpy.random.Generator
        Measurement errors (levels, bearings) and, when ``dk_db`` is None, dK.
    dv_mps, dp0_db : array_like, shape (E,) or scalar
        Offsets added to every target tack's speed, m/s, and noise P0, dB (the experiment's
        true-speed and true-noise axes).
    dk_db : array_like, shape (E,), optional
        Transfer-characteristic error dK of eq. 31, dB; drawn once per run from the class's
        k_error_sd_db when None.
    k_provider : callable, optional
        K of the true paths, ``k_provider(TruePaths) -> (E, T, M)``, dB: default the tables'
        (`tables_k`); ``acoustics.builder.truthk`` computes it with BELLHOP along each cycle's
        target-to-observer geodesic (``tmakit simulate --truth bellhop``).
    """
    if sc.target_class not in tables.class_names:
        raise MeasurementFileError(f"{sc.source}: [scenario] target_class: {sc.target_class!r} "
                                   f"is not a class of the grid ({', '.join(tables.class_names)})")
    ic = tables.class_index(sc.target_class)
    cls = tables.classes[ic]
    sonar = tables.area.sonar
    dv = np.atleast_1d(np.asarray(dv_mps, dtype=float))
    dp = np.atleast_1d(np.asarray(dp0_db, dtype=float))
    e = max(len(dv), len(dp), 1 if dk_db is None else len(np.atleast_1d(dk_db)))
    dv = np.broadcast_to(dv, (e,))
    dp = np.broadcast_to(dp, (e,))
    dk = (rng.normal(0.0, cls.k_error_sd_db, e) if dk_db is None
          else np.broadcast_to(np.atleast_1d(np.asarray(dk_db, dtype=float)), (e,)))
    n_cycles = math.floor(sc.duration_s / sc.cycle_s + 1e-9) + 1
    # about 12 arrays of (E, T) and 6 of (E, T, M) doubles live at once
    check_memory(8.0 * e * n_cycles * (12 + 6 * len(tables.bands)),
                 f"{sc.source}: simulating {e} run(s) of {n_cycles} cycles")
    t = sc.times_s()
    ox, oy, _, _ = observer_track(sc, t)
    try:
        tables.check_observers(ox, oy)
    except ObserverPositionError as exc:  # the position's index is the cycle's
        raise ScenarioError(f"{sc.source}: the observer's path at t = {t[exc.index]:g} s: {exc.reason}") from None
    except InputError as exc:
        raise ScenarioError(f"{sc.source}: the observer's path: {exc}") from None
    # target path per run: offsets change every tack's speed
    xs, ys, cs, vs, ps = [], [], [], [], []
    for j in range(e):
        tacks = tuple(type(tk)(course_deg=tk.course_deg, speed_mps=max(tk.speed_mps + dv[j], 0.0),
                               duration_s=tk.duration_s, noise_db=tk.noise_db + dp[j])
                      for tk in sc.target_tacks)
        x, y, c, v, tack = tack_path(tacks, sc.target_x_m, sc.target_y_m, t)
        xs.append(x), ys.append(y), cs.append(c), vs.append(v)
        ps.append(np.array([tacks[k - 1].noise_db for k in tack]))
    x, y, c, v, p0 = map(np.array, (xs, ys, cs, vs, ps))
    dx, dy = x - ox, y - oy
    r = np.hypot(dx, dy)
    b_true = np.mod(np.degrees(np.arctan2(dx, dy)), 360.0)
    if tables.outside_depth(sc.obs_depth_m):
        raise ScenarioError(f"{sc.source}: [observer] depth_m: "
                            f"{tables.depth_problem(sc.obs_depth_m)}")
    # K at the target's bearing and range from the observer (between radials for a grid with
    if (k_provider is None and abs(sc.target_depth_m - cls.depth_m) > TARGET_DEPTH_TOLERANCE_M
            and not tables.serves_target_depth):
        raise ScenarioError(
            f"{sc.source}: [target] depth_m: {sc.target_depth_m:g} m is not the depth of class "
            f"{cls.name}'s tables ({cls.depth_m:g} m), and {tables.source} holds no TL from the "
            f"observer for other depths: set depth_m = {cls.depth_m:g}, or give the class a "
            f"depth_range_m in the area file and rebuild the grid")
    # bearings; from the tables where the observer is, for an atlas); NaN where the grid has
    # none (beyond land): no level reaches the observer
    provider = k_provider or tables_k(tables)
    k = provider(TruePaths(ic=ic, obs_x_m=ox, obs_y_m=oy, obs_depth_m=sc.obs_depth_m, x_m=x, y_m=y,
                           range_m=r, bearing_deg=b_true, target_depth_m=sc.target_depth_m))  # (E, T, M)
    w_true = p0[..., None] + k + dk[:, None, None] + sonar.receiver_gain_db
    noise = tables.noise_band_db - sonar.directivity_index_db
    snr_db = w_true - sonar.receiver_gain_db - noise
    q = 10.0 ** (snr_db / 10.0)
    df = tables.bandwidth_hz
    q_ind = np.nan_to_num(indicator_snr(snr_db, df, sonar.integration_time_s), nan=0.0)
    det = q_ind >= sonar.detection_threshold
    sd_w = level_sd_db(q, df, sonar.integration_time_s)
    level = np.where(det, w_true + rng.standard_normal(w_true.shape) * sd_w, np.nan)
    # bearing sd from the highest detected band (eq. 2); with none detected, the best band
    m = det.shape[-1]
    idx = np.where(det.any(axis=-1), m - 1 - np.argmax(det[..., ::-1], axis=-1),
                   np.argmax(q_ind, axis=-1))
    q_b = np.maximum(np.take_along_axis(q_ind, idx[..., None], axis=-1)[..., 0], 1.0)
    sd_p = np.maximum(bearing_sd_deg(sonar.beamwidth_deg, q_b), sc.bearing_sd_min_deg)
    bearing = np.mod(b_true + rng.standard_normal(b_true.shape) * sd_p, 360.0) % 360.0
    tack = tack_path(sc.target_tacks, sc.target_x_m, sc.target_y_m, t)[4]
    return SimBatch(t_s=t, obs_x_m=ox, obs_y_m=oy, obs_depth_m=sc.obs_depth_m, x_m=x, y_m=y,
                    course_deg=c, speed_mps=v, noise_db=p0, tack=tack, range_m=r,
                    bearing_true_deg=b_true, bearing_deg=bearing, bearing_sigma_deg=sd_p,
                    level_true_db=w_true, level_db=level, snr_db=snr_db,
                    band_names=tables.band_names)


def measurements_of(sim: SimBatch, run: int = 0, source: str = "simulated") -> Measurements:
    """The measurements of one simulated run."""
    n = len(sim.t_s)
    return Measurements(source=source, t_s=sim.t_s, obs_x_m=sim.obs_x_m, obs_y_m=sim.obs_y_m,
                        obs_depth_m=np.full(n, sim.obs_depth_m), bearing_deg=sim.bearing_deg[run],
                        bearing_sigma_deg=sim.bearing_sigma_deg[run], band_names=sim.band_names,
                        level_db=sim.level_db[run], snr_db=sim.snr_db[run])


def truth_of(sim: SimBatch, sc: Scenario, run: int = 0) -> pd.DataFrame:
    """Truth table of one run (docs/formats.md "Truth CSV")."""
    n = len(sim.t_s)
    return pd.DataFrame({"t_s": sim.t_s, "x_m": sim.x_m[run], "y_m": sim.y_m[run],
                         "depth_m": np.full(n, sc.target_depth_m),
                         "course_deg": sim.course_deg[run], "speed_mps": sim.speed_mps[run],
                         "class": sc.target_class, "noise_db": sim.noise_db[run],
                         "tack": sim.tack})


def simulate(sc: Scenario, tables: Tables, rng: np.random.Generator, *, k_provider=None):
    """One run: (Measurements, truth DataFrame); dK drawn from the class's k_error_sd_db.
    ``k_provider``: as `simulate_batch`'s."""
    sim = simulate_batch(sc, tables, rng, k_provider=k_provider)
    return measurements_of(sim, 0, source=sc.name), truth_of(sim, sc, 0)


def write_simulation(out_dir: str | os.PathLike, m: Measurements, truth: pd.DataFrame) -> dict:
    """Write measurements.csv and truth.csv into out_dir: both or, on any failure, neither."""
    out = Path(out_dir)
    files = {"measurements": out / "measurements.csv", "truth": out / "truth.csv"}
    with atomic_paths(list(files.values())) as (tmp_m, tmp_t):
        write_measurements(tmp_m, m, atomic=False)
        truth.loc[:, list(TRUTH_COLUMNS)].to_csv(tmp_t, index=False, float_format="%.6f")
    return {key: str(path) for key, path in files.items()}
