"""Settings of the regularized particle filter: `RpfConfig` and `Engine`.

References
----------
E. Iglesis, L. de Montella, "Target motion analysis using combined bearings and underwater
sound pressure levels", hal-04796331 (2024), sec. 5 (the default values).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from tracker.rpf.regularise import optimal_bandwidth

#: One knot, m/s (the papers give speeds in knots).
KNOT_MPS = 1852.0 / 3600.0
#: Runs are filtered in blocks of about this many particles (runs x N): a block's arrays then
#: stay in a core's L2 cache (2 MiB), which is faster than one large array of every run.
BLOCK_PARTICLES = 20_000
#: The acceleration sds a bearings-only filter shares out (`RpfConfig.sigma_a_mix_mps2`; the
#: command's ``rpf-bot`` and the studies'): the paper's 1.5e-3 m/s^2 and a fifth and a fifteenth
#: of it. On bearings alone the paper's sd tilts the model's own posterior outward where the range
#: is open (`tracker.rpf.gaussiansum`); with the three the bearings' evidence picks, and a
#: manoeuvring target keeps the paper's.
BEARINGS_ONLY_SIGMA_A_MIX_MPS2 = (1e-4, 3e-4, 1.5e-3)


class Engine(StrEnum):
    """The cycle loop of `tracker.rpf.batch.run_batch`: the compiled fused loop of
    `tracker.rpf.kernel` (the default), or the numpy reference implementation of
    `tracker.rpf.batch` (same statistics, other random numbers)."""

    KERNEL = "kernel"
    NUMPY = "numpy"


@dataclass(frozen=True, slots=True, kw_only=True)
class RpfConfig:
    """Settings of the filter; defaults are the paper's (sec. 5).

    Attributes
    ----------
    n_particles : int
        N (5000).
    sigma_a_mps2 : float
        Acceleration process-noise sd, m/s^2 (1.5e-3; docs/idm.md reads the paper's Q = sigma_a I
        with sigma_a a standard deviation).
    sigma_a_mix_mps2 : tuple of float
        Not in the paper: () (default) gives every particle ``sigma_a_mps2``; else the
        acceleration sds the particles take in turn (particle i the (i mod M)-th), each keeping
        its own through every resampling. The sd is then a static unknown of the track whose
        posterior the weights carry: where the bearings leave the range open, the paper's sd
        tilts the model's posterior outward and the bearings' evidence prefers a smaller one
        (`tracker.rpf.gaussiansum`, docs/depth.md); with the mixture the measurements choose.
    bearing_sigma_deg : float
        sigma_theta of eq. 32, deg (1.5).
    level_sigma_db : float
        sigma_l of eq. 33 used by the filter, dB (10; the paper simulates with 4).
    neff_fraction : float
        N_thr / N (1/3).
    range_mean_m, range_sd_m : float
        Prior range, m (10 km, 2 km).
    range_span_m : tuple of float
        Not in the paper: () (default) draws the prior range from N(``range_mean_m``,
        ``range_sd_m``); two ranges (near, far), m, draw it log-uniform between them instead
        (each factor of range as likely), the prior of a target whose range nobody knows. The
        paper's 10 +- 2 km is its scenario's: a target 20 km off starts five sds out, and the
        command's filter then stated 90 % intervals that held the truth in 17 % of the cycles
        (docs/uncertainty.md, "The command's range prior").
    speed_mean_mps, speed_sd_mps : float
        Prior target speed, m/s (3 kn, 2 kn).
    course_sd_deg : float
        Prior course sd about the first bearing + 180 deg, deg (pi/sqrt(12) rad).
    sl_offset_sd_db : float
        Not in the paper: 0 (default) keeps the 4-component state; > 0 adds a source-level
        offset (dB, prior N(0, sd^2)) estimated jointly with the motion.
    shrink : bool
        Not in the paper: False (default) regularizes as Musso et al. (x = x' + h D eps, which
        inflates the particle covariance by 1 + h^2/(n+4) at each resampling); True shrinks the
        resampled particles toward the weighted mean m first (x = m + a (x' - m) + h D eps,
        a = sqrt(1 - h^2/(n+4))), so that the regularization keeps the covariance. The
        inflation acts as artificial process noise on the velocity; when the bearings carry no
        range information (observer parallel to the target) it lets the filter forget the
        speed prior and drift out along the SL(v) - TL(r) ridge.
    bandwidth_scale : float
        Not in the paper: the regularization kernel's bandwidth is this times eqs. 27-28's h (1,
        the paper's). That h is MISE-optimal for a Gaussian density, and wider than the cloud
        of a posterior with narrow or several modes can stand: each resampling then moves the
        particles off a narrow peak of the levels' likelihood into the broad hills around it
        (docs/uncertainty.md, "The particle cloud's kernel").
    engine : Engine
        The cycle loop (`Engine`; the compiled kernel by default).
    """

    n_particles: int = 5000
    sigma_a_mps2: float = 1.5e-3
    sigma_a_mix_mps2: tuple[float, ...] = ()
    bearing_sigma_deg: float = 1.5
    level_sigma_db: float = 10.0
    neff_fraction: float = 1.0 / 3.0
    range_mean_m: float = 10_000.0
    range_sd_m: float = 2_000.0
    range_span_m: tuple[float, ...] = ()
    speed_mean_mps: float = 3.0 * KNOT_MPS
    speed_sd_mps: float = 2.0 * KNOT_MPS
    course_sd_deg: float = math.degrees(math.pi / math.sqrt(12.0))
    sl_offset_sd_db: float = 0.0
    shrink: bool = False
    bandwidth_scale: float = 1.0
    engine: Engine = Engine.KERNEL

    def __post_init__(self) -> None:
        if int(self.n_particles) != self.n_particles or self.n_particles < 2:
            raise ValueError(f"n_particles must be an integer >= 2, got {self.n_particles}")
        for name in ("sigma_a_mps2", "sl_offset_sd_db"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be >= 0, got {v}")
        for name in ("bearing_sigma_deg", "level_sigma_db", "range_mean_m", "range_sd_m",
                     "speed_sd_mps", "course_sd_deg", "bandwidth_scale"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be > 0, got {v}")
        mix = tuple(float(v) for v in self.sigma_a_mix_mps2)
        if any(not (math.isfinite(v) and v >= 0) for v in mix):
            raise ValueError(f"sigma_a_mix_mps2 must hold sds >= 0, got {self.sigma_a_mix_mps2}")
        if len(mix) > self.n_particles:
            raise ValueError(f"sigma_a_mix_mps2 has {len(mix)} sds for {self.n_particles} particles")
        object.__setattr__(self, "sigma_a_mix_mps2", mix)
        span = tuple(float(v) for v in self.range_span_m)
        if span and not (len(span) == 2 and all(math.isfinite(v) for v in span) and 0 < span[0] < span[1]):
            raise ValueError(f"range_span_m must be () or (near, far) with 0 < near < far, got {self.range_span_m}")
        object.__setattr__(self, "range_span_m", span)
        object.__setattr__(self, "engine", Engine(self.engine))
        if not 0.0 < self.neff_fraction <= 1.0:
            raise ValueError(f"neff_fraction must be in (0, 1], got {self.neff_fraction}")

    @property
    def bandwidth(self) -> float:
        """The regularization kernel's h: eqs. 27-28's for N and n_x, times ``bandwidth_scale``."""
        return self.bandwidth_scale * optimal_bandwidth(self.n_particles, self.n_dim)

    @property
    def particle_sigma_a_mps2(self) -> tuple[float, ...]:
        """The acceleration sds the particles take in turn (``sigma_a_mix_mps2``, else the one
        ``sigma_a_mps2``), m/s^2."""
        return self.sigma_a_mix_mps2 or (self.sigma_a_mps2,)

    @property
    def n_dim(self) -> int:
        """State dimension n_x: 4, or 5 with the source-level offset."""
        return 5 if self.sl_offset_sd_db > 0 else 4
