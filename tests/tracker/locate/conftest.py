"""The paper's example for the tracker.locate tests, and where their data files are.

The paper's example is unit-free (x0 = y0 = 10, VT = 3, first bearing 45 deg, D_alpha = 1 deg);
the formulas are scale-free, so it is used directly as metres here.
"""

from __future__ import annotations

from tests.conftest import MALFORMED as MALFORMED_ROOT
from tracker import locate as loc

MALFORMED = MALFORMED_ROOT / "locate"

# The paper's Fig. 8 example: observer at the origin, target at (10, 10), leg VT = 3.
X0 = Y0 = 10.0
VT = 3.0
D_ALPHA = 1.0  # the captions say 10; the printed numbers are for 1 degree


def paper_route(rule="eq23", n_legs=1, **kw) -> loc.Route:
    return loc.plan_route(target_x_m=X0, target_y_m=Y0, speed_mps=VT, leg_s=1.0, n_legs=n_legs,
                          rule=rule, **kw)


def paper_region(rule="eq23") -> loc.ErrorRegion:
    r = paper_route(rule)
    return loc.error_region(r.obs_x_m, r.obs_y_m, X0, Y0, d_alpha_deg=D_ALPHA)
