"""The Pekeris waveguide's exact field as a sum of its trapped normal modes (the RAM checks' reference).

Isovelocity water (speed c1, density rho1) of depth D over a fluid half-space (c2 > c1, rho2),
pressure-release surface, no loss. A trapped mode is sin(kz z) in the water and
sin(kz D) exp(-gamma (z - D)) below it, with gamma = sqrt(kz_max^2 - kz^2),
kz_max^2 = k1^2 - k2^2; continuity of p and of (1/rho) dp/dz at z = D gives

    kz cos(kz D) / rho1 + gamma sin(kz D) / rho2 = 0,   0 < kz < kz_max,

whose roots are bracketed on a fine grid and refined with brentq. The modes are normalised
to int psi^2 / rho dz = 1, and the field is (Jensen, Kuperman, Porter & Schmidt, Computational
Ocean Acoustics, eq. 5.14)

    p(r, z) = i / (4 rho(zs)) sum_m psi_m(zs) psi_m(z) H0^(1)(kr_m r),

TL = -20 lg |p / p0(1 m)| with |p0(1 m)| = 1 / (4 pi). The continuous spectrum (leaky and
evanescent waves) is left out: it dies within a few kilometres of the source here.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq
from scipy.special import hankel1


def pekeris_wavenumbers(freq_hz: float, depth_m: float, c1_mps: float, c2_mps: float,
                        rho1_gcc: float, rho2_gcc: float) -> np.ndarray:
    """Vertical wavenumbers kz (rad/m) of the trapped modes, increasing (mode 1 first)."""
    omega = 2.0 * np.pi * freq_hz
    k1, k2 = omega / c1_mps, omega / c2_mps
    kz_max = np.sqrt(k1 ** 2 - k2 ** 2)

    def characteristic(kz: float) -> float:
        gamma = np.sqrt(max(kz_max ** 2 - kz ** 2, 0.0))
        return kz * np.cos(kz * depth_m) / rho1_gcc + gamma * np.sin(kz * depth_m) / rho2_gcc

    grid = np.linspace(1e-9 * kz_max, kz_max * (1.0 - 1e-12), 20_000)
    values = np.array([characteristic(k) for k in grid])
    roots = [brentq(characteristic, grid[i], grid[i + 1], xtol=1e-14)
             for i in np.nonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)[0]]
    return np.array(roots)


def pekeris_tl_db(freq_hz: float, source_depth_m: float, depth_m, range_m, *, water_depth_m: float,
                  c1_mps: float, c2_mps: float, rho1_gcc: float, rho2_gcc: float) -> np.ndarray:
    """Coherent TL (depth, range), dB re 1 m, of the trapped-mode sum; receivers in the water."""
    z = np.asarray(depth_m, dtype=float)
    r = np.asarray(range_m, dtype=float)
    omega = 2.0 * np.pi * freq_hz
    k1, k2 = omega / c1_mps, omega / c2_mps
    kz = pekeris_wavenumbers(freq_hz, water_depth_m, c1_mps, c2_mps, rho1_gcc, rho2_gcc)
    kr = np.sqrt(k1 ** 2 - kz ** 2)
    gamma = np.sqrt(k1 ** 2 - k2 ** 2 - kz ** 2)
    d = water_depth_m
    norm = ((d / 2.0 - np.sin(2.0 * kz * d) / (4.0 * kz)) / rho1_gcc
            + np.sin(kz * d) ** 2 / (2.0 * gamma * rho2_gcc))
    amp = 1.0 / np.sqrt(norm)

    def psi(depth):  # (modes, depths); the receivers here are in the water
        return amp[:, None] * np.sin(np.outer(kz, depth))

    source = psi(np.array([source_depth_m]))[:, 0]
    h = hankel1(0, np.outer(kr, r))  # (modes, ranges)
    p = 1j / (4.0 * rho1_gcc) * np.einsum("m,mz,mr->zr", source, psi(z), h)
    return -20.0 * np.log10(np.maximum(4.0 * np.pi * np.abs(p), 1e-10))
