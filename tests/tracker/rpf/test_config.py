"""Settings of the particle filter (RpfConfig)."""

from __future__ import annotations

import pytest

from tracker.rpf.config import RpfConfig


def test_config_rejects_bad_values():
    with pytest.raises(ValueError, match="n_particles"):
        RpfConfig(n_particles=1)
    with pytest.raises(ValueError, match="level_sigma_db"):
        RpfConfig(level_sigma_db=0.0)
