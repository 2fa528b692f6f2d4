"""The compiled loop's inputs and outputs, in named groups, and how they are built from the
filter's settings.

Each group is a `typing.NamedTuple`, which numba passes to compiled code as a plain struct:
reading a field costs what reading a separate argument did. Scalars are converted to Python
``float``, ``int`` and ``bool`` and arrays to C-ordered float64 or int64 copies here, so that
every call has the same type signature (another signature would be another compile).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from tracker.levels import cycle_prior_variance


class Observer(NamedTuple):
    """The observer's track, the same for every run.

    Attributes
    ----------
    t_s : ndarray, shape (K,)
        Cycle times, s.
    state : ndarray, shape (K, 4)
        Observer (x, y, vx, vy) at each cycle, m and m/s.
    """

    t_s: np.ndarray
    state: np.ndarray


class Measured(NamedTuple):
    """Measurements of a block of runs (leading axis ``runs``) or of one run.

    Attributes
    ----------
    bearing_rad : ndarray, shape ([runs,] K)
        Measured bearings, rad; NaN: none that cycle.
    bearing_sd_rad : ndarray, shape ([runs,] K)
        Their sds, rad (eq. 2's at each cycle's SNR, or the filter's sigma_theta).
    level_db : ndarray, shape ([runs,] K, B)
        Measured SPL of each band, dB re 1 uPa; NaN: none that cycle. Unused (zeros, one
        cycle and band) when `Model.use_level` is False.
    """

    bearing_rad: np.ndarray
    bearing_sd_rad: np.ndarray
    level_db: np.ndarray


class Profiles(NamedTuple):
    """The distinct K(r) profiles of the cycles and bands, stacked (`profile_arrays`): the
    level model with the target's depth fixed.

    Attributes
    ----------
    index : ndarray of int64, shape (B, K)
        Row of each band's and cycle's profile (0 where it has none).
    range_m, k_db : ndarray, shape (P, M)
        Range axes, m, and K values, dB, padded with their last value.
    length : ndarray of int64, shape (P,)
        Number of points of each.
    k_sd_db : ndarray, shape (P, M)
        sd of the K error along the same ranges, dB (zeros where a profile has none).
    has_sd : bool
        Whether any profile has one: the level likelihood's variance is then sigma_l^2 + sd(r)^2.
    """

    index: np.ndarray
    range_m: np.ndarray
    k_db: np.ndarray
    length: np.ndarray
    k_sd_db: np.ndarray
    has_sd: bool


class Errors(NamedTuple):
    """The levels' error components each particle integrates out (`tracker.levels.LevelErrors`,
    `tracker.rpf.kernel.levelerrors`), or none (``on`` False: the level likelihood is white
    with sigma_l, the paper's).

    Attributes
    ----------
    on : bool
    h : ndarray, shape (B, S)
        Loadings of the components on each band.
    var : ndarray, shape (K, S)
        Each component's prior variance at each cycle, dB^2 (its sd grown with the observer's
        distance from where the tables were computed).
    inv_time_s, inv_length_m : ndarray, shape (S,)
        1 / correlation time, 1/s, and 1 / correlation length along the path, 1/m (0: none).
    """

    on: bool
    h: np.ndarray
    var: np.ndarray
    inv_time_s: np.ndarray
    inv_length_m: np.ndarray


def errors_of(level_errors, n_bands: int, n_cycles: int, displacement_m=None) -> Errors:
    """The `Errors` group of a `tracker.levels.LevelErrors` (None: off) for ``n_bands`` bands and
    ``n_cycles`` cycles, the observer ``displacement_m`` (K,) from the tables' origin (default 0)."""
    if level_errors is None:
        return Errors(False, np.zeros((n_bands, 1)), np.zeros((n_cycles, 1)), np.zeros(1), np.zeros(1))
    a = level_errors.arrays(n_bands)
    var = cycle_prior_variance(a, n_cycles, displacement_m)
    c = np.ascontiguousarray
    return Errors(True, c(a["h"], dtype=float), c(var, dtype=float), c(a["inv_time_s"], dtype=float),
                  c(a["inv_length_m"], dtype=float))


class Prior(NamedTuple):
    """The prior the particles are drawn from (`tracker.rpf.prior.initial_particles`).

    Attributes
    ----------
    range_mean_m, range_sd_m : float
        Range, m (normal).
    range_log_near, range_log_span : float
        ln of the log-uniform prior's near range (m) and ln(far / near); span 0: the normal.
    bearing_sd_rad : float
        Bearing sd about the first bearing, rad.
    speed_mean_mps, speed_sd_mps : float
        Target speed, m/s.
    course_sd_rad : float
        Course sd about the first bearing + pi, rad.
    offset_sd_db : float
        Source-level offset sd, dB (used with D = 5).
    """

    range_mean_m: float
    range_sd_m: float
    range_log_near: float
    range_log_span: float
    bearing_sd_rad: float
    speed_mean_mps: float
    speed_sd_mps: float
    course_sd_rad: float
    offset_sd_db: float


