"""The one level likelihood: a target's band levels along a path, with the errors that persist
integrated out instead of counted again at every cycle.

Along a path (cycles k, the target at range r_k from the observer) the level of band m is
(Grinenkov & Mashoshin eqs. 12 and 31, the errors split by how long they last and which bands
they touch)

    W_km = P0 + K_m(r_k) + G + sum_j h_jm x_j(k) + n_km,

- n_km: the level measurement's own error, new at every cycle and band (eq. 11's sd from the
  band's SNR, or a filter's sigma_l);
- x_j: the components of `LevelErrors`, each Gaussian with sd ``sd_db`` (growing as
  hypot(sd, growth x d) with the observer's distance d from where the tables were computed:
  tables read away from their origin), common to every band (h_jm = 1) or one band's own:
  * an offset (no correlation scale): P0's error and K's persistent error, the same along the
    whole path (Grinenkov & Mashoshin's dK is drawn once per run); as d grows its variance
    grows by independent increments (what the offset was stays);
  * a residual: K's error that changes along the path, a Gauss-Markov process whose correlation
    between two cycles is exp(-|dt| / time_s - ds / length_m), ds the distance the target moved
    relative to the observer between them (K's error is a field over range and bearing from the
    observer; either scale may be absent).

Given the path every term is linear and Gaussian in dB, so a Kalman filter over the components
gives the exact density of the levels with all of them integrated out (`log_marginal`): the
offset is learned from the levels themselves as the path goes on, and counted once. Counted at
every cycle as white noise instead, a persistent error makes the levels of a long track look
far more informative than they are (the trackers' intervals then miss the truth), and an error
sd that varies with range pulls a filter to where K is best known (docs/sensitivity.md).

The particle filter carries the same Kalman filter per particle in its compiled loop
(`tracker.rpf.kernel.levelerrors`), the ML analysis and the depth posterior evaluate it along
their hypotheses' tracks here, and the Stone Soup measurement model takes one cycle's covariance
between bands from `LevelErrors.cycle_covariance`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

_LN_2PI = math.log(2.0 * math.pi)
#: The level measurement's own sd where a tracker takes one number for it, dB: eq. 11 at the
#: detection threshold (Grinenkov & Mashoshin: "does not exceed 1.1 dB"; less at a higher SNR).
MEASUREMENT_SD_DB = 1.1


@dataclass(frozen=True, slots=True, kw_only=True)
class Component:
    """One error component of the levels (module docstring), dB.

    Attributes
    ----------
    sd_db : float
        sd where the tables were computed (>= 0).
    band : int
        The band it belongs to, or -1 for every band.
    growth_db_per_km : float
        Its sd is hypot(sd_db, growth x d), d the observer's distance from where the tables were
        computed, km.
    time_s, length_m : float or None
        Correlation time, s, and length along the path, m, of a residual; both None: an offset.
    """

    sd_db: float
    band: int = -1
    growth_db_per_km: float = 0.0
    time_s: float | None = None
    length_m: float | None = None

    def __post_init__(self) -> None:
        for name in ("sd_db", "growth_db_per_km"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ValueError(f"level error {name} must be >= 0 dB, got {v}")
        for name in ("time_s", "length_m"):
            v = getattr(self, name)
            if v is not None and not (math.isfinite(v) and v > 0.0):
                raise ValueError(f"level error {name} must be > 0, got {v}")

    @property
    def persistent(self) -> bool:
        """An offset: no correlation scale."""
        return self.time_s is None and self.length_m is None


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelErrors:
    """The levels' errors that last longer than a cycle: a tuple of `Component`.

    Build it with `LevelErrors.tracking` (an offset common to the bands, each band's own offset,
    a residual along the path) or from components.
    """

    components: tuple[Component, ...]

    @classmethod
    def tracking(cls, *, offset_sd_db: float, band_offset_sd_db: float = 0.0, residual_sd_db: float = 0.0,
                 band_residual_sd_db: float = 0.0, residual_length_m: float | None = None,
                 residual_time_s: float | None = None, offset_growth_db_per_km: float = 0.0,
                 residual_growth_db_per_km: float = 0.0, band_residual_growth_db_per_km: float = 0.0,
                 n_bands: int = 1) -> LevelErrors:
        """An offset common to the bands, one per band, a residual common to the bands and one per
        band (its correlation scales ``residual_length_m``, ``residual_time_s``; each growing by
        its own rate); each part left out where its sd is 0 and it does not grow."""
        if (residual_sd_db > 0.0 or band_residual_sd_db > 0.0 or residual_growth_db_per_km > 0.0
                or band_residual_growth_db_per_km > 0.0) and residual_length_m is None and residual_time_s is None:
            raise ValueError("a residual needs its correlation length or time")
        parts = [Component(sd_db=offset_sd_db, growth_db_per_km=offset_growth_db_per_km)]
        parts += [Component(sd_db=band_offset_sd_db, band=m) for m in range(n_bands)] if n_bands > 1 else []
        parts += [Component(sd_db=residual_sd_db, growth_db_per_km=residual_growth_db_per_km,
                            length_m=residual_length_m, time_s=residual_time_s)]
        parts += ([Component(sd_db=band_residual_sd_db, band=m, growth_db_per_km=band_residual_growth_db_per_km,
                             length_m=residual_length_m, time_s=residual_time_s)
                   for m in range(n_bands)] if n_bands > 1 else [])
        if n_bands == 1:  # one band: its own parts are the common ones
            parts[0] = Component(sd_db=math.hypot(offset_sd_db, band_offset_sd_db),
                                 growth_db_per_km=offset_growth_db_per_km)
            parts[1] = Component(sd_db=math.hypot(residual_sd_db, band_residual_sd_db),
                                 growth_db_per_km=math.hypot(residual_growth_db_per_km, band_residual_growth_db_per_km),
                                 length_m=residual_length_m, time_s=residual_time_s)
        return cls(components=tuple(c for c in parts if c.sd_db > 0.0 or c.growth_db_per_km > 0.0))

    @classmethod
    def of_tables(cls, tables, ic: int, bands=None, *, source_sd_db: float = 0.0,
                  bearing_deg: float | None = None) -> LevelErrors:
        """The errors of class ``ic``'s levels read from ``tables``: K's error as the tables know it
        (``Tables.k_error_model``, `acoustics.grid.kerror`) and the source level's sd
        ``source_sd_db`` (P0's: the class's ``noise_sd_db`` for its constant level), persistent
        and common to the bands. ``bands``: the band indices whose levels are given, in their
        order (default every band); ``bearing_deg``: where a study's model is by bearing, the
        bearing the track is on (default its median over the radials). The offset is split between
        a part common to the bands and each band's own by the model's correlation between bands; so
        is the residual, but for its part that is each band's own whatever that correlation
        (``band_own_sd_db``, the tables' own: their interference patterns are off each its own
        way), which stays each band's own with its growth. The sds are the median over the bands."""
        model = tables.k_error_model(ic, bearing_deg)
        idx = list(range(len(model.offset_sd_db))) if bands is None else [int(b) for b in bands]
        rho = model.offset_band_correlation
        read = idx or list(range(len(model.offset_sd_db)))  # no band given: no level to use it on
        off = float(np.median([model.offset_sd_db[b] for b in read]))
        res = float(np.median([model.residual_sd_db[b] for b in read]))
        own, own_growth = model.band_own_sd_db, model.band_own_growth_db_per_km
        shared = math.sqrt(max(res * res - own * own, 0.0))  # the residual less its bands' own part
        return cls.tracking(offset_sd_db=math.hypot(source_sd_db, math.sqrt(rho) * off),
                            band_offset_sd_db=math.sqrt(1.0 - rho) * off,
                            residual_sd_db=math.sqrt(rho) * shared,
                            band_residual_sd_db=math.hypot(math.sqrt(1.0 - rho) * shared, own),
                            residual_length_m=model.residual_length_m,
                            offset_growth_db_per_km=model.offset_growth_db_per_km,
                            residual_growth_db_per_km=math.sqrt(max(model.residual_growth_db_per_km ** 2
                                                                    - own_growth ** 2, 0.0)),
                            band_residual_growth_db_per_km=own_growth, n_bands=len(idx))

    def cycle_sd_db(self, n_bands: int, displacement_m=0.0) -> tuple[np.ndarray, np.ndarray]:
        """One cycle's level errors (every component at its prior variance; the measurement's own
        left out): the sd of the part common to the bands and of each band's own (the root of the
        mean of the bands' variances), dB, each shaped like ``displacement_m``."""
        a = self.arrays(n_bands)
        var = prior_variance(a, displacement_m)                                        # (..., S)
        common = a["h"].all(axis=0)
        own = (a["h"][:, ~common] ** 2).sum(axis=0) / n_bands                           # each band's share
        return np.sqrt((var * common).sum(axis=-1)), np.sqrt((var[..., ~common] * own).sum(axis=-1))

    def arrays(self, n_bands: int) -> dict[str, np.ndarray]:
        """The components as arrays, in order: ``h`` (M, S) loadings, ``sd_db``, ``growth_db_per_km``
        (S,), ``inv_time_s``, ``inv_length_m`` (S,) (0: no forgetting on that scale), ``persistent``
        (S,) bool. A component of a band beyond ``n_bands`` is left out."""
        comps = [c for c in self.components if c.band < n_bands]
        h = np.zeros((n_bands, len(comps)))
        for j, c in enumerate(comps):
            if c.band < 0:
                h[:, j] = 1.0
            else:
                h[c.band, j] = 1.0
        return {"h": h, "sd_db": np.array([c.sd_db for c in comps], dtype=float),
                "growth_db_per_km": np.array([c.growth_db_per_km for c in comps], dtype=float),
                "inv_time_s": np.array([0.0 if c.time_s is None else 1.0 / c.time_s for c in comps]),
                "inv_length_m": np.array([0.0 if c.length_m is None else 1.0 / c.length_m for c in comps]),
                "persistent": np.array([c.persistent for c in comps], dtype=bool)}

    def cycle_covariance(self, n_bands: int, displacement_m: float = 0.0) -> np.ndarray:
        """Covariance between the bands of one cycle's level errors (every component at its
        prior variance, the measurement's own left out), (M, M), dB^2."""
        a = self.arrays(n_bands)
        var = prior_variance(a, displacement_m)
        return (a["h"] * var[None, :]) @ a["h"].T


