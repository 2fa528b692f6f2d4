"""Regularized particle filter for bearings and sound pressure levels (Iglesis & de Montella).

State (eq. 3): the target relative to the observer, x = (x, y, vx, vy), m and m/s, x east and
y north. Optionally a fifth component, a source-level offset in dB (constant in time, estimated
jointly; see `RpfConfig.sl_offset_sd_db`), which is not in the paper.

One cycle, all runs and particles at once (arrays of shape (D, runs, N), component first so
each component is contiguous):

1. prediction, eqs. 4-6 (`predict`): discrete white-noise acceleration, nu ~ N(0, sigma_a^2 I);
2. update, eqs. 18-19 and 31-33 (`bearing_loglik`, `level_loglik`, `normalise`): weights kept
   as logs and normalised with logsumexp;
3. N_eff (eq. 20, `n_eff`) against N_thr = N/3; below it multinomial resampling
   (`multinomial_resample`) then regularization with the Epanechnikov kernel (eq. 26) and the
   MISE-optimal bandwidth (eqs. 27-28, `optimal_bandwidth`) scaled by the empirical
   covariance, x = x' + h D eps with P = D D^T (eq. 21, `regularise`);
4. estimate and covariance after the regularization step, eqs. 29-30 (`estimate`).

The SPL of a particle is h_l = SL(v) - TL (eqs. 11-16): SL(v) = 170 + 53 lg(v / 5.14 m/s)
(eq. 12, Ross) with v the particle's own target speed, TL read from the grid by linear
interpolation in depth and range (eq. 13, `tracker.tables`).

References
----------
E. Iglesis, L. de Montella, "Target motion analysis using combined bearings and underwater
sound pressure levels", hal-04796331 (2024). C. Musso, N. Oudjane, F. Le Gland, "Improving
regularised particle filters" (2001). B. Ristic, S. Arulampalam, N. Gordon, "Beyond the Kalman
filter" (2003), sec. 6.4.1.1 (initialization).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from envdata.classes import ross_source_level_db

log = logging.getLogger(__name__)

KNOT_MPS = 1852.0 / 3600.0
#: Runs are filtered in blocks of about this many particles (runs x N): a block's arrays then
#: stay in a core's L2 cache (2 MiB), which is faster than one large array of every run.
BLOCK_PARTICLES = 20_000
#: Cycle loop of `run_batch`: "kernel" (default) the compiled fused loop of
#: `tracker.rpf_kernel`; "numpy" the reference implementation below (same statistics, other
#: random numbers).
ENGINE = "kernel"


class Method(StrEnum):
    """Which measurements the filter uses."""

    RPF = "rpf"          # bearings and SPL (eq. 31)
    RPF_BOT = "rpf-bot"  # bearings only (eq. 32)
    RPF_VP = "rpf-vp"    # bearings and SPL, variance-preserving regularization (not in the paper)


@dataclass(frozen=True, slots=True, kw_only=True)
class RpfConfig:
    """Settings of the filter; defaults are the paper's (sec. 5).

    Attributes
    ----------
    n_particles : int
        N (5000).
    sigma_a_mps2 : float
        Acceleration process-noise sd, m/s^2 (1.5e-3; DESIGN.md reads the paper's Q = sigma_a I
        with sigma_a a standard deviation).
    bearing_sigma_deg : float
        sigma_theta of eq. 32, deg (1.5).
    level_sigma_db : float
        sigma_l of eq. 33 used by the filter, dB (10; the paper simulates with 4).
    neff_fraction : float
        N_thr / N (1/3).
    range_mean_m, range_sd_m : float
        Prior range, m (10 km, 2 km).
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
    """

    n_particles: int = 5000
    sigma_a_mps2: float = 1.5e-3
    bearing_sigma_deg: float = 1.5
    level_sigma_db: float = 10.0
    neff_fraction: float = 1.0 / 3.0
    range_mean_m: float = 10_000.0
    range_sd_m: float = 2_000.0
    speed_mean_mps: float = 3.0 * KNOT_MPS
    speed_sd_mps: float = 2.0 * KNOT_MPS
    course_sd_deg: float = math.degrees(math.pi / math.sqrt(12.0))
    sl_offset_sd_db: float = 0.0
    shrink: bool = False

    def __post_init__(self) -> None:
        if int(self.n_particles) != self.n_particles or self.n_particles < 2:
            raise ValueError(f"n_particles must be an integer >= 2, got {self.n_particles}")
        for name in ("sigma_a_mps2", "sl_offset_sd_db"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name} must be >= 0, got {v}")
        for name in ("bearing_sigma_deg", "level_sigma_db", "range_mean_m", "range_sd_m",
                     "speed_sd_mps", "course_sd_deg"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be > 0, got {v}")
        if not 0.0 < self.neff_fraction <= 1.0:
            raise ValueError(f"neff_fraction must be in (0, 1], got {self.neff_fraction}")

    @property
    def n_dim(self) -> int:
        """State dimension n_x: 4, or 5 with the source-level offset."""
        return 5 if self.sl_offset_sd_db > 0 else 4


# --------------------------------------------------------------------------------------------
# Scratch arrays reused from cycle to cycle (allocating fresh large arrays every cycle costs a
# page fault per 4 KiB and was the largest single cost of the filter step)


def _buf(work: dict | None, name: str, shape, dtype=float) -> np.ndarray:
    """An uninitialised array of ``shape`` from the scratch dict ``work`` (new if None)."""
    if work is None:
        return np.empty(shape, dtype)
    key = (name, tuple(shape), np.dtype(dtype).char)
    a = work.get(key)
    if a is None:
        a = work[key] = np.empty(shape, dtype)
    return a


# --------------------------------------------------------------------------------------------
# Kernel and bandwidth (eqs. 25-28)


def unit_ball_volume(n_dim: int) -> float:
    """c_n, the volume of the unit ball in R^n: pi^(n/2) / Gamma(n/2 + 1)."""
    return math.pi ** (n_dim / 2.0) / math.gamma(n_dim / 2.0 + 1.0)


def optimal_bandwidth(n_particles: int, n_dim: int) -> float:
    """MISE-optimal bandwidth of the Epanechnikov kernel, eqs. 27-28.

    h = A(K) N^(-1/(n+4)),  A(K) = (8 c_n^-1 (n + 4) (2 sqrt(pi))^n)^(1/(n+4)).
    """
    a = (8.0 / unit_ball_volume(n_dim) * (n_dim + 4) * (2.0 * math.sqrt(math.pi)) ** n_dim
         ) ** (1.0 / (n_dim + 4))
    return a * n_particles ** (-1.0 / (n_dim + 4))


def standard_normal_pairs(shape, rng: np.random.Generator, work: dict | None = None
                          ) -> tuple[np.ndarray, np.ndarray]:
    """Two independent arrays of N(0, 1) draws of ``shape`` (Box-Muller on float32 uniforms).

    r = sqrt(-2 ln U1), (r cos 2 pi U2, r sin 2 pi U2), computed in float32 and returned as
    float32: about 3x cheaper than ``Generator.standard_normal`` for the same count. The 24-bit
    uniforms cut the tail at |z| = 5.77 (probability 8e-9), immaterial for process noise and
    kernel draws.
    """
    u = rng.random((2, *shape), dtype=np.float32, out=_buf(work, "u", (2, *shape), np.float32))
    r = np.subtract(1.0, u[0], out=u[0])  # (0, 1]: finite log
    np.log(r, out=r)
    r *= -2.0
    np.sqrt(r, out=r)
    u[1] *= 2.0 * math.pi
    a = np.cos(u[1], out=_buf(work, "a", shape, np.float32))
    np.sin(u[1], out=u[1])
    a *= r
    u[1] *= r
    return a, u[1]


def epanechnikov_sample(n_dim: int, size, rng: np.random.Generator, work: dict | None = None
                        ) -> np.ndarray:
    """Draws from the Epanechnikov kernel on the unit ball of R^n (eq. 26).

    The first n coordinates of a point uniform on the unit sphere of R^(n+4) are uniform in the
    ball of R^(n+2), whose projection on R^n has density proportional to 1 - |x|^2: the
    Epanechnikov kernel. So: n + 4 normals, scaled by their norm, first n kept. The 4 dropped
    normals enter only through their squared norm, a chi^2 with 4 degrees of freedom, drawn as
    2 (E1 + E2) with E standard exponentials.

    Returns
    -------
    eps : ndarray, shape (n_dim, *size)
    """
    size = (size,) if np.isscalar(size) else tuple(size)
    g = np.empty((n_dim, *size))
    for i in range(0, n_dim, 2):
        a, b = standard_normal_pairs(size, rng, work)
        g[i] = a
        if i + 1 < n_dim:
            g[i + 1] = b
    e = rng.standard_exponential((2, *size))
    norm2 = np.add(e[0], e[1], out=e[0])
    norm2 *= 2.0
    norm2 += np.einsum("i...,i...->...", g, g)
    np.sqrt(norm2, out=norm2)
    g /= norm2
    return g


# --------------------------------------------------------------------------------------------
# Motion model (eqs. 4-6)


def predict(state: np.ndarray, *, dt_s: float, obs_k: np.ndarray, obs_k1: np.ndarray,
            sigma_a_mps2: float, rng: np.random.Generator, work: dict | None = None) -> None:
    """Propagate the relative state one step in place, eq. 4: x' = F (x + x^o_k) - x^o_k1 + G nu.

    Parameters
    ----------
    state : ndarray, shape (D, ...)
        Relative state (x, y, vx, vy[, offset]) per particle, m and m/s; changed in place.
    dt_s : float
        Delta T, s.
    obs_k, obs_k1 : array_like, shape (4,)
        Observer state (x, y, vx, vy) at steps k and k+1, m and m/s.
    sigma_a_mps2 : float
        Acceleration sd, m/s^2 (nu ~ N(0, sigma_a^2 I), eq. 6 for Gamma).
    """
    ox, oy, ovx, ovy = (float(v) for v in obs_k)
    nx, ny, nvx, nvy = (float(v) for v in obs_k1)
    # x_k1 = x + dt (v + dv / 2) + c, v_k1 = v + dv + c', with dv = dt nu: G nu of eq. 6 fused
    tmp = _buf(work, "tmp", state.shape[1:])
    for pos, vel, cp, cv in ((0, 2, ox + dt_s * ovx - nx, ovx - nvx),
                             (1, 3, oy + dt_s * ovy - ny, ovy - nvy)):
        if sigma_a_mps2 > 0:
            if pos == 0:
                nu = standard_normal_pairs(state.shape[1:], rng, work)
            dv = nu[pos]
            dv *= dt_s * sigma_a_mps2
            np.multiply(dv, 0.5, out=tmp)
            tmp += state[vel]
            state[vel] += dv
        else:
            tmp[...] = state[vel]
        tmp *= dt_s
        tmp += cp
        state[pos] += tmp
        state[vel] += cv


# --------------------------------------------------------------------------------------------
# Measurements and likelihoods (eqs. 9, 12, 16, 31-33)


def bearing_rad(x_m, y_m):
    """h_theta of eq. 9: bearing clockwise from north (the y axis), rad, in (-pi, pi]."""
    return np.arctan2(x_m, y_m)


def wrap_rad(angle):
    """Angle wrapped to [-pi, pi)."""
    return np.mod(np.asarray(angle) + math.pi, 2.0 * math.pi) - math.pi


def bearing_loglik(state: np.ndarray, bearing_meas_rad, sigma_rad: float,
                   work: dict | None = None) -> np.ndarray:
    """Log of eq. 32 up to a constant: -(theta - h_theta(x))^2 / (2 sigma^2), angle wrapped.

    ``bearing_meas_rad`` broadcasts against the particle axes (e.g. shape (runs, 1)).
    """
    # rotate each particle by -theta: atan2 of the rotated position is h_theta - theta, wrapped
    z = np.asarray(bearing_meas_rad, dtype=float)
    c, s = np.cos(z), np.sin(z)
    shape = np.broadcast_shapes(state.shape[1:], z.shape)
    east, north, tmp = (_buf(work, name, shape) for name in ("east", "north", "tmp"))
    np.multiply(state[0], c, out=east)
    east -= np.multiply(state[1], s, out=tmp)
    np.multiply(state[1], c, out=north)
    north += np.multiply(state[0], s, out=tmp)
    resid = np.arctan2(east, north, out=east)
    resid *= resid
    resid *= -0.5 / (sigma_rad * sigma_rad)
    return resid


def predicted_level_db(state: np.ndarray, obs_vel_mps, k_profile, *, source_level_model="ross",
                       p0_db: float = math.nan) -> np.ndarray:
    """h_l of eq. 16: SL of each particle's target speed plus K(r) = S - TL(r), dB.

    Parameters
    ----------
    state : ndarray, shape (D, ...)
        Relative state; the target's own velocity is the relative velocity plus the
        observer's. A fifth component, if present, is a source-level offset, dB.
    obs_vel_mps : array_like, shape (2,)
        Observer velocity (east, north), m/s.
    k_profile : callable
        K(r) at the observer depth, dB (`tracker.tables.LevelProfile`).
    """
    r = np.hypot(state[0], state[1])
    if source_level_model == "ross":
        v = np.hypot(state[2] + float(obs_vel_mps[0]), state[3] + float(obs_vel_mps[1]))
        level = ross_source_level_db(v)
    else:
        level = np.full(r.shape, p0_db)
    level += k_profile(r)
    if state.shape[0] > 4:
        level += state[4]
    return level


def level_loglik(state: np.ndarray, level_meas_db, obs_vel_mps, k_profile, sigma_db: float, *,
                 source_level_model="ross", p0_db: float = math.nan) -> np.ndarray:
    """Log of eq. 33 up to a constant: -(l - h_l(x))^2 / (2 sigma_l^2)."""
    pred = predicted_level_db(state, obs_vel_mps, k_profile, source_level_model=source_level_model,
                              p0_db=p0_db)
    return -0.5 * ((level_meas_db - pred) / sigma_db) ** 2


def normalise(log_w: np.ndarray) -> np.ndarray:
    """Normalised log-weights along the last axis (eq. 19 with logsumexp)."""
    return normalise_exp(log_w.copy())[0]


def normalise_exp(log_w: np.ndarray, out: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """In place: log-weights normalised along the last axis, and their exponentials (eq. 19).

    logsumexp by hand: shift by the row maximum, one exp, one sum, one log per row.
    """
    log_w -= log_w.max(axis=-1, keepdims=True)
    w = np.exp(log_w, out=out)
    total = w.sum(axis=-1, keepdims=True)
    w /= total
    log_w -= np.log(total)
    return log_w, w


def n_eff(weights: np.ndarray) -> np.ndarray:
    """Effective sample size 1 / sum w^2 along the last axis, eq. 20."""
    return 1.0 / np.einsum("...i,...i->...", weights, weights)


# --------------------------------------------------------------------------------------------
# Resampling and regularization (eqs. 20-28)


def multinomial_resample(weights: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Indices of a multinomial draw of N particles with probabilities ``weights`` per row.

    Parameters
    ----------
    weights : ndarray, shape (runs, N)
        Normalised weights of each run.

    Returns
    -------
    idx : ndarray of int, shape (runs, N)
        Sorted draws; all rows searched at once by offsetting each row's CDF by its row number.
    """
    runs, n = weights.shape
    cdf = np.cumsum(weights, axis=1)
    cdf /= cdf[:, -1:]
    # n sorted uniforms per row from normalised exponential spacings
    e = rng.exponential(size=(runs, n + 1))
    u = np.cumsum(e, axis=1)
    u = np.divide(u[:, :-1], u[:, -1:], out=e[:, :-1])
    if runs == 1:
        idx = np.searchsorted(cdf[0], u[0], side="right")[None]
    else:
        offset = np.arange(runs, dtype=float)[:, None]
        cdf += offset
        u += offset
        flat = np.searchsorted(cdf.ravel(), u.ravel(), side="right")
        idx = flat.reshape(runs, n) - np.arange(runs)[:, None] * n
    return np.minimum(idx, n - 1, out=idx)


