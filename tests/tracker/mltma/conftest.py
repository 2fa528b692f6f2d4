"""Shared geometry and grid of the ML tracker's tests (plain helpers, imported by the tests)."""

import dataclasses
import math

import numpy as np

import envdata
from acoustics.grid.dataset import flat_dataset
from acoustics.kcurve import spectral_term_db


def geometry(n=61, dt=10.0, tx=20000.0, ty=15000.0, k=300.0, v=6.5):
    """Observer at 90 deg, 2.5 m/s; target from (tx, ty) at course k, speed v; true bearings."""
    t = np.arange(n) * dt
    ox, oy = 2.5 * t, np.zeros(n)                      # observer 90 deg, 2.5 m/s
    x = tx + v * t * math.sin(math.radians(k))
    y = ty + v * t * math.cos(math.radians(k))
    b = np.mod(np.degrees(np.arctan2(x - ox, y - oy)), 360.0)
    return t, ox, oy, x, y, b


def synthetic_grid(truth_p0=131.02, speed=6.5):
    """The ocean-deep area with a monotone K(r), the same at every depth, and class means at the
    truth (a perfect prior): a whole grid dataset, its TL the spectral term less K."""
    area = envdata.load_area("ocean-deep")
    classes = tuple(dataclasses.replace(c, speed_mean_mps=speed, noise_mean_db=truth_p0)
                    if c.name == "TV" else c for c in area.classes)
    area = dataclasses.replace(area, classes=classes)
    r = np.arange(1, 1201) * 100.0
    base = -20 * np.log10(r)
    k = np.stack([np.stack([base - 0.02 * r / 1000 * (j + 1) - 3 * j for j in range(3)])
                  for _ in area.classes])
    depth = np.array([0.0, area.observer.depth_m, area.water.depth_m])
    s = np.array([[spectral_term_db(c, b) for b in area.bands] for c in area.classes])
    tl = np.repeat((s[:, :, None] - k)[:, :, None, :], depth.size, axis=2).astype(np.float32)
    beta = np.zeros(len(area.bands))
    return flat_dataset(area, "synthetic", depth, r, tl, k, k, beta, "synthetic", None)
