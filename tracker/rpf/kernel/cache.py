"""Keeps numba's on-disk cache of the kernel consistent with the kernel's sources.

numba (``cache=True``) keys each cached function on the time stamp and size of its own file
only, but a compiled function carries the code of every function it calls: the fused loop of
`tracker.rpf.kernel.loop` embeds the pieces of the other kernel modules. After an edit of
``likelihood.py``, say, numba would still load the old loop from ``loop.py``'s cache. While
the kernel was one file, any edit invalidated every cache; now that it is several,
`drop_stale_caches` restores that: a cache file older than the newest kernel source is
deleted, so the next call compiles afresh (15-17 s once). Importing `tracker.rpf.kernel` runs
it on the kernel's own ``__pycache__`` (where numba caches when the package directory is
writable, as in a checkout; an installed copy is not edited).
"""

from __future__ import annotations

from pathlib import Path

KERNEL_DIR = Path(__file__).resolve().parent


def drop_stale_caches(cache_dir: Path | str = KERNEL_DIR / "__pycache__",
                      sources: list[Path] | None = None) -> list[Path]:
    """Delete numba cache files (``*.nbi``, ``*.nbc``) older than the newest of ``sources``.

    Parameters
    ----------
    cache_dir : path, optional
        The ``__pycache__`` holding the cache files; default the kernel's own.
    sources : list of paths, optional
        The sources the cached code depends on; default every ``*.py`` of the kernel package.

    Returns
    -------
    list of Path
        The files deleted (none when the directory does not exist or the caches are fresh).
    """
    cache_dir = Path(cache_dir)
    if not cache_dir.is_dir():
        return []
    sources = sorted(KERNEL_DIR.glob("*.py")) if sources is None else sources
    newest = max(Path(p).stat().st_mtime for p in sources)
    dropped = []
    for f in sorted(cache_dir.glob("*.nb[ic]")):
        try:
            if f.stat().st_mtime < newest:
                f.unlink()
                dropped.append(f)
        except FileNotFoundError:  # another process dropped it first
            pass
    return dropped


drop_stale_caches()
