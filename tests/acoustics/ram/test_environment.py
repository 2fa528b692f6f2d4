"""RamEnvironment: from a flat area, from a radial, and the input it refuses."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from acoustics.ram import RamEnvironment, RamInputError
from bench.crosscheck.ram_cases import wedge_area, wedge_radial
from envdata.bottom import Bottom


def test_from_area_takes_the_flat_areas_depth_profile_bottom_and_absorption():
    area = envdata.load_area("munk-1000")
    env = RamEnvironment.from_area(area, 5.0)
    assert env.bathymetry_range_m.tolist() == [0.0]
    assert env.bathymetry_depth_m.tolist() == [area.water.depth_m]
    assert env.speed_mps.shape == (1, len(area.water.ssp.depth_m))  # (range, depth)
    assert_allclose(env.speed_mps[0], area.water.ssp.speed_mps)
    assert env.bottom == area.bottom
    assert env.absorption is area.propagation.absorption
    assert env.end_range_m is None
    with pytest.raises(ValueError):  # frozen all the way down
        env.speed_mps[0, 0] = 1400.0


def test_from_radial_keeps_the_part_ahead_of_the_origin_and_turns_the_section():
    radial = wedge_radial()
    env = RamEnvironment.from_radial(wedge_area(), radial, 100.0)
    assert env.bathymetry_range_m[0] == 0.0 and np.all(env.bathymetry_range_m >= 0.0)
    assert env.bathymetry_depth_m[0] == pytest.approx(200.0)
    assert env.bathymetry_depth_m[-1] == pytest.approx(1.0)  # the radials' shore depth
    assert env.end_range_m == 4000.0  # land ends the radial
    # Radial.speed_mps is (depth, range); the environment's is (range, depth)
    assert env.speed_mps.shape == (env.ssp_range_m.size, radial.ssp_depth_m.size)
    assert env.absorption is envdata.Absorption.NONE


def test_from_radial_interpolates_the_origin_and_turns_a_square_section_the_right_way():
    # a square section (3 depths x 3 ranges) whose speed grows with depth only: transposed by
    # mistake it would grow with range instead
    base = wedge_radial()
    z = np.array([0.0, 100.0, 200.0])
    rp = np.array([-1000.0, 1000.0, 4000.0])
    section = np.array([[1480.0, 1480.0, 1480.0], [1500.0, 1500.0, 1500.0], [1520.0, 1520.0, 1520.0]])
    radial = dataclasses.replace(base, ssp_range_m=rp, ssp_depth_m=z, speed_mps=section)
    env = RamEnvironment.from_radial(wedge_area(), radial, 100.0)
    assert env.ssp_range_m.tolist() == [0.0, 1000.0, 4000.0]
    for row in env.speed_mps:
        assert_allclose(row, [1480.0, 1500.0, 1520.0])
    assert_allclose(env.speed_at_mps(500.0), [1480.0, 1500.0, 1520.0])


def _flat(**overrides) -> RamEnvironment:
    kwargs = dict(bathymetry_range_m=[0.0], bathymetry_depth_m=[100.0], ssp_range_m=[0.0],
                  ssp_depth_m=[0.0, 100.0], speed_mps=[[1500.0, 1500.0]],
                  bottom=Bottom(speed_mps=1800.0, density_gcc=1.8), source_depth_m=36.0)
    kwargs.update(overrides)
    return RamEnvironment(**kwargs)


@pytest.mark.parametrize(("overrides", "match"), [
    ({"source_depth_m": 120.0}, "source_depth_m"),
    ({"source_depth_m": 0.0}, "source_depth_m"),
    ({"speed_mps": [[1500.0], [1500.0]]}, r"shape \(2, 1\) is not \(range points, depth points\) = \(1, 2\)"),
    ({"ssp_depth_m": [0.0, 50.0], "speed_mps": [[1500.0, 1500.0]]}, "above the deepest bottom"),
    ({"bathymetry_range_m": [5.0]}, "increasing strictly from 0 m"),
    ({"bathymetry_depth_m": [np.nan]}, "finite"),
    ({"speed_mps": [[1500.0, 2500.0]]}, "speeds must be in"),
    ({"bottom": Bottom(speed_mps=1800.0, density_gcc=1.8, shear_speed_mps=400.0)}, "shear"),
    ({"end_range_m": -1.0}, "end_range_m"),
])
def test_bad_environments_are_refused_with_the_field_named(overrides, match):
    with pytest.raises(RamInputError, match=match):
        _flat(**overrides)


def test_an_area_with_bathymetry_must_go_through_its_radials():
    area = envdata.load_area("shelf-break")
    with pytest.raises(RamInputError, match="from_radial"):
        RamEnvironment.from_area(area, 100.0)
