"""ML tracker: eqs. 7 and 8 by hand, and exact recovery on noiseless data."""

import dataclasses
import json
import math

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import envdata
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements
from tracker.mltma import course_from_relative_deg, relative_course_deg, trimmed_mean
from tracker.track import track


def _geometry(n=61, dt=10.0, tx=20000.0, ty=15000.0, k=300.0, v=6.5):
    t = np.arange(n) * dt
    ox, oy = 2.5 * t, np.zeros(n)                      # observer 90 deg, 2.5 m/s
    x = tx + v * t * math.sin(math.radians(k))
    y = ty + v * t * math.cos(math.radians(k))
    b = np.mod(np.degrees(np.arctan2(x - ox, y - oy)), 360.0)
    return t, ox, oy, x, y, b


def test_eq8_relative_course_noiseless():
    t, ox, oy, x, y, b = _geometry()
    rel = np.degrees(np.arctan2(6.5 * math.sin(math.radians(300)) - 2.5,
                                6.5 * math.cos(math.radians(300)))) % 360.0
    i0, i1, i2 = np.array([[0, 2]]), np.array([[30, 31]]), np.array([[60, 58]])
    k = relative_course_deg(t, b[None], i0, i1, i2, np.ones((1, 2), bool))
    assert_allclose(k, rel, rtol=0, atol=1e-6)


def test_eq7_course_from_relative_course():
    # V = 6.5 at 300 deg, observer 2.5 m/s at 90 deg: relative velocity (-8.129, 3.25)
    k_rel = math.degrees(math.atan2(-8.1292, 3.25)) % 360.0
    assert_allclose(course_from_relative_deg(k_rel, 6.5, 90.0, 2.5), 300.0, atol=1e-3)
    # stationary observer: course = relative course
    assert_allclose(course_from_relative_deg(123.0, 5.0, 0.0, 0.0), 123.0, atol=1e-12)


def test_robust_smoothing_drops_two_each_end():
    v = np.arange(19.0)[None, :]
    v[0, 0] = 1000.0   # an outlier is dropped
    assert_allclose(trimmed_mean(v, np.array([19]), 2, 19), np.mean(np.arange(3, 18)))  # 3..17 kept


def _synthetic_grid(truth_p0=131.02, speed=6.5):
    """The ocean-deep area with a monotone K(r) and class means at the truth (a perfect prior)."""
    area = envdata.load_area("ocean-deep")
    classes = tuple(dataclasses.replace(c, speed_mean_mps=speed, noise_mean_db=truth_p0)
                    if c.name == "TV" else c for c in area.classes)
    area = dataclasses.replace(area, classes=classes)
    r = np.arange(1, 1201) * 100.0
    base = -20 * np.log10(r)
    k = np.stack([np.stack([base - 0.02 * r / 1000 * (j + 1) - 3 * j for j in range(3)])
                  for _ in area.classes])
    return xr.Dataset({"k_db": (("class", "band", "range"), k)},
                      coords={"class": [c.name for c in area.classes],
                              "band": [b.name for b in area.bands], "range": r},
                      attrs={"area_json": json.dumps(area.to_dict())})


def test_noiseless_exact_recovery():
    grid = _synthetic_grid()
    t, ox, oy, x, y, b = _geometry(n=121)
    kk = grid["k_db"].sel({"class": "TV"}).values
    r_true = np.hypot(x - ox, y - oy)
    idx = np.rint(r_true / 100.0).astype(int) - 1
    lev = 131.02 + kk[:, idx].T                  # W = P0 + K(r) (eq. 12), no error
    m = Measurements(source="noiseless", t_s=t, obs_x_m=ox, obs_y_m=oy,
                     obs_depth_m=np.full(len(t), 100.0), bearing_deg=b,
                     bearing_sigma_deg=np.full(len(t), 0.05), band_names=("FB1", "FB2", "FB3"),
                     level_db=lev, snr_db=np.full(lev.shape, 20.0))
    df = track(grid, m, cls_name="TV")
    last = df.iloc[-1]
    assert last["class"] == "TV" and last.tack == 1
    assert_allclose(last.course_deg, 300.0, atol=0.5)     # search resolution 15/9 deg
    assert_allclose(last.speed_mps, 6.5, atol=0.05)
    assert_allclose(last.range_m, r_true[-1], rtol=0.01)  # grid step and rounding of r_true


def test_nan_bearing_cycles_are_skipped(caplog):
    grid = _synthetic_grid()
    t, ox, oy, x, y, b = _geometry(n=30)
    b = b.copy()
    b[5] = np.nan
    m = Measurements(source="gaps", t_s=t, obs_x_m=ox, obs_y_m=oy, obs_depth_m=np.full(30, 100.0),
                     bearing_deg=b, bearing_sigma_deg=np.full(30, np.nan), band_names=(),
                     level_db=np.zeros((30, 0)), snr_db=np.zeros((30, 0)))
    df = track(grid, m, cls_name="TV")
    assert len(df) == 29 and 50.0 not in df.t_s.values
    assert "without a bearing skipped" in caplog.text


