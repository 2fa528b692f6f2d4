"""A study's files are written all or none (the study, its plots, the area copy)."""

from __future__ import annotations

import pytest

from acoustics import sensitivity as sens
from tests.acoustics.sensitivity.conftest import TINY_SPECS
from tests.conftest import DATA

pytestmark = pytest.mark.bellhop


def test_outputs_are_written_together_or_not_at_all(tmp_path):
    tiny = str(DATA / "tiny-munk.toml")
    out, plot, copy = tmp_path / "s.nc", tmp_path / "s.png", tmp_path / "tiny-k.toml"
    plot.mkdir()  # the plot cannot be put in place: nothing is, and the finished study goes too
    with pytest.raises(OSError):
        sens.run_study_file(tiny, members=2, perturbations=[q for s in TINY_SPECS for q in sens.parse_spec(s)], out=out, plot=plot,
                            write_k_error=copy, workers=2)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.png"]
    plot.rmdir()
    info = sens.run_study_file(tiny, members=2, perturbations=[q for s in TINY_SPECS for q in sens.parse_spec(s)], out=out, plot=plot,
                               write_k_error=copy, workers=2)
    assert set(info["files"]) == {"study", "plot", "area_with_k_error"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.nc", "s.png", "tiny-k.toml"]
    assert sens.open_study(out).members == 2
    assert "measured by tmakit sensitivity" in copy.read_text()
