"""Random numbers of the compiled kernel: a xoshiro256+ generator per run and ziggurat samplers
of the standard normal and exponential laws.

Each run has its own generator (D. Blackman, S. Vigna, "Scrambled linear pseudorandom number
generators", 2021), seeded with 256 bits drawn from the caller's numpy Generator
(`seed_states`); normals and exponentials come from 256-layer ziggurats (G. Marsaglia, W. W.
Tsang, "The ziggurat method for generating random variables", 2000). A run's numbers depend
only on its seed, so results do not depend on how runs are spread over threads.

The generator state ``s`` is a (4,) uint64 array, advanced in place. The ``fill_*`` forms draw
the same stream as the scalar samplers into arrays, with the state held in registers on the
fast path.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH

_TWO_POW_M53 = 1.0 / 9007199254740992.0


@njit(inline="always")
def _rotl(x, k):
    """64-bit rotation of ``x`` left by ``k`` bits."""
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@njit(inline="always")
def _raw(s):
    """Next 64-bit output of xoshiro256+ (s0 + s3), the state ``s`` advanced in place."""
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
def uniform(s):
    """Next U[0, 1) double of the xoshiro256+ generator with state ``s`` (4 uint64, in place)."""
    return float(_raw(s) >> np.uint64(11)) * _TWO_POW_M53


def seed_states(rng: np.random.Generator, runs: int) -> np.ndarray:
    """Generator states, shape (runs, 4) uint64, from 256 random bits per run."""
    s = rng.integers(0, np.iinfo(np.uint64).max, size=(runs, 4), dtype=np.uint64,
                     endpoint=True)
    s[np.all(s == 0, axis=1), 0] = 1  # the all-zero state is the one fixed point
    return s


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


@njit(fastmath=FASTMATH, error_model="numpy")
def normal_pair(s):
    """Two independent N(0, 1) draws."""
    return normal(s), normal(s)


# Deliberate copy: the loop below repeats `normal`'s ziggurat step by hand, unrolled with the
# generator state in local variables (registers) for the whole fill; calling `normal` per draw
# stores the state back to memory each time, which the particle filter's prediction step pays for.
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


@njit(inline="always")
def fill_normals(s, g):
    """g[i] = `normal` for each i (the same stream), with the generator state held in registers
    on the fast path: `fill_normal_pairs` for one array."""
    xt = ZIGGURAT_X
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for k in range(g.size):
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
        g[k] = z
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3


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
#: f(x_i) = exp(-x_i) of the layer edges.
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

