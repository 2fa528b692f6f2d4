"""Perturbation specs: parsing, checking at +-4 sd, and the perturbed areas they make."""

from __future__ import annotations

import dataclasses
import math

import gsw
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from acoustics.sensitivity import perturb as pt
from acoustics.sensitivity import perturbspec as ps
from acoustics.sensitivity.perturbspec import PerturbationError
from tests.conftest import DATA, MALFORMED

BAD = MALFORMED / "perturb"


def test_inline_spec_parses_keys_defaults_and_numbers():
    [p] = ps.parse_spec("temperature:sd_c=0.5")
    assert p.kind is ps.Kind.TEMPERATURE and p.sd == 0.5 and p.option("scale_m") == 200.0
    [p] = ps.parse_spec(" eof:sd_mps=1.5,modes=2,depth_m=800 ")
    assert (p.sd, p.option("modes"), p.option("depth_m"), p.n_draws) == (1.5, 2.0, 800.0, 2)
    assert p.param_names() == ["eof_a1_mps", "eof_a2_mps"]
    assert ps.parse_spec(p.describe()) == [dataclasses.replace(p, source=f"perturbation {p.describe()}")]


def test_file_spec_reads_every_table(tiny_area):
    specs = ps.parse_spec(str(DATA / "perturb" / "tiny-study.toml"))
    assert [p.kind.value for p in specs] == ["displace", "temperature", "bottom-speed", "source-depth"]
    assert specs[1].option("scale_m") == 300.0
    pt.check_perturbations(tiny_area, specs)


@pytest.mark.parametrize("text, match", [
    ("displace", r"perturbation displace: expected KIND:KEY=VALUE"),
    ("displace:", r"expected KIND:KEY=VALUE"),
    ("displace:sd_m", r"expected KEY=VALUE, got 'sd_m'"),
    ("displace:sd_m=1,sd_m=2", r"key 'sd_m' given twice"),
    ("thermocline:sd_m=1", r"unknown perturbation kind 'thermocline'"),
    ("displace:sd_c=1", r"perturbation displace: unknown key 'sd_c' \(keys: sd_m\)"),
    ("displace:sd_m=ten", r"perturbation displace: sd_m must be a number, got 'ten'"),
    ("displace:sd_m=-1", r"perturbation displace: sd_m must be a finite number >= 0, got -1.0"),
    ("displace:sd_m=nan", r"sd_m must be a finite number >= 0, got nan"),
    ("temperature:sd_c=1,scale_m=0", r"scale_m must be > 0 m, got 0"),
    ("mixed-layer:sd_m=1,mean_m=-5", r"mean_m must be >= 0 m, got -5"),
    ("eof:sd_mps=1,modes=0", r"modes must be an integer in \[1, 10\], got 0"),
    ("bottom-speed:scale_m=1", r"perturbation bottom-speed: unknown key 'scale_m'"),
])
def test_malformed_inline_specs_name_the_spec_key_and_value(text, match):
    with pytest.raises(PerturbationError, match=match):
        ps.parse_spec(text)


@pytest.mark.parametrize("name, match", [
    ("negative-sd.toml", r"negative-sd.toml: \[\[perturb\]\] #1: perturbation displace: sd_m must be a finite "
                         r"number >= 0, got -5.0"),
    ("unknown-kind.toml", r"unknown-kind.toml: \[\[perturb\]\] #1: unknown perturbation kind 'thermoclyne'"),
    ("unknown-key.toml", r"unknown-key.toml: \[\[perturb\]\] #1: perturbation bottom-speed: unknown key 'sd_m'"),
    ("missing-sd.toml", r"missing-sd.toml: \[\[perturb\]\] #1: perturbation temperature: missing required key "
                        r"'sd_c'"),
    ("sd-string.toml", r"sd-string.toml: \[\[perturb\]\] #1: perturbation bottom-density: sd_gcc must be a "
                       r"number, got 'a lot'"),
    ("missing-kind.toml", r"missing-kind.toml: \[\[perturb\]\] #1: missing or non-string 'kind', got None"),
    ("no-tables.toml", r"no-tables.toml: unknown top-level key 'title'"),
    ("syntax-error.toml", r"syntax-error.toml: TOML syntax error"),
    ("empty.toml", r"empty.toml: empty perturbation file"),
    ("binary.toml", r"binary.toml: binary file, not a TOML perturbation file"),
    ("eof-modes.toml", r"eof-modes.toml: \[\[perturb\]\] #1: perturbation eof: modes must be an integer"),
])
def test_malformed_spec_files_name_file_table_key_and_value(name, match):
    with pytest.raises(PerturbationError, match=match):
        ps.parse_spec(str(BAD / name))


