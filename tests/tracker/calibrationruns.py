"""Runs whose levels follow the one level model exactly (`tracker.levels`), for the trackers'
calibration tests: the G&M transport's first tack on a synthetic K(r) (the ML tests' grid), each
run's speed, P0 and dK drawn from the class, and a residual along the path (Gauss-Markov over the
model's correlation length of the relative path, the model's sd) added to the levels."""

from __future__ import annotations

import dataclasses

import numpy as np

from acoustics.grid.opentables import open_tables
from tests.tracker.mltma.conftest import synthetic_grid
from tracker.levels import LevelErrors
from tracker.scenario import load_scenario
from tracker.simulate import simulate_batch


def model_runs(seed: int, runs: int = 20):
    """(tables, class index, the simulated batch, the class's LevelErrors)."""
    sc = load_scenario("gm-tv-30km")
    sc = dataclasses.replace(sc, target_tacks=sc.target_tacks[:1])
    tables = open_tables(synthetic_grid(truth_p0=133.02, speed=7.5))
    ic = tables.class_index("TV")
    cls = tables.classes[ic]
    rng = np.random.default_rng(seed)
    first = sc.target_tacks[0]
    sim = simulate_batch(sc, tables, rng,
                         dv_mps=cls.speed_mean_mps - first.speed_mps + rng.normal(0.0, cls.speed_sd_mps, runs),
                         dp0_db=cls.noise_mean_db - first.noise_db + rng.normal(0.0, cls.noise_sd_db, runs),
                         dk_db=rng.normal(0.0, cls.k_error_sd_db, runs))
    errors = LevelErrors.of_tables(tables, ic, [0], source_sd_db=cls.noise_sd_db)
    length, sd = errors.components[1].length_m, errors.components[1].sd_db
    rx, ry = sim.x_m - sim.obs_x_m, sim.y_m - sim.obs_y_m
    step = np.zeros_like(rx)
    step[:, 1:] = np.hypot(np.diff(rx, axis=1), np.diff(ry, axis=1))
    res = np.zeros_like(rx)
    res[:, 0] = rng.normal(0.0, sd, runs)
    for k in range(1, rx.shape[1]):
        rho = np.exp(-step[:, k] / length)
        res[:, k] = rho * res[:, k - 1] + np.sqrt(1.0 - rho * rho) * rng.normal(0.0, sd, runs)
    return tables, ic, dataclasses.replace(sim, level_db=sim.level_db + res[:, :, None]), errors
