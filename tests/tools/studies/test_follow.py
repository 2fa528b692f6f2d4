"""The follow study's summaries: the level ranges against the truth, and one table's error over
another's with its interval over the runs."""

import numpy as np
from numpy.testing import assert_allclose

from tools.studies import follow


def test_level_range_by_time_reads_the_ln_error_and_the_relative_sd_per_bin():
    minutes = np.arange(0.0, 40.0, 1.0 / 3.0)
    r = np.tile(np.linspace(16000.0, 2000.0, minutes.size), (4, 1))
    ln_err = np.where(minutes < 10.0, 0.3, -0.1)                 # long early, short late
    sign = np.array([1.0, 1.0, 1.0, -1.0])[:, None]              # one run off the other way
    record = {"r_level_m": r * np.exp(sign * ln_err), "r_level_sd_m": 0.25 * r}
    record["r_level_m"][0, 0] = np.nan                           # a cycle without a band
    out = follow.level_range_by_time(record, r, minutes)
    assert list(out) == ["0-5", "5-10", "10-15", "15-20", "20-30", "30-40"]
    assert_allclose(out["0-5"]["ln_error_median"], 0.3, atol=1e-3)
    assert_allclose(out["20-30"]["ln_error_median"], -0.1, atol=1e-3)
    assert_allclose(out["0-5"]["ln_error_rms"], 0.3, atol=1e-3)  # the sign-flipped run counts too
    assert all(abs(v["sd_over_range_median"] - 0.25) < 1e-3 for v in out.values())


def test_ratio_to_reference_pairs_the_runs_and_brackets_the_ratio():
    rng = np.random.default_rng(3)
    reference = np.abs(rng.normal(800.0, 300.0, (60, 90)))
    # twice the reference run by run: the ratio is 2 whatever runs are drawn
    exact = follow.ratio_to_reference(2.0 * reference, reference, np.random.default_rng(0))
    assert exact == {"ratio": 2.0, "p05": 2.0, "p95": 2.0}
    # one run far off: the interval widens around the ratio and still holds it
    err = reference.copy()
    err[7] *= 6.0
    out = follow.ratio_to_reference(err, reference, np.random.default_rng(0))
    assert out["p05"] < out["ratio"] < out["p95"]
    assert out["ratio"] > 1.2 and out["p05"] < 1.05


def test_k_slope_reads_spreading_and_absorption_on_a_monotone_k():
    """K = -20 log10 r less a little absorption (tests/tracker/mltma/conftest.py's synthetic grid):
    20 dB per decade of range, a little more for the absorption, every time bin."""
    from acoustics.grid.opentables import open_tables
    from tests.tracker.mltma.conftest import synthetic_grid
    from tracker.scenario import load_scenario
    from tracker.simulate import simulate_batch

    tables = open_tables(synthetic_grid())
    sc = load_scenario("gm-tv-30km")
    ic = tables.class_index(sc.target_class)
    sim = simulate_batch(sc, tables, np.random.default_rng(0), dk_db=np.zeros(1))
    slope = follow.k_slope_by_time(sim, sc, ic, {"synthetic": tables})["synthetic"]
    assert list(slope) == ["0-5", "5-10", "10-15", "15-20", "20-30", "30-40"]
    assert all(20.0 < v < 23.0 for v in slope.values()), slope
