"""Sensitivity studies of a bearing-dependent area: members through the real BELLHOP along radials,
changes to the data the area reads (relief, water, front, month), summaries per bearing."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
import envdata
from acoustics import sensitivity as sens
from acoustics.sensitivity import perturb as pt
from acoustics.sensitivity.members import compute_member
from acoustics.sensitivity.perturbspec import PerturbationError, default_perturbations
from acoustics.sensitivity.spec import StudySpec
from envdata.fieldchange import FieldChange, ReliefChange, SmoothField, WaterChange
from tests.acoustics.sensitivity.conftest import specs
from tests.fixtures.layouts import write_woa
from tests.fixtures.sample_data import WOA_LAT_DEG, WOA_LON_DEG, woa_fields, write_monthly

pytestmark = pytest.mark.bellhop

SHELF_DATA = envdata.area_path("shelf-break").parent


def small_shelf(**water) -> envdata.Area:
    """The shelf-break area cut down: two radials (along the slope, seaward) to 8 km, one band,
    NPS and SW: a member is 2 BELLHOP runs."""
    doc = envdata.load_area("shelf-break").to_dict()
    doc["bearings"] = {"bearing_deg": [90.0, 180.0]}
    doc["grid"] = {**doc["grid"], "range_max_m": 8000.0, "range_step_m": 200.0, "depth_step_m": 20.0}
    doc["bands"] = doc["bands"][:1]
    doc["classes"] = doc["classes"][:2]
    if water:
        doc["water"] = {"bathymetry": doc["water"]["bathymetry"], **water}
    return envdata.parse_area(doc, "small-shelf", folder=SHELF_DATA)


def write_ts_with_sd(folder) -> tuple[str, str]:
    """The August T/S of the sample files with WOA's t_sd / s_sd beside them (0.4 degC, 0.05)."""
    depth, t, s = woa_fields([8])
    paths = []
    for kind, values, sd in (("t", t, 0.4), ("s", s, 0.05)):
        path = folder / f"ts-sd_{kind}.nc"
        write_woa(path, kind, [8], depth, WOA_LAT_DEG, WOA_LON_DEG, values, title="with sd",
                  sd_values=np.where(np.isfinite(values), sd, np.nan))
        paths.append(str(path))
    return paths[0], paths[1]


@pytest.fixture(scope="module")
def area() -> envdata.Area:
    return small_shelf()


def test_a_member_with_every_sd_zero_is_the_unperturbed_grid(area):
    grid = acoustics.build_grid(area, workers=2)
    zero = specs("relief:sd_m=0,sd_frac=0", "water:sd_c=0,sd_psu=0", "front:sd_km=0",
                 "bottom-speed:sd_mps=0", "observer-depth:sd_m=0")
    ds = sens.run_study(area, zero, members=2, seed=3, workers=2)
    assert ds["k_db"].dims == ("member", "class", "band", "bearing", "range")
    nominal = grid["k_db"].transpose("class", "band", "bearing", "range").values
    # the bound: within 0.01 dB wherever the grid has K (the same runs: bitwise here)
    for m in range(2):
        assert np.array_equal(np.isnan(ds["k_db"].values[m]), np.isnan(nominal))
        assert np.nanmax(np.abs(ds["k_db"].values[m] - nominal)) < 0.01
    assert np.nanmax(np.abs(ds["k_nominal_db"].values - nominal)) < 0.01


def test_a_perturbed_study_is_per_bearing_seeded_per_member_and_summarised(area, tmp_path):
    perturbations = specs("relief:sd_frac=0.1,corr_km=3", "water:sd_c=0.5,sd_psu=0.1", "front:sd_km=3",
                          "bottom-speed:sd_mps=30")
    ds = sens.run_study(area, perturbations, members=4, seed=5, workers=2, cache_dir=tmp_path / "cache")
    # member m depends only on (seed, m): computed alone, it is the study's member
    alone = compute_member(StudySpec(area=area, perturbations=tuple(perturbations), members=4, seed=5), 2)
    assert_allclose(alone.k_db, ds["k_db"].values[2], rtol=0, atol=1e-9, equal_nan=True)
    dk = ds["k_db"].values - ds["k_nominal_db"].values[None]
    assert np.nanmax(np.abs(dk)) > 0.5  # the perturbations move K
    summary = sens.summarize(sens.study_face(ds), eval_ranges_m=[2000.0, 5000.0])
    assert summary["k_rms_db"].dims == ("class", "band", "bearing", "range")
    assert_allclose(summary["k_rms_db"].values, np.sqrt(np.nanmean(dk ** 2, axis=0)), atol=1e-12)
    assert summary["range_rms_m"].dims == ("class", "bearing", "eval_range")
    assert summary["detection_range_sd_m"].dims == ("class", "band", "bearing")
    assert np.all(summary["k_error_sd_db"].values > 0)
    # the parameters are member coordinates with their units
    assert ds["front_north_km"].attrs["units"] == "km" and ds["relief_dz_origin_m"].attrs["units"] == "m"


