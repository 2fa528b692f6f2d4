"""Error sds of one cycle's measurements: sigma_dW of the band levels (eq. 11) and sigma_P of the
bearing (eq. 2), from the band SNRs (section 3 steps 3-4).

Rows are hypotheses (B), columns bands (M). A band without a measured SNR (NaN) is taken at the
detection threshold.
"""

from __future__ import annotations

import numpy as np

from acoustics.detection import indicator_snr
from tracker.ranging import bearing_sd_deg, level_sd_db


def threshold_snr(detection_threshold, bandwidth_hz, integration_time_s):
    """Power SNR q at the detection threshold in each band: Q = q sqrt(df T) (eq. 2's Q_ind).

    Returns
    -------
    q : ndarray, shape (M,)
        Linear power SNR at which the indicator SNR equals ``detection_threshold``.
    """
    return detection_threshold / np.sqrt(bandwidth_hz * integration_time_s)


def highest_detected_band(detected):
    """Index of the highest detected band of each row, -1 where no band is detected.

    Parameters
    ----------
    detected : ndarray of bool, shape (B, M)
    """
    n_bands = detected.shape[1]
    return np.where(detected.any(1), n_bands - 1 - np.argmax(detected[:, ::-1], axis=1), -1)


def level_sd_from_snr_db(snr_db, q_threshold, bandwidth_hz, integration_time_s):
    """sigma_dW of each band level (eq. 11), dB.

    Parameters
    ----------
    snr_db : ndarray, shape (B, M)
        Measured power SNR q of each band, dB; NaN: not measured (q at the threshold is used).
    q_threshold : ndarray, shape (M,)
        `threshold_snr`.
    bandwidth_hz : ndarray, shape (M,)
    integration_time_s : float

    Returns
    -------
    sd_db : ndarray, shape (B, M)
    """
    q = np.where(np.isfinite(snr_db), 10.0 ** (snr_db / 10.0), q_threshold[None, :])
    q = np.maximum(q, 1e-6)
    return level_sd_db(q, bandwidth_hz, integration_time_s)


def bearing_sd_from_snr_deg(bearing_sd_deg_in, snr_db, top_band, q_threshold, bandwidth_hz,
                            integration_time_s, beamwidth_deg):
    """sigma_P of each row's bearing (eq. 2) where the measurement does not carry it, deg.

    Eq. 2 is taken at the indicator SNR of the highest detected band (of the band with the
    largest indicator SNR where none is detected), at least 1. The result is floored at
    1e-4 deg.

    Parameters
    ----------
    bearing_sd_deg_in : ndarray, shape (B,)
        The measurement's bearing sd, deg; NaN where eq. 2 is to give it.
    snr_db : ndarray, shape (B, M)
        Power SNR q of each band, dB; NaN: not measured (the threshold's q is used).
    top_band : ndarray of int, shape (B,)
        `highest_detected_band`.
    q_threshold : ndarray, shape (M,)
    bandwidth_hz : ndarray, shape (M,)
    integration_time_s, beamwidth_deg : float

    Returns
    -------
    sd_deg : ndarray, shape (B,)
    """
    sd = bearing_sd_deg_in.copy()
    miss = ~np.isfinite(sd)
    if miss.any():
        q_ind = indicator_snr(np.where(np.isfinite(snr_db), snr_db, 10 * np.log10(q_threshold)),
                              bandwidth_hz, integration_time_s)
        band = np.where(top_band >= 0, top_band, np.argmax(q_ind, axis=1))
        q_band = np.maximum(q_ind[np.arange(len(sd)), band], 1.0)
        sd[miss] = bearing_sd_deg(beamwidth_deg, q_band)[miss]
    return np.maximum(sd, 1e-4)
