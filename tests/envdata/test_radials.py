"""Radials: WGS84 geodesics from the origin, bottom sections, land, sound-speed columns, refusals."""

from __future__ import annotations

import gsw
import numpy as np
import pytest
from numpy.testing import assert_allclose
from pyproj import Geod

import envdata
from envdata.radials import MAX_COLUMN_SPACING_M, SHORE_DEPTH_M, area_radials, geodesic_points
from tests.envdata.conftest import make_area, write_dtm, write_relief, write_ts

GEOD = Geod(ellps="WGS84")


def coast_north(lat, lon):
    """Depth grows 1000 m per 0.1 deg southward; the coast is at 43.1 N (linear in latitude)."""
    return -1000.0 + 10000.0 * (lat - 43.0) + 0.0 * lon


def teos10(z, t, s, lat, lon):
    p = gsw.p_from_z(-np.asarray(z, dtype=float), lat)
    sa = gsw.SA_from_SP(s, p, lon, lat)
    return gsw.sound_speed(sa, gsw.CT_from_t(sa, t, p), p)


def test_one_radial_per_bearing_in_the_areas_order(shelf_area, shelf_radials):
    assert [r.bearing_deg for r in shelf_radials] == list(shelf_area.bearings.bearing_deg)
    listed = make_area({"depth_m": 1000.0, "ssp": "munk"}, bearings={"bearing_deg": [10.0, 95.0, 350.0]})
    assert [r.bearing_deg for r in area_radials(listed)] == [10.0, 95.0, 350.0]


def test_samples_lie_on_the_geodesic_at_their_range_and_bearing(shelf_area, shelf_radials):
    origin = shelf_area.origin
    for radial in shelf_radials:
        r = radial.range_m
        az, _, dist = GEOD.inv(np.full(r.shape, origin.lon_deg), np.full(r.shape, origin.lat_deg),
                               radial.lon_deg, radial.lat_deg)
        assert_allclose(dist, np.abs(r), rtol=0, atol=1e-3)
        ahead, behind = r > 1.0, r < -1.0
        assert_allclose(np.mod(az[ahead], 360.0), radial.bearing_deg, rtol=0, atol=1e-6)
        assert_allclose(np.mod(az[behind] - radial.bearing_deg, 360.0), 180.0, rtol=0, atol=1e-6)
    # far out the geodesic is not a rhumb line: at 1000 km due east it has curved south
    lat, lon = geodesic_points(43.0, 5.0, 90.0, [1.0e6])
    assert lat[0] < 42.5 and 17.0 < lon[0] < 18.0


def test_shelf_break_radials_hold_the_interface(shelf_area, shelf_radials):
    for radial in shelf_radials:
        r = radial.range_m
        assert np.all(np.diff(r) > 0) and r[0] == -5000.0 and 0.0 in r
        assert radial.lat_deg.shape == radial.lon_deg.shape == radial.bottom_depth_m.shape == r.shape
        assert np.all(radial.bottom_depth_m >= SHORE_DEPTH_M)
        assert np.all(np.diff(r) <= shelf_area.grid.range_step_m + 1e-6)
        P = radial.ssp_range_m.size
        assert P >= 2 and radial.ssp_range_m[0] < 0.0 and radial.ssp_range_m[-1] == r[-1]
        assert np.all(np.diff(radial.ssp_range_m) <= MAX_COLUMN_SPACING_M + 1e-6)
        z = radial.ssp_depth_m
        assert z[0] == 0.0 and z[-1] == radial.bottom_depth_m.max() and np.all(np.diff(z) > 0)
        assert radial.speed_mps.shape == (z.size, P)
        # the built-in sample's August Mediterranean water: 1507-1549 m/s by TEOS-10 (measured)
        assert np.all((radial.speed_mps > 1500.0) & (radial.speed_mps < 1560.0))
        with pytest.raises(ValueError):
            radial.range_m[0] = 1.0  # frozen arrays
    by_bearing = {r.bearing_deg: r for r in shelf_radials}
    # the coast: north and north-east radials end on land within 30 km, the others reach 30 km
    assert {b for b, r in by_bearing.items() if r.land_range_m is not None} == {0.0, 30.0, 60.0, 330.0}
    for radial in shelf_radials:
        if radial.land_range_m is None:
            assert radial.range_m[-1] == 30000.0
        else:
            # the built-in sample's coast: 22.0-26.7 km along these four radials (measured)
            assert radial.range_m[-1] == radial.land_range_m and 15000.0 < radial.land_range_m < 30000.0
            assert radial.bottom_depth_m[-1] == SHORE_DEPTH_M
            assert radial.bottom_depth_m[-2] < 60.0  # a shoaling shelf before the shore
    south = by_bearing[180.0]
    assert 450.0 < np.interp(0.0, south.range_m, south.bottom_depth_m) < 700.0  # upper slope at the origin
    assert south.bottom_depth_m[-1] > 2400.0  # the basin
    assert 1530.0 < south.speed_mps[0, 0] < 1538.0  # warm August surface
    # the thermocline: 10 m/s slower within 60 m
    assert south.speed_mps[0, 1] - np.interp(60.0, south.ssp_depth_m, south.speed_mps[:, 1]) > 10.0
    # below WOA's 1500 m the deepest T/S continue: the speed grows with pressure, ~0.017 s^-1
    deep = south.ssp_depth_m > 1500.0
    gradient = np.diff(south.speed_mps[deep, -1]) / np.diff(south.ssp_depth_m[deep])
    assert_allclose(gradient, 0.0170, rtol=0.05)


