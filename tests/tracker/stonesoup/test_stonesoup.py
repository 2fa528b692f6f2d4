"""tmakit's tables inside Stone Soup (tools/stonesoup/, the real Stone Soup of the ``stonesoup``
extra): the measurement model against Stone Soup's own Gaussian likelihood and tmakit's level
model, the detection probability against tmakit's detection map, the converters both ways, and
Stone Soup's particle filter with tmakit's model beside ``tmakit track --method rpf``."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

# the real Stone Soup, of the stonesoup extra (make test installs it), and tmakit as its plugin
from stonesoup.models.measurement.nonlinear import NonLinearGaussianMeasurement
from stonesoup.plugins.tmakit import (
    DetectionProbability,
    TablesBernoulliParticleUpdater,
    TablesMeasurementModel,
    detections_from_measurements,
    observer_lookup,
    track_frame,
    track_from_frame,
)
from stonesoup.types.detection import Detection
from stonesoup.types.state import ParticleState, State, StateVector, StateVectors

import acoustics
import envdata
from acoustics.grid.detectionmap import class_terms, detection_map
from tests.tools.simulated import simulate_on_tiny_grid
from tracker.measurements import read_measurements
from tracker.trackfile import read_track, write_track

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def tables(tiny_grid_file):
    return acoustics.open_tables(tiny_grid_file)


def _model(tables, cls_name, bands=(0, 1), obs=(300.0, -200.0)):
    return TablesMeasurementModel(tables=tables, class_index=tables.class_index(cls_name), band_index=bands,
                                  observer_x_m=obs[0], observer_y_m=obs[1], observer_depth_m=tables.observer_depth_m,
                                  bearing_sd_rad=math.radians(1.5), level_sd_db=3.0)


def _states(obs, ranges, bearings_deg, speed=2.0, course_deg=30.0):
    b = np.radians(bearings_deg)
    c = math.radians(course_deg)
    n = np.broadcast(ranges, b).size
    return StateVectors(np.vstack([obs[0] + ranges * np.sin(b), np.full(n, speed * math.sin(c)),
                                   obs[1] + ranges * np.cos(b), np.full(n, speed * math.cos(c))]))


@pytest.mark.parametrize("cls_index", [0, 1])
def test_the_models_levels_are_the_trackers_level_model(tables, cls_index):
    # W = P0 + K + H, K from the face's level profile (what tmakit's filters read), P0 the class's
    # (Ross at the state's speed for a Ross class); the bearing clockwise from north
    from tracker.rpf import bearing_rad

    cls = tables.classes[cls_index]
    model = _model(tables, cls.name)
    obs = (model.observer_x_m, model.observer_y_m)
    r = np.linspace(500.0, 0.9 * tables.range_m[-1], 9)
    sv = _states(obs, r, np.linspace(10.0, 350.0, 9))
    z = np.asarray(model.function(State(sv)))
    assert_allclose(z[0], bearing_rad(sv[0] - obs[0], sv[2] - obs[1]), atol=1e-12)
    for j, ib in enumerate(model.band_index):
        profile = tables.level_profile(cls_index, ib, tables.observer_depth_m)
        p0 = (envdata.ross_source_level_db(np.hypot(sv[1], sv[3])) if cls.source_level_model.value == "ross"
              else cls.noise_mean_db)
        assert_allclose(z[1 + j], p0 + profile(r) + tables.area.sonar.receiver_gain_db, atol=1e-9)


def test_the_vectorised_likelihood_is_stone_soups_gaussian(tables):
    # on a grid without a measured K-error map the noise is the constant covariance, so the
    # particles' log likelihood at once equals Stone Soup's own (its NonLinearGaussianMeasurement
    # evaluates function() and covar() per state, with the plain bearing residual)
    assert not tables.has_k_error_map
    model = _model(tables, tables.classes[0].name)
    obs = (model.observer_x_m, model.observer_y_m)
    sv = _states(obs, np.linspace(800.0, 4000.0, 7), np.linspace(40.0, 160.0, 7))
    truth = State(StateVector(np.asarray(sv)[:, 3]))
    det = Detection(model.function(truth, noise=True), measurement_model=model)
    ours = model.logpdf(det, ParticleState(sv, log_weight=np.zeros(7)))
    theirs = [NonLinearGaussianMeasurement.logpdf(model, det, State(StateVector(np.asarray(sv)[:, i])))
              for i in range(7)]
    assert_allclose(ours, theirs, rtol=1e-10, atol=1e-9)
    assert np.argmax(ours) == 3
    # across north the bearing residual is wrapped: 359.5 deg measured, a state at 0.5 deg is
    # 1 deg off, not 359
    near = _states(obs, np.array([2000.0]), np.array([0.5]))
    z = np.asarray(model.function(State(StateVector(np.asarray(near)[:, 0])))).ravel()
    z[0] = math.radians(359.5)
    ll = model.logpdf(Detection(StateVector(z), measurement_model=model), State(StateVector(np.asarray(near)[:, 0])))
    # the levels exact: their term is the normal's at zero with the bands' covariance (one level model)
    levels = np.asarray(model.covar())[1:, 1:]
    assert ll == pytest.approx(-0.5 * (1.0 / 1.5) ** 2 - 0.5 * math.log(2 * math.pi * math.radians(1.5) ** 2)
                               - 0.5 * math.log(np.linalg.det(2 * math.pi * levels)), abs=1e-6)
    # the bands' errors are correlated: the offset common to them (the class's K error and P0)
    assert levels.shape == (1, 1) or levels[0, 1] > 0.5 * math.sqrt(levels[0, 0] * levels[1, 1])


def test_the_detection_probability_is_the_detection_maps_rule(tables):
    # the tiny grid has a class with both sides of the detection edge in its range
    edges = [_detection_matches_the_map(tables, i) for i in range(len(tables.classes))]
    assert any(edges)


def _detection_matches_the_map(tables, cls_index) -> bool:
    # at every range of the grid: with no level scatter P_band is the detection map's step (0 or 1
    # where acoustics.detection's rule says), and with the class's sds P_band >= 1/2 exactly where
    # it detects; at the map's farthest range the class is detected, beyond it no band is
    cls = tables.classes[cls_index]
    terms = class_terms(tables, cls.name)
    obs = (0.0, 0.0)
    r = tables.range_m[1:]
    bearing = 75.0
    sv = _states(obs, r, np.full(r.size, bearing), speed=cls.speed_mean_mps)
    k = np.asarray(tables.k_db(tables.observer_depth_m, None)[cls_index])[:, 1:]
    detected = terms.detected(k)                                                  # (M, R)
    step = DetectionProbability(tables, cls_index, level_sd_db=0.0).band_probabilities(
        sv, *obs, tables.observer_depth_m)
    assert_allclose(step, detected.astype(float))
    smooth = DetectionProbability(tables, cls_index).band_probabilities(sv, *obs, tables.observer_depth_m)
    assert np.array_equal(smooth >= 0.5, detected)
    assert np.any((smooth > 0.01) & (smooth < 0.99)) or detected.all()  # not itself a step
    dm = detection_map(tables, cls.name, [bearing])
    pd = DetectionProbability(tables, cls_index)(sv, *obs, tables.observer_depth_m)
    if np.isfinite(dm.range_m[0]):
        i = int(np.flatnonzero(r == dm.range_m[0])[0])
        assert pd[i] >= 0.5 and np.all(np.max(smooth[:, i + 1:], axis=0, initial=0.0) < 0.5)
    return bool(detected.any() and not detected.all())


def test_the_bernoulli_updater_asks_the_tables_where_the_observer_is(tables):
    pd = DetectionProbability(tables, 0)
    sv = _states((1000.0, 500.0), np.array([900.0, 2500.0, 6000.0]), np.array([10.0, 100.0, 200.0]))
    updater = TablesBernoulliParticleUpdater(measurement_model=None, detection=pd,
                                             observer_at=lambda when: (1000.0, 500.0, tables.observer_depth_m))
    prediction = ParticleState(sv, log_weight=np.log(np.full(3, 1 / 3)))
    assert_allclose(np.exp(updater.get_log_detection_probability(prediction)),
                    pd(sv, 1000.0, 500.0, tables.observer_depth_m), rtol=1e-12)


@pytest.fixture(scope="module")
def simulated(tiny_grid_file, tmp_path_factory):
    return simulate_on_tiny_grid(tiny_grid_file, tmp_path_factory.mktemp("stonesoup"))


def test_a_measurement_file_becomes_detections_and_a_track_comes_back(tables, simulated, tmp_path):
    from tracker.trackplot import track_figure

    folder, cls_name = simulated
    m = read_measurements(folder / "measurements.csv", list(tables.band_names))
    cycles = detections_from_measurements(m, tables, cls_name, bearing_sd_deg=1.5, level_sd_db=2.0)
    assert len(cycles) == len(m)
    at = observer_lookup(m)
    for k, (when, dets) in enumerate(cycles):
        assert at(when) == (m.obs_x_m[k], m.obs_y_m[k], m.obs_depth_m[k])
        if not np.isfinite(m.bearing_deg[k]):
            assert dets == set()
            continue
        (det,) = dets
        present = np.isfinite(m.level_db[k])
        assert_allclose(np.asarray(det.state_vector).ravel(),
                        [math.radians(m.bearing_deg[k]), *m.level_db[k][present]])
        assert det.measurement_model.ndim_meas == 1 + present.sum()
        assert det.metadata["obs_x_m"] == m.obs_x_m[k] and det.metadata["t_s"] == m.t_s[k]
    # a Stone Soup track (here: each cycle's particles about the truth) as tmakit's track CSV,
    # read by tmakit's reader and drawn by `tmakit track --plot`'s figure
    import pandas as pd

    truth = pd.read_csv(folder / "truth.csv")
    rng = np.random.default_rng(4)
    states = []
    for k, (when, _) in enumerate(cycles):
        row = truth.iloc[k]
        c = math.radians(row.course_deg)
        mean = np.array([row.x_m, row.speed_mps * math.sin(c), row.y_m, row.speed_mps * math.cos(c)])
        pts = mean[:, None] + rng.normal(0.0, [[50.0], [0.2], [50.0], [0.2]], (4, 400))
        states.append(ParticleState(StateVectors(pts), log_weight=np.full(400, -math.log(400)), timestamp=when))
    df = track_frame(states, m, cls_name)
    path = tmp_path / "ss-track.csv"
    write_track(path, df)
    back = read_track(path)
    assert_allclose(back["x_m"], truth["x_m"][: len(back)], atol=25.0)   # 400 particles of sd 50 m: 4 sd
    assert_allclose(back["range_sd_m"], 50.0, rtol=0.2)
    track_figure(back, m, tables)
    # and back to Stone Soup: a track of Gaussian states at the same times and positions
    ss = track_from_frame(back, cls_name)
    assert len(ss) == len(back)
    assert_allclose([s.state_vector[0, 0] for s in ss], back["x_m"])
    assert_allclose([s.covar[0, 0] for s in ss], back["range_sd_m"] ** 2)
    with pytest.raises(ValueError, match="track has no rows of class 'nope'"):
        track_from_frame(back, "nope")


#: The Stone Soup comparison's particle multiple and bound (issue 28: Stone Soup's median final
#: position error within 2x tmakit's): Stone Soup needs more particles than tmakit's filter for the
#: same error, and is given MULTIPLE x tmakit's PARTICLES here; the benchmark's file, made with the
#: same N and multiple, must support it (`test_the_particle_multiple_rests_on_the_result_file`).
PARTICLES, MULTIPLE, BOUND = 2000, 8, 2.0
RESULT = Path(__file__).resolve().parents[3] / "docs" / "results" / "stonesoup.json"


def _ratios_at(accuracy: dict, multiple: int) -> list[float]:
    """Each seed's Stone Soup over tmakit median final error at ``multiple`` x tmakit's particles."""
    return [math.inf if x["over_rpf"] is None else x["over_rpf"]  # None: half its runs collapsed
            for summ in accuracy["by_seed"].values() for x in summ["stonesoup"] if x["multiple"] == multiple]


def test_a_collapsed_stone_soup_run_counts_as_its_worst():
    # the summary's medians: a run whose cloud collapsed (no final error) ranks above every error,
    # and once half the runs collapsed there is no median to state
    from bench.bench_stonesoup import summary

    def rows(errors):
        return [{"rpf_final_error_m": 100.0, "rpf_seconds": 1.0,
                 "stonesoup": {10: {"final_error_m": e, "seconds": 2.0}}} for e in errors]

    one = summary({"particles": 5, "stonesoup_particles": [10], "runs": rows([50.0, 300.0, None])})["stonesoup"][0]
    assert one["final_error_median_m"] == 300.0 and one["collapsed_runs"] == 1 and one["over_rpf"] == 3.0
    two = summary({"particles": 5, "stonesoup_particles": [10], "runs": rows([50.0, None, None])})["stonesoup"][0]
    assert two["final_error_median_m"] is None and two["over_rpf"] is None and two["collapsed_runs"] == 2


def test_the_particle_multiple_rests_on_the_result_file():
    # the file of bench/bench_stonesoup.py (tmakit at the test's N among others, Stone Soup at 1, 2,
    # 4 and 8 times it, 32 runs per seed): at the multiple the test gives, every seed's ratio is
    # within the bound with room to spare (<= 0.75 of it), and at tmakit's own count the bound would
    # not hold. As made (commit b141a89): 1.39x and 1.24x at 8x, 2.41x and 2.26x at 4x, 3.56x and
    # 2.44x at 2x (one of seed 2's runs collapsed there), 5.41x and 4.17x at 1x (docs/stonesoup.md)
    (acc,) = [a for a in json.loads(RESULT.read_text())["accuracy"]["by_particles"] if a["particles"] == PARTICLES]
    assert MULTIPLE in acc["multiples"] and len(acc["seeds"]) >= 2
    at_multiple = _ratios_at(acc, MULTIPLE)
    assert len(at_multiple) == len(acc["seeds"]) and max(at_multiple) <= 0.75 * BOUND, at_multiple
    assert max(_ratios_at(acc, 1)) > BOUND, _ratios_at(acc, 1)


@pytest.mark.slow
def test_stone_soups_particle_filter_with_tmakits_model_tracks_like_tmakits_rpf(tmp_path):
    # Iglesis & de Montella's manoeuvring-observer scenario on the paper's grid: the same
    # measurements, priors of the same law; Stone Soup's SIR filter (ESS resampling at N/3, its
    # MCMC regulariser) given tmakit's model, against tmakit's regularized filter, as
    # bench/bench_stonesoup.py runs them, with a seed the benchmark does not use. It needs more
    # particles: its regulariser moves resampled particles by Metropolis-Hastings under the
    # posterior, tmakit's Epanechnikov kernel widens them (docs/stonesoup.md); given MULTIPLE x
    # as many, within BOUND x tmakit's error (the figures: the test above)
    from bench import bench_stonesoup as bench

    grid = tmp_path / "munk-1000.nc"
    acoustics.write_grid(acoustics.build_grid(envdata.load_area(bench.AREA), workers=2), grid)
    out = bench.run(particles=PARTICLES, stonesoup_particles=(MULTIPLE * PARTICLES,), runs=24, seed=3,
                    grid_path=grid)
    summ = bench.summary(out)
    rpf, ss = summ["rpf"]["final_error_median_m"], summ["stonesoup"][0]["final_error_median_m"]
    assert rpf < 1000.0 and ss < 1000.0, (rpf, ss)  # both far inside the prior's 5 km range error
    assert ss <= BOUND * rpf, (rpf, ss)
