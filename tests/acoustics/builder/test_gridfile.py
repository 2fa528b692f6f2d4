"""Grid files built once: reuse when current, resume from the runs kept beside the output."""

from __future__ import annotations

import pytest
import xarray as xr

import acoustics
from acoustics.builder.gridfile import build_grid_file, resume_dir
from acoustics.builder.plan import plan_runs, receiver_depths_m
from acoustics.builder.runs import iter_runs


def test_urick_file_is_built_then_reused(tiny_area, tmp_path):
    out = tmp_path / "u.nc"
    built = build_grid_file(tiny_area, out, model="urick")
    assert built.up_to_date is False and built.runs == 0 and built.model == "urick"
    assert built.source_hash == acoustics.expected_source_hash(tiny_area, "urick")
    again = build_grid_file(tiny_area, out, model="urick")
    assert again.up_to_date is True and again.file == out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["u.nc"]


@pytest.mark.bellhop
def test_a_build_resumes_from_the_runs_beside_the_output(tiny_area, tiny_area_path, tiny_grid, tmp_path):
    out = tmp_path / "g.nc"
    cache = resume_dir(out, acoustics.expected_source_hash(tiny_area))
    assert cache.parent == tmp_path and cache.name.startswith(".g.nc.partial-")
    runs = plan_runs(tiny_area, receiver_depths=receiver_depths_m(tiny_area))
    for _ in iter_runs(runs[:3], cache_dir=cache):  # as if a build had been stopped after three runs
        pass
    assert len(list(cache.glob("*.npy"))) == 3
    info = build_grid_file(tiny_area_path, out, workers=2)  # an area file path works as well
    assert info.runs == 4 and info.runs_reused == 3 and not cache.exists()
    xr.testing.assert_identical(acoustics.open_tables(out).dataset.drop_attrs(), tiny_grid.drop_attrs())
