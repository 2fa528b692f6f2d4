"""The depth a target's band levels allow: a likelihood of depth from every band at once that
knows which errors persist, and the posterior over depth it gives.

Along a track (ranges r_i from the observer, cycles i) the levels of band m are, for a target
at depth z (Grinenkov & Mashoshin eq. 12, the errors of eq. 31 split by how long they last and
which bands they touch),

    W_im = P0 + K_m(z, r_i) + G + b + c_m + g(r_i) + f_m(r_i) + u(r_i) + n_im,

- n_im: the level's own error, independent from cycle to cycle and band to band, sd of eq. 11
  from the band's SNR;
- K_m: the tables' K averaged over the track's range uncertainty (`tracker.kstructure`): a
  track estimated from the levels is off in range by a few per cent, and K's fine structure
  (its interference ripple) read there is not the one the target's levels went through;
- g, f_m: the tables' fine K error along the track (the interference pattern a little off), a
  Gauss-Markov process in time (exponential correlation over ``fine_time_s``): g common to the
  bands, sd ``fine_sd_db``, and f_m per band, sd ``fine_band_sd_db``, each growing with the
  observer's distance d from where the tables were computed (hypot(sd, growth x d); tables
  that hold everywhere, d = 0). Their sds are the tables'
  K, read as here (averaged over the range uncertainty), against BELLHOP run from the target
  where nothing else differs (the depth study's ``tables_vs_bellhop_from_target_db``:
  shelf-break, targets at 3-60 m and 3-20 km on a bearing from the observer): 1.94 dB common to
  the bands, 0.73 dB each band's own with the observer at the grid's origin (medians over the
  depths and over a radial and a bearing halfway between two), growing by 1.37 and 0.28 dB per
  km of the observer's distance from the origin (the same check with the observer 2.5 and 5 km
  away, the origin's tables read from there as a moving observer reads them; c_m by 0.32 dB per
  km). The correlation
  time is from the shelf-break slope along a true path (a submarine at 60 m, 10 s cycles, the
  range changing by 20 m a cycle: 0.35 after 50 s);
- u: a slow error common to the bands (the water or the bottom a little off), sd
  ``slow_sd_db`` over ``slow_time_s``;
- c_m: an offset per band, sd ``band_sd_db`` (the source's spectrum is the class's only to
  within it), growing with the observer's distance from the tables' origin as the fine errors
  do (the tables' band ratios read away from where they were computed; its increments a random
  walk: what the bands' offsets were stays);
- b: the offset common to every band and cycle, sd ``offset_sd_db`` (P0's sd and dK's), growing
  with the observer's distance from the tables' origin by ``offset_growth_db_per_km`` as c_m
  does: the origin's tables read from elsewhere are off by an amount that differs from depth to
  depth (the depth study's check: each depth's mean error less the origin's, 1.33 dB per km,
  RMS over 3-60 m) and changes slowly along the track, over kilometres of range (the check's
  part common to the bands, correlated from one km to the next by 0.7 to 0.9 away from the
  origin, -0.1 to 0.6 at it).

All of them are Gaussian and enter linearly: a Kalman filter over (b, c, g, f, u) along the
cycles gives the exact log density of the levels with every one integrated out
(`log_marginal`), and the depth's posterior under a prior uniform in depth is proportional to
it. The processes are correlated in time, not in the track's range: the depths are compared
along tracks that differ (each depth its own level-based range), and a correlation in the
track's range would make the model smoother along a shorter track, favouring the track that
makes the residual look smoothest rather than the depth that predicts the levels.

The prior over depth is uniform in ln(z + 1 m) (`posterior`): a target's depth spans two orders
of magnitude, and the question a sonar operator asks first is surface or submerged; a prior
uniform in depth would give a 2-300 m span's first 15 m 4 % of the mass, and where the levels
say little every target would come out submerged.

The depth cue is what no offset or error process can absorb: the shape of K along the track,
and the ratios of the bands (the sea surface's interference at a near-surface target's end
takes more from the low bands; the thermocline bends the bands' K differently). Where the
levels cannot separate a depth from an offset the posterior stays wide; a persistent error
cannot make it narrow, because it is not counted once per cycle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Surface-or-submerged call: a target at most this deep is at the surface, m ...
SURFACE_MAX_M = 15.0
#: ... and one at least this deep submerged.
SUBMERGED_MIN_M = 40.0
#: The depth prior is uniform in ln(z + this), m (`posterior`): log-uniform below the first
#: metres, defined at the surface.
PRIOR_LOG_OFFSET_M = 1.0
_LN_2PI = math.log(2.0 * math.pi)


#: How the error common to the bands of tables read away from where they were computed grows with
#: that distance, dB per km: the depth study's fit (``tables_vs_bellhop_from_target_db.fit.
#: offset_growth_db_per_km``, each depth's mean error less the origin's on the same bearing);
#: the depth likelihood's `LevelErrors.offset_growth_db_per_km` and the ML analysis's eq. 21.
K_ERROR_GROWTH_DB_PER_KM = 1.33


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelErrors:
    """The errors of the band levels that persist (module docstring): sds in dB, correlation
    times in s.

    Attributes
    ----------
    offset_sd_db : float
        sd of b, common to bands and cycles (hypot of the class's noise_sd_db and k_error_sd_db).
    offset_growth_db_per_km : float
        How b's sd grows with the observer's distance d from where the tables were computed:
        hypot(sd, growth x d), its increments a random walk.
    band_sd_db : float
        sd of c_m where the tables were computed.
    band_growth_db_per_km : float
        How it grows with the observer's distance d from there: hypot(sd, growth x d).
    fine_sd_db, fine_band_sd_db, fine_time_s : float
        sd of g and of f_m where the tables were computed, and their correlation time.
    fine_growth_db_per_km, fine_band_growth_db_per_km : float
        How the sds of g and f_m grow with the observer's distance d from there: hypot(sd,
        growth x d).
    slow_sd_db, slow_time_s : float
        sd of u and its correlation time.
    """

    offset_sd_db: float
    band_sd_db: float = 1.0
    fine_sd_db: float = 1.94
    fine_band_sd_db: float = 0.73
    fine_time_s: float = 60.0
    fine_growth_db_per_km: float = 1.37
    fine_band_growth_db_per_km: float = 0.28
    band_growth_db_per_km: float = 0.32
    slow_sd_db: float = 1.0
    slow_time_s: float = 600.0
    offset_growth_db_per_km: float = K_ERROR_GROWTH_DB_PER_KM

    def __post_init__(self) -> None:
        for name in ("offset_sd_db", "band_sd_db", "fine_sd_db", "fine_band_sd_db", "slow_sd_db",
                     "fine_growth_db_per_km", "fine_band_growth_db_per_km", "band_growth_db_per_km",
                     "offset_growth_db_per_km"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ValueError(f"{name} must be >= 0 dB, got {v}")
        for name in ("fine_time_s", "slow_time_s"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0.0):
                raise ValueError(f"{name} must be > 0 s, got {v}")

    @classmethod
    def of_class(cls, target, **kwargs) -> LevelErrors:
        """The class's offset sd (P0 and dK), the other sds as given or the defaults."""
        return cls(offset_sd_db=math.hypot(target.noise_sd_db or 0.0, target.k_error_sd_db), **kwargs)

    def effects(self, n_bands: int):
        """The state's components: (sd, correlation time in s or None when constant, band or -1
        for every band, growth of the sd per km of the observer's distance), in the Kalman
        filter's order."""
        fine, slow = self.fine_time_s, self.slow_time_s
        out = [(self.offset_sd_db, None, -1, self.offset_growth_db_per_km)]
        out += [(self.band_sd_db, None, m, self.band_growth_db_per_km) for m in range(n_bands)]
        out += [(self.fine_sd_db, fine, -1, self.fine_growth_db_per_km)]
        out += [(self.fine_band_sd_db, fine, m, self.fine_band_growth_db_per_km) for m in range(n_bands)]
        out += [(self.slow_sd_db, slow, -1, 0.0)]
        return [e for e in out if e[0] > 0.0 or e[3] > 0.0]


