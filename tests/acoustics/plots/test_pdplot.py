"""The P_D figures on real BELLHOP tables: what each line and mesh holds, and "beyond the table"
drawn apart from the ranges."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
from acoustics.grid.pdmap import pd_map
from acoustics.plots.mapplot import map_bearings
from acoustics.plots.pdplot import pd_curves_figure, pd_map_figure

pytestmark = pytest.mark.bellhop


def by_gid(fig, gid: str):
    found = [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == gid]
    assert len(found) == 1, (gid, len(found))
    return found[0]


@pytest.mark.parametrize("band", ["FB1", "any"])
def test_the_map_s_lines_are_the_ranges_and_the_arcs_beyond_the_table(tiny_radial_tables, band):
    t = tiny_radial_tables
    fig, summaries = pd_map_figure(t, band=band)
    bearings = map_bearings(t.bearing_deg)
    for cls_name in t.class_names:
        pm = pd_map(t, cls_name, bearings)
        i = pm.row(band)
        mesh = np.ma.filled(by_gid(fig, f"pd:{cls_name}").get_array(), np.nan).reshape(t.range_m.size, -1)
        assert_allclose(mesh, pm.pd[:, i, :].T, equal_nan=True)
        for level in (0.9, 0.5, 0.1):
            theta, r_km = by_gid(fig, f"pd:{cls_name}:{level:g}").get_data()
            assert_allclose(r_km[:-1] * 1000.0, pm.ranges_m[level][i], equal_nan=True)
            arc = by_gid(fig, f"beyond:{cls_name}:{level:g}").get_data()[1][:-1]
            # an arc outside the outer circle exactly where P_D passes the table's end, no line there
            assert np.array_equal(np.isfinite(arc), pm.beyond[level][i])
            assert np.all(arc[np.isfinite(arc)] > t.range_m[-1] / 1000.0)
            assert np.all(np.isnan(r_km[:-1][pm.beyond[level][i]]))
        assert list(summaries[cls_name].bearing_deg) == list(t.bearing_deg)
    assert np.all(np.isfinite(by_gid(fig, "beyond:SHIP:0.1").get_data()[1]))
    assert np.all(np.isnan(by_gid(fig, "beyond:SUB:0.1").get_data()[1]))


def test_a_flat_grid_s_curves_are_p_d_against_range(tiny_grid):
    t = acoustics.open_tables(tiny_grid)
    fig, summaries = pd_curves_figure(t)
    for cls_name in t.class_names:
        pm = summaries[cls_name]
        for i, row in enumerate(pm.rows):
            r_km, p = by_gid(fig, f"pd:{cls_name}:{row}").get_data()
            assert_allclose(r_km, t.range_m / 1000.0)
            assert_allclose(p, pm.pd[0, i])
    titles = [ax.get_title() for ax in fig.axes]
    assert any("beyond the table" in s and "SHIP" in s for s in titles)
    assert not any("beyond the table" in s and "SUB" in s for s in titles)
