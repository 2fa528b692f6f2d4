"""The probability of detecting a target at a state, from tmakit's tables and the sonar, and a
Stone Soup updater that uses it.

A band is detected where its indicator SNR Q = q sqrt(df T) reaches the sonar's threshold
(Grinenkov & Mashoshin eq. 2; ``acoustics.detection``): 10 lg q = P0 + K(r) - (N_band - DI)
must reach 10 lg(threshold / sqrt(df T)). The level a target gives scatters about its class's
mean by the source level's sd and K's error (Gaussian in dB; sigma from
``acoustics.grid.detectionsigma``, the one place P_D maps and tracks take it), so

    P_band = Phi((10 lg q_mean - 10 lg q_needed) / sigma),     (``acoustics.pd``, in logs here)
    P_d = 1 - prod over bands (1 - P_band)        (a detection: any band),

which is 1/2 exactly at the detection map's range (``acoustics.grid.detectionmap``, the class at
its mean level) and becomes its step where the sds go to zero. Stone Soup takes a constant
probability in most of its updaters; its Bernoulli particle updater asks
``get_log_detection_probability(prediction)`` per particle, which
`TablesBernoulliParticleUpdater` answers from the tables where the observer is at the
prediction's time.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.special import log_ndtr
from stonesoup.base import Property
from stonesoup.updater.particle import BernoulliParticleUpdater

from acoustics.detection import band_snr_db, detection_terms
from acoustics.grid.detectionsigma import detection_sigma_db
from tracker.stonesoup.model import geometry, source_level_db


@dataclass(frozen=True)
class DetectionProbability:
    """P_d of one class at states seen from an observer, from a grid face (``acoustics.open_tables``).

    ``level_sd_db`` None: the class's source-level sd and K error sd; 0 gives the detection map's
    step."""

    tables: object
    class_index: int
    level_sd_db: float | None = None

    def band_log_probabilities(self, state_vector, observer_x_m: float, observer_y_m: float,
                               observer_depth_m: float) -> tuple[np.ndarray, np.ndarray]:
        """log P_band and log(1 - P_band) for states (4, N): each (bands, N)."""
        tables = self.tables.at_observer(observer_x_m, observer_y_m)
        cls = tables.classes[self.class_index]
        bearing_rad, rng, speed = geometry(state_vector, observer_x_m, observer_y_m)
        bearing = np.degrees(bearing_rad) % 360.0
        k = np.atleast_2d(tables.k_at(self.class_index, rng, depth_m=observer_depth_m, bearing_deg=bearing)).T
        terms = detection_terms(tables.area, cls, tables.bands)
        p0 = source_level_db(cls, speed)[None, :]
        snr = band_snr_db(k, p0, terms.noise_band_db[:, None], terms.directivity_index_db)
        needed = 10.0 * np.log10(terms.threshold / np.sqrt(terms.bandwidth_hz * terms.integration_time_s))
        if self.level_sd_db is None:
            sd = np.atleast_2d(detection_sigma_db(tables, self.class_index, rng, bearing).total_db).T
        else:
            sd = np.full(snr.shape, float(self.level_sd_db))
        margin = np.nan_to_num(snr - needed[:, None], nan=-np.inf)  # no K (beyond land): never
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.where(sd > 0, margin / np.where(sd > 0, sd, 1.0), np.where(margin >= 0, np.inf, -np.inf))
        return log_ndtr(u), log_ndtr(-u)

    def __call__(self, state_vector, observer_x_m: float, observer_y_m: float,
                 observer_depth_m: float) -> np.ndarray:
        """P_d at each state (N,): any band detected."""
        _, log_miss = self.band_log_probabilities(state_vector, observer_x_m, observer_y_m, observer_depth_m)
        return -np.expm1(np.sum(log_miss, axis=0))

    def band_probabilities(self, state_vector, observer_x_m, observer_y_m, observer_depth_m) -> np.ndarray:
        """P_band at each state, (bands, N)."""
        log_p, _ = self.band_log_probabilities(state_vector, observer_x_m, observer_y_m, observer_depth_m)
        return np.exp(log_p)


class TablesBernoulliParticleUpdater(BernoulliParticleUpdater):
    """Stone Soup's Bernoulli particle updater with each particle's probability of detection from
    tmakit's tables (`DetectionProbability`) where the observer is at the prediction's time."""

    detection: DetectionProbability = Property(default=None, doc="P_d from the tables")
    observer_at: Callable = Property(default=None, doc="timestamp -> (x_m, y_m, depth_m) of the observer")

    def get_log_detection_probability(self, prediction):
        x, y, depth = self.observer_at(prediction.timestamp)
        p = self.detection(prediction.state_vector, x, y, depth)
        return np.log(np.clip(p, 1e-300, 1.0))


__all__ = ["DetectionProbability", "TablesBernoulliParticleUpdater"]
