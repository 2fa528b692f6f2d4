"""Target classes: the Ross source level of Iglesis & de Montella eq. 12."""

import math

import numpy as np
from numpy.testing import assert_allclose

import envdata


def test_ross_source_level_eq12():
    # the paper's reference: 170 dB at 5.14 m/s (10 kn); 53 dB per decade of speed
    assert_allclose(envdata.ross_source_level_db(5.14), 170.0, rtol=0, atol=1e-9)
    assert_allclose(envdata.ross_source_level_db(10.28), 170.0 + 53 * math.log10(2), rtol=0, atol=1e-9)
    assert_allclose(envdata.ross_source_level_db(51.4), 223.0, rtol=0, atol=1e-9)


def test_ross_source_level_is_finite_for_a_stopped_target():
    # a stopped target keeps the level of the smallest modelled speed, never -inf
    sl = envdata.ross_source_level_db(np.array([0.0, 1e-6]))
    assert np.all(np.isfinite(sl))
    assert_allclose(sl, envdata.ross_source_level_db(envdata.classes.ROSS_MIN_SPEED_MPS), atol=1e-12)
