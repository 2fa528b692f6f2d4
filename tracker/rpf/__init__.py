"""Regularized particle filter for bearings and sound pressure levels (Iglesis & de Montella).

State (eq. 3): the target relative to the observer, x = (x, y, vx, vy), m and m/s, x east and
y north. Optionally a fifth component, a source-level offset in dB (constant in time, estimated
jointly; see `RpfConfig.sl_offset_sd_db`), which is not in the paper.

Modules, one part of the filter each:

- `config`: `RpfConfig` (its ``engine``: the compiled kernel or the numpy reference), `Method`,
  `Engine`;
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

from tracker.rpf.batch import BatchResult, run_batch
from tracker.rpf.config import BLOCK_PARTICLES, KNOT_MPS, Engine, Method, RpfConfig
from tracker.rpf.estimate import estimate, particle_sds, weighted_covariance
from tracker.rpf.likelihood import bearing_loglik, bearing_rad, level_loglik, predicted_level_db, wrap_rad
from tracker.rpf.motion import predict
from tracker.rpf.normals import standard_normal_pairs
from tracker.rpf.prior import initial_particles
from tracker.rpf.regularise import epanechnikov_sample, optimal_bandwidth, regularise, unit_ball_volume
from tracker.rpf.resample import multinomial_resample
from tracker.rpf.track import track_measurements
from tracker.rpf.weights import n_eff, normalise, normalise_exp

__all__ = [
    "BLOCK_PARTICLES", "KNOT_MPS", "BatchResult", "Engine", "Method", "RpfConfig", "bearing_loglik",
    "bearing_rad", "epanechnikov_sample", "estimate", "initial_particles", "level_loglik",
    "multinomial_resample", "n_eff", "normalise", "normalise_exp", "optimal_bandwidth",
    "particle_sds", "predict", "predicted_level_db", "regularise", "run_batch",
    "standard_normal_pairs", "track_measurements", "unit_ball_volume", "weighted_covariance",
    "wrap_rad",
]
