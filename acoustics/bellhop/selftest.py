"""A tiny BELLHOP run that checks an executable works and gives physically sane numbers."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure

#: The self-tests' isovelocity 100 m channel: 100 Hz, the water's profile and the bottom's kind
#: (the lines after an .env's title, for BELLHOP and BELLHOP3D alike).
TINY_CHANNEL = """100.0
1
'CVW '
0 0.0 100.0
0.0 1500.0 /
100.0 1500.0 /
'A' 0.0
"""
# The channel, a source at 50 m, receivers at 10 and 90 m out to 1 km.
TINY_ENV = "'tmakit self-test'\n" + TINY_CHANNEL + """100.0 1600.0 0.0 1.8 0.8 0.0 /
1
50.0 /
2
10.0 90.0 /
3
0.1 0.5 1.0 /
'IG'
50
-30.0 30.0 /
0.0 101.0 1.1
"""


def self_test(exe: str | Path) -> dict:
    """Run TINY_ENV; report the time and the TL at 100 m range (near 40 dB of spherical spreading)."""
    start = time.perf_counter()
    result = run_env(TINY_ENV, exe=exe)
    tl = tl_from_pressure(result.field.pressure[0], 200.0)
    seconds = time.perf_counter() - start
    tl_100m = float(tl[0, 0])
    return {"ok": bool(np.all(np.isfinite(tl)) and 30.0 < tl_100m < 60.0), "seconds": seconds,
            "tl_db_at_100m": tl_100m, "shape": list(tl.shape)}
