"""CTD casts in CSV: depth or pressure, T and S, validation with the line named."""

from __future__ import annotations

import gsw
import pytest
from numpy.testing import assert_allclose

import envdata
from envdata.casts import MAX_CAST_TOP_M, read_cast
from tests.conftest import DATA

CASTS = DATA / "casts"


def test_depth_cast_starts_at_the_surface_and_ignores_extra_columns():
    ts = read_cast(CASTS / "good.csv", latitude_deg=43.0)
    assert ts.kind == "cast"
    assert ts.depth_m == (0.0, 2.0, 10.0, 25.0, 50.0, 100.0, 300.0, 600.0, 900.0)
    assert ts.temperature_c[:2] == (22.8, 22.8)  # the 2 m sample continued up to the surface
    assert ts.salinity_psu[-1] == 38.48


def test_pressure_is_converted_to_depth_with_teos10_at_the_latitude():
    ts = read_cast(CASTS / "pressure.csv", latitude_deg=43.0)
    expected = -gsw.z_from_p([0.0, 100.0, 1000.0], 43.0)
    assert_allclose(ts.depth_m, expected, rtol=0, atol=1e-9)
    assert 985.0 < ts.depth_m[-1] < 995.0  # 1000 dbar is ~991 m down
    polar = read_cast(CASTS / "pressure.csv", latitude_deg=80.0)
    assert polar.depth_m[-1] < ts.depth_m[-1]  # stronger gravity near the pole


def test_depth_wins_over_pressure_and_notes_are_skipped(tmp_path):
    path = tmp_path / "both.csv"
    path.write_text("# ship notes\npressure_dbar,depth_m,temperature_c,salinity_psu\n"
                    "0,0,20,38\n# a note between rows\n\n500,480,13.5,38.5\n")
    ts = read_cast(path, latitude_deg=43.0)
    assert ts.depth_m == (0.0, 480.0)


BAD = {
    "deep-start": ("depth_m,temperature_c,salinity_psu\n40,20,38\n400,13,38.5\n",
                   rf"line 2: the cast starts at 40\.0 m, deeper than {MAX_CAST_TOP_M:g} m"),
    "one-row": ("depth_m,temperature_c,salinity_psu\n0,20,38\n", r"a cast needs at least 2 rows of data, got 1$"),
    "hot": ("depth_m,temperature_c,salinity_psu\n0,45,38\n100,13,38\n",
            r"line 2: temperature_c: must be in \[-2\.5, 40\] degC, got 45\.0$"),
    "fresh": ("depth_m,temperature_c,salinity_psu\n0,20,38\n100,13,-1\n",
              r"line 3: salinity_psu: must be in \[0, 42\], got -1\.0$"),
    "nan": ("depth_m,temperature_c,salinity_psu\n0,20,38\n100,nan,38\n",
            r"line 3: temperature_c: must be finite, got 'nan'$"),
    "blank": ("depth_m,temperature_c,salinity_psu\n0,20,38\n100,,38\n",
              r"line 3: temperature_c: must be a number, got ''$"),
    "ragged": ("depth_m,temperature_c,salinity_psu\n0,20,38\n100,13\n", r"line 3: has 2 fields, the header has 3$"),
    "negative": ("depth_m,temperature_c,salinity_psu\n-5,20,38\n100,13,38\n",
                 r"line 2: depth_m: must be >= 0 m, got -5\.0$"),
    "repeat": ("pressure_dbar,temperature_c,salinity_psu\n0,20,38\n100,13,38\n100,13,38\n",
               r"line 4: pressure_dbar: must increase strictly down the cast .*got 100\.0 dbar then 100\.0 dbar$"),
    "no-depth": ("z,temperature_c,salinity_psu\n0,20,38\n", r"line 1: the header needs a depth_m or pressure_dbar column"),
    "no-salinity": ("depth_m,temperature_c\n0,20\n", r"line 1: the header needs a salinity_psu column"),
    "empty": ("# only a note\n\n", r"empty CTD cast \(no header row\)$"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_casts_are_refused_naming_file_and_line(tmp_path, name):
    text, message = BAD[name]
    path = tmp_path / f"{name}.csv"
    path.write_text(text)
    with pytest.raises(envdata.AreaError, match=message) as info:
        read_cast(path, latitude_deg=43.0)
    assert str(info.value).startswith(str(path)) and "\n" not in str(info.value)


def test_binary_and_directory_casts_are_refused(tmp_path):
    (tmp_path / "bin.csv").write_bytes(b"depth_m\x00,x\n")
    with pytest.raises(envdata.AreaError, match=r"bin\.csv: binary file, not a CSV cast$"):
        read_cast(tmp_path / "bin.csv", latitude_deg=43.0)
    with pytest.raises(envdata.AreaError, match=r"is a directory, not a CTD cast$"):
        read_cast(tmp_path, latitude_deg=43.0)
