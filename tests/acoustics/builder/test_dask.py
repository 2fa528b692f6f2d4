"""BELLHOP runs on a real Dask distributed cluster on loopback."""

from __future__ import annotations

import time

import pytest
import xarray as xr

import acoustics
from envdata.errors import InputError

pytestmark = [pytest.mark.bellhop, pytest.mark.slow]


def test_build_on_a_two_worker_cluster_equals_the_local_build(tiny_area, tiny_grid):
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as cluster:
        stats = acoustics.BuildStats()
        ds = acoustics.build_grid(tiny_area, scheduler=cluster.scheduler_address, stats=stats)
    assert stats.runs_total == 4 and stats.bellhop_seconds > 0
    xr.testing.assert_identical(ds.drop_attrs(), tiny_grid.drop_attrs())


def test_unreachable_scheduler_fails_fast_with_a_clear_error(tiny_area):
    start = time.perf_counter()
    with pytest.raises(InputError, match=r"scheduler tcp://127.0.0.1:9: cannot connect to a Dask scheduler"):
        acoustics.build_grid(tiny_area, scheduler="tcp://127.0.0.1:9")
    assert time.perf_counter() - start < 15.0


def test_cli_with_an_unreachable_scheduler_is_one_error_line(capsys, tiny_area_path, tmp_path):
    from tools.cli import main

    out = tmp_path / "g.nc"
    assert main(["grids", "build", str(tiny_area_path), "--out", str(out), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: scheduler tcp://127.0.0.1:9: cannot connect")
    assert list(tmp_path.iterdir()) == []  # no output and no empty resume folder
