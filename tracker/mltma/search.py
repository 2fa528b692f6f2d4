"""The fast search for eq. 25's minimum: the bearing term in pseudo-linear form
(`tracker.mltma.bearing_form`), range in closed form, course x speed on a grid refined twice.

For fixed course and speed the functional is a function of range alone, minimised by Newton
steps; the search runs over course (24 values) x speed (20 values over mV +- 3 sV) and is
refined twice on 7 x 7 local grids, each a third of the last step. The sds come from the
curvature of the functional at the optimum (J = -2 log L: sd = sqrt(2 / J'')).

The form F weights bearing i with 1 / rho_i^2, rho_i the range estimate when it arrived. The
search divides the bearing term by the candidate's own range instead, rho^2 z^T F z / r^2 with
rho the latest range estimate: the residuals are then angles (no pull toward short ranges).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from tracker.mltma.bearing_form import RangeQuadratic, velocity_terms
from tracker.mltma.course import course_from_relative_deg, wrap180
from tracker.mltma.eq25 import Eq25Estimate, Eq25Terms, speed_interval_mps
from tracker.mltma.params import MLParams


class RangeTerms(NamedTuple):
    """The parts of eq. 25 that depend on range, per row: arrays (b,), or (b, 1) against
    (b, c) candidates (`per_candidate`)."""

    e: np.ndarray          # coefficient of r^2 in z^T F z (`RangeQuadratic.e`)
    scale_m2: np.ndarray   # rho^2: the bearing term is rho^2 z^T F z / r^2, m^2
    r0_m: np.ndarray       # R_opt of the range term (0 where there is none), m
    inv_var: np.ndarray    # 1 / sigma_R^2 (0: no range term), 1/m^2

    def per_candidate(self) -> RangeTerms:
        return RangeTerms(*(a[:, None] for a in self))


def range_cost(rt: RangeTerms, lin, const, range_m):
    """The bearing and range terms of eq. 25 at ``range_m``, from lin and const of the form:
    rho^2 (e + 2 lin / r + const / r^2) + (r - R_opt)^2 / sigma_R^2."""
    return (rt.scale_m2 * (rt.e + 2.0 * lin / range_m + const / (range_m * range_m))
            + rt.inv_var * np.square(range_m - rt.r0_m))


def best_range(rt: RangeTerms, lin, const, range_min_m: float, range_max_m: float):
    """Range minimising `range_cost` for each candidate: 6 Newton steps in r (derivatives by
    way of x = 1 / r) from two starts (the bearing term's own minimum, and R_opt), the better
    kept.

    ``rt``'s arrays are (b, 1), ``lin`` and ``const`` (b, c). Returns range_m, cost, (b, c).
    """
    scale, r0, inv_var = rt.scale_m2, rt.r0_m, rt.inv_var
    x_star = -lin / np.maximum(const, 1e-300)
    starts = [np.where(x_star > 0, 1.0 / np.maximum(x_star, 1e-12), range_max_m),
              np.where(inv_var > 0, r0, range_max_m) + 0.0 * lin]
    best_r, best_j = None, None
    for r in starts:
        r = np.clip(r, range_min_m, range_max_m)
        for _ in range(6):
            x = 1.0 / r
            g1 = scale * (2.0 * lin + 2.0 * const * x)        # dJb/dx
            g2 = scale * 2.0 * const
            d1 = -g1 * x * x + 2.0 * inv_var * (r - r0)
            d2 = g2 * x ** 4 + 2.0 * g1 * x ** 3 + 2.0 * inv_var
            step = np.where(d2 > 0, d1 / np.where(d2 > 0, d2, 1.0), np.sign(d1) * 0.2 * r)
            r = np.clip(r - np.clip(step, -0.5 * r, 0.5 * r), range_min_m, range_max_m)
        jr = range_cost(rt, lin, const, r)
        if best_j is None:
            best_r, best_j = r, jr
        else:
            better = jr < best_j
            best_r, best_j = np.where(better, r, best_r), np.where(better, jr, best_j)
    return best_r, best_j


def candidate_cost(q: RangeQuadratic, rt: RangeTerms, terms: Eq25Terms, course_deg, speed_mps,
                   range_min_m: float, range_max_m: float):
    """Eq. 25 (pseudo-linear bearing term) at (b, c) candidates, range minimised for each.

    Returns cost, range_m, both (b, c).
    """
    lin, const = velocity_terms(q, course_deg, speed_mps)
    r, j = best_range(rt.per_candidate(), lin, const, range_min_m, range_max_m)
    mk = course_from_relative_deg(terms.rel_course_deg[:, None], speed_mps, terms.obs_course_deg,
                                  terms.obs_speed_mps)
    j = j + np.square((speed_mps - terms.speed_mean_mps[:, None]) / terms.speed_sd_mps[:, None]) \
        + np.square(wrap180(course_deg - mk)) / np.square(terms.rel_course_sd_deg)[:, None]
    return j, r


def search(q: RangeQuadratic, terms: Eq25Terms, *, rho_m, range_min_m: float,
           range_max_m: float, params: MLParams) -> Eq25Estimate:
    """Minimise eq. 25 over course x speed, range in closed form, for b rows.

    Parameters
    ----------
    q : RangeQuadratic
        The rows' bearing form at the current cycle (`tracker.mltma.bearing_form`).
    terms : Eq25Terms
    rho_m : ndarray, shape (b,)
        The latest range estimate, m: the bearing term is scaled by rho^2 / r^2.
    range_min_m, range_max_m : float
        Range bounds, m.
    params : MLParams
        Grid sizes (``n_course``, ``n_speed``, ``speed_span_sd``, ``refine_passes``).

    Returns
    -------
    Eq25Estimate
        Course in [0, 360); sds capped at 180 deg and 50 m/s.
    """
    p, b = params, len(rho_m)
    rt = RangeTerms(e=q.e, scale_m2=np.square(rho_m),
                    r0_m=np.where(np.isfinite(terms.range_m), terms.range_m, 0.0),
                    inv_var=np.where(np.isfinite(terms.range_sd_m),
                                     1.0 / np.square(terms.range_sd_m), 0.0))

    def cost(course_deg, speed_mps):
        return candidate_cost(q, rt, terms, course_deg, speed_mps, range_min_m, range_max_m)

    # global grid
    kk = np.arange(p.n_course) * 360.0 / p.n_course
    vv = np.linspace(*speed_interval_mps(terms, p.speed_span_sd), p.n_speed).T   # (b, nv)
    K = np.broadcast_to(kk[None, :, None], (b, p.n_course, p.n_speed))
    V = np.broadcast_to(vv[:, None, :], (b, p.n_course, p.n_speed))
    j, _ = cost(K.reshape(b, -1), V.reshape(b, -1))
    best = np.argmin(j, axis=1)
    kb = K.reshape(b, -1)[np.arange(b), best]
    vb = V.reshape(b, -1)[np.arange(b), best]
    # refinement on 7 x 7 local grids, each a third of the last step
    dk = np.full(b, 360.0 / p.n_course)
    dv = vv[:, 1] - vv[:, 0]
    off = np.linspace(-1.0, 1.0, 7)
    for _ in range(p.refine_passes):
        kc = kb[:, None, None] + off[None, :, None] * dk[:, None, None]
        vc = np.clip(vb[:, None, None] + off[None, None, :] * dv[:, None, None],
                     vv[:, :1, None], vv[:, -1:, None])     # the polish keeps this interval
        kc, vc = np.broadcast_arrays(kc, vc)
        jj, _ = cost(kc.reshape(b, -1), vc.reshape(b, -1))
        bi = np.argmin(jj, axis=1)
        kb = kc.reshape(b, -1)[np.arange(b), bi]
        vb = vc.reshape(b, -1)[np.arange(b), bi]
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
    lin, const = velocity_terms(q, kb, vb)
    jr = [range_cost(rt, lin, const, rx) for rx in (r_c - h_r, r_c, r_c + h_r)]
    r_sd = np.sqrt(2.0 / np.maximum((jr[0] + jr[2] - 2 * jr[1]) / h_r ** 2, 1e-300))
    return Eq25Estimate(course_deg=np.mod(kb, 360.0), speed_mps=vb, range_m=r_c,
                        course_sd_deg=np.minimum(k_sd, 180.0), speed_sd_mps=np.minimum(v_sd, 50.0),
                        range_sd_m=r_sd)
