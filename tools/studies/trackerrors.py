"""How far the trackers' estimates are from the truth, run by run and cycle by cycle: what the
shelf, follow and kerror studies compare (one simulated batch, tables to track with)."""

from __future__ import annotations

import numpy as np

from acoustics.grid.face import Tables
from envdata.classes import SourceLevelModel
from tracker.mltma import MLBatch, MLParams
from tracker.rpf import RpfConfig, run_batch
from tracker.rpf.track import cycle_profiles

#: eq. 11's level error at the detection threshold, dB (Grinenkov & Mashoshin: "about 1.1 dB").
LEVEL_SD_DB = 1.1


def ml_errors(tables: Tables, sim, cls_index: int, params: MLParams | None = None,
              record: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Position error of the ML analysis, true class, every run and cycle, m (E, T), and the
    tacks it declared per run (E,). ``record``, if given, receives the level range (eq. 20) and
    its sd (eq. 21) of every run and cycle, ``r_level_m`` and ``r_level_sd_m`` (E, T), m."""
    e, t = sim.bearing_deg.shape
    batch = MLBatch(tables, np.full(e, cls_index), t, params)
    vx, vy = np.gradient(sim.obs_x_m, sim.t_s), np.gradient(sim.obs_y_m, sim.t_s)
    err = np.full((e, t), np.nan)
    kept = {"r_level_m": np.full((e, t), np.nan), "r_level_sd_m": np.full((e, t), np.nan)}
    for i in range(t):
        out = batch.update(sim.t_s[i], sim.obs_x_m[i], sim.obs_y_m[i], vx[i], vy[i], sim.bearing_deg[:, i],
                           sim.bearing_sigma_deg[:, i], sim.level_db[:, i, :], sim.snr_db[:, i, :],
                           obs_depth_m=sim.obs_depth_m)
        err[:, i] = np.hypot(out["x_m"] - sim.x_m[:, i], out["y_m"] - sim.y_m[:, i])
        for key, val in kept.items():
            val[:, i] = out[key]
    if record is not None:
        record.update(kept)
    return err, batch.tack.copy()


def rpf_errors(tables: Tables, sim, cls_index: int, band: int, rng: np.random.Generator, n_particles: int,
               *, level_sigma_db: float | None = None, at_observer: bool = True) -> np.ndarray:
    """Position error of the particle filter (bearings and the band's SPL), m (E, T).

    The class's speed statistics; a range prior around the first range with 25 % sd, the same
    whichever tables are tracked with; sigma_l ``level_sigma_db``, by default eq. 11's 1.1 dB and
    the class's K error. ``at_observer``: the K profiles where the observer is each cycle (else
    at the origin, as a grid's tables are the same everywhere)."""
    e, t = sim.bearing_deg.shape
    obs = np.stack([sim.obs_x_m, sim.obs_y_m, np.gradient(sim.obs_x_m, sim.t_s),
                    np.gradient(sim.obs_y_m, sim.t_s)], axis=-1)
    target = tables.classes[cls_index]
    sigma = float(np.hypot(LEVEL_SD_DB, target.k_error_sd_db)) if level_sigma_db is None else level_sigma_db
    r0 = float(np.mean(sim.range_m[:, 0]))
    cfg = RpfConfig(n_particles=n_particles, bearing_sigma_deg=float(np.median(sim.bearing_sigma_deg)),
                    level_sigma_db=sigma, range_mean_m=r0, range_sd_m=0.25 * r0,
                    speed_mean_mps=target.speed_mean_mps, speed_sd_mps=target.speed_sd_mps, shrink=True)
    where = (sim.obs_x_m, sim.obs_y_m) if at_observer else ()
    err = np.empty((e, t))
    for run in range(e):  # each run its own measured bearings, so its own K profiles
        profiles = cycle_profiles(tables, cls_index, band, np.full(t, sim.obs_depth_m), sim.bearing_deg[run], *where)
        res = run_batch(t_s=sim.t_s, obs_state=obs, bearing_rad_meas=np.radians(sim.bearing_deg[run])[None],
                        level_db_meas=sim.level_db[run, :, band][None], k_profiles=profiles, cfg=cfg, rng=rng,
                        source_level_model=SourceLevelModel.P0, p0_db=target.noise_mean_db,
                        p0_sd_db=target.noise_sd_db)
        mean = res.mean[0]
        err[run] = np.hypot(mean[:, 0] + obs[:, 0] - sim.x_m[run], mean[:, 1] + obs[:, 1] - sim.y_m[run])
    return err
