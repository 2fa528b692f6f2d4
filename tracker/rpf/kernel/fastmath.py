"""Compiler flags of the kernel and the elementary functions it computes without a library call.

A loop that calls ``math.atan2`` or ``math.exp`` does not vectorize; `atan2` and `exp_nonpos`
are polynomial and table forms that LLVM inlines and vectorizes (AVX-512 where the machine has
it), so the bearing likelihood and the weight normalisation run as vector loops.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: LLVM fast-math flags: reassociation, FMA contraction, reciprocal, no signed zeros. Not
#: "nnan"/"ninf": NaN marks a missing measurement and is tested for. Reassociation makes sums
#: differ from numpy's in the last bits.
FASTMATH = {"nsz", "arcp", "contract", "reassoc"}

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
