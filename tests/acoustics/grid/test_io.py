"""Grid files: the netCDF round trip, CF compliance, and every way a grid file can be bad."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
import xarray as xr

import acoustics
from tests.conftest import MALFORMED

pytestmark = pytest.mark.bellhop


def test_round_trip_is_identical(tiny_grid, tiny_grid_file):
    xr.testing.assert_identical(acoustics.open_tables(tiny_grid_file).dataset, tiny_grid)


def test_coordinates_carry_no_fill_value(tiny_grid_file):
    import netCDF4

    with netCDF4.Dataset(tiny_grid_file) as nc:
        for name in ("depth", "range", "band_low_hz", "band_center_hz", "source_depth_m"):
            assert "_FillValue" not in nc.variables[name].ncattrs(), name
        assert nc.variables["tl_db"].units == "dB"


def test_each_table_is_one_chunk(tiny_grid_file):
    import netCDF4

    # acoustics.grid.io.slab_chunks: a (class, band) table whole in one chunk
    with netCDF4.Dataset(tiny_grid_file) as nc:
        tl = nc.variables["tl_db"]
        assert tl.chunking() == [1, 1, *tl.shape[2:]]


def test_write_leaves_no_temporary_file_and_keeps_old_file_on_failure(tiny_grid, tmp_path):
    path = tmp_path / "g.nc"
    acoustics.write_grid(tiny_grid, path)
    before = path.read_bytes()
    bad = tiny_grid.assign_attrs(bad_attr=object())  # netCDF cannot store this attribute
    with pytest.raises(TypeError):
        acoustics.write_grid(bad, path)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.nc"]


def test_written_file_is_what_xarray_to_netcdf_writes_without_importing_dask_distributed(tiny_grid, tmp_path):
    # write_netcdf skips to_netcdf's look for a dask scheduler (it imports dask.distributed, 0.3 s
    # of every build); the file must hold the same: data, attributes, encodings, compression
    import subprocess
    import sys

    import netCDF4

    from acoustics.grid.io import slab_chunks, write_netcdf

    ours, theirs = tmp_path / "ours.nc", tmp_path / "theirs.nc"
    write_netcdf(tiny_grid, ours)
    encoding = {n: {"dtype": "S1", "_FillValue": None} if v.dtype.kind in "UO" else {"_FillValue": None}
                for n, v in tiny_grid.variables.items() if n in tiny_grid.coords or v.dtype.kind in "UO"}
    encoding |= {n: {"zlib": True, "complevel": 1, "shuffle": True, "_FillValue": None,
                     "chunksizes": slab_chunks(v.shape)}
                 for n, v in tiny_grid.data_vars.items() if np.issubdtype(v.dtype, np.floating)}
    tiny_grid.to_netcdf(theirs, format="NETCDF4", engine="netcdf4", encoding=encoding)
    with xr.open_dataset(ours) as a, xr.open_dataset(theirs) as b:
        xr.testing.assert_identical(a, b)
    with netCDF4.Dataset(ours) as a, netCDF4.Dataset(theirs) as b:
        assert a.data_model == b.data_model == "NETCDF4"
        for name, var in b.variables.items():
            assert (a[name].dtype, a[name].dimensions, a[name].filters(), a[name].chunking()) \
                == (var.dtype, var.dimensions, var.filters(), var.chunking()), name
    code = ("import sys, xarray, acoustics; from acoustics.grid.io import write_netcdf; "
            f"write_netcdf(xarray.open_dataset({str(theirs)!r}).load(), {str(tmp_path / 'again.nc')!r}); "
            "print('dask.distributed' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.strip() == "False", out


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
        acoustics.open_tables("no/such.nc")


@pytest.mark.parametrize("name, match", [("not-netcdf.nc", "not a netCDF file"),
                                         ("empty.nc", "empty file, not a netCDF grid")])
def test_malformed_grid_files(name, match):
    path = MALFORMED / "grid" / name
    with pytest.raises(acoustics.GridFileError, match=f"{path}: {match}"):
        acoustics.open_tables(path)


def test_truncated_grid_file(tiny_grid_file, tmp_path):
    cut = tmp_path / "cut.nc"
    raw = tiny_grid_file.read_bytes()
    cut.write_bytes(raw[: len(raw) // 2])
    with pytest.raises(acoustics.GridFileError, match=r"cut.nc: cannot read netCDF \(truncated or damaged\)"):
        acoustics.open_tables(cut)


@pytest.mark.parametrize("var", ["tl_db", "k_db", "k_urick_db"])
def test_grid_without_a_required_variable(tiny_grid, tmp_path, var):
    path = tmp_path / f"no-{var}.nc"
    tiny_grid.drop_vars(var).to_netcdf(path)
    with pytest.raises(acoustics.GridFileError, match=f"missing variable '{var}'"):
        acoustics.open_tables(path)


def test_grid_without_source_hash(tiny_grid, tmp_path):
    path = tmp_path / "nohash.nc"
    ds = tiny_grid.copy()
    del ds.attrs["source_hash"]
    ds.to_netcdf(path)
    with pytest.raises(acoustics.GridFileError, match="missing global attribute 'source_hash'"):
        acoustics.open_tables(path)


def test_netcdf_that_is_not_a_grid(tmp_path):
    path = tmp_path / "other.nc"
    xr.Dataset({"x": ("t", np.arange(3.0))}).to_netcdf(path)
    with pytest.raises(acoustics.GridFileError, match="missing dimension 'class'"):
        acoustics.open_tables(path)


def _edited_area_json(ds, edit):
    data = json.loads(ds.attrs["area_json"])
    edit(data)
    return ds.assign_attrs(area_json=json.dumps(data))


def _nan(ds, name):
    return ds.assign({name: ds[name] * np.nan})


@pytest.mark.parametrize("label, change, match", [
    ("area_json not JSON", lambda ds: ds.assign_attrs(area_json="{not json"),
     r"area_json: not valid JSON"),
    ("area_json a list", lambda ds: ds.assign_attrs(area_json="[1, 2]"),
     r"area_json: must be a JSON object, got list"),
    ("area_json missing", lambda ds: ds.drop_attrs(deep=False).assign_attrs(
        {k: v for k, v in ds.attrs.items() if k != "area_json"}),
     r"missing global attribute 'area_json'"),
    ("class the grid lacks", lambda ds: _edited_area_json(
        ds, lambda d: d["classes"][0].update(name="OTHER")),
     r"area_json: class names OTHER, SHIP do not match the grid's SUB, SHIP"),
    ("negative integration time", lambda ds: _edited_area_json(
        ds, lambda d: d["sonar"].update(integration_time_s=-1.0)),
     r"area_json: \[sonar\] integration_time_s: must be in \(0, 3600\] s, got -1.0"),
    ("unknown key", lambda ds: _edited_area_json(ds, lambda d: d["sonar"].update(gain=3)),
     r"area_json: \[sonar\]: unknown key 'gain'"),
    ("observer elsewhere", lambda ds: ds.assign_attrs(observer_depth_m=55.0),
     r"area_json: observer depth 100 m, but the grid's attribute observer_depth_m is 55 m"),
    ("observer depth a string", lambda ds: ds.assign_attrs(observer_depth_m="deep"),
     r"global attribute 'observer_depth_m' must be a number, got str"),
    ("source hash a number", lambda ds: ds.assign_attrs(source_hash=42),
     r"global attribute 'source_hash' must be a string"),
    ("band edge moved", lambda ds: ds.assign_coords(
        band_low_hz=("band", ds["band_low_hz"].values + 1.0, ds["band_low_hz"].attrs)),
     r"area_json: band_low_hz \d+ Hz, but the grid's coordinate has \d+ Hz"),
    ("all-NaN TL", lambda ds: _nan(ds, "tl_db"), r"variable 'tl_db' holds no finite value"),
    ("all-NaN K", lambda ds: _nan(ds, "k_db"), r"variable 'k_db' holds no finite value"),
])
def test_grid_gate_refuses_inconsistent_grids(tiny_grid, tmp_path, label, change, match):
    path = tmp_path / "bad.nc"
    acoustics.write_grid(change(tiny_grid), path)
    with pytest.raises(acoustics.GridFileError, match=f"^{re.escape(str(path))}: .*{match}"):
        acoustics.open_tables(path)


def test_area_json_reads_back_into_the_same_area(tiny_grid, tiny_area):
    import envdata

    assert envdata.area_from_json(tiny_grid.attrs["area_json"]) == tiny_area
