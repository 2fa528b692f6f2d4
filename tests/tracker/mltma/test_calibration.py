"""The ML analysis's stated sds cover the truth when the truth is drawn from the model it assumes
(DESIGN.md "K's error and stated uncertainty"): the G&M transport's first tack, its speed, P0 and
dK drawn per run from the class (eqs. 31-34) and a residual along the path
(`tests.tracker.calibrationruns`), tracked on the same synthetic K(r)."""

from tests.tracker.calibrationruns import model_runs
from tools.studies.calibration import MEDIAN_ABS_Z
from tools.studies.trackerrors import ml_track


def test_range_interval_covers_the_truth_on_the_first_tack():
    tables, ic, sim, _ = model_runs(5, runs=40)
    minutes = (sim.t_s - sim.t_s[0]) / 60.0
    cal = ml_track(tables, sim, ic).calibration(sim, minutes >= 10.0)["range"]
    # measured 2026-11-28 on seeds 5, 6, 7 with the smoothed sd the latest cycle's (or the
    # window's spread): coverage 0.95, 0.87, 0.91, median |z| 0.63, 0.74, 0.60 (calibrated: 0.90,
    # 0.67; with the window's mixture before, 0.96, 0.86, 0.93 and 0.63, 0.71, 0.58); the
    # conditional curvature the sds came from before that gave 0.05-0.3. Bounds: the issue's 80-97 % band widened by 2 points at the top for 40 runs'
    # scatter (about 40 independent draws: binomial sd of a 0.9 coverage ~0.05)
    assert 0.80 <= cal["coverage_90"] <= 0.99, cal
    assert 0.5 * MEDIAN_ABS_Z <= cal["median_abs_z"] <= 1.5 * MEDIAN_ABS_Z, cal
