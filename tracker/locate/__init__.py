"""Stationary target location from passive-sonar bearings (Schmidt et al.).

A stationary target at (x0, y0) seen from observer positions (X(n), Y(n)) at bearings alpha(n)
satisfies one linear equation per bearing (eq. 4),

    cos(alpha) x0 - sin(alpha) y0 = cos(alpha) X - sin(alpha) Y,

so two bearings give a crossing fix (eqs. 6-8) and n bearings a least-squares fix. The
conditioning number u of the matrix P (eq. 11) and its determinant (eq. 10) say how sensitive
the fix is to bearing errors. The observer's course can be steered perpendicular to the current
bearing (eq. 17) or by the modified algorithm (23) that keeps u from degrading. For a bearing
error bound D_alpha the fix lies in a quadrilateral bounded by the extreme bearing lines; its
diagonals follow eqs. 25-28.

Modules: `bearings` (the input and its CSV), `geometry` (eqs. 1-12), `fixes` (crossing, least
squares, mean), `regions` (eqs. 24-28), `route` (eqs. 13-23), `montecarlo` (Figs. 5, 6, 9) and
`plot` (the figures; not imported here, so that matplotlib loads only when a plot is drawn).

Conventions (docs/formats.md): x east, y north, metres; bearings and courses in degrees clockwise
from north in [0, 360); times in seconds. The paper's formulas are scale-free, so its unit-free
example (x0 = y0 = 10, VT = 3) reads as kilometres or metres alike.

References
----------
A. Schmidt, J. Marszal, R. Salamon, A. Jedel, Z. Ostrowski, "Bearing errors in passive sonar
stationary target location".
"""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "tracker.locate.bearings": ["BEARING_COLUMNS", "Bearings", "read_bearings_csv"],
    "tracker.locate.choices": ["DEFAULT_MAX_U", "CourseRule", "FixMethod", "Side"],
    "tracker.locate.fixes": ["LocateResult", "crossing_fix", "locate", "lsq_fix", "mean_fix"],
    "tracker.locate.geometry": [
        "SAME_POSITION_M", "bearing_system", "bearing_to_deg", "conditioning_number",
        "crossing_point", "pair_conditioning", "wrap_deg",
    ],
    "tracker.locate.montecarlo": ["MonteCarlo", "monte_carlo_first_leg", "monte_carlo_locate"],
    "tracker.locate.regions": ["ErrorPolygon", "ErrorRegion", "error_polygon", "error_region"],
    "tracker.locate.route": [
        "CourseRule", "Route", "Side", "conditioning_vs_course", "course_offset_deg", "plan_route",
    ],
})
