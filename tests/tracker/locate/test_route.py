"""Course planning: eq. 17 and algorithm (23) (eqs. 13-23, Figs. 1-4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tests.tracker.locate.conftest import D_ALPHA, VT, X0, Y0, paper_route
from tracker import locate as loc
from tracker.errors import LocateError


def test_eq23_first_leg_with_r1_known_reaches_the_anticipated_bearing():
    route = paper_route("eq23")
    r1 = math.hypot(X0, Y0)
    alpha2 = 45.0 - math.degrees(math.asin(VT / r1))  # eq. 23, step 2
    assert_allclose(route.bearing_deg, [45.0, alpha2], atol=1e-12)
    assert_allclose(route.course_deg[0], 90.0 + alpha2, atol=1e-12)  # step 3
    assert_allclose(route.range_m[1], math.sqrt(r1 ** 2 - VT ** 2), rtol=1e-12)
    assert_allclose(route.determinant[0], VT / r1, rtol=1e-12)  # eq. 10: sin(arcsin(VT/R1))


def test_eq17_first_leg_is_perpendicular_and_determinant_is_eq18():
    route = paper_route("eq17")
    assert_allclose(route.course_deg[0], 135.0, atol=1e-12)  # eq. 17: alpha1 + 90
    r2 = math.sqrt(X0 ** 2 + Y0 ** 2 + VT ** 2)  # a right angle at the first point
    assert_allclose(route.range_m[1], r2, rtol=1e-12)
    assert_allclose(route.determinant[0], VT / r2, rtol=1e-12)  # eq. 18


def test_eq17_then_eq23_keeps_determinant_constant_fig2():
    # Fig. 2: the two right triangles are identical, R3 = R1 and alpha1 - alpha2 = alpha2 - alpha3
    route = paper_route("eq23", n_legs=2, first_leg_rule="eq17")
    assert_allclose(route.range_m[2], route.range_m[0], rtol=1e-12)
    assert_allclose(route.determinant[1], route.determinant[0], rtol=1e-12)
    assert_allclose(route.course_deg[1], 2 * route.bearing_deg[1] - route.bearing_deg[0] + 90.0,
                    atol=1e-9)  # eq. 20 (with beta measured from north, = 90 + alpha3)


def test_eq23_route_improves_conditioning_and_eq17_degrades_it_fig4():
    good = paper_route("eq23", n_legs=29)
    bad = paper_route("eq17", n_legs=29)
    assert np.all(np.diff(good.u) <= 1e-9)       # u never grows under (23)
    assert np.all(np.diff(bad.u) > 0.0)          # moving away: u grows under eq. 17
    assert good.u[-1] < 3.0 < 9.0 < bad.u[-1]
    # closes the range by sqrt(R^2 - VT^2) until the next step would pass VT/sqrt(2), then circles
    closing = good.range_m[1:] ** 2 - good.range_m[:-1] ** 2
    n_close = int(np.sum(np.isclose(closing, -VT ** 2)))
    assert n_close == 21
    assert_allclose(good.range_m[n_close:], good.range_m[n_close], rtol=1e-9)
    assert np.all(good.range_m >= good.min_range_m)
    # exact bearings: every pair's crossing is the target (step 6)
    assert_allclose(good.fix_x_m, X0, atol=1e-9)
    assert_allclose(good.fix_y_m, Y0, atol=1e-9)


def test_starboard_mirrors_port():
    port = paper_route("eq23", n_legs=4)
    star = paper_route("eq23", n_legs=4, side="starboard")
    # the target on the line y = x: starboard is port mirrored in it (x <-> y)
    assert_allclose(star.obs_x_m, port.obs_y_m, atol=1e-9)
    assert_allclose(star.obs_y_m, port.obs_x_m, atol=1e-9)
    assert_allclose(star.u, port.u, rtol=1e-9)


def test_best_first_course_is_perpendicular_to_the_second_bearing_fig1():
    # Fig. 1 and footnote 1: u is smallest when the course is perpendicular to the second
    # bearing, beta1 = alpha1 + 90 - arcsin(VT/R1); for VT << R1 that tends to eq. 17
    course = np.arange(0.0, 360.0, 0.05)
    for q in (0.05, 0.1, 0.3):
        u = loc.conditioning_vs_course(45.0, q, course)
        best = course[np.argmin(np.where(course < 180.0, u, np.inf))]
        assert_allclose(best, 135.0 - math.degrees(math.asin(q)), atol=0.1)
        assert u[np.argmin(abs(course - 45.0))] > 1e6  # heading at the target: no fix


def test_simulated_route_is_repeatable_and_bearings_within_the_bound():
    a = paper_route("eq23", n_legs=8, d_alpha_deg=D_ALPHA, rng=np.random.default_rng(7))
    b = paper_route("eq23", n_legs=8, d_alpha_deg=D_ALPHA, rng=np.random.default_rng(7))
    assert_allclose(a.obs_x_m, b.obs_x_m, rtol=0)
    true = loc.bearing_to_deg(a.obs_x_m, a.obs_y_m, X0, Y0)
    err = loc.wrap_deg(a.bearing_deg - true)
    assert np.all(np.abs(err) <= D_ALPHA) and np.any(np.abs(err) > 0.1)


@pytest.mark.parametrize(("kw", "match"), [
    ({"speed_mps": 0.0}, r"speed_mps: must be > 0 m/s, got 0.0 m/s"),
    ({"leg_s": -1.0}, r"leg_s: must be > 0 s, got -1.0 s"),
    ({"n_legs": 0}, r"n_legs: must be an integer in \[1, 100000\], got 0"),
    ({"target_x_m": 0.0, "target_y_m": 0.0}, r"coincides with the target guess"),
    ({"min_range_m": -5.0}, r"min_range_m: must be >= 0 m, got -5.0 m"),
    ({"d_alpha_deg": 1.0}, r"needs a random generator"),
])
def test_plan_rejects_bad_options(kw, match):
    args = {"target_x_m": X0, "target_y_m": Y0, "speed_mps": VT, "leg_s": 1.0, "n_legs": 3}
    args.update(kw)
    with pytest.raises(LocateError, match=match):
        loc.plan_route(**args)
