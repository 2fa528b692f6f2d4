"""The one depth rule: TL at given depths from a table on a depth axis."""

from __future__ import annotations

import numpy as np

from acoustics.grid.lookup import tl_at_depths


def test_a_field_linear_in_depth_is_reproduced_between_and_at_the_axis_depths():
    z = np.array([0.0, 10.0, 40.0, 100.0])
    r = np.arange(5.0)
    field = 60.0 + 0.25 * z[:, None] + r[None, :]            # linear in depth at every range
    want = np.array([0.0, 3.0, 10.0, 25.0, 99.5, 100.0])
    got = tl_at_depths(field[None, None], z, want)[0, 0]
    assert got.shape == (want.size, r.size)
    np.testing.assert_allclose(got, 60.0 + 0.25 * want[:, None] + r[None, :], rtol=0, atol=1e-12)


def test_below_the_axis_is_nan_and_above_it_the_first_row():
    z = np.array([5.0, 15.0])
    field = np.array([[1.0, 2.0], [3.0, 4.0]])
    got = tl_at_depths(field, z, [0.0, 15.0, 15.5])
    np.testing.assert_array_equal(got[0], field[0])
    np.testing.assert_array_equal(got[1], field[1])
    assert np.isnan(got[2]).all()


def test_a_one_depth_table_serves_every_depth():
    field = np.array([[[7.0, 8.0, 9.0]]])                    # (class, depth = 1, range)
    got = tl_at_depths(field, np.array([100.0]), [3.0, 250.0])
    assert got.shape == (1, 2, 3)
    np.testing.assert_array_equal(got[0, 1], [7.0, 8.0, 9.0])
