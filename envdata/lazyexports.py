"""A package's re-exports, imported when first asked for (PEP 562's module ``__getattr__``).

A package whose ``__init__`` re-exports names from its modules would otherwise import all of
them (and with them numpy, xarray, pandas, ...) for a caller that needs one small module, such
as ``envdata.errors``; the command line would pay seconds before argparse runs. Written as

    __getattr__, __dir__, __all__ = lazy_exports(__name__, {
        "envdata.area": ["Area", "GridSpec"],
        "envdata.bands": ["Band"],
    })

``from envdata import Area`` then imports ``envdata.area`` at that moment, and ``import envdata``
alone imports nothing. The import-graph test (tests/test_imports.py) reads the table, so the
layering it checks sees these arrows as if they were import statements.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping, Sequence


def lazy_exports(package: str, exports: Mapping[str, Sequence[str]]
                 ) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """The module ``__getattr__``, ``__dir__`` and ``__all__`` of a package that re-exports
    ``exports`` (module -> the names it gives), each imported on first use and then kept."""
    home = {name: module for module, names in exports.items() for name in names}

    def __getattr__(name: str) -> object:
        module = home.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)  # found by plain lookup from now on
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(home))

    return __getattr__, __dir__, sorted(home)
