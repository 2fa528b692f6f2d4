"""The ASA wedge benchmark: RAM (default settings) against BELLHOP at the 30 m receiver.

The setting, the BELLHOP run (coherent, the grids' geometric hat beams) and the 210 m range
average are described in bench/crosscheck/ram_wedge.py, which also writes the measured figures
(docs/results/ram-wedge.json). Tolerance: median |dTL| <= 1.5 dB and 90th percentile <= 3 dB
after the range average, from 100 m to 3.4 km; measured median 0.84 dB, 90th percentile
1.97 dB (point-wise, without the average, 0.95 / 3.05 dB). What is left is mostly BELLHOP's:
beams at 25 Hz in 3.3 wavelengths of water, where the modes approach cut-off upslope.
"""

from __future__ import annotations

import numpy as np
import pytest

from bench.crosscheck.ram_wedge import compare_wedge

pytestmark = pytest.mark.bellhop


def test_ram_agrees_with_bellhop_in_the_asa_wedge():
    r = compare_wedge()
    assert np.all(np.isfinite(r["ram_tl_db"])) and np.all(r["bellhop_tl_db"] < 200.0)
    assert r["median_db"] <= 1.5, r["median_db"]
    assert r["p90_db"] <= 3.0, r["p90_db"]
