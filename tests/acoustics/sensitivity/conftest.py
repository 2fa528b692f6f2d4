"""Shared by the sensitivity tests: perturbation specs from text and a small study of the tiny area."""

from __future__ import annotations

import pytest

from acoustics import sensitivity as sens
from acoustics.sensitivity import perturbspec as ps

TINY_SPECS = ("displace:sd_m=10", "temperature:sd_c=0.3,scale_m=300", "bottom-speed:sd_mps=30",
              "source-depth:sd_frac=0.15", "observer-depth:sd_m=2")


def specs(*texts):
    return [p for text in texts for p in ps.parse_spec(text)]


@pytest.fixture(scope="session")
def tiny_study(tiny_area):
    """Four members of the tiny area (seed 11) on 2 local threads, and the study's stats."""
    stats = sens.StudyStats()
    ds = sens.run_study(tiny_area, specs(*TINY_SPECS), members=4, seed=11, workers=2, stats=stats)
    return ds, stats
