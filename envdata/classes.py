"""Target classes: radiating depth, speed and noise statistics (Grinenkov & Mashoshin Table 1)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from envdata.errors import AreaError
from envdata.names import check_name

# A spectrum falling as f^-2 falls by 20 lg 2 = 6.02 dB per octave (the spectrum behind eq. 13).
F_MINUS_2_DB_PER_OCTAVE = -20.0 * math.log10(2.0)


class SourceLevelModel(StrEnum):
    P0 = "p0"      # noise_mean_db: spectral level at 1 kHz, 1 Hz band, 1 m
    ROSS = "ross"  # SL(v) = 170 + 53 lg(v / 5.14 m/s) at the band centre (Iglesis & de Montella eq. 12)


#: Ross source level (Iglesis & de Montella eq. 12): SL = ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE
#: lg(v / ROSS_REFERENCE_SPEED_MPS), dB re 1 uPa^2/Hz at 1 m at the band centre.
ROSS_LEVEL_DB = 170.0
ROSS_SLOPE_DB_PER_DECADE = 53.0
ROSS_REFERENCE_SPEED_MPS = 5.14  # 10 kn
#: Speeds below this are taken as it, so that a stopped target has a finite level, m/s.
ROSS_MIN_SPEED_MPS = 0.01


def ross_source_level_db(speed_mps):
    """Ross source level, dB re 1 uPa^2/Hz at 1 m, at the band centre.

    Parameters
    ----------
    speed_mps : array_like
        Target speed, m/s; below `ROSS_MIN_SPEED_MPS` the level of that speed (finite at 0).

    References
    ----------
    Iglesis & de Montella (2024), eq. 12: SL = 170 + 53 log10(v / 5.14 m/s).
    """
    import numpy as np

    v = np.maximum(np.asarray(speed_mps, dtype=float), ROSS_MIN_SPEED_MPS)
    return ROSS_LEVEL_DB + ROSS_SLOPE_DB_PER_DECADE * np.log10(v / ROSS_REFERENCE_SPEED_MPS)


@dataclass(frozen=True, slots=True, kw_only=True)
class TargetClass:
    """A class hypothesis: where it radiates from, how fast and how loud it is."""

    name: str
    depth_m: float
    speed_mean_mps: float
    speed_sd_mps: float
    noise_mean_db: float | None = None
    noise_sd_db: float = 0.0
    k_error_sd_db: float = 2.0
    source_slope_db_per_octave: float = F_MINUS_2_DB_PER_OCTAVE
    source_level_model: SourceLevelModel = SourceLevelModel.P0
    #: Depths the target may be at, m (min, max), when its depth is unknown (``tmakit track
    #: --target-depth unknown``); None: the water column the tables hold. ``depth_m`` stays the
    #: depth the tables are computed at.
    depth_range_m: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        where = f"class {self.name!r}"
        if self.depth_range_m is not None:
            span = tuple(float(v) for v in self.depth_range_m)
            if len(span) != 2 or not all(math.isfinite(v) for v in span) or not 0.0 <= span[0] < span[1]:
                raise AreaError(f"{where}: depth_range_m must be two depths [min, max] with "
                                f"0 <= min < max, m, got {list(self.depth_range_m)}")
            object.__setattr__(self, "depth_range_m", span)
        check_name(self.name, "class name")
        for field_name, value, lo in (("depth_m", self.depth_m, 0.0),
                                      ("speed_mean_mps", self.speed_mean_mps, 0.0)):
            if not (math.isfinite(value) and value > lo):
                raise AreaError(f"{where}: {field_name} must be > {lo:g}, got {value}")
        for field_name, value in (("speed_sd_mps", self.speed_sd_mps),
                                  ("noise_sd_db", self.noise_sd_db),
                                  ("k_error_sd_db", self.k_error_sd_db)):
            if not (math.isfinite(value) and value >= 0):
                raise AreaError(f"{where}: {field_name} must be >= 0, got {value}")
        if not (math.isfinite(self.source_slope_db_per_octave)
                and -40.0 <= self.source_slope_db_per_octave <= 20.0):
            raise AreaError(f"{where}: source_slope_db_per_octave must be in [-40, 20] dB/octave, "
                            f"got {self.source_slope_db_per_octave}")
        if self.source_level_model is SourceLevelModel.P0:
            if self.noise_mean_db is None or not math.isfinite(self.noise_mean_db):
                raise AreaError(f"{where}: noise_mean_db is required (finite, dB re 1 uPa) "
                                f"with source_level_model = 'p0', got {self.noise_mean_db}")

    @property
    def spectral_exponent(self) -> float:
        """Exponent a of the radiated power spectrum S(f) ~ f^a (a = -2 for -6.02 dB/octave)."""
        return self.source_slope_db_per_octave / (10.0 * math.log10(2.0))

    @property
    def reference_frequency_hz(self) -> float | None:
        """Frequency at which the class's level is given: 1 kHz for P0, the band centre for Ross."""
        return 1000.0 if self.source_level_model is SourceLevelModel.P0 else None
