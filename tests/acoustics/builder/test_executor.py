"""The executor: the resume cache, tasks on threads and on a real Dask cluster on loopback, errors."""

from __future__ import annotations

import dataclasses
import functools
import re
import time
from pathlib import Path

import numpy as np
import pytest

from acoustics.builder.executor import ResultCache, TaskStats, run_tasks
from acoustics.builder.plan import plan_runs
from acoustics.builder.runs import Run, execute_run
from acoustics.errors import BellhopError
from envdata.areafile import load_area
from envdata.errors import InputError
from tests.conftest import MALFORMED


@pytest.fixture
def broken_run(tiny_area) -> Run:
    """A run of the tiny area that BELLHOP refuses (no such run type): its own message comes back."""
    run = plan_runs(tiny_area)[0]
    assert "'IG" in run.env
    return dataclasses.replace(run, env=re.sub(r"'IG\*?'", "'XG'", run.env))


def test_cache_stores_arrays_as_npy_and_records_as_npz(tmp_path, rng):
    cache = ResultCache(tmp_path / "c")
    assert cache.load("a") is None and not (tmp_path / "c").exists()  # made by the first save
    field = (rng.normal(size=(3, 4)) + 1j * rng.normal(size=(3, 4))).astype(np.complex64)
    assert cache.save("a", field).name == "a.npy"
    record = {"k_db": rng.normal(size=5), "params": {"bottom_speed_mps": 1612.5}, "member": None, "n": 3}
    assert cache.save("b", record).name == "b.npz"
    back = cache.load("a")
    assert back.dtype == np.complex64
    np.testing.assert_array_equal(back, field)
    rec = cache.load("b")
    assert rec["params"] == {"bottom_speed_mps": 1612.5} and rec["member"] is None and rec["n"] == 3
    np.testing.assert_array_equal(rec["k_db"], record["k_db"])
    assert sorted(p.name for p in (tmp_path / "c").iterdir()) == ["a.npy", "b.npz"]  # no temporary left


def test_damaged_entries_are_deleted_and_count_as_missing(tmp_path):
    cache = ResultCache(tmp_path)
    (tmp_path / "a.npy").write_bytes(b"damaged")
    (tmp_path / "b.npz").write_bytes(b"PK\x03\x04 truncated zip")
    assert cache.load("a") is None and cache.load("b") is None
    assert list(tmp_path.iterdir()) == []


def test_cache_codec_stores_what_encode_gives(tmp_path):
    cache = ResultCache(tmp_path, encode=lambda pair: pair[0], decode=lambda array: (array, "from disk"))
    cache.save("x", (np.arange(4), "computed"))
    array, origin = cache.load("x")
    np.testing.assert_array_equal(array, np.arange(4))
    assert origin == "from disk"


def test_reused_results_come_first_and_only_the_rest_runs(tmp_path):
    cache = ResultCache(tmp_path)
    cache.save("7", np.array(7))
    cache.save("11", np.array(-1))  # a reused result is taken as it is, not recomputed
    stats = TaskStats()
    done = list(run_tasks(lambda text: np.array(int(text)), ["3", "7", "5", "11", "3"], key=str, workers=2,
                          cache=cache, stats=stats))
    assert [(d.item, int(d.result), d.reused) for d in done[:2]] == [("7", 7, True), ("11", -1, True)]
    assert sorted((d.item, int(d.result), d.reused) for d in done[2:]) == [("3", 3, False), ("5", 5, False)]
    assert (stats.total, stats.reused, stats.workers) == (4, 2, 2)  # "3" twice is one task
    assert sorted(p.name for p in tmp_path.iterdir()) == ["11.npy", "3.npy", "5.npy", "7.npy"]


def test_one_worker_finishes_tasks_in_the_order_given():
    done = run_tasks(int, ["30", "10", "20", "5"], key=str, workers=1)
    assert [d.result for d in done] == [30, 10, 20, 5]


