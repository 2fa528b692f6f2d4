"""RAM's numerical settings: range and depth steps, Pade terms, stability terms, grid depth.

The default rule (`RamSettings.for_frequency`) comes from the convergence study
``python -m tests.crosscheck.ram_convergence`` (docs/results/ram-convergence.json,
docs/models-ram.md); see `for_frequency` for the rule and what was measured.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from acoustics.ram.errors import RamInputError

#: Wavelength used by the default rule, m/s: lambda = REFERENCE_SPEED_MPS / f.
REFERENCE_SPEED_MPS = 1500.0
#: Default depth step, wavelengths (dz = lambda / 20).
DEPTH_STEP_WAVELENGTHS = 1.0 / 20.0
#: Default range step, wavelengths (dr = lambda / 2).
RANGE_STEP_WAVELENGTHS = 0.5
#: Default number of Pade terms.
PADE_TERMS = 8
#: Default number of stability constraints (RAM's ns).
STABILITY_TERMS = 1
#: Default absorbing layer under the deepest bottom, wavelengths.
ABSORBING_LAYER_WAVELENGTHS = 20.0


@dataclass(frozen=True, slots=True, kw_only=True)
class RamSettings:
    """How RAM discretises one run.

    Attributes
    ----------
    range_step_m : float
        Marching step dr, m (> 0). ``acoustics.ram.run.ram_tl_db`` may shorten it so that its
        output falls exactly on the requested ranges (never lengthens it).
    depth_step_m : float
        Depth step dz of the finite-element grid, m (> 0).
    pade_terms : int
        Terms of the split-step Pade approximation (RAM's np), 1-10.
    stability_terms : int
        Stability constraints on the Pade coefficients (RAM's ns), 0, 1 or 2.
    stability_range_m : float or None
        Range beyond which the stability constraints are dropped (RAM's rs), m; None keeps
        them over the whole run.
    grid_depth_m : float
        Bottom of the computational grid, m: the absorbing layer included. Must reach at least
        ``absorbing_layer_m`` below the environment's deepest bottom; between the deepest bottom
        and the layer lies the bottom half-space itself.
    absorbing_layer_m : float
        Thickness of the absorbing layer at the foot of the grid, m (easypyram's ``lyrw``
        wavelengths): the bottom's own attenuation over its upper three quarters, rising to 10
        dB/wavelength at the foot, so that nothing returns from the grid's end.
    reference_speed_mps : float or None
        RAM's reference speed c0, m/s; None: the depth average of the sound speed in the water
        at range 0.
    """

    range_step_m: float
    depth_step_m: float
    grid_depth_m: float
    absorbing_layer_m: float
    pade_terms: int = PADE_TERMS
    stability_terms: int = STABILITY_TERMS
    stability_range_m: float | None = None
    reference_speed_mps: float | None = None

    def __post_init__(self) -> None:
        for name in ("range_step_m", "depth_step_m", "grid_depth_m", "absorbing_layer_m"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise RamInputError(f"RAM settings {name}: must be > 0 m, got {value}")
        if self.absorbing_layer_m >= self.grid_depth_m:
            raise RamInputError(f"RAM settings absorbing_layer_m: {self.absorbing_layer_m} m must be less "
                                f"than grid_depth_m, {self.grid_depth_m} m")
        if self.depth_step_m * 4 > self.grid_depth_m:
            raise RamInputError(f"RAM settings depth_step_m: {self.depth_step_m} m is too coarse for a "
                                f"grid {self.grid_depth_m} m deep")
        if not (isinstance(self.pade_terms, int) and 1 <= self.pade_terms <= 10):
            raise RamInputError(f"RAM settings pade_terms: must be an integer in [1, 10], got {self.pade_terms}")
        if self.stability_terms not in (0, 1, 2):
            raise RamInputError(f"RAM settings stability_terms: must be 0, 1 or 2, got {self.stability_terms}")
        if self.stability_range_m is not None and not (math.isfinite(self.stability_range_m)
                                                       and self.stability_range_m >= 0.0):
            raise RamInputError(f"RAM settings stability_range_m: must be >= 0 m or None, "
                                f"got {self.stability_range_m}")
        if self.reference_speed_mps is not None and not (math.isfinite(self.reference_speed_mps)
                                                         and 1300.0 <= self.reference_speed_mps <= 2000.0):
            raise RamInputError(f"RAM settings reference_speed_mps: must be in [1300, 2000] m/s or None, "
                                f"got {self.reference_speed_mps}")

    @classmethod
    def for_frequency(cls, freq_hz: float, *, max_bottom_depth_m: float) -> RamSettings:
        """The default settings at ``freq_hz`` for an environment whose deepest bottom is given.

        Parameters
        ----------
        freq_hz : float
            Frequency, Hz (> 0).
        max_bottom_depth_m : float
            The environment's deepest bottom, m (``RamEnvironment.max_bottom_depth_m``).

        Returns
        -------
        RamSettings
            With lambda = 1500 m/s / f: dz = lambda / 20, dr = lambda / 2, 8 Pade terms, one
            stability constraint over the whole run, an absorbing layer 20 lambda thick right
            under the deepest bottom.
        """
        if not (math.isfinite(freq_hz) and freq_hz > 0.0):
            raise RamInputError(f"RAM settings: frequency must be > 0 Hz, got {freq_hz}")
        if not (math.isfinite(max_bottom_depth_m) and max_bottom_depth_m > 0.0):
            raise RamInputError(f"RAM settings: max_bottom_depth_m must be > 0 m, got {max_bottom_depth_m}")
        wavelength_m = REFERENCE_SPEED_MPS / freq_hz
        layer_m = ABSORBING_LAYER_WAVELENGTHS * wavelength_m
        return cls(range_step_m=RANGE_STEP_WAVELENGTHS * wavelength_m,
                   depth_step_m=DEPTH_STEP_WAVELENGTHS * wavelength_m,
                   grid_depth_m=max_bottom_depth_m + layer_m, absorbing_layer_m=layer_m)
