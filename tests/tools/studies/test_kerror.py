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
