"""The shelf-break sample files: the products' exact layouts, reproduced by their generator."""

from __future__ import annotations

import netCDF4
import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from tests.envdata.conftest import SAMPLE
from tests.fixtures import sample_data

RELIEF = SAMPLE / "shelf-break_gebco_15s.nc"
T08 = SAMPLE / "shelf-break_woa_t08_04.nc"
S08 = SAMPLE / "shelf-break_woa_s08_04.nc"
# WOA's standard levels of the monthly fields, written out here independently of the generator
WOA_MONTHLY_LEVELS = ([5.0 * k for k in range(21)] + [100.0 + 25.0 * k for k in range(1, 17)]
                      + [500.0 + 50.0 * k for k in range(1, 21)])


def test_relief_is_in_gebco_layout():
    with netCDF4.Dataset(RELIEF) as nc:
        assert list(nc.dimensions) == ["lat", "lon"]
        elevation = nc["elevation"]
        assert elevation.dimensions == ("lat", "lon") and elevation.dtype == np.int16
        assert elevation.units == "m" and elevation.standard_name == "height_above_reference_ellipsoid"
        assert elevation.long_name == "Elevation relative to sea level"
        for name, units, std in (("lat", "degrees_north", "latitude"), ("lon", "degrees_east", "longitude")):
            v = nc[name]
            assert v.dimensions == (name,) and v.dtype == np.float64
            assert v.units == units and v.standard_name == std
            # 15 arc-second cell centres: (k + 1/2) / 240 deg
            k = v[:] * 240.0 - 0.5
            assert_allclose(k, np.round(k), rtol=0, atol=1e-6)
        assert "not GEBCO data" in nc.title


@pytest.mark.parametrize("path, kind", [(T08, "t"), (S08, "s")])
def test_climatology_is_in_woa_layout(path, kind):
    with netCDF4.Dataset(path) as nc:
        assert {"time", "depth", "lat", "lon", "nbounds"} <= set(nc.dimensions)
        var = nc[f"{kind}_an"]
        assert var.dimensions == ("time", "depth", "lat", "lon") and var.dtype == np.float32
        assert var._FillValue == np.float32(9.96921e36)
        assert var.units == ("degrees_celsius" if kind == "t" else "1")
        assert var.standard_name == ("sea_water_temperature" if kind == "t" else "sea_water_salinity")
        assert f"{kind}_mn" in nc.variables  # WOA's statistical mean beside the analysed field
        assert nc["time"].units == "months since 1955-01-01 00:00:00" and nc["time"].size == 1
        assert "calendar" not in nc["time"].ncattrs() and nc["time"].climatology == "climatology_bounds"
        assert nc["depth"].positive == "down" and nc["depth"].units == "meters"
        assert_allclose(nc["depth"][:], WOA_MONTHLY_LEVELS)
        # WOA's 0.25-degree cell centres: k / 4 + 1/8
        assert_allclose(np.mod(nc["lat"][:] - 0.125, 0.25), 0.0, atol=1e-6)
        raw = var[0].filled(np.nan)
    assert np.isnan(raw).any() and np.isfinite(raw).any()  # land and sea floor hold the fill value
    with pytest.raises(ValueError, match=r"unable to decode time units 'months since 1955-01-01"):
        xr.open_dataset(path)  # as with WOA's own files: the times do not decode


#: Global attributes that name the generator's file: the shipped files were written when it was
#: tools/make_sample_data.py and keep their bytes (their sha256 is part of every shelf-break
#: grid's source hash), a fresh file names tests/fixtures/sample_data.py.
GENERATOR_ATTRS = {"source", "summary"}


def test_the_generator_writes_the_shipped_files(tmp_path):
    assert sample_data.main(["--out", str(tmp_path)]) == 0
    for path in (RELIEF, T08, S08):
        with xr.open_dataset(path, decode_times=False) as shipped, \
                xr.open_dataset(tmp_path / path.name, decode_times=False) as fresh:
            shipped, fresh = shipped.load(), fresh.load()
            for ds in (shipped, fresh):
                ds.attrs = {k: v for k, v in ds.attrs.items() if k not in GENERATOR_ATTRS}
            xr.testing.assert_identical(shipped, fresh)


def test_relief_and_water_are_a_plausible_shelf_break():
    lat = np.linspace(42.6, 43.4, 161)
    east = sample_data.elevation_m(lat, np.full(lat.shape, 5.0))
    assert 450.0 < -sample_data.elevation_m(43.0, 5.0) < 700.0  # the origin on the upper slope
    assert -east.min() > 2400.0  # the basin to the south
    shelf = (lat > 43.07) & (east < 0.0)
    assert shelf.any() and np.all(-east[shelf] <= 150.0)  # a shelf no deeper than 150 m
    assert np.all(np.diff(east[lat < 43.2]) > -6.0)  # shoaling northward, but for metres of roughness
    assert east[-1] > 0.0  # land to the north
    depth, t, s = sample_data.woa_fields([2, 8])
    feb, aug = t[0], t[1]
    cell = (slice(None), 1, 3)  # 42.625 N 4.875 E, a deep cell
    assert aug[cell][0] - feb[cell][0] > 9.0
    assert aug[cell][0] - np.interp(60.0, depth, aug[cell]) > 5.0  # summer thermocline
    assert abs(feb[cell][0] - np.interp(60.0, depth, feb[cell])) < 0.3  # winter mixed layer
    lw = np.argmax(s[1][cell])
    assert 200.0 <= depth[lw] <= 600.0  # Levantine Intermediate Water: the salinity maximum