def prior_variance(arrays: dict, displacement_m=0.0) -> np.ndarray:
    """Each component's variance with the observer ``displacement_m`` (any shape, m) from where
    the tables were computed, sd^2 + (growth d)^2 (`Component`), dB^2, shaped (..., S); ``arrays``
    as `LevelErrors.arrays` gives them. The one place the growth is written, for every tracker."""
    d_km = np.asarray(displacement_m, dtype=float)[..., None] / 1000.0
    return arrays["sd_db"] ** 2 + (arrays["growth_db_per_km"] * d_km) ** 2


def cycle_prior_variance(arrays: dict, n_cycles: int, displacement_m=None) -> np.ndarray:
    """`prior_variance` at each of ``n_cycles`` cycles, (T, S): ``displacement_m`` one per cycle
    or one for all (None: 0, the growth does not act)."""
    d = np.zeros(n_cycles) if displacement_m is None else np.broadcast_to(
        np.asarray(displacement_m, dtype=float), (n_cycles,))
    return prior_variance(arrays, d)


def log_marginal(resid_db, var_db2, errors: LevelErrors, *, t_s=None, step_m=None,
                 displacement_m=None) -> np.ndarray:
    """ln of the levels' density with every component of ``errors`` integrated out, after each
    cycle.

    Parameters
    ----------
    resid_db : array_like, shape (..., T, M)
        Level less its prediction P0 + K_m(r) + G, dB; NaN: no level.
    var_db2 : array_like, shape (..., T, M)
        Variance of the measurement's own error n, dB^2 (> 0 where a level is).
    errors : LevelErrors
    t_s : array_like, shape (T,), optional
        Cycle times, s (needed by components with a correlation time).
    step_m : array_like, shape (..., T), optional
        The distance the target moved relative to the observer since the last cycle along each
        path, m (needed by components with a correlation length; the first cycle's is unused).
    displacement_m : array_like, shape (T,), optional
        The observer's distance from where the tables were computed, m (default 0: the growth
        does not act).

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
    a = errors.arrays(m_n)
    h, s = a["h"], a["h"].shape[1]
    use = np.isfinite(e) & np.isfinite(v) & (v > 0)
    prior = cycle_prior_variance(a, t_n, displacement_m)                              # (T, S)
    if a["inv_time_s"].any() and t_s is None:
        raise ValueError("a component with a correlation time needs the cycle times t_s")
    if a["inv_length_m"].any() and step_m is None:
        raise ValueError("a component with a correlation length needs the paths' steps step_m")
    t = np.zeros(t_n) if t_s is None else np.asarray(t_s, dtype=float)
    step = np.zeros((n, t_n)) if step_m is None else np.broadcast_to(
        np.asarray(step_m, dtype=float), lead + (t_n,)).reshape(n, t_n)
    mean = np.zeros((n, s))
    cov = np.broadcast_to(np.diag(prior[0]), (n, s, s)).copy()
    out = np.zeros((n, t_n))
    total = np.zeros(n)
    eye = np.eye(m_n)
    diag = np.arange(s)
    for i in range(t_n):
        if i > 0 and s:
            # each residual forgets with the time and the path's step; each part's variance
            # brought to this cycle's (an offset's growth by independent increments)
            ds = np.nan_to_num(step[:, i], nan=0.0)
            rho = np.exp(-abs(t[i] - t[i - 1]) * a["inv_time_s"][None, :] - ds[:, None] * a["inv_length_m"][None, :])
            mean *= rho
            cov *= rho[:, :, None] * rho[:, None, :]
            cov[:, diag, diag] += np.maximum(prior[i][None, :] - rho ** 2 * prior[i - 1][None, :], 0.0)
        ok = use[:, i]
        if ok.any():
            hm = h[None] * ok[..., None]                                   # (n, M, S)
            y = np.where(ok, e[:, i], 0.0)
            innov = y - np.einsum("nms,ns->nm", hm, mean)
            ph = np.einsum("nst,nmt->nsm", cov, hm)                        # P H^T (n, S, M)
            sm = np.einsum("nms,nsk->nmk", hm, ph) + np.where(ok, v[:, i], 1.0)[..., None] * eye
            chol = np.linalg.cholesky(sm)
            z = np.linalg.solve(chol, innov[..., None])[..., 0]
            logdet = 2.0 * np.log(np.diagonal(chol, axis1=1, axis2=2)).sum(axis=1)
            k_obs = ok.sum(axis=1)
            # bands without a level: innovation 0, variance 1, no gain: a constant, left out
            total += np.where(k_obs > 0, -0.5 * ((z * z).sum(axis=1) + logdet + k_obs * _LN_2PI), 0.0)
            gain = np.linalg.solve(sm, np.swapaxes(ph, 1, 2))              # S^-1 H P (n, M, S)
            mean += np.einsum("nms,nm->ns", gain, innov)
            cov -= np.einsum("nsm,nmt->nst", ph, gain)
            cov = 0.5 * (cov + np.swapaxes(cov, 1, 2))  # rounding keeps it symmetric
        out[:, i] = total
    return out.reshape(lead + (t_n,))


def at_bearing(radials, values, brg) -> np.ndarray:
    """Each row's value of ``values`` (B, N), given on the radials (N,) deg ascending, read at the
    row's bearing ``brg`` (B,) linearly, across 0/360 (a NaN bearing reads the first radial)."""
    b = np.mod(np.nan_to_num(np.asarray(brg, dtype=float), nan=0.0), 360.0)
    ext = np.concatenate([radials, [radials[0] + 360.0]])
    j = np.clip(np.searchsorted(ext, b, side="right") - 1, 0, radials.size - 1)
    w = (b - ext[j]) / (ext[j + 1] - ext[j])
    rows = np.arange(len(b))
    return (1.0 - w) * values[rows, j] + w * values[rows, (j + 1) % radials.size]


def track_bearing_deg(bearing_deg) -> float | None:
    """The bearing a track is on, for a model of K's error by bearing: the circular mean of its
    measured bearings, deg (None without any)."""
    b = np.radians(np.asarray(bearing_deg, dtype=float))
    b = b[np.isfinite(b)]
    if b.size == 0:
        return None
    return float(np.degrees(np.arctan2(np.sin(b).mean(), np.cos(b).mean())) % 360.0)


def path_steps_m(x_m, y_m) -> np.ndarray:
    """The distance the target moved relative to the observer since the last cycle, m, along
    paths given by relative positions (..., T) (the first cycle's step 0; NaN stays NaN)."""
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    step = np.zeros(np.broadcast_shapes(x.shape, y.shape))
    step[..., 1:] = np.hypot(np.diff(x, axis=-1), np.diff(y, axis=-1))
    return step
