"""Log-likelihoods in the compiled kernel: bearings (eq. 32) and levels (eqs. 12, 16, 33).

As `tracker.rpf.likelihood`, one particle at a time: the bearing residual is the `atan2` of
the particle position rotated by -theta (in (-pi, pi]); the level model is h_l = SL(v) + K(r)
(+ offset), SL the Ross level of the particle's target speed (eq. 12, constants of
`envdata.classes`) or the constant P0, and K(r) by the `tracker.tables.LevelProfile` rule.
"""

from __future__ import annotations

import math

from numba import njit

from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from envdata.classes import ROSS_LEVEL_DB, ROSS_MIN_SPEED_MPS, ROSS_REFERENCE_SPEED_MPS, ROSS_SLOPE_DB_PER_DECADE
from tracker.rpf.kernel.fastmath import FASTMATH, atan2


@njit(inline="always")
def bearing_loglik_particle(x, y, cos_z, sin_z, half_inv_var):
    """Log of eq. 32 up to a constant; the residual is atan2 of (x, y) rotated by -theta."""
    east = x * cos_z - y * sin_z
    north = y * cos_z + x * sin_z
    resid = atan2(east, north)
    return -(resid * resid) * half_inv_var


@njit(inline="always")
def bearing_pass(x, y, log_w, cz, sz, half_b):
    """Eq. 32 added to the log-weights ``log_w`` of 1-D particle arrays ``x``, ``y``; ``cz``,
    ``sz`` are cos and sin of the measured bearing, ``half_b`` = 1 / (2 sigma_theta^2)."""
    for i in range(log_w.size):
        log_w[i] += bearing_loglik_particle(x[i], y[i], cz, sz, half_b)


@njit(fastmath=FASTMATH, error_model="numpy")
def k_at(r, xp, fp, m):
    """K(r) of `tables.LevelProfile`: ``np.interp`` on the first ``m`` points of (xp, fp)
    (end values held), less the beyond-grid penalty past the last range."""
    x0 = xp[0]
    xl = xp[m - 1]
    if r <= x0:
        return fp[0]
    if r >= xl:
        if r > xl:
            return fp[m - 1] - BEYOND_GRID_PENALTY_DB
        return fp[m - 1]
    # first guess as if the axis were uniform, then walk to xp[j] <= r < xp[j + 1]
    j = int((r - x0) / (xl - x0) * (m - 1))
    if j > m - 2:
        j = m - 2
    while j > 0 and xp[j] > r:
        j -= 1
    while j < m - 2 and xp[j + 1] <= r:
        j += 1
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    return slope * (r - xp[j]) + fp[j]


@njit(fastmath=FASTMATH, error_model="numpy")
def level_prediction_particle(x, y, vx, vy, ovx, ovy, ross, p0_db, xp, fp, m):
    """h_l of eqs. 12, 16 of one particle: SL (Ross at its target speed, or P0) + K(r)."""
    r = math.sqrt(x * x + y * y)
    if ross:
        tvx = vx + ovx
        tvy = vy + ovy
        v = max(math.sqrt(tvx * tvx + tvy * tvy), ROSS_MIN_SPEED_MPS)
        sl = ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE * math.log10(v / ROSS_REFERENCE_SPEED_MPS)
    else:
        sl = p0_db
    return sl + k_at(r, xp, fp, m)


@njit(fastmath=FASTMATH, error_model="numpy")
def level_loglik_particle(x, y, vx, vy, offset_db, level_db, ovx, ovy, ross, p0_db, xp, fp, m,
                          half_inv_var):
    """Log of eq. 33 up to a constant, h_l = SL + K(r) + offset (eqs. 12, 16)."""
    r = math.sqrt(x * x + y * y)
    if ross:
        tvx = vx + ovx
        tvy = vy + ovy
        v = max(math.sqrt(tvx * tvx + tvy * tvy), ROSS_MIN_SPEED_MPS)
        sl = ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE * math.log10(v / ROSS_REFERENCE_SPEED_MPS)
    else:
        sl = p0_db
    d = level_db - (sl + k_at(r, xp, fp, m) + offset_db)
    return -(d * d) * half_inv_var



@njit(fastmath=FASTMATH, error_model="numpy")
def level_loglik_particle_sd(x, y, vx, vy, offset_db, level_db, ovx, ovy, ross, p0_db, xp, fp, sp, m,
                             var_l):
    """`level_loglik_particle` with the K error sd of the grid at the particle's range added:
    the variance is sigma_l^2 + sd(r)^2 (``sp`` the sd profile on ``xp``). The density's
    -1/2 ln(var) is left out, as `tracker.rpf.likelihood.level_loglik` says why."""
    r = math.sqrt(x * x + y * y)
    if ross:
        tvx = vx + ovx
        tvy = vy + ovy
        v = max(math.sqrt(tvx * tvx + tvy * tvy), ROSS_MIN_SPEED_MPS)
        sl = ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE * math.log10(v / ROSS_REFERENCE_SPEED_MPS)
    else:
        sl = p0_db
    d = level_db - (sl + k_at(r, xp, fp, m) + offset_db)
    sd = sd_at(r, xp, sp, m)
    var = var_l + sd * sd
    return -0.5 * (d * d) / var


@njit(fastmath=FASTMATH, error_model="numpy")
def sd_at(r, xp, sp, m):
    """The sd profile at r: linear on the first ``m`` points, end values held (no penalty)."""
    if r <= xp[0]:
        return sp[0]
    if r >= xp[m - 1]:
        return sp[m - 1]
    j = int((r - xp[0]) / (xp[m - 1] - xp[0]) * (m - 1))
    if j > m - 2:
        j = m - 2
    while j > 0 and xp[j] > r:
        j -= 1
    while j < m - 2 and xp[j + 1] <= r:
        j += 1
    return sp[j] + (sp[j + 1] - sp[j]) * (r - xp[j]) / (xp[j + 1] - xp[j])
