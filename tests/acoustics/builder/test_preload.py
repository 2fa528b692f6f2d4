"""The dataset's imports done on a thread beside the runs (``acoustics.builder.preload``)."""

import subprocess
import sys

SCRIPT = """
import sys
from acoustics.builder import preload
from acoustics.builder.runs import iter_runs
import acoustics.builder.gridfile, tools.grids_cmd  # what ``tmakit grids build`` imports to plan
before = "xarray" in sys.modules or "dask.array" in sys.modules
list(iter_runs([]))  # no runs: it starts the imports and waits for them
print(before, "xarray" in sys.modules and "dask.array" in sys.modules,
      preload._thread is not None and not preload._thread.is_alive())
"""


def test_iter_runs_leaves_the_dataset_imports_done():
    # a fresh interpreter: this one may have imported dask already
    out = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.split() == ["False", "True", "True"], out.stdout + out.stderr
