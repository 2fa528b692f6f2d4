"""The kernel's prediction (eqs. 4-6) against eq. 4 and the numpy predict."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.conftest import RTOL, particles
from tests.tracker.rpf.kernel.wrappers import predict_arrays
from tracker.rpf.motion import predict
from tracker.rpf.normals import standard_normal_pairs


def test_prediction_matches_eq4_and_rpf_predict():
    rng = np.random.default_rng(6)
    state = particles(rng)
    obs_k, obs_k1 = np.array([100.0, -50.0, 2.0, 1.5]), np.array([220.0, 40.0, 1.0, 2.5])
    dt, sa = 60.0, 1.5e-3
    # the noise predict draws from this seed (its first call of standard_normal_pairs)
    nu = standard_normal_pairs(state.shape[1:], np.random.default_rng(8))
    gx, gy = nu[0].astype(float), nu[1].astype(float)
    ref = state.copy()
    predict(ref, dt_s=dt, obs_k=obs_k, obs_k1=obs_k1, sigma_a_mps2=sa,
            rng=np.random.default_rng(8))
    got = state.copy()
    predict_arrays(got, gx, gy, dt, dt * sa, obs_k[0] + dt * obs_k[2] - obs_k1[0],
                   obs_k[1] + dt * obs_k[3] - obs_k1[1], obs_k[2] - obs_k1[2],
                   obs_k[3] - obs_k1[3])
    # eq. 4 in float64: absolute target state advanced by F and G nu, minus the new observer
    dv = np.stack([gx, gy]) * dt * sa
    tgt = state[:4] + obs_k[:, None]
    expect = np.empty_like(tgt)
    expect[:2] = tgt[:2] + dt * tgt[2:] + 0.5 * dt * dv
    expect[2:] = tgt[2:] + dv
    expect -= obs_k1[:, None]
    assert_allclose(got[:2], expect[:2], rtol=RTOL)
    assert_allclose(got[2:], expect[2:], rtol=RTOL, atol=1e-12)
    # predict scales the float32 noise in float32: agreement to float32 rounding of dv
    assert_allclose(got, ref, rtol=0, atol=dt * 1e-7 * np.abs(dv).max())
