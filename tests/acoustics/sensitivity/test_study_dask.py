"""Sensitivity studies on a real Dask distributed cluster on loopback: 2 worker processes,
results independent of the number of workers, a worker killed mid-study, an unreachable scheduler."""

from __future__ import annotations

import os
import signal
import time

import pytest
import xarray as xr

from acoustics import sensitivity as sens
from acoustics.sensitivity import perturbspec as ps
from envdata.errors import InputError

pytestmark = [pytest.mark.bellhop, pytest.mark.slow]

SPECS = ("displace:sd_m=10", "bottom-speed:sd_mps=30", "bottom-attenuation:sd_db_per_wavelength=0.2",
         "source-depth:sd_frac=0.15")


def specs():
    return [p for text in SPECS for p in ps.parse_spec(text)]


@pytest.fixture(scope="module")
def one_worker_study(tiny_area):
    return sens.run_study(tiny_area, specs(), members=10, seed=3, workers=1)


@pytest.fixture
def cluster():
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as c:
        yield c


def test_two_worker_cluster_gives_the_one_worker_numbers(tiny_area, one_worker_study, cluster):
    stats = sens.StudyStats()
    ds = sens.run_study(tiny_area, specs(), members=10, seed=3, scheduler=cluster.scheduler_address,
                        stats=stats)
    assert stats.workers == 2 and stats.members_total == 10
    assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
    xr.testing.assert_identical(ds.drop_attrs(), one_worker_study.drop_attrs())


def test_a_worker_killed_mid_study_does_not_lose_members(tiny_area, one_worker_study, cluster, tmp_path):
    from distributed import Client

    with Client(cluster.scheduler_address) as client:
        pids = client.run(os.getpid)
    assert len(pids) == 2
    victim = sorted(pids.values())[0]
    done_at_kill = []

    def kill_once(result):
        if not done_at_kill:
            done_at_kill.append(len(list(tmp_path.glob("*.npz"))))
            os.kill(victim, signal.SIGKILL)

    stats = sens.StudyStats()
    ds = sens.run_study(tiny_area, specs(), members=10, seed=3, scheduler=cluster.scheduler_address,
                        cache_dir=tmp_path, stats=stats, on_result=kill_once)
    assert done_at_kill == [1]  # killed after the first of 11 results (nominal + 10 members) came in
    with pytest.raises(ProcessLookupError):
        os.kill(victim, 0)
    assert sorted(p.name for p in tmp_path.glob("member-*.npz")) == [f"member-{m:06d}.npz" for m in range(10)]
    xr.testing.assert_identical(ds.drop_attrs(), one_worker_study.drop_attrs())


def test_unreachable_scheduler_fails_within_seconds(tiny_area, tmp_path):
    start = time.perf_counter()
    with pytest.raises(InputError, match=r"scheduler tcp://127.0.0.1:9: cannot connect to a Dask scheduler"):
        sens.run_study(tiny_area, specs(), members=2, scheduler="tcp://127.0.0.1:9", cache_dir=tmp_path / "c")
    assert time.perf_counter() - start < 10.0  # 5 s connect timeout
    assert not (tmp_path / "c").exists()