def test_flat_single_profile_area_gives_constant_radials():
    area = make_area({"depth_m": 1000.0, "ssp": "munk"}, bearings={"step_deg": 45.0}, range_max_m=8000.0)
    radials = area_radials(area, behind_m=2000.0)
    assert len(radials) == 8
    for radial in radials:
        assert radial.land_range_m is None
        assert radial.range_m[0] == -2000.0 and radial.range_m[-1] == 8000.0
        assert np.all(radial.bottom_depth_m == 1000.0)
        assert_allclose(np.diff(radial.range_m), area.grid.range_step_m)
        assert np.array_equal(radial.ssp_range_m, [-2000.0, 8000.0])
        assert np.array_equal(radial.ssp_depth_m, area.water.ssp.depth_m)
        assert np.array_equal(radial.speed_mps[:, 0], area.water.ssp.speed_mps)
        assert np.array_equal(radial.speed_mps[:, 0], radial.speed_mps[:, 1])


def test_land_ends_the_radial_at_the_shore(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north)
    area = make_area({"bathymetry": "coast.nc", "ssp": "munk"}, folder=tmp_path, range_max_m=15000.0,
                     bearings={"bearing_deg": [0.0, 90.0, 180.0]})
    north, east, south = area_radials(area)
    _, _, coast_m = GEOD.inv(5.0, 43.0, 5.0, 43.1)  # the shore due north
    assert north.land_range_m == pytest.approx(coast_m, abs=10.0)  # int16 metres of a 10 m/km... relief
    assert north.range_m[-1] == north.land_range_m and north.bottom_depth_m[-1] == SHORE_DEPTH_M
    assert north.range_m[-2] < north.land_range_m <= north.range_m[-2] + 100.0 + 1e-6
    # the bottom follows the plane: 1000 m at the origin, shoaling northward
    assert_allclose(north.bottom_depth_m[:-1], -coast_north(north.lat_deg[:-1], north.lon_deg[:-1]), atol=0.6)
    assert east.land_range_m is None and south.land_range_m is None
    assert east.range_m[-1] == 15000.0 and south.bottom_depth_m[-1] > 2000.0
    # Munk over a bathymetry: cut at each radial's own deepest bottom
    assert south.ssp_depth_m[-1] == pytest.approx(south.bottom_depth_m.max())
    assert_allclose(south.speed_mps[:, 0], envdata.munk_speed_mps(south.ssp_depth_m), atol=0.02)
    # behind a southern radial lies the northern shore: the radial starts there when it is nearer
    (far_back,) = area_radials(make_area({"bathymetry": "coast.nc", "ssp": "munk"}, folder=tmp_path,
                                         range_max_m=5000.0, bearings={"bearing_deg": [180.0]}), behind_m=20000.0)
    assert far_back.range_m[0] == pytest.approx(-coast_m, abs=10.0)
    assert far_back.bottom_depth_m[0] == SHORE_DEPTH_M and far_back.land_range_m is None


