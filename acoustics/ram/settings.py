"""RAM's numerical settings: range and depth steps, Pade terms, stability terms, grid depth.

The default rule (`RamSettings.for_frequency`, `RamSettings.for_environment`) comes from the
convergence study ``python -m bench.crosscheck.ram_convergence``
(docs/results/ram-convergence.json, docs/models.md); `for_frequency` states the rule and
what was measured.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from acoustics.ram.environment import RamEnvironment
from acoustics.ram.errors import RamInputError

#: Wavelength used by the default rule, m/s: lambda = REFERENCE_SPEED_MPS / f.
REFERENCE_SPEED_MPS = 1500.0
#: Default depth step, wavelengths (dz = lambda / 30).
DEPTH_STEP_WAVELENGTHS = 1.0 / 30.0
#: Default range step where the environment changes with range, wavelengths (dr = lambda / 2).
RANGE_STEP_WAVELENGTHS = 0.5
#: Default range step where it does not, wavelengths (dr = 2 lambda).
RANGE_STEP_FLAT_WAVELENGTHS = 2.0
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
    def for_frequency(cls, freq_hz: float, *, max_bottom_depth_m: float,
                      range_dependent: bool = True) -> RamSettings:
        """The default settings at ``freq_hz`` for an environment whose deepest bottom is given.

        Parameters
        ----------
        freq_hz : float
            Frequency, Hz (> 0).
        max_bottom_depth_m : float
            The environment's deepest bottom, m (``RamEnvironment.max_bottom_depth_m``).
        range_dependent : bool
            Whether the bottom or the sound speed changes with range
            (``RamEnvironment.is_range_dependent``).

        Returns
        -------
        RamSettings
            With lambda = 1500 m/s / f: dz = lambda / 30; dr = lambda / 2 where the environment
            changes with range, 2 lambda where it does not; 8 Pade terms; one stability
            constraint over the whole run; an absorbing layer 20 lambda thick right under the
            deepest bottom.

        Notes
        -----
        Measured (``python -m bench.crosscheck.ram_convergence``, docs/results/
        ram-convergence.json): against dz = lambda/80, dr = lambda/8 on the Pekeris waveguide
        (50-400 Hz, to 10 km), the ASA wedge (25-100 Hz, to 4 km) and the munk-1000 area
        (50-200 Hz, to 20 km), receivers from 500 m on. The depth step is what matters: after a
        running intensity mean over 20 wavelengths of range, dz = lambda/30 changes TL by at
        most 0.30 dB median (0.98 dB 90th percentile) in every case, lambda/20 by up to 0.43
        (1.65) and lambda/10 by up to 1.31 (3.78). Point-wise, lambda/30 stays within 0.36 dB
        median on the wedge and the Munk profile; on the Pekeris waveguide no dz down to
        lambda/40 brings the coherent field 10 km out within 0.5 dB of the reference, because
        RAM puts the flat bottom on its depth grid and a tenth of a metre there moves the
        interference pattern (the range mean removes it). The range step matters only where
        the environment changes with range: without range dependence dr = lambda/4 to
        4 lambda give the same TL within 0.01 dB median; in the wedge lambda/2 is within
        0.14 dB point-wise, 2 lambda 0.24 dB, 4 lambda 0.83 dB. 4 and 6 Pade terms give what
        8 give (2 do not: up to 1.43 dB); a 10-lambda absorbing layer what 20 give.
        """
        if not (math.isfinite(freq_hz) and freq_hz > 0.0):
            raise RamInputError(f"RAM settings: frequency must be > 0 Hz, got {freq_hz}")
        if not (math.isfinite(max_bottom_depth_m) and max_bottom_depth_m > 0.0):
            raise RamInputError(f"RAM settings: max_bottom_depth_m must be > 0 m, got {max_bottom_depth_m}")
        wavelength_m = REFERENCE_SPEED_MPS / freq_hz
        layer_m = ABSORBING_LAYER_WAVELENGTHS * wavelength_m
        dr_wavelengths = RANGE_STEP_WAVELENGTHS if range_dependent else RANGE_STEP_FLAT_WAVELENGTHS
        return cls(range_step_m=dr_wavelengths * wavelength_m,
                   depth_step_m=DEPTH_STEP_WAVELENGTHS * wavelength_m,
                   grid_depth_m=max_bottom_depth_m + layer_m, absorbing_layer_m=layer_m)

    @classmethod
    def for_environment(cls, env: RamEnvironment, freq_hz: float) -> RamSettings:
        """The default settings (`for_frequency`) for ``env`` at ``freq_hz``."""
        return cls.for_frequency(freq_hz, max_bottom_depth_m=env.max_bottom_depth_m,
                                 range_dependent=env.is_range_dependent)
