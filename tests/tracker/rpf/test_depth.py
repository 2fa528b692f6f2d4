"""The particle filter with the target's depth as a state (compiled kernel) on the tiny grid."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from tracker.rpf import RpfConfig
from tracker.rpf.depthbatch import DepthConfig, run_batch_depth
from tracker.rpf.kernel.depth import k_at_depth
from tracker.rpf.kernel.depthparams import depth_table

pytestmark = pytest.mark.bellhop


def test_the_kernels_k_is_the_tables_k(tiny_depth_grid):
    tk = acoustics.as_tables(tiny_depth_grid).target_depth_k(0, 0)
    table = depth_table(tk, np.zeros(1), 1)
    rng = np.random.default_rng(3)
    for z, r in zip(rng.uniform(0.0, 1000.0, 50), rng.uniform(50.0, 4999.0, 50)):
        # the same bilinear rule; fast-math reassociation moves the last bits only
        assert_allclose(k_at_depth(r, z, table.depth_m, table.range_m, table.k_db, 0, 0, 0.0),
                        tk.at(z, r), atol=1e-9)
    last = tk.range_m[-1]
    beyond = k_at_depth(last + 100.0, 300.0, table.depth_m, table.range_m, table.k_db, 0, 0, 0.0)
    assert_allclose(beyond, tk.at(300.0, last) - BEYOND_GRID_PENALTY_DB, atol=1e-9)


def test_the_depth_state_learns_the_depth_from_the_levels(tiny_depth_grid):
    t = acoustics.as_tables(tiny_depth_grid)
    ic, ib, true_depth, p0 = 0, 0, 400.0, 88.0
    n = 120
    ts = np.arange(n) * 10.0
    obs = np.zeros((n, 4))
    obs[:, 2], obs[:, 0] = 3.0, 3.0 * ts
    tx, ty = 500.0 - ts, np.full(n, 3000.0)
    r = np.hypot(tx - obs[:, 0], ty - obs[:, 1])
    rng = np.random.default_rng(1)
    level = p0 + t.at_target_depth(true_depth).k_at(ic, r)[:, ib] + rng.normal(0.0, 1.0, n)
    bearing = np.arctan2(tx - obs[:, 0], ty - obs[:, 1]) + rng.normal(0.0, np.radians(1.0), n)
    cfg = RpfConfig(n_particles=2000, bearing_sigma_deg=1.0, level_sigma_db=1.5, range_mean_m=3000.0,
                    range_sd_m=800.0, speed_mean_mps=1.0, speed_sd_mps=0.5, shrink=True)
    span = DepthConfig(depth_min_m=20.0, depth_max_m=900.0)
    res = run_batch_depth(t_s=ts, obs_state=obs, bearing_rad_meas=bearing[None],
                          level_db_meas=level[None], target_k=t.target_depth_k(ic, ib),
                          cycle_bearing_deg=np.degrees(bearing), depth=span, cfg=cfg, rng=rng,
                          source_level_model="p0", p0_db=p0, summaries=True)
    depth, sd = res.mean[0][:, -1], np.sqrt(res.cov[0][:, -1, -1])
    assert res.mean.shape == (1, n, 5)
    assert np.all((depth >= 20.0) & (depth <= 900.0))  # the walls hold the particles
    prior_sd = 880.0 / np.sqrt(12.0)                   # uniform over the span: 254 m
    assert abs(sd[0] - prior_sd) < 0.15 * prior_sd     # 2000 draws: a few % off
    # the levels narrow it and pull it to the truth (seeded: 432 +- 99 m at the end, 400 true)
    assert sd[-1] < 0.5 * prior_sd and abs(depth[-1] - true_depth) < 1.5 * sd[-1]
    pos = np.hypot(res.mean[0][-1, 0] + obs[-1, 0] - tx[-1], res.mean[0][-1, 1] + obs[-1, 1] - ty[-1])
    assert pos < 500.0


def test_a_depth_span_must_be_ordered():
    with pytest.raises(ValueError, match="depth span must satisfy"):
        DepthConfig(depth_min_m=300.0, depth_max_m=20.0)
