"""What a grid figure shows (``tmakit grids plot --what``); a module of its own so that the
command line lists the choices without importing the figures."""

from __future__ import annotations

from enum import StrEnum


class What(StrEnum):
    """What to draw: a bearing-dependent grid's map of K(r) in one band or of the detection range
    per band, the probability of detection in one band or any band (a map, or P_D against range
    on a grid without bearings: ``acoustics.plots.pdplot``), or K against target depth and range
    on one bearing (any grid that holds TL from the observer: ``acoustics.plots.depthplot``)."""

    K = "k"
    DETECTION = "detection"
    PD = "pd"
    DEPTH = "depth"