@pytest.mark.bellhop
def test_level_range_uses_k_at_the_rows_observer_depth(tiny_grid):
    from tracker.mltma import MLBatch
    from tracker.tables import GridTables

    ic = list(tiny_grid["class"].values).index("SHIP")
    raxis = tiny_grid["range"].values
    k300 = GridTables.from_grid(tiny_grid).k_db(300.0)[ic]
    j = int(np.argmin(np.abs(raxis - 3000.0)))
    r_true = raxis[j]
    p0 = 133.0                                      # the class mean: a perfect prior
    lev = p0 + k300[:, j]                           # W = P0 + K(r) at 300 m (eq. 12)
    est = {}
    for depth in (300.0, None):                     # None: the grid's 100 m observer depth
        batch = MLBatch(tiny_grid, [ic], 1)
        out = batch.update(0.0, 0.0, 0.0, 0.0, 2.0, 45.0, 0.5, lev[None, :],
                           np.full((1, 2), 30.0), obs_depth_m=depth)
        est[depth] = float(out["r_level_m"][0])
    # eq. 20 at the right depth recovers the range (grid step 1 node); at 100 m it does not
    assert abs(est[300.0] - r_true) <= raxis[1] - raxis[0]
    assert abs(est[None] - r_true) > abs(est[300.0] - r_true)


@pytest.mark.bellhop
def test_observer_depth_outside_the_grid_is_an_error(tiny_grid):
    t, ox, oy, x, y, b = _geometry(n=5)
    depth = np.full(5, 100.0)
    depth[3] = 1500.0
    m = Measurements(source="deep.csv", t_s=t, obs_x_m=ox, obs_y_m=oy, obs_depth_m=depth,
                     bearing_deg=b, bearing_sigma_deg=np.full(5, 0.5), band_names=(),
                     level_db=np.zeros((5, 0)), snr_db=np.zeros((5, 0)))
    with pytest.raises(MeasurementFileError, match=r"^deep.csv: row 4, column obs_depth_m: 1500 m "
                                                   r"is outside the grid's depth axis \[0, 1000\] m$"):
        track(tiny_grid, m)


def test_cycles_without_a_detected_band_track_on_bearings_only():
    grid = _synthetic_grid()
    t, ox, oy, x, y, b = _geometry(n=121)
    kk = grid["k_db"].sel({"class": "TV"}).values
    idx = np.rint(np.hypot(x - ox, y - oy) / 100.0).astype(int) - 1
    lev = 131.02 + kk[:, idx].T
    lev[:40] = np.nan                               # no band detected in the first 40 cycles
    lev[80:90, :] = np.nan                          # nor in 10 later ones
    m = Measurements(source="gaps", t_s=t, obs_x_m=ox, obs_y_m=oy,
                     obs_depth_m=np.full(len(t), 100.0), bearing_deg=b,
                     bearing_sigma_deg=np.full(len(t), 0.05), band_names=("FB1", "FB2", "FB3"),
                     level_db=lev, snr_db=np.where(np.isfinite(lev), 20.0, np.nan))
    from tracker.mltma import MLTracker

    trk = MLTracker(grid, capacity=len(t), class_names=["TV"])
    vx, vy = m.obs_velocity_mps()
    r_level = []
    for i in range(len(t)):
        trk.update_from(m, i, obs_vel=(vx[i], vy[i]))
        r_level.append(float(trk.batch.last_out["r_level_m"][0]))
    r_level = np.array(r_level)
    # no level range where no band is detected; one wherever a band is
    assert np.all(np.isnan(r_level[:40])) and np.all(np.isnan(r_level[80:90]))
    assert np.all(np.isfinite(r_level[40:80])) and np.all(np.isfinite(r_level[90:]))
    df = track(grid, m, cls_name="TV")
    assert len(df) == len(t)
    # the bearings still give course every cycle; range has no estimate before any level
    assert np.all(np.isfinite(df.course_deg)) and np.all(np.isfinite(df.bearing_deg))
    assert np.isnan(df.range_m.iloc[0])
    # after the first levels the bearing-only gap keeps a range (the last one as prior)
    assert np.all(np.isfinite(df.range_m.iloc[80:90]))
    assert_allclose(df.range_m.iloc[-1], np.hypot(x - ox, y - oy)[-1], rtol=0.02)


def _exact_eq25(t, ox, oy, brg_deg, sd_deg, n, r_opt, r_sd, mV, sV, k_rel, obs_course, obs_speed,
                sk_deg, courses, speeds, ranges):
    """Eq. 25 as written, on a full grid: every bearing's exact residual, no approximation."""
    a = math.radians(brg_deg[n])
    K, V, R = np.meshgrid(courses, speeds, ranges, indexing="ij")
    kx, ky = np.sin(np.radians(K)), np.cos(np.radians(K))
    px0, py0 = ox[n] + R * math.sin(a), oy[n] + R * math.cos(a)
    j = np.square((R - r_opt) / r_sd) + np.square((V - mV) / sV)
    mk = course_from_relative_deg(k_rel, V, obs_course, obs_speed)
    j += np.square(np.mod(K - mk + 180.0, 360.0) - 180.0) / sk_deg ** 2
    for i in range(n + 1):
        dt = t[n] - t[i]
        pred = np.degrees(np.arctan2(px0 - V * kx * dt - ox[i], py0 - V * ky * dt - oy[i]))
        j += np.square((np.mod(brg_deg[i] - pred + 180.0, 360.0) - 180.0) / sd_deg[i])
    best = np.unravel_index(np.argmin(j), j.shape)
    return K[best], V[best], R[best], j[best]


