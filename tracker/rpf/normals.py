"""Standard normal draws for the numpy engine: Box-Muller on float32 uniforms.

The process noise (eq. 6) and the kernel draws (eq. 26) need many normals whose far tail does
not matter; this is about 3x cheaper than ``Generator.standard_normal`` for the same count.
"""

from __future__ import annotations

import math

import numpy as np

from tracker.rpf.scratch import scratch


def standard_normal_pairs(shape, rng: np.random.Generator, work: dict | None = None
                          ) -> tuple[np.ndarray, np.ndarray]:
    """Two independent arrays of N(0, 1) draws of ``shape`` (Box-Muller on float32 uniforms).

    r = sqrt(-2 ln U1), (r cos 2 pi U2, r sin 2 pi U2), computed in float32 and returned as
    float32. The 24-bit uniforms cut the tail at |z| = 5.77 (probability 8e-9), immaterial for
    process noise and kernel draws.

    Parameters
    ----------
    shape : tuple of int
        Shape of each array.
    rng : numpy.random.Generator
    work : dict, optional
        Scratch arrays (`tracker.rpf.scratch`); the results live in them.

    Returns
    -------
    a, b : ndarray of float32, shape ``shape``
    """
    u = rng.random((2, *shape), dtype=np.float32,
                   out=scratch(work, "u", (2, *shape), np.float32))
    r = np.subtract(1.0, u[0], out=u[0])  # (0, 1]: finite log
    np.log(r, out=r)
    r *= -2.0
    np.sqrt(r, out=r)
    u[1] *= 2.0 * math.pi
    a = np.cos(u[1], out=scratch(work, "a", shape, np.float32))
    np.sin(u[1], out=u[1])
    a *= r
    u[1] *= r
    return a, u[1]
