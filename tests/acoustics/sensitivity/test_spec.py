"""The study spec: sizes and perturbations are checked before anything runs."""

from __future__ import annotations

import pytest

from acoustics import sensitivity as sens
from acoustics.sensitivity import perturbspec as ps
from envdata.errors import InputError
from tests.acoustics.sensitivity.conftest import specs


def test_study_spec_rejects_bad_sizes_and_unphysical_specs(tiny_area):
    with pytest.raises(InputError, match=r"members: must be in \[1, 100000\], got 0"):
        sens.StudySpec(area=tiny_area, perturbations=(), members=0)
    with pytest.raises(InputError, match=r"seed: must be in \[0, 2\^63\), got -1"):
        sens.StudySpec(area=tiny_area, perturbations=(), members=1, seed=-1)
    with pytest.raises(ps.PerturbationError, match=r"non-monotonic in depth"):
        sens.run_study(tiny_area, specs("displace:sd_m=2000"), members=1)
