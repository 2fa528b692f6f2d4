"""Column names of the Iglesis & de Montella study's CSV and JSON, shared by the study and its plot.

Each filter the study compares writes ``rmse_STEM_m`` and ``median_STEM_m`` columns (and the
same keys in the JSON); the plot reads them back by the same stems.
"""

from __future__ import annotations

#: Column stem of each filter in the CSV and JSON (``rmse_STEM_m``, ``median_STEM_m``).
COLUMN = {"rpf-bot": "bot", "rpf": "spl", "rpf-vp": "spl_vp", "rpf-sl": "spl_offset"}
