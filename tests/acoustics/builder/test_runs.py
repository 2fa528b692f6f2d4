"""A grid's BELLHOP runs on the executor: longest first, the same fields on any number of workers."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from acoustics.builder.plan import plan_runs
from acoustics.builder.runs import RunStats, iter_runs

pytestmark = pytest.mark.bellhop


def test_runs_start_longest_first_so_the_half_fans_come_last(tiny_area):
    # three class depths x one band: an odd count, so the last run is cut into two half fans
    third = dataclasses.replace(tiny_area.classes[0], name="MID", depth_m=60.0)
    area = dataclasses.replace(tiny_area, classes=tiny_area.classes + (third,), bands=tiny_area.bands[1:])
    runs = plan_runs(area)
    assert sorted(run.n_beams for run in runs) == [150, 150, 300, 300]
    halves_first = sorted(runs, key=lambda run: run.n_beams)
    order = [run.n_beams for run, _ in iter_runs(halves_first, workers=1)]  # one worker: finish order = start order
    assert order == [300, 300, 150, 150]


def test_one_and_two_workers_give_the_same_fields_and_the_cache_the_same_again(tiny_area, tmp_path):
    runs = plan_runs(tiny_area)
    one = dict((run.key, field) for run, field in iter_runs(runs, workers=1))
    stats = RunStats()
    two = dict((run.key, field) for run, field in iter_runs(runs, workers=2, cache_dir=tmp_path, stats=stats))
    assert stats.runs_total == 4 and stats.runs_reused == 0 and stats.bellhop_seconds > 0
    again = RunStats()
    cached = dict((run.key, field) for run, field in iter_runs(runs, workers=2, cache_dir=tmp_path, stats=again))
    assert again.runs_reused == 4 and again.bellhop_seconds == 0.0
    for key, field in one.items():
        np.testing.assert_array_equal(two[key], field)
        np.testing.assert_array_equal(cached[key], field)
