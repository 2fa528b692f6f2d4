"""Frequency bands in which the sonar measures a target's signal level."""

from __future__ import annotations

import math
from dataclasses import dataclass

from envdata.errors import AreaError
from envdata.names import check_name


@dataclass(frozen=True, slots=True, kw_only=True)
class Band:
    """A frequency band [low_hz, high_hz]; equal bounds make a single frequency (1 Hz band)."""

    name: str
    low_hz: float
    high_hz: float

    def __post_init__(self) -> None:
        check_name(self.name, "band name")
        if not (math.isfinite(self.low_hz) and math.isfinite(self.high_hz)):
            raise AreaError(f"band {self.name!r}: bounds must be finite, "
                            f"got {self.low_hz} Hz, {self.high_hz} Hz")
        if not 0 < self.low_hz <= self.high_hz:  # equal bounds: one frequency
            raise AreaError(f"band {self.name!r}: need 0 < low_hz <= high_hz, "
                            f"got {self.low_hz} Hz, {self.high_hz} Hz")

    @property
    def center_hz(self) -> float:
        """Equivalent (geometric-mean) frequency f_ekv of eq. 13, Hz."""
        return math.sqrt(self.low_hz * self.high_hz)

    @property
    def is_single_frequency(self) -> bool:
        return self.low_hz == self.high_hz

    @property
    def width_hz(self) -> float:
        """Bandwidth used in eqs. 11 and 13, Hz; 1 Hz for a single frequency (spectral level)."""
        return 1.0 if self.is_single_frequency else self.high_hz - self.low_hz
