"""Error models (eqs. 2, 11) and level ranging (eqs. 20, 21) against hand values."""

import math

import numpy as np
from numpy.testing import assert_allclose

from acoustics.levelrange import level_range
from tracker.ranging import bearing_sd_deg, level_sd_db, offset_nodes


def test_eq2_bearing_sd():
    # 0.2 * 5 deg / Q: Q = 5 gives 0.2 deg
    assert_allclose(bearing_sd_deg(5.0, 5.0), 0.2, rtol=0, atol=1e-12)


def test_eq11_at_threshold_is_about_1p1_db():
    # small q with q sqrt(df T) = 5: 10 lg(1 + sqrt(2)/5) = 1.078 dB ("does not exceed 1.1 dB")
    df, t = 2000.0, 10.0
    q = 5.0 / math.sqrt(df * t)
    expected = 10 * math.log10(1 + math.sqrt((q + 1) ** 2 + 1) / 5.0)
    assert_allclose(level_sd_db(q, df, t), expected, rtol=0, atol=1e-12)
    assert 1.05 < expected < 1.1


def test_eq20_exact_on_monotone_k_and_eq21_spread():
    r = np.arange(1, 201) * 100.0
    k = np.stack([-20 * np.log10(r), -20 * np.log10(r) - r / 1000.0])     # (2, R)
    true = 7300.0
    w = 100.0 + k[:, 72]
    r_opt, r_sd = level_range(w[None], np.ones((1, 2), bool), np.ones((1, 2)), np.array([100.0]),
                              k, r)
    assert r_opt[0] == true and r_sd[0] == 0.0
    off, wts = offset_nodes(2.5, 2.0, 5)
    _, r_sd = level_range(w[None], np.ones((1, 2), bool), np.ones((1, 2)), np.array([100.0]),
                          k, r, offsets_db=off, weights=wts)
    assert 500.0 < r_sd[0] < 5000.0  # a few dB of offset move the range by ~30-50%
    r_none, _ = level_range(w[None], np.zeros((1, 2), bool), np.ones((1, 2)),
                            np.array([100.0]), k, r)
    assert np.isnan(r_none[0])


def test_a_k_error_sd_the_same_at_every_range_is_the_levels_sd_grown_by_it():
    # the ML analysis folds each band's own K error (no range dependence) into eq. 20's sd: the
    # fast path then answers what the weights over every range answer
    rng = np.random.default_rng(5)
    r = np.linspace(500.0, 30000.0, 300)
    k = np.stack([-20.0 * np.log10(r) - a * r / 1000.0 + rng.normal(0.0, 1.5, r.size) for a in (0.02, 0.05, 0.1)])
    level = 150.0 + k[:, [120, 40, 250]].T.diagonal()[None, :].repeat(4, axis=0) + rng.normal(0.0, 2.0, (4, 3))
    sd = np.full((4, 3), 1.1)
    own = np.array([0.5, 1.0, 2.0, 3.0])
    offsets, weights = offset_nodes(4.0, 3.0)
    detected = np.ones((4, 3), dtype=bool)
    p0 = np.full(4, 150.0)
    slow = level_range(level, detected, sd, p0, k, r, offsets_db=offsets, weights=weights,
                       k_sd_db=np.broadcast_to(own[:, None, None], (4, 3, r.size)))
    fast = level_range(level, detected, np.hypot(sd, own[:, None]), p0, k, r, offsets_db=offsets, weights=weights)
    assert_allclose(fast, slow)
