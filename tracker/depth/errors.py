"""The depth likelihood's model of the levels' errors: which persist, which change along the track
and how, as the depth study measured them; its density is the one level likelihood's
(`tracker.levels.log_marginal`, the errors as its components).

Along a track (ranges r_i from the observer, cycles i) the levels of band m are, for a target
at depth z (Grinenkov & Mashoshin eq. 12, the errors of eq. 31 split by how long they last and
which bands they touch),

    W_im = P0 + K_m(z, r_i) + G + b + c_m + g(r_i) + f_m(r_i) + u(r_i) + n_im,

- n_im: the level's own error, independent from cycle to cycle and band to band, sd of eq. 11
  from the band's SNR;
- K_m: the tables' K averaged over the track's range uncertainty (`tracker.depth.kstructure`): a
  track estimated from the levels is off in range by a few per cent, and K's fine structure
  (its interference ripple) read there is not the one the target's levels went through;
- g, f_m: the tables' fine K error along the track (the interference pattern a little off), a
  Gauss-Markov process in time (exponential correlation over ``fine_time_s``): g common to the
  bands, sd ``fine_sd_db``, and f_m per band, sd ``fine_band_sd_db``, each growing with the
  observer's distance d from where the tables were computed (hypot(sd, growth x d); tables
  that hold everywhere, d = 0). Their sds are the tables'
  K, read as here (averaged over the range uncertainty), against BELLHOP run from the target
  where nothing else differs (the depth study's ``tables_vs_bellhop_from_target_db``:
  shelf-break, targets at 3-60 m and 3-20 km on a bearing from the observer): 1.89 dB common to
  the bands, 0.75 dB each band's own with the observer at the grid's origin (medians over the
  depths and over a radial and a bearing halfway between two), growing by 1.31 and 0.27 dB per
  km of the observer's distance from the origin (the same check with the observer 2.5 and 5 km
  away, the origin's tables read from there as a moving observer reads them; c_m by 0.31 dB per
  km; the fit made at 9eb1f5a on the mirrored arrivals run, 1.94, 0.73, 1.37, 0.28 and
  0.32 before). The correlation
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

All of them are Gaussian and enter linearly: `tracker.levels.log_marginal` (a Kalman filter
over them along the cycles) gives the exact log density of the levels with every one integrated
out (`log_marginal`), and the depth's posterior (`tracker.depth.posterior`) is proportional to
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

from tracker import levels

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
    fine_sd_db: float = 1.89
    fine_band_sd_db: float = 0.75
    fine_time_s: float = 60.0
    fine_growth_db_per_km: float = 1.31
    fine_band_growth_db_per_km: float = 0.27
    band_growth_db_per_km: float = 0.31
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


    def as_components(self, n_bands: int) -> levels.LevelErrors:
        """The same errors as the one level likelihood's components (`tracker.levels`)."""
        return levels.LevelErrors(components=tuple(
            levels.Component(sd_db=sd, band=band, growth_db_per_km=growth, time_s=corr)
            for sd, corr, band, growth in self.effects(n_bands)))


def log_marginal(resid_db, var_db2, t_s, errors: LevelErrors, displacement_m=None) -> np.ndarray:
    """ln of the levels' density with b, c, g, f and u integrated out, after each cycle
    (`tracker.levels.log_marginal` with `LevelErrors.as_components`).

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
    n_bands = np.shape(resid_db)[-1]
    return levels.log_marginal(resid_db, var_db2, errors.as_components(n_bands), t_s=t_s,
                               displacement_m=displacement_m)
