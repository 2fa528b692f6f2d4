"""Weights (Iglesis & de Montella eqs. 19-20): logsumexp normalisation and N_eff."""

from __future__ import annotations

import numpy as np
from numpy.testing import assert_allclose

from tracker.rpf.weights import n_eff, normalise


def test_normalise_with_logsumexp_survives_huge_log_likelihoods():
    log_w = np.array([[-1e5, -1e5 - 1.0, -1e5 - 2.0], [0.0, 0.0, 0.0]])
    w = np.exp(normalise(log_w))
    assert_allclose(w.sum(axis=1), 1.0, rtol=1e-9)  # logs near -1e5 keep ~11 digits
    assert_allclose(w[0], np.exp([0, -1, -2]) / np.exp([0, -1, -2]).sum(), rtol=1e-9)


def test_n_eff_eq20():
    assert_allclose(n_eff(np.full((1, 50), 1 / 50)), [50.0])
    assert_allclose(n_eff(np.array([[1.0, 0.0, 0.0]])), [1.0])
    assert_allclose(n_eff(np.array([[0.5, 0.5, 0.0, 0.0]])), [2.0])