def test_one_ts_profile_over_a_bathymetry_continues_its_deepest_ts(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north)
    area = make_area({"bathymetry": "coast.nc", "ssp_depth_m": [0.0, 50.0, 400.0],
                      "temperature_c": [22.0, 15.0, 13.2], "salinity_psu": [38.1, 38.3, 38.5]},
                     folder=tmp_path, range_max_m=10000.0, bearings={"bearing_deg": [180.0]})
    (radial,) = area_radials(area)
    z = radial.ssp_depth_m
    assert z[0] == 0.0 and 50.0 in z and 400.0 in z and z[-1] == radial.bottom_depth_m.max() > 1900.0
    assert np.all(np.diff(z[z > 400.0]) <= 100.0 + 1e-9)  # EXTENSION_STEP_M below the deepest level
    assert np.array_equal(radial.speed_mps[:, 0], radial.speed_mps[:, 1])
    t = np.interp(z, [0.0, 50.0, 400.0], [22.0, 15.0, 13.2])
    s = np.interp(z, [0.0, 50.0, 400.0], [38.1, 38.3, 38.5])
    assert_allclose(radial.speed_mps[:, 0], teos10(z, t, s, 43.0, 5.0), rtol=0, atol=1e-6)


def test_climatology_columns_use_teos10_at_their_latitude_with_ts_filled_down(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north, box=(42.5, 43.2, 4.8, 5.2))

    def temperature(z, y, x):  # horizontally uniform, but the north-east cell is land
        return np.where((y > 43.2) & (x > 5.2), np.nan, 22.0 - 8.0 * (1.0 - np.exp(-z / 200.0)))

    def salinity(z, y, x):
        return np.where((y > 43.2) & (x > 5.2), np.nan, 38.0 + z / 5000.0)

    write_ts(tmp_path, temperature, salinity)
    area = make_area({"bathymetry": "coast.nc", "temperature": "ts_t.nc", "salinity": "ts_s.nc"}, folder=tmp_path,
                     range_max_m=40000.0, bearings={"bearing_deg": [0.0, 180.0]})
    north, south = area_radials(area)
    assert north.land_range_m is not None and south.land_range_m is None
    assert south.ssp_range_m.size >= 5  # 45 km in columns at most 10 km apart
    assert south.ssp_depth_m[-1] > 4000.0  # deeper than the 1500 m of WOA's monthly fields
    lat, lon = geodesic_points(43.0, 5.0, 180.0, south.ssp_range_m)
    z = south.ssp_depth_m
    zt = np.minimum(z, 1500.0)  # below 1500 m the 1500 m values continue
    t = 22.0 - 8.0 * (1.0 - np.exp(-zt / 200.0))
    s = 38.0 + zt / 5000.0
    # linear in depth between WOA's levels: compare at the levels and below the last one
    levels = np.isin(z, [0.0, 100.0, 500.0, 1000.0, 1500.0]) | (z > 1500.0)
    for j in range(south.ssp_range_m.size):
        expected = teos10(z[levels], t[levels], s[levels], lat[j], lon[j])
        assert_allclose(south.speed_mps[levels, j], expected, rtol=0, atol=2e-3)  # float32 T/S
    # pressure at the column's latitude: the columns differ only through it, and only slightly
    assert not np.array_equal(south.speed_mps[:, 0], south.speed_mps[:, -1])
    assert_allclose(south.speed_mps[:, 0], south.speed_mps[:, -1], rtol=0, atol=0.01)


def test_origin_on_land_outside_or_too_shallow_is_refused(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north)
    water = {"bathymetry": "coast.nc", "ssp": "munk"}
    with pytest.raises(envdata.AreaError, match=r"coast\.nc: the origin 43\.15 N 5\.0 E is on land \(elevation "
                                                r"500\.0 m\): every radial starts on land$"):
        area_radials(make_area(water, folder=tmp_path, origin=(43.15, 5.0)))
    with pytest.raises(envdata.AreaError, match=r"coast\.nc: the origin 44\.0 N 5\.0 E is outside the bathymetry "
                                                r"file \(lat 42\.8000 \.\. 43\.2000 deg, lon 4\.8000 \.\. 5\.2000 deg\)$"):
        area_radials(make_area(water, folder=tmp_path, origin=(44.0, 5.0)))
    with pytest.raises(envdata.AreaError, match=r"\[observer\] depth_m: 100 m is not above the bottom at the origin, "
                                                r"\d+\.\d m deep in .*coast\.nc$"):
        area_radials(make_area(water, folder=tmp_path, origin=(43.092, 5.0)))


