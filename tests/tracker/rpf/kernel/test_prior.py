"""The kernel's prior particles against the numpy initial_particles."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.conftest import RTOL
from tests.tracker.rpf.kernel.wrappers import init_arrays
from tracker.rpf.config import RpfConfig
from tracker.rpf.kernel.params import prior_of
from tracker.rpf.prior import initial_particles


@pytest.mark.parametrize("span", [(), (500.0, 30_000.0)], ids=["normal", "log-uniform"])
def test_prior_particles_match_rpf_initial_particles(span):
    cfg = RpfConfig(n_particles=3000, range_span_m=span)
    ref = initial_particles(0.7, [1.0, -2.0], cfg, 1, np.random.default_rng(14))[:, 0]
    g = np.random.default_rng(14).standard_normal((4, 1, 3000))[:, 0]
    prior = prior_of(cfg)
    got = init_arrays(np.ascontiguousarray(g), 0.7, 1.0, -2.0, prior)
    assert_allclose(got, ref, rtol=RTOL, atol=1e-9)
