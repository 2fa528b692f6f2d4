"""Compiled, fused cycle loop of the regularized particle filter (numba).

`tracker.rpf` (numpy) is the reference implementation; this module runs the same algorithm,
eq. for eq., one run at a time with every particle of a cycle handled in a few passes over
data that stay in the core's cache:

1. the process noise (2 normals per particle, drawn in sequence from the run's generator);
2. prediction (eqs. 4-6, discrete white-noise acceleration), one loop per axis;
3. bearing log-likelihood (eq. 32; residual in (-pi, pi] as the atan2 of the particle position
   rotated by -theta) added to the log-weights;
4. SPL log-likelihood (eq. 33, h_l = SL(v) + K(r) of eqs. 12-16, or the constant P0; K by the
   `tables.LevelProfile` rule) when the cycle has a level;
5. logsumexp normalisation (eq. 19), N_eff (eq. 20), weighted mean and covariance (eqs. 29-30);
6. when N_eff < N_thr: multinomial resampling (cumulative sum + sorted uniforms), optional
   shrinkage toward the mean, regularization x = x' + h D eps with the Epanechnikov kernel
   (eqs. 21-28), then mean and covariance again with equal weights.

The loops of 2, 3 and 5 call no library function (our own `atan2` and `exp_nonpos`), so LLVM
vectorizes them. Fast-math allows reassociation, so sums differ from numpy's in the last bits.

Random numbers: each run has its own xoshiro256+ generator (D. Blackman, S. Vigna, "Scrambled
linear pseudorandom number generators", 2021), seeded with 256 bits drawn from the caller's
numpy Generator; normals and exponentials by 256-layer ziggurats (G. Marsaglia, W. W. Tsang,
"The ziggurat method for generating random variables", 2000). A run's numbers depend only on
its seed, so results do not depend on how runs are spread over threads.

The scalar pieces (`predict_axis`, `bearing_loglik_particle`, `level_loglik_particle`,
`k_at`) and the per-run array pieces (`normalise_run`, `moments_run`, `regularise_run`) are
the ones the fused loop calls; the test suite checks them against the numpy functions.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from envdata.classes import (ROSS_LEVEL_DB, ROSS_MIN_SPEED_MPS, ROSS_REFERENCE_SPEED_MPS,
                             ROSS_SLOPE_DB_PER_DECADE)
from tracker.tables import BEYOND_GRID_PENALTY_DB

#: LLVM fast-math flags: reassociation, FMA contraction, reciprocal, no signed zeros. Not
#: "nnan"/"ninf": NaN marks a missing measurement and is tested for.
FASTMATH = {"nsz", "arcp", "contract", "reassoc"}
_TWO_POW_M53 = 1.0 / 9007199254740992.0


# --------------------------------------------------------------------------------------------
# Random numbers


@njit(inline="always")
def _rotl(x, k):
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@njit(inline="always")
def uniform(s):
    """Next U[0, 1) double of the xoshiro256+ generator with state ``s`` (4 uint64, in place)."""
    return float(_raw(s) >> np.uint64(11)) * _TWO_POW_M53


def _ziggurat_table(layers: int = 256, r: float = 3.6541528853610088,
                    v: float = 0.00492867323399) -> np.ndarray:
    """Layer edges x_0..x_256 of the 256-layer ziggurat of exp(-x^2/2) (Marsaglia & Tsang,
    "The ziggurat method for generating random variables", 2000): equal-area layers v, base
    layer x_0 = v / f(r) wide with the tail beyond r, x_1 = r, x_(i+1) = f^-1(v / x_i + f(x_i)),
    x_256 = 0."""
    x = np.empty(layers + 1)
    x[0] = v / math.exp(-0.5 * r * r)
    x[1] = r
    for i in range(1, layers - 1):
        x[i + 1] = math.sqrt(-2.0 * math.log(v / x[i] + math.exp(-0.5 * x[i] * x[i])))
    x[layers] = 0.0
    return x


ZIGGURAT_X = _ziggurat_table()
ZIGGURAT_R = ZIGGURAT_X[1]
#: f(x_i) = exp(-x_i^2 / 2) of the layer edges.
ZIGGURAT_F = np.exp(-0.5 * ZIGGURAT_X ** 2)


@njit(inline="always")
def _raw(s):
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    result = s0 + s3
    t = s1 << np.uint64(17)
    s2 ^= s0
    s3 ^= s1
    s1 ^= s2
    s0 ^= s3
    s2 ^= t
    s3 = _rotl(s3, 45)
    s[0] = s0
    s[1] = s1
    s[2] = s2
    s[3] = s3
    return result


@njit(inline="always")
def _normal_slow(s, i, u, z):
    """The rare branches of `normal` after a fast-path miss in layer ``i``: a tail draw (base
    layer) or the wedge test; NaN: rejected, draw again."""
    if i == 0:
        while True:
            a = -math.log(1.0 - uniform(s)) / ZIGGURAT_R
            b = -math.log(1.0 - uniform(s))
            if 2.0 * b > a * a:
                return ZIGGURAT_R + a if u > 0 else -(ZIGGURAT_R + a)
    y = ZIGGURAT_F[i + 1] + uniform(s) * (ZIGGURAT_F[i] - ZIGGURAT_F[i + 1])
    if y < math.exp(-0.5 * z * z):
        return z
    return math.nan


@njit(fastmath=FASTMATH, error_model="numpy")
def normal(s):
    """One N(0, 1) draw by the ziggurat: a layer from bits 3-10 of a 64-bit output (the lowest
    bits of xoshiro256+ are weak), a signed uniform from its top 53 bits; the base layer's
    overflow is drawn from the tail beyond r (Marsaglia's exponential rejection), a wedge point
    is kept with probability ratio f(z) / its layer."""
    xt = ZIGGURAT_X
    while True:
        raw = _raw(s)
        i = int((raw >> np.uint64(3)) & np.uint64(255))
        u = 2.0 * (float(raw >> np.uint64(11)) * _TWO_POW_M53) - 1.0
        z = u * xt[i]
        if abs(z) < xt[i + 1]:
            return z
        z = _normal_slow(s, i, u, z)
        if not math.isnan(z):
            return z


@njit(inline="always")
def fill_normal_pairs(s, gx, gy):
    """gx[i], gy[i] = `normal`, `normal` for each i (the same stream), with the generator
    state held in registers on the fast path."""
    xt = ZIGGURAT_X
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for k in range(2 * gx.size):
        while True:
            raw = s0 + s3
            t = s1 << np.uint64(17)
            s2 ^= s0
            s3 ^= s1
            s1 ^= s2
            s0 ^= s3
            s2 ^= t
            s3 = _rotl(s3, 45)
            i = int((raw >> np.uint64(3)) & np.uint64(255))
            u = 2.0 * (float(raw >> np.uint64(11)) * _TWO_POW_M53) - 1.0
            z = u * xt[i]
            if abs(z) < xt[i + 1]:
                break
            s[0], s[1], s[2], s[3] = s0, s1, s2, s3
            z = _normal_slow(s, i, u, z)
            s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
            if not math.isnan(z):
                break
        if k % 2 == 0:
            gx[k // 2] = z
        else:
            gy[k // 2] = z
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3


@njit(cache=True, error_model="numpy")
def normal_pairs_filled(s, n):
    """`fill_normal_pairs` into two new arrays of ``n`` (for tests)."""
    gx = np.empty(n)
    gy = np.empty(n)
    fill_normal_pairs(s, gx, gy)
    return gx, gy


@njit(fastmath=FASTMATH, error_model="numpy")
def normal_pair(s):
    """Two independent N(0, 1) draws."""
    return normal(s), normal(s)


def _ziggurat_exp_table(layers: int = 256, r: float = 7.69711747013104972,
                        v: float = 0.0039496598225815571993) -> np.ndarray:
    """Layer edges of the 256-layer ziggurat of exp(-x) (Marsaglia & Tsang 2000), as
    `_ziggurat_table`: x_(i+1) = -ln(v / x_i + exp(-x_i))."""
    x = np.empty(layers + 1)
    x[0] = v / math.exp(-r)
    x[1] = r
    for i in range(1, layers - 1):
        x[i + 1] = -math.log(v / x[i] + math.exp(-x[i]))
    x[layers] = 0.0
    return x


ZIGGURAT_EXP_X = _ziggurat_exp_table()
ZIGGURAT_EXP_R = ZIGGURAT_EXP_X[1]
ZIGGURAT_EXP_F = np.exp(-ZIGGURAT_EXP_X)


@njit(inline="always")
def exponential(s):
    """A standard exponential draw by the ziggurat of exp(-x); beyond r the tail is r plus a
    new draw (the exponential forgets)."""
    xt = ZIGGURAT_EXP_X
    ft = ZIGGURAT_EXP_F
    base = 0.0
    while True:
        raw = _raw(s)
        i = int((raw >> np.uint64(3)) & np.uint64(255))
        z = (float(raw >> np.uint64(11)) * _TWO_POW_M53) * xt[i]
        if z < xt[i + 1]:
            return base + z
        if i == 0:
            base += ZIGGURAT_EXP_R
            continue
        y = ft[i + 1] + uniform(s) * (ft[i] - ft[i + 1])
        if y < math.exp(-z):
            return base + z


@njit(inline="always")
def fill_exponentials(s, out):
    """out[i] = `exponential` for each i (the same stream), the generator state in registers
    on the fast path."""
    xt = ZIGGURAT_EXP_X
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for k in range(out.size):
        base = 0.0
        while True:
            raw = s0 + s3
            t = s1 << np.uint64(17)
            s2 ^= s0
            s3 ^= s1
            s1 ^= s2
            s0 ^= s3
            s2 ^= t
            s3 = _rotl(s3, 45)
            i = int((raw >> np.uint64(3)) & np.uint64(255))
            z = (float(raw >> np.uint64(11)) * _TWO_POW_M53) * xt[i]
            if z < xt[i + 1]:
                break
            if i == 0:
                base += ZIGGURAT_EXP_R
                continue
            s[0], s[1], s[2], s[3] = s0, s1, s2, s3
            y = ZIGGURAT_EXP_F[i + 1] + uniform(s) * (ZIGGURAT_EXP_F[i] - ZIGGURAT_EXP_F[i + 1])
            s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
            if y < math.exp(-z):
                break
        out[k] = base + z
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3


@njit(cache=True, error_model="numpy")
def exponentials(s, n):
    """``n`` standard exponentials from the state ``s`` (for tests)."""
    out = np.empty(n)
    for i in range(n):
        out[i] = exponential(s)
    return out


@njit(cache=True, error_model="numpy")
def exponentials_filled(s, n):
    """`fill_exponentials` into a new array of ``n`` (for tests)."""
    out = np.empty(n)
    fill_exponentials(s, out)
    return out


def seed_states(rng: np.random.Generator, runs: int) -> np.ndarray:
    """Generator states, shape (runs, 4) uint64, from 256 random bits per run."""
    s = rng.integers(0, np.iinfo(np.uint64).max, size=(runs, 4), dtype=np.uint64,
                     endpoint=True)
    s[np.all(s == 0, axis=1), 0] = 1  # the all-zero state is the one fixed point
    return s


@njit(cache=True, error_model="numpy")
def uniforms(s, n):
    """``n`` uniforms from the state ``s`` (for tests)."""
    out = np.empty(n)
    for i in range(n):
        out[i] = uniform(s)
    return out


@njit(cache=True, error_model="numpy")
def normals(s, n):
    """``2 n`` normals from the state ``s`` (for tests)."""
    out = np.empty(2 * n)
    for i in range(n):
        out[2 * i], out[2 * i + 1] = normal_pair(s)
    return out


# --------------------------------------------------------------------------------------------
# Per particle: motion model (eqs. 4-6) and likelihoods (eqs. 12, 16, 31-33)


@njit(inline="always")
def predict_axis(pos, vel, g, dt_s, dv_scale, cp, cv):
    """Eq. 4 along one axis for one particle: x' = F (x + x^o_k) - x^o_k1 + G nu with
    nu = sigma_a g; ``dv_scale`` = dt sigma_a, ``cp`` = x^o_k + dt v^o_k - x^o_k1 and
    ``cv`` = v^o_k - v^o_k1 (observer position and velocity terms)."""
    dv = g * dv_scale
    return pos + ((vel + 0.5 * dv) * dt_s + cp), (vel + dv) + cv


_TAN_PI_24 = math.tan(math.pi / 24)
_TAN_3PI_24 = math.tan(3 * math.pi / 24)
_TAN_5PI_24 = math.tan(5 * math.pi / 24)
_TAN_PI_12 = math.tan(math.pi / 12)
_TAN_PI_6 = math.tan(math.pi / 6)


@njit(inline="always")
def atan2(y, x):
    """atan2(y, x) in [-pi, pi] without a library call, so that a loop using it vectorizes.

    t = min/max of |y|, |x| in [0, 1]; t is moved to the nearest of tan(0), tan(pi/12),
    tan(pi/6), tan(pi/4) by atan t = c + atan((t - tan c) / (1 + t tan c)), leaving |t'| <=
    tan(pi/24) = 0.132, where 9 terms of the Taylor series of atan have error below
    t'^19 / 19 < 1e-17 t'; then the octant is unfolded. Small angles (the usual bearing
    residual) keep full relative precision (t' = t there).
    """
    ay = abs(y)
    ax = abs(x)
    big = max(ay, ax)
    small = min(ay, ax)
    t = small / big if big > 0.0 else 0.0
    c = 0.0
    tc = 0.0
    if t > _TAN_PI_24:
        c = math.pi / 12
        tc = _TAN_PI_12
    if t > _TAN_3PI_24:
        c = math.pi / 6
        tc = _TAN_PI_6
    if t > _TAN_5PI_24:
        c = math.pi / 4
        tc = 1.0
    tr = (t - tc) / (1.0 + t * tc)
    z = tr * tr
    p = 1.0 / 17.0
    p = 1.0 / 15.0 - z * p
    p = 1.0 / 13.0 - z * p
    p = 1.0 / 11.0 - z * p
    p = 1.0 / 9.0 - z * p
    p = 1.0 / 7.0 - z * p
    p = 1.0 / 5.0 - z * p
    p = 1.0 / 3.0 - z * p
    p = 1.0 - z * p
    a = c + tr * p
    if ay > ax:
        a = math.pi / 2 - a
    if x < 0.0:
        a = math.pi - a
    if y < 0.0:
        a = -a
    return a


@njit(inline="always")
def bearing_loglik_particle(x, y, cos_z, sin_z, half_inv_var):
    """Log of eq. 32 up to a constant; the residual is atan2 of (x, y) rotated by -theta."""
    east = x * cos_z - y * sin_z
    north = y * cos_z + x * sin_z
    resid = atan2(east, north)
    return -(resid * resid) * half_inv_var


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


# --------------------------------------------------------------------------------------------
# Per run: weights, estimate, regularization (eqs. 19-30)


_LN2_HI = 0.6931471803691238  # ln 2 split so that k * _LN2_HI is exact for |k| < 2^11
_LN2_LO = 1.9082149292705877e-10
#: 2^-j, j = 0..1160 (the smallest are subnormal or 0, as exp's own underflow).
_POW2_NEG = np.ldexp(1.0, -np.arange(1161))


@njit(inline="always")
def exp_nonpos(x):
    """exp(x) for x <= 0 without a library call (the normalisation loop then vectorizes).

    x = k ln 2 + r with |r| <= ln2 / 2; exp(r) by 13 terms of its Taylor series (error below
    r^13 / 13! < 2e-16), times 2^k from a table. x < -800 gives 0 like exp itself.
    """
    x = max(x, -800.0)
    k = int(x * (1.0 / math.log(2.0)) - 0.5)  # rounds to nearest for x <= 0
    r = (x - k * _LN2_HI) - k * _LN2_LO
    p = 1.0 / 479001600.0
    p = 1.0 / 39916800.0 + r * p
    p = 1.0 / 3628800.0 + r * p
    p = 1.0 / 362880.0 + r * p
    p = 1.0 / 40320.0 + r * p
    p = 1.0 / 5040.0 + r * p
    p = 1.0 / 720.0 + r * p
    p = 1.0 / 120.0 + r * p
    p = 1.0 / 24.0 + r * p
    p = 1.0 / 6.0 + r * p
    p = 0.5 + r * p
    p = 1.0 + r * p
    p = 1.0 + r * p
    return p * _POW2_NEG[-k]


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def normalise_run(log_w, w):
    """In place: log-weights normalised (logsumexp, eq. 19), ``w`` their exponentials; N_eff
    (eq. 20) returned."""
    n = log_w.size
    top = -np.inf
    for i in range(n):
        if log_w[i] > top:
            top = log_w[i]
    total = 0.0
    for i in range(n):
        log_w[i] -= top
        e = exp_nonpos(log_w[i])
        w[i] = e
        total += e
    inv = 1.0 / total
    lt = math.log(total)
    sq = 0.0
    for i in range(n):
        wi = w[i] * inv
        w[i] = wi
        sq += wi * wi
        log_w[i] -= lt
    return 1.0 / sq


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


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def cholesky_loaded(cov, chol):
    """Lower Cholesky factor of ``cov`` + (1e-12 max diag + 1e-18) I, as `rpf.regularise`."""
    d = cov.shape[0]
    scale = 0.0
    for a in range(d):
        scale = max(scale, cov[a, a])
    load = 1e-12 * scale + 1e-18
    for a in range(d):
        for b in range(d):
            chol[a, b] = 0.0
    for j in range(d):
        acc = cov[j, j] + load
        for k in range(j):
            acc -= chol[j, k] * chol[j, k]
        diag = math.sqrt(max(acc, 0.0))
        chol[j, j] = diag
        for i in range(j + 1, d):
            acc = cov[i, j]
            for k in range(j):
                acc -= chol[i, k] * chol[j, k]
            chol[i, j] = acc / diag if diag > 0.0 else 0.0


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def resample_indices(w, s, cdf, idx, spac):
    """Multinomial draw of N indices with probabilities ``w`` into ``idx``, sorted: N sorted
    uniforms from normalised exponential spacings (``spac``, N + 1 long) walked along the
    cumulative sum (as `rpf.multinomial_resample`, ``searchsorted(side="right")``)."""
    n = w.size
    acc = 0.0
    for i in range(n):
        acc += w[i]
        cdf[i] = acc
    inv_cdf = 1.0 / acc
    for i in range(n):
        cdf[i] *= inv_cdf
    fill_exponentials(s, spac)
    total = 0.0
    for i in range(n + 1):
        total += spac[i]
        spac[i] = total
    inv = 1.0 / total
    j = 0
    for i in range(n):
        u = spac[i] * inv
        while j < n - 1 and cdf[j] <= u:
            j += 1
        idx[i] = j


@njit(inline="always")
def fill_epanechnikov(s, eps, e1, e2):
    """N draws of the Epanechnikov kernel on the unit ball of R^d into ``eps`` (d, N) (eq. 26):
    d normals over the root of their squared norm plus a chi^2_4 = 2 (E1 + E2); ``e1``, ``e2``
    (N,) are scratch."""
    d, n = eps.shape
    for a in range(0, d, 2):
        if a + 1 < d:
            fill_normal_pairs(s, eps[a], eps[a + 1])
        else:
            fill_normal_pairs(s, eps[a], e2)
    fill_exponentials(s, e1)
    fill_exponentials(s, e2)
    for i in range(n):
        e1[i] = 2.0 * (e1[i] + e2[i])
    for a in range(d):
        for i in range(n):
            e1[i] += eps[a, i] * eps[a, i]
    for i in range(n):
        e1[i] = 1.0 / math.sqrt(e1[i])
    for a in range(d):
        for i in range(n):
            eps[a, i] *= e1[i]


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def regularise_run(state, idx, mean, chol, eps, h, shrink, new):
    """Eq. 21 for one run into ``new`` (D, N): x = x'_idx + h D eps, or with ``shrink``
    x = m + a (x'_idx - m) + h D eps, a = sqrt(1 - h^2/(D+4)). ``eps`` is (D, N)."""
    d, n = state.shape
    a = math.sqrt(max(0.0, 1.0 - h * h / (d + 4))) if shrink else 1.0
    for r in range(d):
        src = state[r]
        dst = new[r]
        for i in range(n):
            dst[i] = src[idx[i]]
        if shrink:
            m = mean[r]
            for i in range(n):
                dst[i] = m + a * (dst[i] - m)
        for c in range(r + 1):
            hc = h * chol[r, c]
            e = eps[c]
            for i in range(n):
                dst[i] += hc * e[i]


# --------------------------------------------------------------------------------------------
# Initialization (rpf.initial_particles)


@njit(fastmath=FASTMATH, error_model="numpy")
def init_particle(g0, g1, g2, g3, z0, ovx, ovy, range_mean_m, range_sd_m, theta_sd,
                  speed_mean_mps, speed_sd_mps, course_sd):
    """(x, y, vx, vy) of one prior particle from four N(0, 1) draws (`rpf.initial_particles`)."""
    rng_m = range_mean_m + range_sd_m * g0
    theta = z0 + theta_sd * g1
    speed = speed_mean_mps + speed_sd_mps * g2
    course = z0 + math.pi + course_sd * g3
    return (rng_m * math.sin(theta), rng_m * math.cos(theta),
            speed * math.sin(course) - ovx, speed * math.cos(course) - ovy)


# --------------------------------------------------------------------------------------------
# One run, every cycle


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def run_one(s, t_s, obs, bearing, level, prof_idx, prof_r, prof_k, prof_len, use_level, ross,
            p0_db, prior, sigma_a, sigma_theta, sigma_l, offset_sd_db, n, d, n_thr, h, shrink,
            summaries, means, covs, resampled, sds):
    """The filter over every cycle for one run (generator state ``s``).

    ``prior`` = (range mean, range sd, bearing sd rad, speed mean, speed sd, course sd rad);
    outputs ``means`` (K, D), ``covs`` (K, D, D), ``resampled`` (K,) uint8, ``sds`` (K, 3).
    """
    n_cycles = t_s.size
    state = np.empty((d, n))
    log_w = np.empty(n)
    w = np.empty(n)
    cdf = np.empty(n)
    idx = np.empty(n, np.int64)
    new = np.empty((d, n))
    eps = np.empty((d, n))
    spac = np.empty(n + 1)
    mean = np.empty(d)
    cov = np.empty((d, d))
    chol = np.empty((d, d))
    gx = np.zeros(n)
    gy = np.zeros(n)
    half_b = 0.5 / (sigma_theta * sigma_theta)
    half_l = 0.5 / (sigma_l * sigma_l)
    log_n = -math.log(n)

    z0 = bearing[0]
    ovx0, ovy0 = obs[0, 2], obs[0, 3]
    for i in range(n):
        g0, g1 = normal_pair(s)
        g2, g3 = normal_pair(s)
        state[0, i], state[1, i], state[2, i], state[3, i] = init_particle(
            g0, g1, g2, g3, z0, ovx0, ovy0, prior[0], prior[1], prior[2], prior[3], prior[4],
            prior[5])
        if d > 4:
            state[4, i] = offset_sd_db * normal_pair(s)[0]
        log_w[i] = log_n

    for k in range(n_cycles):
        has_b = k > 0 and not math.isnan(bearing[k])
        has_l = use_level and not math.isnan(level[k])
        moving = k > 0
        if moving:
            dt = t_s[k] - t_s[k - 1]
            dv_scale = dt * sigma_a
            cpx = obs[k - 1, 0] + dt * obs[k - 1, 2] - obs[k, 0]
            cpy = obs[k - 1, 1] + dt * obs[k - 1, 3] - obs[k, 1]
            cvx = obs[k - 1, 2] - obs[k, 2]
            cvy = obs[k - 1, 3] - obs[k, 3]
        else:
            dt = dv_scale = cpx = cpy = cvx = cvy = 0.0
        cz = math.cos(bearing[k]) if has_b else 1.0
        sz = math.sin(bearing[k]) if has_b else 0.0
        p = prof_idx[k] if has_l else 0
        m = prof_len[p] if has_l else 1
        xp = prof_r[p]
        fp = prof_k[p]
        lv = level[k] if has_l else 0.0
        ovx, ovy = obs[k, 2], obs[k, 3]

        # pass 1: process noise (sequential generator), then prediction and bearing
        # likelihood in one loop free of calls (it vectorizes), then the level likelihood
        if moving and sigma_a > 0.0:
            fill_normal_pairs(s, gx, gy)
        if moving:
            _predict_axis(state[0], state[2], gx, dt, dv_scale, cpx, cvx)
            _predict_axis(state[1], state[3], gy, dt, dv_scale, cpy, cvy)
        if has_b:
            _bearing_pass(state[0], state[1], log_w, cz, sz, half_b)
        if has_l:
            for i in range(n):
                off = state[4, i] if d > 4 else 0.0
                log_w[i] += level_loglik_particle(state[0, i], state[1, i], state[2, i],
                                                  state[3, i], off, lv, ovx, ovy, ross, p0_db,
                                                  xp, fp, m, half_l)

        # pass 2-3: weights, N_eff, mean and covariance (the covariance also feeds eq. 21)
        neff = normalise_run(log_w, w)
        moments_run(state, w, mean, cov)
        if neff < n_thr:
            cholesky_loaded(cov, chol)
            resample_indices(w, s, cdf, idx, spac)
            fill_epanechnikov(s, eps, gx, gy)  # the process noise arrays as scratch
            regularise_run(state, idx, mean, chol, eps, h, shrink, new)
            state, new = new, state
            for i in range(n):
                log_w[i] = log_n
                w[i] = 1.0 / n
            moments_run(state, w, mean, cov)
            resampled[k] = 1
        for a in range(d):
            means[k, a] = mean[a]
            for b in range(d):
                covs[k, a, b] = cov[a, b]
        if summaries:
            _summaries(state, w, ovx, ovy, sds[k])


@njit(inline="always")
def _predict_axis(pos, vel, g, dt, dv_scale, cp, cv):
    """Eq. 4 along one axis over 1-D particle arrays (one loop, two arrays written: few alias
    checks, so it vectorizes)."""
    for i in range(pos.size):
        pos[i], vel[i] = predict_axis(pos[i], vel[i], g[i], dt, dv_scale, cp, cv)


@njit(inline="always")
def _bearing_pass(x, y, log_w, cz, sz, half_b):
    for i in range(log_w.size):
        log_w[i] += bearing_loglik_particle(x[i], y[i], cz, sz, half_b)


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def predict_arrays(state, gx, gy, dt, dv_scale, cpx, cpy, cvx, cvy):
    """Eq. 4 for (D, N) particles with noise (gx, gy) (as the fused loop; for tests)."""
    _predict_axis(state[0], state[2], gx, dt, dv_scale, cpx, cvx)
    _predict_axis(state[1], state[3], gy, dt, dv_scale, cpy, cvy)


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def bearing_loglik_arrays(state, z, sigma_rad):
    """Eq. 32 for (D, N) particles (as the fused loop; for tests)."""
    out = np.zeros(state.shape[1])
    _bearing_pass(state[0], state[1], out, math.cos(z), math.sin(z),
                  0.5 / (sigma_rad * sigma_rad))
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def level_loglik_arrays(state, level_db, ovx, ovy, ross, p0_db, xp, fp, sigma_db):
    """Eq. 33 for (D, N) particles (as the fused loop; for tests)."""
    n = state.shape[1]
    out = np.empty(n)
    for i in range(n):
        off = state[4, i] if state.shape[0] > 4 else 0.0
        out[i] = level_loglik_particle(state[0, i], state[1, i], state[2, i], state[3, i], off,
                                       level_db, ovx, ovy, ross, p0_db, xp, fp, xp.size,
                                       0.5 / (sigma_db * sigma_db))
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def k_at_arrays(r, xp, fp):
    """`k_at` at each range of ``r`` (for tests)."""
    out = np.empty(r.size)
    for i in range(r.size):
        out[i] = k_at(r[i], xp, fp, xp.size)
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def init_arrays(g, z0, ovx, ovy, prior):
    """Prior particles (4, N) from normals ``g`` (4, N), as the fused loop (for tests)."""
    n = g.shape[1]
    out = np.empty((4, n))
    for i in range(n):
        out[0, i], out[1, i], out[2, i], out[3, i] = init_particle(
            g[0, i], g[1, i], g[2, i], g[3, i], z0, ovx, ovy, prior[0], prior[1], prior[2],
            prior[3], prior[4], prior[5])
    return out


@njit(cache=True, error_model="numpy")
def epanechnikov_draws(s, d, n):
    """``n`` kernel draws, shape (n, d) (for tests)."""
    eps = np.empty((d, n))
    fill_epanechnikov(s, eps, np.empty(n), np.empty(n))
    return eps.T.copy()


@njit(cache=True, error_model="numpy")
def resample_draw(w, s):
    """`resample_indices` for one weight vector (for tests)."""
    idx = np.empty(w.size, np.int64)
    resample_indices(w, s, np.empty(w.size), idx, np.empty(w.size + 1))
    return idx


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def summaries_arrays(state, w, ovx, ovy):
    """`_summaries` of (D, N) particles (for tests)."""
    out = np.empty(3)
    _summaries(state, w, ovx, ovy, out)
    return out


@njit(fastmath=FASTMATH, error_model="numpy")
def _summaries(state, w, ovx, ovy, out):
    """Weighted sd of range (m), course (deg, circular) and target speed (m/s), as
    `rpf._particle_sds`."""
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


# --------------------------------------------------------------------------------------------
# Every run of a block


@njit(cache=True, nogil=True, error_model="numpy")
def run_runs(states, t_s, obs, bearing, level, prof_idx, prof_r, prof_k, prof_len, use_level,
               ross, p0_db, prior, sigma_a, sigma_theta, sigma_l, offset_sd_db, n, d, n_thr, h,
               shrink, summaries, means, covs, resampled, sds):
    """`run_one` for each run in turn. Releases the GIL: `rpf.run_batch` runs blocks of runs on
    Python threads (no numba threading layer, which is not safe in forked workers)."""
    for r in range(states.shape[0]):
        run_one(states[r], t_s, obs, bearing[r], level[r], prof_idx, prof_r, prof_k, prof_len,
                use_level, ross, p0_db, prior, sigma_a, sigma_theta, sigma_l, offset_sd_db, n, d,
                n_thr, h, shrink, summaries, means[r], covs[r], resampled[r], sds[r])


# --------------------------------------------------------------------------------------------
# Driver


def profile_arrays(k_profiles, n_cycles: int):
    """Stack the distinct K(r) profiles (objects with ``range_m`` and ``k_db``) of the cycles.

    Returns
    -------
    prof_idx : ndarray of int, shape (K,)
        Row of each cycle's profile (0 where the cycle has none).
    prof_r, prof_k : ndarray, shape (P, M)
        Range axes, m, and K values, dB, padded with their last value.
    prof_len : ndarray of int, shape (P,)
        Number of points of each.
    """
    rows, where = [], {}
    prof_idx = np.zeros(n_cycles, dtype=np.int64)
    for k in range(n_cycles):
        p = None if k_profiles is None else k_profiles[k]
        if p is None:
            continue
        if id(p) not in where:
            where[id(p)] = len(rows)
            rows.append((np.asarray(p.range_m, dtype=float), np.asarray(p.k_db, dtype=float)))
        prof_idx[k] = where[id(p)]
    if not rows:
        return prof_idx, np.zeros((1, 1)), np.zeros((1, 1)), np.ones(1, dtype=np.int64)
    m = max(r.size for r, _ in rows)
    prof_r = np.empty((len(rows), m))
    prof_k = np.empty((len(rows), m))
    for i, (r, kk) in enumerate(rows):
        prof_r[i, :r.size], prof_r[i, r.size:] = r, r[-1]
        prof_k[i, :kk.size], prof_k[i, kk.size:] = kk, kk[-1]
    return prof_idx, prof_r, prof_k, np.array([r.size for r, _ in rows], dtype=np.int64)


def run(*, t_s, obs_state, bearing_rad_meas, level_db_meas, k_profiles, cfg, rng, ross: bool,
        p0_db: float, sigma_l_db: float, bandwidth: float, summaries: bool):
    """All runs, all cycles (`rpf.run_batch` for one block); ``rng`` seeds one generator per
    run.

    Returns
    -------
    means (runs, K, D), covs (runs, K, D, D), resampled (runs, K) bool, sds (runs, K, 3)
    """
    # fresh C-ordered writable copies: a read-only or strided input would be another type
    # signature, i.e. another compile
    bearing = np.array(bearing_rad_meas, dtype=float, order="C")
    runs, n_cycles = bearing.shape
    d, n = cfg.n_dim, cfg.n_particles
    use_level = level_db_meas is not None
    level = (np.array(level_db_meas, dtype=float, order="C") if use_level
             else np.zeros((runs, 1)))
    prof_idx, prof_r, prof_k, prof_len = profile_arrays(k_profiles if use_level else None,
                                                        n_cycles)
    prior = np.array([cfg.range_mean_m, cfg.range_sd_m, math.radians(cfg.bearing_sigma_deg),
                      cfg.speed_mean_mps, cfg.speed_sd_mps, math.radians(cfg.course_sd_deg)])
    states = seed_states(rng, runs)
    means = np.empty((runs, n_cycles, d))
    covs = np.empty((runs, n_cycles, d, d))
    resampled = np.zeros((runs, n_cycles), dtype=np.uint8)
    sds = np.full((runs, n_cycles if summaries else 1, 3), np.nan)
    args = (states, np.array(t_s, dtype=float, order="C"),
            np.array(obs_state, dtype=float, order="C"), bearing, level, prof_idx, prof_r,
            prof_k, prof_len, use_level, bool(ross), float(p0_db), prior, float(cfg.sigma_a_mps2),
            math.radians(cfg.bearing_sigma_deg), float(sigma_l_db), float(cfg.sl_offset_sd_db),
            n, d, float(cfg.neff_fraction * n), float(bandwidth), bool(cfg.shrink),
            bool(summaries), means, covs, resampled, sds)
    run_runs(*args)
    return means, covs, resampled.astype(bool), sds
