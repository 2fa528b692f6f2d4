"""The ML tracker over whole measurement files: exact recovery, gaps, the observer depth."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.grid.opentables import open_tables
from tests.tracker.mltma.conftest import geometry, synthetic_grid
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements
from tracker.mltma import MLTracker
from tracker.track import track


def test_noiseless_exact_recovery():
    grid = synthetic_grid()
    t, ox, oy, x, y, b = geometry(n=121)
    kk = grid["k_db"].sel({"class": "TV"}).values
    r_true = np.hypot(x - ox, y - oy)
    idx = np.rint(r_true / 100.0).astype(int) - 1
    lev = 131.02 + kk[:, idx].T                  # W = P0 + K(r) (eq. 12), no error
    m = Measurements(source="noiseless", t_s=t, obs_x_m=ox, obs_y_m=oy,
                     obs_depth_m=np.full(len(t), 100.0), bearing_deg=b,
                     bearing_sigma_deg=np.full(len(t), 0.05), band_names=("FB1", "FB2", "FB3"),
                     level_db=lev, snr_db=np.full(lev.shape, 20.0))
    df = track(open_tables(grid), m, cls_name="TV")
    last = df.iloc[-1]
    assert last["class"] == "TV" and last.tack == 1
    assert_allclose(last.course_deg, 300.0, atol=0.5)     # search resolution 15/9 deg
    assert_allclose(last.speed_mps, 6.5, atol=0.05)
    assert_allclose(last.range_m, r_true[-1], rtol=0.01)  # grid step and rounding of r_true


def test_nan_bearing_cycles_are_skipped(caplog):
    grid = synthetic_grid()
    t, ox, oy, x, y, b = geometry(n=30)
    b = b.copy()
    b[5] = np.nan
    m = Measurements(source="gaps", t_s=t, obs_x_m=ox, obs_y_m=oy, obs_depth_m=np.full(30, 100.0),
                     bearing_deg=b, bearing_sigma_deg=np.full(30, np.nan), band_names=(),
                     level_db=np.zeros((30, 0)), snr_db=np.zeros((30, 0)))
    df = track(open_tables(grid), m, cls_name="TV")
    assert len(df) == 29 and 50.0 not in df.t_s.values
    assert "without a bearing skipped" in caplog.text


@pytest.mark.bellhop
def test_observer_depth_outside_the_grid_is_an_error(tiny_grid):
    t, ox, oy, x, y, b = geometry(n=5)
    depth = np.full(5, 100.0)
    depth[3] = 1500.0
    m = Measurements(source="deep.csv", t_s=t, obs_x_m=ox, obs_y_m=oy, obs_depth_m=depth,
                     bearing_deg=b, bearing_sigma_deg=np.full(5, 0.5), band_names=(),
                     level_db=np.zeros((5, 0)), snr_db=np.zeros((5, 0)))
    with pytest.raises(MeasurementFileError, match=r"^deep.csv: row 4, column obs_depth_m: 1500 m "
                                                   r"is outside the grid's depth axis \[0, 1000\] m$"):
        track(open_tables(tiny_grid), m)


def test_cycles_without_a_detected_band_track_on_bearings_only():
    grid = synthetic_grid()
    t, ox, oy, x, y, b = geometry(n=121)
    kk = grid["k_db"].sel({"class": "TV"}).values
    idx = np.rint(np.hypot(x - ox, y - oy) / 100.0).astype(int) - 1
    lev = 131.02 + kk[:, idx].T
    lev[:40] = np.nan                               # no band detected in the first 40 cycles
    lev[80:90, :] = np.nan                          # nor in 10 later ones
    m = Measurements(source="gaps", t_s=t, obs_x_m=ox, obs_y_m=oy,
                     obs_depth_m=np.full(len(t), 100.0), bearing_deg=b,
                     bearing_sigma_deg=np.full(len(t), 0.05), band_names=("FB1", "FB2", "FB3"),
                     level_db=lev, snr_db=np.where(np.isfinite(lev), 20.0, np.nan))
    trk = MLTracker(open_tables(grid), capacity=len(t), class_names=["TV"])
    vx, vy = m.obs_velocity_mps()
    r_level = []
    for i in range(len(t)):
        trk.update_from(m, i, obs_vel=(vx[i], vy[i]))
        r_level.append(float(trk.batch.last_estimates["r_level_m"][0]))
    r_level = np.array(r_level)
    # no level range where no band is detected; one wherever a band is
    assert np.all(np.isnan(r_level[:40])) and np.all(np.isnan(r_level[80:90]))
    assert np.all(np.isfinite(r_level[40:80])) and np.all(np.isfinite(r_level[90:]))
    df = track(open_tables(grid), m, cls_name="TV")
    assert len(df) == len(t)
    # the bearings still give course every cycle; range has no estimate before any level
    assert np.all(np.isfinite(df.course_deg)) and np.all(np.isfinite(df.bearing_deg))
    assert np.isnan(df.range_m.iloc[0])
    # after the first levels the bearing-only gap keeps a range (the last one as prior)
    assert np.all(np.isfinite(df.range_m.iloc[80:90]))
    assert_allclose(df.range_m.iloc[-1], np.hypot(x - ox, y - oy)[-1], rtol=0.02)