@pytest.mark.parametrize("name, match", [
    ("nonpositive-speed.toml", r"perturbation bottom-speed:sd_mps=20000: only \d+ % of its draws within \+-4 sd "
                               r"give a valid area \(need 25 %\); lower the sd \(at -0.0\d sd: \[bottom\] speed_mps"),
    ("water-speed-nonpositive.toml", r"perturbation eof:sd_mps=500,modes=2,depth_m=1000: only \d+ % .*makes the "
                                     r"speed \d+\.\d m/s at 0 m, outside \[1400, 1650\] m/s"),
    ("nonmonotonic.toml", r"perturbation displace:sd_m=2000: only \d+ % .*a displacement of [-\d.]+ m in 1000 m "
                          r"of water makes the profile non-monotonic in depth"),
    ("duplicate-kind.toml", r"duplicate-kind.toml: \[\[perturb\]\] #2: perturbation displace given twice"),
])
def test_specs_that_truncation_would_swallow_are_rejected(tiny_area, name, match):
    specs = ps.parse_spec(str(BAD / name))
    with pytest.raises(PerturbationError, match=match):
        pt.check_perturbations(tiny_area, specs)


def test_unphysical_temperature_and_source_depth_are_rejected(tiny_area):
    with pytest.raises(PerturbationError, match=r"temperature:sd_c=200,scale_m=200: only \d+ % .*temperature "
                                                r"-?\d+\.\d+ degC at \d+ m is outside"):
        pt.check_perturbations(tiny_area, ps.parse_spec("temperature:sd_c=200"))
    with pytest.raises(PerturbationError, match=r"source-depth:sd_frac=30: only \d+ % .*makes the class depths "
                                                r"non-positive"):
        pt.check_perturbations(tiny_area, ps.parse_spec("source-depth:sd_frac=30"))


def test_draws_are_truncated_at_the_physical_range_and_plain_normal_elsewhere(tiny_area):
    # sd 250 m of water depth: a plain normal would put the bottom above the 150 m class below
    # -3.4 sd; sd 0.5 dB/wavelength on the 0.8 dB/wavelength bottom: negative below -1.6 sd
    specs = [*ps.parse_spec(str(DATA / "perturb" / "wide-water-depth.toml")),
             *ps.parse_spec("bottom-attenuation:sd_db_per_wavelength=0.5")]
    pt.check_perturbations(tiny_area, specs)
    depth, att, xis = [], [], []
    for member in range(2000):
        rng = np.random.default_rng([9, member])
        first = pt.draw(specs, rng)
        area, params = pt.member_area(tiny_area, specs, 9, member)
        depth.append(params["water_depth_m"])
        att.append(params["bottom_attenuation_db_per_wavelength"])
        xis.append([float(x[0]) for x in first])
    depth, att, xis = np.array(depth), np.array(att), np.array(xis)
    assert depth.min() > 150.0 and att.min() >= 0.0
    # a member whose first draws are valid keeps them: the plain normal draws
    plain = xis[:, 1] > -1.6
    assert_allclose(att[plain], 0.8 + 0.5 * xis[plain, 1], atol=1e-9)
    # about Phi(-1.6) = 5.5 % of the members are redrawn
    assert 0.035 < 1.0 - plain.mean() < 0.075
    assert not np.allclose(att[~plain], 0.8 + 0.5 * xis[~plain, 1])


def _variant(doc_changes):
    import json

    import envdata

    doc = envdata.load_area(DATA / "tiny-munk.toml").to_dict()
    doc_changes(doc)
    return envdata.area_from_json(json.dumps(doc))


def _sandy(doc):
    doc["bottom"]["attenuation_db_per_wavelength"] = 0.5


def _lossless(doc):
    doc["bottom"]["attenuation_db_per_wavelength"] = 0.0


def _soft(doc):
    doc["bottom"].update(speed_mps=1000.0, density_gcc=1.0)


def _near_surface_observer(doc):
    doc["observer"]["depth_m"] = 1.0


def _near_bottom_classes(doc):
    for c in doc["classes"]:
        c["depth_m"] = 995.0


