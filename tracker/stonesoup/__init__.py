"""tmakit's tables inside Stone Soup, as a Stone Soup plugin (``pip install 'tmakit[stonesoup]'``).

Registered under Stone Soup's ``stonesoup.plugins`` entry-point group as ``tmakit``, so that once
installed it is imported the way Stone Soup documents for plugins:

    from stonesoup.plugins.tmakit import TablesMeasurementModel, detections_from_measurements

- ``model``: `TablesMeasurementModel`, a measurement model for bearing and band levels whose level
  function is tmakit's (P0 + K(r) + H from the grid or atlas face);
- ``detection``: `DetectionProbability` from the same tables and the sonar, and
  `TablesBernoulliParticleUpdater`, Stone Soup's Bernoulli particle updater that uses it;
- ``convert``: tmakit's measurement CSV as Stone Soup detections (`detections_from_measurements`,
  `observer_lookup`) and Stone Soup tracks as tmakit's track table and back (`track_frame`,
  `track_from_frame`).

docs/stonesoup.md shows them at work. Nothing else of tmakit imports Stone Soup (the core runs
without the extra); the comparison with tmakit's own filter is a benchmark
(``bench/bench_stonesoup.py``).
"""

from tracker.stonesoup.convert import (
    EPOCH,
    detections_from_measurements,
    observer_lookup,
    timestamp,
    track_frame,
    track_from_frame,
)
from tracker.stonesoup.detection import DetectionProbability, TablesBernoulliParticleUpdater
from tracker.stonesoup.model import TablesMeasurementModel

__all__ = ["EPOCH", "DetectionProbability", "TablesBernoulliParticleUpdater", "TablesMeasurementModel",
           "detections_from_measurements", "observer_lookup", "timestamp", "track_frame", "track_from_frame"]
