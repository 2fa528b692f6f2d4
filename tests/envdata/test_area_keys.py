"""Area-file keys of range- and bearing-dependent areas: reading, writing back, area_json round trip."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from envdata.area import MUNK_TABLE_DEPTH_M
from envdata.datafiles import DataFile, file_sha256
from envdata.geometry import Bearings
from tests.conftest import DATA
from tests.envdata.conftest import AREAS, SAMPLE, area_document, make_area

CASTS = DATA / "casts"


def test_shelf_break_keeps_references_to_its_files_not_data(shelf_area):
    water = shelf_area.water
    assert water.depth_m is None and water.ssp is None and water.ts is None
    assert water.bathymetry.file.path == "data/shelf-break_gebco_15s.nc"
    assert water.bathymetry.file.resolved() == SAMPLE / "shelf-break_gebco_15s.nc"
    assert water.climatology.temperature.resolved() == SAMPLE / "shelf-break_woa_t08_04.nc"
    assert water.climatology.salinity.resolved() == SAMPLE / "shelf-break_woa_s08_04.nc"
    assert (shelf_area.origin.lat_deg, shelf_area.origin.lon_deg) == (43.0, 5.0)
    assert (shelf_area.latitude_deg, shelf_area.longitude_deg) == (43.0, 5.0)  # the origin's
    assert shelf_area.bearings.bearing_deg == tuple(float(b) for b in range(0, 360, 30))
    assert shelf_area.propagation.step_m == 25.0
    assert shelf_area.grid.range_max_m == 30000.0
    assert shelf_area.is_bearing_dependent and not envdata.load_area("ocean-deep").is_bearing_dependent


def test_to_dict_writes_the_keys_back_as_given(shelf_area):
    doc = shelf_area.to_dict()
    assert doc["water"] == {"bathymetry": "data/shelf-break_gebco_15s.nc",
                            "temperature": "data/shelf-break_woa_t08_04.nc",
                            "salinity": "data/shelf-break_woa_s08_04.nc"}
    assert doc["origin"] == {"lat_deg": 43.0, "lon_deg": 5.0}
    assert doc["bearings"] == {"step_deg": 30.0}
    assert doc["propagation"]["step_m"] == 25.0
    listed = make_area({"depth_m": 1000.0, "ssp": "munk"}, bearings={"bearing_deg": [10.0, 200.5]})
    assert listed.to_dict()["bearings"] == {"bearing_deg": [10.0, 200.5]}
    assert listed.bearings.bearing_deg == (10.0, 200.5)


def test_area_json_reads_back_without_the_data_files(shelf_area, tmp_path):
    # the area file alone, away from its data: loading touches no data file
    shutil.copy(AREAS / "shelf-break.toml", tmp_path / "shelf-break.toml")
    alone = envdata.load_area(tmp_path / "shelf-break.toml")
    assert alone == shelf_area  # the folder is not part of equality
    assert not alone.water.bathymetry.file.resolved().exists()
    text = envdata.area_to_json(alone)
    again = envdata.area_from_json(text, "grid.nc")
    assert again == shelf_area and envdata.area_to_json(again) == text
    assert again.water.bathymetry.file.folder is None  # area_json: no folder, paths as written
    assert json.loads(text)["water"]["temperature"] == "data/shelf-break_woa_t08_04.nc"


@pytest.mark.parametrize("water", [
    {"bathymetry": "relief.nc", "bathymetry_variable": "z", "climatology": "ts.nc", "month": 2},
    {"depth_m": 800.0, "climatology": "ts.nc"},
    {"bathymetry": "relief.nc", "ssp": "munk", "ssp_interpolation": "S"},
    {"bathymetry": "relief.nc", "ssp_depth_m": [0.0, 100.0, 2000.0], "ssp_speed_mps": [1520.0, 1505.0, 1520.0]},
    {"bathymetry": "relief.nc", "ssp_depth_m": [0.0, 300.0], "temperature_c": [20.0, 13.5],
     "salinity_psu": [38.1, 38.5]},
    {"depth_m": 1000.0, "ssp": "munk"},
    {"bathymetry": "dtm.nc", "temperature": "tem.nc", "salinity": "sal.nc", "month": 8,
     "temperature_variable": "thetao", "salinity_variable": "so"},
], ids=["bathy-clim-month", "flat-clim", "bathy-munk", "bathy-table", "bathy-ts", "flat-origin-munk",
        "named-variables"])
def test_new_keys_round_trip_through_area_json(water):
    area = make_area(water)
    text = envdata.area_to_json(area)
    again = envdata.area_from_json(text)
    assert again == area
    assert envdata.area_to_json(again) == text
    for key in ("bathymetry", "bathymetry_variable", "climatology", "month", "temperature_variable",
                "salinity_variable"):
        if key in water:
            assert json.loads(text)["water"][key] == water[key]


def test_flat_area_json_is_unchanged_by_the_new_keys():
    # an area without [origin] writes exactly the keys it always did, so grid hashes stay put
    doc = envdata.load_area("ocean-deep").to_dict()
    assert set(doc) == {"area", "water", "bottom", "noise", "observer", "sonar", "bands", "classes", "grid",
                        "propagation"}
    assert set(doc["water"]) == {"depth_m", "ssp_depth_m", "ssp_speed_mps", "ssp_interpolation"}
    assert "step_m" not in doc["propagation"]


def test_munk_over_a_bathymetry_is_kept_by_name_and_tabulated_deep():
    area = make_area({"bathymetry": "relief.nc", "ssp": "munk"})
    assert area.water.ssp.kind == "munk" and area.water.ssp.bottom_m == MUNK_TABLE_DEPTH_M
    assert_allclose(area.water.ssp.speed_at(1300.0), 1500.0, rtol=0, atol=1e-9)
    assert area.to_dict()["water"]["ssp"] == "munk"
    with pytest.raises(envdata.AreaError, match=r"depth axis runs to the deepest bottom of the radials"):
        area.depth_m()


def test_ts_table_over_a_bathymetry_stays_temperature_and_salinity():
    area = make_area({"bathymetry": "relief.nc", "ssp_depth_m": [0.0, 300.0],
                      "temperature_c": [20.0, 13.5], "salinity_psu": [38.1, 38.5]})
    ts = area.water.ts
    assert area.water.ssp is None and ts.temperature_c == (20.0, 13.5)
    t, s = ts.ts_at([150.0, 2000.0])  # linear, then the deepest sample continued
    assert_allclose(t, [16.75, 13.5])
    assert_allclose(s, [38.3, 38.5])


def test_flat_cast_becomes_a_profile_to_the_bottom(tmp_path):
    shutil.copy(CASTS / "good.csv", tmp_path / "cast.csv")
    area = make_area({"depth_m": 1200.0, "cast": "cast.csv"}, folder=tmp_path)
    ssp = area.water.ssp
    assert ssp.kind == "cast" and ssp.depth_m[0] == 0.0 and ssp.depth_m[-1] == 1200.0
    assert ssp.depth_m[1:-1] == (2.0, 10.0, 25.0, 50.0, 100.0, 300.0, 600.0, 900.0)
    # below the cast's 900 m its deepest T/S continue: TEOS-10 at 1200 m with 13.0 degC, 38.48
    import gsw

    p = gsw.p_from_z(-1200.0, 43.0)
    c = gsw.sound_speed(gsw.SA_from_SP(38.48, p, 5.0, 43.0),
                        gsw.CT_from_t(gsw.SA_from_SP(38.48, p, 5.0, 43.0), 13.0, p), p)
    assert_allclose(ssp.speed_mps[-1], c, rtol=0, atol=0.001)
    assert area.water.cast.path == "cast.csv"
    # a cast deeper than a flat bottom is cut at the bottom
    shallow = make_area({"depth_m": 400.0, "cast": "cast.csv"}, folder=tmp_path)
    assert shallow.water.ssp.depth_m[-2:] == (300.0, 400.0)


def test_cast_area_rebuilds_from_area_json_without_the_csv(tmp_path):
    shutil.copy(CASTS / "good.csv", tmp_path / "cast.csv")
    for water in ({"depth_m": 1200.0, "cast": "cast.csv"}, {"bathymetry": "relief.nc", "cast": "cast.csv"}):
        area = make_area(water, folder=tmp_path)
        text = envdata.area_to_json(area)
        (tmp_path / "cast.csv").rename(tmp_path / "away.csv")
        try:
            again = envdata.area_from_json(text)
        finally:
            (tmp_path / "away.csv").rename(tmp_path / "cast.csv")
        assert again == area
        assert "cast" not in json.loads(text)["water"]  # the table read from it, not the file
    over_bathymetry = make_area({"bathymetry": "relief.nc", "cast": "cast.csv"}, folder=tmp_path)
    assert over_bathymetry.water.ts.kind == "cast" and over_bathymetry.water.ts.depth_m[0] == 0.0
    assert json.loads(envdata.area_to_json(over_bathymetry))["water"]["temperature_c"][:2] == [22.8, 22.8]


def test_data_file_paths_resolve_against_the_area_folder(tmp_path):
    assert DataFile(path="a/b.nc", folder=tmp_path).resolved() == tmp_path / "a" / "b.nc"
    assert DataFile(path="/abs/b.nc", folder=tmp_path).resolved().as_posix() == "/abs/b.nc"
    assert DataFile(path="b.nc").resolved().as_posix() == "b.nc"
    assert DataFile(path="b.nc", folder=tmp_path) == DataFile(path="b.nc")
    assert DataFile(path="b.nc") != DataFile(path="c.nc")
    (tmp_path / "f.bin").write_bytes(b"abc")
    assert file_sha256(tmp_path / "f.bin") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"


def test_bearings_from_a_step():
    assert Bearings(step_deg=90.0).bearing_deg == (0.0, 90.0, 180.0, 270.0)
    assert len(Bearings(step_deg=0.5).bearing_deg) == 720
    assert Bearings(step_deg=360.0).bearing_deg == (0.0,)


def test_python_api_area_with_an_origin_needs_the_same_position():
    area = make_area({"depth_m": 1000.0, "ssp": "munk"})
    import dataclasses

    with pytest.raises(envdata.AreaError, match=r"differ from \[origin\] 43\.0, 5\.0 deg"):
        dataclasses.replace(area, latitude_deg=45.0)
    with pytest.raises(envdata.AreaError, match=r"\[origin\]: needs \[bearings\]"):
        dataclasses.replace(area, bearings=None)


def test_area_document_keys_are_checked_for_types():
    doc = area_document({"bathymetry": 12, "ssp": "munk"})
    with pytest.raises(envdata.AreaError, match=r"^x\.toml: \[water\] bathymetry: must be a string, got 12$"):
        envdata.parse_area(doc, "x.toml")
    doc = area_document({"depth_m": 1000.0, "ssp": "munk"}, bearings={"bearing_deg": "north"})
    with pytest.raises(envdata.AreaError, match=r"\[bearings\] bearing_deg: must be a non-empty list"):
        envdata.parse_area(doc, "x.toml")
    doc = area_document({"depth_m": 1000.0, "ssp": "munk"})
    doc["origin"]["lat_deg"] = "43N"
    with pytest.raises(envdata.AreaError, match=r"\[origin\] lat_deg: must be a number, got '43N'"):
        envdata.parse_area(doc, "x.toml")
    doc = area_document({"bathymetry": "r.nc", "climatology": "ts.nc", "month": True})
    with pytest.raises(envdata.AreaError, match=r"\[water\] month: must be an integer in 1\.\.12, got True"):
        envdata.parse_area(doc, "x.toml")
    doc = area_document({"bathymetry": "r.nc", "climatology": "ts.nc", "temperature_variable": 3})
    with pytest.raises(envdata.AreaError, match=r"^x\.toml: \[water\] temperature_variable: must be a string, got 3$"):
        envdata.parse_area(doc, "x.toml")
    doc = area_document({"bathymetry": "r.nc", "climatology": "ts.nc", "salinity_variable": " "})
    with pytest.raises(envdata.AreaError, match=r"^x\.toml: \[water\] salinity_variable: must be a variable name, "
                                                r"got ' '$"):
        envdata.parse_area(doc, "x.toml")


def test_observer_must_be_below_the_surface_over_a_bathymetry():
    with pytest.raises(envdata.AreaError, match=r"\[observer\] depth_m: must be > 0 m, got 0\.0"):
        make_area({"bathymetry": "relief.nc", "ssp": "munk"}, observer_m=0.0)


def test_sample_data_total_size_is_small():
    sizes = [p.stat().st_size for p in SAMPLE.iterdir()]
    assert len(sizes) == 3 and sum(sizes) < 400_000
    assert np.all(np.array(sizes) > 10_000)
