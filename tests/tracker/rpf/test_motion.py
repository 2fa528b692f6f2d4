"""Motion model (Iglesis & de Montella eqs. 4-6): prediction and its process noise."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tracker.rpf.motion import predict


def test_predict_without_noise_is_eq4(rng):
    x = np.array([5000.0, 800.0, -1.65, -1.97])
    obs_k = np.array([10.0, 20.0, 1.0, -2.0])
    obs_k1 = np.array([70.0, -100.0, 0.5, 0.5])
    state = np.tile(x[:, None, None], (1, 1, 3))
    predict(state, dt_s=60.0, obs_k=obs_k, obs_k1=obs_k1, sigma_a_mps2=0.0, rng=rng)
    f = np.array([[1, 0, 60, 0], [0, 1, 0, 60], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    assert_allclose(state[:, 0, 0], f @ (x + obs_k) - obs_k1, rtol=1e-12)


def test_process_noise_covariance_is_sigma_a2_gamma_gamma_t(rng):
    dt, sa = 60.0, 1.5e-3
    state = np.zeros((4, 1, 400_000))
    zero = np.zeros(4)
    predict(state, dt_s=dt, obs_k=zero, obs_k1=zero, sigma_a_mps2=sa, rng=rng)
    gamma = np.array([[dt * dt / 2, 0], [0, dt * dt / 2], [dt, 0], [0, dt]])
    expected = sa ** 2 * gamma @ gamma.T
    # sampling sd of a covariance entry: sqrt((s_ii s_jj + s_ij^2) / n); allow 5 sd (a zero
    # entry, x with y, has sd 7.3 / sqrt(400000) = 0.012)
    n = state.shape[2]
    sd = np.sqrt((np.outer(np.diag(expected), np.diag(expected)) + expected ** 2) / n)
    assert (np.abs(np.cov(state[:, 0]) - expected) < 5 * sd).all()
