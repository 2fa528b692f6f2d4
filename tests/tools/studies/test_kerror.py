"""``tmakit experiment kerror``: what it refuses before any work (the study itself runs on a
sensitivity study of the shelf-break area, docs/sensitivity.md)."""

from __future__ import annotations

import re

import pytest

from tools import cli


@pytest.mark.parametrize(("args", "message"), [
    (["kerror", "shelf-tv"], r"--grid, --study: the kerror study needs"),
    (["kerror", "shelf-nps", "--grid", "g.nc", "--study", "s.nc"], r"written for scenario 'shelf-tv'"),
    (["kerror", "shelf-tv", "--grid", "g.nc", "--study", "s.nc", "--level-sigma-db", "4"], r"--level-sigma-db"),
    (["shelf", "shelf-tv", "--study", "s.nc"], r"--study: only the kerror study"),
    (["kerror", "shelf-tv", "--grid", "g.nc", "--study", "s.nc", "--runs", "0"], r"--runs: must be in"),
])
def test_the_kerror_study_refuses_what_it_cannot_run(args, message, tmp_path, capsys):
    assert cli.main(["experiment", *args, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and re.search(message, err), err


def test_the_halves_and_the_one_number(tiny_radial_tables):
    # the study's pieces on a tiny radial grid: the one number as a model (no residual of its own,
    # the tables' beside it), a member's sea (the nominal grid with the member's K, no model)
    import numpy as np

    import acoustics
    from acoustics.grid.dataset import with_k_error_model
    from acoustics.grid.kerror import TABLE_RESIDUAL_SD_DB
    from tools.studies import kerror

    one = acoustics.open_tables(with_k_error_model(tiny_radial_tables.dataset,
                                                   kerror._scalar_model(tiny_radial_tables, 4.2), "t"))
    model = one.as_everywhere().k_error_model(0, bearing_deg=30.0)
    assert model.offset_sd_db == (4.2,) * len(one.bands)
    assert model.residual_sd_db == (TABLE_RESIDUAL_SD_DB,) * len(one.bands)
    assert model.offset_growth_db_per_km == 0.0
    assert np.isfinite(one.k_grid_db).any()
