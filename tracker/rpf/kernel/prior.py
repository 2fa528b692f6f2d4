"""Prior particles in the compiled kernel, as `tracker.rpf.prior.initial_particles`
(Ristic et al. 2003, sec. 6.4.1.1; the paper's sec. 5)."""

from __future__ import annotations

import math

from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH


@njit(fastmath=FASTMATH, error_model="numpy")
def init_particle(g0, g1, g2, g3, z0, ovx, ovy, prior):
    """(x, y, vx, vy) of one prior particle from four N(0, 1) draws (`rpf.initial_particles`).

    ``z0`` is the first bearing, rad; ``ovx``, ``ovy`` the observer velocity, m/s (the state
    is relative); ``prior`` a `tracker.rpf.kernel.params.Prior`.
    """
    if prior.range_log_span > 0.0:  # log-uniform: the normal draw through its CDF
        rng_m = math.exp(prior.range_log_near + prior.range_log_span * 0.5 * math.erfc(-g0 / math.sqrt(2.0)))
    else:
        rng_m = prior.range_mean_m + prior.range_sd_m * g0
    theta = z0 + prior.bearing_sd_rad * g1
    speed = prior.speed_mean_mps + prior.speed_sd_mps * g2
    course = z0 + math.pi + prior.course_sd_rad * g3
    return (rng_m * math.sin(theta), rng_m * math.cos(theta),
            speed * math.sin(course) - ovx, speed * math.cos(course) - ovy)
