"""The compiled (numba) engine of the regularized particle filter: the same algorithm as the
numpy reference of `tracker.rpf.batch`, fused into one loop per run.

Modules: `random` (the generator and the ziggurat samplers), `fastmath` (compiler flags and
call-free atan2 and exp), the per-particle and per-run pieces by role (`prior`, `motion`,
`likelihood`, `weights`, `estimate`, `resample`, `regularise`), `params` (the loop's inputs
and outputs in named groups), `loop` (the fused cycle loop), `driver` (`run`: arrays in,
estimates out, for one block of runs) and `cache` (drops numba caches older than the kernel's
sources, on import: the loop's cache embeds the code of every kernel module).

Not imported by `tracker.rpf`: numba loads only when the kernel engine runs.
"""

from tracker.rpf.kernel.cache import drop_stale_caches
from tracker.rpf.kernel.driver import run
from tracker.rpf.kernel.params import Measured, Model, Observer, Outputs, Prior, Profiles, Settings, profile_arrays
from tracker.rpf.kernel.random import seed_states

__all__ = ["Measured", "Model", "Observer", "Outputs", "Prior", "Profiles", "Settings",
           "drop_stale_caches", "profile_arrays", "run", "seed_states"]
