"""K against target depth and range (``acoustics.plots.depthplot``) on the tiny flat grid built
with ``tl_obs_db``: the figure's data read back from its artists (by gid) against the face's
``target_depth_k`` and the class's depths; the bearing-dependent case is in test_radialplots."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import acoustics
from acoustics.errors import GridFileError
from acoustics.plots.depthplot import depth_k_figure
from acoustics.plots.gridplots import PlotRequest, plot_grid, plot_paths
from acoustics.plots.what import What
from envdata.errors import InputError

pytestmark = pytest.mark.bellhop


def by_gid(fig, gid: str):
    found = [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == gid]
    assert len(found) == 1, (gid, len(found))
    return found[0]


def test_the_flat_figure_is_the_tables_k_at_every_target_depth(tiny_depth_grid):
    t = acoustics.open_tables(tiny_depth_grid)
    fig = depth_k_figure(t, cls_name="SUB", band="F500")
    ic, ib = t.class_index("SUB"), t.band_index("F500")
    expected = t.target_depth_k(ic, ib).k_db[0]                       # (Z, R), the one column
    shown = np.ma.filled(np.asarray(by_gid(fig, "depth:k").get_array(), dtype=float), np.nan)
    assert_array_equal(shown.reshape(expected.shape), expected)       # the values drawn, unchanged
    # independently: K at 300 m = S - TL from the observer at 300 m (eq. 13), the grid's own
    # variable read with xarray; the grid holds TL in float32, so the face's K is rounded to
    # float32 (some 4e-6 dB at 60 dB) and this float64 difference is not
    row = int(np.flatnonzero(t.depth_m == 300.0)[0])
    tl_obs = tiny_depth_grid["tl_obs_db"].sel({"class": "SUB", "band": "F500", "depth": 300.0}).values
    assert_allclose(shown.reshape(expected.shape)[row], t.spectral_db(ic, ib) - tl_obs, rtol=0, atol=1e-5)
    assert by_gid(fig, "depth:table").get_ydata()[0] == 150.0          # SUB's tables are at 150 m
    assert by_gid(fig, "depth:span:min").get_ydata()[0] == 20.0        # its depth_range_m
    assert by_gid(fig, "depth:span:max").get_ydata()[0] == 300.0
    assert by_gid(fig, "observer").get_ydata()[0] == 100.0


def test_a_flat_grid_takes_no_bearing_and_needs_tl_obs(tiny_depth_grid, tiny_grid, tmp_path):
    t = acoustics.open_tables(tiny_depth_grid)
    out = tmp_path / "depth.png"
    request = PlotRequest(what=What.DEPTH, bearing_deg=45.0)
    assert plot_paths(t, out, request) == {"depth": out}
    with pytest.raises(InputError, match="a bearing is for a bearing-dependent grid"):
        plot_grid(t, out, request)
    with pytest.raises(GridFileError, match="no TL from the observer depth"):
        plot_grid(acoustics.open_tables(tiny_grid), out, PlotRequest(what=What.DEPTH))
    assert not out.exists()
    written = plot_grid(t, out, PlotRequest(what=What.DEPTH, band="FB1"))
    assert written.files == {"depth": out} and out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
