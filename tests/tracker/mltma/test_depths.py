"""The ML analysis over depth hypotheses (`tracker.mltma.depths`): the tracks its depths are read along."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from tracker.depth.bank import _carried_back, bearing_fit
from tracker.measurements import Measurements


def _measurements(n: int) -> Measurements:
    t = 20.0 * np.arange(n)
    return Measurements(source="test", t_s=t, obs_x_m=2.0 * t, obs_y_m=np.zeros(n), obs_depth_m=np.full(n, 100.0),
                        bearing_deg=np.full(n, 90.0), bearing_sigma_deg=np.full(n, 0.5), band_names=("FB1",),
                        level_db=np.full((n, 1), 60.0), snr_db=np.full((n, 1), 10.0))


def _track(n: int, turn: int) -> pd.DataFrame:
    """Causal estimates that wander (a converging analysis), a new tack from cycle ``turn``: north
    at 3 m/s, then east at 4 m/s."""
    rng = np.random.default_rng(0)
    t = 20.0 * np.arange(n)
    first = np.arange(n) < turn
    course = np.where(first, 0.0, 90.0)
    speed = np.where(first, 3.0, 4.0)
    x = 5000.0 + rng.normal(0.0, 300.0, n)
    y = 1000.0 + 3.0 * t + rng.normal(0.0, 300.0, n)
    return pd.DataFrame({"x_m": x, "y_m": y, "course_deg": course, "speed_mps": speed,
                         "tack": np.where(first, 1, 2)})


def test_every_tack_is_carried_back_and_every_cycle_has_a_track():
    # a hypothesis that declared a manoeuvre at cycle 40: as known at cycle 59 its track covers
    # cycles 0-59 (its depths are judged on the same levels as every other hypothesis's), each
    # tack the line through that tack's last estimate with that estimate's velocity
    n, turn, i = 60, 40, 59
    m, trk = _measurements(n), _track(n, turn)
    r, b = _carried_back([trk], m, np.array([10, i]))
    assert np.all(np.isfinite(r[0, 1, :i + 1])) and np.all(np.isnan(r[0, 0, 11:]))
    x = m.obs_x_m[:i + 1] + r[0, 1, :i + 1] * np.sin(np.radians(b[0, 1, :i + 1]))
    y = m.obs_y_m[:i + 1] + r[0, 1, :i + 1] * np.cos(np.radians(b[0, 1, :i + 1]))
    t = m.t_s
    for s0, e0, vx, vy in ((0, turn - 1, 0.0, 3.0), (turn, i, 4.0, 0.0)):
        assert_allclose(x[s0:e0 + 1], trk["x_m"][e0] - vx * (t[e0] - t[s0:e0 + 1]), atol=1e-6)
        assert_allclose(y[s0:e0 + 1], trk["y_m"][e0] - vy * (t[e0] - t[s0:e0 + 1]), atol=1e-6)


def test_the_bearings_fit_prefers_the_track_they_lie_on():

    # measured bearings with 0.1 deg noise; one hypothesis's track gives their true values, another
    # is off by 0.5 deg, a third by 0.5 deg only after cycle 20; a bearing missing counts for none
    rng = np.random.default_rng(4)
    true = np.linspace(150.0, 140.0, 40)[None]
    measured = true + rng.normal(0.0, 0.1, true.shape)
    measured[0, 5] = np.nan
    late = true.copy()
    late[0, 20:] += 0.5
    fit = bearing_fit(measured, np.stack([true, true + 0.5, late]))      # (E, T, H)
    assert fit.shape == (1, 40, 3)
    assert np.all(fit[0, 1:, 0] > fit[0, 1:, 1])
    assert_allclose(fit[0, :20, 2], fit[0, :20, 0])
    assert np.all(fit[0, 21:, 2] < fit[0, 21:, 0])
    # the cycle without a bearing adds nothing: as if it were not there
    keep = np.r_[0:5, 6:40]
    without = bearing_fit(measured[:, keep], np.stack([true, true + 0.5, late])[:, :, keep])
    assert_allclose(fit[0, 5], without[0, 4])
    assert_allclose(fit[0, 6:], without[0, 5:])


def test_an_unknown_track_rule_is_refused():
    from tracker.depth.bank import weigh_tracks

    with pytest.raises(ValueError, match="rule must be one of weight, bearings"):
        weigh_tracks(None, 0, _measurements(3), [], [], (0.0, 1.0), rule="nearest")
