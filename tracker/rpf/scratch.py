"""Scratch arrays reused from cycle to cycle by the numpy engine.

Allocating fresh large arrays every cycle costs a page fault per 4 KiB and was the largest
single cost of the filter step; the engine keeps one dict of scratch arrays per block of runs
and the filter's parts take it as ``work``.
"""

from __future__ import annotations

import numpy as np


def scratch(work: dict | None, name: str, shape, dtype=float) -> np.ndarray:
    """An uninitialised array of ``shape`` from the scratch dict ``work`` (new if None).

    Parameters
    ----------
    work : dict or None
        Scratch arrays keyed by (name, shape, dtype); None: always a new array.
    name : str
        Role of the array; two roles never share memory.
    shape : tuple of int
    dtype : numpy dtype, optional
    """
    if work is None:
        return np.empty(shape, dtype)
    key = (name, tuple(shape), np.dtype(dtype).char)
    a = work.get(key)
    if a is None:
        a = work[key] = np.empty(shape, dtype)
    return a
