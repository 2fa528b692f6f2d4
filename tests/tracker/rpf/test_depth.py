"""The particle filter with the target's depth as a state (compiled kernel) on the tiny grid."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
from acoustics.grid.targetdepth import TargetDepthK
from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from envdata.classes import SourceLevelModel
from tracker.rpf import RpfConfig
from tracker.rpf.depthbatch import DepthConfig, run_batch_depth
from tracker.rpf.kernel.depth import k_at_depth, pass_k_db
from tracker.rpf.kernel.depthparams import depth_table, regular_part, regular_step

pytestmark = pytest.mark.bellhop


def test_the_kernels_k_is_the_tables_k(tiny_depth_grid):
    tk = acoustics.open_tables(tiny_depth_grid).target_depth_k(0, 0)
    table = depth_table(tk, np.zeros(1), 1)
    rng = np.random.default_rng(3)
    for z, r in zip(rng.uniform(0.0, 1000.0, 50), rng.uniform(50.0, 4999.0, 50)):
        # the same bilinear rule; fast-math reassociation moves the last bits only
        assert_allclose(k_at_depth(r, z, table.depth_m, table.range_m, table.k_db[0], 0, 0, 0.0),
                        tk.at(z, r), atol=1e-9)
    last = tk.range_m[-1]
    beyond = k_at_depth(last + 100.0, 300.0, table.depth_m, table.range_m, table.k_db[0], 0, 0, 0.0)
    assert_allclose(beyond, tk.at(300.0, last) - BEYOND_GRID_PENALTY_DB, atol=1e-9)


def test_the_depth_state_learns_the_depth_from_the_levels(tiny_depth_grid):
    t = acoustics.open_tables(tiny_depth_grid)
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
                          source_level_model=SourceLevelModel.P0, p0_db=p0, summaries=True)
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


def _shifted_last_depth(tk, last_m):
    """``tk`` with its last depth moved to ``last_m`` (a depth axis ending at a bottom between
    two steps, as the shelf-break grid's 0, 10, ..., 2490, 2495.7 m)."""
    depth = np.array(tk.depth_m, dtype=float)
    depth[-1] = last_m
    return TargetDepthK(bearing_deg=tk.bearing_deg, depth_m=depth, range_m=tk.range_m, k_db=tk.k_db)


def _without_surface_rows(tk):
    """``tk`` on its regular rows alone (0, s, 2s, ...: the near-surface rows dropped)."""
    keep = np.r_[0, np.arange(4, len(tk.depth_m))]
    return TargetDepthK(bearing_deg=tk.bearing_deg, depth_m=np.asarray(tk.depth_m)[keep], range_m=tk.range_m,
                        k_db=np.asarray(tk.k_db)[:, keep])


def test_the_loops_k_by_index_arithmetic_is_the_search_rule(tiny_depth_grid):
    tk = acoustics.open_tables(tiny_depth_grid).target_depth_k(0, 0)
    # the table from the observer has its near-surface rows within the first step (6.25, 12.5,
    # 25 m under 50 m steps), searched; the rest by index arithmetic
    assert regular_part(tk.depth_m) == (50.0, 4)
    step = float(tk.depth_m[5] - tk.depth_m[4])
    cases = {"regular after the surface rows": (tk, True),
             "regular": (_without_surface_rows(tk), True),
             "shorter last step": (_shifted_last_depth(tk, tk.depth_m[-2] + 0.3 * step), True),
             "longer last step": (_shifted_last_depth(tk, tk.depth_m[-2] + 1.5 * step), False)}
    rng = np.random.default_rng(4)
    # every cell, the ends, beyond both axes
    z = np.concatenate([rng.uniform(-20.0, tk.depth_m[-1] + 2.0 * step, 300), tk.depth_m])
    r = np.concatenate([rng.uniform(0.0, tk.range_m[-1] + 500.0, 300),
                        np.resize(tk.range_m, tk.depth_m.size)])
    for name, (t, regular) in cases.items():
        table = depth_table(t, np.zeros(1), 1)
        assert table.regular is regular, name
        fast = np.array([pass_k_db(ri, zi, table, 0, 0, 0, 0.0) for ri, zi in zip(r, z)])
        search = np.array([k_at_depth(ri, zi, table.depth_m, table.range_m, table.k_db[0], 0, 0, 0.0)
                           for ri, zi in zip(r, z)])
        # the cell weight by (v - first) / step against (v - a[j]) / (a[j+1] - a[j]): rounding
        # only; pass_k_db reads K back through a square root of (1e4 + K)^2, 1e-12 relative
        assert_allclose(fast, search, rtol=0, atol=1e-8, err_msg=name)
        inside = (z >= t.depth_m[0]) & (z <= t.depth_m[-1]) & (r <= t.range_m[-1])
        assert_allclose(fast[inside], t.at(z[inside], r[inside]), rtol=0, atol=1e-8, err_msg=name)


def test_regular_step_refuses_uneven_axes():
    assert regular_part([0.0, 1.25, 2.5, 5.0, 10.0, 20.0, 25.0]) == (10.0, 4)
    assert regular_part([0.0, 10.0, 20.0]) == (10.0, 0) and regular_part([0.0, 15.0, 20.0, 30.0]) == (None, 0)
    assert regular_step([0.0, 10.0, 20.0, 25.0]) == 10.0
    assert regular_step([0.0, 10.0, 21.0, 30.0]) is None
    assert regular_step([0.0, 10.0, 20.0, 35.0]) is None
    assert regular_step([5.0]) is None


#: The depth state's final estimates over the 40 runs of `test_the_depth_estimates_are_those_of_
#: the_first_kernel`, from the first kernel (commit 697f842: two walk normals per particle drawn,
#: one used; cells by search), the same seeds: mean 379.01 m, sd over runs 10.63 m, mean
#: posterior sd 31.84 m.
FIRST_KERNEL_DEPTH_MEAN_M, FIRST_KERNEL_DEPTH_SD_M, FIRST_KERNEL_POSTERIOR_SD_M = 379.01, 10.63, 31.84


def test_the_depth_estimates_are_those_of_the_first_kernel(tiny_depth_grid):
    """Same seed, same statistics: the faster loop draws one walk normal per particle instead of
    two, so its random stream, and each run's numbers, differ from the first kernel's; their
    distribution over runs must not."""
    t = acoustics.open_tables(tiny_depth_grid)
    ic, ib, true_depth, p0, n, runs = 0, 0, 400.0, 88.0, 120, 40
    ts = np.arange(n) * 10.0
    obs = np.zeros((n, 4))
    obs[:, 2], obs[:, 0] = 3.0, 3.0 * ts
    tx, ty = 500.0 - ts, np.full(n, 3000.0)
    r = np.hypot(tx - obs[:, 0], ty - obs[:, 1])
    rng = np.random.default_rng(1)
    level = p0 + t.at_target_depth(true_depth).k_at(ic, r)[:, ib] + rng.normal(0.0, 1.0, (runs, n))
    bearing = np.arctan2(tx - obs[:, 0], ty - obs[:, 1]) + rng.normal(0.0, np.radians(1.0), (runs, n))
    cfg = RpfConfig(n_particles=2000, bearing_sigma_deg=1.0, level_sigma_db=1.5, range_mean_m=3000.0,
                    range_sd_m=800.0, speed_mean_mps=1.0, speed_sd_mps=0.5, shrink=True)
    res = run_batch_depth(t_s=ts, obs_state=obs, bearing_rad_meas=bearing, level_db_meas=level,
                          target_k=t.target_depth_k(ic, ib), cycle_bearing_deg=np.degrees(bearing[0]),
                          depth=DepthConfig(depth_min_m=20.0, depth_max_m=900.0), cfg=cfg,
                          rng=np.random.default_rng(7), source_level_model=SourceLevelModel.P0, p0_db=p0)
    depth = res.mean[:, -1, -1]
    posterior_sd = np.sqrt(res.cov[:, -1, -1, -1])
    # two independent samples of 40 runs: the means' difference has sd
    # sqrt(10.6^2 + s^2) / sqrt(40) ~ 2.6 m (s ~ 12.8 m, this kernel's): within 4 of those
    # (a 6e-5 chance of failing when the laws are equal); a wrong cell or a walk of the wrong
    # size moves the estimate by tens of metres (the depth sd at the end is ~32 m)
    se = np.hypot(FIRST_KERNEL_DEPTH_SD_M, depth.std(ddof=1)) / np.sqrt(runs)
    assert abs(depth.mean() - FIRST_KERNEL_DEPTH_MEAN_M) < 4.0 * se
    # the spread over runs: an F ratio of two 40-run variances is within [0.5, 2] at the
    # 3-sigma level (sd ratio within [0.7, 1.4])
    assert 0.7 < depth.std(ddof=1) / FIRST_KERNEL_DEPTH_SD_M < 1.4
    # the posterior sd, averaged over 40 runs: its run-to-run sd is some 10 % of it, its mean's
    # a few %: within 10 %
    assert abs(posterior_sd.mean() / FIRST_KERNEL_POSTERIOR_SD_M - 1.0) < 0.10
