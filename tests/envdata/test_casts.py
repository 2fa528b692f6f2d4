"""CTD casts in CSV and Sea-Bird .cnv: depth or pressure, T and S, validation with the line named."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import gsw
import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from envdata.casts import MAX_CAST_TOP_M, read_cast
from tests.conftest import DATA
from tests.fixtures import sample_data
from tests.fixtures.layouts import SEABIRD_BAD_FLAG

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


# --- Sea-Bird .cnv casts ---------------------------------------------------------------------

SHELF_CNV = CASTS / "shelf-ctd.cnv"
SHELF_CSV = CASTS / "shelf-ctd.csv"


def _scans(**changes) -> dict:
    return {name: np.array(values) for name, values in {**sample_data.cast_scans(), **changes}.items()}


def _without(columns: dict, rows) -> dict:
    keep = np.ones(len(columns["flag"]), dtype=bool)
    keep[rows] = False
    return {name: values[keep] for name, values in columns.items()}


def test_the_generator_writes_the_shipped_cast(tmp_path):
    assert sample_data.main(["--cast", str(tmp_path)]) == 0
    for path in (SHELF_CNV, SHELF_CSV):
        assert (tmp_path / path.name).read_bytes() == path.read_bytes()


def test_sample_cnv_is_in_sea_birds_layout():
    raw = SHELF_CNV.read_bytes()
    assert raw.count(b"\r\n") == raw.count(b"\n")  # SBE Data Processing's Windows line ends
    lines = raw.decode("ascii").splitlines()
    assert lines[0] == "* Sea-Bird SBE 9 Data File:" and "* NMEA Latitude = 43 00.00 N" in lines
    end = lines.index("*END*")
    assert lines[end - 1] == "# file_type = ascii"
    assert "# nquan = 5" in lines and "# nvalues = 100" in lines and "# bad_flag = -9.990e-29" in lines
    assert [line for line in lines if line.startswith("# name")] == [
        "# name 0 = prDM: Pressure, Digiquartz [db]",
        "# name 1 = depSM: Depth [salt water, m], lat = 43.00",
        "# name 2 = t090C: Temperature [ITS-90, deg C]",
        "# name 3 = sal00: Salinity, Practical [PSU]",
        "# name 4 = flag:  0.000e+00"]
    data = lines[end + 1:]
    assert len(data) == 100 and {len(line) for line in data} == {5 * 11}  # fixed-width columns
    assert data[0] == "      5.040      5.000    23.1107    38.1535  0.000e+00"


def test_cnv_and_its_csv_twin_give_the_same_profile():
    cnv = read_cast(SHELF_CNV, latitude_deg=43.0)
    assert cnv == read_cast(SHELF_CSV, latitude_deg=43.0)
    assert cnv.kind == "cast"
    assert cnv.depth_m == (0.0, *(5.0 * k for k in range(1, 101)))  # depSM, not prDM, continued up to 0 m
    t, s = sample_data.cast_ts(np.array(cnv.depth_m[1:]))
    assert_allclose(cnv.temperature_c[1:], t, rtol=0, atol=5e-5)  # written to 4 decimals
    assert_allclose(cnv.salinity_psu[1:], s, rtol=0, atol=5e-5)


def test_a_sea_bird_header_is_read_as_cnv_whatever_the_name(tmp_path):
    shutil.copy(SHELF_CNV, tmp_path / "stn01.asc")
    assert read_cast(tmp_path / "stn01.asc", latitude_deg=43.0) == read_cast(SHELF_CNV, latitude_deg=43.0)


def test_cnv_pressure_is_converted_to_depth_with_teos10_at_the_latitude(tmp_path):
    columns = _scans()
    del columns["depSM"]
    columns = _without(columns, [])
    binned = {name: columns[name][10:400:40] for name in ("prDM", "t090C", "sal00")}  # increasing: used as they are
    path = sample_data.write_scans(tmp_path / "pressure.cnv", binned)
    pressure = np.round(binned["prDM"], 3)  # as written
    ts = read_cast(path, latitude_deg=43.0)
    assert_allclose(ts.depth_m[1:], -gsw.z_from_p(pressure, 43.0), rtol=0, atol=1e-9)
    assert read_cast(path, latitude_deg=80.0).depth_m[-1] < ts.depth_m[-1]  # stronger gravity near the pole


def test_ipts68_temperature_is_converted_to_its90(tmp_path):
    depth = np.array([2.0, 50.0, 300.0])
    t90, s = sample_data.cast_ts(depth)
    path = sample_data.write_scans(tmp_path / "t68.cnv", {"depSM": depth, "t068C": t90 * 1.00024, "sal00": s})
    ts = read_cast(path, latitude_deg=43.0)
    assert_allclose(ts.temperature_c[1:], t90, rtol=0, atol=1e-4)
    assert_allclose(ts.temperature_c[1:], gsw.t90_from_t68(np.round(t90 * 1.00024, 4)), rtol=0, atol=1e-12)


def test_scans_are_binned_to_1_m_within_the_binning(tmp_path):
    columns = _scans()
    assert np.any(np.diff(columns["depSM"][8:2000]) < 0.0)  # the heave takes the CTD back up
    ts = read_cast(sample_data.write_scans(tmp_path / "scans.cnv", columns), latitude_deg=43.0)
    z = np.array(ts.depth_m)
    assert z[0] == 0.0 and z[1] == 2.0 and z[-1] == np.round(columns["depSM"].max())
    assert np.all(np.diff(z[1:]) == 1.0)  # every whole metre from 2 m down
    # each bin's mean lies between the extremes of the water over its metre (+ the 4 decimals)
    fine = z[1:, None] + np.linspace(-0.5, 0.5, 201)[None, :]
    t, s = sample_data.cast_ts(fine.ravel())
    t, s = t.reshape(fine.shape), s.reshape(fine.shape)
    for got, model in ((ts.temperature_c[1:], t), (ts.salinity_psu[1:], s)):
        assert np.all(got >= model.min(axis=1) - 1e-4) and np.all(got <= model.max(axis=1) + 1e-4)
    # the CSV twin (5 m bins) agrees at its depths from 5 m down (above, each continues its own
    # shallowest sample): to 0.2 degC in the thermocline (0.4 degC/m), 0.005 degC below 100 m
    csv = read_cast(SHELF_CSV, latitude_deg=43.0)
    at = np.array(csv.depth_m[1:])
    error = np.abs(np.interp(at, z, ts.temperature_c) - csv.temperature_c[1:])
    assert error.max() < 0.2 and error[at >= 100.0].max() < 5e-3
    assert_allclose(np.interp(at, z, ts.salinity_psu), csv.salinity_psu[1:], rtol=0, atol=2e-3)


def test_the_upcast_and_the_scans_on_deck_are_ignored(tmp_path):
    columns = _scans()
    bottom = int(np.argmax(columns["depSM"]))
    whole = read_cast(sample_data.write_scans(tmp_path / "whole.cnv", columns), latitude_deg=43.0)
    down = read_cast(sample_data.write_scans(tmp_path / "down.cnv", _without(columns, slice(bottom + 1, None))),
                     latitude_deg=43.0)
    wet = read_cast(sample_data.write_scans(tmp_path / "wet.cnv", _without(columns, slice(0, 8))),
                    latitude_deg=43.0)
    assert whole == down == wet
    assert whole.temperature_c[-1] < sample_data.cast_ts([whole.depth_m[-1]])[0][0] + 1e-3  # not 0.3 warmer


def test_flagged_scans_and_bad_values_are_dropped(tmp_path):
    columns = _scans()
    spikes = [300, 301, 1500, 2600]  # bubbles in the conductivity cell: flagged bad by hand
    columns["t090C"][spikes] += 5.0
    columns["sal00"][spikes] -= 3.0
    columns["flag"][spikes] = SEABIRD_BAD_FLAG
    missing = [900, 1700]
    columns["sal00"][missing[0]] = SEABIRD_BAD_FLAG  # no value: the sensor dropped out
    columns["t090C"][missing[1]] = SEABIRD_BAD_FLAG
    path = sample_data.write_scans(tmp_path / "flagged.cnv", columns)
    assert " -9.990e-29" in path.read_text()
    clean = sample_data.write_scans(tmp_path / "clean.cnv", _without(columns, spikes + missing))
    assert read_cast(path, latitude_deg=43.0) == read_cast(clean, latitude_deg=43.0)
    # a binned file: its flagged bin is left out
    binned = sample_data.write_cast(tmp_path)[0]
    lines = binned.read_text().splitlines()
    row = lines.index("*END*") + 50
    lines[row] = lines[row][:-11] + f"{SEABIRD_BAD_FLAG:11.3e}"
    binned.write_text("\n".join(lines) + "\n")
    ts = read_cast(binned, latitude_deg=43.0)
    assert len(ts.depth_m) == 100 and 250.0 not in ts.depth_m and 245.0 in ts.depth_m


def test_cnv_is_not_imported_before_it_is_needed():
    code = "import sys, envdata, envdata.casts; print('ctd' in sys.modules, 'matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]  # ctd imports matplotlib.pyplot: 1 s


def _sample_lines() -> list[str]:
    return SHELF_CNV.read_text().splitlines()


def _replace_value(row: int, column: int, text: str) -> bytes:
    lines = _sample_lines()
    k = lines.index("*END*") + row
    lines[k] = lines[k][:11 * column] + f"{text:>11}" + lines[k][11 * (column + 1):]
    return ("\n".join(lines) + "\n").encode()


def _drop(*names: str) -> dict:
    return {k: v for k, v in _scans().items() if k not in names}


def _header_only() -> bytes:
    lines = _sample_lines()
    return ("\n".join(lines[:lines.index("*END*") + 1]) + "\n\n").encode()


BAD_CNV = {
    "no-temperature": (lambda p: sample_data.write_scans(p, _drop("t090C")),
                       r"no-temperature\.cnv: no temperature column \(t090C or t068C\) "
                       r"among prDM, depSM, sal00, timeS, flag$"),
    "no-salinity": (lambda p: sample_data.write_scans(p, _drop("sal00")),
                    r"no salinity column \(sal00\) among prDM, depSM, t090C, timeS, flag$"),
    "no-depth": (lambda p: sample_data.write_scans(p, _drop("depSM", "prDM")),
                 r"no depth or pressure column \(depSM or prDM\) among t090C, sal00, timeS, flag$"),
    "garbage": (lambda p: p.write_bytes(bytes(range(256)) * 8), r"garbage\.cnv: binary file, not a Sea-Bird \.cnv cast$"),
    "latin-text": (lambda p: p.write_bytes(b"\xe9t\xe9 \xff\xfe junk\r\n" * 20),
                   r"no \*END\* line closing the header: not a Sea-Bird \.cnv file, or one cut short$"),
    "empty": (lambda p: p.write_bytes(b"\r\n\r\n"), r"empty\.cnv: empty file, not a Sea-Bird \.cnv cast$"),
    "header-only": (lambda p: p.write_bytes(_header_only()), r"a header without data: no scans after \*END\*$"),
    "no-names": (lambda p: p.write_text("\n".join(line for line in _sample_lines() if not line.startswith("# name"))),
                 r"the header names no columns \(no '# name N = \.\.\.' lines\)$"),
    "not-a-number": (lambda p: p.write_bytes(_replace_value(3, 2, "abc")),
                     r"line 43: t090C: must be a finite number, got 'abc'$"),
    "nan": (lambda p: p.write_bytes(_replace_value(3, 3, "nan")), r"line 43: sal00: must be a finite number, got 'nan'$"),
    "ragged": (lambda p: p.write_bytes(_replace_value(4, 4, "")),
               r"line 44: has 4 values, the header names 5 columns$"),
    "hot": (lambda p: p.write_bytes(_replace_value(2, 2, "45.0000")),
            r"line 42: t090C: must be in \[-2\.5, 40\] degC, got 45\.0$"),
    "deep-start": (lambda p: sample_data.write_scans(p, {"depSM": [40.0, 400.0], "t090C": [20.0, 13.0],
                                                              "sal00": [38.0, 38.5]}),
                   rf"line 31: the cast starts at 40\.0 m, deeper than {MAX_CAST_TOP_M:g} m"),
    "one-metre": (lambda p: sample_data.write_scans(p, {"depSM": [3.0, 2.9, 3.2, 3.1], "t090C": [20.0] * 4,
                                                             "sal00": [38.0] * 4}),
                  r"a cast needs at least 2 depths of good scans on the down-cast, got 1$"),
    # a column ctd converts to int and cannot: its error, on one line
    "bpos": (lambda p: sample_data.write_scans(p, _scans(), names={"timeS": "bpos"}),
             r"bpos\.cnv: ctd could not read the \.cnv table: invalid literal for int\(\) .*'\d+\.\d+'$"),
}


@pytest.mark.parametrize("name", sorted(BAD_CNV))
def test_bad_cnv_casts_are_refused_in_one_line_naming_the_file(tmp_path, name):
    write, message = BAD_CNV[name]
    path = tmp_path / f"{name}.cnv"
    write(path)
    with pytest.raises(envdata.AreaError, match=message) as info:
        read_cast(path, latitude_deg=43.0)
    assert str(info.value).startswith(str(path)) and "\n" not in str(info.value)


def _area_file(folder: Path, cast: str) -> Path:
    text = (DATA / "tiny-munk.toml").read_text()
    path = folder / "area.toml"
    path.write_text(text.replace('ssp = "munk"', f'cast = "{cast}"'))
    return path


def test_an_area_file_takes_a_cnv_cast(tmp_path):
    shutil.copy(SHELF_CNV, tmp_path / "stn01.cnv")
    shutil.copy(SHELF_CSV, tmp_path / "stn01.csv")
    area = envdata.load_area(_area_file(tmp_path, "stn01.cnv"))
    ssp = area.water.ssp
    assert ssp.kind == "cast" and ssp.depth_m[0] == 0.0 and ssp.depth_m[-1] == area.water.depth_m == 1000.0
    assert area.water.cast.path == "stn01.cnv"
    (tmp_path / "area.toml").unlink()
    assert envdata.load_area(_area_file(tmp_path, "stn01.csv")).water.ssp == ssp
    _area_file(tmp_path, "bad.cnv")
    (tmp_path / "bad.cnv").write_bytes(_header_only())
    with pytest.raises(envdata.AreaError, match=r"area\.toml: \[water\] cast: .*bad\.cnv: a header without data"):
        envdata.load_area(tmp_path / "area.toml")
