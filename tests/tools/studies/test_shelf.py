"""The shelf study: a target in a range-dependent area, tracked with both kinds of grid."""

from __future__ import annotations

import json

import numpy as np
import pytest

import acoustics
import envdata
from tools import cli
from tools.studies.shelf import origin_area

pytestmark = [pytest.mark.bellhop, pytest.mark.slow]


def test_the_shortcut_is_the_origins_column_over_a_flat_bottom():
    area = envdata.load_area("shelf-break")
    flat = origin_area(area)
    assert not flat.is_bearing_dependent and flat.water.is_flat
    # the origin sits on the upper slope, some 540-600 m deep
    assert 500.0 < flat.water.depth_m < 650.0
    assert flat.water.ssp.bottom_m == flat.water.depth_m
    assert [c.name for c in flat.classes] == [c.name for c in area.classes]
    assert envdata.area_from_json(envdata.area_to_json(flat)) == flat


def test_the_study_through_the_command_line(tmp_path, capsys):
    out = tmp_path / "shelf"
    assert cli.main(["experiment", "shelf", "shelf-tv", "--runs", "3", "--out", str(out), "--truth", "tables",
                     "--workers", "2", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert sorted(p.name for p in out.iterdir()) == ["grids", "shelf.json", "shelf_rmse.csv",
                                                       "shelf_rmse.png"]
    bearing = acoustics.open_tables(out / "grids" / "shelf-break-bellhop.nc")
    flat = acoustics.open_tables(out / "grids" / "shelf-break-origin-bellhop.nc")
    assert bearing.bearing_axis_deg is not None and flat.bearing_axis_deg is None  # radials, one profile
    errors = summary["mean_rmse_after_5min_m"]
    # the shortcut misplaces the transport: the slope and the basin change K by tens of dB from
    # what one column over a flat bottom gives.  Since the trackers carry the tables' K error
    # (a persistent offset integrated out, the residual growing off the origin) they lean on the
    # bearings where the levels disagree, so the ML analysis loses less than it did (these 3 runs
    # at 12499da: 2.33 against 1.71 km, 1.36x, was 2.9x with the class's 1.5 dB alone; bound 1.2x
    # set after measuring, margin 0.16) and the particle filter still 2.7x (3.95 against 1.49 km;
    # 1.88x, 3.81 against 2.02 km, with the studies' half bandwidth, which on these 3 runs happens
    # to cost the right tables' filter more than the shortcut's; bound 1.5x set after measuring)
    assert errors["ml_isotropic"] > 1.2 * errors["ml_bearing"]
    assert errors["rpf_isotropic"] > 1.5 * errors["rpf_bearing"]
    assert np.isfinite(list(errors.values())).all()
    # every tracker's stated sds are checked against the truth after the first minutes
    cal = summary["calibration_after_late_min"]
    assert set(cal) == {f"{m}_{g}" for m in ("ml", "rpf", "bot") for g in ("bearing", "isotropic")}
    assert all(0.0 <= c[q]["coverage_90"] <= 1.0 for c in cal.values() for q in ("range", "course", "speed"))
    assert (out / "shelf_rmse.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_study_refuses_another_area_before_building_anything(tmp_path):
    from tools.studies import shelf

    with pytest.raises(ValueError, match="shelf-break"):
        shelf.run(runs=1, out_dir=tmp_path / "out", truth="tables", area=envdata.load_area("ocean-deep"))
    assert not (tmp_path / "out").exists()
