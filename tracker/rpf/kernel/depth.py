"""The target's depth in the compiled kernel: K at a particle's depth, bearing and range, the
depth's slow random walk and the reflection that keeps it in the water.

K comes from the (depth, range) slabs of `acoustics.grid.targetdepth.TargetDepthK` (one per
radial, one on a flat grid), loaded once for the class and band: bilinear in depth and range,
linear between the two radials around the cycle's measured bearing (weights computed once per
cycle), the cells without water carrying the trackers' penalty already
(`TargetDepthK.level_table`). As `tables.LevelProfile`: ranges below the axis take the first
value, beyond it the last value less ``BEYOND_GRID_PENALTY_DB``; depths outside the axis take
the end rows (the particles are kept inside the prior's span anyway).

What it costs (docs/depth.md, "Cost"): the walk and the level likelihood run as one pass over
the particles (`walk_level_pass`), the two slabs of the cycle taken out of the table once
before it, and a particle's cell found by index arithmetic on the grid's regular axes
(`regular_cell`; equal steps, the depth axis's last step shorter where it ends at the deepest
bottom), by a search (`axis_cell`) only on other axes.
"""

from __future__ import annotations

import math

import numpy as np
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
def regular_cell(v, axis, first, inv_step, start=0):
    """Cell j and weight f of ``v`` on an axis of equal steps whose last step may be shorter (a
    grid's depth axis ends at the deepest bottom), by index arithmetic instead of a search; as
    `axis_cell`, v = (1 - f) axis[j] + f axis[j + 1], the ends held. The axis is regular from
    index ``start`` on (a table from the observer has near-surface rows before: searched),
    ``first`` is axis[start], ``inv_step`` 1 / the step
    (`tracker.rpf.kernel.depthparams.regular_part`)."""
    m = axis.size
    if start > 0 and v < first:
        return axis_cell(v, axis[:start + 1])
    u = (v - first) * inv_step
    if u <= 0.0:
        return start, 0.0
    j = int(u) + start
    if j < m - 2:
        return j, u - (j - start)
    last = axis[m - 1]
    if v >= last:
        return m - 2, 1.0
    return m - 2, (v - axis[m - 2]) / (last - axis[m - 2])


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
    """K at range ``r`` and target depth ``z``, dB: slabs ``j0`` and ``j1`` of one band's ``k_db`` (J, Z, R),
    the second of weight ``w1`` (not read when 0), less the penalty beyond the range axis; the
    cells by search on any axes. `walk_level_pass` applies the same rule (`pass_k_db`)."""
    jz, fz = axis_cell(z, depth_m)
    jr, fr = axis_cell(r, range_m)
    k = slab_k(k_db[j0], jz, fz, jr, fr)
    if w1 > 0.0:
        k = k + w1 * (slab_k(k_db[j1], jz, fz, jr, fr) - k)
    if r > range_m[range_m.size - 1]:
        k -= BEYOND_GRID_PENALTY_DB
    return k


@njit(inline="always")
def source_level(vx, vy, ovx, ovy, ross, p0_db):
    """SL of eq. 12 at the particle's target speed (Ross), or the constant ``p0_db``, dB."""
    if ross:
        tvx = vx + ovx
        tvy = vy + ovy
        v = max(math.sqrt(tvx * tvx + tvy * tvy), ROSS_MIN_SPEED_MPS)
        return ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE * math.log10(v / ROSS_REFERENCE_SPEED_MPS)
    return p0_db


@njit(inline="always")
def reflect(z, lo, hi):
    """``z`` folded back into [lo, hi] at its ends (a random walk with reflecting walls)."""
    if z < lo:
        z = 2.0 * lo - z
    if z > hi:
        z = 2.0 * hi - z
    return min(max(z, lo), hi)


