"""MLBatch: the ML tracker's state over B rows and T cycles, and one cycle of the algorithm.

Rows are class hypotheses of one track, or runs x classes of the Monte Carlo experiment; they
share one observer and one cycle clock. Every cycle, for every row in parallel, `MLBatch.update`
takes the steps of section 3 (paper's numbering):

1. maneuver detection from bearings (eqs. 26-27) and levels (eq. 29), a test firing on
   ``maneuver_confirm`` consecutive cycles; a detection starts a new tack (the last estimates
   carry over as output until eq. 25 applies on the new tack) -- `tracker.mltma.maneuver`;
2. the cycle's bearing, band SNRs and levels (the arguments);
3. sigma_P (eq. 2), unless the measurement carries the bearing sd, and
4. sigma_dW (eq. 11) from the SNRs -- `tracker.mltma.measurement_sd`;
5. relative course by least squares over bearing triples (eq. 8, Annex 1) once the bearing
   change since the tack start passes eq. 30 (4.5 sigma_P) and the bearing trace's curvature
   is significant (quadratic term of a fit over the tack > 4.5 sd; eq. 8 is undetermined on a
   straight trace), else the reverse bearing; in eq. 25 the relative course of eq. 8 has the
   paper's sd sK_rho = 4 deg, the reverse bearing 30 deg (conclusion 4's course errors) --
   `tracker.mltma.gates`, `tracker.mltma.course`;
6. course from the relative course and the class's mean speed (eq. 7);
7. level-based ML range (eq. 20) and its a-posteriori sd (eq. 21) over the cycle's level error
   as the one level model has it (`tracker.levels.LevelErrors.of_tables`: K's offset and its
   residual along the track, both widened with the observer's distance from where tables of one
   position were computed; the part common to the bands in eq. 21's nodes with P0's sd, each
   band's own in eq. 20's weights; docs/gm.md); without a detected band the last range is a
   weak prior -- `tracker.mltma.range_prior`;
8. the joint ML estimate of course, speed and range (eq. 25) when the bearing changed by more
   than 3 sigma_P over the last 3 minutes (section 4 step 8, Russian original), else the
   fallbacks listed after eq. 25 (mean speed, eq.-8/reverse-bearing course, eq.-20 range):
   a fast search with the bearing term in pseudo-linear form, a running 5 x 5 quadratic form
   over the tack (`tracker.mltma.bearing_form`, `tracker.mltma.search`), then damped
   Gauss-Newton steps on eq. 25 as written (`tracker.mltma.polish`);
9. robust smoothing over the last L = 19 cycles of the tack, dropping the 2 largest and the 2
   smallest (ranges are first carried to the current time with each cycle's velocity) --
   `tracker.mltma.smoothing`.
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.grid.face import Tables
from tracker.errors import MeasurementFileError
from tracker.levels import LevelErrors, at_bearing
from tracker.mltma import bearing_form, gates, maneuver, measurement_sd, smoothing
from tracker.mltma.course import course_from_relative_deg, course_speed_slope_deg_per_mps, relative_course_on_tack_deg
from tracker.mltma.covariance import marginal_sds
from tracker.mltma.eq25 import Eq25Estimate, Eq25Terms
from tracker.mltma.params import MLParams
from tracker.mltma.polish import polish
from tracker.mltma.range_prior import level_ranges_m, range_prior_m
from tracker.mltma.search import search
from tracker.mltma.window import TackWindow, tack_window
from tracker.ranging import offset_nodes, offset_nodes_per_row


class MLBatch:
    """The ML tracker over B rows sharing one observer and one cycle clock.

    Parameters
    ----------
    tables : Tables
        Propagation grid (k_db and the area's classes, sonar, noise).
    class_index : array of int, shape (B,)
        Class hypothesis (index into the grid's class axis) of each row.
    capacity : int
        Largest number of cycles to be fed.
    params : MLParams
    """

    def __init__(self, tables: Tables, class_index, capacity: int,
                 params: MLParams | None = None):
        self.params = params or MLParams()
        self.tables = tables
        self.sonar = self.tables.area.sonar
        self.bandwidth_hz = self.tables.bandwidth_hz           # (M,) of eqs. 2 and 11, Hz
        self.range_axis_m = self.tables.range_m                # (R,) range axis of K(r), m
        self.class_index = np.asarray(class_index, dtype=int)  # (B,) class hypothesis of each row
        b = len(self.class_index)
        self.n_rows = b                                        # B
        self.n_bands = len(self.tables.band_names)             # M
        self.capacity = int(capacity)                          # T, the most cycles to be fed
        classes = [self.tables.classes[i] for i in self.class_index]
        for c in dict.fromkeys(classes):
            if c.noise_mean_db is None:
                raise MeasurementFileError(f"{self.tables.source}: class {c.name!r} has no "
                                           f"noise_mean_db; the ML tracker needs P0 "
                                           f"(source_level_model = 'p0')")
        # each row's class: mV, sV of eqs. 6, 25 and mP0 of eq. 20
        self.speed_mean_mps = np.array([c.speed_mean_mps for c in classes])
        self.speed_sd_mps = np.array([c.speed_sd_mps for c in classes])
        self.p0_db = np.array([c.noise_mean_db for c in classes])     # dB re 1 uPa
        # sP0 of eq. 21; K's error at one cycle of every grid class (tracker.levels), its part common
        # to the bands (eq. 21's sigma_dK) and each band's own (eq. 20's weights)
        self.noise_sd_db = np.array([c.noise_sd_db for c in classes])
        self.k_errors = [LevelErrors.of_tables(self.tables, ic) for ic in range(len(self.tables.classes))]
        k0 = [e.cycle_sd_db(self.n_bands) for e in self.k_errors]
        self.k_common_sd_db = np.array([float(k0[c][0]) for c in self.class_index])   # (B,) at the origin
        self.k_band_sd_db = np.array([float(k0[c][1]) for c in self.class_index])     # (B,)
        # a study's model by bearing (`Tables.k_error_model`): each class's errors on every radial,
        # each row's read at its bearing every cycle
        self.k_errors_by_bearing = None
        self._k_parts = {}  # their sds per observer distance from the tables' origin (rounded to 1 m)
        radials = self.tables.bearing_axis_deg
        if self.tables.k_error_measured is not None and radials is not None:
            self.k_errors_by_bearing = (np.asarray(radials, dtype=float), [
                [LevelErrors.of_tables(self.tables, ic, bearing_deg=float(b)) for b in radials]
                for ic in range(len(self.tables.classes))])
        # eq. 21 quadrature (offsets_db, weights) over P0 and K(r) errors, per grid class
        self.level_offsets = [offset_nodes(c.noise_sd_db, float(k[0]), self.params.offsets_n)
                              for c, k in zip(self.tables.classes, k0)]
        self.n_cycles = 0                                      # cycles fed so far
        # per cycle: time and observer position (shared by the rows)
        self.t_s = np.zeros(self.capacity)
        self.obs_x_m = np.zeros(self.capacity)
        self.obs_y_m = np.zeros(self.capacity)
        # per row and cycle: bearing and its sd sigma_P (eq. 2), deg
        self.bearing_deg = np.zeros((b, self.capacity))
        self.bearing_sd_deg = np.ones((b, self.capacity))
        # per row and cycle: highest detected band (-1: none) and its level (eq. 29), dB
        self.top_band = np.full((b, self.capacity), -1)
        self.top_level_db = np.full((b, self.capacity), np.nan)
        # eq. 29's statistics on the level and on the level less K along the track (level_vs_k), dB
        self.level_step_db = np.full((2, b, self.capacity), np.nan)
        # each row's K(r) in that cycle's highest detected band (band 0 without one) at its bearing,
        # from the tables where the observer was then, for the last F + 4 cycles that eq. 29's
        # window and current cycle span (a ring: cycle n at n % (F + 4)), dB (level_vs_k)
        self.k_top_db = (np.full((self.params.level_f + 4, b, self.range_axis_m.size), np.nan)
                         if self.params.level_vs_k else None)
        # the current tack of each row: first cycle, number (1, 2, ...), and the number of
        # consecutive cycles on which a maneuver test (eqs. 26-29) has fired
        self.tack_start = np.zeros(b, dtype=int)
        self.tack = np.ones(b, dtype=int)
        self.maneuver_pending = np.zeros(b, dtype=int)
        # (B, 5, 5): sum over the tack of w_i a_i a_i^T, the pseudo-linear bearing term of
        # eq. 25 as a quadratic form z^T F z in z = (x, y at the tack start, vx, vy, 1)
        # (tracker.mltma.bearing_form)
        self.bearing_form = np.zeros((b, 5, 5))
        self.rel_course_sd_deg = np.full(b, self.params.rel_course_sd_deg)  # sK_rho of eq. 25
        # raw (unsmoothed) estimates of each row and cycle, the input of the smoothing (step 9)
        self.raw = {k: np.full((b, self.capacity), np.nan)
                    for k in ("course_deg", "speed_mps", "x_m", "y_m", "vx_mps", "vy_mps",
                          "range_sd_m", "course_sd_deg", "speed_sd_mps")}
        # smoothed range, course, speed of each cycle: input of the second pass (smooth_passes 2)
        self.smoothed = ({k: np.full((b, self.capacity), np.nan)
                          for k in ("range_m", "course_deg", "speed_mps")}
                         if self.params.smooth_passes > 1 else None)
        self.last_range_m = np.full(b, np.nan)                 # last smoothed range (NaN: none)
        self.last_estimates = None                             # the last cycle's output

    def _away_m(self, obs_x_m: float, obs_y_m: float) -> float:
        """The observer's distance from where the tables were computed, m (0 for tables that hold
        everywhere, `acoustics.grid.face.Tables.distance_from_origin_m`)."""
        d = self.tables.distance_from_origin_m(obs_x_m, obs_y_m)
        return 0.0 if d is None else float(d)

    def _k_error_sds(self, away_m: float, brg):
        """Each row's K error at this cycle: eq. 21's nodes over P0 and the part common to the bands
        (None where it is the class's at the origin), and each band's own sd for eq. 20's weights
        (B,), dB (None where no row has one). Where the tables carry a study's model by bearing,
        each row's at its bearing ``brg`` (B,), linear between radials."""
        if self.k_errors_by_bearing is not None:
            radials, per_class = self.k_errors_by_bearing
            key = round(away_m, 0)
            if key not in self._k_parts:
                self._k_parts[key] = np.array([[e.cycle_sd_db(self.n_bands, away_m) for e in row]
                                               for row in per_class])                        # (C, N, 2)
            parts = self._k_parts[key]
            common, band = (at_bearing(radials, parts[self.class_index, :, j], brg) for j in (0, 1))
            nodes = offset_nodes_per_row(self.noise_sd_db, common, self.params.offsets_n)
        elif away_m > 0.0:
            parts = [e.cycle_sd_db(self.n_bands, away_m) for e in self.k_errors]
            common = np.array([float(parts[c][0]) for c in self.class_index])
            band = np.array([float(parts[c][1]) for c in self.class_index])
            nodes = offset_nodes_per_row(self.noise_sd_db, common, self.params.offsets_n)
        else:
            band, nodes = self.k_band_sd_db, None
        return nodes, (band if band.any() else None)

    def update(self, t_s: float, obs_x_m: float, obs_y_m: float, obs_vx_mps: float,
               obs_vy_mps: float, bearing_deg, bearing_sd, level_db, snr_db,
               obs_depth_m: float | None = None) -> dict:
        """Feed one cycle (bearing and bearing sd (B,), levels and SNR (B, M)); return estimates.

        K(r) is taken at ``obs_depth_m`` (TL linear in depth; default the grid's observer
        depth), `acoustics.grid.face.Tables.k_db`.

        Returns
        -------
        dict of str to ndarray, shape (B,)
            Smoothed ``range_m``, ``course_deg``, ``speed_mps``, ``x_m``, ``y_m`` and the
            ``bearing_deg``, with their sds ``range_sd_m``, ``course_sd_deg``, ``speed_sd_mps``
            (`tracker.mltma.smoothing.window_sd`); ``tack``; ``used_eq25``; the level range
            ``r_level_m`` (eq. 20, NaN: no band detected) and its sd ``r_level_sd_m`` (eq. 21);
            the raw ``raw_course_deg``, ``raw_speed_mps``, ``raw_range_m`` and this cycle's
            ``raw_range_sd_m`` (eq. 25's marginal sd, `tracker.mltma.covariance`).
        """
        p, n, b = self.params, self.n_cycles, self.n_rows
        if n >= self.capacity:
            raise ValueError(f"MLBatch capacity {self.capacity} cycles exceeded")
        brg = np.broadcast_to(np.asarray(bearing_deg, dtype=float), (b,))
        level = np.broadcast_to(np.asarray(level_db, dtype=float), (b, self.n_bands))
        snr = np.broadcast_to(np.asarray(snr_db, dtype=float), (b, self.n_bands))
        detected = np.isfinite(level)
        top = measurement_sd.highest_detected_band(detected)
        # steps 3-4: sd_p = sigma_P (eq. 2) unless the measurement carries it, (B,), deg;
        # sd_w = sigma_dW (eq. 11), (B, M), dB
        q_thr = measurement_sd.threshold_snr(self.sonar.detection_threshold, self.bandwidth_hz,
                                             self.sonar.integration_time_s)
        sd_w = measurement_sd.level_sd_from_snr_db(snr, q_thr, self.bandwidth_hz,
                                                    self.sonar.integration_time_s)
        sd_p = measurement_sd.bearing_sd_from_snr_deg(
            np.broadcast_to(np.asarray(bearing_sd, dtype=float), (b,)), snr, top, q_thr,
            self.bandwidth_hz, self.sonar.integration_time_s, self.sonar.beamwidth_deg)
        self._record(n, t_s, obs_x_m, obs_y_m, brg, sd_p, level, top)

        # K at the row's bearing from the observer on a bearing-dependent grid, from the tables
        # where the observer is (an atlas's follow it): (C, M, B, R)
        k_db = self.tables.at_observer(obs_x_m, obs_y_m).k_db(obs_depth_m, bearing_deg=brg)
        if self.k_top_db is not None:
            self.k_top_db[n % len(self.k_top_db)] = self._k_rows(k_db, np.maximum(top, 0))

        # step 7: level range (eqs. 20-21); the range term of eq. 25
        # each band's own K error is the same at every range: it joins sigma_dW in eq. 20's weights
        nodes, band_sd = self._k_error_sds(self._away_m(obs_x_m, obs_y_m), brg)
        r_level, r_level_sd = level_ranges_m(
            level, detected, sd_w if band_sd is None else np.hypot(sd_w, band_sd[:, None]), self.p0_db,
            self.class_index, k_db, self.range_axis_m, self.level_offsets, self.sonar.receiver_gain_db,
            row_offsets=nodes)

        # step 1: maneuver detection; a confirmed one starts a new tack
        new_tack = self._detect_maneuver(n, sd_p, sd_w, k_db, r_level, r_level_sd)
        r_prior, r_prior_sd = range_prior_m(r_level, r_level_sd, self.last_range_m)

        # this cycle's bearing joins the bearing form, weighted with the latest range
        rho = np.where(np.isfinite(self.last_range_m), self.last_range_m,
                       np.where(np.isfinite(r_level), r_level, 10000.0))
        self._accumulate_form(n, new_tack, sd_p, rho)

        # steps 5-6: relative course (eqs. 30, 8) and course (eq. 7)
        obs_speed = math.hypot(obs_vx_mps, obs_vy_mps)
        obs_course = math.degrees(math.atan2(obs_vx_mps, obs_vy_mps)) % 360.0
        k_rel = self._relative_course(n, brg, sd_p)
        course_fallback_deg = course_from_relative_deg(k_rel, self.speed_mean_mps, obs_course,
                                                       obs_speed)

        # step 8: eq. 25 where the bearing changed enough over 3 minutes, else the fallbacks
        use25 = gates.eq25_applies(t_s, self.t_s, self.bearing_deg, self.tack_start, n, sd_p,
                                   r_prior, window_s=p.eq25_window_s, factor=p.eq25_factor,
                                   min_cycles=p.eq25_min_cycles)
        bearing_unit = np.array([np.sin(np.radians(brg)), np.cos(np.radians(brg))])   # (2, B)
        # the fallbacks listed after eq. 25: eq.-7 course at the mean speed, the mean speed,
        # the eq.-20 range; the course sd is sK_rho widened by the speed sd through eq. 7
        course = course_fallback_deg.copy()
        speed = self.speed_mean_mps.copy()
        range_est_m = r_prior.copy()
        course_sd = np.hypot(p.rel_course_sd_deg, course_speed_slope_deg_per_mps(
            k_rel, self.speed_mean_mps, obs_course, obs_speed) * self.speed_sd_mps)
        speed_sd = self.speed_sd_mps.copy()
        range_sd = r_prior_sd.copy()
        # a new tack starts from the last estimates (step 1) until eq. 25 applies on it
        carry = ~use25 & (self.tack > 1) & (self.last_estimates is not None)
        if carry.any():
            k_c, v_c, r_c = maneuver.carried_estimates(self.last_estimates,
                                                       t_s - self.t_s[n - 1], obs_x_m, obs_y_m)
            course = np.where(carry, k_c, course)
            speed = np.where(carry, v_c, speed)
            range_est_m = np.where(carry, r_c, range_est_m)
        if use25.any():
            rows = np.flatnonzero(use25)
            terms = self.eq25_terms(rows, k_rel[rows], obs_course, obs_speed, r_prior[rows],
                                    r_prior_sd[rows])
            est = self.solve_eq25(rows, n, terms)
            course[rows], course_sd[rows] = est.course_deg, est.course_sd_deg
            speed[rows], speed_sd[rows] = est.speed_mps, est.speed_sd_mps
            range_est_m[rows], range_sd[rows] = est.range_m, est.range_sd_m

        # step 9: raw estimates of this cycle (position and velocity) and the smoothing
        x = obs_x_m + range_est_m * bearing_unit[0]
        y = obs_y_m + range_est_m * bearing_unit[1]
        vx = speed * np.sin(np.radians(course))
        vy = speed * np.cos(np.radians(course))
        for key, val in (("course_deg", course), ("speed_mps", speed), ("x_m", x), ("y_m", y),
                         ("vx_mps", vx), ("vy_mps", vy), ("range_sd_m", range_sd),
                         ("course_sd_deg", course_sd), ("speed_sd_mps", speed_sd)):
            self.raw[key][:, n] = val
        out = self._smooth(n, obs_x_m, obs_y_m, brg)
        out.update(tack=self.tack.copy(), used_eq25=use25, r_level_m=r_level, r_level_sd_m=r_level_sd,
                   raw_course_deg=course, raw_speed_mps=speed, raw_range_m=range_est_m,
                   raw_range_sd_m=range_sd)
        self.last_range_m = np.where(np.isfinite(out["range_m"]), out["range_m"],
                                     self.last_range_m)
        self.last_estimates = out
        return out

    # ------------------------------------------------------------------ the steps' state
    def _record(self, n, t_s, obs_x_m, obs_y_m, brg, sd_p, level, top) -> None:
        """Store cycle n's time, observer, bearings and sds, and the highest band's level."""
        self.t_s[n], self.obs_x_m[n], self.obs_y_m[n] = t_s, obs_x_m, obs_y_m
        self.bearing_deg[:, n] = brg
        self.bearing_sd_deg[:, n] = sd_p
        self.top_band[:, n] = top
        self.top_level_db[:, n] = np.where(top >= 0, level[np.arange(self.n_rows),
                                                           np.maximum(top, 0)], np.nan)
        self.n_cycles = n + 1

    def _detect_maneuver(self, n, sd_p, sd_w, k_db, range_m, range_sd_m):
        """Step 1: eqs. 26-27 and 29; rows whose test fired on enough consecutive cycles start
        a new tack at the first of those cycles. Returns the rows that did, (B,) bool.
        ``k_db`` is this cycle's K (`update`), ``range_m``, ``range_sd_m`` (B,) the level range
        and its sd (eqs. 20-21)."""
        p = self.params
        if p.maneuver_curved:
            # the fit's relative velocity is bounded by the observer's speed and the class's fastest
            # (mean + 3 sd) over the range tracked so far (the level range before there is one;
            # without either, half the grid's range: a fit left free there is dominated by the
            # curvature of noise, gm-nps's weak runs declared 1-4 manoeuvres in 15 min)
            obs_speed = math.hypot(self.obs_x_m[n] - self.obs_x_m[max(n - 1, 0)],
                                   self.obs_y_m[n] - self.obs_y_m[max(n - 1, 0)]) / max(
                self.t_s[n] - self.t_s[max(n - 1, 0)], 1e-9)
            fired = maneuver.bearing_maneuver_curved(
                self.t_s, self.bearing_deg, self.tack_start, n, sd_p, s_cycles=p.maneuver_s,
                l_cycles=p.maneuver_l, factor=p.maneuver_factor,
                range_m=np.where(np.isfinite(self.last_range_m), self.last_range_m,
                                 np.where(np.isfinite(range_m), range_m, 0.5 * self.range_axis_m[-1])),
                relative_speed_mps=obs_speed + self.speed_mean_mps + 3.0 * self.speed_sd_mps,
                bearing_sd_history_deg=self.bearing_sd_deg)
        else:
            fired = maneuver.bearing_maneuver(self.t_s, self.bearing_deg, self.tack_start, n, sd_p,
                                              s_cycles=p.maneuver_s, l_cycles=p.maneuver_l,
                                              factor=p.maneuver_factor)
        if p.level_vs_k:
            fired |= self._level_test(n, sd_w, k_db, range_sd_m)
        else:
            fired |= maneuver.level_maneuver(self.top_band, self.top_level_db, sd_w, self.tack_start,
                                             n, f_cycles=p.level_f, factor=p.maneuver_factor,
                                             sd_floor_db=p.level_sd_floor_db)
        self.maneuver_pending = np.where(fired, self.maneuver_pending + 1, 0)
        new = self.maneuver_pending >= p.maneuver_confirm
        if new.any():
            self.tack_start[new] = n - p.maneuver_confirm + 1
            self.tack[new] += 1
            self.maneuver_pending[new] = 0
            self.bearing_form[new] = 0.0
        return new

    def _level_test(self, n, sd_w, k_db, range_sd_m):
        """Eq. 29 on the level and on the level less K along the track tracked until now, each row
        on the one whose sd is the smaller (`tracker.mltma.maneuver.level_maneuver_robust`).

        K is read at the window's and this cycle's ranges on one track (the last estimates carried
        back and forth), so that the jitter of the range tracked from cycle to cycle does not enter
        the step; each cycle's K is its own (the tables where the observer was then, at that
        cycle's bearing: an atlas's follow the observer, a bearing-dependent grid's change with the
        bearing), so that K's change with the observer's position is not taken for the target's
        (this cycle's K read at the window's ranges put up to 5 dB into the step where an observer
        crossed a slope, docs/atlas-tracking.md). Model sds: sigma_dW's (floored, with the window
        mean's); for the level less K, K's structure under the range sd of eq. 21; for the level,
        the change of K along that track less what that structure leaves unknown (a change the
        tracked range cannot predict does not count against the level's own prediction, no
        change)."""
        p = self.params
        top = np.maximum(self.top_band[:, n], 0)
        rows = np.arange(self.n_rows)
        var = np.maximum(sd_w[rows, top], p.level_sd_floor_db) ** 2 * (1.0 + 1.0 / p.level_f)
        lo = n - 3 - p.level_f
        steps = np.full((2, self.n_rows), np.nan)
        var_raw = var_k = var
        steps[0] = maneuver.level_step_db(self.top_band, self.top_level_db, self.tack_start, n, f_cycles=p.level_f)
        last = self.last_estimates
        if last is not None and lo >= 0:
            course = np.radians(last["course_deg"])
            vx, vy = last["speed_mps"] * np.sin(course), last["speed_mps"] * np.cos(course)
            cycles = np.append(np.arange(lo, n - 3), n)
            dt = self.t_s[cycles] - self.t_s[n - 1]                                         # (F + 1,)
            r = np.hypot(last["x_m"][:, None] + vx[:, None] * dt - self.obs_x_m[cycles],
                         last["y_m"][:, None] + vy[:, None] * dt - self.obs_y_m[cycles])
            k_rows = self._k_rows(k_db, top)                                                   # (B, R)
            ring = self.k_top_db
            k_win = np.moveaxis(ring[np.arange(lo, n - 3) % len(ring)], 0, 1)                  # (B, F, R)
            k_track = np.concatenate([self._k_interp(k_win, r[:, :-1]), self._k_interp(k_rows, r[:, -1:])],
                                     axis=1)                                                   # (B, F + 1)
            steps[1] = maneuver.level_step_db(self.top_band, self.top_level_db, self.tack_start, n,
                                              f_cycles=p.level_f, k_window_db=k_track[:, :-1],
                                              k_now_db=k_track[:, -1])
            test = np.isfinite(steps[1])
            if test.any():
                window = np.where(self.top_band[:, lo:n - 3] == self.top_band[:, n:n + 1], r[:, :-1], np.nan)
                structure = maneuver.k_structure_var_db2(k_rows, self.range_axis_m, np.where(test, r[:, -1], np.nan),
                                                         window, range_sd_m, k_window_db=k_win)
                var_k = var + structure
                # the change of K along the track, which the level itself leaves in its step, as
                # far as the range is known well enough to predict it
                change2 = np.nan_to_num(np.square(steps[0] - steps[1]))
                var_raw = var + change2 * change2 / np.maximum(change2 + structure, 1e-12)
        fired = maneuver.level_maneuver_robust(steps, self.level_step_db, n, np.sqrt(np.stack([var_raw, var_k])),
                                               factor=p.maneuver_factor, history_cycles=p.level_history_cycles,
                                               min_history=p.level_min_history)
        self.level_step_db[:, :, n] = steps
        return fired

    def _k_interp(self, k_rows, range_m):
        """Each row's K (B, R), or each row's per column (B, J, R), at its ranges (B, J), linear,
        held at the axis's ends (`tracker.mltma.maneuver.k_along_range`), NaN at a NaN range, dB."""
        axis = self.range_axis_m
        k = maneuver.k_along_range(k_rows, axis, np.nan_to_num(range_m, nan=axis[0]))
        return np.where(np.isfinite(range_m), k, np.nan)

    def _k_rows(self, k_db, band):
        """Each row's K(r) in the given band (B,) of its class, (B, R), dB."""
        rows = np.arange(self.n_rows)
        return k_db[self.class_index, band, rows] if k_db.ndim == 4 else k_db[self.class_index, band]

    def _accumulate_form(self, n, new_tack, sd_p, rho) -> None:
        """Add cycle n's bearing to the bearing form; a new tack's form is first rebuilt from
        the cycles that confirmed the maneuver (with this cycle's sigma_P and range)."""
        if new_tack.any():
            rows = np.flatnonzero(new_tack)
            for i in range(int(self.tack_start[rows].min()), n):
                sel = rows[self.tack_start[rows] <= i]
                self.bearing_form[sel] += bearing_form.cycle_term(
                    self.bearing_deg[sel, i], sd_p[sel], rho[sel],
                    self.t_s[i] - self.t_s[self.tack_start[sel]], self.obs_x_m[i],
                    self.obs_y_m[i])
        self.bearing_form += bearing_form.cycle_term(
            self.bearing_deg[:, n], sd_p, rho, self.t_s[n] - self.t_s[self.tack_start],
            self.obs_x_m[n], self.obs_y_m[n])

    def _relative_course(self, n, brg, sd_p):
        """Step 5: eq. 8 where eq. 30 and the curvature test pass, else the reverse bearing;
        sets the relative course's sd in eq. 25 (sK_rho, wider for the reverse bearing)."""
        p, b = self.params, self.n_rows
        eq30 = gates.eq30_passes(brg, self.bearing_deg[np.arange(b), self.tack_start], sd_p,
                                 n - self.tack_start + 1, p.eq30_factor)
        if p.curvature_factor > 0 and eq30.any():
            eq30 &= gates.bearing_curvature_significant(self.tack_window(n), p.curvature_factor)
        k_rel = np.mod(brg + 180.0, 360.0)                 # reverse bearing
        self.rel_course_sd_deg = np.where(eq30, p.rel_course_sd_deg, p.reverse_course_sd_deg)
        if eq30.any():
            rows = np.flatnonzero(eq30)
            k_rel[rows] = relative_course_on_tack_deg(self.t_s, self.bearing_deg[rows, :n + 1],
                                                      self.tack_start[rows], n, p.triples)
        return k_rel

    def _smooth(self, n, obs_x_m, obs_y_m, brg) -> dict:
        """Step 9: robust smoothing over the last L cycles of each row's tack."""
        p = self.params
        idx, count = smoothing.smoothing_window(self.tack_start, n, p.smooth_cycles)
        r, k, v, sds = smoothing.smooth_raw(self.raw, self.t_s, n, idx, count, obs_x_m, obs_y_m,
                                            drop=p.smooth_drop, width=p.smooth_cycles)
        if p.smooth_passes > 1:
            s = self.smoothed
            s["range_m"][:, n], s["course_deg"][:, n], s["speed_mps"][:, n] = r, k, v
            r, k, v = smoothing.smooth_again(s, idx, count, k, drop=p.smooth_drop,
                                             width=p.smooth_cycles)
        a = np.radians(brg)
        return {"range_m": r, "course_deg": np.mod(k, 360.0), "speed_mps": v,
                "x_m": obs_x_m + r * np.sin(a), "y_m": obs_y_m + r * np.cos(a),
                "bearing_deg": brg.copy(), **sds}

    # ------------------------------------------------------------------ eq. 25 on given rows
    def tack_window(self, n, rows=slice(None)) -> TackWindow:
        """The chosen rows' tacks up to cycle n (`tracker.mltma.window`)."""
        return tack_window(self.t_s, self.obs_x_m, self.obs_y_m, self.bearing_deg,
                           self.bearing_sd_deg, self.tack_start, n, rows)

    def eq25_terms(self, rows, rel_course_deg, obs_course_deg: float, obs_speed_mps: float,
                   range_m, range_sd_m) -> Eq25Terms:
        """Eq. 25's terms for the given rows: their class priors and relative-course sd with
        the given relative course, observer motion and range term."""
        return Eq25Terms(range_m=range_m, range_sd_m=range_sd_m,
                         speed_mean_mps=self.speed_mean_mps[rows],
                         speed_sd_mps=self.speed_sd_mps[rows], rel_course_deg=rel_course_deg,
                         rel_course_sd_deg=self.rel_course_sd_deg[rows],
                         obs_course_deg=obs_course_deg, obs_speed_mps=obs_speed_mps)

    def solve_eq25(self, rows, n, terms: Eq25Terms) -> Eq25Estimate:
        """Eq. 25's minimum for the given rows at cycle n: the fast search, then the polish."""
        p = self.params
        range_max_m = self.range_axis_m[-1]
        q = bearing_form.range_quadratic(
            self.bearing_form[rows], self.t_s[n] - self.t_s[self.tack_start[rows]],
            self.obs_x_m[n], self.obs_y_m[n], self.bearing_deg[rows, n])
        last = self.last_range_m[rows]
        rho = np.where(np.isfinite(last), last,
                       np.where(np.isfinite(terms.range_m), terms.range_m, 10000.0))
        est = search(q, terms, rho_m=rho, range_min_m=p.range_min_m, range_max_m=range_max_m,
                     params=p)
        window = self.tack_window(n, rows)
        if p.polish_iters > 0:
            est = polish(window, est, terms, range_min_m=p.range_min_m,
                         range_max_m=range_max_m, speed_span_sd=p.speed_span_sd,
                         iterations=p.polish_iters)
        return marginal_sds(window, est, terms, range_max_m)
