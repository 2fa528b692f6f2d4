"""ram_tl_db: array orientation, the receiver grid, the masks and the input it refuses.

easypyram takes the sound speed as (depth, range) and returns (depth, range) fields; the
environment holds (range, depth). A square section passes easypyram's shape check either
way round (pyram's issue 5 is this trap), so the orientation is tested with square sections.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.absorption import thorp_db_per_km
from acoustics.ram import RamEnvironment, RamInputError, RamSettings, ram_tl_db
from envdata.area import Absorption
from envdata.bottom import Bottom

FREQ_HZ = 100.0
BOTTOM = Bottom(speed_mps=1700.0, density_gcc=1.5, attenuation_db_per_wavelength=0.5)


def _env(z, speed_by_range, ranges=(0.0,), **overrides) -> RamEnvironment:
    kwargs = dict(bathymetry_range_m=[0.0], bathymetry_depth_m=[100.0], ssp_range_m=list(ranges),
                  ssp_depth_m=list(z), speed_mps=speed_by_range, bottom=BOTTOM, source_depth_m=30.0)
    kwargs.update(overrides)
    return RamEnvironment(**kwargs)


def _settings(env: RamEnvironment) -> RamSettings:
    return RamSettings.for_frequency(FREQ_HZ, max_bottom_depth_m=env.max_bottom_depth_m)


DEPTHS = np.array([0.0, 10.0, 30.0, 55.0, 90.0, 100.0, 120.0])
RANGES = np.arange(200.0, 3001.0, 200.0)


def test_a_square_section_reaches_easypyram_as_depth_by_range():
    # speed varies with depth only, given as a square (range x depth) section: it must give the
    # field of the same single profile; transposed, it would vary with range instead
    z = [0.0, 50.0, 100.0]
    profile = [1480.0, 1500.0, 1520.0]
    one = _env(z, [profile])
    square = _env(z, [profile, profile, profile], ranges=(0.0, 1500.0, 3000.0))
    tl_one = ram_tl_db(one, FREQ_HZ, DEPTHS, RANGES, _settings(one))
    tl_square = ram_tl_db(square, FREQ_HZ, DEPTHS, RANGES, _settings(square))
    assert_allclose(tl_square, tl_one, rtol=0, atol=1e-6, equal_nan=True)
    # and a section that changes with range does change the field (the columns are used)
    fast = [1530.0, 1530.0, 1530.0]
    changing = _env(z, [profile, fast, fast], ranges=(0.0, 1000.0, 3000.0))
    tl_changing = ram_tl_db(changing, FREQ_HZ, DEPTHS, RANGES, _settings(changing))
    assert np.nanmedian(np.abs(tl_changing - tl_one)[:, RANGES > 1500.0]) > 1.0


def test_the_output_is_depth_by_range_with_the_surface_capped_and_nan_below_the_bottom():
    env = _env([0.0, 100.0], [[1500.0, 1500.0]])
    tl = ram_tl_db(env, FREQ_HZ, DEPTHS, RANGES, _settings(env))
    assert tl.shape == (DEPTHS.size, RANGES.size)
    assert_allclose(tl[0], 200.0)                   # pressure release: zero pressure, capped
    assert np.all(np.isnan(tl[DEPTHS > 100.0]))     # below the bottom
    inside = tl[(DEPTHS > 0.0) & (DEPTHS <= 100.0)]
    assert np.all(np.isfinite(inside)) and np.all((inside > 30.0) & (inside < 120.0))
    # spreading: TL grows with range on the whole (cylindrical beyond the first bounces)
    assert np.mean(inside[:, -3:]) > np.mean(inside[:, :3]) + 5.0


def test_ranges_beyond_the_end_are_nan_and_the_bottom_follows_the_bathymetry():
    env = _env([0.0, 100.0], [[1500.0, 1500.0]], bathymetry_range_m=[0.0, 3000.0],
               bathymetry_depth_m=[100.0, 40.0], end_range_m=2500.0)
    tl = ram_tl_db(env, FREQ_HZ, DEPTHS, RANGES, _settings(env))
    assert np.all(np.isnan(tl[:, RANGES > 2500.0]))
    bottom = np.interp(RANGES, [0.0, 3000.0], [100.0, 40.0])
    wet = (DEPTHS[:, None] <= bottom[None, :] + 1e-6) & (RANGES <= 2500.0)[None, :]
    assert np.all(np.isfinite(tl[wet])) and np.all(np.isnan(tl[~wet]))


def test_irregular_ranges_are_interpolated_between_rams_own_steps():
    env = _env([0.0, 100.0], [[1500.0, 1500.0]])
    # a step that divides the 200 m spacing: both paths march with the same dr
    settings = dataclasses.replace(_settings(env), range_step_m=200.0 / 27.0)
    aligned = ram_tl_db(env, FREQ_HZ, DEPTHS[1:5], RANGES, settings)
    # one range nudged off the grid: RAM then writes every step and the envelope is
    # interpolated between the two steps around it; the other ranges are RAM's own steps
    nudged = RANGES.copy()
    nudged[3] += 0.3
    irregular = ram_tl_db(env, FREQ_HZ, DEPTHS[1:5], nudged, settings)
    others = np.arange(RANGES.size) != 3
    assert_allclose(irregular[:, others], aligned[:, others], rtol=0, atol=1e-6)
    # 0.3 m further at 100 Hz (a fiftieth of a wavelength) moves TL by well under a dB
    assert_allclose(irregular[:, 3], aligned[:, 3], rtol=0, atol=0.5)


def test_volume_absorption_adds_alpha_r():
    lossless = _env([0.0, 100.0], [[1500.0, 1500.0]])
    thorp = dataclasses.replace(lossless, absorption=Absorption.THORP)
    tl0 = ram_tl_db(lossless, FREQ_HZ, DEPTHS[1:5], RANGES, _settings(lossless))
    tl1 = ram_tl_db(thorp, FREQ_HZ, DEPTHS[1:5], RANGES, _settings(thorp))
    assert_allclose(tl1 - tl0, np.broadcast_to(thorp_db_per_km(FREQ_HZ) * RANGES / 1000.0, tl0.shape),
                    rtol=0, atol=1e-9)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"range_m": [0.0, 100.0]}, "range_m: values must be finite and > 0 m"),
    ({"depth_m": [-1.0]}, "depth_m: values must be finite and >= 0 m"),
    ({"depth_m": [[10.0]]}, "depth_m: need a 1-D array"),
    ({"freq_hz": 0.0}, "frequency must be > 0 Hz"),
])
def test_bad_receivers_are_refused(kwargs, match):
    env = _env([0.0, 100.0], [[1500.0, 1500.0]])
    args = {"freq_hz": FREQ_HZ, "depth_m": [10.0], "range_m": [100.0]} | kwargs
    with pytest.raises(RamInputError, match=match):
        ram_tl_db(env, args["freq_hz"], args["depth_m"], args["range_m"], _settings(env))


def test_a_grid_that_does_not_reach_below_the_bottom_is_refused():
    env = _env([0.0, 100.0], [[1500.0, 1500.0]])
    shallow = dataclasses.replace(_settings(env), grid_depth_m=150.0, absorbing_layer_m=100.0)
    with pytest.raises(RamInputError, match="grid_depth_m"):
        ram_tl_db(env, FREQ_HZ, [10.0], [100.0], shallow)


@pytest.mark.parametrize(("overrides", "match"), [
    ({"depth_step_m": 0.0}, "depth_step_m: must be > 0 m"),
    ({"absorbing_layer_m": 500.0}, "less than grid_depth_m"),
    ({"pade_terms": 0}, "pade_terms"),
    ({"stability_terms": 3}, "stability_terms"),
    ({"reference_speed_mps": 340.0}, "reference_speed_mps"),
])
def test_bad_settings_are_refused(overrides, match):
    base = dict(range_step_m=7.5, depth_step_m=0.75, grid_depth_m=400.0, absorbing_layer_m=300.0)
    with pytest.raises(RamInputError, match=match):
        RamSettings(**(base | overrides))


def test_the_default_settings_scale_with_the_wavelength():
    s = RamSettings.for_frequency(150.0, max_bottom_depth_m=1000.0)
    wavelength = 1500.0 / 150.0
    assert s.depth_step_m == pytest.approx(wavelength / 30.0)
    assert s.range_step_m == pytest.approx(wavelength / 2.0)
    assert s.grid_depth_m - s.absorbing_layer_m == pytest.approx(1000.0)
    flat = RamSettings.for_frequency(150.0, max_bottom_depth_m=1000.0, range_dependent=False)
    assert flat.range_step_m == pytest.approx(2.0 * wavelength)
    with pytest.raises(RamInputError, match="frequency"):
        RamSettings.for_frequency(-1.0, max_bottom_depth_m=1000.0)


def test_for_environment_takes_the_longer_range_step_only_without_range_dependence():
    flat = _env([0.0, 100.0], [[1500.0, 1500.0]])
    sloping = _env([0.0, 100.0], [[1500.0, 1500.0]], bathymetry_range_m=[0.0, 3000.0],
                   bathymetry_depth_m=[100.0, 40.0])
    changing = _env([0.0, 100.0], [[1500.0, 1500.0], [1490.0, 1500.0]], ranges=(0.0, 1000.0))
    assert not flat.is_range_dependent and sloping.is_range_dependent and changing.is_range_dependent
    assert RamSettings.for_environment(flat, 150.0).range_step_m == pytest.approx(20.0)
    assert RamSettings.for_environment(sloping, 150.0).range_step_m == pytest.approx(5.0)
    assert RamSettings.for_environment(changing, 150.0).range_step_m == pytest.approx(5.0)
