"""Area files: built-in areas load, bad files fail with one clear message each."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from envdata.classes import F_MINUS_2_DB_PER_OCTAVE
from tests.conftest import MALFORMED

AREA_CASES = {
    "missing-water.toml": r"top level: missing required key 'water'",
    "depth-string.toml": r"\[water\] depth_m: must be a number, got 'deep'",
    "negative-depth.toml": r"\[water\] depth_m: must be > 0 m, got -1000.0",
    "nonmonotonic-ssp.toml": r"depths must increase strictly, got 500.0 m then 400.0 m",
    "nan-speed.toml": r"ssp_speed_mps: must be finite, got nan",
    "ssp-too-deep.toml": r"goes to 1200.0 m, deeper than the water",
    "ssp-short.toml": r"ends at 800.0 m and does not reach the bottom",
    "ssp-not-at-surface.toml": r"must start at the surface, 0 m, got 100.0 m",
    "ssp-unphysical-speed.toml": r"speed 15100.0 m/s at 500.0 m is outside \[1400, 1650\] m/s",
    "ts-salinity.toml": r"salinity_psu must be in \[0, 42\], got 60.0",
    "inverted-band.toml": r"band 'FB1': need 0 < low_hz <= high_hz, got 300.0 Hz, 100.0 Hz",
    "negative-band.toml": r"band 'FB1': need 0 < low_hz <= high_hz, got -100.0 Hz",
    "duplicate-class.toml": r"duplicate class name 'SUB'",
    "syntax-error.toml": r"TOML syntax error",
    "unknown-key.toml": r"\[water\]: unknown key 'colour'",
    "observer-below-bottom.toml": r"\[observer\] depth_m: must be inside the water \(0, 1000.0\) m, got 2000.0",
    "class-below-bottom.toml": r"class 'SUB': depth_m 1500.0 m is not above the bottom",
    "bad-mode.toml": r"\[propagation\] mode: must be one of incoherent, semicoherent, coherent, got 'fast'",
    "bottom-speed.toml": r"\[bottom\] speed_mps: must be in \[1000, 6000\] m/s, got -1600.0",
    "missing-bands.toml": r"missing required key 'bands'",
    "class-speed-string.toml": r"\[\[classes\]\] #1 speed_mean_mps: must be a number, got 'fast'",
    "grid-step.toml": r"\[grid\] range_step_m: must be > 0 m, got 0.0",
    "empty.toml": r"empty area file",
    "binary.toml": r"binary file, not a TOML area file",
    "nested-deep.toml": r"TOML nested too deeply to read",
    "name-newline.toml": r"\[area\] name: must be letters, digits, '\.', '_' or '-'",
    "name-quote.toml": r"\[area\] name: must be letters, digits",
    "band-name-space.toml": r"band name: must be letters, digits, .*got 'FB 1'",
    "run-timeout-negative.toml": r"\[propagation\] run_timeout_s: must be in \(0, 2592000\] s \(30 days\), got -5.0",
    # range- and bearing-dependent areas (docs/formats.md "[origin] and [bearings]")
    "origin-without-bearings.toml": r"\[origin\]: needs \[bearings\] \(step_deg or bearing_deg\)",
    "bearings-without-origin.toml": r"\[bearings\]: needs \[origin\] \(lat_deg, lon_deg\)",
    "bathymetry-without-origin.toml": r"\[water\] bathymetry: a data file needs \[origin\]",
    "climatology-without-origin.toml": r"\[water\] climatology: a data file needs \[origin\]",
    "month-13.toml": r"\[water\] month: must be an integer in 1\.\.12, got 13$",
    "month-fraction.toml": r"\[water\] month: must be an integer in 1\.\.12, got 8\.5$",
    "month-without-climatology.toml": r"\[water\] month: only with a climatology file",
    "temperature-variable-without-climatology.toml": r"\[water\] temperature_variable: only with a climatology "
                                                     r"file \(climatology, or temperature and salinity\)$",
    "step-not-dividing.toml": r"\[bearings\] step_deg: 7\.0 deg does not divide 360 deg into whole steps",
    "step-negative.toml": r"\[bearings\] step_deg: must be in \(0, 360\] deg, got -10\.0$",
    "step-too-fine.toml": r"\[bearings\] step_deg: 0\.1 deg gives 3600 radials, more than 720$",
    "bearing-360.toml": r"\[bearings\] bearing_deg: each bearing must be in \[0, 360\) deg, got 360\.0$",
    "bearing-duplicate.toml": r"\[bearings\] bearing_deg: duplicate bearing 90\.0 deg$",
    "bearing-decreasing.toml": r"\[bearings\] bearing_deg: bearings must increase, got 90\.0 deg then 45\.0 deg$",
    "bearings-both.toml": r"\[bearings\]: give either step_deg or bearing_deg",
    "bearings-unknown-key.toml": r"\[bearings\]: unknown key 'start_deg'$",
    "origin-pole.toml": r"\[origin\] lat_deg: must be in \(-90, 90\) deg .*got 90\.0$",
    "origin-missing-lon.toml": r"\[origin\]: missing required key 'lon_deg'$",
    "depth-and-bathymetry.toml": r"\[water\]: depth_m and bathymetry both given; give one",
    "two-sound-speeds.toml": r"\[water\]: ssp and a climatology both give the sound speed; give one$",
    "temperature-without-salinity.toml": r"\[water\] salinity: missing; a climatology is one file",
    "climatology-and-split.toml": r"\[water\] climatology: give either climatology or temperature and salinity",
    "bathymetry-variable-alone.toml": r"\[water\] bathymetry_variable: only with a bathymetry file$",
    "bathymetry-empty-name.toml": r"\[water\] bathymetry: must be a file name, got ' '$",
    "interpolation-with-climatology.toml": r"\[water\] ssp_interpolation: only for one profile, not with a climatology$",
    "step-m-zero.toml": r"\[propagation\] step_m: must be in \(0, 100000\] m, got 0\.0$",
    "image-beams-few.toml": r"\[propagation\] surface_image_beams: must be in \[100, 200000\], got 50$",
    "latitude-differs-from-origin.toml": r"\[area\] latitude_deg, longitude_deg: 40\.0, 5\.0 deg differ from \[origin\] 43\.0, 5\.0",
    "cast-missing.toml": r"\[water\] cast: .*no-such-cast\.csv: CTD cast not found$",
    "cast-above-observer.toml": r"\[water\] cast: '\.\./\.\./casts/shallow\.csv' ends at 50 m and does not reach below "
                                r"the observer at 100 m$",
    "cast-not-a-number.toml": r"\[water\] cast: .*not-a-number\.csv: line 3: temperature_c: must be a number, got 'abc'$",
    "cast-upcast.toml": r"upcast\.csv: line 4: depth_m: must increase strictly down the cast .*got 500\.0 m then 400\.0 m$",
    "cast-no-temperature.toml": r"no-temperature\.csv: line 1: the header needs a temperature_c column, got depth_m, "
                                r"temp, salinity_psu$",
    "cast-and-table.toml": r"\[water\]: a speed table and a cast both give the sound speed; give one$",
}


def test_every_malformed_area_file_has_a_case():
    on_disk = {p.name for p in (MALFORMED / "area").iterdir()}
    assert on_disk == set(AREA_CASES)


@pytest.mark.parametrize("name", sorted(AREA_CASES))
def test_malformed_area_raises_one_line_error_naming_the_file(name):
    path = MALFORMED / "area" / name
    with pytest.raises(envdata.AreaError, match=AREA_CASES[name]) as info:
        envdata.load_area(path)
    message = str(info.value)
    assert message.startswith(str(path)), message
    assert "\n" not in message


def test_missing_file_and_unknown_name():
    with pytest.raises(envdata.AreaError, match="area file not found"):
        envdata.load_area("no/such/area.toml")
    with pytest.raises(envdata.AreaError, match="no built-in area of that name"):
        envdata.load_area("atlantis")


@pytest.mark.parametrize("name", ["ocean-deep", "munk-1000"])
def test_flat_builtin_areas_load(name):
    area = envdata.load_area(name)
    assert area.name == name
    assert area.water.ssp.bottom_m == area.water.depth_m
    assert area.depth_m()[0] == 0.0 and area.depth_m()[-1] == area.water.depth_m
    assert area.grid.range_m()[0] == area.grid.range_step_m
    assert area.grid.range_m()[-1] == pytest.approx(area.grid.range_max_m)


def test_ocean_deep_matches_grinenkov_mashoshin_section_4():
    area = envdata.load_area("ocean-deep")
    assert area.observer.depth_m == 100.0
    assert [c.name for c in area.classes] == ["NPS", "SW", "TV"]
    # Table 1 levels are dB re 20 uPa; +20 lg 20 = 26.02 dB gives dB re 1 uPa
    ref20 = 20 * np.log10(20.0)
    assert_allclose([c.noise_mean_db for c in area.classes], np.array([62.0, 100.0, 107.0]) + ref20,
                    rtol=0, atol=0.005)
    assert_allclose(area.noise.spectrum_level_1khz_db, 31.0 + ref20, rtol=0, atol=0.005)
    assert area.target_class("NPS").depth_m == 200.0
    assert area.grid.range_max_m >= 120_000.0
    assert [(b.low_hz, b.high_hz) for b in area.bands] == [(100, 300), (300, 1000), (1000, 3000)]


def test_munk_1000_is_the_iglesis_de_montella_appendix():
    area = envdata.load_area("munk-1000")
    assert area.water.depth_m == 1000.0
    assert area.observer.depth_m == 300.0
    assert area.bands[0].is_single_frequency and area.bands[0].center_hz == 50.0
    (ship,) = area.classes
    assert ship.depth_m == 5.0 and ship.source_level_model is envdata.SourceLevelModel.ROSS
    assert (area.bottom.speed_mps, area.bottom.density_gcc, area.bottom.attenuation_db_per_wavelength) == (
        1600.0, 1.8, 0.8)
    # the appendix's table is the canonical Munk profile at its seven depths (0.01 m/s: 2 decimals)
    assert_allclose(area.water.ssp.speed_mps, envdata.munk_speed_mps(np.array(area.water.ssp.depth_m)),
                    rtol=0, atol=0.01)


def test_munk_profile_canonical_values():
    assert_allclose(envdata.munk_speed_mps(1300.0), 1500.0, rtol=0, atol=1e-9)  # on the axis
    assert_allclose(envdata.munk_speed_mps(0.0), 1548.52, rtol=0, atol=0.005)
    ssp = envdata.munk_profile(5000.0)
    assert ssp.depth_m[0] == 0.0 and ssp.depth_m[-1] == 5000.0
    assert np.argmin(ssp.speed_mps) == pytest.approx(1300.0 / 25.0)


def test_ts_profile_uses_teos10():
    ssp = envdata.ts_profile([0.0, 1000.0], [10.0, 4.0], [35.0, 35.0], latitude_deg=45.0, longitude_deg=-30.0)
    # TEOS-10 at 10 degC, 35 psu, surface: 1489.8 m/s (Mackenzie's formula gives 1489.8 too)
    assert_allclose(ssp.speed_mps[0], 1489.8, rtol=0, atol=0.3)
    assert 1480.0 < ssp.speed_mps[1] < 1495.0  # cold but under 100 bar of pressure


def test_class_slope_default_is_f_minus_2():
    cls = envdata.TargetClass(name="x", depth_m=10.0, speed_mean_mps=5.0, speed_sd_mps=1.0, noise_mean_db=100.0)
    assert cls.source_slope_db_per_octave == F_MINUS_2_DB_PER_OCTAVE
    assert_allclose(cls.spectral_exponent, -2.0, rtol=0, atol=1e-12)


def test_band_center_is_geometric_mean_and_single_frequency_band_is_1hz():
    band = envdata.Band(name="FB1", low_hz=100.0, high_hz=400.0)
    assert band.center_hz == pytest.approx(200.0)
    assert band.width_hz == 300.0
    single = envdata.Band(name="F50", low_hz=50.0, high_hz=50.0)
    assert single.width_hz == 1.0 and single.is_single_frequency


def test_area_is_frozen_and_varied_with_replace(tiny_area):
    with pytest.raises(dataclasses.FrozenInstanceError):
        tiny_area.name = "other"  # type: ignore[misc]
    deeper = dataclasses.replace(tiny_area, observer=envdata.Observer(depth_m=300.0))
    assert deeper.observer.depth_m == 300.0 and tiny_area.observer.depth_m == 100.0


def test_noise_band_level_integrates_the_spectrum():
    noise = envdata.Noise(spectrum_level_1khz_db=57.0, slope_db_per_octave=0.0)
    band = envdata.Band(name="b", low_hz=1000.0, high_hz=2000.0)
    assert_allclose(noise.band_level_db(band), 57.0 + 30.0, rtol=0, atol=1e-9)  # flat: + 10 lg 1000 Hz
    single = envdata.Band(name="s", low_hz=2000.0, high_hz=2000.0)
    assert_allclose(envdata.Noise(spectrum_level_1khz_db=57.0).band_level_db(single), 52.0, rtol=0, atol=1e-9)


AREA_JSON_SOURCES = ["ocean-deep", "munk-1000", "shelf-break", "tests/data/tiny-munk.toml"]


@pytest.mark.parametrize("name", AREA_JSON_SOURCES)
def test_area_json_round_trip_gives_the_same_area(name):
    area = envdata.load_area(name)
    text = envdata.area_to_json(area)
    again = envdata.area_from_json(text, "grid.nc")
    assert again == area
    assert envdata.area_to_json(again) == text  # and the same text: hashes stay put


def test_area_json_of_a_ts_profile_keeps_its_speeds():
    data = {**envdata.load_area("tests/data/tiny-munk.toml").to_dict()}
    data["water"] = {"depth_m": 1000.0, "ssp_depth_m": [0.0, 500.0, 1000.0],
                     "temperature_c": [15.0, 5.0, 3.0], "salinity_psu": [35.0, 34.8, 34.9]}
    area = envdata.parse_area(data, "ts.toml")
    again = envdata.area_from_json(envdata.area_to_json(area))
    assert again == area and again.water.ssp.speed_mps == area.water.ssp.speed_mps


def test_area_json_is_validated_like_an_area_file():
    data = envdata.load_area("tests/data/tiny-munk.toml").to_dict()
    data["bottom"]["speed_mps"] = -1600.0
    import json

    with pytest.raises(envdata.AreaError, match=r"^g.nc: area_json: \[bottom\] speed_mps: must be in "
                                                r"\[1000, 6000\] m/s, got -1600.0$"):
        envdata.area_from_json(json.dumps(data), "g.nc")
    with pytest.raises(envdata.AreaError, match=r"^g.nc: area_json: not valid JSON"):
        envdata.area_from_json("[" * 100_000, "g.nc")
