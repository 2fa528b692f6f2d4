"""The receiving array: what sets bearing accuracy (eq. 2) and level accuracy (eq. 11)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from envdata.errors import AreaError


@dataclass(frozen=True, slots=True, kw_only=True)
class Sonar:
    beamwidth_deg: float
    directivity_index_db: float
    integration_time_s: float
    detection_threshold: float  # linear indicator SNR Q = q sqrt(df T) at which a band is detected
    receiver_gain_db: float = 0.0  # H_k of eq. 12

    def __post_init__(self) -> None:
        checks = (("beamwidth_deg", self.beamwidth_deg, 0.0, 360.0, "deg"),
                  ("directivity_index_db", self.directivity_index_db, 0.0, 60.0, "dB"),
                  ("integration_time_s", self.integration_time_s, 0.0, 3600.0, "s"),
                  ("detection_threshold", self.detection_threshold, 0.0, 1e6, ""))
        for name, value, lo, hi, unit in checks:
            if not (math.isfinite(value) and lo < value <= hi) and not (name == "directivity_index_db"
                                                                      and value == 0.0):
                raise AreaError(f"[sonar] {name}: must be in ({lo:g}, {hi:g}] {unit}, got {value}".rstrip())
        if not math.isfinite(self.receiver_gain_db):
            raise AreaError(f"[sonar] receiver_gain_db: must be finite, got {self.receiver_gain_db}")
