"""The image pairs of ``acoustics.builder.surfaceimage``, compiled (numba): each arrival's band
averages, and per receiver each arrival matched with its surface twin, the pair's intensity
restored from its stronger member."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def band_sums(attenuation, depth_m, speed_mps, angle_deg, freqs_hz, ratio, weights):
    """Per class and arrival, the band averages of I(f) / A^2 and of I(f) G(theta, f) / A^2:
    ``attenuation`` is each arrival's volume attenuation at the run frequency (intensity ratio),
    at frequency f raised to ``ratio[f]``; G = 2 sin^2(2 pi f z sin(theta) / c) at the arrival's
    receiver depth ``depth_m`` and sound speed ``speed_mps``; ``weights`` (class, frequency)."""
    n_class, n_freq = weights.shape
    n = attenuation.size
    plain = np.zeros((n_class, n))
    lloyd = np.zeros((n_class, n))
    for i in range(n):
        log_a = np.log(max(attenuation[i], 1e-300))
        path = np.sin(np.radians(angle_deg[i])) * depth_m[i] / speed_mps[i]  # z sin(theta) / c, s
        for j in range(n_freq):
            a = np.exp(ratio[j] * log_a)
            s = np.sin(2.0 * np.pi * freqs_hz[j] * path)
            g = 2.0 * s * s
            for c in range(n_class):
                plain[c, i] += weights[c, j] * a
                lloyd[c, i] += weights[c, j] * a * g
    return plain, lloyd


@njit(cache=True)
def pair_sums(intensity, factor, angle_deg, bounces, offsets, tolerance_deg):
    """``offsets[i]:offsets[i + 1]`` are receiver i's arrivals, with their intensity and Lloyd
    factor. Strongest first, each unmatched arrival takes the strongest unmatched twin (angle of
    the other sign, magnitude within ``tolerance_deg[i]``, surface reflections differing by at most
    one); the pair adds max(I_a, I_b) (G_a + G_b), an arrival without a twin 2 I_a G_a (its twin
    was cut by the beams' truncation at the surface): the two members of an image pair carry
    one intensity, and each its own angle's factor."""
    n = offsets.size - 1
    out = np.zeros(n)
    for i in range(n):
        lo, hi = offsets[i], offsets[i + 1]
        m = hi - lo
        if m == 0:
            continue
        order = np.argsort(-intensity[lo:hi]) + lo
        used = np.zeros(m, dtype=np.bool_)
        total = 0.0
        for a in order:
            if used[a - lo]:
                continue
            used[a - lo] = True
            best, best_value = -1, -1.0
            for b in order:
                if used[b - lo] or (angle_deg[b] < 0.0) == (angle_deg[a] < 0.0):
                    continue
                if abs(abs(angle_deg[b]) - abs(angle_deg[a])) >= tolerance_deg[i]:
                    continue
                if abs(bounces[b] - bounces[a]) > 1.0:
                    continue
                if intensity[b] > best_value:
                    best, best_value = b, intensity[b]
            if best >= 0:
                used[best - lo] = True
                total += intensity[a] * (factor[a] + factor[best])
            else:
                total += 2.0 * intensity[a] * factor[a]
        out[i] = total
    return out