def _touch_after(item: tuple[str, float]) -> str:
    """A task with a visible effect: sleep, then create the file ``item[0]``."""
    path, seconds = item
    time.sleep(seconds)
    Path(path).touch()
    return path


def test_tasks_not_yet_started_are_cancelled_when_the_caller_stops(tmp_path):
    items = [(str(tmp_path / "a"), 0.0), (str(tmp_path / "b"), 2.0), (str(tmp_path / "c"), 0.0)]
    tasks = run_tasks(_touch_after, items, key=lambda item: Path(item[0]).name, workers=1)
    first = next(tasks)
    assert first.result.endswith("a")  # b has started or is next; c waits behind b's 2 s
    tasks.close()  # waits for b if it started, cancels what waits
    done = sorted(p.name for p in tmp_path.iterdir())
    assert done in (["a"], ["a", "b"])


def test_workers_must_be_positive():
    with pytest.raises(InputError, match=r"workers: must be >= 1, got 0"):
        list(run_tasks(int, ["1"], key=str, workers=0))


@pytest.mark.bellhop
def test_a_bellhop_failure_on_a_thread_reaches_the_caller_as_itself(tmp_path, broken_run):
    with pytest.raises(BellhopError, match=r"BELLHOP failed \(exit 1\): READIN: Unknown RunType selected") as info:
        list(run_tasks(execute_run, [broken_run], key=lambda run: run.key, workers=2,
                       cache=ResultCache(tmp_path / "c")))
    assert info.value.prt_text and info.value.command[-1] == "tmakit"
    assert not (tmp_path / "c").exists()  # nothing finished, nothing saved


def test_an_input_error_on_a_thread_reaches_the_caller_as_itself():
    path = MALFORMED / "area" / "negative-depth.toml"
    with pytest.raises(InputError, match=r"negative-depth.toml: "):
        list(run_tasks(load_area, [path], key=lambda p: p.stem, workers=2))


@pytest.fixture(scope="module")
def scheduler():
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as cluster:
        yield cluster.scheduler_address


@pytest.mark.bellhop
@pytest.mark.slow
def test_dask_results_equal_the_thread_results(tiny_area, scheduler, tmp_path):
    runs = plan_runs(tiny_area)
    task = functools.partial(execute_run, exe=None)
    local = {d.item.key: d.result[0] for d in run_tasks(task, runs, key=lambda run: run.key, workers=2)}
    stats = TaskStats()
    cache = ResultCache(tmp_path, encode=lambda out: out[0], decode=lambda field: (field, 0.0))
    remote = {d.item.key: d.result for d in run_tasks(task, runs, key=lambda run: run.key, scheduler=scheduler,
                                                      cache=cache, stats=stats)}
    assert scheduler.startswith("tcp://127.0.0.1:") and stats.workers == 2 and stats.total == len(runs)
    for key, field in local.items():
        np.testing.assert_array_equal(remote[key][0], field)
        assert remote[key][1] > 0  # BELLHOP's own time, measured on the worker
        np.testing.assert_array_equal(np.load(tmp_path / f"{key}.npy"), field)


@pytest.mark.bellhop
@pytest.mark.slow
def test_errors_on_the_cluster_keep_their_type_or_become_bellhop_errors(scheduler, broken_run):
    with pytest.raises(BellhopError, match=r"BELLHOP failed \(exit 1\): READIN: Unknown RunType selected") as info:
        list(run_tasks(execute_run, [broken_run], key=lambda run: run.key, scheduler=scheduler))
    assert "*** FATAL ERROR ***" in info.value.prt_text  # BELLHOP's print file travelled back
    with pytest.raises(InputError, match=r"negative-depth.toml: "):
        list(run_tasks(load_area, [MALFORMED / "area" / "negative-depth.toml"], key=lambda p: p.stem,
                       scheduler=scheduler))
    with pytest.raises(BellhopError, match=r"^parse: x failed on the Dask cluster: ValueError: invalid literal"):
        list(run_tasks(int, ["1", "x"], key=str, scheduler=scheduler, desc="parse"))
