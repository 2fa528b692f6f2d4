"""The ensemble: the study dataset, a zero-sd study, resume from finished members, a TL study."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import acoustics
from acoustics import sensitivity as sens
from acoustics.sensitivity import perturb as pt
from tests.acoustics.sensitivity.conftest import TINY_SPECS, specs


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
    nominal = acoustics.build_k(tiny_area).values
    assert_allclose(ds["k_nominal_db"].values, nominal, rtol=0, atol=1e-9)
    assert np.all(np.abs(ds["k_db"] - ds["k_nominal_db"]).max("range") > 0.01)  # every member moved
    assert ds.attrs["seed"] == 11 and ds.attrs["area"] == "tiny-munk"


@pytest.mark.bellhop
def test_zero_sd_study_reproduces_the_nominal_area(tiny_area):
    ds = sens.run_study(tiny_area, specs("bottom-speed:sd_mps=0", "observer-depth:sd_m=0"), members=2,
                        workers=1)
    assert_allclose(ds["k_db"] - ds["k_nominal_db"], 0.0, atol=1e-9)
    # a zero displacement resamples the (piecewise-linear) profile more finely: BELLHOP's ray steps
    # stop at each profile node, which moves K by a few hundredths of a dB
    resampled = sens.run_study(tiny_area, specs("displace:sd_m=0"), members=1, workers=1)
    assert_allclose(resampled["k_db"] - resampled["k_nominal_db"], 0.0, atol=0.15)
    summary = sens.summarize(sens.study_face(ds), eval_ranges_m=(1000.0, 3000.0))
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
    from acoustics.sensitivity.plot import plot_sd_map

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
    png = plot_sd_map(sens.study_face(ds), tmp_path / "map.png")
    assert png.stat().st_size > 10_000
