"""Volume absorption of sound in sea water."""

from __future__ import annotations

import numpy as np

from envdata.area import Absorption


def thorp_db_per_km(freq_hz):
    """Thorp volume attenuation as BELLHOP applies it (its option 'T'), dB/km.

    alpha = 3.3e-3 + 0.11 f^2 / (1 + f^2) + 44 f^2 / (4100 + f^2) + 3.0e-4 f^2, f in kHz.

    References
    ----------
    Jensen, Kuperman, Porter & Schmidt, Computational Ocean Acoustics, eq. 1.34 (the form
    BELLHOP's AttenMod uses), after Thorp (1967).
    """
    f2 = (np.asarray(freq_hz, dtype=float) / 1000.0) ** 2  # the formula is written in kHz
    return 3.3e-3 + 0.11 * f2 / (1.0 + f2) + 44.0 * f2 / (4100.0 + f2) + 3.0e-4 * f2


def absorption_db_per_km(freq_hz, model: Absorption):
    """Volume attenuation by the area's model, dB/km (zero for ``Absorption.NONE``)."""
    if model is Absorption.THORP:
        return thorp_db_per_km(freq_hz)
    return np.zeros_like(np.asarray(freq_hz, dtype=float))
