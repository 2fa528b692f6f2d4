"""The cumulative P_D along a track on a real BELLHOP grid (tracker.pdtrack): against a Monte
Carlo of the same model, the persistent offset drawn once per track, and the track CSV's rules."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
from acoustics.grid.detectionsigma import SigmaOverride
from acoustics.pd import normal_cdf
from tracker.errors import MeasurementFileError
from tracker.pdtrack import TrackPath, read_track_path, track_pd

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def flat(tiny_grid):
    return acoustics.open_tables(tiny_grid)


def approach(seconds: float = 600.0) -> TrackPath:
    """A submarine closing from 4.8 km to 0.3 km at 7.5 m/s on a static observer at the origin."""
    t = np.array([0.0, seconds])
    return TrackPath(t_s=t, obs_x_m=np.zeros(2), obs_y_m=np.zeros(2), x_m=np.zeros(2),
                     y_m=np.array([4800.0, 4800.0 - 7.5 * seconds]), obs_depth_m=None, target_depth_m=None,
                     cls_name="SUB", source="approach")


def _excess(tables, result):
    """SE at each look, eqs. 2 and 11 written out from the class's numbers and K at the range."""
    ic = tables.class_index("SUB")
    cls, sonar = tables.classes[ic], tables.area.sonar
    k = tables.k_at(ic, result.range_m)
    snr = cls.noise_mean_db + k - (tables.noise_band_db - sonar.directivity_index_db)
    return snr - 10 * np.log10(sonar.detection_threshold / np.sqrt(tables.bandwidth_hz * sonar.integration_time_s))


def _sigma(tables, cls):
    """The level's sd about the class's mean: its source level sd and K's error model's offset and
    residual (the class's k_error_sd_db and the tables' own residual), all lasting along a track."""
    model = tables.k_error_model(tables.class_index(cls.name))
    return float(np.hypot(cls.noise_sd_db, np.hypot(model.offset_sd_db[0], model.residual_sd_db[0])))


def test_looks_are_one_per_integration_time_along_the_path(flat):
    result = track_pd(flat, approach(), "SUB")
    assert_allclose(np.diff(result.path.t_s), flat.area.sonar.integration_time_s)
    assert_allclose(result.range_m, 4800.0 - 7.5 * result.path.t_s)
    assert result.rows == ("FB1", "F500", "any")
    assert np.all(np.diff(result.cumulative, axis=0) >= 0.0)
    # each look's P_D is Phi(SE / sigma), sigma the class's source level sd and K's error (offset and residual)
    sub = flat.classes[flat.class_index("SUB")]
    assert_allclose(result.pd[:, :2], normal_cdf(_excess(flat, result) / _sigma(flat, sub)),
                    rtol=0, atol=1e-12)


def test_without_a_per_look_part_detection_by_t_is_the_best_look_so_far(flat):
    # all of today's sigma is persistent: one draw per track, so P_cum = Phi(max SE_i / sigma)
    result = track_pd(flat, approach(), "SUB")
    sub = flat.classes[flat.class_index("SUB")]
    best = np.maximum.accumulate(_excess(flat, result), axis=0)
    assert_allclose(result.cumulative[:, :2], normal_cdf(best / _sigma(flat, sub)),
                    rtol=0, atol=1e-12)
    assert_allclose(result.cumulative[:, 2], 1.0 - np.prod(1.0 - result.cumulative[:, :2], axis=1), atol=1e-12)
    # one offset shared by the bands: the best band's look so far
    assert_allclose(result.cumulative_shared, normal_cdf(best.max(axis=1) / _sigma(flat, sub)),
                    rtol=0, atol=1e-12)
    assert np.all(result.cumulative_shared <= result.cumulative[:, 2] + 1e-12)
    # far more than the independent-looks answer, which would detect almost surely by the end
    independent = 1.0 - np.cumprod(1.0 - result.pd[:, 0])
    assert result.cumulative[20, 0] < independent[20] - 0.2


def test_the_cumulative_p_d_is_a_monte_carlo_of_the_same_model(flat, rng):
    # a per-look part of 1.5 dB beside the class's persistent 3.7 dB: the model the integral solves,
    # drawn: one offset per band per track, a fresh error per look
    over = SigmaOverride(look_sd_db=1.5)
    result = track_pd(flat, approach(300.0), "SUB", override=over)
    se = _excess(flat, result)                                                   # (T, M)
    sub = flat.classes[flat.class_index("SUB")]
    s = _sigma(flat, sub)
    draws = 100_000   # binomial sd at most 0.0016: the 0.01 bound is 6 of them
    offset = s * rng.standard_normal((draws, 1, se.shape[1]))
    look = 1.5 * rng.standard_normal((draws,) + se.shape)
    hit = np.logical_or.accumulate(se[None] + offset + look >= 0.0, axis=1)      # (N, T, M)
    mc = np.concatenate([hit.mean(axis=0), hit.any(axis=2).mean(axis=0)[:, None]], axis=1)
    assert_allclose(result.cumulative, mc, rtol=0, atol=0.01)
    # and one offset for both bands, drawn the same way
    shared = np.logical_or.accumulate((se[None] + offset[..., :1] + look >= 0.0).any(axis=2), axis=1).mean(axis=0)
    assert_allclose(result.cumulative_shared, shared, rtol=0, atol=0.01)
    first = result.first["any"]
    assert 0.0 < first["mean_s_given_detected"] < result.path.t_s[-1]


def test_a_track_csv_s_rules(tmp_path):
    good = tmp_path / "t.csv"
    good.write_text("t_s,class,range_m,bearing_deg,x_m,y_m\n0,SUB,1000,90,5,5\n10,SUB,900,90,5,5\n"
                    "0,SHIP,2000,0,5,5\n10,SHIP,1900,0,5,5\n")
    path = read_track_path(good, "SUB")
    # range and bearing from the observer win over x, y; the observer at the origin when not given
    assert_allclose(path.x_m, [1000.0, 900.0])
    assert_allclose(path.y_m, [0.0, 0.0], atol=1e-9)
    assert not path.observer_given
    with pytest.raises(MeasurementFileError, match="rows of several classes .SHIP, SUB.; say which with --class"):
        read_track_path(good)
    with pytest.raises(MeasurementFileError, match="no rows of class 'NPS'"):
        read_track_path(good, "NPS")
    cases = {"t_s,x_m\n0,1\n": "missing column 'y_m'",
             "x_m,y_m\n0,1\n": "missing column 't_s'",
             "t_s,x_m,y_m\n0,1,a\n": "column 'y_m', row 1: 'a' is not a finite number",
             "t_s,x_m,y_m\n0,1,2\n0,1,2\n": "t_s must increase",
             "t_s,x_m,y_m,obs_x_m\n0,1,2,3\n": "obs_x_m without its pair",
             "t_s,x_m,y_m\n": "no rows",
             "t_s,range_m,bearing_deg\n0,-5,10\n": "range_m must be >= 0 m",
             "t_s,x_m,y_m\n0,3e7,0\n": "x_m: a position beyond 20000 km"}
    for text, message in cases.items():
        bad = tmp_path / "bad.csv"
        bad.write_text(text)
        with pytest.raises(MeasurementFileError, match=message):
            read_track_path(bad)
