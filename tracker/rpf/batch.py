"""The filter over a batch of runs sharing one observer track: `run_batch`.

One cycle, all runs and particles at once (arrays of shape (D, runs, N), component first so
each component is contiguous):

1. prediction, eqs. 4-6 (`tracker.rpf.motion.predict`): discrete white-noise acceleration,
   nu ~ N(0, sigma_a^2 I);
2. update, eqs. 18-19 and 31-33 (`tracker.rpf.likelihood`, `tracker.rpf.weights.normalise_exp`):
   weights kept as logs and normalised with logsumexp;
3. N_eff (eq. 20, `tracker.rpf.weights.n_eff`) against N_thr = N/3; below it multinomial
   resampling then regularization with the Epanechnikov kernel (eq. 26) and the MISE-optimal
   bandwidth (eqs. 27-28) scaled by the empirical covariance, x = x' + h D eps with P = D D^T
   (eq. 21, `tracker.rpf.regularise.regularise`);
4. estimate and covariance after the regularization step, eqs. 29-30
   (`tracker.rpf.estimate.estimate`).

The levels may be of several bands at once (each band's eq. 33 added). With ``level_errors``
(`tracker.levels.LevelErrors`: the source level's and K's persistent offset, K's error along the
path) the level likelihood is not the paper's white one but the exact marginal one with those
errors integrated out, each particle carrying their Gaussian posterior along its own path
(`tracker.rpf.levelerrors`): the persistent part is learned from the levels and counted once.

This module's cycle loop is the numpy reference engine; by default (`RpfConfig.engine`)
each block of runs goes to the compiled fused loop of `tracker.rpf.kernel` instead.

References
----------
E. Iglesis, L. de Montella, "Target motion analysis using combined bearings and underwater
sound pressure levels", hal-04796331 (2024), sec. 4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from envdata.classes import SourceLevelModel
from tracker.rpf.config import BLOCK_PARTICLES, Engine, RpfConfig
from tracker.rpf.estimate import estimate, particle_sds
from tracker.rpf.levelerrors import ParticleErrors
from tracker.rpf.likelihood import bearing_loglik, level_loglik, predicted_level_db
from tracker.rpf.motion import predict
from tracker.rpf.prior import initial_particles
from tracker.rpf.regularise import regularise
from tracker.rpf.scratch import scratch
from tracker.rpf.weights import n_eff, normalise_exp


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
              rng: np.random.Generator, source_level_model: SourceLevelModel | str = SourceLevelModel.ROSS,
              p0_db: float = math.nan, p0_sd_db: float = 0.0,
              summaries: bool = False, threads: int = 1, level_errors=None,
              displacement_m=None, bearing_sd_rad: np.ndarray | None = None) -> BatchResult:
    """Run the RPF over K cycles for a batch of runs sharing one observer track.

    Parameters
    ----------
    t_s : ndarray, shape (K,)
        Cycle times, s.
    obs_state : ndarray, shape (K, 4)
        Observer (x, y, vx, vy) at each cycle, m and m/s.
    bearing_rad_meas : ndarray, shape (runs, K)
        Measured bearings, rad; NaN: no bearing this cycle. The first cycle must have one.
    bearing_sd_rad : ndarray, shape (runs, K), optional
        Each bearing's sd, rad (eq. 2's at its SNR: a quiet stretch's bearings are worse); NaN
        or None: the filter's sigma_theta (``cfg.bearing_sigma_deg``).
    level_db_meas : ndarray, shape (runs, K) or (runs, K, B), or None
        Measured SPL of one band or of B bands, dB re 1 uPa; None for bearings only (rpf-bot);
        NaN: none that cycle.
    k_profiles : sequence of callables, length K (for B bands, a sequence of B of them)
        K(r) at the observer depth of each cycle (`LevelProfile`); unused without levels.
    cfg : RpfConfig
    rng : numpy.random.Generator
    source_level_model : SourceLevelModel
        ``ROSS`` (eq. 12) or ``P0`` (constant ``p0_db``). Without ``level_errors`` the P0's sd
        ``p0_sd_db`` is added to sigma_l (the paper's white model); with them it belongs in
        their offset (`tracker.levels.LevelErrors`), and sigma_l is the level's own error.
    summaries : bool
        Also return per-cycle particle sd of range, course and target speed (for track CSVs).
    threads : int
        Blocks of runs filtered at once on this many threads (the compiled loop and numpy's
        array loops release the GIL). The results do not depend on it: the runs go in blocks
        of about ``BLOCK_PARTICLES`` particles, each with its own generator spawned from
        ``rng`` (and, with the kernel engine, one generator per run seeded from it).
    level_errors : tracker.levels.LevelErrors, optional
        The levels' errors that last longer than a cycle, integrated out per particle (module
        docstring); None: the paper's white level likelihood with sigma_l.
    displacement_m : ndarray, shape (K,), optional
        The observer's distance from where the tables were computed at each cycle, m (the
        errors' growth, `tracker.levels`); default 0.

    Returns
    -------
    BatchResult
    """
    source_level_model = SourceLevelModel(source_level_model)
    if level_errors is not None and cfg.n_dim > 4:
        raise ValueError("the levels' offset is integrated out with level_errors: "
                         "a source-level offset state (sl_offset_sd_db) would count it twice")
    runs = bearing_rad_meas.shape[0]
    block = max(1, BLOCK_PARTICLES // cfg.n_particles)
    starts = list(range(0, runs, block))
    rngs = rng.spawn(len(starts))

    def one(i):
        rows = slice(starts[i], starts[i] + block)
        return _run_block(t_s=t_s, obs_state=obs_state, bearing_rad_meas=bearing_rad_meas[rows],
                          bearing_sd_rad=None if bearing_sd_rad is None else np.broadcast_to(
                              bearing_sd_rad, bearing_rad_meas.shape)[rows],
                          level_db_meas=None if level_db_meas is None else level_db_meas[rows],
                          k_profiles=k_profiles, cfg=cfg, rng=rngs[i],
                          source_level_model=source_level_model, p0_db=p0_db,
                          p0_sd_db=p0_sd_db, summaries=summaries, level_errors=level_errors,
                          displacement_m=displacement_m)

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
               source_level_model, p0_db, p0_sd_db, summaries, level_errors=None,
               displacement_m=None, bearing_sd_rad=None) -> BatchResult:
    """`run_batch` on one block of runs, one generator."""
    multi = level_db_meas is not None and np.ndim(level_db_meas) == 3
    per_band = (list(k_profiles) if multi else [k_profiles]) if k_profiles is not None else []
    white_p0 = source_level_model is not SourceLevelModel.ROSS and level_errors is None
    sigma_l = math.hypot(cfg.level_sigma_db, p0_sd_db if white_p0 else 0.0)
    if cfg.engine is Engine.KERNEL and (level_db_meas is None
                                      or all(p is None or hasattr(p, "k_db")
                                             for profiles in per_band for p in profiles)):
        from tracker.rpf.kernel import run as run_kernel  # numba loads only here

        means, covs, resampled, sds = run_kernel(
            t_s=t_s, obs_state=obs_state, bearing_rad_meas=bearing_rad_meas,
            level_db_meas=level_db_meas, k_profiles=k_profiles, cfg=cfg, rng=rng,
            ross=source_level_model is SourceLevelModel.ROSS, p0_db=p0_db, sigma_l_db=sigma_l,
            bandwidth=cfg.bandwidth, summaries=summaries,
            level_errors=level_errors, displacement_m=displacement_m, bearing_sd_rad=bearing_sd_rad)
        return BatchResult(mean=means, cov=covs, resampled=resampled,
                           extra={"sd": sds} if summaries else {})
    runs, n_cycles = bearing_rad_meas.shape
    sigma_theta = np.full(bearing_rad_meas.shape, math.radians(cfg.bearing_sigma_deg))
    if bearing_sd_rad is not None:
        sigma_theta = np.where(np.isfinite(bearing_sd_rad) & (bearing_sd_rad > 0), bearing_sd_rad, sigma_theta)
    n_thr = cfg.neff_fraction * cfg.n_particles
    levels = None if level_db_meas is None else (level_db_meas if multi else level_db_meas[..., None])
    means = np.empty((runs, n_cycles, cfg.n_dim))
    covs = np.empty((runs, n_cycles, cfg.n_dim, cfg.n_dim))
    resampled = np.zeros((runs, n_cycles), dtype=bool)
    sds = np.full((runs, n_cycles, 3), np.nan) if summaries else None

    state = initial_particles(bearing_rad_meas[:, 0], obs_state[0, 2:], cfg, runs, rng)
    # each particle's acceleration sd (RpfConfig.sigma_a_mix_mps2), carried through resampling
    mix = np.asarray(cfg.particle_sigma_a_mps2, dtype=float)
    sigma_a = np.broadcast_to(mix[np.arange(cfg.n_particles) % mix.size], (runs, cfg.n_particles)).copy() \
        if mix.size > 1 else float(mix[0])
    errors = None if (levels is None or level_errors is None) else ParticleErrors(
        level_errors, levels.shape[2], n_cycles, state.shape[1:], displacement_m)
    log_w = np.full((runs, cfg.n_particles), -math.log(cfg.n_particles))
    last = np.zeros((cfg.n_dim, runs))  # the last cycle's estimate (its relative velocity)
    work = {}  # scratch arrays reused by every cycle
    for k in range(n_cycles):
        if k > 0:
            dt = float(t_s[k] - t_s[k - 1])
            predict(state, dt_s=dt, obs_k=obs_state[k - 1], obs_k1=obs_state[k],
                    sigma_a_mps2=sigma_a, rng=rng, work=work)
            if errors is not None:  # each run's estimated relative move since the last cycle
                errors.predict(k, dt, dt * np.hypot(last[2], last[3]))
            z = bearing_rad_meas[:, k]
            have = np.isfinite(z)
            if have.all():
                log_w += bearing_loglik(state, z[:, None], sigma_theta[:, k, None], work)
            elif have.any():
                log_w[have] += bearing_loglik(state[:, have], z[have, None], sigma_theta[have, k, None])
        # the first bearing is in the prior already; the first level is used like the others
        for b in range(0 if levels is None else levels.shape[2]):
            lv = levels[:, k, b]
            have = np.isfinite(lv)
            if not have.any():
                continue
            if errors is not None:
                resid = lv[:, None] - predicted_level_db(state, obs_state[k, 2:], per_band[b][k],
                                                         source_level_model=source_level_model, p0_db=p0_db)
                log_w += errors.update(b, resid, have[:, None], sigma_l ** 2)
                continue
            sub = state if have.all() else state[:, have]
            ll = level_loglik(sub, lv[have, None], obs_state[k, 2:], per_band[b][k], sigma_l,
                              source_level_model=source_level_model, p0_db=p0_db)
            if have.all():
                log_w = log_w + ll
            else:
                log_w[have] += ll
        log_w, w = normalise_exp(log_w, scratch(work, "w", log_w.shape))
        low = n_eff(w) < n_thr
        if low.any():
            if low.all():
                state, idx = regularise(state, w, rng, bandwidth=cfg.bandwidth, shrink=cfg.shrink, work=work,
                                        indices=True)
            else:
                state[:, low], idx = regularise(state[:, low], w[low], rng, bandwidth=cfg.bandwidth,
                                                shrink=cfg.shrink, work=work, indices=True)
            if errors is not None:
                errors.resample(low, idx)
            if mix.size > 1:
                sigma_a[low] = np.take_along_axis(sigma_a[low], idx, axis=-1)
            log_w[low] = -math.log(cfg.n_particles)
            w[low] = 1.0 / cfg.n_particles
            resampled[low, k] = True
        mean, cov = estimate(state, w, work)  # after the regularization step (sec. 4.4)
        means[:, k] = mean.T
        covs[:, k] = cov
        last = mean
        if summaries:
            sds[:, k] = particle_sds(state, w, obs_state[k, 2:])
    return BatchResult(mean=means, cov=covs, resampled=resampled,
                       extra={"sd": sds} if summaries else {})
