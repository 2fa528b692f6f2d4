"""Ambient sea noise: a spectrum level at 1 kHz and a slope in dB per octave."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from envdata.bands import Band
from envdata.errors import AreaError


@dataclass(frozen=True, slots=True, kw_only=True)
class Noise:
    spectrum_level_1khz_db: float  # dB re 1 uPa^2/Hz at 1 kHz
    slope_db_per_octave: float = -5.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.spectrum_level_1khz_db) and 0.0 <= self.spectrum_level_1khz_db <= 150.0):
            raise AreaError(f"[noise] spectrum_level_1khz_db: must be in [0, 150] dB re 1 uPa^2/Hz, "
                            f"got {self.spectrum_level_1khz_db}")
        if not (math.isfinite(self.slope_db_per_octave) and -20.0 <= self.slope_db_per_octave <= 10.0):
            raise AreaError(f"[noise] slope_db_per_octave: must be in [-20, 10] dB/octave, "
                            f"got {self.slope_db_per_octave}")

    def spectrum_level_db(self, freq_hz):
        """Spectral level at ``freq_hz``, dB re 1 uPa^2/Hz."""
        return self.spectrum_level_1khz_db + self.slope_db_per_octave * np.log2(np.asarray(freq_hz) / 1000.0)

    def band_level_db(self, band: Band) -> float:
        """Noise level in the band, dB re 1 uPa (the spectral level for a single-frequency band)."""
        if band.is_single_frequency:
            return float(self.spectrum_level_db(band.low_hz))
        # integrate the power spectrum N(f) = N(1 kHz) (f / 1 kHz)^a analytically
        a = self.slope_db_per_octave / (10.0 * math.log10(2.0))
        lo, hi = band.low_hz / 1000.0, band.high_hz / 1000.0
        integral_khz = math.log(hi / lo) if abs(a + 1.0) < 1e-12 else (hi ** (a + 1) - lo ** (a + 1)) / (a + 1)
        return self.spectrum_level_1khz_db + 10.0 * math.log10(integral_khz * 1000.0)
