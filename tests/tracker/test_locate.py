"""Stationary target location (Schmidt et al.): fixes, conditioning, routes, error region.

The paper's example is unit-free (x0 = y0 = 10, VT = 3, first bearing 45 deg, D_alpha = 1 deg);
the formulas are scale-free, so it is used directly as metres here.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tracker import locate as loc
from tracker.errors import LocateError, MeasurementFileError

DATA = Path(__file__).resolve().parents[1] / "data"
MALFORMED = DATA / "malformed" / "locate"

# The paper's Fig. 8 example: observer at the origin, target at (10, 10), leg VT = 3.
X0 = Y0 = 10.0
VT = 3.0
D_ALPHA = 1.0  # the captions say 10; the printed numbers are for 1 degree


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


def paper_route(rule="eq23", n_legs=1, **kw) -> loc.Route:
    return loc.plan_route(target_x_m=X0, target_y_m=Y0, speed_mps=VT, leg_s=1.0, n_legs=n_legs,
                          rule=rule, **kw)


def paper_region(rule="eq23") -> loc.ErrorRegion:
    r = paper_route(rule)
    return loc.error_region(r.obs_x_m, r.obs_y_m, X0, Y0, d_alpha_deg=D_ALPHA)


# ------------------------------------------------------------------ conditioning (eqs. 10-12)

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


# ------------------------------------------------------------------ fixes (eqs. 6-8, 29)

@pytest.mark.parametrize("method", list(loc.Method))
@pytest.mark.parametrize("n", [2, 3, 7])
def test_noise_free_bearings_give_the_target_exactly(method, n, rng):
    tx, ty = rng.uniform(-30e3, 30e3, 2)
    ox = tx + rng.uniform(5e3, 20e3, n) * np.cos(np.linspace(0.0, 2.0, n))
    oy = ty + rng.uniform(5e3, 20e3, n) * np.sin(np.linspace(0.0, 2.0, n))
    b = loc.Bearings.from_arrays(ox, oy, loc.bearing_to_deg(ox, oy, tx, ty))
    fix = loc.locate(b, method=method)
    assert_allclose([fix.x_m, fix.y_m], [tx, ty], rtol=0, atol=1e-6)
    assert_allclose(fix.residual_deg, 0.0, atol=1e-9)
    assert fix.u >= 1.0


def test_lsq_equals_the_crossing_for_two_bearings(rng):
    ox, oy = np.array([0.0, 3000.0]), np.array([0.0, -500.0])
    bearing = np.array([40.0, 20.0]) + rng.uniform(-1.0, 1.0, 2)
    b = loc.Bearings.from_arrays(ox, oy, bearing)
    cross = loc.crossing_fix(b)
    lsq = loc.lsq_fix(b)
    assert_allclose([lsq.x_m, lsq.y_m], [cross.x_m, cross.y_m], atol=1e-6)
    assert_allclose(lsq.u, cross.u, rtol=1e-9)
    assert_allclose(lsq.determinant, abs(cross.determinant), rtol=1e-9)


def test_crossing_solves_eq6_and_determinant_is_eq10(rng):
    ox, oy = rng.uniform(-1e4, 1e4, 2), rng.uniform(-1e4, 1e4, 2)
    tx, ty = 2e4, 3e4
    bearing = loc.bearing_to_deg(ox, oy, tx, ty) + rng.uniform(-2.0, 2.0, 2)
    fix = loc.crossing_fix(loc.Bearings.from_arrays(ox, oy, bearing))
    a = np.radians(bearing)
    p = np.array([[np.cos(a[0]), -np.sin(a[0])], [np.cos(a[1]), -np.sin(a[1])]])  # eq. 6
    rhs = np.array([np.cos(a[k]) * ox[k] - np.sin(a[k]) * oy[k] for k in range(2)])
    assert_allclose([fix.x_m, fix.y_m], np.linalg.solve(p, rhs), rtol=1e-10)  # eq. 8
    assert_allclose(fix.determinant, np.linalg.det(p), rtol=1e-10)
    assert_allclose(fix.determinant, math.sin(a[0] - a[1]), rtol=1e-10)  # eq. 10


def test_mean_is_the_average_of_consecutive_pair_fixes_eq29(rng):
    route = paper_route(n_legs=6, d_alpha_deg=D_ALPHA, rng=rng)
    b = route.bearings()
    mean = loc.mean_fix(b)
    pairs = [loc.crossing_fix(loc.Bearings.from_arrays(b.obs_x_m[k:k + 2], b.obs_y_m[k:k + 2],
                                                       b.bearing_deg[k:k + 2]))
             for k in range(len(b) - 1)]
    assert mean.pair_rows == tuple((k, k + 1) for k in range(6))
    assert_allclose(mean.x_m, np.mean([p.x_m for p in pairs]), rtol=1e-12)
    assert_allclose(mean.y_m, np.mean([p.y_m for p in pairs]), rtol=1e-12)
    assert_allclose(mean.u, max(p.u for p in pairs), rtol=1e-12)


def test_mean_leaves_out_an_ill_conditioned_pair():
    # rows 2 and 3 are 0.01 deg apart (u = 11459): the mean uses pairs (1, 2) and (3, 4)
    tx, ty = 0.0, 10000.0
    ox = np.array([-5000.0, 0.0, 1.7, 5000.0])
    oy = np.array([0.0, 0.0, 0.0, 0.0])
    bearing = loc.bearing_to_deg(ox, oy, tx, ty)
    fix = loc.mean_fix(loc.Bearings.from_arrays(ox, oy, bearing))
    assert fix.pairs_skipped == 1
    assert fix.pair_rows == ((0, 1), (2, 3))
    assert_allclose([fix.x_m, fix.y_m], [tx, ty], atol=1e-6)


def test_nearly_parallel_bearings_raise_with_u_instead_of_a_wild_fix():
    b = loc.Bearings.from_arrays([0.0, 100.0], [0.0, 0.0], [10.0, 9.95])
    for method in loc.Method:
        with pytest.raises(LocateError, match=r"parallel or nearly so.*u = 2292 exceeds"):
            loc.locate(b, method=method)
    fix = loc.locate(b, method="crossing", max_u=5000.0)  # a looser limit gives the fix
    assert_allclose(fix.u, 2291.8, atol=0.1)


def test_bearings_from_arrays_are_validated():
    with pytest.raises(LocateError, match=r"row 2: -5.0 deg is outside \[0, 360\) deg"):
        loc.Bearings.from_arrays([0.0, 1.0], [0.0, 0.0], [45.0, -5.0])
    with pytest.raises(LocateError, match=r"row 1: nan m is not a finite number"):
        loc.Bearings.from_arrays([math.nan, 1.0], [0.0, 0.0], [45.0, 30.0])
    with pytest.raises(LocateError, match="differ in length"):
        loc.Bearings.from_arrays([0.0, 1.0], [0.0], [45.0, 30.0])
    with pytest.raises(LocateError, match="method: must be one of"):
        loc.locate(loc.Bearings.from_arrays([0.0, 1.0], [0.0, 0.0], [45.0, 30.0]), method="x")


# ------------------------------------------------------------------ reading bearings CSV

def test_read_bearings_ignores_extra_columns_in_any_order():
    b = loc.read_bearings_csv(DATA / "locate" / "six_bearings_extra_columns.csv")
    assert len(b) == 6
    assert_allclose(b.t_s, np.arange(6) * 60.0)
    fix = loc.locate(b, method="lsq")
    # the file holds bearings to (-4000, 7500) m rounded to 12 digits
    assert_allclose([fix.x_m, fix.y_m], [-4000.0, 7500.0], atol=1e-3)
    assert list(b.to_frame().columns) == list(loc.BEARING_COLUMNS)


MALFORMED_CASES = [
    ("empty.csv", MeasurementFileError, r"empty\.csv: the file is empty"),
    ("binary.csv", MeasurementFileError, r"binary\.csv: not a text CSV file \(binary data"),
    ("not_utf8.csv", MeasurementFileError, r"not_utf8\.csv: not a text CSV file \(not UTF-8"),
    ("header_only.csv", MeasurementFileError, r"header_only\.csv: no data rows"),
    ("missing_column.csv", MeasurementFileError,
     r"missing_column\.csv: missing column 'bearing_deg'"),
    ("non_numeric.csv", MeasurementFileError,
     r"non_numeric\.csv: row 2 \(line 3\), column obs_x_m: 'east' is not a number \(m\)"),
    ("blank_value.csv", MeasurementFileError,
     r"blank_value\.csv: row 2 \(line 3\), column bearing_deg: blank value"),
    ("nan_bearing.csv", MeasurementFileError,
     r"nan_bearing\.csv: row 2 \(line 3\), column bearing_deg: nan deg is not a finite number"),
    ("bearing_out_of_range.csv", MeasurementFileError,
     r"bearing_out_of_range\.csv: row 2 \(line 3\), column bearing_deg: 360 deg is outside "
     r"\[0, 360\) deg"),
    ("ragged_row.csv", MeasurementFileError,
     r"ragged_row\.csv: row 2 \(line 3\): has 3 fields, the header has 4"),
    ("time_not_increasing.csv", MeasurementFileError,
     r"time_not_increasing\.csv: row 2 \(line 3\), column t_s: 0 s is not after the previous "
     r"row's 600 s"),
]

LOCATE_CASES = [
    ("one_bearing.csv", "lsq", r"one_bearing\.csv: need at least 2 bearings.*got 1"),
    ("duplicate_position.csv", "lsq",
     r"duplicate_position\.csv: rows 2 and 3 have the same observer position "
     r"\(obs_x_m, obs_y_m\) = \(3000, 0\) m"),
    ("parallel.csv", "crossing",
     r"parallel\.csv: the bearing lines of rows 1 and 2 are parallel or nearly so.*u = inf "
     r"exceeds the limit 1000"),
    ("parallel.csv", "lsq", r"parallel\.csv: the 2 bearing lines are parallel or nearly so.*"
                            r"u = inf"),
    ("nearly_parallel.csv", "mean",
     r"nearly_parallel\.csv: the bearing lines of every consecutive pair \(1\) are parallel or "
     r"nearly so \(bearing difference 0.05 deg\): conditioning number u = 2292"),
    ("behind.csv", "crossing",
     r"behind\.csv: the crossing fix \(500.0, 500.0\) m lies behind the observer of row 2 "
     r"\(-707.1 m along its bearing 135 deg\)"),
    ("behind.csv", "lsq", r"behind\.csv: the least-squares fix \(500.0, 500.0\) m lies behind"),
    ("behind.csv", "mean",
     r"behind\.csv: every well-conditioned pair of consecutive bearings crosses behind"),
]


@pytest.mark.parametrize(("name", "error", "match"), MALFORMED_CASES)
def test_malformed_bearing_files_raise(name, error, match):
    with pytest.raises(error, match=match) as info:
        loc.read_bearings_csv(MALFORMED / name)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(("name", "method", "match"), LOCATE_CASES)
def test_bearings_that_give_no_fix_raise(name, method, match):
    bearings = loc.read_bearings_csv(MALFORMED / name)
    with pytest.raises(LocateError, match=match) as info:
        loc.locate(bearings, method=method)
    assert "\n" not in str(info.value)


def test_missing_bearing_file_raises():
    with pytest.raises(MeasurementFileError, match=r"no_such\.csv: cannot read"):
        loc.read_bearings_csv(MALFORMED / "no_such.csv")


def test_every_malformed_file_is_tested():
    used = {c[0] for c in MALFORMED_CASES} | {c[0] for c in LOCATE_CASES}
    assert {p.name for p in MALFORMED.iterdir()} == used


# ------------------------------------------------------------------ course planning (13-23)

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


# ------------------------------------------------------------------ error region (eqs. 24-28)

def test_error_region_matches_the_papers_numbers_fig8():
    reg = paper_region("eq23")
    # d13 (eq. 25) = 0.4936; we get 0.49363 (eq. 25) and 0.49355 (exact chord, which has an
    # extra cos(D_alpha)); both round to the paper's figure, atol 1e-4 is its last digit
    assert_allclose(reg.d13_eq25_m, 0.4936, atol=1e-4)
    assert_allclose(reg.d13_m, 0.4936, atol=1e-4)
    assert_allclose(reg.d13_m, VT * math.sin(math.radians(2 * D_ALPHA)) / (VT / math.hypot(X0, Y0)),
                    rtol=1e-12)  # inscribed-angle chord: VT sin(2 D) / sin(delta)
    # d24 exact = 4.6992 in the paper; we get 4.69987. atol 1e-3: the fourth digit differs,
    # our vertices are exact line crossings (checked below), so we take it as the paper's rounding
    assert_allclose(reg.d24_m, 4.6992, atol=1e-3)
    # eq. 27 as printed gives 4 sin(1 deg) 3 / sin^2(delta) with sin(delta) = VT/R1 = 3/sqrt(200):
    # 4.6540 exactly. The paper prints 4.6662, which eq. 27 cannot give for these inputs
    # (it would need delta = 12.23 deg instead of 12.25 deg); hence atol 0.015 to the paper
    # and a tight check of the formula itself.
    assert_allclose(reg.d24_eq27_m, 4 * math.sin(math.radians(1.0)) * 3.0 / (9.0 / 200.0),
                    rtol=1e-12)
    assert_allclose(reg.d24_eq27_m, 4.6662, atol=0.015)
    # area "1.16": the paper's figure is d13*d24/2 (1.1598); the true (shoelace) area of the
    # quadrilateral is 1.1530 because its diagonals cross at 84 deg, not 90 deg: atol 0.01
    assert_allclose(reg.area_diagonals_m2, 1.16, atol=1e-3)
    assert_allclose(reg.area_m2, 1.16, atol=0.01)
    # eq. 28: d24/d13 ~ 2/sin(delta) = 9.428; the paper's exact diagonals give 4.6992/0.4936
    assert_allclose(reg.ratio_eq28, 2.0 * math.sqrt(200.0) / 3.0, rtol=1e-12)
    assert_allclose(reg.ratio, 4.6992 / 0.4936, atol=0.01)
    assert_allclose(reg.ratio, reg.ratio_eq28, rtol=0.02)
    assert_allclose(reg.delta_deg, math.degrees(math.asin(VT / math.hypot(X0, Y0))), rtol=1e-12)


def test_eq17_first_leg_gives_d13_near_0505():
    reg = paper_region("eq17")
    assert_allclose(reg.d13_eq25_m, 0.5046, atol=1e-4)
    assert_allclose(reg.d13_m, 0.505, atol=1e-3)
    assert reg.d13_m > paper_region("eq23").d13_m


def test_error_region_vertices_lie_on_the_extreme_bearing_lines_fig7():
    route = paper_route("eq23")
    reg = loc.error_region(route.obs_x_m, route.obs_y_m, X0, Y0, d_alpha_deg=D_ALPHA)
    signs = [(1, 1), (1, -1), (-1, -1), (-1, 1)]
    for (e1, e2), (vx, vy) in zip(signs, reg.vertices_m):
        for k, e in ((0, e1), (1, e2)):
            seen = loc.bearing_to_deg(route.obs_x_m[k], route.obs_y_m[k], vx, vy)
            assert_allclose(loc.wrap_deg(seen - route.bearing_deg[k] - e * D_ALPHA), 0.0,
                            atol=1e-9)
    # the diagonals cross practically at the target (the paper): within 2 % of d24
    v = reg.vertices_m
    fx, fy, *_ = loc.crossing_point(v[0, 0], v[0, 1], loc.bearing_to_deg(*v[0], *v[2]),
                                    v[1, 0], v[1, 1], loc.bearing_to_deg(*v[1], *v[3]))
    assert math.hypot(fx - X0, fy - Y0) < 0.02 * reg.d24_m
    assert reg.contains(X0, Y0)


def test_error_polygon_of_two_bearings_is_the_quadrilateral():
    route = paper_route("eq23")
    reg = loc.error_region(route.obs_x_m, route.obs_y_m, X0, Y0, d_alpha_deg=D_ALPHA)
    poly = loc.error_polygon(route.obs_x_m, route.obs_y_m, X0, Y0, d_alpha_deg=D_ALPHA)
    assert_allclose(poly.area_m2, reg.area_m2, rtol=1e-9)
    assert_allclose(poly.diameter_m, reg.d24_m, rtol=1e-9)


def test_error_polygon_shrinks_with_more_bearings():
    route = paper_route("eq23", n_legs=6)
    two = loc.error_polygon(route.obs_x_m[:2], route.obs_y_m[:2], X0, Y0, d_alpha_deg=D_ALPHA)
    all_ = loc.error_polygon(route.obs_x_m, route.obs_y_m, X0, Y0, d_alpha_deg=D_ALPHA)
    assert all_.area_m2 < 0.5 * two.area_m2
    assert all_.contains(X0, Y0)


def test_error_region_needs_bearings_more_than_2_d_alpha_apart():
    # delta = arcsin(3/14.14) = 12.25 deg: D_alpha = 6.2 deg leaves the region open
    route = paper_route("eq23")
    with pytest.raises(LocateError, match=r"differ by 12.25 deg, which does not exceed "
                                          r"2 D_alpha = 12.4 deg"):
        loc.error_region(route.obs_x_m, route.obs_y_m, X0, Y0, d_alpha_deg=6.2)
    with pytest.raises(LocateError, match=r"d_alpha_deg: the bearing error bound must be in "
                                          r"\(0, 45\) deg, got 0.0 deg"):
        loc.error_region(route.obs_x_m, route.obs_y_m, X0, Y0, d_alpha_deg=0.0)


# ------------------------------------------------------------------ Monte Carlo (Fig. 9)

def test_monte_carlo_fixes_lie_in_the_quadrilateral_fig9(rng):
    reg = paper_region("eq23")
    fixed = loc.monte_carlo_first_leg(target_x_m=X0, target_y_m=Y0, leg_m=VT,
                                      d_alpha_deg=D_ALPHA, n_trials=1000, rng=rng,
                                      steer_on_measured=False)
    assert fixed.x_m.size == 1000
    assert np.all(reg.contains(fixed.x_m, fixed.y_m, tol_m=1e-9))  # exact: both wedges
    steered = loc.monte_carlo_first_leg(target_x_m=X0, target_y_m=Y0, leg_m=VT,
                                        d_alpha_deg=D_ALPHA, n_trials=1000, rng=rng)
    # steering on the measured first bearing moves the second point a little; "practically
    # all" fixes stay inside
    assert np.mean(reg.contains(steered.x_m, steered.y_m, tol_m=1e-3)) >= 0.99
    assert np.ptp(steered.obs2_x_m) > 0.0
    # the fixes fill the quadrilateral: they reach near both ends of the long diagonal
    along = np.hypot(steered.x_m - X0, steered.y_m - Y0)
    assert along.max() > 0.35 * reg.d24_m


def test_monte_carlo_mean_is_near_the_papers_eq29(rng):
    mc = loc.monte_carlo_first_leg(target_x_m=X0, target_y_m=Y0, leg_m=VT, d_alpha_deg=D_ALPHA,
                                   n_trials=1000, rng=rng)
    # paper: (10.0531, 10.0385) from 1000 trials. The standard error of a 1000-trial mean is
    # 0.019 in x and 0.023 in y here, so two of them (0.05) bound the difference
    assert_allclose([mc.mean_x_m, mc.mean_y_m], [10.0531, 10.0385], atol=0.05)
    big = loc.monte_carlo_first_leg(target_x_m=X0, target_y_m=Y0, leg_m=VT, d_alpha_deg=D_ALPHA,
                                    n_trials=200_000, rng=rng)
    # the expectation is about (10.038, 10.047) (standard error 0.0015): the paper's values lie
    # within its own sampling error (0.02) of it; the crossing fix is biased away from the
    # observer by about 0.04 = 1 % of d24
    assert_allclose([big.mean_x_m, big.mean_y_m], [10.0531, 10.0385], atol=0.02)
    assert 0.02 < big.mean_x_m - X0 < 0.06 and 0.02 < big.mean_y_m - Y0 < 0.06


def test_monte_carlo_locate_is_unbiased_for_noise_free_limit(rng):
    route = paper_route("eq23", n_legs=5)
    b = route.bearings()
    for method in loc.Method:
        mc = loc.monte_carlo_locate(b, X0, Y0, d_alpha_deg=0.01, n_trials=200, rng=rng,
                                    method=method)
        assert mc.x_m.size == 200
        assert_allclose([mc.mean_x_m, mc.mean_y_m], [X0, Y0], atol=0.01)
    reg = loc.error_region(route.obs_x_m[-2:], route.obs_y_m[-2:], X0, Y0, d_alpha_deg=1.0)
    mc = loc.monte_carlo_locate(b, X0, Y0, d_alpha_deg=1.0, n_trials=500, rng=rng,
                                method="crossing")
    assert np.all(reg.contains(mc.x_m, mc.y_m, tol_m=1e-9))


@pytest.mark.parametrize("method", list(loc.Method))
def test_vectorised_monte_carlo_applies_the_estimator_to_each_trial(method):
    route = paper_route("eq23", n_legs=4)
    b = route.bearings()
    mc = loc.monte_carlo_locate(b, X0, Y0, d_alpha_deg=2.0, n_trials=20,
                                rng=np.random.default_rng(5), method=method)
    # the same draws, one trial at a time through locate()
    errors = np.random.default_rng(5).uniform(-2.0, 2.0, (20, len(b)))
    exact = loc.bearing_to_deg(b.obs_x_m, b.obs_y_m, X0, Y0)
    fixes = [loc.locate(loc.Bearings.from_arrays(b.obs_x_m, b.obs_y_m, (exact + e) % 360.0),
                        method=method) for e in errors]
    assert_allclose(mc.x_m, [f.x_m for f in fixes], rtol=0, atol=1e-9)
    assert_allclose(mc.y_m, [f.y_m for f in fixes], rtol=0, atol=1e-9)


def test_duplicate_positions_are_found_among_many_rows():
    n = 5000
    ox, oy = np.arange(n) * 10.0, np.zeros(n)
    ox[4321] = ox[17] + 0.0002  # within a millimetre of row 18
    b = loc.Bearings.from_arrays(ox, oy, loc.bearing_to_deg(ox, oy, 1e4, 5e4))
    with pytest.raises(LocateError, match=r"rows 18 and 4322 have the same observer position"):
        loc.locate(b)
