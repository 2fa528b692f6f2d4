"""The depth study's settings (`tools.studies.depth`), shared with its summary
(`tools.studies.depth_summary`)."""

from __future__ import annotations

AREA = "shelf-break"
#: The scenario the command names; the study runs `SCENARIOS`.
SCENARIO = "shelf-nps"
SCENARIOS = ("shelf-nps", "shelf-slope-nps")
TRUE_DEPTHS_M = (6.0, 20.0, 40.0, 60.0, 100.0, 200.0)
#: The span a submarine's depth is searched over, m (the depth_range_m a class would give).
DEPTH_SPAN_M = (2.0, 300.0)
VARIANTS = ("class", "true", "unknown")
METHODS = ("rpf", "ml")
#: Each method's ways of meeting the unknown depth besides the class's and the true one: a bank
#: of particle filters at the ML analysis's depth hypotheses weighed by the depth posterior
#: along each one's track; the ML analysis over its hypotheses.
UNKNOWN = {"rpf": ("bank",), "ml": ("unknown",)}
#: How each method weighing depth hypotheses picks the track it reports each cycle
#: (`tracker.depth.bank.TRACK_RULES`, as `tmakit track` does); the other rule's figures are
#: kept as variant ``<variant>_by_<rule>`` (the ML analysis by the bearings, the bank by the
#: weight alone).
TRACK_RULE = {"rpf": "bearings", "ml": "weight"}
#: The rows of the depth posterior along the true track (the motion known): what the levels
#: themselves say of the depth, whatever a tracker makes of the motion.
KNOWN = "known_motion"
#: The position error is taken from this many minutes after the first cycle.
LATE_MIN = 5.0
#: The stated range sds are checked from this many minutes after the first cycle.
CALIBRATION_MIN = 10.0
#: Targets of the issue: the 90 % interval covers the truth in this share of runs; the particle
#: filter with the depth unknown within this factor of the filter given the true depth.
TARGET_COVERAGE = 0.85
TARGET_RATIO = 1.1
