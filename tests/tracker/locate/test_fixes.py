"""Fixes from bearings: crossing (eqs. 6-8), least squares (eq. 4) and mean (eq. 29).

Also the malformed bearing files that read but give no fix.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tests.tracker.locate.conftest import D_ALPHA, MALFORMED, paper_route
from tests.tracker.locate.test_bearings import MALFORMED_CASES
from tracker import locate as loc
from tracker.errors import LocateError


@pytest.mark.parametrize("method", list(loc.FixMethod))
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
    for method in loc.FixMethod:
        with pytest.raises(LocateError, match=r"parallel or nearly so.*u = 2292 exceeds"):
            loc.locate(b, method=method)
    fix = loc.locate(b, method="crossing", max_u=5000.0)  # a looser limit gives the fix
    assert_allclose(fix.u, 2291.8, atol=0.1)


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


@pytest.mark.parametrize(("name", "method", "match"), LOCATE_CASES)
def test_bearings_that_give_no_fix_raise(name, method, match):
    bearings = loc.read_bearings_csv(MALFORMED / name)
    with pytest.raises(LocateError, match=match) as info:
        loc.locate(bearings, method=method)
    assert "\n" not in str(info.value)


def test_every_malformed_file_is_tested():
    used = {c[0] for c in MALFORMED_CASES} | {c[0] for c in LOCATE_CASES}
    assert {p.name for p in MALFORMED.iterdir()} == used


def test_duplicate_positions_are_found_among_many_rows():
    n = 5000
    ox, oy = np.arange(n) * 10.0, np.zeros(n)
    ox[4321] = ox[17] + 0.0002  # within a millimetre of row 18
    b = loc.Bearings.from_arrays(ox, oy, loc.bearing_to_deg(ox, oy, 1e4, 5e4))
    with pytest.raises(LocateError, match=r"rows 18 and 4322 have the same observer position"):
        loc.locate(b)
