"""The sea floor as an acousto-elastic half-space (BELLHOP bottom option 'A')."""

from __future__ import annotations

import math
from dataclasses import dataclass

from envdata.errors import AreaError


@dataclass(frozen=True, slots=True, kw_only=True)
class Bottom:
    speed_mps: float
    density_gcc: float
    attenuation_db_per_wavelength: float = 0.0
    shear_speed_mps: float = 0.0

    def __post_init__(self) -> None:
        checks = (("speed_mps", self.speed_mps, 1000.0, 6000.0, "m/s"),
                  ("density_gcc", self.density_gcc, 1.0, 4.0, "g/cm^3"),
                  ("attenuation_db_per_wavelength", self.attenuation_db_per_wavelength, 0.0, 10.0,
                   "dB/wavelength"),
                  ("shear_speed_mps", self.shear_speed_mps, 0.0, 4000.0, "m/s"))
        for name, value, lo, hi, unit in checks:
            if not (math.isfinite(value) and lo <= value <= hi):
                raise AreaError(f"[bottom] {name}: must be in [{lo:g}, {hi:g}] {unit}, got {value}")
