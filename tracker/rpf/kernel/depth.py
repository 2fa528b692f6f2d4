"""The target's depth in the compiled kernel: K at a particle's depth, bearing and range, the
depth's prior draw, its slow random walk and the reflection that keeps it in the water.

K comes from the (depth, range) slabs of `acoustics.grid.targetdepth.TargetDepthK` (one per
radial, one on a flat grid), loaded once for the class and band: bilinear in depth and range,
linear between the two radials around the cycle's measured bearing (weights computed once per
cycle), the cells without water carrying the trackers' penalty already
(`TargetDepthK.level_table`). As `tables.LevelProfile`: ranges below the axis take the first
value, beyond it the last value less ``BEYOND_GRID_PENALTY_DB``; depths outside the axis take
the end rows (the particles are kept inside the prior's span anyway).
"""

from __future__ import annotations

import math

from numba import njit

from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from envdata.classes import ROSS_LEVEL_DB, ROSS_MIN_SPEED_MPS, ROSS_REFERENCE_SPEED_MPS, ROSS_SLOPE_DB_PER_DECADE
from tracker.rpf.kernel.fastmath import FASTMATH


@njit(inline="always")
def axis_cell(v, axis):
    """Cell j and weight f of ``v`` on an increasing axis, v = (1 - f) axis[j] + f axis[j + 1],
    the ends held (f in [0, 1]); a first guess as if the axis were uniform, then a walk."""
    m = axis.size
    if m < 2 or v <= axis[0]:
        return 0, 0.0
    if v >= axis[m - 1]:
        return m - 2, 1.0
    j = int((v - axis[0]) / (axis[m - 1] - axis[0]) * (m - 1))
    if j > m - 2:
        j = m - 2
    while j > 0 and axis[j] > v:
        j -= 1
    while j < m - 2 and axis[j + 1] <= v:
        j += 1
    return j, (v - axis[j]) / (axis[j + 1] - axis[j])


@njit(inline="always")
def slab_k(slab, jz, fz, jr, fr):
    """Bilinear K of one (depth, range) slab at cell (jz, fz) in depth and (jr, fr) in range."""
    jz1 = min(jz + 1, slab.shape[0] - 1)
    jr1 = min(jr + 1, slab.shape[1] - 1)
    low = slab[jz, jr] + fr * (slab[jz, jr1] - slab[jz, jr])
    high = slab[jz1, jr] + fr * (slab[jz1, jr1] - slab[jz1, jr])
    return low + fz * (high - low)


@njit(fastmath=FASTMATH, error_model="numpy")
def k_at_depth(r, z, depth_m, range_m, k_db, j0, j1, w1):
    """K at range ``r`` and target depth ``z``, dB: slabs ``j0`` and ``j1`` of ``k_db`` (J, Z, R),
    the second of weight ``w1`` (not read when 0), less the penalty beyond the range axis."""
    jz, fz = axis_cell(z, depth_m)
    jr, fr = axis_cell(r, range_m)
    k = slab_k(k_db[j0], jz, fz, jr, fr)
    if w1 > 0.0:
        k = k + w1 * (slab_k(k_db[j1], jz, fz, jr, fr) - k)
    if r > range_m[range_m.size - 1]:
        k -= BEYOND_GRID_PENALTY_DB
    return k


@njit(fastmath=FASTMATH, error_model="numpy")
def level_loglik_depth_particle(x, y, vx, vy, offset_db, z, level_db, ovx, ovy, ross, p0_db,
                                table, j0, j1, w1, half_inv_var):
    """Log of eq. 33 up to a constant with K at the particle's depth: h_l = SL + K(z, r) + offset
    (eqs. 12, 16); ``table`` a `tracker.rpf.kernel.depthparams.DepthTable`."""
    r = math.sqrt(x * x + y * y)
    if ross:
        tvx = vx + ovx
        tvy = vy + ovy
        v = max(math.sqrt(tvx * tvx + tvy * tvy), ROSS_MIN_SPEED_MPS)
        sl = ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE * math.log10(v / ROSS_REFERENCE_SPEED_MPS)
    else:
        sl = p0_db
    k = k_at_depth(r, z, table.depth_m, table.range_m, table.k_db, j0, j1, w1)
    d = level_db - (sl + k + offset_db)
    return -(d * d) * half_inv_var


@njit(inline="always")
def reflect(z, lo, hi):
    """``z`` folded back into [lo, hi] at its ends (a random walk with reflecting walls)."""
    if z < lo:
        z = 2.0 * lo - z
    if z > hi:
        z = 2.0 * hi - z
    return min(max(z, lo), hi)


@njit(inline="always")
def walk_pass(z, g, step_sd, lo, hi):
    """The depth's random walk over a run's particles: z += step_sd g, reflected into [lo, hi]."""
    for i in range(z.size):
        z[i] = reflect(z[i] + step_sd * g[i], lo, hi)


@njit(inline="always")
def reflect_pass(z, lo, hi):
    """Every particle's depth folded back into [lo, hi] (after the regularization's jitter)."""
    for i in range(z.size):
        z[i] = reflect(z[i], lo, hi)
