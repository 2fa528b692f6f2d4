"""Monte Carlo of uniform bearing errors (Figs. 5, 6, 9) and the mean fix (eq. 29)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tests.tracker.locate.conftest import D_ALPHA, VT, X0, Y0, paper_region, paper_route
from tracker import locate as loc


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
    for method in loc.FixMethod:
        mc = loc.monte_carlo_locate(b, X0, Y0, d_alpha_deg=0.01, n_trials=200, rng=rng,
                                    method=method)
        assert mc.x_m.size == 200
        assert_allclose([mc.mean_x_m, mc.mean_y_m], [X0, Y0], atol=0.01)
    reg = loc.error_region(route.obs_x_m[-2:], route.obs_y_m[-2:], X0, Y0, d_alpha_deg=1.0)
    mc = loc.monte_carlo_locate(b, X0, Y0, d_alpha_deg=1.0, n_trials=500, rng=rng,
                                method="crossing")
    assert np.all(reg.contains(mc.x_m, mc.y_m, tol_m=1e-9))


@pytest.mark.parametrize("method", list(loc.FixMethod))
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
