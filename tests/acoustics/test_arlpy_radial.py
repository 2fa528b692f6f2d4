"""Cross-check of a range-dependent radial: tmakit's .env/.bty/.ssp against arlpy's create_env2d.

The same radial of the built-in shelf-break area (bottom and sound-speed section sampled along
its geodesic), at one frequency, with the source at the observer's depth: once through tmakit's
own BELLHOP input (acoustics.bellhop.radialfiles) and once through arlpy (its own environment,
.venv-arlpy), both running the same bellhop.exe. Agreement: median |dTL| <= 1 dB and 90th
percentile <= 3 dB over the receivers where both see sound (TL < 120 dB).

arlpy is given the whole radial, the samples behind the origin included: with the bottom and
the columns from the source on only, a ray sent back by the slope leaves the 'Q' field and
BELLHOP stops ("ray is outside the box where the soundspeed is defined"), the range-dependent
SSP pitfall arlpy users meet. Measured figures: docs/results/arlpy-radial.json (written by
``python -m bench.crosscheck.radial``). What is left is the inputs, not the model: tmakit sets the
ray step (25 m) where arlpy leaves BELLHOP's automatic one (a tenth of the deepest depth, some
250 m here), and arlpy sizes the ray box and the end of its sound-speed field itself.
"""

from __future__ import annotations

import numpy as np
import pytest

from bench.crosscheck.radial import BEARINGS_DEG, compare_radial

pytestmark = pytest.mark.bellhop


@pytest.mark.parametrize("bearing", BEARINGS_DEG)
def test_a_shelf_break_radial_agrees_with_arlpy(tmp_path, bearing):
    r = compare_radial(bearing, tmp_path)
    assert r["theirs"].shape == r["ours"].shape
    assert r["heard"].sum() > 0.3 * r["wet"].sum()
    d = r["abs_diff_db"]
    assert np.median(d) <= 1.0, np.median(d)
    assert np.percentile(d, 90) <= 3.0, np.percentile(d, 90)