def _shallow_cold(doc):
    # 40 m of near-freezing water (1440 m/s), observer at 2 m, classes at 38 and 5 m
    doc["water"] = {"depth_m": 40.0, "ssp_depth_m": [0.0, 40.0], "ssp_speed_mps": [1440.0, 1441.0]}
    doc["observer"]["depth_m"] = 2.0
    doc["classes"][0]["depth_m"], doc["classes"][1]["depth_m"] = 38.0, 5.0
    doc["grid"]["depth_step_m"] = 5.0


@pytest.mark.parametrize("change", [_sandy, _lossless, _soft, _near_surface_observer, _near_bottom_classes,
                                    _shallow_cold])
def test_default_perturbations_work_on_valid_areas_near_their_limits(change):
    area = _variant(change)
    specs = ps.default_perturbations(area)
    pt.check_perturbations(area, specs)
    for member in range(30):
        member_area, _ = pt.member_area(area, specs, 11, member)
        assert 0.0 < member_area.observer.depth_m < member_area.water.depth_m


def test_members_are_reproducible_and_independent_of_order_of_computation(tiny_area):
    specs = ps.default_perturbations(tiny_area)
    a3, p3 = pt.member_area(tiny_area, specs, 7, 3)
    pt.member_area(tiny_area, specs, 7, 0)
    b3, q3 = pt.member_area(tiny_area, specs, 7, 3)
    assert a3 == b3 and p3 == q3
    _, p4 = pt.member_area(tiny_area, specs, 7, 4)
    assert p3 != p4
    assert set(p3) == {n for p in specs for n in p.param_names()}
    assert a3.bottom.speed_mps == p3["bottom_speed_mps"]
    assert a3.water.depth_m == p3["water_depth_m"] == a3.water.ssp.bottom_m
    assert a3.observer.depth_m == p3["observer_depth_m"]
    assert [c.depth_m for c in a3.classes] == pytest.approx(
        [c.depth_m * p3["source_depth_factor"] for c in tiny_area.classes], rel=1e-12)


def test_zero_sd_leaves_the_area_unchanged_except_resampling(tiny_area):
    specs = [p for s in ("bottom-speed:sd_mps=0", "observer-depth:sd_m=0", "displace:sd_m=0") for p in ps.parse_spec(s)]
    area, params = pt.perturb_area(tiny_area, specs, np.random.default_rng(1))
    assert area.bottom == tiny_area.bottom and area.observer == tiny_area.observer
    z = np.asarray(area.water.ssp.depth_m)
    assert_allclose(area.water.ssp.speed_mps, tiny_area.water.ssp.speed_at(z), atol=5e-4)  # rounding to 1 mm/s
    assert params == {"bottom_speed_mps": 1600.0, "observer_depth_m": 100.0, "displace_dz_m": 0.0}


def test_draws_are_truncated_at_4_sd():
    [p] = ps.parse_spec("eof:sd_mps=1,modes=10")
    xi = np.concatenate([pt.draw([p], np.random.default_rng([3, m]))[0] for m in range(3000)])
    assert np.abs(xi).max() <= pt.TRUNCATE_SD
    assert abs(xi.std() - 1.0) < 0.03  # 30000 draws: sd of the sample sd ~ 0.004; truncation at 4 removes 0.06 %


def test_displacement_moves_the_profile_by_the_mode_1_shape(tiny_area):
    [p] = ps.parse_spec("displace:sd_m=10")
    area, values = pt._apply_one(tiny_area, p, np.array([2.0]))
    d = values["displace_dz_m"]
    assert d == 20.0
    ssp0, ssp1 = tiny_area.water.ssp, area.water.ssp
    # c'(z) = c(z - d sin(pi z / D)): at mid-depth the whole 20 m shift, none at surface and bottom
    assert_allclose(ssp1.speed_at(500.0), ssp0.speed_at(480.0), atol=1e-3)
    assert_allclose(ssp1.speed_at(0.0), ssp0.speed_at(0.0), atol=1e-3)
    assert_allclose(ssp1.speed_at(1000.0), ssp0.speed_at(1000.0), atol=1e-3)


def test_mixed_layer_is_isothermal_with_the_pressure_gradient(tiny_area):
    [p] = ps.parse_spec("mixed-layer:sd_m=10,mean_m=60")
    area, values = pt._apply_one(tiny_area, p, np.array([1.0]))
    h = values["mixed_layer_depth_m"]
    assert h == 70.0
    ssp0, ssp1 = tiny_area.water.ssp, area.water.ssp
    assert_allclose(ssp1.speed_at(h), ssp0.speed_at(h), atol=1e-3)
    # 0.0163 /s: the speed gradient of isothermal sea water from pressure alone
    assert_allclose(ssp1.speed_at(h) - ssp1.speed_at(0.0), 0.0163 * h, atol=2e-3)
    assert_allclose(ssp1.speed_at(500.0), ssp0.speed_at(500.0), atol=1e-3)


