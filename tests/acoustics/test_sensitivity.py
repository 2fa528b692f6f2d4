"""Sensitivity studies: K(r) per member, the ensemble dataset, summaries, write-back, resume."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import envdata
from acoustics import perturb as pt
from acoustics import sensitivity as sens
from envdata.errors import InputError
from tests.conftest import DATA


def specs(*texts):
    return [p for text in texts for p in pt.parse_spec(text)]


TINY_SPECS = ("displace:sd_m=10", "temperature:sd_c=0.3,scale_m=300", "bottom-speed:sd_mps=30",
              "source-depth:sd_frac=0.15", "observer-depth:sd_m=2")


def test_k_runs_use_reciprocity_for_deep_classes_and_direct_for_shallow(tiny_area):
    sources, receivers, where = sens.k_runs(tiny_area)  # SUB 150 m, SHIP 5 m, observer 100 m
    assert sources == [5.0, 100.0] and receivers == [100.0, 150.0]
    assert where == {"SUB": (1, 1), "SHIP": (0, 0)}  # SUB: observer -> 150 m; SHIP: 5 m -> observer
    sources, receivers, where = sens.k_runs(tiny_area, reciprocity_min_depth_m=1e9)
    assert sources == [5.0, 150.0] and receivers == [100.0]


@pytest.mark.bellhop
def test_member_k_matches_the_grid_build(tiny_area, tiny_grid):
    direct, seconds = sens.compute_k(tiny_area, reciprocity_min_depth_m=1e9)
    assert seconds > 0
    # same BELLHOP inputs per (source, receiver) pair as the grid build: equal to float32 rounding
    assert_allclose(direct, tiny_grid["k_db"].values, rtol=0, atol=1e-3)
    mixed, _ = sens.compute_k(tiny_area)
    assert_allclose(mixed[1], tiny_grid["k_db"].values[1], rtol=0, atol=1e-3)  # SHIP: direct
    diff = np.abs(mixed[0] - tiny_grid["k_db"].values[0])  # SUB at 150 m: by reciprocity
    assert np.median(diff) < 0.2  # measured 0.05 dB; incoherent beams are nearly reciprocal at depth


@pytest.fixture(scope="module")
def tiny_study(tiny_area):
    stats = sens.StudyStats()
    ds = sens.run_study(tiny_area, specs(*TINY_SPECS), members=4, seed=11, workers=2, stats=stats)
    return ds, stats


@pytest.mark.bellhop
def test_study_dataset_has_the_contract_layout(tiny_area, tiny_study):
    ds, stats = tiny_study
    assert ds["k_db"].dims == ("member", "class", "band", "range")
    assert ds.sizes == {"member": 4, "class": 2, "band": 2, "range": 50}
    assert stats.members_total == 4 and stats.members_reused == 0 and stats.workers == 2
    assert stats.bellhop_seconds > 0
    for name in ("displace_dz_m", "temperature_dt_c", "bottom_speed_mps", "source_depth_factor",
                 "observer_depth_m"):
        assert ds[name].dims == ("member",)
    for m in range(4):
        _, params = pt.member_area(tiny_area, specs(*TINY_SPECS), 11, m)
        assert {k: float(ds[k].values[m]) for k in params} == params
    nominal, _ = sens.compute_k(tiny_area)
    assert_allclose(ds["k_nominal_db"].values, nominal, rtol=0, atol=1e-9)
    assert np.all(np.abs(ds["k_db"] - ds["k_nominal_db"]).max("range") > 0.01)  # every member moved
    assert ds.attrs["seed"] == 11 and ds.attrs["area"] == "tiny-munk"


@pytest.mark.bellhop
def test_study_file_round_trip(tiny_study, tmp_path):
    ds, _ = tiny_study
    path = sens.write_study(ds, tmp_path / "s.nc")
    xr.testing.assert_identical(sens.open_study(path), ds)
    with pytest.raises(sens.StudyFileError, match=r"nope.nc: study file not found"):
        sens.open_study(tmp_path / "nope.nc")
    (tmp_path / "bad.nc").write_text("k_db = 1\n")
    with pytest.raises(sens.StudyFileError, match=r"bad.nc: not a netCDF file"):
        sens.open_study(tmp_path / "bad.nc")
    ds.drop_vars("k_db").to_netcdf(tmp_path / "nok.nc")
    with pytest.raises(sens.StudyFileError, match=r"nok.nc: missing variable k_db\('member', 'class', 'band', "
                                                   r"'range'\)"):
        sens.open_study(tmp_path / "nok.nc")


@pytest.mark.bellhop
def test_zero_sd_study_reproduces_the_nominal_area(tiny_area):
    ds = sens.run_study(tiny_area, specs("bottom-speed:sd_mps=0", "observer-depth:sd_m=0"), members=2,
                        workers=1)
    assert_allclose(ds["k_db"] - ds["k_nominal_db"], 0.0, atol=1e-9)
    # a zero displacement resamples the (piecewise-linear) profile more finely: BELLHOP's ray steps
    # stop at each profile node, which moves K by a few hundredths of a dB
    resampled = sens.run_study(tiny_area, specs("displace:sd_m=0"), members=1, workers=1)
    assert_allclose(resampled["k_db"] - resampled["k_nominal_db"], 0.0, atol=0.15)
    summary = sens.summarize(ds, eval_ranges_m=(1000.0, 3000.0))
    assert_allclose(summary["range_error_m"], 0.0)
    assert np.all(summary["k_error_sd_db"] < 0.01)


@pytest.mark.bellhop
def test_resume_reuses_finished_members_and_gives_the_same_numbers(tiny_area, tiny_study, tmp_path):
    ds, _ = tiny_study
    cache = tmp_path / "cache"
    first = sens.StudyStats()
    sens.run_study(tiny_area, specs(*TINY_SPECS), members=2, seed=11, workers=1, cache_dir=cache, stats=first)
    assert sorted(p.name for p in cache.iterdir()) == ["member-000000.npz", "member-000001.npz", "nominal.npz"]
    (cache / "member-000001.npz").write_bytes(b"damaged")  # a damaged entry is recomputed
    again = sens.StudyStats()
    seen = []
    resumed = sens.run_study(tiny_area, specs(*TINY_SPECS), members=4, seed=11, workers=1, cache_dir=cache,
                             stats=again, on_result=lambda r: seen.append(r.member))
    assert again.members_reused == 1 and sorted(seen) == [1, 2, 3]
    xr.testing.assert_equal(resumed.drop_attrs(), ds.drop_attrs())


@pytest.mark.bellhop
@pytest.mark.slow
def test_tl_study_keeps_tl_on_the_nominal_depths(tiny_area, tmp_path):
    from acoustics.sensitivity_plot import plot_sd_map

    ds = sens.run_study(tiny_area, specs("water-depth:sd_m=20", "bottom-speed:sd_mps=20"), members=3,
                        seed=5, tl=True, workers=2)
    assert ds["tl_db"].dims == ("member", "class", "band", "depth", "range")
    assert_allclose(ds["depth"], tiny_area.depth_m())
    shallower = 0
    for m in range(3):
        depth = float(ds["water_depth_m"][m])
        below = ds["depth"].values > depth + 1e-9
        if below.any():
            shallower += 1
            assert np.all(np.isnan(ds["tl_db"].values[m][:, :, below]))
        assert not np.any(np.isnan(ds["tl_db"].values[m][:, :, ~below]))
    assert shallower == 1  # seed 5 draws water depths 984, 1009 and 1039 m
    # K from the grid is direct for every class; TL at the observer row gives it back
    assert ds.attrs["k_method"].startswith("grid build")
    png = plot_sd_map(ds, tmp_path / "map.png")
    assert png.stat().st_size > 10_000


def synthetic_study(offsets_db, ramp_db=None, n_range=400):
    """A study whose members are the nominal K(r) = -20 lg r - 60 (eq. 13 with A = 1, beta = 0)
    plus a constant offset per member (and optionally a zero-mean ramp)."""
    r = 100.0 * np.arange(1, n_range + 1)
    nominal = -20 * np.log10(r / 1000.0) - 60.0
    k_nom = np.broadcast_to(nominal, (1, 2, n_range)).copy()
    offsets = np.asarray(offsets_db, dtype=float)
    k = k_nom[None] + offsets[:, None, None, None]
    if ramp_db is not None:
        ramp = np.linspace(-1.0, 1.0, n_range)
        k = k + np.asarray(ramp_db)[:, None, None, None] * ramp
    return xr.Dataset({"k_db": (("member", "class", "band", "range"), k),
                       "k_nominal_db": (("class", "band", "range"), k_nom)},
                      coords={"member": np.arange(offsets.size), "class": ["C"], "band": ["B1", "B2"],
                              "range": r, "bottom_speed_mps": ("member", 1600.0 + 10.0 * offsets)})


def test_constant_offsets_are_recognised_as_constant():
    offsets = np.array([-2.0, -1.0, 0.5, 1.0, 1.5])
    summary = sens.summarize(synthetic_study(offsets), eval_ranges_m=(5000.0, 20000.0))
    assert_allclose(summary["k_constant_fraction"], 1.0)
    assert_allclose(summary["k_residual_rms_db"], 0.0, atol=1e-12)
    assert_allclose(summary["k_offset_sd_db"], offsets.std(ddof=1))
    assert_allclose(summary["k_sd_db"], offsets.std(ddof=1))
    assert_allclose(summary["k_bias_db"], offsets.mean(), atol=1e-12)
    assert_allclose(summary["k_error_sd_db"], np.sqrt(np.mean(offsets ** 2)))
    assert list(summary["parameter"].values) == ["bottom_speed_mps"]
    assert_allclose(summary["k_offset_correlation"], 1.0)  # the offsets were made as 0.1 dB per m/s
    # eq. 20 with K = -20 lg r: a level dK dB too high reads as a range 10^(-dK/20) times the truth
    for i, r0 in enumerate((5000.0, 20000.0)):
        expect = r0 * 10 ** (-offsets / 20.0)
        assert_allclose(summary["range_error_m"].values[:, 0, i] + r0, expect, atol=50.0)  # 100 m grid


def test_zero_mean_ramps_are_recognised_as_range_varying():
    summary = sens.summarize(synthetic_study(np.zeros(4), ramp_db=[-3.0, -1.0, 1.0, 3.0]))
    assert_allclose(summary["k_constant_fraction"], 0.0, atol=1e-12)
    assert_allclose(summary["k_offset_sd_db"], 0.0, atol=1e-12)
    assert float(summary["k_residual_rms_db"][0, 0]) > 1.0


def test_summary_window_must_hold_ranges():
    with pytest.raises(InputError, match=r"range window \[50000, 60000\] m contains no range of the study"):
        sens.summarize(synthetic_study([1.0, 2.0], n_range=100), range_min_m=50000.0, range_max_m=60000.0)


def test_level_ranging_eq20_weights_bands_by_their_sd():
    r = 100.0 * np.arange(1, 101)
    table = np.stack([-20 * np.log10(r), -30 * np.log10(r)])
    levels = np.array([-20 * np.log10(4000.0), -30 * np.log10(6000.0)])  # the two bands disagree
    assert sens.level_range_m(levels, table, r, sigma_db=np.array([0.1, 10.0])) == pytest.approx(4000.0)
    assert sens.level_range_m(levels, table, r, sigma_db=np.array([10.0, 0.1])) == pytest.approx(6000.0)


def test_write_k_error_keeps_the_file_and_replaces_the_values(tmp_path):
    out = sens.write_k_error(DATA / "tiny-munk.toml", {"SUB": 3.14159, "SHIP": 0.5}, tmp_path / "a.toml")
    area = envdata.load_area(out)
    assert {c.name: c.k_error_sd_db for c in area.classes} == {"SUB": 3.14, "SHIP": 0.5}
    text = out.read_text()
    assert "# A tiny Munk area for tests" in text and text.count("k_error_sd_db") == 2
    # a class without the key gets it
    src = tmp_path / "nokey.toml"
    src.write_text((DATA / "tiny-munk.toml").read_text().replace("k_error_sd_db = 1.5\n", ""))
    area = envdata.load_area(sens.write_k_error(src, {"SHIP": 0.75}, tmp_path / "b.toml"))
    assert area.target_class("SHIP").k_error_sd_db == 0.75 and area.target_class("SUB").k_error_sd_db == 2.0
    with pytest.raises(InputError, match=r"tiny-munk.toml: no \[\[classes\]\] entry named 'NOPE'"):
        sens.write_k_error(DATA / "tiny-munk.toml", {"NOPE": 1.0}, tmp_path / "c.toml")
    assert not (tmp_path / "c.toml").exists()


def test_study_spec_rejects_bad_sizes_and_unphysical_specs(tiny_area):
    with pytest.raises(InputError, match=r"--members: must be in \[1, 100000\], got 0"):
        sens.StudySpec(area=tiny_area, perturbations=(), members=0)
    with pytest.raises(InputError, match=r"--seed: must be in \[0, 2\^63\), got -1"):
        sens.StudySpec(area=tiny_area, perturbations=(), members=1, seed=-1)
    with pytest.raises(pt.PerturbationError, match=r"non-monotonic in depth"):
        sens.run_study(tiny_area, specs("displace:sd_m=100"), members=1)
