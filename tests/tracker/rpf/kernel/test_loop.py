"""The whole compiled filter through run_batch: the default engine, independence of the thread
count, the RMSE curves against the numpy reference engine, and cycles without a bearing."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.conftest import profile
from tools.studies.idm import simulate
from tools.studies.idm_scenarios import get_scenario
from tracker.rpf.batch import run_batch
from tracker.rpf.config import Engine, RpfConfig


def _batch(engine, monkeypatch, *, runs, n, levels, seed, threads=1, shrink=False):
    sc = get_scenario("idm-static")
    p = profile(uniform=shrink)  # both K(r) paths of the kernel: the walk and the uniform axis
    t = sc.t_s
    obs = sc.observer_state(t)
    rel = sc.target_state(t) - obs
    b, lv = simulate(sc, p, runs, np.random.default_rng(100))  # same measurements for both
    cfg = RpfConfig(n_particles=n, shrink=shrink, engine=engine)
    res = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b,
                    level_db_meas=lv if levels else None, k_profiles=[p] * t.size, cfg=cfg,
                    rng=np.random.default_rng(seed), threads=threads)
    err = np.hypot(res.mean[:, :, 0] - rel[None, :, 0], res.mean[:, :, 1] - rel[None, :, 1])
    return res, err


def test_kernel_is_the_default_and_independent_of_threads(monkeypatch):
    assert RpfConfig().engine is Engine.KERNEL
    a, _ = _batch("kernel", monkeypatch, runs=9, n=500, levels=True, seed=3, threads=1)
    b, _ = _batch("kernel", monkeypatch, runs=9, n=500, levels=True, seed=3, threads=2)
    c, _ = _batch("kernel", monkeypatch, runs=9, n=500, levels=True, seed=4, threads=1)
    assert_allclose(a.mean, b.mean, rtol=0, atol=0)
    assert_allclose(a.cov, b.cov, rtol=0, atol=0)
    assert np.array_equal(a.resampled, b.resampled)
    assert not np.allclose(a.mean, c.mean)


@pytest.mark.slow
@pytest.mark.parametrize("levels, shrink", [(False, False), (True, False), (True, True)])
def test_rmse_curves_agree_with_the_numpy_reference(levels, shrink, monkeypatch):
    # 100 runs, N = 1000 on idm-static (bearings only, and bearings + SPL with a synthetic
    # K(r)), the same measurements for both engines. The RMSE's Monte Carlo standard error is
    # sd(e^2) / (2 RMSE sqrt(R)) (delta method); the two curves are independent estimates, so
    # their difference is within 4 combined standard errors at each checked cycle unless the
    # statistics differ (4 sd: ~1e-3 false-alarm risk over the 6 checked cycles).
    runs = 100
    res_k, err_k = _batch("kernel", monkeypatch, runs=runs, n=1000, levels=levels, seed=21,
                          shrink=shrink)
    res_n, err_n = _batch("numpy", monkeypatch, runs=runs, n=1000, levels=levels, seed=22,
                          shrink=shrink)
    for k in (10, 30, 60, 90, 120, 150):
        rm_k, rm_n = (np.sqrt(np.mean(e[:, k] ** 2)) for e in (err_k, err_n))
        se = math.hypot(*(np.std(e[:, k] ** 2) / (2 * np.sqrt(np.mean(e[:, k] ** 2))
                                                  * math.sqrt(runs)) for e in (err_k, err_n)))
        assert abs(rm_k - rm_n) < 4 * se, (k, rm_k, rm_n, se)
    # resampling fraction: per-run fractions' standard error, same 4-sd rule
    fk, fn = (r.resampled[:, 1:].mean(axis=1) for r in (res_k, res_n))
    se = math.hypot(fk.std(), fn.std()) / math.sqrt(runs)
    assert abs(fk.mean() - fn.mean()) < 4 * se + 1e-3
    # the filters' own spread: mean position sd at the end within 15 % (a systematic
    # difference in the regularization would show here first)
    sd_k, sd_n = (np.sqrt(r.cov[:, -1, 0, 0] + r.cov[:, -1, 1, 1]).mean() for r in (res_k, res_n))
    assert abs(sd_k / sd_n - 1) < 0.15, (sd_k, sd_n)


def test_track_summaries_and_missing_bearings(monkeypatch):
    t = np.arange(0.0, 600.0, 60.0)
    obs = np.zeros((t.size, 4))
    obs[:, 2] = 2.0
    obs[:, 0] = 2.0 * t
    b = np.full((1, t.size), math.radians(80.0))
    b[0, 3] = np.nan  # a cycle without a bearing: prediction alone
    res = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None,
                    k_profiles=None, cfg=RpfConfig(n_particles=400),
                    rng=np.random.default_rng(1), summaries=True)
    sd = res.extra["sd"]
    assert sd.shape == (1, t.size, 3) and np.all(np.isfinite(sd))
    assert np.all(np.isfinite(res.mean)) and np.all(np.isfinite(res.cov))
