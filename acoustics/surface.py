"""The sea surface at the target's end of a path: Lloyd's mirror, band-averaged.

A source at depth z under the pressure-release surface interferes with its image at -z: a ray
leaving at grazing angle theta and its surface-reflected twin differ in path by 2 z sin(theta)
and in sign, so their summed intensity is the single ray's times

    G(theta, f) = 2 sin^2(k z sin(theta)),    k = 2 pi f / c(z)            (Lloyd's mirror)

relative to the incoherent sum of the two (which counts each once: factor 1 on average). Below
f ~ c / (4 z sin(theta)) the pair radiates as a dipole (G ~ 2 (k z theta)^2, a loss) -- for a
surface ship at 6 m and 100 Hz over the deep channel's angles that is 6-7 dB that incoherent
beams do not see. BELLHOP's semicoherent mode multiplies each beam's launch amplitude by sqrt(G)
at one frequency; over a band the intensity average of those runs is one run with the band
average of G as the source's beam pattern (``band_lloyd_factor``: the band's spectrum weights
the frequencies), because in incoherent beams frequency acts otherwise only through volume
absorption. By reciprocity the same factor belongs to a receiver at depth z, at the angle each
arrival reaches it (``acoustics.builder.surfaceimage``).

The surface acts within a few wavelengths of it (``surface_reach_m``); deeper, the band average
of G is 1 except at grazing angles that carry no energy, and the end is left incoherent.
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.kcurve import band_weights
from envdata.bands import Band
from envdata.classes import TargetClass

#: The surface acts within this many wavelengths (at the band's lowest frequency) of it: the
#: Lloyd cut-off angle there is asin(1 / (4 * 5)) = 2.9 deg. Measured on the Munk channel at
#: 100 Hz against KRAKEN's coherent field averaged over 1 km: at 70 m (4.5 wavelengths) the
#: mirror brings the median error from 2.6 to 2.4 dB and the mean from -1.4 to -0.2 dB; at
#: 100 m (6.5) it makes the median worse (2.4 -> 3.4 dB); docs/models.md "The sea surface".
REACH_WAVELENGTHS = 5.0

#: Quadrature frequencies across a band per wavelength of path difference: the band average of
#: G is an integral over frequency whose integrand turns 2 z sin(theta) / lambda times.
_POINTS_PER_TURN = 8
_MIN_POINTS, _MAX_POINTS = 33, 4097


def surface_reach_m(band: Band, speed_mps: float) -> float:
    """Depth within which the surface acts on a band's levels, m (``REACH_WAVELENGTHS``
    wavelengths at the band's lowest frequency)."""
    return REACH_WAVELENGTHS * speed_mps / band.low_hz


def band_quadrature(cls: TargetClass, band: Band, depth_m: float, speed_mps: float, *,
                    points_per_turn: int = _POINTS_PER_TURN, min_points: int = _MIN_POINTS
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (Hz) and weights (sum 1) of the band's spectrum-weighted average of
    ``lloyd_factor`` for an end at ``depth_m``: dense enough to follow G's turns at grazing 90 deg
    (``points_per_turn`` of them a turn, at least ``min_points``)."""
    if band.is_single_frequency:
        return np.array([band.center_hz]), np.ones(1)
    turns = 2.0 * depth_m * (band.high_hz - band.low_hz) / speed_mps  # of k 2 z across the band
    n = int(np.clip(points_per_turn * turns + 1, min_points, _MAX_POINTS))
    freqs = np.geomspace(band.low_hz, band.high_hz, n)
    return freqs, band_weights(cls, freqs)  # the class spectrum's weights, trapezoids in ln f


def lloyd_factor(depth_m, speed_mps, freqs_hz, weights, angle_deg) -> np.ndarray:
    """Band average of G = 2 sin^2(k z sin(theta)) at each grazing angle, intensity ratio.

    Parameters
    ----------
    depth_m : float or array_like
        Depth of the end (source or receiver) under the surface, m (an array broadcasts
        against ``angle_deg``: one end per angle).
    speed_mps : float or array_like
        Sound speed there, m/s (likewise).
    freqs_hz, weights : array_like
        The band's quadrature (``band_quadrature``); one frequency for a tone.
    angle_deg : array_like
        Ray angles at the end, deg (either sign).
    """
    freqs = np.asarray(freqs_hz, dtype=float)
    w = np.asarray(weights, dtype=float)
    # z sin(theta) / c for each end, then times omega for each frequency
    slowness_path = np.sin(np.radians(np.asarray(angle_deg, dtype=float))) * np.asarray(depth_m, dtype=float) \
        / np.asarray(speed_mps, dtype=float)
    phase = np.multiply.outer(slowness_path, 2.0 * math.pi * freqs)  # (..., frequency)
    return 2.0 * (np.sin(phase) ** 2) @ w


def band_lloyd_factor(cls: TargetClass, band: Band, depth_m: float, speed_mps: float, angle_deg) -> np.ndarray:
    """``lloyd_factor`` averaged over ``band`` with ``cls``'s spectrum."""
    freqs, w = band_quadrature(cls, band, depth_m, speed_mps)
    return lloyd_factor(depth_m, speed_mps, freqs, w, angle_deg)


def incoherent_error_db(cls: TargetClass, band: Band, depth_m: float, speed_mps: float,
                        max_angle_deg: float) -> float:
    """How much louder incoherent beams make a target at ``depth_m`` in ``band`` than the
    surface lets it be, dB (negative: too loud): 10 lg of the band-averaged Lloyd factor over
    the angles that carry its sound far, uniformly in angle up to ``max_angle_deg`` (the
    angle trapped by the bottom, or the fan's edge)."""
    angles = np.linspace(-max_angle_deg, max_angle_deg, 721)
    g = band_lloyd_factor(cls, band, depth_m, speed_mps, angles)
    return float(10.0 * np.log10(max(float(np.mean(g)), 1e-30)))


#: Rows a table from the observer adds within the first step of its depth axis (fractions of
#: the step), where the surface acts: the loss grows without bound toward the surface (the
#: dipole's 20 lg z), so a target at 5 m is not read between the surface and 10 m.
SURFACE_ROWS = (0.125, 0.25, 0.5)


def with_surface_rows(depth_m) -> np.ndarray:
    """A depth axis from 0 with ``SURFACE_ROWS`` added within its first step, m."""
    z = np.asarray(depth_m, dtype=float)
    if z.size < 2 or z[0] != 0.0:
        return z
    return np.unique(np.concatenate([z, z[1] * np.asarray(SURFACE_ROWS)]))


#: Depth whose loss a table from the observer holds in its 0 m row, m: the pressure-release
#: surface itself has no level and no target is there, and interpolating in depth then stays
#: between losses the table computed (whatever its step).
SURFACE_ROW_M = 1.0
