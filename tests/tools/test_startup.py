"""The command line starts without the scientific stack: ``tmakit --help`` and ``tmakit COMMAND
--help`` import neither numpy nor xarray, pandas or matplotlib (each command imports what it needs
when it runs), and the package ``__init__``s re-export lazily (``envdata.lazyexports``).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("numpy", "xarray", "pandas", "matplotlib", "numba", "scipy", "pyproj", "dask", "zarr", "netCDF4")


def _heavy_after(code: str) -> list[str]:
    """The heavy modules a fresh interpreter holds after running ``code``."""
    probe = f"{code}\nimport json, sys\nprint(json.dumps(sorted(m for m in {HEAVY!r} if m in sys.modules)))"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_the_parser_of_every_command_is_built_without_the_heavy_stack():
    # what `tmakit --help` and `tmakit COMMAND --help` run before printing
    assert _heavy_after("from tools.cli import build_parser\nbuild_parser()") == []


@pytest.mark.parametrize("module", ["envdata.errors", "acoustics.errors", "acoustics.ram.errors", "tracker.errors",
                                    "tracker.methods", "tracker.locate.choices", "acoustics.plots.what"])
def test_a_small_module_does_not_bring_its_package_re_exports(module):
    assert _heavy_after(f"import {module}") == []


def test_a_lazy_re_export_is_the_module_s_own_object():
    import envdata
    from envdata.area import Area

    assert envdata.Area is Area
    assert "Area" in dir(envdata) and "Area" in envdata.__all__
    with pytest.raises(AttributeError, match="has no attribute 'NoSuchName'"):
        envdata.NoSuchName  # noqa: B018


def test_the_help_quotes_the_library_s_choices_and_defaults():
    # the parser states these without importing the modules that define them
    import acoustics
    from acoustics.builder.plan import RECIPROCITY_MIN_DEPTH_M
    from tools import grids_cmd, sensitivity_cmd

    assert grids_cmd.MODELS == tuple(m.value for m in acoustics.Model)
    assert sensitivity_cmd.RECIPROCITY_MIN_DEPTH_M_SHOWN == RECIPROCITY_MIN_DEPTH_M
