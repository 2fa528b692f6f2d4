"""Each arrival's band averages of its intensity and of its Lloyd factor, compiled (numba): the
inner loop of ``acoustics.builder.surfaceimage``."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: Arrivals reduced together: their running sums stay in the core's cache across a band's frequencies.
BLOCK = 256
#: The running attenuation a^r is carried from one frequency to the next by exp(dr ln a) as a
#: Taylor polynomial (``_exp_small``) where every |dr ln a| of a block is at most this (error
#: below 1e-17 relative); a block beyond it takes exp itself.
SMALL_EXPONENT = 0.05
#: The reduced sine (``_sin_squared``) holds to about 1e-16 for arguments up to this, rad; a
#: block beyond it takes sin itself.
LARGE_PHASE = 1.0e5
_TWO_OVER_PI = 0.6366197723675814
_PIO2_HI = 1.57079632673412561417e+00  # pi / 2 in two parts (Cody and Waite): the first 33 bits
_PIO2_LO = 6.07710050650619224932e-11


@njit(inline="always")
def _exp_small(x):
    """exp(x) for |x| <= SMALL_EXPONENT: Taylor to x^9."""
    return 1.0 + x * (1.0 + x * (1.0 / 2 + x * (1.0 / 6 + x * (1.0 / 24 + x * (1.0 / 120 + x * (
        1.0 / 720 + x * (1.0 / 5040 + x * (1.0 / 40320 + x * (1.0 / 362880)))))))))


@njit(inline="always")
def _sin_squared(x):
    """sin(x)^2 for |x| <= LARGE_PHASE without a branch (so that the loop vectorises): x reduced by
    multiples k of pi / 2, then sin^2 or cos^2 of the rest by k's parity."""
    k = math.floor(x * _TWO_OVER_PI + 0.5)
    r = (x - k * _PIO2_HI) - k * _PIO2_LO
    r2 = r * r
    s = r * (1.0 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 + r2 * (
        -1.0 / 39916800 + r2 * (1.0 / 6227020800 + r2 * (-1.0 / 1307674368000))))))))
    c = 1.0 + r2 * (-1.0 / 2 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (
        -1.0 / 3628800 + r2 * (1.0 / 479001600 + r2 * (-1.0 / 87178291200 + r2 * (1.0 / 20922789888000))))))))
    odd = k - 2.0 * math.floor(0.5 * k)
    return odd * (c * c) + (1.0 - odd) * (s * s)


# nogil: the build's threads reduce their radials' arrivals beside the BELLHOP runs; no
# reassociation (it would undo the two-part reduction of the sine's argument)
@njit(cache=True, nogil=True, fastmath={"nsz", "contract", "nnan", "ninf"})
def band_sums(attenuation, depth_m, speed_mps, angle_deg, freqs_hz, ratio, weights):
    """Per class and arrival, the band averages of I(f) / A^2 and of I(f) G(theta, f) / A^2:
    ``attenuation`` is each arrival's volume attenuation at the run frequency (intensity ratio),
    at frequency f raised to ``ratio[f]``; G = 2 sin^2(2 pi f z sin(theta) / c) at the arrival's
    receiver depth ``depth_m`` and sound speed ``speed_mps``; ``weights`` (class, frequency).

    Blocks of ``BLOCK`` arrivals go through the band's frequencies together: a^ratio carried from
    one frequency to the next (``_exp_small``) and sin^2 from a polynomial (``_sin_squared``), no
    library call in the inner loops; the same sums as exp and sin at every frequency to about
    1e-14 relative (tests/acoustics/builder/test_lloyd.py)."""
    n_class, n_freq = weights.shape
    n = attenuation.size
    plain = np.zeros((n_class, n))
    lloyd = np.zeros((n_class, n))
    log_a = np.empty(BLOCK)
    phase = np.empty(BLOCK)
    a = np.empty(BLOCK)
    g = np.empty(BLOCK)
    p_sum = np.empty((n_class, BLOCK))
    l_sum = np.empty((n_class, BLOCK))
    max_step = 0.0
    for j in range(1, n_freq):
        max_step = max(max_step, abs(ratio[j] - ratio[j - 1]))
    f_max = 0.0
    for j in range(n_freq):
        f_max = max(f_max, abs(freqs_hz[j]))
    for lo in range(0, n, BLOCK):
        m = min(BLOCK, n - lo)
        worst_log, worst_phase = 0.0, 0.0
        for i in range(m):
            log_a[i] = np.log(max(attenuation[lo + i], 1e-300))
            # 2 pi z sin(theta) / c: the phase of G's sine per Hz
            phase[i] = 2.0 * np.pi * np.sin(np.radians(angle_deg[lo + i])) * depth_m[lo + i] / speed_mps[lo + i]
            a[i] = np.exp(ratio[0] * log_a[i])
            worst_log = max(worst_log, abs(log_a[i]))
            worst_phase = max(worst_phase, abs(phase[i]) * f_max)
        carried = worst_log * max_step <= SMALL_EXPONENT
        reduced = worst_phase <= LARGE_PHASE
        p_sum[:, :m] = 0.0
        l_sum[:, :m] = 0.0
        for j in range(n_freq):
            if j > 0:
                if carried:
                    step = ratio[j] - ratio[j - 1]
                    for i in range(m):
                        a[i] *= _exp_small(step * log_a[i])
                else:
                    for i in range(m):
                        a[i] = np.exp(ratio[j] * log_a[i])
            f = freqs_hz[j]
            if reduced:
                for i in range(m):
                    g[i] = 2.0 * a[i] * _sin_squared(f * phase[i])
            else:
                for i in range(m):
                    s = np.sin(f * phase[i])
                    g[i] = 2.0 * a[i] * s * s
            for c in range(n_class):
                w = weights[c, j]
                for i in range(m):
                    p_sum[c, i] += w * a[i]
                    l_sum[c, i] += w * g[i]
        plain[:, lo:lo + m] = p_sum[:, :m]
        lloyd[:, lo:lo + m] = l_sum[:, :m]
    return plain, lloyd