@pytest.mark.slow
def test_fast_eq25_search_matches_exhaustive_search(rng):
    """The fast search (24 x 20 grid refined twice, Newton in range, pseudo-linear running sums)
    against a plain exhaustive search of eq. 25 over every bearing on a fine grid.

    Fine grid: course 1 deg over the whole circle, speed 0.05 m/s over mV +- 3 sV, range 1 %
    (log spacing) over 5-60 km: 360 x 121 x 250 candidates. Both searches minimise the same
    functional, so the estimates must agree within one fine-grid step (the exhaustive argmin
    lies within half a step of the true minimum, the fast search's refinement ends at 15/9 =
    1.7 deg and 0.35/9 m/s with Newton in range, and its pseudo-linear bearing term differs
    from the exact one by O(residual^2)): 1.5 steps are allowed for course and speed, 1.5 %
    for range.
    """
    from tracker.mltma import MLBatch
    from tracker.ranging import level_range, offset_nodes

    grid = _synthetic_grid()
    kk = grid["k_db"].sel({"class": "TV"}).values
    n_cyc = 36
    for trial in range(2):
        t, ox, oy, x, y, b_true = _geometry(n=n_cyc, tx=18000.0 + 4000 * trial, ty=16000.0)
        r_true = np.hypot(x - ox, y - oy)
        sd = np.full(n_cyc, 0.1)
        b = np.mod(b_true + rng.normal(0.0, 0.1, n_cyc), 360.0)
        idx = np.rint(r_true / 100.0).astype(int) - 1
        lev = 131.02 + kk[:, idx].T + rng.normal(0.0, 1.0, (n_cyc, 3))
        ci = [str(c) for c in grid["class"].values].index("TV")
        batch = MLBatch(grid, [ci], n_cyc)
        for i in range(n_cyc):
            out = batch.update(t[i], ox[i], oy[i], 2.5, 0.0, b[i:i + 1], sd[i:i + 1],
                               lev[i][None, :], np.full((1, 3), 20.0))
        n = n_cyc - 1
        assert out["used_eq25"][0]
        k_rel = batch._rel_course(np.array([0]), n)
        cls = batch.classes[ci]
        off, wts = offset_nodes(cls.noise_sd_db, cls.k_error_sd_db)
        from tracker.ranging import level_sd_db
        sd_w = level_sd_db(np.full((1, 3), 100.0), batch.bandwidth_hz,
                           batch.sonar.integration_time_s)
        r_opt, r_sd = level_range(lev[n][None, :], np.ones((1, 3), bool), sd_w, batch.p0[:1],
                                  batch.k_db[ci], batch.range_axis, offsets_db=off, weights=wts)
        r_sd = np.maximum(r_sd, 100.0)
        u = np.array([[math.sin(math.radians(b[n]))], [math.cos(math.radians(b[n]))]])
        res = batch._search(np.array([0]), n, u, k_rel, 90.0, 2.5, r_opt, r_sd)
        k_f, v_f, r_f = batch._polish(np.array([0]), n, res, k_rel, 90.0, 2.5, r_opt, r_sd)[:3]
        courses = np.arange(0.0, 360.0, 1.0)
        speeds = np.linspace(cls.speed_mean_mps - 3 * cls.speed_sd_mps,
                             cls.speed_mean_mps + 3 * cls.speed_sd_mps, 121)
        ranges = 5000.0 * 1.01 ** np.arange(250)
        k_e, v_e, r_e, j_e = _exact_eq25(t, ox, oy, b, sd, n, r_opt[0], r_sd[0], cls.speed_mean_mps,
                                    cls.speed_sd_mps, k_rel[0], 90.0, 2.5,
                                    batch.sk_deg[0], courses, speeds, ranges)
        j_f = _exact_eq25(t, ox, oy, b, sd, n, r_opt[0], r_sd[0], cls.speed_mean_mps,
                          cls.speed_sd_mps, k_rel[0], 90.0, 2.5, batch.sk_deg[0],
                          k_f, v_f, r_f)[3]
        assert j_f <= j_e + 0.01, (trial, j_f, j_e)
        assert abs((k_f[0] - k_e + 180.0) % 360.0 - 180.0) <= 1.5 * 1.0, (trial, k_f, k_e)
        assert abs(v_f[0] - v_e) <= 0.3, (trial, v_f, v_e)
        assert abs(r_f[0] / r_e - 1.0) <= 0.04, (trial, r_f, r_e)
