"""Band quantities: spectral terms of eq. 13, band-averaged TL, and K(r) = spectral term - TL.

A band level is W = P0 + 10 lg int S(f)/S(f_ref) df - TL_band (Grinenkov & Mashoshin eq. 12 with
K = W - P0): the class spectrum S(f) ~ f^a (a = -2 for the -6 dB/octave behind eq. 13) weights
the intensity average that defines TL_band, and P0 is the spectral level at f_ref (1 kHz for
the 'p0' model, the band centre for the Ross model).
"""

from __future__ import annotations

import math

import numpy as np

from envdata.bands import Band
from envdata.classes import TargetClass


def reference_frequency_hz(cls: TargetClass, band: Band) -> float:
    ref = cls.reference_frequency_hz
    return band.center_hz if ref is None else ref


def spectral_term_db(cls: TargetClass, band: Band) -> float:
    """10 lg of the integral of (f / f_ref)^a over the band, dB (the first two terms of eq. 13).

    For a = -2 and f_ref = 1 kHz this is exactly -20 lg f_ekv[kHz] + 10 lg (f_high - f_low)[Hz];
    for a single-frequency band it is the spectral term alone (1 Hz band, no bandwidth term).
    """
    a = cls.spectral_exponent
    ref = reference_frequency_hz(cls, band)
    if band.is_single_frequency:
        return 10.0 * a * math.log10(band.low_hz / ref)
    lo, hi = band.low_hz / ref, band.high_hz / ref
    integral = math.log(hi / lo) if abs(a + 1.0) < 1e-12 else (hi ** (a + 1) - lo ** (a + 1)) / (a + 1)
    return 10.0 * math.log10(integral * ref)


def band_frequencies_hz(band: Band, n: int) -> np.ndarray:
    """Quadrature frequencies across the band, spaced evenly in log frequency."""
    if band.is_single_frequency or n == 1:
        return np.array([band.center_hz])
    return np.geomspace(band.low_hz, band.high_hz, n)


def band_weights(cls: TargetClass, freqs_hz: np.ndarray) -> np.ndarray:
    """Weights w_i (sum 1) of the spectrum-weighted intensity average over the band.

    Trapezoid rule in ln f of int S(f) I(f) df = int f S(f) I(f) d(ln f), S(f) ~ f^a.
    """
    f = np.asarray(freqs_hz, dtype=float)
    if f.size == 1:
        return np.ones(1)
    x = np.log(f)
    trapz = np.zeros_like(x)
    dx = np.diff(x)
    trapz[:-1] += dx / 2
    trapz[1:] += dx / 2
    w = trapz * (f / f[0]) ** (cls.spectral_exponent + 1.0)
    return w / w.sum()


def band_average_tl_db(tl_db_per_freq: np.ndarray, weights: np.ndarray, tl_max_db: float) -> np.ndarray:
    """Band TL from TL at the quadrature frequencies (first axis): averages intensity, never dB."""
    intensity = np.tensordot(weights, 10.0 ** (-np.asarray(tl_db_per_freq, dtype=float) / 10.0), axes=1)
    floor = 10.0 ** (-tl_max_db / 10.0)
    return -10.0 * np.log10(np.maximum(intensity, floor))
