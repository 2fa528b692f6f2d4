"""MLBatch, the batched engine: K(r) at the rows' observer depth."""

import numpy as np
import pytest

from acoustics.grid.opentables import open_tables
from tracker.mltma import MLBatch


@pytest.mark.bellhop
def test_level_range_uses_k_at_the_rows_observer_depth(tiny_grid):
    ic = list(tiny_grid["class"].values).index("SHIP")
    raxis = tiny_grid["range"].values
    k300 = open_tables(tiny_grid).k_db(300.0)[ic]
    j = int(np.argmin(np.abs(raxis - 3000.0)))
    r_true = raxis[j]
    p0 = 133.0                                      # the class mean: a perfect prior
    lev = p0 + k300[:, j]                           # W = P0 + K(r) at 300 m (eq. 12)
    est = {}
    for depth in (300.0, None):                     # None: the grid's 100 m observer depth
        batch = MLBatch(open_tables(tiny_grid), [ic], 1)
        out = batch.update(0.0, 0.0, 0.0, 0.0, 2.0, 45.0, 0.5, lev[None, :],
                           np.full((1, 2), 30.0), obs_depth_m=depth)
        est[depth] = float(out["r_level_m"][0])
    # eq. 20 at the right depth recovers the range (grid step 1 node); at 100 m it does not
    assert abs(est[300.0] - r_true) <= raxis[1] - raxis[0]
    assert abs(est[None] - r_true) > abs(est[300.0] - r_true)


def _first_cycle(tables, obs_x_m):
    """The level range and its sd (eq. 21, the first cycle's range sd) of levels that K at the
    middle of the range axis gives, the observer ``obs_x_m`` east of the tables' origin."""
    ic = tables.class_index("SHIP")
    j = tables.range_m.size // 2
    k = tables.k_db(None, bearing_deg=np.array([0.0]))[ic]
    k = k[:, 0] if k.ndim == 3 else k                               # (M, R)
    lev = tables.classes[ic].noise_mean_db + tables.area.sonar.receiver_gain_db + k[:, j]
    out = MLBatch(tables, [ic], 1).update(0.0, obs_x_m, 0.0, 0.0, 2.0, 0.0, 0.5, lev[None, :],
                                          np.full((1, lev.size), 30.0))
    return float(out["r_level_m"][0]), float(out["range_sd_m"][0])


@pytest.mark.bellhop
def test_eq21_widens_with_the_observers_distance_from_where_the_tables_were_computed(tiny_radial_tables, tiny_grid):
    # tables of one position (a radial grid): the same K wherever the observer is, so the same
    # level range, but less sure of it the farther the observer is from that position
    near, mid, far = (_first_cycle(tiny_radial_tables, x) for x in (0.0, 3000.0, 6000.0))
    assert near[0] == mid[0] == far[0]
    assert near[1] < mid[1] < far[1]
    # a flat area's tables hold everywhere: nothing changes with the observer's position
    flat = open_tables(tiny_grid)
    assert _first_cycle(flat, 0.0) == _first_cycle(flat, 6000.0)


@pytest.mark.bellhop
def test_eq21_reads_a_studys_model_at_each_rows_bearing(tiny_radial_tables):
    # a study's model with a small offset on the radial at 0 deg and a large one at 120 deg: two
    # rows with the same levels, one on each radial, get eq. 21 sds in that order
    import xarray as xr

    from acoustics.grid.dataset import with_k_error_model

    t = tiny_radial_tables
    c, m, n = len(t.classes), len(t.bands), t.bearing_axis_deg.size
    off = np.broadcast_to(np.array([0.5, 6.0, 3.0]), (c, m, n)).copy()               # 0, 120, 240 deg
    coords = {"class": t.dataset["class"].values, "band": t.dataset["band"].values, "bearing": t.bearing_axis_deg}
    model = xr.Dataset({"k_offset_sd_db": (("class", "band", "bearing"), off),
                        "k_residual_sd_db": (("class", "band", "bearing"), np.zeros((c, m, n))),
                        "k_residual_length_m": (("class",), np.full(c, 500.0)),
                        "k_offset_band_correlation": (("class",), np.ones(c))}, coords=coords)
    tables = open_tables(with_k_error_model(t.dataset, model, "test"))
    ic = tables.class_index("SHIP")
    j = tables.range_m.size // 2
    lev = []
    for b in (0.0, 120.0):
        k = tables.k_db(None, bearing_deg=np.array([b]))[ic][:, 0]
        lev.append(tables.classes[ic].noise_mean_db + tables.area.sonar.receiver_gain_db + k[:, j])
    out = MLBatch(tables, [ic, ic], 1).update(0.0, 0.0, 0.0, 0.0, 2.0, np.array([0.0, 120.0]), 0.5,
                                              np.array(lev), np.full((2, m), 30.0))
    assert out["r_level_sd_m"][0] < out["r_level_sd_m"][1]