def test_temperature_change_is_converted_with_teos10(tiny_area):
    [p] = ps.parse_spec("temperature:sd_c=1,scale_m=100000")
    area, _ = pt._apply_one(tiny_area, p, np.array([1.0]))
    z = np.array([0.0, 500.0])
    dc = area.water.ssp.speed_at(z) - tiny_area.water.ssp.speed_at(z)
    # independent check: invert TEOS-10 for t at S = 35 with a bracketing search, add 1 degC
    lat, lon = tiny_area.latitude_deg, tiny_area.longitude_deg
    for zi, dci in zip(z, dc):
        p_dbar = gsw.p_from_z(-zi, lat)
        sa = gsw.SA_from_SP(35.0, p_dbar, lon, lat)
        c0 = tiny_area.water.ssp.speed_at(zi)
        lo, hi = -2.0, 40.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if gsw.sound_speed(sa, gsw.CT_from_t(sa, mid, p_dbar), p_dbar) < c0 else (lo, mid)
        t = 0.5 * (lo + hi)
        dt = math.exp(-zi / 100000.0)  # the spec's shape, dT exp(-z / scale_m)
        expect = (gsw.sound_speed(sa, gsw.CT_from_t(sa, t + dt, p_dbar), p_dbar)
                  - gsw.sound_speed(sa, gsw.CT_from_t(sa, t, p_dbar), p_dbar))
        assert_allclose(dci, expect, atol=2e-3)  # profile speeds are rounded to 1 mm/s
        # and Medwin's simple formula, c(T) = 1449.2 + 4.6 T - 0.055 T^2 + 0.00029 T^3 (+ S, z terms
        # that cancel), gives the same step within 0.1 m/s (its fit error is ~0.2 m/s in c itself)

        def medwin(temp):
            return 1449.2 + 4.6 * temp - 0.055 * temp ** 2 + 0.00029 * temp ** 3

        assert_allclose(dci, medwin(t + dt) - medwin(t), atol=0.1)


def test_water_depth_cuts_or_extends_the_profile(tiny_area):
    [p] = ps.parse_spec("water-depth:sd_m=20")
    deeper, v = pt._apply_one(tiny_area, p, np.array([2.0]))
    assert v["water_depth_m"] == 1040.0 and deeper.water.ssp.bottom_m == 1040.0
    z, c = tiny_area.water.ssp.depth_m, tiny_area.water.ssp.speed_mps
    gradient = (c[-1] - c[-2]) / (z[-1] - z[-2])
    assert_allclose(deeper.water.ssp.speed_mps[-1], c[-1] + 40.0 * gradient, atol=1e-3)
    shallower, v = pt._apply_one(tiny_area, p, np.array([-1.5]))
    assert shallower.water.depth_m == 970.0 == shallower.water.ssp.bottom_m
    assert_allclose(shallower.water.ssp.speed_at(970.0), tiny_area.water.ssp.speed_at(970.0), atol=1e-3)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2 ** 32), member=st.integers(0, 10_000),
       sd=st.floats(0.0, 1.0), mixed=st.floats(0.0, 200.0))
def test_specs_that_pass_the_check_always_give_valid_members(tiny_area, seed, member, sd, mixed):
    specs = [p for s in (f"displace:sd_m={50 * sd}", f"mixed-layer:sd_m={20 * sd},mean_m={mixed}",
                         f"eof:sd_mps={2 * sd},modes=3,depth_m=600", f"salinity:sd_psu={0.2 * sd}",
                         f"bottom-attenuation:sd_db_per_wavelength={0.2 * sd}",
                         f"source-depth:sd_frac={0.2 * sd}", f"observer-depth:sd_m={20 * sd}")
             for p in ps.parse_spec(s)]
    pt.check_perturbations(tiny_area, specs)
    area, params = pt.member_area(tiny_area, specs, seed, member)
    z = np.asarray(area.water.ssp.depth_m)
    assert np.all(np.diff(z) > 0) and z[-1] == area.water.depth_m
    assert all(math.isfinite(v) for v in params.values())
