"""The Urick approximate transfer characteristic (Grinenkov & Mashoshin eq. 13)."""

from __future__ import annotations

import numpy as np

from acoustics.kcurve import spectral_term_db
from envdata.bands import Band
from envdata.classes import TargetClass


def spherical_tl_db(range_m, *, beta_db_per_km: float = 0.0):
    """Spherical spreading plus absorption: 20 lg r[m] + beta r[km], dB (60 dB at 1 km, beta = 0)."""
    range_m = np.asarray(range_m, dtype=float)
    return 20.0 * np.log10(range_m) + beta_db_per_km * range_m / 1000.0


def k_urick_db(range_m, band: Band, cls: TargetClass, *, beta_db_per_km: float, anomaly_db=0.0):
    """Transfer characteristic K(r) by the Urick approximate formula.

    Parameters
    ----------
    range_m : array_like
        Horizontal range, m. Must be > 0.
    band : Band
        Frequency band; eq. 13 uses its bounds and centre.
    cls : TargetClass
        The class, whose spectrum slope and reference frequency give the spectral terms.
    beta_db_per_km : float
        Spatial attenuation at the band centre, dB/km.
    anomaly_db : array_like, optional
        Propagation anomaly 10 lg A, dB; 0 for A = 1.

    Returns
    -------
    k_db : ndarray
        K(r), dB; band level W = P0 + K(r) + H (eq. 12).

    References
    ----------
    Grinenkov & Mashoshin (2024), eq. 13 (r in km there):
    K = -20 lg f_ekv + 10 lg (f_e - f_n) - beta r + 10 lg A - 20 lg r - 60.
    """
    range_km = np.asarray(range_m, dtype=float) / 1000.0  # eq. 13 is written in km
    if np.any(range_km <= 0):
        raise ValueError("k_urick_db: ranges must be > 0 m")
    return (spectral_term_db(cls, band) - beta_db_per_km * range_km + np.asarray(anomaly_db)
            - 20.0 * np.log10(range_km) - 60.0)


def urick_tables(area, range_m) -> tuple[np.ndarray, np.ndarray]:
    """The Urick K(r) of every class and band of an area and the bands' volume attenuation: what
    every grid and atlas stores beside the model's K.

    Returns
    -------
    k_urick_db : ndarray, shape (C, M, R)
        `k_urick_db` with A = 1 along ``range_m``, dB.
    beta_db_per_km : ndarray, shape (M,)
        Attenuation at each band's centre by the area's absorption model, dB/km.
    """
    from acoustics.absorption import absorption_db_per_km

    absorption = area.propagation.absorption
    beta = np.array([float(absorption_db_per_km(b.center_hz, absorption)) for b in area.bands])
    k = np.stack([np.stack([k_urick_db(range_m, band, cls, beta_db_per_km=beta[ib])
                            for ib, band in enumerate(area.bands)]) for cls in area.classes])
    return k, beta
