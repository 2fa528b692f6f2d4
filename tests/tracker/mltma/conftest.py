"""Shared geometry and grid of the ML tracker's tests (plain helpers, imported by the tests)."""

import dataclasses
import json
import math

import numpy as np
import xarray as xr

import envdata


def geometry(n=61, dt=10.0, tx=20000.0, ty=15000.0, k=300.0, v=6.5):
    """Observer at 90 deg, 2.5 m/s; target from (tx, ty) at course k, speed v; true bearings."""
    t = np.arange(n) * dt
    ox, oy = 2.5 * t, np.zeros(n)                      # observer 90 deg, 2.5 m/s
    x = tx + v * t * math.sin(math.radians(k))
    y = ty + v * t * math.cos(math.radians(k))
    b = np.mod(np.degrees(np.arctan2(x - ox, y - oy)), 360.0)
    return t, ox, oy, x, y, b


def synthetic_grid(truth_p0=131.02, speed=6.5):
    """The ocean-deep area with a monotone K(r) and class means at the truth (a perfect prior)."""
    area = envdata.load_area("ocean-deep")
    classes = tuple(dataclasses.replace(c, speed_mean_mps=speed, noise_mean_db=truth_p0)
                    if c.name == "TV" else c for c in area.classes)
    area = dataclasses.replace(area, classes=classes)
    r = np.arange(1, 1201) * 100.0
    base = -20 * np.log10(r)
    k = np.stack([np.stack([base - 0.02 * r / 1000 * (j + 1) - 3 * j for j in range(3)])
                  for _ in area.classes])
    return xr.Dataset({"k_db": (("class", "band", "range"), k)},
                      coords={"class": [c.name for c in area.classes],
                              "band": [b.name for b in area.bands], "range": r},
                      attrs={"area_json": json.dumps(area.to_dict())})
