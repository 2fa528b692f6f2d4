"""Scenario files: the built-ins of section 4 and malformed files."""

import math
from pathlib import Path

import pytest

from tracker.scenario import ScenarioError, builtin_scenario_names, load_scenario, target_track

BAD = Path(__file__).parent.parent / "data" / "malformed" / "scenario"


def test_builtin_gm_nps_geometry():
    sc = load_scenario("gm-nps")
    # section 4 items 3-4, 7: detected at 11.2 km, 26 deg to port of the 90 deg course
    assert math.hypot(sc.target_x_m, sc.target_y_m) == pytest.approx(11200.0, abs=1e-6)
    assert math.degrees(math.atan2(sc.target_x_m, sc.target_y_m)) == pytest.approx(64.0)
    x, y, c, v, p0, tack = target_track(sc, sc.times_s())
    assert c[0] == 270.0 and c[-1] == 210.0 and tack[-1] == 2
    assert p0[0] == pytest.approx(63.0 + 26.02)  # 63 dB re 20 uPa -> re 1 uPa
    assert {"gm-nps", "gm-tv-110km", "gm-tv-30km"} <= set(builtin_scenario_names())


@pytest.mark.parametrize("name, match", [
    ("unknown_key.toml", r"\[scenario\]: unknown key 'colour'"),
    ("course_out_of_range.toml", r"course_deg: must be in \[0, 360\) deg, got 400"),
    ("speed_not_number.toml", r"speed_mps: must be a number, got 'fast'"),
    ("missing_noise.toml", r"missing required key 'noise_db'"),
])
def test_malformed_scenarios(name, match):
    with pytest.raises(ScenarioError, match=match) as info:
        load_scenario(BAD / name)
    assert name in str(info.value)