def weighted_covariance(state: np.ndarray, weights: np.ndarray, work: dict | None = None
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Weighted mean (D, runs) and covariance (runs, D, D) of the particles, eqs. 29-30."""
    # each run's covariance is one (D, N) @ (N, D) product (strided views BLAS takes as they
    # are); all runs in one batched matmul
    mean = np.einsum("drn,rn->dr", state, weights)
    dev = np.subtract(state, mean[:, :, None], out=_buf(work, "dev", state.shape))
    dw = np.multiply(dev, weights, out=_buf(work, "dw", state.shape))
    cov = np.matmul(dev.transpose(1, 0, 2), dw.transpose(1, 2, 0))
    return mean, cov


def regularise(state: np.ndarray, weights: np.ndarray, rng: np.random.Generator, *,
               bandwidth: float | None = None, shrink: bool = False,
               work: dict | None = None) -> np.ndarray:
    """Resample then jitter with the Epanechnikov kernel, eq. 21: x = x' + h D eps.

    Parameters
    ----------
    state : ndarray, shape (D, runs, N)
        Particles before resampling.
    weights : ndarray, shape (runs, N)
        Their normalised weights.
    bandwidth : float, optional
        h; default the optimal one of eqs. 27-28 for N and D.
    shrink : bool
        Variance-preserving form (not in the paper): x = m + a (x' - m) + h D eps with m the
        weighted mean and a = sqrt(1 - h^2/(n+4)); the kernel's covariance is I/(n+4).

    Returns
    -------
    new_state : ndarray, shape (D, runs, N)
        Resampled, regularized particles (equal weights 1/N).

    Notes
    -----
    D is the Cholesky factor of the weighted empirical covariance P_k of the particles before
    resampling (Musso et al.); a tiny diagonal load keeps it defined when P_k is singular.
    """
    n_dim, runs, n = state.shape
    h = optimal_bandwidth(n, n_dim) if bandwidth is None else bandwidth
    mean, cov = weighted_covariance(state, weights, work)
    scale = np.maximum(np.einsum("rii->ri", cov), 0.0).max(axis=1)
    cov = cov + (1e-12 * scale + 1e-18)[:, None, None] * np.eye(n_dim)
    d = np.linalg.cholesky(cov)  # (runs, D, D)
    idx = multinomial_resample(weights, rng)
    idx += (np.arange(runs) * n)[:, None]  # flat index into the (D, runs * N) particles
    new = np.take(state.reshape(n_dim, runs * n), idx.ravel(), axis=1).reshape(state.shape)
    if shrink:
        a = math.sqrt(max(0.0, 1.0 - h * h / (n_dim + 4)))
        m = mean[:, :, None]
        new -= m
        new *= a
        new += m
    eps = epanechnikov_sample(n_dim, (runs, n), rng, work)
    d *= h
    tmp = _buf(work, "tmp", (runs, n))
    for i in range(n_dim):  # new += h D eps, D lower triangular
        for j in range(i + 1):
            new[i] += np.multiply(d[:, i, j, None], eps[j], out=tmp)
    return new


def estimate(state: np.ndarray, weights: np.ndarray, work: dict | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """Estimate x_hat (eq. 29), shape (D, runs), and covariance P_hat (eq. 30), (runs, D, D)."""
    return weighted_covariance(state, weights, work)


# --------------------------------------------------------------------------------------------
# Initialization (Ristic et al. 2003, sec. 6.4.1.1, as in the paper's sec. 5)


def initial_particles(bearing0_rad, obs_vel_mps, cfg: RpfConfig, runs: int,
                      rng: np.random.Generator) -> np.ndarray:
    """Particles from the first bearing: range N(r, sd), bearing N(z0, sigma_theta),
    speed N(s, sd), course N(z0 + pi, pi/sqrt 12).

    Parameters
    ----------
    bearing0_rad : array_like, shape (runs,) or scalar
        First bearing of each run, rad.
    obs_vel_mps : array_like, shape (2,)
        Observer velocity at the first cycle, m/s (the state is relative).

    Returns
    -------
    state : ndarray, shape (D, runs, N)
    """
    n = cfg.n_particles
    z0 = np.broadcast_to(np.asarray(bearing0_rad, dtype=float), (runs,))[:, None]
    g = rng.standard_normal((cfg.n_dim, runs, n))
    state = np.empty((cfg.n_dim, runs, n))
    rng_m = cfg.range_mean_m + cfg.range_sd_m * g[0]
    theta = z0 + math.radians(cfg.bearing_sigma_deg) * g[1]
    speed = cfg.speed_mean_mps + cfg.speed_sd_mps * g[2]
    course = z0 + math.pi + math.radians(cfg.course_sd_deg) * g[3]
    state[0] = rng_m * np.sin(theta)
    state[1] = rng_m * np.cos(theta)
    state[2] = speed * np.sin(course) - float(obs_vel_mps[0])
    state[3] = speed * np.cos(course) - float(obs_vel_mps[1])
    if cfg.n_dim > 4:
        state[4] = cfg.sl_offset_sd_db * g[4]
    return state


# --------------------------------------------------------------------------------------------
# The filter over a batch of runs


@dataclass(frozen=True, slots=True, kw_only=True)
class BatchResult:
    """Output of `run_batch`.

    Attributes
    ----------
    mean : ndarray, shape (runs, K, D)
        Estimates after each cycle (eq. 29), relative state.
    cov : ndarray, shape (runs, K, D, D)
        Their covariances (eq. 30).
    resampled : ndarray of bool, shape (runs, K)
        Whether the regularization-resampling step ran.
    extra : dict
        Per-cycle particle summaries when asked for (range, course and speed sd).
    """

    mean: np.ndarray
    cov: np.ndarray
    resampled: np.ndarray
    extra: dict = field(default_factory=dict)


def run_batch(*, t_s: np.ndarray, obs_state: np.ndarray, bearing_rad_meas: np.ndarray,
              level_db_meas: np.ndarray | None, k_profiles, cfg: RpfConfig,
              rng: np.random.Generator, source_level_model: str = "ross",
              p0_db: float = math.nan, p0_sd_db: float = 0.0,
              summaries: bool = False, threads: int = 1) -> BatchResult:
    """Run the RPF over K cycles for a batch of runs sharing one observer track.

    Parameters
    ----------
    t_s : ndarray, shape (K,)
        Cycle times, s.
    obs_state : ndarray, shape (K, 4)
        Observer (x, y, vx, vy) at each cycle, m and m/s.
    bearing_rad_meas : ndarray, shape (runs, K)
        Measured bearings, rad; NaN: no bearing this cycle. The first cycle must have one.
    level_db_meas : ndarray, shape (runs, K) or None
        Measured SPL, dB re 1 uPa; None for bearings only (rpf-bot); NaN: bearing only.
    k_profiles : sequence of callables, length K
        K(r) at the observer depth of each cycle (`LevelProfile`); unused without levels.
    cfg : RpfConfig
    rng : numpy.random.Generator
    source_level_model : str
        "ross" (eq. 12) or "p0" (constant ``p0_db``, its sd ``p0_sd_db`` added to sigma_l).
    summaries : bool
        Also return per-cycle particle sd of range, course and target speed (for track CSVs).
    threads : int
        Blocks of runs filtered at once on this many threads (the compiled loop and numpy's
        array loops release the GIL). The results do not depend on it: the runs go in blocks
        of about ``BLOCK_PARTICLES`` particles, each with its own generator spawned from
        ``rng`` (and, with ``ENGINE = "kernel"``, one generator per run seeded from it).

    Returns
    -------
    BatchResult
    """
    runs = bearing_rad_meas.shape[0]
    block = max(1, BLOCK_PARTICLES // cfg.n_particles)
    starts = list(range(0, runs, block))
    rngs = rng.spawn(len(starts))

    def one(i):
        rows = slice(starts[i], starts[i] + block)
        return _run_block(t_s=t_s, obs_state=obs_state, bearing_rad_meas=bearing_rad_meas[rows],
                          level_db_meas=None if level_db_meas is None else level_db_meas[rows],
                          k_profiles=k_profiles, cfg=cfg, rng=rngs[i],
                          source_level_model=source_level_model, p0_db=p0_db,
                          p0_sd_db=p0_sd_db, summaries=summaries)

    if threads > 1 and len(starts) > 1:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=threads) as pool:
            parts = list(pool.map(one, range(len(starts))))
    else:
        parts = [one(i) for i in range(len(starts))]
    if len(parts) == 1:
        return parts[0]
    return BatchResult(mean=np.concatenate([p.mean for p in parts]),
                       cov=np.concatenate([p.cov for p in parts]),
                       resampled=np.concatenate([p.resampled for p in parts]),
                       extra={"sd": np.concatenate([p.extra["sd"] for p in parts])}
                       if summaries else {})


def _run_block(*, t_s, obs_state, bearing_rad_meas, level_db_meas, k_profiles, cfg, rng,
               source_level_model, p0_db, p0_sd_db, summaries) -> BatchResult:
    """`run_batch` on one block of runs, one generator."""
    if ENGINE == "kernel" and (level_db_meas is None
                               or all(p is None or hasattr(p, "k_db") for p in k_profiles)):
        from tracker import rpf_kernel

        sigma_l = math.hypot(cfg.level_sigma_db,
                             p0_sd_db if source_level_model != "ross" else 0.0)
        means, covs, resampled, sds = rpf_kernel.run(
            t_s=t_s, obs_state=obs_state, bearing_rad_meas=bearing_rad_meas,
            level_db_meas=level_db_meas, k_profiles=k_profiles, cfg=cfg, rng=rng,
            ross=source_level_model == "ross", p0_db=p0_db, sigma_l_db=sigma_l,
            bandwidth=optimal_bandwidth(cfg.n_particles, cfg.n_dim), summaries=summaries)
        return BatchResult(mean=means, cov=covs, resampled=resampled,
                           extra={"sd": sds} if summaries else {})
    runs, n_cycles = bearing_rad_meas.shape
    sigma_theta = math.radians(cfg.bearing_sigma_deg)
    sigma_l = math.hypot(cfg.level_sigma_db, p0_sd_db if source_level_model != "ross" else 0.0)
    n_thr = cfg.neff_fraction * cfg.n_particles
    d = cfg.n_dim
    means = np.empty((runs, n_cycles, d))
    covs = np.empty((runs, n_cycles, d, d))
    resampled = np.zeros((runs, n_cycles), dtype=bool)
    sds = np.full((runs, n_cycles, 3), np.nan) if summaries else None

    state = initial_particles(bearing_rad_meas[:, 0], obs_state[0, 2:], cfg, runs, rng)
    log_w = np.full((runs, cfg.n_particles), -math.log(cfg.n_particles))
    work = {}  # scratch arrays reused by every cycle
    for k in range(n_cycles):
        if k > 0:
            predict(state, dt_s=float(t_s[k] - t_s[k - 1]), obs_k=obs_state[k - 1],
                    obs_k1=obs_state[k], sigma_a_mps2=cfg.sigma_a_mps2, rng=rng, work=work)
            z = bearing_rad_meas[:, k]
            have = np.isfinite(z)
            if have.all():
                log_w += bearing_loglik(state, z[:, None], sigma_theta, work)
            elif have.any():
                log_w[have] += bearing_loglik(state[:, have], z[have, None], sigma_theta)
        # the first bearing is in the prior already; the first level is used like the others
        if level_db_meas is not None:
            lv = level_db_meas[:, k]
            have = np.isfinite(lv)
            if have.any():
                sub = state if have.all() else state[:, have]
                ll = level_loglik(sub, lv[have, None], obs_state[k, 2:], k_profiles[k], sigma_l,
                                  source_level_model=source_level_model, p0_db=p0_db)
                if have.all():
                    log_w = log_w + ll
                else:
                    log_w[have] += ll
        log_w, w = normalise_exp(log_w, _buf(work, "w", log_w.shape))
        low = n_eff(w) < n_thr
        if low.any():
            if low.all():
                state = regularise(state, w, rng, shrink=cfg.shrink, work=work)
            else:
                state[:, low] = regularise(state[:, low], w[low], rng, shrink=cfg.shrink,
                                           work=work)
            log_w[low] = -math.log(cfg.n_particles)
            w[low] = 1.0 / cfg.n_particles
            resampled[low, k] = True
        mean, cov = estimate(state, w, work)  # after the regularization step (sec. 4.4)
        means[:, k] = mean.T
        covs[:, k] = cov
        if summaries:
            sds[:, k] = _particle_sds(state, w, obs_state[k, 2:])
    return BatchResult(mean=means, cov=covs, resampled=resampled,
                       extra={"sd": sds} if summaries else {})


def _particle_sds(state: np.ndarray, w: np.ndarray, obs_vel) -> np.ndarray:
    """Weighted sd of range (m), course (deg, circular) and target speed (m/s) per run."""
    r = np.hypot(state[0], state[1])
    vx = state[2] + float(obs_vel[0])
    vy = state[3] + float(obs_vel[1])
    speed = np.hypot(vx, vy)
    course = np.arctan2(vx, vy)

    def sd(a):
        m = np.einsum("rn,rn->r", a, w)
        return np.sqrt(np.maximum(np.einsum("rn,rn->r", (a - m[:, None]) ** 2, w), 0.0))

    c = np.einsum("rn,rn->r", np.cos(course), w)
    s = np.einsum("rn,rn->r", np.sin(course), w)
    resultant = np.clip(np.hypot(c, s), 1e-300, 1.0)
    course_sd = np.degrees(np.sqrt(-2.0 * np.log(resultant)))
    return np.stack([sd(r), course_sd, sd(speed)], axis=-1)


# --------------------------------------------------------------------------------------------
# From a measurement CSV (``tmakit track --method rpf|rpf-bot``)


def track_measurements(tables, measurements, *, method: str, rng: np.random.Generator,
                       cls_name: str | None = None, band: str | None = None,
                       config: RpfConfig | None = None):
    """Track one target from a measurement CSV with the RPF; one row per cycle per class.

    The measurements are checked against the grid by ``tracker.track.track``, the way in.

    Parameters
    ----------
    tables : tracker.tables.GridTables
        The propagation grid's tables.
    measurements : tracker.measurements.Measurements
        Bearings and band levels. ``rpf`` needs the ``level_db_NAME`` column of the band; a
        blank level uses the bearing alone that cycle, a blank bearing the level alone.
    method : {"rpf", "rpf-bot", "rpf-vp"}
        Bearings and SPL, bearings only, or bearings and SPL with the variance-preserving
        regularization (``RpfConfig.shrink``).
    rng : numpy.random.Generator
        Seeded generator: same seed, same track.
    cls_name : str, optional
        Class hypothesis (source level model and depth); default every class of the grid.
    band : str, optional
        Band whose level is the SPL; default the first grid band with a level column.
    config : RpfConfig, optional
        Filter settings (the paper's by default). A ``bearing_sigma_deg`` column, where
        complete, sets sigma_theta (its median).

    Returns
    -------
    pandas.DataFrame
        Columns ``tracker.trackfile.TRACK_COLUMNS``; absolute target position, its course and
        speed, sd of range, course and speed from the particles; ``tack`` is 1.

    Raises
    ------
    MeasurementFileError
        No level column for the band (rpf).
    GridFileError
        A class with source level model "p0" but no noise_mean_db.
    """
    import pandas as pd

    from acoustics.errors import GridFileError
    from envdata.classes import SourceLevelModel
    from tracker.errors import MeasurementFileError

    m = measurements
    try:
        method = Method(method)
    except ValueError:
        raise MeasurementFileError(f"--method: {method!r} is not an RPF method (rpf, rpf-bot, "
                                   f"rpf-vp)") from None
    spl = method is not Method.RPF_BOT
    cfg = config or RpfConfig()
    if method is Method.RPF_VP:
        cfg = _replace(cfg, shrink=True)
    sig = np.asarray(m.bearing_sigma_deg, dtype=float)
    if sig.size and np.all(np.isfinite(sig)):
        cfg = _replace(cfg, bearing_sigma_deg=float(np.median(sig)))
    levels = None
    bands = tables.band_names
    if spl:
        if band is None:
            usable = [b for b in bands if b in m.band_names]
            if not usable:
                raise MeasurementFileError(
                    f"{m.source}: method rpf needs a level column level_db_NAME for a band of "
                    f"the grid ({', '.join(bands)}); none found (use --method rpf-bot for "
                    f"bearings only)")
            band = usable[0]
        if band not in m.band_names:
            raise MeasurementFileError(f"{m.source}: missing column 'level_db_{band}' needed by "
                                       f"method rpf for band {band!r}")
        levels = np.asarray(m.level_db[:, m.band_index(band)], dtype=float)
    bearings = np.radians(np.asarray(m.bearing_deg, dtype=float))
    first = int(np.flatnonzero(np.isfinite(bearings))[0])
    if first > 0:
        log.warning("%s: rows 1-%d have no bearing; the filter starts at row %d",
                    m.source, first, first + 1)
    n_nan_b = int(np.sum(~np.isfinite(bearings[first:])))
    if n_nan_b:
        log.warning("%s: %d rows without a bearing use %s", m.source, n_nan_b,
                    "the level alone" if levels is not None else "the prediction alone")
    if levels is not None and np.any(~np.isfinite(levels[first:])):
        log.warning("%s: %d rows without a level_db_%s use the bearing alone", m.source,
                    int(np.sum(~np.isfinite(levels[first:]))), band)
    rows = slice(first, None)
    t = np.asarray(m.t_s, dtype=float)[rows]
    vx, vy = m.obs_velocity_mps()
    obs = np.stack([m.obs_x_m, m.obs_y_m, vx, vy], axis=-1)[rows]
    depth = np.asarray(m.obs_depth_m, dtype=float)[rows]

    hypotheses = [cls_name] if cls_name is not None else list(tables.class_names)
    if method is Method.RPF_BOT:
        hypotheses = hypotheses[:1]  # bearings alone do not depend on the class
    frames = []
    for name in hypotheses:
        profiles = [None] * t.size
        model, p0, p0_sd = "ross", math.nan, 0.0
        if spl:
            ic, ib = tables.class_index(name), tables.band_index(band)
            target = tables.classes[ic]
            model = str(target.source_level_model)
            if target.source_level_model is SourceLevelModel.P0:
                if target.noise_mean_db is None:
                    raise GridFileError(f"{tables.source}: class {name!r} has source level "
                                        f"model {model!r} but no noise_mean_db")
                p0, p0_sd = target.noise_mean_db, target.noise_sd_db
            cache = {}
            for k, d in enumerate(depth):
                if d not in cache:
                    cache[d] = tables.level_profile(ic, ib, float(d))
                profiles[k] = cache[d]
        res = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=bearings[rows][None],
                        level_db_meas=None if levels is None else levels[rows][None],
                        k_profiles=profiles, cfg=cfg, rng=rng, source_level_model=model,
                        p0_db=p0, p0_sd_db=p0_sd, summaries=True)
        mean = res.mean[0]
        ax, ay = mean[:, 0] + obs[:, 0], mean[:, 1] + obs[:, 1]
        tvx, tvy = mean[:, 2] + obs[:, 2], mean[:, 3] + obs[:, 3]
        sds = res.extra["sd"][0]
        frames.append(pd.DataFrame({
            "t_s": t, "class": name if spl or cls_name else "any",
            "x_m": ax, "y_m": ay, "range_m": np.hypot(mean[:, 0], mean[:, 1]),
            "bearing_deg": np.mod(np.degrees(bearing_rad(mean[:, 0], mean[:, 1])), 360.0),
            "course_deg": np.mod(np.degrees(np.arctan2(tvx, tvy)), 360.0),
            "speed_mps": np.hypot(tvx, tvy), "range_sd_m": sds[:, 0],
            "course_sd_deg": sds[:, 1], "speed_sd_mps": sds[:, 2], "tack": 1,
            "method": method.value}))
    return pd.concat(frames, ignore_index=True)


def _replace(cfg: RpfConfig, **changes) -> RpfConfig:
    from dataclasses import replace

    return replace(cfg, **changes)
