"""One member: which BELLHOP runs give K(r), K against the grid build, the member's cache record."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from acoustics.builder.bandruns import BuildStats
from acoustics.builder.executor import ResultCache
from acoustics.builder.kobserver import k_at_observer_db
from acoustics.builder.plan import k_runs
from acoustics.sensitivity.members import MemberResult, member_key


def test_k_runs_use_reciprocity_for_deep_classes_and_direct_for_shallow(tiny_area):
    sources, receivers, where = k_runs(tiny_area)  # SUB 150 m, SHIP 5 m, observer 100 m
    assert sources == [5.0, 100.0] and receivers == [100.0, 150.0]
    assert where == {"SUB": (1, 1), "SHIP": (0, 0)}  # SUB: observer -> 150 m; SHIP: 5 m -> observer
    sources, receivers, where = k_runs(tiny_area, reciprocity_min_depth_m=1e9)
    assert sources == [5.0, 150.0] and receivers == [100.0]


@pytest.mark.bellhop
def test_member_k_matches_the_grid_build(tiny_area, tiny_grid):
    stats = BuildStats()
    direct = k_at_observer_db(tiny_area, reciprocity_min_depth_m=1e9, stats=stats)
    # per frequency a run of the submarine and one of the ship's (its source pattern is its own)
    assert stats.bellhop_seconds > 0 and stats.runs_total == 4
    # same BELLHOP inputs per (source, receiver) pair as the grid build: equal to float32 rounding
    assert_allclose(direct, tiny_grid["k_db"].values, rtol=0, atol=1e-3)
    mixed = k_at_observer_db(tiny_area)
    assert_allclose(mixed[1], tiny_grid["k_db"].values[1], rtol=0, atol=1e-3)  # SHIP: direct
    diff = np.abs(mixed[0] - tiny_grid["k_db"].values[0])  # SUB at 150 m: by reciprocity
    assert np.median(diff) < 0.2  # measured 0.05 dB; incoherent beams are nearly reciprocal at depth


@pytest.mark.parametrize("member, with_tl", [(None, False), (7, True)])
def test_member_record_survives_the_resume_cache(tmp_path, rng, member, with_tl):
    tl = rng.normal(80.0, 10.0, (2, 2, 3, 5)).astype(np.float32) if with_tl else None
    result = MemberResult(member=member, k_db=rng.normal(-70.0, 5.0, (2, 2, 5)),
                          params={"bottom_speed_mps": 1612.25, "displace_dz_m": -3.5},
                          bellhop_seconds=1.25, tl_db=tl)
    cache = ResultCache(tmp_path, encode=MemberResult.to_record, decode=MemberResult.from_record)
    path = cache.save(member_key(member), result)
    assert path.name == ("nominal.npz" if member is None else "member-000007.npz")
    back = cache.load(member_key(member))
    assert back.member == member and back.params == result.params and back.bellhop_seconds == 1.25
    np.testing.assert_array_equal(back.k_db, result.k_db)
    if with_tl:
        assert back.tl_db.dtype == np.float32
        np.testing.assert_array_equal(back.tl_db, tl)
    else:
        assert back.tl_db is None


def test_a_record_that_is_not_a_member_is_deleted_and_recomputed(tmp_path):
    cache = ResultCache(tmp_path, encode=MemberResult.to_record, decode=MemberResult.from_record)
    ResultCache(tmp_path).save("member-000001", {"k_db": np.zeros(3), "params": [1, 2]})
    assert cache.load("member-000001") is None  # unreadable as a member: recomputed
    assert list(tmp_path.iterdir()) == []