def test_a_radial_leaving_the_file_is_named_with_its_range(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north)
    area = make_area({"bathymetry": "coast.nc", "ssp": "munk"}, folder=tmp_path, range_max_m=30000.0,
                     bearings={"bearing_deg": [0.0, 90.0]})
    # north meets land at 11 km, inside the file; east leaves it at 0.2 deg of longitude, ~16.3 km
    with pytest.raises(envdata.AreaError, match=r"coast\.nc: the radial at bearing 90 deg leaves the bathymetry "
                                                r"file at range 16\d{3} m \(lat 42\.8000") as info:
        area_radials(area)
    _, _, edge_m = GEOD.inv(5.0, 43.0, 5.2, 43.0)
    assert abs(float(str(info.value).split("range ")[1].split(" m")[0]) - edge_m) <= 100.0


def test_a_radial_across_the_antimeridian_is_refused(tmp_path):
    write_relief(tmp_path / "dateline.nc", lambda lat, lon: -3000.0 + 0.0 * lat * lon, box=(42.8, 43.2, 179.6, 180.0))
    area = make_area({"bathymetry": "dateline.nc", "ssp": "munk"}, folder=tmp_path, origin=(43.0, 179.9),
                     range_max_m=20000.0, bearings={"bearing_deg": [0.0, 90.0]})
    with pytest.raises(envdata.AreaError, match=r"dateline\.nc: the radial at bearing 90 deg crosses the antimeridian "
                                                r"at range 8\d{3} m, and the file does not continue across it"):
        area_radials(area)


def test_cells_without_value_end_the_radial_like_land(tmp_path):
    import xarray as xr

    # a GEBCO-like float file with NaN (no attribute) south of 42.95 N: a hole is land too
    lat = np.arange(42.8, 43.2, 0.01) + 0.005
    lon = np.arange(4.8, 5.2, 0.01) + 0.005
    values = -1000.0 + 0.0 * lat[:, None] * lon[None, :]
    values[lat < 42.95, :] = np.nan
    xr.Dataset({"elevation": (("lat", "lon"), values, {"units": "m"})},
               coords={"lat": lat, "lon": lon}).to_netcdf(tmp_path / "holes.nc")
    area = make_area({"bathymetry": "holes.nc", "ssp": "munk"}, folder=tmp_path, range_max_m=8000.0,
                     bearings={"bearing_deg": [180.0]})
    (south,) = area_radials(area)
    _, _, edge_m = GEOD.inv(5.0, 43.0, 5.0, 42.95)  # the edge between the 42.955 and 42.945 centres
    assert south.land_range_m == pytest.approx(edge_m, abs=1.0)
    assert south.range_m[-1] == south.land_range_m and south.bottom_depth_m[-1] == SHORE_DEPTH_M
    assert_allclose(south.bottom_depth_m[:-1], 1000.0)  # the sea floor holds to the edge


