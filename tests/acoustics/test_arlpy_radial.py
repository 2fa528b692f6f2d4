"""Cross-check of a range-dependent radial: tmakit's .env/.bty/.ssp against arlpy's create_env2d.

The same radial of the built-in shelf-break area (bottom and sound-speed section sampled along
its geodesic), at one frequency, with the source at the observer's depth: once through tmakit's
own BELLHOP input (acoustics.bellhop.radialfiles) and once through arlpy (its own environment,
.venv-arlpy), both running the same bellhop.exe. Agreement: median |dTL| <= 1 dB and 90th
percentile <= 3 dB over the receivers where both see sound (TL < 120 dB).

arlpy is given the whole radial, the samples behind the origin included: with the bottom and
the columns from the source on only, a ray sent back by the slope leaves the 'Q' field and
BELLHOP stops ("ray is outside the box where the soundspeed is defined"), the range-dependent
SSP pitfall arlpy users meet. Measured: median 0.3 dB, 90th percentile 1.4 dB (seaward, 180 deg)
and 1.7 dB (toward the coast, 0 deg). What is left is the inputs, not the model: tmakit sets the
ray step (25 m) where arlpy leaves BELLHOP's automatic one (a tenth of the deepest depth, some
250 m here), and arlpy sizes the ray box and the end of its sound-speed field itself.
"""

from __future__ import annotations

import numpy as np
import pytest

import envdata
from acoustics.bellhop.envfile import RunSpec
from acoustics.bellhop.radialfiles import radial_files
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from envdata.radials import area_radials
from tests.crosscheck.run_arlpy import arlpy_tl_db

pytestmark = pytest.mark.bellhop


@pytest.mark.parametrize("bearing", [180.0, 0.0])  # down the slope to the basin; up to the coast
def test_a_shelf_break_radial_agrees_with_arlpy(tmp_path, bearing):
    area = envdata.load_area("shelf-break")
    radial = next(r for r in area_radials(area) if r.bearing_deg == bearing)
    end = radial.land_range_m if radial.land_range_m is not None else area.grid.range_max_m
    rx_range = np.arange(500.0, min(end, area.grid.range_max_m) - 1.0, 500.0)
    ahead = radial.range_m >= 0.0
    deepest_ahead = float(radial.bottom_depth_m[ahead].max())  # arlpy: no receiver below it
    rx_depth = np.arange(10.0, min(deepest_ahead, 2000.0), 50.0)
    freq = 300.0
    beams = 2000
    obs = area.observer.depth_m

    spec = RunSpec(title="radial cross-check", freq_hz=freq, source_depth_m=(obs,),
                   receiver_depth_m=tuple(rx_depth), range_m=tuple(rx_range), n_beams=beams,
                   angle_min_deg=-80.0, angle_max_deg=80.0, absorption=envdata.Absorption.THORP)
    box_m = float(rx_range[-1]) * 1.01 + 10.0
    files = radial_files(area, radial, spec, step_m=25.0, box_range_m=box_m)
    ours = tl_from_pressure(run_env(files["env"], files={"bty": files["bty"], "ssp": files["ssp"]})
                            .field.pressure[0], 200.0)

    case = {
        "frequency_hz": freq, "source_depth_m": obs,
        "receiver_depth_m": rx_depth.tolist(), "receiver_range_m": rx_range.tolist(),
        "bathymetry": {"range_m": radial.range_m.tolist(),
                       "depth_m": radial.bottom_depth_m.tolist()},
        "ssp": {"depth_m": radial.ssp_depth_m.tolist(),
                "range_m": radial.ssp_range_m.tolist(),
                "speed_mps": radial.speed_mps.tolist()},
        "bottom": {"speed_mps": area.bottom.speed_mps, "density_gcc": area.bottom.density_gcc,
                   "attenuation_db_per_wavelength": area.bottom.attenuation_db_per_wavelength},
        "beams": {"count": beams, "min_angle_deg": -80.0, "max_angle_deg": 80.0},
        "mode": "incoherent", "tl_max_db": 200.0,
    }
    theirs = arlpy_tl_db(case, tmp_path)["tl_db"]
    assert theirs.shape == ours.shape == (rx_depth.size, rx_range.size)
    # receivers in the water on this radial, where both see sound
    bottom = np.interp(rx_range, radial.range_m, radial.bottom_depth_m)
    wet = rx_depth[:, None] < bottom[None, :]
    heard = wet & (ours < 120.0) & (theirs < 120.0)
    assert heard.sum() > 0.3 * wet.sum()
    d = np.abs(ours - theirs)[heard]
    assert np.median(d) <= 1.0, np.median(d)
    assert np.percentile(d, 90) <= 3.0, np.percentile(d, 90)
