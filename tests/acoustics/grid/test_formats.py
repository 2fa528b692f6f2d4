"""Versioned files: a grid or study of an older format opens through its upgrade step or is refused
with its format, this version's and the command that writes it anew, through the command line.

``tests/data/grid-format1.nc`` is the tiny-munk grid written by the last release before formats
were numbered (commit 08b016e: ``tmakit grids build tests/data/tiny-munk.toml``), and
``grid-format0.nc`` the same area written before ``area_json`` became the area-file document
(commit e95a778^). Both were made once from those commits and are kept, not regenerated.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
import xarray as xr

import acoustics
import envdata
from acoustics.grid.formats import GRID_FORMAT, STUDY_FORMAT, upgrade_study
from acoustics.sensitivity.files import StudyFileError
from tests.conftest import DATA
from tools.cli import main

FORMAT1 = DATA / "grid-format1.nc"
FORMAT0 = DATA / "grid-format0.nc"


def test_a_new_grid_carries_this_versions_format(tiny_grid, tiny_grid_file):
    assert tiny_grid.attrs["tmakit_format"] == GRID_FORMAT == 3
    assert acoustics.open_tables(tiny_grid_file).dataset.attrs["tmakit_format"] == 3


def test_the_previous_releases_grid_opens_through_the_upgrade(tiny_area):
    raw = xr.open_dataset(FORMAT1)
    assert "tmakit_format" not in raw.attrs  # written before formats were numbered
    tables = acoustics.open_tables(FORMAT1)
    assert tables.dataset.attrs["tmakit_format"] == GRID_FORMAT
    # the same area and BELLHOP in that release's mode (incoherent beams, before the surface was
    # put at the target's end): the same numbers as a grid built now
    incoherent = dataclasses.replace(tiny_area, propagation=dataclasses.replace(
        tiny_area.propagation, mode=envdata.TlMode.INCOHERENT))
    now = acoustics.build_grid(incoherent, workers=2)
    np.testing.assert_allclose(tables.k_grid_db, now["k_db"].values, rtol=0, atol=1e-9)


def test_the_previous_releases_grid_through_the_command_line(capsys, tmp_path):
    assert main(["grids", "show", str(FORMAT1), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["attrs"]["tmakit_format"] == GRID_FORMAT and shown["dims"]["class"] == 2


@pytest.mark.parametrize("path, fmt, why", [(FORMAT0, 0, "its area_json is not an area-file document")])
def test_an_older_grid_is_refused_naming_its_format_and_the_rebuild(capsys, tmp_path, path, fmt, why):
    assert main(["grids", "show", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {path}: a grid of tmakit format {fmt} ({why}); this version reads formats "
                   f"1-{GRID_FORMAT}; write it anew with tmakit grids build tiny-munk"]


def test_a_grid_from_a_newer_tmakit_is_refused(capsys, tmp_path, tiny_grid):
    path = tmp_path / "future.nc"
    acoustics.write_grid(tiny_grid.assign_attrs(tmakit_format=GRID_FORMAT + 1), path)
    out = tmp_path / "track.csv"
    assert main(["track", "--grid", str(path), "--measurements", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"error: {path}: a grid of tmakit format {GRID_FORMAT + 1} (written by a newer tmakit); "
                   f"this version reads formats 1-{GRID_FORMAT}; write it anew with tmakit grids build tiny-munk")
    assert not out.exists()


def test_a_format_that_is_not_an_integer_is_refused(tmp_path, tiny_grid):
    path = tmp_path / "odd.nc"
    acoustics.write_grid(tiny_grid.assign_attrs(tmakit_format="two"), path)
    with pytest.raises(acoustics.GridFileError, match="tmakit_format must be an integer, got 'two'"):
        acoustics.open_tables(path)


def test_a_study_without_a_format_is_format_1_and_a_newer_one_is_refused():
    ds = xr.Dataset(attrs={"area": "tiny-munk"})
    assert upgrade_study(ds, "s.nc", StudyFileError).attrs["tmakit_format"] == STUDY_FORMAT
    with pytest.raises(StudyFileError, match=r"format 3 \(written by a newer tmakit\); this version reads "
                                             r"formats 1-2; write it anew with tmakit sensitivity tiny-munk"):
        upgrade_study(ds.assign_attrs(tmakit_format=3), "s.nc", StudyFileError)