def log_marginal(resid_db, var_db2, t_s, errors: LevelErrors, displacement_m=None) -> np.ndarray:
    """ln of the levels' density with b, c, g, f and u integrated out, after each cycle.

    Parameters
    ----------
    resid_db : array_like, shape (..., T, M)
        Level less its prediction P0 + K_m(z, r) + G, dB; NaN: no level.
    var_db2 : array_like, shape (..., T, M)
        Variance of the independent part n_im, dB^2 (> 0 where a level is).
    t_s : array_like, shape (T,)
        Cycle times, s (the processes' correlation).
    errors : LevelErrors
    displacement_m : array_like, shape (T,), optional
        The observer's distance from where the tables were computed at each cycle, m (the fine
        errors' growth); default 0.

    Returns
    -------
    ndarray, shape (..., T)
        ln L of the cycles up to and including each one (0 before any level).
    """
    e = np.asarray(resid_db, dtype=float)
    v = np.broadcast_to(np.asarray(var_db2, dtype=float), e.shape)
    lead, (t_n, m_n) = e.shape[:-2], e.shape[-2:]
    n = int(np.prod(lead, dtype=np.int64)) if lead else 1
    e = e.reshape(n, t_n, m_n)
    v = v.reshape(n, t_n, m_n)
    t = np.asarray(t_s, dtype=float)
    use = np.isfinite(e) & np.isfinite(v) & (v > 0)
    effects = errors.effects(m_n)
    s = len(effects)
    h = np.zeros((m_n, s))
    for j, (_, _, band, _) in enumerate(effects):
        if band < 0:
            h[:, j] = 1.0
        else:
            h[band, j] = 1.0
    d_km = np.zeros(t_n) if displacement_m is None else np.broadcast_to(
        np.asarray(displacement_m, dtype=float) / 1000.0, (t_n,))
    # each component's variance at each cycle (T, S): constant unless the tables' error grows
    sd0 = np.array([e[0] for e in effects])
    growth = np.array([e[3] for e in effects])
    prior = sd0[None, :] ** 2 + (growth[None, :] * d_km[:, None]) ** 2
    moving = [(j, corr) for j, (_, corr, _, _) in enumerate(effects) if corr is not None]
    mean = np.zeros((n, s))
    cov = np.broadcast_to(np.diag(prior[0]), (n, s, s)).copy()
    out = np.zeros((n, t_n))
    total = np.zeros(n)
    eye = np.eye(m_n)
    diag = np.arange(s)
    for i in range(t_n):
        if i > 0 and moving:  # the Gauss-Markov processes forget with time
            rho = np.ones(s)
            for j, tau in moving:
                rho[j] = math.exp(-abs(t[i] - t[i - 1]) / tau)
            mean *= rho
            cov *= rho[:, None] * rho[None, :]
            # the innovation that brings each process to this cycle's variance (stationary: the
            # usual prior (1 - rho^2); a variance that shrinks is left to the forgetting)
            cov[:, diag, diag] += np.maximum(prior[i] - rho ** 2 * prior[i - 1], 0.0)
        ok = use[:, i]
        if ok.any():
            hm = h[None] * ok[..., None]                                   # (n, M, S)
            y = np.where(ok, e[:, i], 0.0)
            innov = y - np.einsum("nms,ns->nm", hm, mean)
            ph = np.einsum("nst,nmt->nsm", cov, hm)                        # P H^T (n, S, M)
            sm = np.einsum("nms,nsk->nmk", hm, ph) + np.where(ok, v[:, i], 1.0)[..., None] * eye
            chol = np.linalg.cholesky(sm)
            a = np.linalg.solve(chol, innov[..., None])[..., 0]
            logdet = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
            k_obs = ok.sum(axis=1)
            # rows without a level: innovation 0, variance 1, no gain: a constant, left out
            total += np.where(k_obs > 0, -0.5 * ((a * a).sum(axis=1) + logdet + k_obs * _LN_2PI), 0.0)
            gain = np.linalg.solve(sm, np.swapaxes(ph, 1, 2))              # S^-1 H P (n, M, S)
            mean += np.einsum("nms,nm->ns", gain, innov)
            cov -= np.einsum("nsm,nmt->nst", ph, gain)
            cov = 0.5 * (cov + np.swapaxes(cov, 1, 2))  # rounding keeps it symmetric
        out[:, i] = total
    return out.reshape(lead + (t_n,))


