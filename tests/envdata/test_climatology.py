"""WOA-layout climatologies: split files, 12-month files, fill-down, renormalised bilinear columns."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import envdata
from envdata.climatology import fill_down, open_climatology
from envdata.datafiles import ClimatologySource, DataFile
from tests.envdata.conftest import SAMPLE, write_ts
from tests.fixtures.sample_data import write_monthly

T08 = SAMPLE / "shelf-break_woa_t08_04.nc"
S08 = SAMPLE / "shelf-break_woa_s08_04.nc"


def split(t_path, s_path, month=None) -> ClimatologySource:
    return ClimatologySource(temperature_file=DataFile(path=str(t_path)),
                             salinity_file=DataFile(path=str(s_path)), month=month)


def single(path, month=None) -> ClimatologySource:
    return ClimatologySource(file=DataFile(path=str(path)), month=month)


def test_fill_down_continues_the_deepest_value_per_column():
    nan = np.nan
    field = np.array([[1.0, nan, nan, 7.0],
                      [2.0, 5.0, nan, nan],
                      [nan, 6.0, nan, 8.0],
                      [nan, nan, nan, 9.0]])  # (levels, columns)
    out = fill_down(field)
    assert_allclose(out[:, 0], [1.0, 2.0, 2.0, 2.0])  # stops above the bottom: 2 continues
    assert_allclose(out[:, 1], [5.0, 5.0, 6.0, 6.0])  # top missing: the shallowest value up
    assert np.all(np.isnan(out[:, 2]))  # land stays land
    assert_allclose(out[:, 3], [7.0, 7.0, 8.0, 9.0])  # a gap takes the value above it
    cube = field.reshape(4, 2, 2)
    assert_allclose(fill_down(cube).reshape(4, 4), out)


def test_sample_split_files_give_t_an_and_s_an_filled_down():
    with open_climatology(split(T08, S08)) as clim:
        assert clim.temperature.name == "t_an" and clim.salinity.name == "s_an"  # not t_mn / s_mn
        assert clim.depth_m.size == 57 and clim.depth_m[-1] == 1500.0
        field = clim.load_box([42.9, 43.1], [4.9, 5.1])
    with xr.open_dataset(T08, decode_times=False) as ds:
        t_an = ds.t_an.isel(time=0).values
        lat, lon = ds.lat.values, ds.lon.values
    # a shelf cell: its column stops above 1500 m
    counts = np.isfinite(t_an).sum(axis=0)
    fi, fj = (int(v[0]) for v in np.nonzero((counts > 0) & (counts < 57)))
    i = int(np.argmin(np.abs(field.lat_deg - lat[fi])))
    j = int(np.argmin(np.abs(field.lon_deg - lon[fj])))
    column = t_an[:, fi, fj]
    valid = np.isfinite(column)
    assert_allclose(field.temperature_c[valid, i, j], column[valid], rtol=0, atol=1e-5)
    assert_allclose(field.temperature_c[~valid, i, j], column[valid][-1], rtol=0, atol=1e-5)
    # at a cell centre the column is that cell's
    t, s = field.columns_at([float(lat[fi])], [float(lon[fj])])
    assert_allclose(t[:, 0], field.temperature_c[:, i, j], rtol=0, atol=1e-9)
    assert 37.5 < s[0, 0] < 38.4 and 38.3 < s[-1, 0] < 38.6
    assert field.valid.any() and not field.valid.all()  # land cells in the box hold no column


def test_twelve_month_file_picks_the_month(tmp_path):
    t_path, s_path = write_monthly(tmp_path)
    with xr.open_dataset(t_path, decode_times=False) as ds:
        assert ds.sizes["time"] == 12 and ds.time.attrs["units"] == "months since 1955-01-01 00:00:00"
    point = ([43.0], [5.0])
    with open_climatology(split(t_path, s_path, month=8)) as clim:
        aug = clim.load_box(*point).columns_at(*point)
    with open_climatology(split(T08, S08)) as clim:
        aug_split = clim.load_box(*point).columns_at(*point)
    with open_climatology(split(t_path, s_path, month=2)) as clim:
        feb = clim.load_box(*point).columns_at(*point)
    assert_allclose(aug[0], aug_split[0], rtol=0, atol=1e-5)  # the month-th step is that month
    assert_allclose(aug[1], aug_split[1], rtol=0, atol=1e-5)
    assert aug[0][0, 0] - feb[0][0, 0] > 8.0  # summer surface far warmer than winter
    assert aug[0][0, 0] - aug[0][15, 0] > 5.0  # August thermocline within 75 m
    assert abs(feb[0][0, 0] - feb[0][15, 0]) < 0.5  # February mixed
    with pytest.raises(envdata.AreaError, match=r"has 12 time steps \(months\); give \[water\] month = 1\.\.12$"):
        open_climatology(split(t_path, s_path))


def test_one_file_with_both_variables(tmp_path):
    with xr.open_dataset(T08, decode_times=False) as t, xr.open_dataset(S08, decode_times=False) as s:
        both = xr.merge([t, s[["s_an", "s_mn"]]], compat="override", join="override")
        both.to_netcdf(tmp_path / "both.nc")
    point = ([42.95], [5.02])
    with open_climatology(single(tmp_path / "both.nc")) as clim:
        one = clim.load_box(*point).columns_at(*point)
    with open_climatology(split(T08, S08)) as clim:
        two = clim.load_box(*point).columns_at(*point)
    assert_allclose(one[0], two[0])
    assert_allclose(one[1], two[1])


def test_bilinear_weights_of_wet_columns_are_renormalised(tmp_path):
    lat = np.array([42.875, 43.125, 43.375])
    lon = np.array([4.875, 5.125, 5.375])
    # T = 10 + column number, one value for every level; the north-east 2 x 2 block is land
    base = 10.0 + np.arange(9.0).reshape(3, 3)
    base[1:, 1:] = np.nan

    def temperature(z, y, x):
        iy = np.searchsorted(lat, y[0, :, 0] - 1e-9)
        ix = np.searchsorted(lon, x[0, 0, :] - 1e-9)
        return np.broadcast_to(base[np.ix_(iy, ix)], z.shape)

    t_path, s_path = write_ts(tmp_path, temperature, lambda z, y, x: np.where(np.isnan(temperature(z, y, x)),
                                                                               np.nan, 38.0), lat=lat, lon=lon)
    with open_climatology(split(t_path, s_path)) as clim:
        field = clim.load_box([43.0], [5.0])
        # the centre of the four south-west columns: three wet (10, 11, 13), one land
        t, _ = field.columns_at([43.0], [5.0])
        assert_allclose(t[:, 0], (10.0 + 11.0 + 13.0) / 3.0)
        # a quarter of the way: weights 9/16 3/16 3/16 (1/16 on land), renormalised
        t, _ = field.columns_at([42.9375], [4.9375])
        assert_allclose(t[:, 0], (9 * 10.0 + 3 * 11.0 + 3 * 13.0) / 15.0)
        # among land cells only: the nearest wet column
        t, _ = field.columns_at([43.2, 43.3], [5.25, 5.2])
        assert_allclose(t[:, 0], 13.0)  # 43.125 N 4.875 E, 22 km away (11 at 42.875 N is 36 km)
        assert_allclose(t[:, 1], 16.0)  # 43.375 N 4.875 E


def test_columns_stopping_above_the_bottom_are_filled_before_interpolating(tmp_path):
    lat = np.array([42.875, 43.125])
    lon = np.array([4.875, 5.125])

    def temperature(z, y, x):  # 20 - z/100 everywhere, but the north row stops at 50 m
        t = 20.0 - z / 100.0
        return np.where((y > 43.0) & (z > 50.0), np.nan, t)

    t_path, s_path = write_ts(tmp_path, temperature, lambda z, y, x: np.where(np.isnan(temperature(z, y, x)),
                                                                               np.nan, 38.5), lat=lat, lon=lon)
    with open_climatology(split(t_path, s_path)) as clim:
        field = clim.load_box([43.0], [5.0])
        t, _ = field.columns_at([43.0], [5.0])  # half-way between the rows
    z = clim.depth_m
    expected = np.where(z <= 50.0, 20.0 - z / 100.0, 0.5 * (20.0 - z / 100.0) + 0.5 * 19.5)
    assert_allclose(t[:, 0], expected, rtol=0, atol=1e-5)


def test_refusals_name_the_file(tmp_path):
    t_path, s_path = write_ts(tmp_path, lambda z, y, x: 15.0 + 0 * z, lambda z, y, x: 38.0 + 0 * z)
    with pytest.raises(envdata.AreaError, match=r"ts_t\.nc: no salinity variable: none is named s_an"):
        open_climatology(split(t_path, t_path))
    with pytest.raises(envdata.AreaError, match=r"is outside the climatology \(lat 42\.5000 \.\. 43\.5000 deg"):
        with open_climatology(split(t_path, s_path)) as clim:
            clim.load_box([44.0], [5.0])
    with xr.open_dataset(t_path, decode_times=False) as ds:
        kelvin = ds.load()
    kelvin["t_an"].attrs["units"] = "degF"
    kelvin.to_netcdf(tmp_path / "fahrenheit.nc")
    with pytest.raises(envdata.AreaError, match=r"fahrenheit\.nc: variable 't_an' \(temperature\) has units "
                                                r"'degF'; need degrees_celsius or K$"):
        open_climatology(split(tmp_path / "fahrenheit.nc", s_path))
    preformed = kelvin.rename({"t_an": "sp"}).drop_vars("t_mn")
    preformed["sp"].attrs.update(units="g/kg", standard_name="sea_water_preformed_salinity")
    preformed.to_netcdf(tmp_path / "preformed.nc")
    with pytest.raises(envdata.AreaError, match=r"preformed\.nc: 'sp' holds preformed salinity "
                                                r"\(sea_water_preformed_salinity\); tmakit reads in-situ, potential"):
        open_climatology(split(t_path, tmp_path / "preformed.nc"))
    three = xr.concat([kelvin] * 3, dim="time", data_vars="all")
    three["t_an"].attrs["units"] = "degrees_celsius"
    three.to_netcdf(tmp_path / "three.nc")
    with pytest.raises(envdata.AreaError, match=r"three\.nc: 't_an' has 3 time steps and a time axis that does "
                                                r"not decode \(units 'months since 1955-01-01 00:00:00'\); need 1 "
                                                r"\(used as it is\) or 12"):
        open_climatology(split(tmp_path / "three.nc", s_path))
    other_t, _ = write_ts(tmp_path, lambda z, y, x: 15.0 + 0 * z, lambda z, y, x: 38.0 + 0 * z,
                          lat=np.arange(40.125, 41.0, 0.25), stem="elsewhere")
    with pytest.raises(envdata.AreaError, match=r"ts_s\.nc: its latitudes differ from those of the temperature "
                                                r"file .*elsewhere_t\.nc; the two files must be on one grid$"):
        open_climatology(split(other_t, s_path))
    hot, _ = write_ts(tmp_path, lambda z, y, x: 55.0 + 0 * z, lambda z, y, x: 38.0 + 0 * z, stem="hot")
    with pytest.raises(envdata.AreaError, match=r"hot_t\.nc: 't_an' holds temperature 55 outside \[-2\.5, 40\]"):
        with open_climatology(split(hot, s_path)) as clim:
            clim.load_box([43.0], [5.0])
    with pytest.raises(envdata.AreaError, match=r"missing\.nc: temperature climatology file not found$"):
        open_climatology(split(tmp_path / "missing.nc", s_path))


def test_a_box_with_no_water_is_refused(tmp_path):
    t_path, s_path = write_ts(tmp_path, lambda z, y, x: np.nan + z, lambda z, y, x: np.nan + z)
    with open_climatology(split(t_path, s_path)) as clim:
        field = clim.load_box([43.0], [5.0])
    with pytest.raises(envdata.AreaError, match=r"ts_t\.nc: no water \(no valid temperature and salinity\) in "
                                                r"the cells around 43\.0000 N 5\.0000 E$"):
        field.columns_at([43.0], [5.0])


def test_woa_standard_deviations_are_read_beside_the_means(tmp_path):
    from tests.fixtures.layouts import WOA_LEVELS_M, write_woa

    with open_climatology(split(T08, S08)) as clim:  # the sample files have none
        field = clim.load_box([43.0], [5.0])
        assert field.temperature_sd_c is None and field.salinity_sd_psu is None
    lat = np.array([42.875, 43.125])
    lon = np.array([4.875, 5.125])
    depth = WOA_LEVELS_M[:57]
    z, y, x = np.meshgrid(depth, lat, lon, indexing="ij")
    t = (20.0 - z / 100.0)[None]
    s = (38.0 + z / 5000.0)[None]
    t_sd = np.where(z <= 1000.0, 0.8 - z / 2000.0, np.nan)[None]  # no statistics below 1000 m
    t_sd[0, :, 1, 1] = np.nan  # a wet column without any
    write_woa(tmp_path / "t.nc", "t", [8], depth, lat, lon, t, title="test", sd_values=t_sd)
    write_woa(tmp_path / "s.nc", "s", [8], depth, lat, lon, s, title="test", sd_values=0.05 + 0.0 * s)
    with open_climatology(split(tmp_path / "t.nc", tmp_path / "s.nc")) as clim:
        assert (clim.temperature.sd_name, clim.salinity.sd_name) == ("t_sd", "s_sd")
        field = clim.load_box([43.0], [5.0])
    assert field.temperature_sd_c.shape == field.temperature_c.shape
    column = field.temperature_sd_c[:, 0, 0]
    above = depth <= 1000.0
    assert_allclose(column[above], 0.8 - depth[above] / 2000.0, rtol=0, atol=1e-6)
    assert_allclose(column[~above], 0.3, rtol=0, atol=1e-6)  # the deepest value continues down, as T
    assert np.all(np.isnan(field.temperature_sd_c[:, 1, 1]))  # none in the file: NaN, not made up
    assert_allclose(field.salinity_sd_psu, 0.05, rtol=0, atol=1e-7)
    # only the temperature file has them
    write_woa(tmp_path / "s0.nc", "s", [8], depth, lat, lon, s, title="test")
    with open_climatology(split(tmp_path / "t.nc", tmp_path / "s0.nc")) as clim:
        field = clim.load_box([43.0], [5.0])
    assert field.temperature_sd_c is not None and field.salinity_sd_psu is None
    write_woa(tmp_path / "neg.nc", "t", [8], depth, lat, lon, t, title="test", sd_values=-0.1 + 0.0 * t)
    with pytest.raises(envdata.AreaError, match=r"neg\.nc: 't_sd' holds a standard deviation -0\.1 < 0 "
                                                r"\(units 'degrees_celsius'\)$"):
        with open_climatology(split(tmp_path / "neg.nc", tmp_path / "s.nc")) as clim:
            clim.load_box([43.0], [5.0])
