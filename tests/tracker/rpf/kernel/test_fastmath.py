"""The kernel's call-free atan2 and exp against the library functions."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.wrappers import bearing_loglik_arrays
from tracker.rpf.kernel.weights import normalise_run


def test_atan2_and_exp_match_the_library():
    rng = np.random.default_rng(5)
    y = rng.standard_normal(100_000) * 10.0 ** rng.uniform(-8, 4, 100_000)
    x = rng.standard_normal(100_000) * 10.0 ** rng.uniform(-8, 4, 100_000)
    a = bearing_loglik_arrays(np.stack([y, x, x, x]), 0.0, math.sqrt(0.5))  # -atan2^2
    assert_allclose(np.sqrt(-a), np.abs(np.arctan2(y, x)), rtol=1e-14, atol=1e-300)
    log_w = -rng.random(10_000) * 700.0
    w = np.empty_like(log_w)
    normalise_run(log_w.copy(), w)
    top = log_w.max()
    assert_allclose(w, np.exp(log_w - top) / np.exp(log_w - top).sum(), rtol=1e-13,
                    atol=1e-300)
