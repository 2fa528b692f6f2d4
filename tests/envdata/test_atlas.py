"""The [atlas] table of an area file: lattice, listed positions, months, depth axis, screening."""

from __future__ import annotations

import numpy as np
import pytest

import envdata
from envdata.atlas import metres_per_degree
from envdata.atlasarea import radial_reach, screen_positions
from envdata.watersources import load_bathymetry_box
from tests.acoustics.atlas.atlasarea import load_atlas_area


def _doc(**atlas):
    doc = envdata.load_area("shelf-break").to_dict()
    doc["water"] = {k: str(envdata.area_path("shelf-break").parent / v) if k in ("bathymetry", "temperature",
                                                                                  "salinity") else v
                    for k, v in doc["water"].items()}
    doc["atlas"] = atlas
    return doc


def test_the_lattice_rows_and_columns_are_spacing_km_apart_at_the_centre_latitude():
    area = envdata.parse_area(_doc(lat_deg=[42.9, 43.1], lon_deg=[4.9, 5.1], spacing_km=5.0), "t")
    lat, lon, rc = area.atlas.all_positions()
    per_lat, per_lon = metres_per_degree(43.0)
    # 1 deg of latitude at 43 N is 111.1 km (WGS84 meridional radius), of longitude 81.6 km
    assert per_lat == pytest.approx(111_120.0, abs=100.0)
    assert per_lon == pytest.approx(81_550.0, abs=100.0)
    assert area.atlas.lattice_shape == (5, 4)  # 22.2 km / 5 -> 4 steps; 16.3 km / 5 -> 3 steps
    assert np.diff(np.unique(lat)) * per_lat == pytest.approx(np.full(4, 5000.0), abs=1e-6)
    assert lat.min() == 42.9 and lon.min() == 4.9 and lat.max() <= 43.1 and lon.max() <= 5.1
    assert rc[-1].tolist() == [4, 3]
    # the area file reads back equal, [atlas] included
    assert envdata.area_from_json(envdata.area_to_json(area)) == area


@pytest.mark.parametrize(("atlas", "message"), [
    ({"lat_deg": [43.1, 42.9], "lon_deg": [4.9, 5.1], "spacing_km": 5.0}, r"\[atlas\] lat_deg: need"),
    ({"lat_deg": [42.9, 43.1], "lon_deg": [4.9, 5.1], "spacing_km": 0.0}, r"spacing_km: must be"),
    ({"lat_deg": [-80.0, 80.0], "lon_deg": [-170.0, 170.0], "spacing_km": 1.0}, r"more than 100000"),
    ({"lat_deg": [42.9, 43.1], "lon_deg": [4.9, 5.1]}, r"give a lattice"),
    ({"positions": [[43.0, 5.0]], "spacing_km": 5.0}, r"not both"),
    ({"positions": [[43.0, 5.0], [43.0, 5.0]]}, r"duplicate position"),
    ({"positions": [[43.0]]}, r"\[lat_deg, lon_deg\]"),
    ({"positions": [[43.0, 5.0]], "months": [8, 2]}, r"months: must increase"),
    ({"positions": [[43.0, 5.0]], "months": [13]}, r"1\.\.12"),
    ({"positions": [[43.0, 5.0]], "depth_m": [0.0, 50.0, 20.0]}, r"depth_m: depths must increase"),
    ({"positions": [[43.0, 5.0]], "depth_step_m": 10.0, "depth_m": [0.0]}, r"not both"),
    ({"positions": [[43.0, 5.0]], "spacing": 5.0}, r"unknown key 'spacing'"),
])
def test_a_bad_atlas_table_is_refused_naming_the_key(atlas, message):
    with pytest.raises(envdata.AreaError, match=message):
        envdata.parse_area(_doc(**atlas), "t")


def test_months_need_a_climatology():
    doc = envdata.load_area("ocean-deep").to_dict()
    doc["origin"] = {"lat_deg": 45.0, "lon_deg": -30.0}
    doc["bearings"] = {"step_deg": 90.0}
    doc["atlas"] = {"positions": [[45.0, -30.0]], "months": [2, 8]}
    with pytest.raises(envdata.AreaError, match=r"one profile, the same in every month"):
        envdata.parse_area(doc, "t")
    del doc["origin"], doc["bearings"]
    doc["atlas"]["months"] = [2]
    with pytest.raises(envdata.AreaError, match=r"\[atlas\]: needs \[origin\]"):
        envdata.parse_area(doc, "t")


def test_positions_on_land_or_shallower_than_the_observer_are_left_out(tmp_path):
    area = load_atlas_area(tmp_path)
    lat, lon, _ = area.atlas.all_positions()
    bathy = load_bathymetry_box(area, *radial_reach(area, lat, lon))
    keep, left = screen_positions(area, lat, lon, bathy)
    # the northern row is on the shelf (65-100 m of water) under an observer at 100 m
    assert keep.tolist() == [True] * 6 + [False] * 3
    assert all("not deeper than the observer" in p.reason for p in left)
    elevation, _ = bathy.grid.sea_elevation_at(lat, lon)
    assert np.all(-elevation[keep] > 100.0) and np.all(-elevation[~keep] <= 100.0)