@njit(inline="always")
def walk_level_pass(state, iz, io, log_w, g, step_sd, lo, hi, level_db, ovx, ovy, ross, p0_db,
                    table, band, j0, j1, w1, half_inv_var, var_l):
    """The depth's walk (``step_sd`` > 0: z += step_sd g, reflected into [lo, hi]) and the level
    log-likelihood of one band (eq. 33, h_l = SL + K(z, r) + offset, eqs. 12 and 16, K at the
    particle's new depth) added to ``log_w``, in one pass over a run's particles.

    ``state`` (D, N), the depth in row ``iz``, the source-level offset in row ``io`` (< 0: none);
    ``table`` a `tracker.rpf.kernel.depthparams.DepthTable`, ``band`` its band, ``j0``, ``j1``,
    ``w1`` the cycle's slabs. With the table's K error sd (``has_sd``) the variance is
    ``var_l`` + sd^2 at the particle (its -1/2 ln is left out, as `tracker.rpf.likelihood` says
    why), else 1 / (2 ``half_inv_var``). The slabs and axes are taken out of the table here,
    once: a slice or an array read from a tuple per particle costs a reference count each (it
    was most of the depth state's cost).
    """
    slab0 = table.k_db[band, j0]
    slab1 = table.k_db[band, j1]
    has_sd = table.has_sd
    sd0 = table.k_sd_db[band if has_sd else 0, j0 if has_sd else 0]
    sd1 = table.k_sd_db[band if has_sd else 0, j1 if has_sd else 0]
    depth_m, range_m, regular = table.depth_m, table.range_m, table.regular
    z0, dz_inv, r0, dr_inv = (table.depth_first_m, table.depth_inv_step, table.range_first_m,
                              table.range_inv_step)
    z_start = table.depth_regular_from
    r_last = range_m[range_m.size - 1]
    z_row, x_row, y_row, vx_row, vy_row = state[iz], state[0], state[1], state[2], state[3]
    # K by the rule of `k_at_depth`, written out here: a helper taking the slabs and axes,
    # inlined one level deeper, brings the reference counts back into the loop
    for i in range(log_w.size):
        z = z_row[i]
        if step_sd > 0.0:
            z = reflect(z + step_sd * g[i], lo, hi)
            z_row[i] = z
        x, y = x_row[i], y_row[i]
        r = math.sqrt(x * x + y * y)
        off = state[io, i] if io >= 0 else 0.0
        sl = source_level(vx_row[i], vy_row[i], ovx, ovy, ross, p0_db)
        if regular:
            jz, fz = regular_cell(z, depth_m, z0, dz_inv, z_start)
            jr, fr = regular_cell(r, range_m, r0, dr_inv)
        else:
            jz, fz = axis_cell(z, depth_m)
            jr, fr = axis_cell(r, range_m)
        k = slab_k(slab0, jz, fz, jr, fr)
        if w1 > 0.0:
            k = k + w1 * (slab_k(slab1, jz, fz, jr, fr) - k)
        if r > r_last:
            k -= BEYOND_GRID_PENALTY_DB
        d = level_db - (sl + k + off)
        if has_sd:
            sd = slab_k(sd0, jz, fz, jr, fr)
            if w1 > 0.0:
                sd = sd + w1 * (slab_k(sd1, jz, fz, jr, fr) - sd)
            log_w[i] -= 0.5 * (d * d) / (var_l + sd * sd)
        else:
            log_w[i] -= (d * d) * half_inv_var


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


@njit(fastmath=FASTMATH, error_model="numpy")
def pass_k_db(r, z, table, band, j0, j1, w1):
    """K at range ``r`` and target depth ``z``, dB, as `walk_level_pass` computes it: the pass run
    on one particle at (r, 0) with SL 1e4 dB, no walk and no offset, K read back from the
    log-likelihood -(1e4 + K)^2 / 2 (for tests; K > -1e4 dB, the cells without water included;
    a table without a K error sd)."""
    state = np.zeros((5, 1))
    state[0, 0] = r
    state[4, 0] = z
    log_w = np.zeros(1)
    walk_level_pass(state, 4, -1, log_w, np.zeros(1), 0.0, z, z, 0.0, 0.0, 0.0, False, 1e4,
                    table, band, j0, j1, w1, 0.5, 1.0)
    return math.sqrt(-2.0 * log_w[0]) - 1e4
