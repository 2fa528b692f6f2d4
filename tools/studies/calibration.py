"""Whether a tracker's stated uncertainty means what it says: the coverage of its 90 % intervals
and its normalised errors against the truth (DESIGN.md "K's error and stated uncertainty").

A tracker that states ``range_m`` with ``range_sd_m`` promises that ``range_m +- 1.645
range_sd_m`` holds the true range in 90 % of cycles; with Gaussian errors the median of
|error| / sd is then 0.674 and the mean of (error / sd)^2 (the normalised squared error, NEES
of one component) is 1. Every study reports these three for range, course and speed (and depth
where estimated) over the cycles after its first minutes, on runs the tracker was not tuned on.
"""

from __future__ import annotations

import numpy as np

#: The 90 % interval is the estimate +- this many sd (the normal's 95th percentile).
Z90 = 1.6448536269514722
#: The median of |error| / sd of a calibrated Gaussian estimate.
MEDIAN_ABS_Z = 0.6744897501960817


def interval_calibration(error, sd, keep=None) -> dict:
    """Coverage of the 90 % interval, median |error| / sd and mean (error / sd)^2.

    Parameters
    ----------
    error : array_like
        Estimate less the truth (an angle wrapped to +- 180 deg), any shape.
    sd : array_like
        The sd the tracker stated for each estimate, same shape.
    keep : array_like of bool, optional
        The estimates to count (e.g. the cycles after the first minutes); every finite pair
        with a positive sd by default.

    Returns
    -------
    dict
        ``cycles`` counted, ``coverage_90`` (share with |error| <= 1.645 sd), ``median_abs_z``
        (calibrated: 0.674) and ``mean_sq_z`` (calibrated: 1); NaN where none is counted.
    """
    e = np.asarray(error, dtype=float)
    s = np.broadcast_to(np.asarray(sd, dtype=float), e.shape)
    ok = np.isfinite(e) & np.isfinite(s) & (s > 0)
    if keep is not None:
        ok &= np.broadcast_to(np.asarray(keep, dtype=bool), e.shape)
    z = np.abs(e[ok]) / s[ok]
    if z.size == 0:
        return {"cycles": 0, "coverage_90": float("nan"), "median_abs_z": float("nan"), "mean_sq_z": float("nan")}
    return {"cycles": int(z.size), "coverage_90": round(float(np.mean(z <= Z90)), 4),
            "median_abs_z": round(float(np.median(z)), 3), "mean_sq_z": round(float(np.mean(z * z)), 3)}


def wrap_deg(angle_deg):
    """An angle difference wrapped to [-180, 180) deg."""
    return np.mod(np.asarray(angle_deg, dtype=float) + 180.0, 360.0) - 180.0


#: Speed nodes of the studies' runs, in the class's sds: the quantiles 1/10, 3/10, ..., 9/10 of
#: the normal, each as likely. A run's path depends on its speed; with BELLHOP along the true
#: paths each distinct path costs a BELLHOP run per cycle, so the speeds are drawn from these
#: five, the levels' offsets (P0, dK) from the normal itself.
SPEED_NODES_SD = (-1.2815515655446004, -0.5244005127080407, 0.0, 0.5244005127080407, 1.2815515655446004)


def class_draws(sc, cls, runs: int, rng) -> dict[str, np.ndarray]:
    """Each run's target drawn from its class (the prior the trackers assume): the first tack's
    speed and P0 set to the class's means plus a draw (later tacks keep the scenario's changes
    from the first), and dK of eq. 31 from the class's ``k_error_sd_db``; keyword arguments of
    `tracker.simulate.simulate_batch` (``dv_mps``, ``dp0_db``, ``dk_db``), (runs,) each."""
    first = sc.target_tacks[0]
    nodes = np.asarray(SPEED_NODES_SD)[rng.integers(0, len(SPEED_NODES_SD), runs)]
    speed = cls.speed_mean_mps + cls.speed_sd_mps * nodes
    return {"dv_mps": speed - first.speed_mps,
            "dp0_db": cls.noise_mean_db - first.noise_db + rng.normal(0.0, cls.noise_sd_db, runs),
            "dk_db": rng.normal(0.0, cls.k_error_sd_db, runs)}
