"""The kernel's weights (eqs. 19-20) and moments (eqs. 29-30) against the numpy functions."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.conftest import RTOL, particles
from tracker.rpf.estimate import estimate
from tracker.rpf.kernel.estimate import moments_run
from tracker.rpf.kernel.weights import normalise_run
from tracker.rpf.weights import n_eff, normalise_exp


def test_weights_neff_and_moments_match_rpf():
    rng = np.random.default_rng(12)
    state = particles(rng, d=5)
    log_w = -0.5 * rng.chisquare(3, state.shape[1]) * 4.0 - 1e5
    ref_lw, ref_w = normalise_exp(log_w[None].copy())
    lw, w = log_w.copy(), np.empty_like(log_w)
    neff = normalise_run(lw, w)
    assert_allclose(lw, ref_lw[0], rtol=RTOL)
    assert_allclose(w, ref_w[0], rtol=RTOL)
    assert_allclose(neff, n_eff(ref_w)[0], rtol=RTOL)
    mean, cov = np.empty(5), np.empty((5, 5))
    moments_run(state, w, mean, cov)
    ref_mean, ref_cov = estimate(state[:, None], ref_w)
    assert_allclose(mean, ref_mean[:, 0], rtol=RTOL)
    assert_allclose(cov, ref_cov[0], rtol=RTOL)
    four_m, four_c = np.empty(4), np.empty((4, 4))  # the unrolled 4-state covariance
    moments_run(np.ascontiguousarray(state[:4]), w, four_m, four_c)
    assert_allclose(four_c, ref_cov[0, :4, :4], rtol=RTOL)
