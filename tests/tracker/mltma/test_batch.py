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
