"""Two grids of one area compared (``acoustics.grid.compare``), and two that are not refused."""

from __future__ import annotations

import numpy as np
import pytest

import acoustics
import envdata
from acoustics.grid.compare import GridMismatchError, compare_grids

pytestmark = pytest.mark.bellhop


def _shifted(grid, tl_shift_db: float, k_shift_db: float):
    out = grid.copy(deep=True)
    out["tl_db"] = out["tl_db"] + np.float32(tl_shift_db)
    out["k_db"] = out["k_db"] + k_shift_db
    out.attrs["model"] = "shifted"
    return out


def test_a_known_shift_is_measured_exactly(tiny_grid):
    a = acoustics.open_tables(tiny_grid, name="a.nc")
    b = acoustics.open_tables(_shifted(tiny_grid, 1.5, -0.75), name="b.nc")
    c = compare_grids(a, b)
    assert (c.model_a, c.model_b, c.axis_name) == ("bellhop", "shifted", "depth")
    assert [(r.cls_name, r.band) for r in c.rows] == [(cn, bn) for cn in a.class_names for bn in a.band_names]
    for row in c.rows:
        # float32 TL: the shift survives to 1e-4 dB; the shadows (at the 200 dB cap in A, 201.5 in
        # B) are not compared but counted apart
        assert row.tl_median_db == pytest.approx(1.5, abs=1e-4) and row.tl_p90_db == pytest.approx(1.5, abs=1e-4)
        assert row.tl_signed_median_db == pytest.approx(1.5, abs=1e-4)
        assert row.k_median_db == pytest.approx(0.75, abs=1e-9) and row.k_p90_db == pytest.approx(0.75, abs=1e-9)
        assert row.tl_cells > 0
    assert np.nanmax(np.abs(c.field_db - 1.5)) < 1e-4
    data = c.to_dict()
    assert data["rows"][0]["tl_median_db"] == 1.5 and data["area"] == "tiny-munk"


def test_grids_on_other_axes_are_refused(tiny_grid):
    a = acoustics.open_tables(tiny_grid, name="a.nc")
    shorter = acoustics.open_tables(tiny_grid.isel(range=slice(0, 40)), name="b.nc")
    with pytest.raises(GridMismatchError, match=r"a.nc and b.nc are not grids of one area.*range axis 50 values "
                                                r"100-5000 m against 40 values 100-4000 m"):
        compare_grids(a, shorter)
    other = acoustics.open_tables(acoustics.build_grid(envdata.load_area("munk-1000"), model="urick"), name="m.nc")
    with pytest.raises(GridMismatchError, match=r"area 'tiny-munk' against 'munk-1000'"):
        compare_grids(a, other)
