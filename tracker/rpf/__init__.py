"""Regularized particle filter for bearings and sound pressure levels (Iglesis & de Montella).

State (eq. 3): the target relative to the observer, x = (x, y, vx, vy), m and m/s, x east and
y north. Optionally a fifth component, a source-level offset in dB (constant in time, estimated
jointly; see `RpfConfig.sl_offset_sd_db`), which is not in the paper.

Modules, one part of the filter each:

- `config`: `RpfConfig` (its ``engine``: the compiled kernel or the numpy reference) and
  `Engine` (the filter's methods are `tracker.methods.Method`);
- `prior`: initial particles from the first bearing;
- `motion`: prediction, eqs. 4-6; `normals`: the normal draws it and the kernel use;
- `likelihood`: bearings and levels, eqs. 9, 12, 16, 31-33;
- `weights`: logsumexp normalisation and N_eff, eqs. 19-20;
- `resample`: multinomial resampling; `regularise`: the Epanechnikov jitter, eqs. 21-28;
- `estimate`: estimate and covariance, eqs. 29-30, and the particle spreads;
- `batch`: `run_batch`, the numpy reference engine and the dispatch to `kernel`, the compiled
  fused cycle loop;
- `track`: `track_measurements`, from a measurement CSV to track rows.

References
----------
E. Iglesis, L. de Montella, "Target motion analysis using combined bearings and underwater
sound pressure levels", hal-04796331 (2024). C. Musso, N. Oudjane, F. Le Gland, "Improving
regularised particle filters" (2001). B. Ristic, S. Arulampalam, N. Gordon, "Beyond the Kalman
filter" (2003), sec. 6.4.1.1 (initialization).
"""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "tracker.rpf.batch": ["BatchResult", "run_batch"],
    "tracker.rpf.config": ["BLOCK_PARTICLES", "KNOT_MPS", "Engine", "RpfConfig"],
    "tracker.rpf.estimate": ["estimate", "particle_sds", "weighted_covariance"],
    "tracker.rpf.likelihood": [
        "bearing_loglik", "bearing_rad", "level_loglik", "predicted_level_db", "wrap_rad",
    ],
    "tracker.rpf.motion": ["predict"],
    "tracker.rpf.normals": ["standard_normal_pairs"],
    "tracker.rpf.prior": ["initial_particles"],
    "tracker.rpf.regularise": ["epanechnikov_sample", "optimal_bandwidth", "regularise", "unit_ball_volume"],
    "tracker.rpf.resample": ["multinomial_resample"],
    "tracker.rpf.track": ["track_measurements"],
    "tracker.rpf.weights": ["n_eff", "normalise", "normalise_exp"],
})
