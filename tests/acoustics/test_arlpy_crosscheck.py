"""Cross-check: our .env writer and .shd reader against arlpy.uwapm driving the same BELLHOP."""

from __future__ import annotations

import os

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from acoustics.bellhop.envfile import RunSpec, env_text
from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure

pytestmark = pytest.mark.bellhop


def _with_bellhop_on_path(fn):
    """arlpy runs 'bellhop.exe' from PATH: put the executable tmakit uses first on PATH."""
    old = os.environ.get("PATH", "")
    os.environ["PATH"] = f"{find_bellhop().path.parent}{os.pathsep}{old}"
    try:
        return fn()
    finally:
        os.environ["PATH"] = old


def test_tl_agrees_with_arlpy_on_the_munk_1000_environment():
    import arlpy.uwapm as pm

    area = envdata.load_area("munk-1000")
    ssp = area.water.ssp
    rx_depth = np.arange(50.0, 1000.0, 100.0)
    rx_range = np.arange(500.0, 20_001.0, 500.0)
    env = pm.create_env2d(
        depth=area.water.depth_m, soundspeed=[[z, c] for z, c in zip(ssp.depth_m, ssp.speed_mps)],
        bottom_soundspeed=area.bottom.speed_mps, bottom_density=area.bottom.density_gcc * 1000.0,
        bottom_absorption=area.bottom.attenuation_db_per_wavelength, tx_depth=5.0, rx_depth=rx_depth,
        rx_range=rx_range, frequency=50.0, nbeams=2000, min_angle=-80.0, max_angle=80.0,
        soundspeed_interp=pm.linear)  # tabulated profiles are linear (BELLHOP C), as in DESIGN.md
    p_arlpy = _with_bellhop_on_path(lambda: pm.compute_transmission_loss(env, mode=pm.incoherent))
    assert p_arlpy is not None, "arlpy's BELLHOP run failed (arlpy prints the reason)"
    tl_arlpy = tl_from_pressure(np.asarray(p_arlpy, dtype=complex), 200.0)

    # arlpy always asks BELLHOP for Thorp absorption ('CVWT') and geometric beams ('IG')
    spec = RunSpec(title="cross-check", freq_hz=50.0, source_depth_m=(5.0,), receiver_depth_m=tuple(rx_depth),
                   range_m=tuple(rx_range), n_beams=2000, angle_min_deg=-80.0, angle_max_deg=80.0,
                   absorption=envdata.Absorption.THORP)
    tl_ours = tl_from_pressure(run_env(env_text(area, spec)).field.pressure[0], 200.0)
    assert tl_ours.shape == tl_arlpy.shape == (rx_depth.size, rx_range.size)
    # same executable and physics; the two env files differ only in formatting and box size,
    # so the fields agree to rounding of the written numbers
    assert_allclose(tl_ours, tl_arlpy, rtol=0, atol=0.05)