@dataclass(frozen=True, slots=True, kw_only=True)
class DepthPosterior:
    """A posterior over depth on a grid of depths, each standing for the cell between the
    midpoints to its neighbours (the span's ends outside), within which it is spread as the
    prior is: uniform in ln(z + ``log_offset_m``) (the default prior, `posterior`), or uniform
    in z when ``log_offset_m`` is None.

    Attributes
    ----------
    depth_m : ndarray, shape (D,)
        The grid, m, increasing.
    weight : ndarray, shape (..., D)
        Posterior mass of each cell (sums to 1 over the last axis).
    edges_m : ndarray, shape (D + 1,)
        The cells' edges, m.
    log_offset_m : float or None
        The prior's offset z0, m (> 0), or None for a prior uniform in depth.
    """

    depth_m: np.ndarray
    weight: np.ndarray
    edges_m: np.ndarray
    log_offset_m: float | None = None

    def _u(self, z):
        """The coordinate in which the mass is uniform within a cell."""
        z = np.asarray(z, dtype=float)
        return z if self.log_offset_m is None else np.log(z + self.log_offset_m)

    def _z(self, u):
        return u if self.log_offset_m is None else np.exp(u) - self.log_offset_m

    def _cdf(self) -> np.ndarray:
        return np.concatenate([np.zeros(self.weight.shape[:-1] + (1,)), np.cumsum(self.weight, axis=-1)], axis=-1)

    def quantile(self, q) -> np.ndarray:
        """Depth below which the mass is ``q``, m (as the prior within a cell), shape (...)."""
        flat = self._cdf().reshape(-1, self.edges_m.size)
        u = self._u(self.edges_m)
        out = np.array([np.interp(q, np.maximum.accumulate(c), u) for c in flat])
        return self._z(out).reshape(self.weight.shape[:-1])

    def mass_between(self, lo_m: float, hi_m: float) -> np.ndarray:
        """Posterior mass between two depths, m (as the prior within a cell), shape (...)."""
        cdf = self._cdf()
        u = self._u(self.edges_m)

        def at(z):
            i = np.clip(np.searchsorted(self.edges_m, z, side="right") - 1, 0, self.depth_m.size - 1)
            lo, hi = u[i], u[i + 1]
            f = np.clip((self._u(z) - lo) / (hi - lo), 0.0, 1.0) if hi > lo else 1.0
            return cdf[..., i] + f * (cdf[..., i + 1] - cdf[..., i])

        return at(hi_m) - at(lo_m)

    def _cell_moments(self) -> tuple[np.ndarray, np.ndarray]:
        """Each cell's mean depth and mean squared depth under the prior's spread, m and m^2."""
        lo, hi = self.edges_m[:-1], self.edges_m[1:]
        if self.log_offset_m is None:
            return 0.5 * (lo + hi), (lo * lo + lo * hi + hi * hi) / 3.0
        z0 = self.log_offset_m
        a, b = lo + z0, hi + z0
        span = np.log(b / a)
        with np.errstate(invalid="ignore", divide="ignore"):
            m1 = np.where(span > 0, (b - a) / span, a)                       # E[z + z0]
            m2 = np.where(span > 0, (b * b - a * a) / (2.0 * span), a * a)   # E[(z + z0)^2]
        return m1 - z0, m2 - 2.0 * z0 * m1 + z0 * z0

    def mean(self) -> np.ndarray:
        return (self.weight * self._cell_moments()[0]).sum(axis=-1)

    def sd(self) -> np.ndarray:
        """sd of the depth, m (each cell's own spread included)."""
        second = (self.weight * self._cell_moments()[1]).sum(axis=-1)
        return np.sqrt(np.maximum(second - self.mean() ** 2, 0.0))

    def at_cycle(self, weight) -> DepthPosterior:
        """The same grid and prior with other weights (a cycle's, a run's)."""
        return DepthPosterior(depth_m=self.depth_m, weight=weight, edges_m=self.edges_m,
                              log_offset_m=self.log_offset_m)

    def surface_probability(self) -> tuple[np.ndarray, np.ndarray]:
        """Posterior mass at most `SURFACE_MAX_M` deep and at least `SUBMERGED_MIN_M` deep."""
        top = self.edges_m[0]
        return (self.mass_between(top, SURFACE_MAX_M),
                self.mass_between(SUBMERGED_MIN_M, self.edges_m[-1]))


