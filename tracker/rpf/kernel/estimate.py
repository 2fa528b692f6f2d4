"""Moments of one run's particles in the compiled kernel: weighted mean and covariance
(eqs. 29-30) and the particle spreads of a track file, as `tracker.rpf.estimate`."""

from __future__ import annotations

import math

from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def moments_run(state, w, mean, cov):
    """Weighted mean (eq. 29) and covariance (eq. 30) of one run's particles, into ``mean``
    (D,) and ``cov`` (D, D); ``state`` is (D, N)."""
    d, n = state.shape
    for a in range(d):
        acc = 0.0
        for i in range(n):
            acc += state[a, i] * w[i]
        mean[a] = acc
    _cov_run(state, w, mean, cov)


@njit(inline="always")
def _cov_run(state, w, mean, cov):
    d, n = state.shape
    if d == 4:
        m0, m1, m2, m3 = mean[0], mean[1], mean[2], mean[3]
        c00 = c01 = c02 = c03 = c11 = c12 = c13 = c22 = c23 = c33 = 0.0
        for i in range(n):
            a0 = state[0, i] - m0
            a1 = state[1, i] - m1
            a2 = state[2, i] - m2
            a3 = state[3, i] - m3
            wi = w[i]
            b0 = a0 * wi
            b1 = a1 * wi
            b2 = a2 * wi
            b3 = a3 * wi
            c00 += a0 * b0
            c01 += a0 * b1
            c02 += a0 * b2
            c03 += a0 * b3
            c11 += a1 * b1
            c12 += a1 * b2
            c13 += a1 * b3
            c22 += a2 * b2
            c23 += a2 * b3
            c33 += a3 * b3
        cov[0, 0] = c00
        cov[0, 1] = cov[1, 0] = c01
        cov[0, 2] = cov[2, 0] = c02
        cov[0, 3] = cov[3, 0] = c03
        cov[1, 1] = c11
        cov[1, 2] = cov[2, 1] = c12
        cov[1, 3] = cov[3, 1] = c13
        cov[2, 2] = c22
        cov[2, 3] = cov[3, 2] = c23
        cov[3, 3] = c33
        return
    for a in range(d):
        for b in range(a + 1):
            acc = 0.0
            ma = mean[a]
            mb = mean[b]
            for i in range(n):
                acc += (state[a, i] - ma) * ((state[b, i] - mb) * w[i])
            cov[a, b] = acc
            cov[b, a] = acc


@njit(fastmath=FASTMATH, error_model="numpy")
def particle_sds_run(state, w, ovx, ovy, out):
    """Weighted sd of range (m), course (deg, circular) and target speed (m/s), as
    `tracker.rpf.estimate.particle_sds`."""
    n = w.size
    mr = ms = mc = msn = 0.0
    for i in range(n):
        x, y = state[0, i], state[1, i]
        vx, vy = state[2, i] + ovx, state[3, i] + ovy
        r = math.sqrt(x * x + y * y)
        sp = math.sqrt(vx * vx + vy * vy)
        course = math.atan2(vx, vy)
        mr += w[i] * r
        ms += w[i] * sp
        mc += w[i] * math.cos(course)
        msn += w[i] * math.sin(course)
    vr = vs = 0.0
    for i in range(n):
        x, y = state[0, i], state[1, i]
        vx, vy = state[2, i] + ovx, state[3, i] + ovy
        dr = math.sqrt(x * x + y * y) - mr
        ds = math.sqrt(vx * vx + vy * vy) - ms
        vr += w[i] * dr * dr
        vs += w[i] * ds * ds
    res = min(max(math.sqrt(mc * mc + msn * msn), 1e-300), 1.0)
    out[0] = math.sqrt(max(vr, 0.0))
    out[1] = math.degrees(math.sqrt(-2.0 * math.log(res)))
    out[2] = math.sqrt(max(vs, 0.0))

