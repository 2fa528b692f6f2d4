"""The filter over a batch of runs (run_batch)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tracker.rpf.batch import run_batch
from tracker.rpf.config import RpfConfig


def test_run_batch_is_deterministic_given_the_seed():
    t = np.arange(0.0, 600.0, 60.0)
    obs = np.zeros((t.size, 4))
    b = np.full((2, t.size), math.radians(80.0))
    cfg = RpfConfig(n_particles=300)
    a = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None,
                  k_profiles=None, cfg=cfg, rng=np.random.default_rng(7))
    c = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None,
                  k_profiles=None, cfg=cfg, rng=np.random.default_rng(7))
    assert_allclose(a.mean, c.mean, rtol=0, atol=0)
    assert a.mean.shape == (2, t.size, 4) and a.cov.shape == (2, t.size, 4, 4)


@pytest.mark.parametrize("engine", ["kernel", "numpy"])
def test_bandwidth_scale_sets_the_kernel_jitter_in_both_engines(engine):
    # one resampling at the second cycle (N_thr = N, bearings so vague that the weights barely
    # differ), no process noise: the regularization then inflates the cloud's covariance by
    # 1 + h^2 / (n + 4) with h the scaled bandwidth (Musso et al.'s kernel, shrink off). The
    # same seed in both configurations draws the same resampling and the same kernel points,
    # so the ratio of the two inflations is that of the two bandwidths' almost exactly
    t = np.array([0.0, 1.0])
    obs = np.zeros((2, 4))
    b = np.full((20, 2), math.radians(80.0))
    out = {}
    for scale in (1.0, 0.25):
        cfg = RpfConfig(n_particles=4000, sigma_a_mps2=0.0, neff_fraction=1.0, bearing_sigma_deg=170.0,
                        bandwidth_scale=scale, engine=engine)
        res = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=b, level_db_meas=None, k_profiles=None,
                        cfg=cfg, rng=np.random.default_rng(11))
        assert res.resampled[:, 1].all()
        out[scale] = np.diagonal(res.cov[:, 1], axis1=1, axis2=2).mean(axis=0)
    h = RpfConfig(n_particles=4000).bandwidth
    assert_allclose(RpfConfig(n_particles=4000, bandwidth_scale=0.25).bandwidth, 0.25 * h, rtol=1e-12)
    expected = (1.0 + h * h / 8.0) / (1.0 + (0.25 * h) ** 2 / 8.0)
    # 20 runs of 4000 particles: the resampling's own scatter of a variance is ~0.4 %; 2 % is 5 x
    assert_allclose(out[1.0] / out[0.25], expected, rtol=0.02)


@pytest.mark.parametrize("scale", [0.0, -0.5, float("nan")])
def test_bandwidth_scale_must_be_positive(scale):
    with pytest.raises(ValueError, match="bandwidth_scale"):
        RpfConfig(bandwidth_scale=scale)
