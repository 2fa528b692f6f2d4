"""Relative course (eq. 8) and course (eq. 7) by hand."""

import math

import numpy as np
from numpy.testing import assert_allclose

from tests.tracker.mltma.conftest import geometry
from tracker.mltma import course_from_relative_deg, relative_course_deg


def test_eq8_relative_course_noiseless():
    t, ox, oy, x, y, b = geometry()
    rel = np.degrees(np.arctan2(6.5 * math.sin(math.radians(300)) - 2.5,
                                6.5 * math.cos(math.radians(300)))) % 360.0
    i0, i1, i2 = np.array([[0, 2]]), np.array([[30, 31]]), np.array([[60, 58]])
    k = relative_course_deg(t, b[None], i0, i1, i2, np.ones((1, 2), bool))
    assert_allclose(k, rel, rtol=0, atol=1e-6)


def test_eq7_course_from_relative_course():
    # V = 6.5 at 300 deg, observer 2.5 m/s at 90 deg: relative velocity (-8.129, 3.25)
    k_rel = math.degrees(math.atan2(-8.1292, 3.25)) % 360.0
    assert_allclose(course_from_relative_deg(k_rel, 6.5, 90.0, 2.5), 300.0, atol=1e-3)
    # stationary observer: course = relative course
    assert_allclose(course_from_relative_deg(123.0, 5.0, 0.0, 0.0), 123.0, atol=1e-12)
