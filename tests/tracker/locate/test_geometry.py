"""Bearing geometry and conditioning (eqs. 10-12): u, |P| and the system P x = b."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from tracker import locate as loc


def test_conditioning_of_30_and_31_deg_is_about_115_eq11():
    # the paper's example below eq. 12: s_max = 1.4142, s_min = 0.0123, u "about 115",
    # |P| = -0.0175; u = cot(0.5 deg) = 114.59 exactly, hence atol 0.5 on "about 115"
    p, _ = loc.bearing_system([0.0, 0.0], [0.0, 0.0], [30.0, 31.0])
    assert_allclose(p, [[0.8660, -0.5000], [0.8572, -0.5150]], atol=5e-5)
    sv = np.linalg.svd(p, compute_uv=False)
    assert_allclose(sv, [1.4142, 0.0123], atol=5e-5)
    assert_allclose(loc.conditioning_number([30.0, 31.0]), 115.0, atol=0.5)
    assert_allclose(np.linalg.det(p), -0.0175, atol=5e-5)  # eq. 10: sin(30 - 31 deg)
    assert_allclose(loc.pair_conditioning(-1.0), loc.conditioning_number([30.0, 31.0]),
                    rtol=1e-12)


def test_perpendicular_bearings_have_u_one_and_unit_determinant_eq12():
    assert_allclose(loc.conditioning_number([30.0, 120.0]), 1.0, rtol=1e-12)
    b = loc.Bearings.from_arrays([0.0, 2000.0], [0.0, 0.0], [45.0, 315.0])
    fix = loc.locate(b, method="crossing")
    assert_allclose([fix.x_m, fix.y_m], [1000.0, 1000.0], atol=1e-9)
    assert_allclose(fix.u, 1.0, rtol=1e-12)
    assert_allclose(abs(fix.determinant), 1.0, rtol=1e-12)


def test_parallel_bearings_have_infinite_u():
    assert loc.conditioning_number([45.0, 45.0]) == math.inf
    assert loc.conditioning_number([45.0, 225.0]) == math.inf  # opposite: the same line
