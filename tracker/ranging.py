"""Error models of Grinenkov & Mashoshin (eqs. 2 and 11) and the nodes of eq. 21.

Everything here is vectorised over a leading batch axis (class hypotheses, Monte Carlo runs),
so that one code path serves the one-cycle tracker API and the 1331-run experiment. Level-based
ranging itself (eqs. 20-21, `level_range`) is ``acoustics.levelrange``, the lowest layer that
uses it (the sensitivity studies' range error too).
"""

from __future__ import annotations

import numpy as np


def bearing_sd_deg(beamwidth_deg, q_ind):
    """RMS bearing error, deg (eq. 2): sigma_P = 0.2 * beamwidth / Q_ind.

    Parameters
    ----------
    beamwidth_deg : float
        Width of the array's beam, deg.
    q_ind : array_like
        Indicator (output) SNR Q = q sqrt(df T), linear.
    """
    return 0.2 * np.asarray(beamwidth_deg, dtype=float) / np.asarray(q_ind, dtype=float)


def level_sd_db(q, bandwidth_hz, integration_time_s):
    """RMS error of a band level estimate, dB (eq. 11 = A2.6).

    sigma = 10 lg(1 + sqrt((q + 1)^2 + 1) / (q sqrt(df T))), q the linear power SNR at the
    output of the linear part of the receiver. At the indicator SNR q sqrt(df T) = 5 and small q
    this is 10 lg(1 + sqrt(2)/5) = 1.08 dB, the paper's "does not exceed 1.1 dB".
    """
    q = np.asarray(q, dtype=float)
    return 10.0 * np.log10(1.0 + np.sqrt((q + 1.0) ** 2 + 1.0)
                           / (q * np.sqrt(np.asarray(bandwidth_hz) * integration_time_s)))


def offset_nodes(noise_sd_db: float, k_error_sd_db: float, n: int = 5):
    """Quadrature nodes of eq. 21 over p in mP0 +- 2 sP0 and dK in +- 2 sigma_dK.

    Only the sum c = (p - mP0) + dK enters eq. 20, so the n x n product rule is returned as
    offsets c, dB, and normalised normal-density weights.
    """
    u = np.linspace(-2.0, 2.0, n)
    w = np.exp(-0.5 * u ** 2)
    c = (u[:, None] * noise_sd_db + u[None, :] * k_error_sd_db).ravel()
    ww = (w[:, None] * w[None, :]).ravel()
    return c, ww / ww.sum()


def offset_nodes_per_row(noise_sd_db, k_error_sd_db, n: int = 5):
    """`offset_nodes` with each row's own sds: offsets (n*n, B), dB, and the weights (n*n,).

    Parameters
    ----------
    noise_sd_db, k_error_sd_db : array_like, shape (B,)
        sP0 and sigma_dK of each row, dB (sigma_dK at the row's bearing and range where the grid
        carries a measured ``k_error_sd_db``).
    """
    u = np.linspace(-2.0, 2.0, n)
    w = np.exp(-0.5 * u ** 2)
    sp = np.asarray(noise_sd_db, dtype=float)
    sk = np.asarray(k_error_sd_db, dtype=float)
    c = (u[:, None, None] * sp[None, None, :] + u[None, :, None] * sk[None, None, :]).reshape(n * n, -1)
    ww = (w[:, None] * w[None, :]).ravel()
    return c, ww / ww.sum()
