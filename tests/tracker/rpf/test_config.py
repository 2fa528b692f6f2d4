"""Settings of the particle filter (RpfConfig)."""

from __future__ import annotations

import pytest

from tracker.rpf.config import RpfConfig


def test_config_rejects_bad_values():
    with pytest.raises(ValueError, match="n_particles"):
        RpfConfig(n_particles=1)
    with pytest.raises(ValueError, match="level_sigma_db"):
        RpfConfig(level_sigma_db=0.0)
    with pytest.raises(ValueError, match="sigma_a_mix_mps2"):
        RpfConfig(sigma_a_mix_mps2=(1e-4, -1e-3))
    with pytest.raises(ValueError, match="sigma_a_mix_mps2"):
        RpfConfig(n_particles=2, sigma_a_mix_mps2=(1e-4, 3e-4, 1e-3))


def test_config_holds_the_mixture_as_floats():
    assert RpfConfig(sigma_a_mix_mps2=[1e-4, 3e-4]).sigma_a_mix_mps2 == (1e-4, 3e-4)
