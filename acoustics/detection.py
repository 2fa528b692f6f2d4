"""When a band is detected: the indicator SNR of a class's level against the sea noise.

docs/formats.md "[sonar]" and "[[bands]]" and Grinenkov & Mashoshin eqs. 2, 11, 12:
the band level is W = P0 + K(r) + H; the band SNR after the array is

    10 lg q = W - H - (N_band - DI) = P0 + K(r) - (N_band - DI),

N_band the area's sea noise in the band and DI the array's directivity index; the indicator SNR
is Q = q sqrt(df T) (df the band's width, 1 Hz for one frequency; T the integration time), and a
band is detected where Q >= the sonar's detection threshold. The detection range along a bearing
is the largest grid range where the band (or, for the class, any band) is detected
(``acoustics.grid.detectionmap``). The simulator and the ML tracker take the indicator SNR from
here too: the formula lives once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from envdata.area import Area
from envdata.bands import Band
from envdata.classes import SourceLevelModel, TargetClass, ross_source_level_db


def band_snr_db(k_db, p0_db, noise_band_db, directivity_index_db: float) -> np.ndarray:
    """Band SNR 10 lg q = P0 + K(r) - (N_band - DI), dB (eqs. 11-12; H cancels)."""
    return np.asarray(p0_db, dtype=float) + np.asarray(k_db, dtype=float) - (
        np.asarray(noise_band_db, dtype=float) - directivity_index_db)


def indicator_snr(snr_db, bandwidth_hz, integration_time_s: float) -> np.ndarray:
    """Indicator SNR Q = q sqrt(df T) of eq. 2, linear, from the band SNR 10 lg q in dB."""
    q = 10.0 ** (np.asarray(snr_db, dtype=float) / 10.0)
    return q * np.sqrt(np.asarray(bandwidth_hz, dtype=float) * integration_time_s)


def k_needed_db(p0_db, noise_band_db, directivity_index_db: float, bandwidth_hz,
                integration_time_s: float, threshold: float) -> np.ndarray:
    """The K(r) at which a band reaches the detection threshold, dB: Q = threshold solved for K.

    10 lg q = 10 lg(threshold / sqrt(df T)), so K = 10 lg(threshold / sqrt(df T)) - P0 + N_band - DI;
    a band with K(r) at or above this is detected.
    """
    snr_needed = 10.0 * np.log10(threshold / np.sqrt(np.asarray(bandwidth_hz, dtype=float)
                                                     * integration_time_s))
    return snr_needed - np.asarray(p0_db, dtype=float) + np.asarray(noise_band_db, dtype=float) \
        - directivity_index_db


def farthest_m(range_m, detected) -> np.ndarray:
    """The largest range (last axis) where ``detected`` holds, m; NaN where it never does."""
    det = np.asarray(detected, dtype=bool)
    r = np.broadcast_to(np.asarray(range_m, dtype=float), det.shape)
    best = np.max(np.where(det, r, -np.inf), axis=-1)
    return np.where(np.isfinite(best), best, np.nan)


def class_mean_level(cls: TargetClass) -> tuple[float, str]:
    """The class's mean source level for a detection map, dB, and how the title names it.

    'p0' classes: ``noise_mean_db`` (P0, spectral level at 1 kHz); 'ross' classes: the Ross level
    at the class's mean speed (at the band centre, as their K is referred).
    """
    if cls.source_level_model is SourceLevelModel.ROSS:
        level = float(ross_source_level_db(cls.speed_mean_mps))
        return level, f"Ross SL {level:.1f} dB at {cls.speed_mean_mps:g} m/s"
    return float(cls.noise_mean_db), f"P0 {cls.noise_mean_db:g} dB"


@dataclass(frozen=True, slots=True, kw_only=True)
class DetectionTerms:
    """What decides detection for one class in the bands of a grid (grid band order).

    Attributes
    ----------
    p0_db : float
        The class's mean level (``class_mean_level``), dB re 1 uPa.
    level_label : str
        How a title names that level.
    noise_band_db : ndarray, shape (M,)
        Sea noise in each band, dB re 1 uPa.
    bandwidth_hz : ndarray, shape (M,)
        df of each band, Hz (1 Hz for one frequency).
    directivity_index_db, integration_time_s, threshold : float
        The sonar's DI, dB; T, s; and the indicator-SNR threshold, linear.
    """

    p0_db: float
    level_label: str
    noise_band_db: np.ndarray
    bandwidth_hz: np.ndarray
    directivity_index_db: float
    integration_time_s: float
    threshold: float

    def detected(self, k_db) -> np.ndarray:
        """Where a band is detected, for K(r) of shape (..., M, R) in dB; NaN K never is."""
        snr = band_snr_db(k_db, self.p0_db, self.noise_band_db[:, None], self.directivity_index_db)
        q_ind = indicator_snr(snr, self.bandwidth_hz[:, None], self.integration_time_s)
        return np.nan_to_num(q_ind, nan=0.0) >= self.threshold

    def k_needed_db(self) -> np.ndarray:
        """The K(r) each band needs to be detected, dB, shape (M,)."""
        return k_needed_db(self.p0_db, self.noise_band_db, self.directivity_index_db,
                           self.bandwidth_hz, self.integration_time_s, self.threshold)


def detection_terms(area: Area, cls: TargetClass, bands: tuple[Band, ...]) -> DetectionTerms:
    """The detection terms of a class of an area in the given bands (in that order)."""
    p0, label = class_mean_level(cls)
    sonar = area.sonar
    return DetectionTerms(p0_db=p0, level_label=label,
                          noise_band_db=np.array([area.noise.band_level_db(b) for b in bands]),
                          bandwidth_hz=np.array([b.width_hz for b in bands]),
                          directivity_index_db=sonar.directivity_index_db,
                          integration_time_s=sonar.integration_time_s,
                          threshold=sonar.detection_threshold)
