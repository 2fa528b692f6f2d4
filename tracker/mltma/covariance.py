"""The sds of eq. 25's estimate from the whole curvature of its functional: marginal, not
conditional.

J = sum of the squared residuals of eq. 25 (`tracker.mltma.eq25.residuals`) is -2 ln L, so near
its minimum the covariance of (course, speed, range) is (F^T F)^-1, F the residuals' Jacobian
(Gauss-Newton's Hessian of ln L). Its diagonal gives each parameter's sd with the other two
free. In bearings-plus-levels motion analysis range, speed and course trade against each other
along a valley of J; the curvature in range with course and speed held at the optimum (what
`tracker.mltma.search` reads off its grid) measures the valley's steep walls, not its length,
and is tens of times too small a range sd.
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.eq25 import Eq25Estimate, Eq25Terms, residuals
from tracker.mltma.window import TackWindow

#: The sds are capped here: course (deg), speed (m/s); range at the range axis's end.
COURSE_SD_CAP_DEG = 180.0
SPEED_SD_CAP_MPS = 50.0


def marginal_sds(window: TackWindow, est: Eq25Estimate, terms: Eq25Terms, range_max_m: float) -> Eq25Estimate:
    """``est`` with its sds replaced by the marginal ones of (F^T F)^-1 at its point.

    Parameters
    ----------
    window : TackWindow
        The rows' tacks up to the current cycle.
    est : Eq25Estimate
        The minimiser of eq. 25 (`tracker.mltma.search`, `tracker.mltma.polish`).
    terms : Eq25Terms
    range_max_m : float
        Cap of the range sd, m (the tables' last range).
    """
    _, jac = residuals(window, terms, est.course_deg, est.speed_mps, est.range_m, jacobian=True)
    info = np.einsum("bni,bnj->bij", jac, jac)
    # scale to unit diagonal before inverting (course in deg, speed in m/s and range in m
    # differ by orders of magnitude)
    d = np.sqrt(np.maximum(np.einsum("bii->bi", info), 1e-300))
    corr = info / (d[:, :, None] * d[:, None, :])
    cov_scaled = np.linalg.pinv(corr, hermitian=True)
    var = np.einsum("bii->bi", cov_scaled) / (d * d)
    sd = np.sqrt(np.maximum(var, 0.0))
    return est._replace(course_sd_deg=np.minimum(sd[:, 0], COURSE_SD_CAP_DEG),
                        speed_sd_mps=np.minimum(sd[:, 1], SPEED_SD_CAP_MPS),
                        range_sd_m=np.minimum(sd[:, 2], range_max_m))
