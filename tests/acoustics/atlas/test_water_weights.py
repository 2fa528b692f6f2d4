"""An atlas's weights between positions tempered by the water depth (README "Atlases")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from acoustics.grid.atlas.weights import water_weights


def test_positions_of_the_observers_water_keep_their_bilinear_weights():
    w = np.array([[0.1, 0.2, 0.3, 0.4]])
    out = water_weights(w, np.full((1, 4), 250.0), np.array([250.0]))
    np.testing.assert_allclose(out, w, rtol=0, atol=1e-15)


def test_a_position_ratio_times_deeper_or_shallower_keeps_e_to_minus_half_of_its_share():
    w = np.array([[0.5, 0.5, 0.0], [0.5, 0.5, 0.0]])
    h = np.array([[100.0, 300.0, np.nan], [100.0, 100.0 / 3.0, np.nan]])  # a third position without weight
    out = water_weights(w, h, np.array([100.0, 100.0]), ratio=3.0)
    # the odds of the second position against the first fall by e^-1/2, deeper or shallower alike
    np.testing.assert_allclose(out[:, 1] / out[:, 0], math.exp(-0.5), rtol=1e-12)
    np.testing.assert_allclose(out.sum(axis=1), 1.0, rtol=1e-12)
    assert np.all(out[:, 2] == 0.0)


def test_a_shelf_position_beside_a_slope_observer_counts_for_less():
    # the follow study's 10 km cell at the start: two slope nodes (1156, 1375 m) and two shelf nodes
    # (175, 237 m) around an observer in 595 m of water, bilinear weights about a quarter each
    w = np.array([[0.23, 0.22, 0.28, 0.27]])
    h = np.array([[1156.0, 1375.0, 175.0, 237.0]])
    out = water_weights(w, h, np.array([595.0]))
    assert out[0, 2:].sum() < w[0, 2:].sum() - 0.05   # 0.55 -> 0.49
    assert out[0, 2] / out[0, 3] < w[0, 2] / w[0, 3]   # the shallower of them the less
    # further down the slope (1150 m of water) the shelf is all but gone
    assert water_weights(w, h, np.array([1150.0]))[0, 2:].sum() < 0.3


@pytest.mark.parametrize("h, h_obs", [([[np.nan, 200.0]], [200.0]), ([[0.0, 200.0]], [200.0]),
                                      ([[100.0, 200.0]], [np.nan]), ([[100.0, 200.0]], [-5.0])])
def test_a_depth_not_known_leaves_the_weights_as_they_are(h, h_obs):
    w = np.array([[0.6, 0.4]])
    np.testing.assert_array_equal(water_weights(w, np.array(h), np.array(h_obs)), w)
