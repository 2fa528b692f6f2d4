"""Grid building: the dataset of docs/formats.md, K(r) from BELLHOP, the shortcuts and their cost."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import acoustics
import envdata
from acoustics.builder.flat import combined_tl_db
from acoustics.builder.plan import plan_runs
from acoustics.builder.runs import execute_runs
from acoustics.kcurve import spectral_term_db

pytestmark = pytest.mark.bellhop


def test_grid_has_the_contract_dimensions_and_coordinates(tiny_grid, tiny_area):
    ds = tiny_grid
    assert ds["tl_db"].dims == ("class", "band", "depth", "range")
    assert ds["k_db"].dims == ds["k_urick_db"].dims == ds["anomaly_db"].dims == ("class", "band", "range")
    assert list(ds["class"].values) == ["SUB", "SHIP"] and list(ds["band"].values) == ["FB1", "F500"]
    assert_allclose(ds["range"].values, np.arange(100.0, 5001.0, 100.0))
    assert_allclose(ds["depth"].values, np.arange(0.0, 1001.0, 50.0))
    assert_allclose(ds["band_center_hz"].values, [np.sqrt(100 * 300), 500.0])
    assert_allclose(ds["source_depth_m"].values, [150.0, 5.0])
    assert ds.attrs["Conventions"] == "CF-1.8" and ds.attrs["model"] == "bellhop"
    assert ds.attrs["observer_depth_m"] == 100.0
    assert ds.attrs["source_hash"] == acoustics.expected_source_hash(tiny_area)
    assert "aubellhop" in ds.attrs["bellhop_version"]
    for name in ("tl_db", "k_db", "k_urick_db", "depth", "range", "band_low_hz"):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs or name in ("depth", "range")


def test_k_is_spectral_term_minus_band_tl_at_the_observer_depth(tiny_grid, tiny_area):
    for cls in tiny_area.classes:
        for band in tiny_area.bands:
            sel = {"class": cls.name, "band": band.name}
            tl_obs = tiny_grid["tl_db"].sel(sel).sel(depth=100.0).values  # observer on the depth grid
            assert_allclose(tiny_grid["k_db"].sel(sel).values, spectral_term_db(cls, band) - tl_obs,
                            rtol=0, atol=1e-4)  # float32 storage of tl_db
            assert_allclose(tiny_grid["anomaly_db"].sel(sel), tiny_grid["k_db"].sel(sel) - tiny_grid["k_urick_db"].sel(sel),
                            rtol=0, atol=1e-9)


def test_bellhop_tl_is_near_spherical_spreading_close_to_the_source(tiny_grid):
    # at 100-300 m from a source at 150 m, receiver at 150 m, the direct path dominates:
    # TL within 3 dB of 20 lg r (surface and bottom paths add a little, never much)
    tl = tiny_grid["tl_db"].sel({"class": "SUB", "band": "FB1"}).sel(depth=150.0, range=[100.0, 200.0, 300.0])
    spherical = 20 * np.log10([100.0, 200.0, 300.0])
    assert np.all(np.abs(tl.values - spherical) < 3.0)


def test_urick_model_is_spherical_spreading_plus_absorption(tiny_area):
    ds = acoustics.build_grid(tiny_area, model="urick")
    assert ds.attrs["model"] == "urick" and "bellhop_version" not in ds.attrs
    assert_allclose(ds["k_db"], ds["k_urick_db"], rtol=0, atol=0)
    beta = float(acoustics.thorp_db_per_km(np.sqrt(100 * 300)))
    tl = ds["tl_db"].sel({"class": "SUB", "band": "FB1", "depth": 500.0, "range": 1000.0})
    assert_allclose(float(tl), 60.0 + beta, rtol=0, atol=1e-4)


def test_classes_at_the_same_depth_share_runs(tiny_area):
    twin = dataclasses.replace(tiny_area.classes[1], name="SHIP2")
    area = dataclasses.replace(tiny_area, classes=tiny_area.classes + (twin,))
    runs = plan_runs(area)
    # 2 distinct depths x (FB1 centre + F500) with the incoherent frequency shortcut
    assert len({r.key for r in runs}) == 4


def test_frequency_shortcut_costs_little_accuracy(tiny_area):
    """One run per band vs a run per quadrature frequency (incoherent beams, fixed fan; the 5 m
    ship's runs with the band-averaged Lloyd pattern against each frequency's own)."""
    full = dataclasses.replace(tiny_area, propagation=dataclasses.replace(tiny_area.propagation,
                                                                          frequency_shortcut=False))
    assert len(plan_runs(full)) == 2 * (7 + 1) and len(plan_runs(tiny_area)) == 2 * 2
    a = acoustics.build_grid(tiny_area, workers=2)
    b = acoustics.build_grid(full, workers=2)
    diff = np.abs(a["k_db"] - b["k_db"]).values
    # incoherent beams with a fixed fan depend on frequency only through absorption (and the
    # frequency-dependent beam step); 0.3 dB is well inside the 1.5-2 dB K error of the paper
    assert np.median(diff) < 0.05 and np.percentile(diff, 99) < 0.3


def test_rebuild_is_deterministic(tiny_grid, tiny_area):
    again = acoustics.build_grid(tiny_area, workers=1)
    xr.testing.assert_allclose(again.drop_attrs(), tiny_grid.drop_attrs(), rtol=0, atol=0)
    assert again.attrs["source_hash"] == tiny_grid.attrs["source_hash"]


def test_source_hash_changes_with_anything_that_changes_the_numbers(tiny_area):
    base = acoustics.expected_source_hash(tiny_area)
    moved = dataclasses.replace(tiny_area, observer=envdata.Observer(depth_m=101.0))
    assert acoustics.expected_source_hash(moved) != base
    assert acoustics.expected_source_hash(tiny_area, "urick") != base
    assert acoustics.expected_source_hash(tiny_area) == base


def test_k_alone_direct_equals_the_grid_k(tiny_grid, tiny_area):
    stats = acoustics.BuildStats()
    k = acoustics.build_k(tiny_area, reciprocity_min_depth_m=math.inf, stats=stats)
    # a run per frequency for the submarine and one for the ship (its own source pattern)
    assert stats.runs_total == 4 and k.attrs["reciprocity_min_depth_m"] == math.inf
    # one receiver depth instead of 21, same rays: the same K to float32 rounding of tl_db
    assert_allclose(k.values, tiny_grid["k_db"].values, rtol=0, atol=1e-4)


def test_k_by_reciprocity_holds_for_the_submerged_class(tiny_grid, tiny_area):
    k = acoustics.build_k(tiny_area, reciprocity_min_depth_m=0.0)
    diff = np.abs(k.sel({"class": "SUB"}) - tiny_grid["k_db"].sel({"class": "SUB"})).values
    # source 150 m / receiver 100 m swapped: beam tracing is reciprocal to a fraction of a dB
    # away from caustics (ocean-deep, 200 m class: 0.1 dB median, 1.2 dB p95; see bench/run.py)
    assert np.median(diff) < 0.3


def test_coherent_mode_runs_every_quadrature_frequency(tiny_area):
    area = dataclasses.replace(tiny_area, propagation=dataclasses.replace(
        tiny_area.propagation, mode=envdata.TlMode.COHERENT))
    runs = plan_runs(area)
    assert len(runs) == 2 * (7 + 1)  # 2 depths x (7 frequencies of FB1 + the single F500)
    assert all("'CG'" in r.env for r in runs)


def test_semicoherent_mode_gives_the_near_surface_source_a_pattern(tiny_area):
    """One run per band; the 5 m ship's runs carry the band-averaged Lloyd pattern (a .sbp file,
    run type 'IG*'), the 150 m submarine's are plain incoherent runs (beyond the surface's reach:
    5 wavelengths at 100 Hz is 77 m)."""
    area = dataclasses.replace(tiny_area, propagation=dataclasses.replace(
        tiny_area.propagation, mode=envdata.TlMode.SEMICOHERENT))
    runs = plan_runs(area, balance=False)
    assert len(runs) == 2 * 2
    ship = [r for r in runs if r.source_depth_m == 5.0]
    sub = [r for r in runs if r.source_depth_m == 150.0]
    assert all("'IG*'" in r.env and dict(r.files)["sbp"].startswith("300\n") and r.pattern_key for r in ship)
    assert all("'IG'" in r.env and not r.files and not r.pattern_key for r in sub)
    # the pattern is the dipole: 2 (k z theta)^2 at grazing angles (the beams nearest 0 deg, at
    # +-0.27 deg: -33 dB over 100-300 Hz), the band average of 2 sin^2 (about 0 dB) when steep
    levels = {float(a): float(v) for a, v in (line.split() for line in dict(ship[0].files)["sbp"].splitlines()[1:])}
    assert levels[-80.0] > -1.0 and levels[min(levels, key=abs)] < -30.0


@pytest.mark.parametrize("mode", ["incoherent", "coherent"])
def test_beam_fan_slices_add_up_to_the_whole_fan(tiny_area, mode):
    """Slices of one fan with the same angular spacing sum (intensity or pressure) to the fan."""
    area = dataclasses.replace(tiny_area, propagation=dataclasses.replace(
        tiny_area.propagation, mode=envdata.TlMode(mode)))
    whole = plan_runs(area, source_depths_m=[150.0], pieces=1)[:1]
    sliced = plan_runs(area, source_depths_m=[150.0], pieces=3)[:3]
    assert [r.n_beams for r in sliced] == [100, 100, 100] and whole[0].n_beams == 300
    # spacing 160 / 299 deg kept: slices -80..-27.02, -26.49..26.49, 27.02..80 deg
    assert "-80 -27.023411 /" in sliced[0].env and "27.023411 80 /" in sliced[2].env
    fields = execute_runs(whole + sliced)
    tl_whole = combined_tl_db([fields[whole[0].key]], area.propagation.mode, 200.0)
    tl_sliced = combined_tl_db([fields[r.key] for r in sliced], area.propagation.mode, 200.0)
    audible = tl_whole < 150.0
    # the same beams, summed in another order and stored as single precision: to 0.01 dB
    assert_allclose(tl_sliced[audible], tl_whole[audible], rtol=0, atol=0.01)


def test_an_odd_number_of_runs_gets_its_last_run_halved(tiny_area):
    three_bands = dataclasses.replace(tiny_area, bands=tiny_area.bands + (
        envdata.Band(name="F900", low_hz=900.0, high_hz=900.0),), classes=tiny_area.classes[:1])
    runs = plan_runs(three_bands)
    assert [(r.freq_hz, r.part, r.n_parts, r.n_beams) for r in runs][-2:] == [
        (900.0, 0, 2, 150), (900.0, 1, 2, 150)]
    assert len(runs) == 4 and all(r.n_parts == 1 for r in runs[:2])


def test_a_frequency_shared_by_two_bands_is_one_run_counted_once(tiny_area):
    """FB1 100-300 Hz and FB2 300-900 Hz share 300 Hz: one run, and its intensity is not doubled."""
    bands = (envdata.Band(name="FB1", low_hz=100.0, high_hz=300.0),
             envdata.Band(name="FB2", low_hz=300.0, high_hz=900.0))
    prop = dataclasses.replace(tiny_area.propagation, frequency_shortcut=False, freqs_per_band=3)
    area = dataclasses.replace(tiny_area, bands=bands, classes=tiny_area.classes[:1], propagation=prop)
    runs = plan_runs(area)
    assert sorted({round(r.freq_hz) for r in runs}) == [100, 173, 300, 520, 900]
    assert len(runs) == 6  # five runs, the odd last one in two fan slices
    k = acoustics.build_k(area, reciprocity_min_depth_m=math.inf)
    grid = acoustics.build_grid(area)
    assert_allclose(k.values, grid["k_db"].values, rtol=0, atol=1e-4)
    # FB2 alone, with nothing shared, gives the same K
    alone = acoustics.build_k(dataclasses.replace(area, bands=bands[1:]), reciprocity_min_depth_m=math.inf)
    assert_allclose(k.sel(band="FB2").values, alone.sel(band="FB2").values, rtol=0, atol=1e-9)
