"""GEBCO-layout bathymetry: variables by name or standard_name, lazy boxes, bilinear values, refusals."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import envdata
from envdata.bathymetry import open_bathymetry
from envdata.datafiles import BathymetrySource, DataFile
from tests.envdata.conftest import SAMPLE, write_dtm, write_relief
from tests.fixtures.layouts import EMODNET_FILL, gebco_axis_deg


def source(path, variable=None) -> BathymetrySource:
    return BathymetrySource(file=DataFile(path=str(path)), variable=variable)


def plane(lat, lon):
    """A tilted plane: bilinear interpolation reproduces it exactly (up to int16 rounding)."""
    return -1000.0 + 10000.0 * (lat - 43.0) + 2000.0 * (lon - 5.0)


def test_sample_relief_opens_lazily_and_loads_a_box():
    with open_bathymetry(source(SAMPLE / "shelf-break_gebco_15s.nc")) as bf:
        assert bf.variable == "elevation" and bf.sign == 1.0
        assert bf.axes.lat_deg.size == 240 and bf.axes.lon_deg.size == 288
        # 15 arc-seconds: 463 m north-south, 339 m east-west at 43 N
        assert_allclose(bf.axes.cell_m(43.0), 463.3 * np.cos(np.radians(43.0)), rtol=2e-3)
        grid = bf.load_box([42.99, 43.01], [4.99, 5.01])
        # the cells around the positions and two more each side, far less than the file
        assert grid.elevation_m.shape == (grid.lat_deg.size, grid.lon_deg.size) == (10, 10)
        assert grid.lat_deg[2] < 42.99 < grid.lat_deg[3] and grid.lat_deg[-4] < 43.01 < grid.lat_deg[-3]
        assert grid.lon_deg[2] < 4.99 < grid.lon_deg[3] and grid.lon_deg[-4] < 5.01 < grid.lon_deg[-3]
        with xr.open_dataset(SAMPLE / "shelf-break_gebco_15s.nc") as ds:
            raw = ds.elevation.sel(lat=grid.lat_deg[5], lon=grid.lon_deg[7]).item()
        # at a cell centre the value is the file's
        assert grid.elevation_at(grid.lat_deg[5], grid.lon_deg[7])[0] == pytest.approx(raw, abs=1e-9)
        assert -700 < grid.elevation_at(43.0, 5.0)[0] < -450  # the origin is on the upper slope


def test_elevation_is_bilinear_between_cell_centres(tmp_path):
    path = write_relief(tmp_path / "plane.nc", plane)
    with open_bathymetry(source(path)) as bf:
        lat = np.array([43.0013, 42.9, 43.15])
        lon = np.array([5.0021, 4.95, 5.11])
        grid = bf.load_box(lat, lon)
        assert_allclose(grid.elevation_at(lat, lon), plane(lat, lon), rtol=0, atol=0.5)  # int16 metres
        # between two centres of unequal values: their weighted mean
        la, lo = grid.lat_deg[3], grid.lon_deg[3:5]
        v = grid.elevation_m[3, 3:5]
        assert_allclose(grid.elevation_at(la, 0.25 * lo[0] + 0.75 * lo[1])[0], 0.25 * v[0] + 0.75 * v[1])


def test_variable_by_name_by_standard_name_and_depth_positive_down(tmp_path):
    lat, lon = gebco_axis_deg(42.9, 43.1), gebco_axis_deg(4.9, 5.1)
    depth = 1000.0 - 10000.0 * (lat[:, None] - 43.0) + 0 * lon[None, :]
    ds = xr.Dataset({"z": (("lat", "lon"), -depth, {"units": "m"}),
                     "seafloor": (("latitude", "longitude"), depth,
                                  {"units": "meters", "standard_name": "sea_floor_depth_below_geoid"}),
                     "topo": (("lat", "lon"), -depth,
                              {"units": "metres", "standard_name": "height_above_mean_sea_level"})},
                    coords={"lat": ("lat", lat, {"units": "degrees_north"}),
                            "lon": ("lon", lon, {"units": "degrees_east"}),
                            "latitude": ("latitude", lat, {"standard_name": "latitude"}),
                            "longitude": ("longitude", lon, {"standard_name": "longitude"})})
    ds.to_netcdf(tmp_path / "many.nc")
    for variable, sign in (("z", 1.0), ("seafloor", -1.0), ("topo", 1.0)):
        with open_bathymetry(source(tmp_path / "many.nc", variable)) as bf:
            assert bf.sign == sign
            e = bf.load_box([43.05], [5.0]).elevation_at(43.05, 5.0)[0]
            assert_allclose(e, -500.0, rtol=0, atol=1e-6)
    ds[["seafloor"]].to_netcdf(tmp_path / "depth.nc")  # found by its standard_name, negated
    with open_bathymetry(source(tmp_path / "depth.nc")) as bf:
        assert bf.variable == "seafloor"
        assert_allclose(bf.load_box([43.0], [5.0]).elevation_at(43.0, 5.0), [-1000.0], atol=1e-6)
    ds[["z"]].rename({"z": "depth"}).pipe(lambda d: d.assign(depth=-d.depth)).to_netcdf(tmp_path / "named.nc")
    with open_bathymetry(source(tmp_path / "named.nc")) as bf:  # "depth", no attribute: positive down
        assert bf.variable == "depth" and bf.sign == -1.0
        assert_allclose(bf.load_box([43.0], [5.0]).elevation_at(43.0, 5.0), [-1000.0], atol=1e-6)
    ds[["seafloor", "topo"]].to_netcdf(tmp_path / "two.nc")
    with pytest.raises(envdata.AreaError, match=r"several variables could be the elevation "
                                                r"\(seafloor, topo, by standard_name\); name one$"):
        open_bathymetry(source(tmp_path / "two.nc"))


def test_descending_latitudes_and_0_360_longitudes_read_the_same(tmp_path):
    lat, lon = gebco_axis_deg(42.9, 43.1), gebco_axis_deg(-0.1, 0.1)
    values = plane(lat[:, None], lon[None, :] + 5.0)
    up = xr.Dataset({"elevation": (("lat", "lon"), values, {"units": "m"})},
                    coords={"lat": ("lat", lat, {"units": "degrees_north"}),
                            "lon": ("lon", lon, {"units": "degrees_east"})})
    up.to_netcdf(tmp_path / "up.nc")
    up.isel(lat=slice(None, None, -1)).to_netcdf(tmp_path / "down.nc")
    shifted = up.assign_coords(lon=np.mod(lon, 360.0)).sortby("lon")  # 0.0..0.1 and 359.9..360
    shifted.to_netcdf(tmp_path / "east.nc")
    lat_q, lon_q = np.array([42.95, 43.07]), np.array([-0.03, 0.04])
    results = []
    for name in ("up.nc", "down.nc"):
        with open_bathymetry(source(tmp_path / name)) as bf:
            results.append(bf.load_box(lat_q, lon_q).elevation_at(lat_q, lon_q))
    assert_allclose(results[0], plane(lat_q, lon_q + 5.0), atol=1e-6)
    assert_allclose(results[1], results[0], atol=1e-9)
    with open_bathymetry(source(tmp_path / "east.nc")) as bf:
        assert bf.axes.file_lon(-0.03) == pytest.approx(359.97)
        # 359.9..360 and 0..0.1 are one file but not one block: the box around -0.03 is on its side
        assert_allclose(bf.load_box(lat_q[:1], lon_q[:1]).elevation_at(lat_q[:1], lon_q[:1]),
                        results[0][:1], atol=1e-6)


def test_refusals_name_the_file(tmp_path):
    good = write_relief(tmp_path / "r.nc", plane)
    with pytest.raises(envdata.AreaError, match=r"r\.nc: no variable 'depth' \(the elevation\); the file has "
                                                r"crs, elevation$"):
        open_bathymetry(source(good, "depth"))
    with pytest.raises(envdata.AreaError, match=r"r\.nc: position 45\.00000 N 5\.00000 E is outside the file "
                                                r"\(lat 42\.8000 \.\. 43\.2000 deg"):
        with open_bathymetry(source(good)) as bf:
            bf.load_box([45.0], [5.0])
    xr.Dataset({"elevation": (("lat", "lon"), np.zeros((3, 3)), {"units": "ft"})},
               coords={"lat": [1.0, 2.0, 3.0], "lon": [1.0, 2.0, 3.0]}).to_netcdf(tmp_path / "ft.nc")
    with pytest.raises(envdata.AreaError, match=r"ft\.nc: variable 'elevation' must be in metres "
                                                r"\(units = \"m\"\), got units = 'ft'$"):
        open_bathymetry(source(tmp_path / "ft.nc"))
    xr.Dataset({"elevation": (("lat", "lon"), np.zeros((3, 3)))},
               coords={"lat": [1.0, 2.0, 3.0], "lon": [1.0, 2.0, 3.0]}).to_netcdf(tmp_path / "nounits.nc")
    with pytest.raises(envdata.AreaError, match=r"must be in metres .*got units = ''$"):
        open_bathymetry(source(tmp_path / "nounits.nc"))
    xr.Dataset({"h": (("lat", "lon"), np.zeros((3, 3)), {"units": "m"})},
               coords={"lat": [1.0, 2.0, 3.0], "lon": [1.0, 2.0, 3.0]}).to_netcdf(tmp_path / "h.nc")
    with pytest.raises(envdata.AreaError, match=r"h\.nc: no elevation variable: none is named elevation or depth or "
                                                r"has the standard_name height_above_reference_ellipsoid"):
        open_bathymetry(source(tmp_path / "h.nc"))
    xr.Dataset({"elevation": (("t", "lat", "lon"), np.zeros((2, 3, 3)), {"units": "m"})},
               coords={"lat": [1.0, 2.0, 3.0], "lon": [1.0, 2.0, 3.0]}).to_netcdf(tmp_path / "t.nc")
    with pytest.raises(envdata.AreaError, match=r"must be 2-D on \(lat, lon\), got dimensions \(t, lat, lon\)$"):
        open_bathymetry(source(tmp_path / "t.nc"))
    xr.Dataset({"elevation": (("a", "b"), np.zeros((3, 3)), {"units": "m"})}).to_netcdf(tmp_path / "ab.nc")
    with pytest.raises(envdata.AreaError, match=r"has no latitude coordinate among its dimensions \(a, b\)"):
        open_bathymetry(source(tmp_path / "ab.nc"))
    (tmp_path / "text.nc").write_text("not netCDF\n")
    with pytest.raises(envdata.AreaError, match=r"text\.nc: cannot read the bathymetry file as netCDF"):
        open_bathymetry(source(tmp_path / "text.nc"))
    with pytest.raises(envdata.AreaError, match=r"nope\.nc: bathymetry file not found$"):
        open_bathymetry(source(tmp_path / "nope.nc"))
    with pytest.raises(envdata.AreaError, match=r"is a directory, not a bathymetry file$"):
        open_bathymetry(source(tmp_path))


def dry_north(lat, lon):
    """The plane, with no value (land) where it would be shallower than 30 m (north of 43.097 N)."""
    e = plane(lat, lon + 0.0 * lat)
    return np.where(e >= -30.0, np.nan, e)


@pytest.mark.parametrize("fill", ["_FillValue", "missing_value", "nan"])
@pytest.mark.parametrize("positive", ["up", "down"])
def test_emodnet_layout_reads_fill_cells_as_no_value(tmp_path, fill, positive):
    path = write_dtm(tmp_path / "dtm.nc", dry_north, fill=fill, positive=positive)
    with xr.open_dataset(path, mask_and_scale=False) as raw:
        name = "elevation" if positive == "up" else "depth"
        stored = raw[name].values
        if fill == "nan":
            assert np.isnan(stored).any() and not {"_FillValue", "missing_value"} & set(raw[name].attrs)
        else:
            assert (stored == EMODNET_FILL).any() and not np.isnan(stored).any()
    with open_bathymetry(source(path)) as bf:
        assert bf.variable == name and bf.sign == (1.0 if positive == "up" else -1.0)  # not elevation_min
        lat = np.array([43.0, 43.05, 43.15])
        lon = np.array([5.0, 5.0, 5.0])
        grid = bf.load_box(lat, lon)
        elevation, no_data = grid.sea_elevation_at(lat, lon)
        assert_allclose(elevation[:2], plane(lat[:2], lon[:2]), rtol=0, atol=1e-3)  # float32 metres
        assert no_data.tolist() == [False, False, True] and np.isnan(elevation[2])


def test_sea_elevation_holds_up_to_the_edge_of_cells_without_value(tmp_path):
    path = write_dtm(tmp_path / "dtm.nc", dry_north)
    with open_bathymetry(source(path)) as bf:
        grid = bf.load_box([43.09, 43.1], [5.0, 5.0])
        j = int(np.argmin(np.abs(grid.lon_deg - 5.0)))
        column = grid.elevation_m[:, j]
        row = int(np.argmax(~np.isfinite(column)))  # the first row with no value
        assert row > 0 and np.isfinite(column[row - 1])
        wet, dry = grid.lat_deg[row - 1], grid.lat_deg[row]
        edge = 0.5 * (wet + dry)
        lat = np.array([wet, edge - 1e-5, edge + 1e-5])
        elevation, no_data = grid.sea_elevation_at(lat, np.full(3, grid.lon_deg[j]))
        assert no_data.tolist() == [False, False, True]
        # between the last wet centre and the edge: the wet cell's value, not NaN
        assert_allclose(elevation[:2], column[row - 1], rtol=0, atol=1e-9)
        # elevation_at keeps its meaning (NaN once a corner without a value has weight)
        assert np.isnan(grid.elevation_at(edge - 1e-5, grid.lon_deg[j])[0])
