"""numba caches older than the kernel's sources are dropped (the fused loop's cache embeds the
code of every kernel module, which numba does not track)."""

from __future__ import annotations

import os

from tracker.rpf.kernel.cache import KERNEL_DIR, drop_stale_caches


def _touch(path, mtime):
    path.write_text("x")
    os.utime(path, (mtime, mtime))


def test_caches_older_than_a_source_are_dropped_and_fresh_ones_kept(tmp_path):
    src_a, src_b = tmp_path / "loop.py", tmp_path / "likelihood.py"
    cache = tmp_path / "__pycache__"
    cache.mkdir()
    _touch(src_a, 1000.0)
    _touch(src_b, 3000.0)  # edited after the loop was compiled
    old = [cache / "loop.run_runs-160.py311.nbi", cache / "loop.run_runs-160.py311.1.nbc"]
    new = [cache / "weights.normalise_run-14.py311.nbi"]
    other = cache / "loop.cpython-311.pyc"  # Python's own bytecode: not numba's to drop
    for f in old:
        _touch(f, 2000.0)
    _touch(new[0], 4000.0)
    _touch(other, 2000.0)
    dropped = drop_stale_caches(cache, [src_a, src_b])
    assert sorted(dropped) == sorted(old)
    assert not any(f.exists() for f in old)
    assert new[0].exists() and other.exists()
    assert drop_stale_caches(cache, [src_a, src_b]) == []  # what is left is fresh


def test_no_cache_directory_is_nothing_to_drop(tmp_path):
    assert drop_stale_caches(tmp_path / "__pycache__", [KERNEL_DIR / "loop.py"]) == []


def test_the_kernel_sources_are_the_default(tmp_path):
    # against every module of the kernel package: a cache from before the newest is dropped
    newest = max(p.stat().st_mtime for p in KERNEL_DIR.glob("*.py"))
    cache = tmp_path / "__pycache__"
    cache.mkdir()
    _touch(cache / "loop.run_runs-160.py311.nbi", newest - 1.0)
    _touch(cache / "loop.run_one-45.py311.nbi", newest + 1.0)
    assert [f.name for f in drop_stale_caches(cache)] == ["loop.run_runs-160.py311.nbi"]
