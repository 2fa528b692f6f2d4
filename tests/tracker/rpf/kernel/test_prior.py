"""The kernel's prior particles against the numpy initial_particles."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.conftest import RTOL
from tests.tracker.rpf.kernel.wrappers import init_arrays
from tracker.rpf.config import RpfConfig
from tracker.rpf.kernel.params import prior_of
from tracker.rpf.prior import initial_particles


def test_prior_particles_match_rpf_initial_particles():
    cfg = RpfConfig(n_particles=3000)
    ref = initial_particles(0.7, [1.0, -2.0], cfg, 1, np.random.default_rng(14))[:, 0]
    g = np.random.default_rng(14).standard_normal((4, 1, 3000))[:, 0]
    prior = prior_of(cfg)
    got = init_arrays(np.ascontiguousarray(g), 0.7, 1.0, -2.0, prior)
    assert_allclose(got, ref, rtol=RTOL, atol=1e-9)
