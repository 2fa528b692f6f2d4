"""Study files: the netCDF round trip and one error per way a file can be wrong."""

from __future__ import annotations

import pytest
import xarray as xr

from acoustics import sensitivity as sens


@pytest.mark.bellhop
def test_study_file_round_trip(tiny_study, tmp_path):
    ds, _ = tiny_study
    path = sens.write_study(ds, tmp_path / "s.nc")
    study = sens.open_study(path)
    xr.testing.assert_identical(study.dataset, ds)
    # the face: K in one order, the drawn parameters per member, the area read back
    assert study.k_db.shape == ds["k_db"].shape and study.members == ds.sizes["member"]
    assert study.class_names == tuple(str(c) for c in ds["class"].values)
    assert set(study.parameters) == {n for n, c in ds.coords.items() if c.dims == ("member",) and n != "member"}
    assert study.area is not None and study.area.name == ds.attrs["area"]
    with pytest.raises(sens.StudyFileError, match=r"nope.nc: study file not found"):
        sens.open_study(tmp_path / "nope.nc")
    (tmp_path / "bad.nc").write_text("k_db = 1\n")
    with pytest.raises(sens.StudyFileError, match=r"bad.nc: not a netCDF file"):
        sens.open_study(tmp_path / "bad.nc")
    ds.drop_vars("k_db").to_netcdf(tmp_path / "nok.nc")
    with pytest.raises(sens.StudyFileError, match=r"nok.nc: missing variable k_db\('member', 'class', 'band', "
                                                   r"'range'\)"):
        sens.open_study(tmp_path / "nok.nc")
