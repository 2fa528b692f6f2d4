"""Shared pieces of the kernel tests: the precision bar, a particle cloud, a K(r) profile, and
fresh numba caches for the compiled test helpers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from acoustics.grid.levelprofile import LevelProfile
from tracker.rpf.kernel.cache import drop_stale_caches

RTOL = 1e-9  # the brief's bar for the exact pieces; both sides are double precision


def particles(rng, n=4000, d=4):
    """A (d, n) cloud of relative states spread over tens of km and a few m/s."""
    s = np.empty((d, n))
    s[0] = rng.normal(3000.0, 4000.0, n)
    s[1] = rng.normal(-2000.0, 4000.0, n)
    s[2] = rng.normal(0.5, 2.0, n)
    s[3] = rng.normal(-1.0, 2.0, n)
    if d > 4:
        s[4] = rng.normal(0.0, 3.0, n)
    return s


def profile(uniform=False):
    """A K(r) profile to 20 km, on a uniform range axis or one `k_at` must walk."""
    r = np.linspace(100.0, 20_000.0, 60 if not uniform else 400)
    if not uniform:
        r[10:] += 37.0  # not uniform: the index guess must walk (`k_at`)
    return LevelProfile(range_m=r, k_db=-20.0 * np.log10(r) - 1e-4 * r + 5.0 * np.sin(r / 900.0))


@pytest.fixture(autouse=True, scope="session")
def _fresh_wrapper_caches():
    """The cached helpers of `wrappers` embed kernel code, which numba does not track: drop
    their caches when a kernel source is newer, so that the tests run the kernel as it is."""
    drop_stale_caches(Path(__file__).parent / "__pycache__")
