"""ML target motion analysis without observer maneuver (Grinenkov & Mashoshin 2024).

Every cycle, for every class hypothesis in parallel (section 3, steps 1-9):

1. maneuver detection from bearings (eqs. 26-27) and levels (eq. 29); a detection starts a new
   tack (the last estimates carry over as range weights and output until the new tack has data);
2. sigma_P (eq. 2, or the measurement's bearing_sigma_deg) and sigma_dW (eq. 11) from the SNRs;
3. relative course by least squares over bearing triples (eq. 8, Annex 1) once the bearing
   change since the tack start passes eq. 30 (4.5 sigma_P) and the bearing trace's curvature
   is significant (quadratic term of a fit over the tack > 4.5 sd; eq. 8 is undetermined on a
   straight trace), else the reverse bearing; in eq. 25 the relative course of eq. 8 has the
   paper's sd sK_rho = 4 deg, the reverse bearing 30 deg (conclusion 4's course errors);
4. course from the relative course and the class's mean speed (eq. 7);
5. level-based ML range (eq. 20) and its a-posteriori sd (eq. 21);
6. the joint ML estimate of course, speed and range (eq. 25) when the bearing changed by more
   than 3 sigma_P over the last 3 minutes (section 4 step 8, Russian original), else the
   fallbacks listed after eq. 25 (mean speed, eq.-8/reverse-bearing course, eq.-20 range);
7. robust smoothing over the last L = 19 cycles of the tack, dropping the 2 largest and the 2
   smallest (ranges are first carried to the current time with each cycle's velocity).

Search (eq. 25). The bearing term sum_i (p_i - P(t_i, k, v, r))^2 / sigma_Pi^2 is evaluated in
its pseudo-linear form sum_i w_i (u_i^perp . d_i)^2 with d_i the target's position relative to
the observer, u_i^perp the unit normal of the measured bearing line and w_i = 1/(sigma_Pi^2
rho_i^2) (rho_i the range estimate when bearing i arrived); u^perp . d = rho sin(residual), so
the two agree to first order and both vanish on noiseless data. In this form the bearing term
is a quadratic form in (position, velocity) whose 5 x 5 matrix is a running sum over the tack:
nothing is recomputed over old bearings. For fixed course and speed the whole functional (25)
is quadratic in range, so range is minimised in closed form; the search runs over course
(24 values) x speed (20 values) and is refined twice on 7 x 7 local grids; then damped
Gauss-Newton steps (analytic Jacobian) minimise eq. 25 as written, with the exact bearing
residuals over every bearing of the tack. The same code serves
one track (rows = class hypotheses) and the Monte Carlo experiment (rows = runs x classes).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from tracker.errors import MeasurementFileError
from tracker.mltma.course import course_from_relative_deg, relative_course_deg, wrap180
from tracker.mltma.params import MLParams
from tracker.mltma.smoothing import trimmed_mean
from tracker.ranging import bearing_sd_deg, indicator_snr, level_range, level_sd_db, offset_nodes
from tracker.tables import GridTables


class MLBatch:
    """The ML tracker over B rows sharing one observer and one cycle clock.

    Parameters
    ----------
    grid : xr.Dataset or GridTables
        Propagation grid (k_db and the area's classes, sonar, noise).
    class_index : array of int, shape (B,)
        Class hypothesis (index into the grid's class axis) of each row.
    capacity : int
        Largest number of cycles to be fed.
    params : MLParams
    """

    def __init__(self, grid: xr.Dataset | GridTables, class_index, capacity: int,
                 params: MLParams | None = None):
        self.params = params or MLParams()
        self.tables = grid if isinstance(grid, GridTables) else GridTables.from_grid(grid)
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
        # eq. 21 quadrature (offsets_db, weights) over P0 and K(r) errors, per grid class
        self.level_offsets = [offset_nodes(c.noise_sd_db, c.k_error_sd_db, self.params.offsets_n)
                              for c in self.tables.classes]
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
        # the current tack of each row: first cycle, number (1, 2, ...), and the number of
        # consecutive cycles on which a maneuver test (eqs. 26-29) has fired
        self.tack_start = np.zeros(b, dtype=int)
        self.tack = np.ones(b, dtype=int)
        self.maneuver_pending = np.zeros(b, dtype=int)
        # (B, 5, 5): sum over the tack of w_i a_i a_i^T, the pseudo-linear bearing term of
        # eq. 25 as a quadratic form z^T F z in z = (x, y at the tack start, vx, vy, 1)
        self.bearing_form = np.zeros((b, 5, 5))
        self.rel_course_sd_deg = np.full(b, self.params.rel_course_sd_deg)  # sK_rho of eq. 25
        # raw (unsmoothed) estimates of each row and cycle, the input of the smoothing (step 9)
        self.raw = {k: np.full((b, self.capacity), np.nan)
                    for k in ("course_deg", "speed_mps", "x_m", "y_m", "vx_mps", "vy_mps")}
        # smoothed range, course, speed of each cycle: input of the second pass (smooth_passes 2)
        self.smoothed = ({k: np.full((b, self.capacity), np.nan)
                          for k in ("range_m", "course_deg", "speed_mps")}
                         if self.params.smooth_passes > 1 else None)
        self.last_range_m = np.full(b, np.nan)                 # last smoothed range (NaN: none)
        self.last_estimates = None                             # the last cycle's output

    # ------------------------------------------------------------------ one cycle
    def update(self, t_s: float, obs_x_m: float, obs_y_m: float, obs_vx_mps: float,
               obs_vy_mps: float, bearing_deg, bearing_sd, level_db, snr_db,
               obs_depth_m: float | None = None) -> dict:
        """Feed one cycle (bearing and bearing sd (B,), levels and SNR (B, M)); return estimates.

        K(r) is taken at ``obs_depth_m`` (TL linear in depth; default the grid's observer
        depth), `tracker.tables.GridTables.k_db`.
        """
        p, n, b = self.params, self.n_cycles, self.n_rows
        if n >= self.capacity:
            raise ValueError(f"MLBatch capacity {self.capacity} cycles exceeded")
        self.t_s[n], self.obs_x_m[n], self.obs_y_m[n] = t_s, obs_x_m, obs_y_m
        brg = np.broadcast_to(np.asarray(bearing_deg, dtype=float), (b,))
        self.bearing_deg[:, n] = brg
        level = np.broadcast_to(np.asarray(level_db, dtype=float), (b, self.n_bands))
        snr = np.broadcast_to(np.asarray(snr_db, dtype=float), (b, self.n_bands))
        det = np.isfinite(level)
        df = self.bandwidth_hz
        tt = self.sonar.integration_time_s
        # step 4: sigma_dW (eq. 11); without a measured SNR, q at the detection threshold
        q_thr = self.sonar.detection_threshold / np.sqrt(df * tt)
        q = np.where(np.isfinite(snr), 10.0 ** (snr / 10.0), q_thr[None, :])
        q = np.maximum(q, 1e-6)
        sd_w = level_sd_db(q, df, tt)
        # step 3: sigma_P (eq. 2) unless the measurement carries it
        sd_p = np.broadcast_to(np.asarray(bearing_sd, dtype=float), (b,)).copy()
        miss = ~np.isfinite(sd_p)
        if miss.any():
            q_ind = indicator_snr(np.where(np.isfinite(snr), snr, 10 * np.log10(q_thr)), df, tt)
            top = np.where(det.any(1), self.n_bands - 1 - np.argmax(det[:, ::-1], axis=1),
                           np.argmax(q_ind, axis=1))
            qb = np.maximum(q_ind[np.arange(b), top], 1.0)
            sd_p[miss] = bearing_sd_deg(self.sonar.beamwidth_deg, qb)[miss]
        sd_p = np.maximum(sd_p, 1e-4)
        self.bearing_sd_deg[:, n] = sd_p
        topb = np.where(det.any(1), self.n_bands - 1 - np.argmax(det[:, ::-1], axis=1), -1)
        self.top_band[:, n] = topb
        self.top_level_db[:, n] = np.where(topb >= 0, level[np.arange(b), np.maximum(topb, 0)], np.nan)
        self.n_cycles = n + 1

        # step 1: maneuver detection (eqs. 26-27 and 29), confirmed on consecutive cycles
        self._maneuver(n, sd_p, sd_w)

        # step 5 (eqs. 20-21) per class
        r_opt = np.full(b, np.nan)
        r_sd = np.full(b, np.nan)
        k_now = self.tables.k_db(obs_depth_m)
        for c in np.unique(self.class_index):
            rows = np.flatnonzero(self.class_index == c)
            off, wts = self.level_offsets[c]
            r_opt[rows], r_sd[rows] = level_range(
                level[rows], det[rows], sd_w[rows], self.p0_db[rows], k_now[c], self.range_axis_m,
                offsets_db=off, weights=wts, gain_db=self.sonar.receiver_gain_db)
        r_sd = np.maximum(r_sd, self.range_axis_m[1] - self.range_axis_m[0])
        have_r = np.isfinite(r_opt)
        # bearings-only cycles keep the last range as a weak prior
        r_prior = np.where(have_r, r_opt, self.last_range_m)
        r_prior_sd = np.where(have_r, r_sd, np.where(np.isfinite(self.last_range_m),
                                                     0.5 * self.last_range_m, np.inf))

        # accumulate the pseudo-linear bearing quadratic form of this cycle
        rho = np.where(np.isfinite(self.last_range_m), self.last_range_m,
                       np.where(have_r, r_opt, 10000.0))
        self._accumulate(n, brg, sd_p, rho)

        # steps 5-6: relative course and course (eqs. 30, 8, 7)
        obs_speed = math.hypot(obs_vx_mps, obs_vy_mps)
        obs_course = math.degrees(math.atan2(obs_vx_mps, obs_vy_mps)) % 360.0
        n_tack = n - self.tack_start + 1
        change = np.abs(wrap180(brg - self.bearing_deg[np.arange(b), self.tack_start]))
        eq30 = (change > p.eq30_factor * sd_p) & (n_tack >= 3)
        if p.curvature_factor > 0 and eq30.any():
            eq30 &= self._curved(n, p.curvature_factor)
        k_rel = np.mod(brg + 180.0, 360.0)                 # reverse bearing
        # sd of the relative course entering eq. 25: sK_rho for eq. 8, wider for the reverse bearing
        self.rel_course_sd_deg = np.where(eq30, p.rel_course_sd_deg, p.reverse_course_sd_deg)
        if eq30.any():
            rows = np.flatnonzero(eq30)
            k_rel[rows] = self._rel_course(rows, n)
        k_fb = course_from_relative_deg(k_rel, self.speed_mean_mps, obs_course, obs_speed)

        # step 8 condition: bearing change over the last 3 minutes > 3 sigma_P
        back = np.searchsorted(self.t_s[:n + 1], t_s - p.eq25_window_s)
        back = np.maximum(back, self.tack_start)
        change3 = np.abs(wrap180(brg - self.bearing_deg[np.arange(b), back]))
        use25 = (change3 > p.eq25_factor * sd_p) & (n_tack >= p.eq25_min_cycles) & np.isfinite(r_prior)

        u = np.array([np.sin(np.radians(brg)), np.cos(np.radians(brg))])   # (2, B)
        course = k_fb.copy()
        speed = self.speed_mean_mps.copy()
        rng_est = r_prior.copy()
        course_sd = np.hypot(p.rel_course_sd_deg, self._dk_dv(k_rel, obs_course, obs_speed) * self.speed_sd_mps)
        speed_sd = self.speed_sd_mps.copy()
        range_sd = r_prior_sd.copy()
        # a new tack starts from the last estimates (step 1) until eq. 25 applies on it
        carry = ~use25 & (self.tack > 1) & (self.last_estimates is not None)
        if carry.any():
            lo = self.last_estimates
            dt = t_s - self.t_s[n - 1]
            a = np.radians(lo["course_deg"])
            px = lo["x_m"] + lo["speed_mps"] * np.sin(a) * dt
            py = lo["y_m"] + lo["speed_mps"] * np.cos(a) * dt
            rc = np.hypot(px - obs_x_m, py - obs_y_m)
            course = np.where(carry, lo["course_deg"], course)
            speed = np.where(carry, lo["speed_mps"], speed)
            rng_est = np.where(carry, rc, rng_est)
        if use25.any():
            rows = np.flatnonzero(use25)
            res = self._search(rows, n, u[:, rows], k_rel[rows], obs_course, obs_speed,
                               r_prior[rows], r_prior_sd[rows])
            if p.polish_iters > 0:
                res = self._polish(rows, n, res, k_rel[rows], obs_course, obs_speed,
                                   r_prior[rows], r_prior_sd[rows])
            course[rows], speed[rows], rng_est[rows] = res[0], res[1], res[2]
            course_sd[rows], speed_sd[rows], range_sd[rows] = res[3], res[4], res[5]
        # raw estimates of this cycle: position and velocity
        x = obs_x_m + rng_est * u[0]
        y = obs_y_m + rng_est * u[1]
        vx = speed * np.sin(np.radians(course))
        vy = speed * np.cos(np.radians(course))
        for key, val in (("course_deg", course), ("speed_mps", speed), ("x_m", x), ("y_m", y),
                         ("vx_mps", vx), ("vy_mps", vy)):
            self.raw[key][:, n] = val
        out = self._smooth(n, obs_x_m, obs_y_m, brg)
        out.update(range_sd_m=range_sd, course_sd_deg=course_sd, speed_sd_mps=speed_sd,
                   tack=self.tack.copy(), used_eq25=use25, r_level_m=r_opt, raw_course_deg=course,
                   raw_speed_mps=speed, raw_range_m=rng_est)
        self.last_range_m = np.where(np.isfinite(out["range_m"]), out["range_m"], self.last_range_m)
        self.last_estimates = out
        return out

    # ------------------------------------------------------------------ pieces
    def _dk_dv(self, k_rel, obs_course, obs_speed):
        """|dK/dV| of eq. 7 at the mean speed, deg per m/s (for the fallback course sd)."""
        h = 0.05
        k1 = course_from_relative_deg(k_rel, self.speed_mean_mps + h, obs_course, obs_speed)
        k0 = course_from_relative_deg(k_rel, np.maximum(self.speed_mean_mps - h, 1e-3), obs_course, obs_speed)
        return np.abs(wrap180(k1 - k0)) / (2 * h)

    def _maneuver(self, n, sd_p, sd_w):
        p, b = self.params, self.n_rows
        rows = np.arange(b)
        fire = np.zeros(b, dtype=bool)
        ok = (n - self.tack_start) >= p.maneuver_l
        if ok.any():
            i_s, i_l = n - p.maneuver_s, n - p.maneuver_l
            ts, tl, tn = self.t_s[i_s], self.t_s[i_l], self.t_s[n]
            ps, pl, pn = self.bearing_deg[:, i_s], self.bearing_deg[:, i_l], self.bearing_deg[:, n]
            rate = wrap180(ps - pl) / (ts - tl)                                     # eq. 27
            fire |= ok & (np.abs(wrap180(ps + rate * (tn - ts) - pn)) > p.maneuver_factor * sd_p)
        # eq. 29: level of the highest band vs its mean over F previous cycles but the last 3
        okl = (n - self.tack_start) >= p.level_f + 3
        if okl.any():
            top = self.top_band[:, n]
            lo = n - 3 - p.level_f
            win_b = self.top_band[:, lo:n - 3]
            win = np.where(win_b == top[:, None], self.top_level_db[:, lo:n - 3], np.nan)
            cnt = np.isfinite(win).sum(1)
            mean = np.where(cnt > p.level_f // 2, np.nansum(win, 1) / np.maximum(cnt, 1), np.nan)
            sdw = np.maximum(sd_w[rows, np.maximum(top, 0)], p.level_sd_floor_db)
            fire |= okl & (top >= 0) & np.isfinite(mean) & \
                (np.abs(mean - self.top_level_db[:, n]) > p.maneuver_factor * sdw)
        self.maneuver_pending = np.where(fire, self.maneuver_pending + 1, 0)
        new = self.maneuver_pending >= p.maneuver_confirm
        if new.any():
            self.tack_start[new] = n - p.maneuver_confirm + 1
            self.tack[new] += 1
            self.maneuver_pending[new] = 0
            self.bearing_form[new] = 0.0
            # rebuild the quadratic form from the confirming cycles on the new tack
            self._rebuild = new

    def _rows_a(self, idx_rows, i, brg, sd_p, rho, t0):
        a = np.radians(brg)
        c, s = np.cos(a), np.sin(a)
        tau = self.t_s[i] - t0
        vec = np.stack([c, -s, c * tau, -s * tau, -(c * self.obs_x_m[i] - s * self.obs_y_m[i])], axis=1)
        w = 1.0 / (np.square(np.radians(sd_p)) * np.square(rho))
        return w[:, None, None] * vec[:, :, None] * vec[:, None, :]

    def _accumulate(self, n, brg, sd_p, rho):
        rebuild = getattr(self, "_rebuild", None)
        if rebuild is not None and rebuild.any():
            rows = np.flatnonzero(rebuild)
            for i in range(int(self.tack_start[rows].min()), n):
                sel = rows[self.tack_start[rows] <= i]
                self.bearing_form[sel] += self._rows_a(sel, i, self.bearing_deg[sel, i], sd_p[sel], rho[sel],
                                            self.t_s[self.tack_start[sel]])
            self._rebuild = None
        self.bearing_form += self._rows_a(None, n, brg, sd_p, rho, self.t_s[self.tack_start])

    def _curved(self, n, factor):
        """Rows whose bearings over the tack curve significantly (eq. 8 is then determined).

        Weighted least-squares fit P(t) = a + b t + c t^2 over the tack (bearings unwrapped from
        the tack's first); True where |c| > factor x sd(c). Eq. 8 rests on the bearing's
        curvature (a straight bearing trace leaves the relative course undetermined), as eq. 30
        rests on its change.
        """
        b = self.n_rows
        lo = int(self.tack_start.min())
        idx = np.arange(lo, n + 1)[None, :]
        on = idx >= self.tack_start[:, None]
        t0 = self.t_s[self.tack_start][:, None]
        tc = np.where(on, self.t_s[None, lo:n + 1] - t0, 0.0)
        scale = np.maximum(tc.max(1, keepdims=True), 1.0)
        x = tc / scale
        y = wrap180(self.bearing_deg[:, lo:n + 1] - self.bearing_deg[np.arange(b), self.tack_start][:, None])
        w = np.where(on, 1.0 / np.square(self.bearing_sd_deg[:, lo:n + 1]), 0.0)
        X = np.stack([np.ones_like(x), x, x * x], axis=2)                  # (B, N, 3)
        XtWX = np.einsum("bni,bn,bnj->bij", X, w, X)
        XtWy = np.einsum("bni,bn,bn->bi", X, w, y)
        ok = on.sum(1) >= 5
        XtWX = np.where(ok[:, None, None], XtWX, np.eye(3)[None])
        try:
            cov = np.linalg.inv(XtWX)
        except np.linalg.LinAlgError:
            return np.zeros(b, dtype=bool)
        coef = np.einsum("bij,bj->bi", cov, np.where(ok[:, None], XtWy, 0.0))
        sd_c = np.sqrt(np.maximum(cov[:, 2, 2], 1e-300))
        return ok & (np.abs(coef[:, 2]) > factor * sd_c)

    def _rel_course(self, rows, n):
        s0 = self.tack_start[rows]
        length = n - s0 + 1
        j = np.arange(self.params.triples)[None, :]
        span = np.maximum(length // 4, 1)[:, None]
        i0 = s0[:, None] + (j * span) // self.params.triples
        i2 = n - (j * span) // self.params.triples
        i1 = (i0 + i2) // 2
        valid = (i0 < i1) & (i1 < i2)
        i0, i1, i2 = (np.clip(v, 0, n) for v in (i0, i1, i2))
        return relative_course_deg(self.t_s[:n + 1], self.bearing_deg[rows, :n + 1], i0, i1, i2, valid)

    @staticmethod
    def _lin_const(f0, f1, c0, c1, C2, k_deg, v):
        vx, vy = v * np.sin(np.radians(k_deg)), v * np.cos(np.radians(k_deg))
        lin = f0 + f1[:, 0] * vx + f1[:, 1] * vy
        const = (c0 + 2.0 * (c1[:, 0] * vx + c1[:, 1] * vy) + C2[:, 0, 0] * vx * vx
                 + 2.0 * C2[:, 0, 1] * vx * vy + C2[:, 1, 1] * vy * vy)
        return lin, const

    def _search(self, rows, n, u, k_rel, obs_course, obs_speed, r_prior, r_prior_sd):
        """Minimise eq. 25 over course x speed (range in closed form) for the given rows."""
        p = self.params
        A = self.bearing_form[rows]
        tau = self.t_s[n] - self.t_s[self.tack_start[rows]]
        g = np.zeros((len(rows), 5))
        g[:, 0], g[:, 1], g[:, 4] = self.obs_x_m[n], self.obs_y_m[n], 1.0
        H = np.zeros((len(rows), 5, 2))
        H[:, 0, 0] = H[:, 1, 1] = -tau
        H[:, 2, 0] = H[:, 3, 1] = 1.0
        ze = np.zeros((len(rows), 5))
        ze[:, 0], ze[:, 1] = u[0], u[1]
        Ag = np.einsum("bij,bj->bi", A, g)
        AH = np.einsum("bij,bjk->bik", A, H)
        Aze = np.einsum("bij,bj->bi", A, ze)
        c0 = np.einsum("bi,bi->b", g, Ag)
        c1 = np.einsum("bi,bik->bk", g, AH)
        C2 = np.einsum("bik,bil->bkl", H, AH)
        f0 = np.einsum("bi,bi->b", ze, Ag)
        f1 = np.einsum("bi,bik->bk", ze, AH)
        e = np.einsum("bi,bi->b", ze, Aze)
        inv_var = np.where(np.isfinite(r_prior_sd), 1.0 / np.square(r_prior_sd), 0.0)
        r0 = np.where(np.isfinite(r_prior), r_prior, 0.0)
        mV, sV = self.speed_mean_mps[rows], self.speed_sd_mps[rows]
        sk2 = np.square(self.rel_course_sd_deg[rows])[:, None]
        r_lo, r_hi = p.range_min_m, self.range_axis_m[-1]
        scale = np.square(np.where(np.isfinite(self.last_range_m[rows]), self.last_range_m[rows],
                                   np.where(np.isfinite(r_prior), r_prior, 10000.0)))

        def cost(k_deg, v):
            """k_deg, v: (b, c) candidates -> cost (b, c), range (b, c)."""
            vx = v * np.sin(np.radians(k_deg))
            vy = v * np.cos(np.radians(k_deg))
            lin = f0[:, None] + f1[:, 0:1] * vx + f1[:, 1:2] * vy
            const = (c0[:, None] + 2.0 * (c1[:, 0:1] * vx + c1[:, 1:2] * vy)
                     + C2[:, 0, 0, None] * vx * vx + 2.0 * C2[:, 0, 1, None] * vx * vy
                     + C2[:, 1, 1, None] * vy * vy)
            # bearing term rho_N^2 (e + 2 lin x + const x^2), x = 1/r (residuals divided by the
            # candidate's own range: no pull toward short ranges); + range prior; Newton in r
            jb = lambda r: scale[:, None] * (e[:, None] + 2.0 * lin / r + const / (r * r))  # noqa: E731
            x_star = -lin / np.maximum(const, 1e-300)
            starts = [np.where(x_star > 0, 1.0 / np.maximum(x_star, 1e-12), r_hi),
                      np.where(inv_var[:, None] > 0, r0[:, None], r_hi) + 0.0 * lin]
            best_r, best_j = None, None
            for r in starts:
                r = np.clip(r, r_lo, r_hi)
                for _ in range(6):
                    x = 1.0 / r
                    g1 = scale[:, None] * (2.0 * lin + 2.0 * const * x)        # dJb/dx
                    g2 = scale[:, None] * 2.0 * const
                    d1 = -g1 * x * x + 2.0 * inv_var[:, None] * (r - r0[:, None])
                    d2 = g2 * x ** 4 + 2.0 * g1 * x ** 3 + 2.0 * inv_var[:, None]
                    step = np.where(d2 > 0, d1 / np.where(d2 > 0, d2, 1.0), np.sign(d1) * 0.2 * r)
                    r = np.clip(r - np.clip(step, -0.5 * r, 0.5 * r), r_lo, r_hi)
                jr = jb(r) + inv_var[:, None] * np.square(r - r0[:, None])
                if best_j is None:
                    best_r, best_j = r, jr
                else:
                    better = jr < best_j
                    best_r, best_j = np.where(better, r, best_r), np.where(better, jr, best_j)
            r, j = best_r, best_j
            mk = course_from_relative_deg(k_rel[:, None], v, obs_course, obs_speed)
            j = j + np.square((v - mV[:, None]) / sV[:, None]) \
                + np.square(wrap180(k_deg - mk)) / sk2
            return j, r

        kk = np.arange(p.n_course) * 360.0 / p.n_course
        vv = np.linspace(np.maximum(mV - p.speed_span_sd * sV, 0.2),
                         mV + p.speed_span_sd * sV, p.n_speed).T               # (b, nv)
        K = np.broadcast_to(kk[None, :, None], (len(rows), p.n_course, p.n_speed))
        V = np.broadcast_to(vv[:, None, :], (len(rows), p.n_course, p.n_speed))
        j, _ = cost(K.reshape(len(rows), -1), V.reshape(len(rows), -1))
        best = np.argmin(j, axis=1)
        kb = K.reshape(len(rows), -1)[np.arange(len(rows)), best]
        vb = V.reshape(len(rows), -1)[np.arange(len(rows)), best]
        dk = np.full(len(rows), 360.0 / p.n_course)
        dv = vv[:, 1] - vv[:, 0]
        off = np.linspace(-1.0, 1.0, 7)
        for _ in range(p.refine_passes):
            kc = kb[:, None, None] + off[None, :, None] * dk[:, None, None]
            vc = np.clip(vb[:, None, None] + off[None, None, :] * dv[:, None, None],
                         vv[:, :1, None], vv[:, -1:, None])     # the polish keeps this interval
            kc, vc = np.broadcast_arrays(kc, vc)
            jj, _ = cost(kc.reshape(len(rows), -1), vc.reshape(len(rows), -1))
            bi = np.argmin(jj, axis=1)
            kb = kc.reshape(len(rows), -1)[np.arange(len(rows)), bi]
            vb = vc.reshape(len(rows), -1)[np.arange(len(rows)), bi]
            dk, dv = dk / 3.0, dv / 3.0
        # final point and curvatures (cost = -2 log L: sd = sqrt(2 / J''))
        h_k, h_v = np.maximum(dk, 0.2), np.maximum(dv, 0.02)
        kc = np.stack([kb, kb - h_k, kb + h_k, kb, kb], axis=1)
        vc = np.stack([vb, vb, vb, np.maximum(vb - h_v, 0.01), vb + h_v], axis=1)
        jj, rr = cost(kc, vc)
        d2k = (jj[:, 1] + jj[:, 2] - 2 * jj[:, 0]) / h_k ** 2
        d2v = (jj[:, 3] + jj[:, 4] - 2 * jj[:, 0]) / h_v ** 2
        k_sd = np.sqrt(2.0 / np.maximum(d2k, 1e-12))
        v_sd = np.sqrt(2.0 / np.maximum(d2v, 1e-12))
        r_c = rr[:, 0]
        h_r = np.maximum(0.01 * r_c, 1.0)
        jr = [scale * (e + 2.0 * lin_r / rx + cst_r / (rx * rx)) + inv_var * (rx - r0) ** 2
              for rx in (r_c - h_r, r_c, r_c + h_r)
              for lin_r, cst_r in [self._lin_const(f0, f1, c0, c1, C2, kb, vb)]]
        r_sd = np.sqrt(2.0 / np.maximum((jr[0] + jr[2] - 2 * jr[1]) / h_r ** 2, 1e-300))
        return (np.mod(kb, 360.0), vb, rr[:, 0], np.minimum(k_sd, 180.0), np.minimum(v_sd, 50.0),
                r_sd)

    def _eq25_residuals(self, rows, n, k_deg, v, r, k_rel, obs_course, obs_speed, r0, r_sd,
                        jacobian: bool = False):
        """Residuals of eq. 25 as written (exact bearing residuals over the tack), (b, N + 3).

        With ``jacobian``, also their derivatives by (course deg, speed m/s, range m),
        (b, N + 3, 3): analytic for the bearings, central differences for mK(v) of eq. 7.
        """
        p = self.params
        lo = int(self.tack_start[rows].min())
        s0 = self.tack_start[rows]
        idx = np.arange(lo, n + 1)[None, :]
        on = idx >= s0[:, None]
        a = np.radians(self.bearing_deg[rows, n])
        dt = (self.t_s[n] - self.t_s[lo:n + 1])[None, :]
        kr = np.radians(k_deg)
        sk, ck = np.sin(kr)[:, None], np.cos(kr)[:, None]
        dx = (self.obs_x_m[n] + r * np.sin(a))[:, None] - v[:, None] * sk * dt - self.obs_x_m[None, lo:n + 1]
        dy = (self.obs_y_m[n] + r * np.cos(a))[:, None] - v[:, None] * ck * dt - self.obs_y_m[None, lo:n + 1]
        pred = np.degrees(np.arctan2(dx, dy))
        inv_sd = np.where(on, 1.0 / self.bearing_sd_deg[rows, lo:n + 1], 0.0)
        res_b = wrap180(self.bearing_deg[rows, lo:n + 1] - pred) * inv_sd
        mk = course_from_relative_deg(k_rel, v, obs_course, obs_speed)
        inv = np.where(np.isfinite(r_sd), 1.0 / r_sd, 0.0)
        res_p = np.stack([(r - np.where(np.isfinite(r0), r0, 0.0)) * inv,
                          (v - self.speed_mean_mps[rows]) / self.speed_sd_mps[rows],
                          wrap180(k_deg - mk) / self.rel_course_sd_deg[rows]], axis=1)
        f = np.concatenate([res_b, res_p], axis=1)
        if not jacobian:
            return f
        # d pred / d(dx, dy) = (dy, -dx) / rho^2 (radians); residual = -(180/pi) pred / sd
        rho2 = np.maximum(dx * dx + dy * dy, 1e-6)
        gx, gy = dy / rho2, -dx / rho2
        c = -np.degrees(1.0) * inv_sd
        vv = v[:, None]
        d_k = c * (gx * (-vv * ck * dt) + gy * (vv * sk * dt)) * (math.pi / 180.0)
        d_v = c * (gx * (-sk * dt) + gy * (-ck * dt))
        d_r = c * (gx * np.sin(a)[:, None] + gy * np.cos(a)[:, None])
        Jb = np.stack([d_k, d_v, d_r], axis=2)
        h = 1e-3
        dmk = wrap180(course_from_relative_deg(k_rel, v + h, obs_course, obs_speed)
                      - course_from_relative_deg(k_rel, np.maximum(v - h, 1e-6), obs_course,
                                                 obs_speed)) / (2 * h)
        Jp = np.zeros((len(rows), 3, 3))
        Jp[:, 0, 2] = inv
        Jp[:, 1, 1] = 1.0 / self.speed_sd_mps[rows]
        Jp[:, 2, 0] = 1.0 / self.rel_course_sd_deg[rows]
        Jp[:, 2, 1] = -dmk / self.rel_course_sd_deg[rows]
        return f, np.concatenate([Jb, Jp], axis=1)

    def _polish(self, rows, n, res, k_rel, obs_course, obs_speed, r0, r_sd):
        """Damped Gauss-Newton on eq. 25 with exact bearing residuals from the search's optimum.

        The grid search minimises the pseudo-linear form of the bearing term (weights from the
        earlier range estimates); this polish makes the estimate the local minimum of eq. 25
        as written. A step is kept only where it lowers the functional; speed stays in the
        search's interval.
        """
        k, v, r = res[0].copy(), res[1].copy(), res[2].copy()
        r_hi = self.range_axis_m[-1]
        mV, sV = self.speed_mean_mps[rows], self.speed_sd_mps[rows]               # the search's speed interval
        v_lo = np.maximum(mV - self.params.speed_span_sd * sV, 0.2)
        v_hi = mV + self.params.speed_span_sd * sV
        args = (k_rel, obs_course, obs_speed, r0, r_sd)
        f, J = self._eq25_residuals(rows, n, k, v, r, *args, jacobian=True)
        cost = np.square(f).sum(1)
        lam = np.full(len(rows), 1e-3)
        for it in range(self.params.polish_iters):
            Jt = J.transpose(0, 2, 1)
            JtJ = Jt @ J
            g = (Jt @ f[:, :, None])[:, :, 0]
            diag = np.einsum("bii->bi", JtJ)
            A = JtJ + (lam[:, None] * np.maximum(diag, 1e-12))[:, :, None] * np.eye(3)[None]
            try:
                step = -np.linalg.solve(A, g[:, :, None])[:, :, 0]
            except np.linalg.LinAlgError:
                break
            if np.all((np.abs(step[:, 0]) < 1e-3) & (np.abs(step[:, 1]) < 1e-4)
                      & (np.abs(step[:, 2]) < 1e-5 * r)):
                break                                        # converged everywhere
            k1 = k + step[:, 0]
            v1 = np.clip(v + step[:, 1], v_lo, v_hi)
            r1 = np.clip(r + step[:, 2], self.params.range_min_m, r_hi)
            last = it == self.params.polish_iters - 1
            out = self._eq25_residuals(rows, n, k1, v1, r1, *args, jacobian=not last)
            f1, J1 = (out, None) if last else out
            c1 = np.square(f1).sum(1)
            ok = np.isfinite(c1) & (c1 < cost)
            k, v, r = np.where(ok, k1, k), np.where(ok, v1, v), np.where(ok, r1, r)
            if last:
                break
            f = np.where(ok[:, None], f1, f)
            J = np.where(ok[:, None, None], J1, J)
            cost = np.where(ok, c1, cost)
            lam = np.where(ok, lam * 0.3, lam * 10.0)
        return (np.mod(k, 360.0), v, r) + tuple(res[3:])

    def _smooth(self, n, ox, oy, brg):
        """Robust smoothing over the last L cycles of each row's tack (step 9)."""
        p, b = self.params, self.n_rows
        lo = np.maximum(self.tack_start, n - p.smooth_cycles + 1)
        count = n - lo + 1
        width = p.smooth_cycles
        idx = lo[:, None] + np.arange(width)[None, :]
        idx = np.minimum(idx, n)
        g = lambda key: np.take_along_axis(self.raw[key], idx, axis=1)  # noqa: E731
        dt = self.t_s[n] - self.t_s[idx]
        px = g("x_m") + g("vx_mps") * dt
        py = g("y_m") + g("vy_mps") * dt
        rng = np.hypot(px - ox, py - oy)
        course_raw = g("course_deg")
        ref = self.raw["course_deg"][:, n]
        course_u = ref[:, None] + wrap180(course_raw - ref[:, None])
        out_r = trimmed_mean(rng, count, p.smooth_drop, width)
        out_k = trimmed_mean(course_u, count, p.smooth_drop, width)
        out_v = trimmed_mean(g("speed_mps"), count, p.smooth_drop, width)
        if p.smooth_passes > 1:
            out_r, out_k, out_v = self._second_pass(n, out_r, out_k, out_v, count)
        a = np.radians(brg)
        return {"range_m": out_r, "course_deg": np.mod(out_k, 360.0), "speed_mps": out_v,
                "x_m": ox + out_r * np.sin(a), "y_m": oy + out_r * np.cos(a),
                "bearing_deg": brg.copy()}

    def _second_pass(self, n, r, k, v, count):
        s1 = self.smoothed
        s1["range_m"][:, n], s1["course_deg"][:, n], s1["speed_mps"][:, n] = r, k, v
        width = self.params.smooth_cycles
        lo = np.maximum(self.tack_start, n - width + 1)
        idx = np.minimum(lo[:, None] + np.arange(width)[None, :], n)
        g = lambda key: np.take_along_axis(s1[key], idx, axis=1)  # noqa: E731
        ku = k[:, None] + wrap180(g("course_deg") - k[:, None])
        return (trimmed_mean(g("range_m"), count, self.params.smooth_drop, width),
                trimmed_mean(ku, count, self.params.smooth_drop, width),
                trimmed_mean(g("speed_mps"), count, self.params.smooth_drop, width))
