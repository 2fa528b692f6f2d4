"""Moments of one run's particles with the target's depth as a state (eqs. 29-30), as
`tracker.rpf.kernel.estimate.moments_run`, with a one-pass covariance for the depth state with
the source-level offset (D = 6).

`moments_run` sums each of the D (D + 1) / 2 entries in its own pass over the particles (21
passes for D = 6); here the 21 sums stay in registers through one pass. A separate function
rather than a branch of `moments_run`: the fixed-depth loop compiles that one, and a new branch
there moves its results in the last bits (LLVM vectorizes the other branches differently).
"""

from __future__ import annotations

from numba import njit

from tracker.rpf.kernel.estimate import moments_run
from tracker.rpf.kernel.fastmath import FASTMATH


@njit(fastmath=FASTMATH, error_model="numpy")
def moments_depth_run(state, w, mean, cov):
    """Weighted mean (eq. 29) and covariance (eq. 30) of one run's particles, into ``mean``
    (D,) and ``cov`` (D, D); ``state`` is (D, N). D = 6 in one pass, else `moments_run`."""
    if state.shape[0] != 6:
        moments_run(state, w, mean, cov)
        return
    m0 = m1 = m2 = m3 = m4 = m5 = 0.0
    for i in range(w.size):
        wi = w[i]
        m0 += state[0, i] * wi
        m1 += state[1, i] * wi
        m2 += state[2, i] * wi
        m3 += state[3, i] * wi
        m4 += state[4, i] * wi
        m5 += state[5, i] * wi
    mean[0], mean[1], mean[2], mean[3], mean[4], mean[5] = m0, m1, m2, m3, m4, m5
    c00 = c01 = c02 = c03 = c04 = c05 = c11 = c12 = c13 = c14 = c15 = 0.0
    c22 = c23 = c24 = c25 = c33 = c34 = c35 = c44 = c45 = c55 = 0.0
    for i in range(w.size):
        a0 = state[0, i] - m0
        a1 = state[1, i] - m1
        a2 = state[2, i] - m2
        a3 = state[3, i] - m3
        a4 = state[4, i] - m4
        a5 = state[5, i] - m5
        wi = w[i]
        b0 = a0 * wi
        b1 = a1 * wi
        b2 = a2 * wi
        b3 = a3 * wi
        b4 = a4 * wi
        b5 = a5 * wi
        c00 += a0 * b0
        c01 += a0 * b1
        c02 += a0 * b2
        c03 += a0 * b3
        c04 += a0 * b4
        c05 += a0 * b5
        c11 += a1 * b1
        c12 += a1 * b2
        c13 += a1 * b3
        c14 += a1 * b4
        c15 += a1 * b5
        c22 += a2 * b2
        c23 += a2 * b3
        c24 += a2 * b4
        c25 += a2 * b5
        c33 += a3 * b3
        c34 += a3 * b4
        c35 += a3 * b5
        c44 += a4 * b4
        c45 += a4 * b5
        c55 += a5 * b5
    sums = ((c00, c01, c02, c03, c04, c05), (c01, c11, c12, c13, c14, c15),
            (c02, c12, c22, c23, c24, c25), (c03, c13, c23, c33, c34, c35),
            (c04, c14, c24, c34, c44, c45), (c05, c15, c25, c35, c45, c55))
    for a in range(6):
        row = sums[a]
        for b in range(6):
            cov[a, b] = row[b]
