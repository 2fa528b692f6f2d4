"""Grid files: the netCDF round trip, CF compliance, and every way a grid file can be bad."""

from __future__ import annotations

import re

import numpy as np
import pytest
import xarray as xr

import acoustics
from tests.conftest import MALFORMED

pytestmark = pytest.mark.bellhop


def test_round_trip_is_identical(tiny_grid, tiny_grid_file):
    xr.testing.assert_identical(acoustics.open_grid(tiny_grid_file), tiny_grid)


def test_coordinates_carry_no_fill_value(tiny_grid_file):
    import netCDF4

    with netCDF4.Dataset(tiny_grid_file) as nc:
        for name in ("depth", "range", "band_low_hz", "band_center_hz", "source_depth_m"):
            assert "_FillValue" not in nc.variables[name].ncattrs(), name
        assert nc.variables["tl_db"].units == "dB"


def test_write_leaves_no_temporary_file_and_keeps_old_file_on_failure(tiny_grid, tmp_path):
    path = tmp_path / "g.nc"
    acoustics.write_grid(tiny_grid, path)
    before = path.read_bytes()
    bad = tiny_grid.assign_attrs(bad_attr=object())  # netCDF cannot store this attribute
    with pytest.raises(TypeError):
        acoustics.write_grid(bad, path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.nc"]


def test_compliance_checker_finds_no_high_priority_failure_but_db_units(tiny_grid_file):
    from compliance_checker.runner import CheckSuite

    CheckSuite.load_all_available_checkers()
    suite = CheckSuite()
    ds = suite.load_dataset(str(tiny_grid_file))
    results = suite.run_all(ds, ["cf:1.8"], skip_checks=[])
    groups = results["cf:1.8"][0]
    failures = []
    for result in groups:
        if result.weight == 3 and result.value[0] < result.value[1]:  # high priority, not all passed
            failures += [str(m) for m in result.msgs]
    # UDUNITS has no dB: the checker's complaint about dB units is the one accepted exception
    db_units = re.compile(r'units for \w+, "dB[^"]*" are not recognized by UDUNITS')
    assert any(db_units.fullmatch(m) for m in failures)  # the checker did look at our variables
    others = [m for m in failures if not db_units.fullmatch(m)]
    assert others == [], others


def test_missing_file():
    with pytest.raises(acoustics.GridFileError, match=r"no/such.nc: grid file not found"):
        acoustics.open_grid("no/such.nc")


@pytest.mark.parametrize("name, match", [("not-netcdf.nc", "not a netCDF file"),
                                         ("empty.nc", "empty file, not a netCDF grid")])
def test_malformed_grid_files(name, match):
    path = MALFORMED / "grid" / name
    with pytest.raises(acoustics.GridFileError, match=f"{path}: {match}"):
        acoustics.open_grid(path)


def test_truncated_grid_file(tiny_grid_file, tmp_path):
    cut = tmp_path / "cut.nc"
    raw = tiny_grid_file.read_bytes()
    cut.write_bytes(raw[: len(raw) // 2])
    with pytest.raises(acoustics.GridFileError, match=r"cut.nc: cannot read netCDF \(truncated or damaged\)"):
        acoustics.open_grid(cut)


@pytest.mark.parametrize("var", ["tl_db", "k_db", "k_urick_db"])
def test_grid_without_a_required_variable(tiny_grid, tmp_path, var):
    path = tmp_path / f"no-{var}.nc"
    tiny_grid.drop_vars(var).to_netcdf(path)
    with pytest.raises(acoustics.GridFileError, match=f"missing variable '{var}'"):
        acoustics.open_grid(path)


def test_grid_without_source_hash(tiny_grid, tmp_path):
    path = tmp_path / "nohash.nc"
    ds = tiny_grid.copy()
    del ds.attrs["source_hash"]
    ds.to_netcdf(path)
    with pytest.raises(acoustics.GridFileError, match="missing global attribute 'source_hash'"):
        acoustics.open_grid(path)


def test_netcdf_that_is_not_a_grid(tmp_path):
    path = tmp_path / "other.nc"
    xr.Dataset({"x": ("t", np.arange(3.0))}).to_netcdf(path)
    with pytest.raises(acoustics.GridFileError, match="missing dimension 'class'"):
        acoustics.open_grid(path)
