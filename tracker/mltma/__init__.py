"""ML target motion analysis without observer maneuver (Grinenkov & Mashoshin 2024).

tracker.py: MLTracker (one cycle at a time) and track_measurements (a whole file), both
on batch.py's MLBatch, the state of B rows over T cycles, whose update takes the paper's steps:
measurement_sd (eqs. 2, 11), maneuver (eqs. 26-27, 29), range_prior (eqs. 20-21), gates (eq. 30,
curvature, section 4 step 8), course (eqs. 7, 8), eq. 25 by bearing_form + search + polish
(eq25 holds its terms and exact residuals; window cuts a tack's cycles) and covariance (its
marginal sds), smoothing (step 9, with the sds of the smoothed estimates).
params: MLParams.
"""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "tracker.mltma.batch": ["MLBatch"],
    "tracker.mltma.course": ["course_from_relative_deg", "relative_course_deg", "wrap180"],
    "tracker.mltma.params": ["MLParams"],
    "tracker.mltma.smoothing": ["trimmed_mean"],
    "tracker.mltma.tracker": ["MLTracker", "track_measurements"],
})
