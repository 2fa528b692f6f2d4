"""The modules a build's last step needs, imported on a thread while its BELLHOP runs go.

The dataset and its netCDF need xarray (with pandas, 0.5 s to import), and xarray imports
dask.array (and with it scipy.sparse) the first time it makes a variable, to know a dask array
when it meets one: together most of a flat grid's fixed cost on this machine, paid before the
first run or after the last (docs/results/build-profile.json). The build command's modules leave
them out of their imports (``import xarray`` for annotations only, the dataset's module where it
is called), ``iter_runs`` starts them here beside its first runs, where on one worker the second
core is idle, and waits for them after its last, so that the dataset's step finds them done.
"""

from __future__ import annotations

import importlib
import logging
import sys
import threading

log = logging.getLogger(__name__)

#: What the dataset's step imports first.
MODULES = ("xarray", "dask.array", "netCDF4", "xarray.backends.netCDF4_")

_lock = threading.Lock()
_thread: threading.Thread | None = None


def start() -> None:
    """Import `MODULES` on a daemon thread, once a process (nothing if they are imported)."""
    global _thread
    with _lock:
        if _thread is None and not all(name in sys.modules for name in MODULES):
            _thread = threading.Thread(target=_load, name="tmakit-preload", daemon=True)
            _thread.start()


def wait() -> None:
    """Return once the imports `start` began are over."""
    thread = _thread
    if thread is not None:
        thread.join()


def _load() -> None:
    for name in MODULES:
        try:
            importlib.import_module(name)
        except Exception as exc:  # noqa: BLE001 - whoever needs it imports it again and says why
            log.debug("preloading %s failed: %s", name, exc)
