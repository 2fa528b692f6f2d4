"""The measurement simulator (section 4 steps 1-6) on the tiny BELLHOP grid."""


import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.grid.opentables import open_tables
from acoustics.kcurve import spectral_term_db
from tracker.ranging import bearing_sd_deg
from tracker.scenario import ScenarioError, load_scenario
from tracker.simulate import simulate_batch

SCENARIO = """[scenario]
name = "tiny"
target_class = "SHIP"
bearing_sd_min_deg = 0.0
[observer]
depth_m = {depth}
[[observer.tacks]]
course_deg = 90.0
speed_mps = 2.5
duration_s = 900.0
[target]
depth_m = 5.0
x_m = 1000.0
y_m = 4500.0
[[target.tacks]]
course_deg = 0.0
speed_mps = 3.0
noise_db = {noise}
duration_s = 900.0
"""


def _scenario(tmp_path, depth=300.0, noise=95.0):
    path = tmp_path / "tiny.toml"
    path.write_text(SCENARIO.format(depth=depth, noise=noise))
    return load_scenario(str(path))


@pytest.mark.bellhop
def test_k_at_depth_is_spectral_term_minus_tl(tiny_grid, tiny_area):
    k_at = open_tables(tiny_grid).k_db
    # at the grid's observer depth it is the grid's k_db (to float rounding)
    assert_allclose(k_at(tiny_area.observer.depth_m), tiny_grid["k_db"].values, atol=1e-9)
    assert_allclose(k_at(None), tiny_grid["k_db"].values, atol=1e-9)
    # at a depth node: K = S - TL(depth) (tl_db is stored as float32: 1e-3 dB)
    k300 = k_at(300.0)
    for ic, cls in enumerate(tiny_area.classes):
        for ib, band in enumerate(tiny_area.bands):
            tl = tiny_grid["tl_db"].values[ic, ib, list(tiny_grid["depth"].values).index(300.0)]
            assert_allclose(k300[ic, ib], spectral_term_db(cls, band) - tl, atol=1e-3)
    # between nodes: linear in depth
    assert_allclose(k_at(325.0), 0.5 * (k_at(300.0) + k_at(350.0)), atol=1e-9)
    assert not np.allclose(k300, tiny_grid["k_db"].values, atol=0.5)  # the depth matters here
    with pytest.raises(ValueError, match="receiver depth 1200 m is outside"):
        k_at(1200.0)


@pytest.mark.bellhop
def test_simulated_levels_use_k_at_the_observer_depth(tiny_grid, tmp_path, rng):
    sc = _scenario(tmp_path, depth=300.0)
    sim = simulate_batch(sc, open_tables(tiny_grid), rng, dk_db=0.0)
    tables = open_tables(tiny_grid)
    sonar = tables.area.sonar
    ic = list(tiny_grid["class"].values).index("SHIP")
    k = tables.k_db(300.0)[ic]                                          # (M, R)
    raxis = tiny_grid["range"].values
    expect = np.stack([np.interp(sim.range_m[0], raxis, k[j]) for j in range(k.shape[0])], -1)
    # W = P0 + K(r) + dK + H (eq. 12, 31) with K at the scenario's 300 m observer depth
    assert_allclose(sim.level_true_db[0], 95.0 + expect + sonar.receiver_gain_db, atol=1e-6)


@pytest.mark.bellhop
def test_simulated_bearing_sd_is_eq2_of_the_highest_detected_band(tiny_grid, tmp_path, rng):
    sc = _scenario(tmp_path, depth=100.0, noise=110.0)   # FB1 alone, or FB1 and F500
    sim = simulate_batch(sc, open_tables(tiny_grid), rng, dk_db=np.linspace(-6.0, 6.0, 8))
    tables = open_tables(tiny_grid)
    sonar = tables.area.sonar
    det = np.isfinite(sim.level_db)                                      # (E, T, M)
    q_ind = 10.0 ** (sim.snr_db / 10.0) * np.sqrt(tables.bandwidth_hz * sonar.integration_time_s)
    m = det.shape[-1]
    any_det = det.any(-1)
    assert any_det.sum() > 10
    top = m - 1 - np.argmax(det[..., ::-1], axis=-1)
    q_top = np.take_along_axis(q_ind, top[..., None], -1)[..., 0]
    expect = bearing_sd_deg(sonar.beamwidth_deg, np.maximum(q_top, 1.0))   # eq. 2
    assert_allclose(sim.bearing_sigma_deg[any_det], expect[any_det], rtol=1e-12)
    # both cases occur: the top band detected, and only the lower band detected
    assert np.any(any_det & (top == m - 1)) and np.any(any_det & (top < m - 1))


@pytest.mark.bellhop
def test_scenario_depth_outside_the_grid(tiny_grid, tmp_path, rng):
    sc = _scenario(tmp_path, depth=2000.0)
    with pytest.raises(ScenarioError, match=r"tiny.toml: \[observer\] depth_m: 2000 m is outside"):
        simulate_batch(sc, open_tables(tiny_grid), rng)
