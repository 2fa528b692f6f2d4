"""The kernel's particle spreads against the numpy particle_sds."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tests.tracker.rpf.kernel.conftest import RTOL, particles
from tests.tracker.rpf.kernel.wrappers import summaries_arrays
from tracker.rpf.estimate import particle_sds


def test_summaries_match_rpf_particle_sds():
    rng = np.random.default_rng(15)
    state = particles(rng)
    w = rng.random(state.shape[1])
    w /= w.sum()
    ref = particle_sds(state[:, None], w[None], [1.0, -0.5])[0]
    assert_allclose(summaries_arrays(state, w, 1.0, -0.5), ref, rtol=RTOL)