@pytest.mark.parametrize("fill", ["_FillValue", "missing_value", "nan"])
def test_emodnet_land_without_value_ends_the_radial_at_its_cell_edge(tmp_path, fill):
    def dtm(lat, lon):  # coast_north, no value where shallower than 30 m (as EMODnet leaves land)
        e = coast_north(lat, lon)
        return np.where(e >= -30.0, np.nan, e)

    write_dtm(tmp_path / "dtm.nc", dtm, fill=fill, lat_name="latitude", lon_name="longitude")
    area = make_area({"bathymetry": "dtm.nc", "ssp": "munk"}, folder=tmp_path, range_max_m=15000.0,
                     bearings={"bearing_deg": [0.0, 90.0]})
    north, east = area_radials(area)
    # the first cell without value: centre (k + 1/2)/960 deg with coast_north >= -30 m; its edge
    k = int(np.ceil(43.097 * 960 - 0.5))
    _, _, edge_m = GEOD.inv(5.0, 43.0, 5.0, k / 960.0)
    assert north.land_range_m == pytest.approx(edge_m, abs=1.0)
    assert north.range_m[-1] == north.land_range_m and north.bottom_depth_m[-1] == SHORE_DEPTH_M
    assert np.all(np.diff(north.range_m) > 0.0)
    # 0.6 m: the relief is stored as int16 metres (0.5 m rounding) and read bilinearly
    assert_allclose(north.bottom_depth_m[:-1], -coast_north(north.lat_deg[:-1], north.lon_deg[:-1]), atol=0.6)
    assert north.bottom_depth_m[-2] >= 30.0 - 0.6  # the last wet cell's depth, up to its edge
    # behind a southern radial the same land: it starts at the edge
    (south,) = area_radials(make_area({"bathymetry": "dtm.nc", "ssp": "munk"}, folder=tmp_path, range_max_m=5000.0,
                                      bearings={"bearing_deg": [180.0]}), behind_m=20000.0)
    assert south.range_m[0] == pytest.approx(-edge_m, abs=1.0) and south.bottom_depth_m[0] == SHORE_DEPTH_M
    assert east.land_range_m is None and east.range_m[-1] == 15000.0
    # an origin in a cell without value is on land
    with pytest.raises(envdata.AreaError, match=r"dtm\.nc: the origin 43\.15 N 5\.0 E is in a cell with no elevation "
                                                r"\(land, or no data, in the file's 'elevation'\): every radial "
                                                r"starts on land$"):
        area_radials(make_area({"bathymetry": "dtm.nc", "ssp": "munk"}, folder=tmp_path, origin=(43.15, 5.0)))


def test_short_speed_tables_are_refused(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north)
    short = make_area({"bathymetry": "coast.nc", "ssp_depth_m": [0.0, 500.0], "ssp_speed_mps": [1510.0, 1500.0]},
                      folder=tmp_path, bearings={"bearing_deg": [180.0]})
    with pytest.raises(envdata.AreaError, match=r"\[water\] sound-speed profile: ends at 500 m, above the deepest "
                                                r"bottom, 1\d{3}\.\d m, of the radial at bearing 180 deg"):
        area_radials(short)


def test_a_climatology_smaller_than_the_radials_is_refused(tmp_path):
    write_relief(tmp_path / "coast.nc", coast_north)
    write_ts(tmp_path, lambda z, y, x: 14.0 + 0 * z, lambda z, y, x: 38.4 + 0 * z,
             lat=np.array([42.975, 43.025]), lon=np.array([4.875, 5.125]))
    area = make_area({"bathymetry": "coast.nc", "climatology": "ts_t.nc"}, folder=tmp_path)
    with pytest.raises(envdata.AreaError, match=r"ts_t\.nc: no salinity variable"):
        area_radials(area)
    area = make_area({"bathymetry": "coast.nc", "temperature": "ts_t.nc", "salinity": "ts_s.nc"}, folder=tmp_path,
                     range_max_m=15000.0, bearings={"bearing_deg": [180.0]})
    with pytest.raises(envdata.AreaError, match=r"ts_[ts]\.nc .*: the radial at bearing 180 deg leaves the "
                                                r"climatology at range \d+ m \(42\.9\d+ N"):
        area_radials(area)


def test_radials_need_an_origin_and_the_files(shelf_area, tmp_path):
    with pytest.raises(envdata.AreaError, match=r"area 'tiny-munk': has no \[origin\] and \[bearings\]"):
        area_radials(envdata.load_area("tests/data/tiny-munk.toml"))
    rebuilt = envdata.area_from_json(envdata.area_to_json(shelf_area))  # no folder: the paths as written
    with pytest.raises(envdata.AreaError, match=r"data/shelf-break_gebco_15s\.nc: bathymetry file not found$"):
        area_radials(rebuilt)
    with pytest.raises(ValueError, match=r"behind_m: must be > 0 m, got 0\.0"):
        area_radials(shelf_area, behind_m=0.0)


def test_progress_bar_goes_to_stderr(shelf_area, capsys):
    radials = area_radials(shelf_area, progress=True)
    captured = capsys.readouterr()
    assert len(radials) == 12 and captured.out == "" and "12/12" in captured.err
