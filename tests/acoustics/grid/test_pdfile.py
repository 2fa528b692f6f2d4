"""P_D maps as CF netCDF on latitude and longitude (acoustics.grid.pdfile): a real file opened by
xarray, its CF attributes, the CF checker, and its values against the P_D map on the radials."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from acoustics.grid.pdfile import grid_pd_dataset, write_pd_file
from acoustics.pd import normal_cdf
from envdata.geometry import lat_lon_to_local_plane

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def pd_file(tiny_radial_tables, tmp_path_factory):
    path = tmp_path_factory.mktemp("pd") / "pd.nc"
    write_pd_file(grid_pd_dataset(tiny_radial_tables, "any"), path)
    return path


def test_the_map_opens_in_xarray_on_lat_lon_with_cf_attributes(pd_file, tiny_radial_tables):
    with xr.open_dataset(pd_file) as ds:
        assert ds.attrs["Conventions"] == "CF-1.8" and ds.attrs["institution"] == "tmakit"
        assert ds["lat"].attrs["standard_name"] == "latitude" and ds["lat"].attrs["units"] == "degrees_north"
        assert ds["lon"].attrs["standard_name"] == "longitude" and ds["lon"].attrs["units"] == "degrees_east"
        assert ds["crs"].attrs["grid_mapping_name"] == "latitude_longitude"
        assert_allclose([ds["crs"].attrs["semi_major_axis"], ds["crs"].attrs["inverse_flattening"]],
                        [6378137.0, 298.257223563])
        for name in ("pd", "beyond_table"):
            assert ds[name].dims == ("class", "lat", "lon") and ds[name].attrs["grid_mapping"] == "crs"
        assert list(ds["class"].values) == ["SUB", "SHIP"]
        # the raster covers the tables' reach around the origin, evenly spaced
        assert ds["lat"].min() < 43.0 - 4.9 / 111.1 and ds["lat"].max() > 43.0 + 4.9 / 111.1
        assert np.ptp(np.diff(ds["lat"].values)) < 1e-9 and np.ptp(np.diff(ds["lon"].values)) < 1e-9
        pd = ds["pd"].values
        assert np.nanmin(pd) >= 0.0 and np.nanmax(pd) <= 1.0
        # beyond the last range no P_D is given; the ship is flagged there, the submarine is not
        lat, lon = np.meshgrid(ds["lat"].values, ds["lon"].values, indexing="ij")
        x, y = lat_lon_to_local_plane(43.0, 5.0, lat, lon)
        outside = np.hypot(x, y) > tiny_radial_tables.range_m[-1]
        assert np.all(np.isnan(pd[:, outside]))
        assert np.all(ds["beyond_table"].sel({"class": "SHIP"}).values[outside] == 1)
        assert np.all(ds["beyond_table"].sel({"class": "SUB"}).values == 0)
        assert np.isnan(ds["detection_range_m"].sel({"class": "SHIP"})).all()
        assert (ds["detection_beyond_table"].sel({"class": "SHIP"}) == 1).all()


def test_a_cell_s_p_d_is_that_of_a_target_there(pd_file, tiny_radial_tables):
    t = tiny_radial_tables
    sub = t.classes[t.class_index("SUB")]
    sonar = t.area.sonar
    with xr.open_dataset(pd_file) as ds:
        lat, lon = np.meshgrid(ds["lat"].values, ds["lon"].values, indexing="ij")
        x, y = lat_lon_to_local_plane(43.0, 5.0, lat, lon)
        r, b = np.hypot(x, y), np.mod(np.degrees(np.arctan2(x, y)), 360.0)
        inside = r <= t.range_m[-1]
        # K where the target is, eqs. 2 and 11 written out, sigma the class's source level sd and
        # K's error model's offset and residual (the class's k_error_sd_db, the tables' own)
        k = t.k_at(t.class_index("SUB"), r[inside], bearing_deg=b[inside])
        snr = sub.noise_mean_db + k - (t.noise_band_db - sonar.directivity_index_db)
        needed = 10 * np.log10(sonar.detection_threshold / np.sqrt(t.bandwidth_hz * sonar.integration_time_s))
        model = t.k_error_model(t.class_index("SUB"))
        sigma = np.hypot(sub.noise_sd_db, np.hypot(model.offset_sd_db, model.residual_sd_db))
        p_band = normal_cdf((snr - needed) / sigma)
        expected = 1.0 - np.prod(1.0 - p_band, axis=-1)
        assert_allclose(ds["pd"].sel({"class": "SUB"}).values[inside], expected, rtol=0, atol=1e-6)  # float32
        assert 0.05 < expected.mean() < 0.95   # the map holds both detection and its absence


def test_the_cf_checker_finds_no_high_priority_failure(pd_file):
    from compliance_checker.runner import CheckSuite

    CheckSuite.load_all_available_checkers()
    suite = CheckSuite()
    results = suite.run_all(suite.load_dataset(str(pd_file)), ["cf:1.8"], skip_checks=[])
    failures = [str(m) for r in results["cf:1.8"][0] if r.weight == 3 and r.value[0] < r.value[1] for m in r.msgs]
    assert failures == []
