"""The filter over a batch of runs (run_batch)."""

from __future__ import annotations

import math

import numpy as np
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