def cell_edges(depth_m, span_m: tuple[float, float]) -> np.ndarray:
    """Edges of the cells of a depth grid: midpoints between neighbours, the span's ends outside."""
    z = np.asarray(depth_m, dtype=float)
    mid = 0.5 * (z[1:] + z[:-1])
    return np.concatenate([[min(span_m[0], z[0])], mid, [max(span_m[1], z[-1])]])


def posterior(depth_m, log_likelihood, span_m: tuple[float, float], *,
              prior: str = "log") -> DepthPosterior:
    """The posterior over a depth grid from ln L at each grid depth (last axis).

    ``prior="log"`` (the default): uniform in ln(z + `PRIOR_LOG_OFFSET_M`) over ``span_m``, each
    cell's prior mass ln((hi + z0) / (lo + z0)); ``"uniform"``: uniform in depth, each cell's mass
    its width. Why the first (module docstring): a target's depth spans two orders of magnitude,
    and the operational question is surface or submerged; a prior uniform in depth gives the
    first 15 m of a 2-300 m span 4 % of its mass, so that where the levels say little (they
    often do) the posterior calls every target submerged and no 90 % interval reaches a
    surface ship; the log prior gives them 36 % and 43 % (<= 15 m, >= 40 m), near even.
    """
    if prior not in ("log", "uniform"):
        raise ValueError(f"prior must be 'log' or 'uniform', got {prior!r}")
    z = np.asarray(depth_m, dtype=float)
    edges = cell_edges(z, span_m)
    if edges[0] < 0.0:
        raise ValueError(f"depths must be >= 0 m, got a span from {edges[0]:g} m")
    z0 = PRIOR_LOG_OFFSET_M if prior == "log" else None
    cell = np.diff(edges) if z0 is None else np.log((edges[1:] + z0) / (edges[:-1] + z0))
    ll = np.asarray(log_likelihood, dtype=float)
    # no depth possible (each ruled out somewhere, ``TrackDepthLikelihood``): the levels say nothing
    ll = np.where(np.isneginf(ll).all(axis=-1, keepdims=True), 0.0, ll)
    lw = ll + np.log(np.maximum(cell, 1e-12))
    lw = lw - lw.max(axis=-1, keepdims=True)
    w = np.exp(lw)
    return DepthPosterior(depth_m=z, weight=w / w.sum(axis=-1, keepdims=True), edges_m=edges, log_offset_m=z0)


def depth_grid_m(axis_m, span_m: tuple[float, float]) -> np.ndarray:
    """The depths a posterior is computed on: the tables' depth axis inside the span, with the
    span's ends."""
    a = np.asarray(axis_m, dtype=float)
    lo, hi = span_m
    inside = a[(a > lo) & (a < hi)]
    return np.unique(np.concatenate([[lo], inside, [hi]]))