class Model(NamedTuple):
    """Motion and measurement model.

    Attributes
    ----------
    sigma_a_mps2 : ndarray, shape (M,)
        Acceleration process-noise sds, m/s^2 (eq. 6): particle i keeps the (i mod M)-th through
        every resampling (`tracker.rpf.config.RpfConfig.sigma_a_mix_mps2`; M = 1: the paper's one).
    sigma_theta_rad : float
        Bearing sd of eq. 32, rad.
    use_level : bool
        Whether the SPL enters the likelihood (eq. 31) or the bearings alone (eq. 32).
    ross : bool
        Source level SL(v) of eq. 12 (True) or the constant ``p0_db``.
    p0_db : float
        Source level of the constant model, dB.
    sigma_l_db : float
        Level sd of eq. 33, dB.
    """

    sigma_a_mps2: np.ndarray
    sigma_theta_rad: float
    use_level: bool
    ross: bool
    p0_db: float
    sigma_l_db: float


class Settings(NamedTuple):
    """Size and resampling settings of the filter.

    Attributes
    ----------
    n : int
        Particles per run, N.
    d : int
        State dimension, D (4, or 5 with the source-level offset).
    n_thr : float
        N_thr: resample when N_eff (eq. 20) falls below it.
    bandwidth : float
        Kernel bandwidth h (eqs. 27-28).
    shrink : bool
        Variance-preserving regularization (`RpfConfig.shrink`).
    summaries : bool
        Whether to write the particle spreads of each cycle.
    """

    n: int
    d: int
    n_thr: float
    bandwidth: float
    shrink: bool
    summaries: bool


class Outputs(NamedTuple):
    """What the loop writes, for a block of runs (leading axis ``runs``) or for one run.

    Attributes
    ----------
    means : ndarray, shape (runs, K, D)
        Estimates after each cycle (eq. 29).
    covs : ndarray, shape (runs, K, D, D)
        Their covariances (eq. 30).
    resampled : ndarray of uint8, shape (runs, K)
        1 where the regularization-resampling step ran.
    sds : ndarray, shape (runs, K, 3), or (runs, 1, 3) without summaries
        Range sd, m, course sd, deg, and speed sd, m/s, of the particles.
    """

    means: np.ndarray
    covs: np.ndarray
    resampled: np.ndarray
    sds: np.ndarray


def profile_arrays(k_profiles, n_cycles: int, n_bands: int = 1) -> Profiles:
    """Stack the distinct K(r) profiles (objects with ``range_m`` and ``k_db``) of the cycles.

    Parameters
    ----------
    k_profiles : sequence of LevelProfile or None, length K, or None; or, for several bands, a
        sequence of ``n_bands`` of those
        The profile of each cycle (`tracker.tables.LevelProfile`); None: no level that cycle.
    n_cycles : int
        K.
    n_bands : int
        B: ``k_profiles`` is one per-cycle sequence per band when B > 1.
    """
    per_band = [k_profiles] if n_bands == 1 or k_profiles is None else list(k_profiles)
    rows, where, sds = [], {}, []
    prof_idx = np.zeros((n_bands, n_cycles), dtype=np.int64)
    for b, profiles in enumerate(per_band):
        for k in range(n_cycles):
            p = None if profiles is None else profiles[k]
            if p is None:
                continue
            if id(p) not in where:
                where[id(p)] = len(rows)
                rows.append((np.asarray(p.range_m, dtype=float), np.asarray(p.k_db, dtype=float)))
                sds.append(getattr(p, "k_sd_db", None))
            prof_idx[b, k] = where[id(p)]
    if not rows:
        return Profiles(prof_idx, np.zeros((1, 1)), np.zeros((1, 1)), np.ones(1, dtype=np.int64),
                        np.zeros((1, 1)), False)
    m = max(r.size for r, _ in rows)
    prof_r = np.empty((len(rows), m))
    prof_k = np.empty((len(rows), m))
    for i, (r, kk) in enumerate(rows):
        prof_r[i, :r.size], prof_r[i, r.size:] = r, r[-1]
        prof_k[i, :kk.size], prof_k[i, kk.size:] = kk, kk[-1]
    prof_sd = np.zeros((len(rows), m))
    for i, sd in enumerate(sds):
        if sd is not None:
            sd = np.asarray(sd, dtype=float)
            prof_sd[i, :sd.size], prof_sd[i, sd.size:] = sd, sd[-1]
    return Profiles(prof_idx, prof_r, prof_k, np.array([r.size for r, _ in rows], dtype=np.int64),
                    prof_sd, any(sd is not None for sd in sds))


def prior_of(cfg) -> Prior:
    """The prior of `tracker.rpf.config.RpfConfig` ``cfg``, angles in radians."""
    near, far = np.log(cfg.range_span_m) if cfg.range_span_m else (0.0, 0.0)
    return Prior(range_mean_m=float(cfg.range_mean_m), range_sd_m=float(cfg.range_sd_m),
                 range_log_near=float(near), range_log_span=float(far - near),
                 bearing_sd_rad=math.radians(cfg.bearing_sigma_deg),
                 speed_mean_mps=float(cfg.speed_mean_mps), speed_sd_mps=float(cfg.speed_sd_mps),
                 course_sd_rad=math.radians(cfg.course_sd_deg),
                 offset_sd_db=float(cfg.sl_offset_sd_db))


def model_of(cfg, *, use_level: bool, ross: bool, p0_db: float, sigma_l_db: float) -> Model:
    """The model of ``cfg`` with the level settings `tracker.rpf.batch.run_batch` resolved."""
    return Model(sigma_a_mps2=np.array(cfg.particle_sigma_a_mps2, dtype=float),
                 sigma_theta_rad=math.radians(cfg.bearing_sigma_deg), use_level=bool(use_level),
                 ross=bool(ross), p0_db=float(p0_db), sigma_l_db=float(sigma_l_db))
