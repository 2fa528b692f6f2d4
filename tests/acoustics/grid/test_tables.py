"""TL and K(r) read from a real BELLHOP grid by linear interpolation in depth and range (eq. 13)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.errors import GridFileError
from acoustics.grid.opentables import open_tables
from acoustics.kcurve import spectral_term_db
from acoustics.levelrange import BEYOND_GRID_PENALTY_DB

pytestmark = pytest.mark.bellhop


def _table(grid, cls_name, band):
    """The tables of a grid, and the (class, band) indices of one of its tables."""
    tab = open_tables(grid)
    return tab, tab.class_index(cls_name), tab.band_index(band)


def test_interpolation_returns_grid_values_at_grid_points(tiny_grid):
    tab, ic, ib = _table(tiny_grid, "SUB", "F500")
    grid = tiny_grid["tl_db"].sel({"class": "SUB", "band": "F500"})
    for iz in (0, 3, len(tab.depth_m) - 1):
        for ir in (0, 7, len(tab.range_m) - 1):
            assert_allclose(tab.tl_at(ic, ib, tab.depth_m[iz], tab.range_m[ir]),
                            float(grid.isel(depth=iz, range=ir)), rtol=0, atol=1e-5)


def test_interpolation_is_bilinear_between_grid_points(tiny_grid):
    tab, ic, ib = _table(tiny_grid, "SHIP", "FB1")
    t = tiny_grid["tl_db"].sel({"class": "SHIP", "band": "FB1"}).values.astype(float)
    iz, ir = 4, 10
    z = 0.25 * tab.depth_m[iz] + 0.75 * tab.depth_m[iz + 1]
    r = 0.5 * (tab.range_m[ir] + tab.range_m[ir + 1])
    expected = (0.25 * 0.5 * (t[iz, ir] + t[iz, ir + 1]) + 0.75 * 0.5 * (t[iz + 1, ir] + t[iz + 1, ir + 1]))
    assert_allclose(tab.tl_at(ic, ib, z, r), expected, rtol=0, atol=1e-5)
    # the same through the per-depth profile used by the filter, and vectorised
    prof = tab.tl_profile_db(ic, ib, z)
    assert_allclose(np.interp(r, tab.range_m, prof), expected, rtol=0, atol=1e-5)
    rs = np.linspace(tab.range_m[0], tab.range_m[-1], 57)
    assert_allclose(tab.tl_at(ic, ib, np.full(rs.shape, z), rs), np.interp(rs, tab.range_m, prof),
                    rtol=0, atol=1e-9)


def test_ranges_outside_the_axis_take_the_end_values(tiny_grid):
    tab, ic, ib = _table(tiny_grid, "SUB", "FB1")
    z = tab.depth_m[2]
    assert_allclose(tab.tl_at(ic, ib, z, 1.0), tab.tl_at(ic, ib, z, tab.range_m[0]), atol=1e-9)
    assert_allclose(tab.tl_at(ic, ib, z, 1e7), tab.tl_at(ic, ib, z, tab.range_m[-1]), atol=1e-9)


def test_level_profile_at_the_observer_depth_is_the_grids_k(tiny_grid, tiny_area):
    for cls in tiny_area.classes:
        for band in tiny_area.bands:
            tab, ic, ib = _table(tiny_grid, cls.name, band.name)
            # K = S - TL; S the spectral term of the band (acoustics.kcurve), recovered from the grid
            s_db = tiny_grid["k_db"].sel({"class": cls.name, "band": band.name}).values + \
                tab.tl_profile_db(ic, ib, tiny_area.observer.depth_m)
            assert_allclose(s_db, spectral_term_db(cls, band), rtol=0, atol=1e-3)
            assert tab.spectral_db(ic, ib) == spectral_term_db(cls, band)
            k = tab.level_profile(ic, ib, tiny_area.observer.depth_m)(tab.range_m)
            grid_k = tiny_grid["k_db"].sel({"class": cls.name, "band": band.name}).values
            assert_allclose(k, grid_k, rtol=0, atol=1e-3)
            assert tab.classes[ic].source_level_model == "p0"
            assert_allclose(tab.classes[ic].noise_mean_db, cls.noise_mean_db)


def test_unknown_class_band_and_depth_are_errors(tiny_grid):
    with pytest.raises(GridFileError, match=r"class 'NOPE' is not in the grid \(classes: SUB, SHIP\)"):
        _table(tiny_grid, "NOPE", "FB1")
    with pytest.raises(GridFileError, match=r"band 'F50' is not in the grid"):
        _table(tiny_grid, "SUB", "F50")
    tab, ic, ib = _table(tiny_grid, "SUB", "FB1")
    with pytest.raises(GridFileError, match=r"receiver depth 1500 m is outside the grid's depth axis"):
        tab.tl_at(ic, ib, 1500.0, 1000.0)
    with pytest.raises(GridFileError, match=r"receiver depth -1 m"):
        tab.level_profile(ic, ib, -1.0)


def test_level_profile_rejects_ranges_beyond_the_grid(tiny_grid):
    # beyond the last range the level model has no value: K drops by BEYOND_GRID_PENALTY_DB, so
    # that a particle out there keeps a weight only when every particle is out there
    tab, ic, ib = _table(tiny_grid, "SUB", "FB1")
    prof = tab.level_profile(ic, ib, 100.0)
    r_end, k_end = prof.range_m[-1], prof.k_db[-1]
    assert_allclose(prof(r_end), k_end, atol=1e-9)
    assert_allclose(prof([r_end + 1.0, 1e7]), k_end - BEYOND_GRID_PENALTY_DB, atol=1e-9)
    assert_allclose(prof(0.5 * prof.range_m[0]), prof.k_db[0], atol=1e-9)