def test_relief_change_keeps_land_and_sea_and_has_the_sd_asked():
    rng = np.random.default_rng(1)
    field = SmoothField.draw(rng, (3000.0, 3000.0))
    change = FieldChange(origin_lat_deg=43.0, origin_lon_deg=5.0,
                         relief=ReliefChange(field=field, sd_m=50.0))
    lat = np.linspace(42.7, 43.3, 120)
    lon = np.linspace(4.6, 5.4, 120)
    elevation = np.full((120, 120), -1000.0)
    elevation[:10] = 200.0           # land
    elevation[10:20] = np.nan        # no value (EMODnet's land)
    elevation[20:30] = -3.0          # shallow sea near the coast
    new = change.change_relief(lat, lon, elevation)
    assert np.all(new[:10] == 200.0) and np.all(np.isnan(new[10:20]))
    assert np.all(new[20:] <= -1.0)  # sea stays sea (at least 1 m of water)
    dz = (new - elevation)[30:]
    # a unit-variance field times 50 m: the spread over a 60 x 80 km box of 3 km correlation is
    # close to 50 m (64 random modes: within 25 %)
    assert 37.5 < dz.std() < 62.5
    # smooth: neighbours 0.5 km apart differ far less than the sd
    assert np.abs(np.diff(dz, axis=1)).mean() < 0.2 * dz.std()


def test_water_change_takes_the_files_own_sd_and_the_front_moves_the_water(tmp_path):
    t_path, s_path = write_ts_with_sd(tmp_path)
    area = small_shelf(temperature=t_path, salinity=s_path)
    assert pt.check_perturbations(area, specs("water:sd_factor=1")) is None  # the file has t_sd
    rng = np.random.default_rng(2)
    water = WaterChange(temperature_field=SmoothField.draw(rng, (2e4, 2e4, 200.0)),
                        salinity_field=SmoothField.draw(rng, (2e4, 2e4, 200.0)))
    with envdata.climatology.open_climatology(area.water.climatology) as clim:
        ts = clim.load_box(np.array([42.8, 43.2]), np.array([4.8, 5.2]))
    changed = FieldChange(origin_lat_deg=43.0, origin_lon_deg=5.0, water=water).change_water(ts)
    wet = np.isfinite(ts.temperature_c)
    dt = (changed.temperature_c - ts.temperature_c)[wet]
    ds = (changed.salinity_psu - ts.salinity_psu)[wet]
    # the file's sds, 0.4 degC and 0.05, scale unit-variance fields: at most 4 sd anywhere here
    assert 0 < np.abs(dt).max() < 4 * 0.4 and 0 < np.abs(ds).max() < 4 * 0.05
    assert 0.1 < dt.std() / 0.4 < 2.0
    # a front displaced 5 km north: the water at a point is what was 5 km south of it
    front = FieldChange(origin_lat_deg=43.0, origin_lon_deg=5.0, front_north_m=5000.0)
    lat, lon = front.water_positions(np.array([43.1]), np.array([5.0]))
    assert_allclose((43.1 - lat) * 111_132.0, 5000.0, rtol=1e-9)
    assert_allclose(lon, 5.0)
    # a what-if member: no draw, the displacement given
    _, change, params = pt.member_environment(area, specs("front:north_km=5"), 0, 0)
    assert change.front_north_m == 5000.0 and change.front_east_m == 0.0
    assert params == {"front_east_km": 0.0, "front_north_km": 5.0}


def test_month_kind_mixes_a_neighbouring_month_of_a_12_month_file(tmp_path):
    t_path, s_path = write_monthly(tmp_path)
    area = small_shelf(temperature=str(t_path), salinity=str(s_path), month=8)
    spec = specs("month:offset_months=0.5")
    pt.check_perturbations(area, spec)
    _, change, params = pt.member_environment(area, spec, 0, 0)
    assert (change.other_month, change.month_weight, params["month_offset"]) == (9, 0.5, 0.5)
    nominal = envdata.area_radials(area)[1]
    mixed = envdata.area_radials(area, change=change)[1]
    september = envdata.area_radials(small_shelf(temperature=str(t_path), salinity=str(s_path), month=9))[1]
    # sound speed is nearly linear in T over a month's change: halfway within 0.05 m/s
    halfway = 0.5 * (nominal.speed_mps + september.speed_mps)
    assert np.abs(mixed.speed_mps - halfway).max() < 0.05
    assert np.abs(september.speed_mps - nominal.speed_mps).max() > 1.0


def test_kinds_an_area_cannot_take_are_refused_before_anything_runs(area, tiny_area):
    with pytest.raises(PerturbationError, match="changes one profile over a flat bottom"):
        pt.check_perturbations(area, specs("displace:sd_m=10"))
    with pytest.raises(PerturbationError, match="changes the data of an area with \\[origin\\]"):
        pt.check_perturbations(tiny_area, specs("relief:sd_m=10"))
    # the sample climatology has no t_sd: the water kind needs given sds
    with pytest.raises(PerturbationError, match="no standard deviations .* give sd_c and sd_psu"):
        pt.check_perturbations(area, specs("water:sd_factor=1"))
    with pytest.raises(PerturbationError, match="holds one month"):
        pt.check_perturbations(area, specs("month:sd_months=0.2"))
    with pytest.raises(PerturbationError, match="sd_months must be <= 0.25"):
        specs("month:sd_months=1")
    # the defaults of an area with data never fail
    defaults = default_perturbations(area)
    assert {p.kind.value for p in defaults} >= {"relief", "water", "bottom-speed"}
    pt.check_perturbations(area, defaults)
