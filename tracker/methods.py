"""Which estimator tracks a target: ``tmakit track --method`` and `tracker.track.track`.

A module of its own (no numpy) so that the command line lists the choices without importing
the trackers.
"""

from __future__ import annotations

from enum import StrEnum


class Method(StrEnum):
    """The trackers: the maximum-likelihood motion analysis of Grinenkov & Mashoshin and the
    regularized particle filters of Iglesis & de Montella."""

    ML = "ml"            # maximum-likelihood motion analysis without observer manoeuvre
    RPF = "rpf"          # particle filter on bearings and SPL (I&dM eq. 31)
    RPF_BOT = "rpf-bot"  # particle filter on bearings only (eq. 32)
    RPF_VP = "rpf-vp"    # bearings and SPL, variance-preserving regularization (not in the paper)

    @property
    def is_particle_filter(self) -> bool:
        return self is not Method.ML
