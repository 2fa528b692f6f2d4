"""Grids built with RAM (``--model ram``) and with RAM below the crossover and BELLHOP above
(``--model auto``): real easypyram runs in worker processes, the real BELLHOP, real files.

The area is a small shelf (150 m, 3 km, a 50-100 Hz band and a 400 Hz one) so that the 21 RAM
runs per band cost a few seconds.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
import envdata
from acoustics.builder.bandruns import BuildStats
from acoustics.builder.gridfile import build_grid_file, resume_dir
from acoustics.builder.modelchoice import AUTO_CROSSOVER_HZ, RAM_FREQS_PER_BAND
from acoustics.kcurve import band_average_tl_db, band_frequencies_hz, band_weights
from acoustics.ram import RamEnvironment, RamSettings, ram_tl_db
from envdata.limits import TooLargeError, memory_limit
from tests.conftest import DATA

pytestmark = pytest.mark.bellhop


def _shelf_doc() -> dict:
    doc = envdata.load_area(DATA / "tiny-munk.toml").to_dict()
    doc["area"] = {**doc["area"], "name": "tiny-shelf"}
    doc["water"] = {"depth_m": 150.0, "ssp_depth_m": [0.0, 50.0, 150.0], "ssp_speed_mps": [1510.0, 1500.0, 1495.0]}
    doc["observer"] = {"depth_m": 60.0}
    doc["bands"] = [{"name": "LO", "low_hz": 50.0, "high_hz": 100.0}, {"name": "HI", "low_hz": 400.0, "high_hz": 400.0}]
    doc["classes"] = [{**doc["classes"][0], "depth_m": 40.0}]
    doc["grid"] = {"range_max_m": 3000.0, "range_step_m": 100.0, "depth_step_m": 10.0}
    return doc


@pytest.fixture(scope="module")
def shelf() -> envdata.Area:
    doc = _shelf_doc()
    doc["bands"] = doc["bands"][:1]  # RAM alone: the 50-100 Hz band
    return envdata.parse_area(doc, "tiny-shelf")


@pytest.fixture(scope="module")
def ram_grid(shelf):
    stats = BuildStats()
    return acoustics.build_grid(shelf, model="ram", workers=2, stats=stats), stats


def test_a_ram_band_is_the_intensity_average_of_21_coherent_runs(shelf, ram_grid):
    grid, stats = ram_grid
    tables = acoustics.open_tables(grid)  # the contract holds
    assert tables.model == "ram"
    assert stats.runs_total == RAM_FREQS_PER_BAND and stats.ram_seconds > 0.0
    settings = json.loads(grid.attrs["ram_settings"])
    assert settings["freqs_per_band"] == RAM_FREQS_PER_BAND == 21
    assert settings["depth_step_wavelengths"] == pytest.approx(1 / 30)
    # the same band from ram_tl_db directly, at the class depth's source and the grid's receivers
    band, cls = shelf.bands[0], shelf.classes[0]
    env = RamEnvironment.from_area(shelf, cls.depth_m)
    freqs = band_frequencies_hz(band, 21)
    depth, rng = grid["depth"].values, grid["range"].values
    per_freq = np.stack([ram_tl_db(env, f, depth, rng, RamSettings.for_environment(env, f)) for f in freqs])
    expected = band_average_tl_db(per_freq, band_weights(cls, freqs), 200.0)
    # float32 storage: 1e-3 dB
    assert_allclose(grid["tl_db"].values[0, 0], expected, rtol=0, atol=1e-3)


def test_ram_and_bellhop_agree_on_k_over_the_shelf(shelf, ram_grid):
    grid, _ = ram_grid
    bellhop = acoustics.build_grid(shelf, workers=2)
    far = grid["range"].values >= 500.0
    dk = np.abs(grid["k_db"].values[0, 0, far] - bellhop["k_db"].values[0, 0, far])
    # two models of a 150 m shelf at 50-100 Hz (coherent RAM bands, incoherent beams): a band
    # average of 21 runs keeps ~0.5 dB of fringes; 3 dB median, 6 dB p90 would be a wrong
    # bottom, source or spreading, not a difference of models
    assert np.median(dk) < 3.0 and np.percentile(dk, 90) < 6.0, (np.median(dk), np.percentile(dk, 90))


def test_source_hash_and_resume_cover_the_ram_runs(shelf, tmp_path):
    base = acoustics.expected_source_hash(shelf, "ram")
    assert base != acoustics.expected_source_hash(shelf, "bellhop")
    assert base != acoustics.expected_source_hash(shelf, "auto")
    out = tmp_path / "shelf-ram.nc"
    cache = resume_dir(out, base)
    # a build interrupted after its runs: the runs are in the resume folder, the file is not
    first = BuildStats()
    acoustics.build_grid(shelf, model="ram", workers=2, cache_dir=cache, stats=first)
    assert len(list(cache.glob("ram-*.npy"))) == RAM_FREQS_PER_BAND
    info = build_grid_file(shelf, out, model="ram", workers=2)
    assert info.runs_reused == info.runs == RAM_FREQS_PER_BAND and info.ram_seconds == 0.0
    assert not cache.exists()  # removed once the file is written
    assert acoustics.open_tables(out).dataset.attrs["source_hash"] == base
    again = build_grid_file(shelf, out, model="ram")
    assert again.up_to_date


def test_auto_takes_ram_below_the_crossover_and_bellhop_above(shelf, ram_grid):
    area = envdata.parse_area(_shelf_doc(), "tiny-shelf")  # LO 50-100 Hz and HI 400 Hz
    assert area.bands[0].high_hz < AUTO_CROSSOVER_HZ <= area.bands[1].low_hz
    auto = acoustics.build_grid(area, model="auto", workers=2)
    bellhop = acoustics.build_grid(area, workers=2)
    assert auto.attrs["model"] == "auto"
    assert json.loads(auto.attrs["ram_settings"])["crossover_hz"] == AUTO_CROSSOVER_HZ
    # the band under the crossover is RAM's band, the one over it BELLHOP's, to the bit
    assert_allclose(auto["tl_db"].values[:, 0], ram_grid[0]["tl_db"].values[:, 0], rtol=0, atol=0)
    assert_allclose(auto["tl_db"].values[:, 1], bellhop["tl_db"].values[:, 1], rtol=0, atol=0)


def test_auto_splits_a_band_across_the_crossover():
    from acoustics.builder.bandruns import Model
    from acoustics.builder.modelchoice import band_plans

    doc = _shelf_doc()
    doc["bands"] = [{"name": "MID", "low_hz": 150.0, "high_hz": 600.0}]
    plan = band_plans(envdata.parse_area(doc, "mid"), Model.AUTO)[0]
    assert len(plan.freqs_hz) == 21
    assert all(f < AUTO_CROSSOVER_HZ for f in plan.ram_hz) and all(f >= AUTO_CROSSOVER_HZ for f in plan.bellhop_hz)
    assert len(plan.ram_hz) + len(plan.bellhop_hz) == 21 and plan.ram_hz and plan.bellhop_hz


def test_a_ram_grid_too_large_is_refused_before_any_run(shelf, tmp_path):
    cache = tmp_path / "cache"
    with memory_limit(1e-5), pytest.raises(TooLargeError, match=r"RAM grid of area tiny-shelf would need "
                                                                 r"[0-9.]+ GiB"):
        acoustics.build_grid(shelf, model="ram", workers=2, cache_dir=cache)
    assert not cache.exists()


def test_a_bearing_dependent_ram_grid_of_a_flat_area_is_the_flat_ram_grid(shelf, ram_grid, monkeypatch):
    # this build's runs go to two worker processes however small (else they run here)
    monkeypatch.setattr("acoustics.builder.ramruns.IN_PROCESS_WORK", 0.0)
    doc = shelf.to_dict()
    doc["origin"] = {"lat_deg": 43.0, "lon_deg": 5.0}
    doc["bearings"] = {"bearing_deg": [0.0, 90.0]}
    doc["area"] = {**doc["area"], "latitude_deg": 43.0, "longitude_deg": 5.0}
    doc["classes"] = [{**doc["classes"][0], "depth_m": shelf.observer.depth_m}]
    radial_area = envdata.parse_area(doc, "shelf-with-origin")
    stats = BuildStats()
    radial = acoustics.build_grid(radial_area, model="ram", workers=2, stats=stats)
    assert acoustics.open_tables(radial).model == "ram" and radial["tl_db"].attrs["fixed_end"] == "observer"
    # identical radials are one set of runs
    assert stats.runs_total == RAM_FREQS_PER_BAND
    del doc["origin"], doc["bearings"]
    flat = acoustics.build_grid(envdata.parse_area(doc, "flat"), model="ram", workers=2)
    depth = flat["depth"].values
    for bearing in radial["bearing"].values:
        a = radial["tl_db"].sel(bearing=bearing, depth=depth).values
        # the radial's sound speed comes through the climatology-free section builder and its
        # 500 m RAM columns; with one profile it is the flat problem to float32 rounding (below
        # the surface: a table from the observer holds the loss 1 m down in its 0 m row, where
        # RAM's coherent field is zero and the flat grid's receiver capped)
        assert np.nanmax(np.abs(a - flat["tl_db"].values)[..., 1:, :]) < 0.05, bearing
        assert (a[..., 0, :] < flat["tl_db"].values[..., 0, :] - 30.0).all()


@pytest.mark.slow
def test_auto_on_a_two_worker_dask_cluster_equals_the_local_build():
    from distributed import LocalCluster

    area = envdata.parse_area(_shelf_doc(), "tiny-shelf")
    local = acoustics.build_grid(area, model="auto", workers=2)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as cluster:
        stats = BuildStats()
        remote = acoustics.build_grid(area, model="auto", scheduler=cluster.scheduler_address, stats=stats)
    # RAM's runs and BELLHOP's both went to the cluster: 21 RAM runs and one BELLHOP run
    assert stats.runs_total == RAM_FREQS_PER_BAND + 1 and stats.ram_seconds > 0 and stats.bellhop_seconds > 0
    assert_allclose(remote["tl_db"].values, local["tl_db"].values, rtol=0, atol=0)
    assert_allclose(remote["k_db"].values, local["k_db"].values, rtol=0, atol=0)
