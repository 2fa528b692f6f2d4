"""The Stone Soup glue is a Stone Soup plugin: the installed tmakit registers ``tracker.stonesoup``
under Stone Soup's ``stonesoup.plugins`` entry-point group, and Stone Soup's own loader makes it
``stonesoup.plugins.tmakit`` (its documented way in for third-party code)."""

from __future__ import annotations

import json
import subprocess
import sys
from importlib.metadata import entry_points

import tracker.stonesoup


def test_the_installed_package_registers_the_plugin():
    # the installed distribution's metadata (pyproject's [project.entry-points."stonesoup.plugins"])
    found = [(e.name, e.value, e.dist.name) for e in entry_points(group="stonesoup.plugins")]
    assert ("tmakit", "tracker.stonesoup", "tmakit") in found


def test_stone_soup_loads_the_plugin_as_a_user_imports_it(tmp_path):
    # a fresh interpreter outside the checkout, as a user's script: Stone Soup's loader imports every
    # entry point of the group when stonesoup.plugins is imported, and warns (here: fails) on one
    # that does not import
    code = ("import json, sys\n"
            "from stonesoup.plugins.tmakit import TablesMeasurementModel\n"
            "import stonesoup.plugins.tmakit as plugin\n"
            "print(json.dumps([plugin.__name__, TablesMeasurementModel.__module__, sorted(plugin.__all__)]))\n")
    done = subprocess.run([sys.executable, "-W", "error::UserWarning", "-c", code], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    name, model_module, names = json.loads(done.stdout.strip().splitlines()[-1])
    assert (name, model_module) == ("tracker.stonesoup", "tracker.stonesoup.model")
    assert names == sorted(tracker.stonesoup.__all__)
    assert {"TablesMeasurementModel", "DetectionProbability", "TablesBernoulliParticleUpdater",
            "detections_from_measurements", "track_frame", "track_from_frame"} <= set(names)
