"""``tmakit grids plot`` on a bearing-dependent grid, and the demo's checks, through the real
command line on a small real shelf-break grid."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

import envdata
from tests.acoustics.plots.test_radialplots import PNG_SIGNATURE, png_size, small_shelf_area_file
from tools import cli

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def shelf_grid_file(tmp_path_factory) -> Path:
    """Built by the command line, as a user would."""
    folder = tmp_path_factory.mktemp("shelf-cli")
    out = folder / "shelf.nc"
    assert cli.main(["grids", "build", str(small_shelf_area_file(folder)), "--out", str(out),
                     "--workers", "2"]) == 0
    return out


def run_json(capsys, *argv) -> dict:
    assert cli.main([*map(str, argv), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def run_error(capsys, *argv) -> str:
    """Exit status 2 and exactly one ``error:`` line (README, after the command list)."""
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    return lines[0]


def test_plot_writes_the_map_the_bottom_and_the_section(capsys, tmp_path, shelf_grid_file):
    data = run_json(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "shelf.png",
                    "--what", "detection", "--bearing", "45", "--class", "SW", "--band", "FB2")
    assert data["files"] == {"map": str(tmp_path / "shelf.png"),
                             "bottom": str(tmp_path / "shelf-bottom.png"),
                             "section": str(tmp_path / "shelf-section.png")}
    assert data["what"] == "detection"
    # the area file named its relief by absolute path, so the grid's record finds it
    assert data["bathymetry"]["found"] == "as named in the grid" and data["bathymetry"]["matches_grid"]
    for path in data["files"].values():
        width, height = png_size(Path(path))
        assert width >= 1000 and height >= 500 and Path(path).stat().st_size > 30_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["shelf-bottom.png", "shelf-section.png", "shelf.png"]


def test_plot_without_a_bearing_writes_the_map_and_the_bottom(capsys, tmp_path, shelf_grid_file):
    assert cli.main(["grids", "plot", str(shelf_grid_file), "--out", str(tmp_path / "m.png")]) == 0
    out = capsys.readouterr().out
    assert f"wrote {tmp_path / 'm.png'} (map)" in out and f"wrote {tmp_path / 'm-bottom.png'} (bottom)" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m-bottom.png", "m.png"]


def test_a_given_bathymetry_file_is_drawn_and_compared_with_the_record(capsys, tmp_path, shelf_grid_file):
    builtin = envdata.area_path("shelf-break").parent / "data" / "shelf-break_gebco_15s.nc"
    copy = tmp_path / "relief.nc"
    shutil.copyfile(builtin, copy)
    data = run_json(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "m.png",
                    "--bathymetry", copy)
    assert data["bathymetry"] == {"file": str(copy), "found": "given", "matches_grid": True}
    # a climatology file is not a bathymetry file: one clean line, nothing written
    climatology = builtin.parent / "shelf-break_woa_t08_04.nc"
    line = run_error(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "n.png",
                     "--bathymetry", climatology)
    assert str(climatology) in line and "no elevation variable" in line
    line = run_error(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "n.png",
                     "--bathymetry", tmp_path / "missing.nc")
    assert "bathymetry file not found" in line
    assert not (tmp_path / "n.png").exists() and not (tmp_path / "n-bottom.png").exists()


@pytest.mark.parametrize("options, message", [
    (["--class", "SUB"], "class 'SUB' is not a class of the grid (NPS, SW, TV)"),
    (["--band", "FB9"], "band 'FB9' is not a band of the grid (FB1, FB2, FB3)"),
    (["--bearing", "360"], "bearing 360 deg: must be in [0, 360) deg"),
    (["--bearing", "-10"], "bearing -10 deg: must be in [0, 360) deg"),
    (["--bearing", "inf"], "bearing inf deg: must be in [0, 360) deg"),
])
def test_bad_options_are_one_error_line_and_write_nothing(capsys, tmp_path, shelf_grid_file, options, message):
    line = run_error(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "m.png", *options)
    assert line.startswith(f"error: {shelf_grid_file}: {message}")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("option, said", [(["--bearing", "45"], "a section's bearing"),
                                          (["--band", "F1"], "a map's band"),
                                          (["--what", "k"], "a map (K or detection ranges)"),
                                          (["--bathymetry", "relief.nc"], "a bathymetry file")])
def test_bearing_options_on_a_flat_grid_are_errors(capsys, tmp_path, tiny_grid_file, option, said):
    line = run_error(capsys, "grids", "plot", tiny_grid_file, "--out", tmp_path / "m.png", *option)
    assert line.startswith(f"error: {tiny_grid_file}: {said} is for a bearing-dependent grid")
    assert list(tmp_path.iterdir()) == []


def test_a_flat_grid_still_plots_one_file(capsys, tmp_path, tiny_grid_file):
    data = run_json(capsys, "grids", "plot", tiny_grid_file, "--out", tmp_path / "flat.png", "--class", "SHIP")
    assert data == {"file": str(tmp_path / "flat.png")}
    assert png_size(tmp_path / "flat.png")[0] > 1000
    assert [p.name for p in tmp_path.iterdir()] == ["flat.png"]


def test_every_output_is_checked_before_work(capsys, tmp_path, shelf_grid_file):
    notes = tmp_path / "m-bottom.png"
    notes.write_text("not a picture\n")
    line = run_error(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "m.png")
    assert line == f"error: {notes}: exists and is not a PNG image; not replaced (--force replaces it)"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m-bottom.png"] and notes.read_text() == "not a picture\n"
    (tmp_path / "m-section.png").mkdir()
    line = run_error(capsys, "grids", "plot", shelf_grid_file, "--out", tmp_path / "m.png", "--bearing", "10",
                     "--force")
    assert "m-section.png: is a directory" in line
    assert notes.read_text() == "not a picture\n" and not (tmp_path / "m.png").exists()
    assert cli.main(["grids", "plot", str(shelf_grid_file), "--out", str(tmp_path / "m.png"), "--force"]) == 0
    assert notes.read_bytes()[:8] == PNG_SIGNATURE


def test_an_output_under_a_file_is_refused(capsys, tmp_path, shelf_grid_file):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    line = run_error(capsys, "grids", "plot", shelf_grid_file, "--out", blocker / "m.png")
    assert "is a file, not a folder" in line
    assert [p.name for p in tmp_path.iterdir()] == ["file"] and blocker.read_text() == "x"


def test_the_demo_checks_the_map_outputs_before_any_work(capsys, tmp_path):
    out = tmp_path / "demo"
    out.mkdir()
    (out / "shelf-break-detection.png").write_text("my notes\n")
    line = run_error(capsys, "demo", "--out", out)
    assert line == (f"error: {out / 'shelf-break-detection.png'}: exists and is not a PNG image; "
                     f"not replaced (--force replaces it)")
    assert [p.name for p in out.iterdir()] == ["shelf-break-detection.png"]  # no grid was built
    (out / "shelf-break-detection.png").unlink()
    (out / "shelf-break-bellhop.nc").write_text("not a grid\n")
    line = run_error(capsys, "demo", "--out", out)
    assert "shelf-break-bellhop.nc: exists and is not a tmakit netCDF file" in line
    assert [p.name for p in out.iterdir()] == ["shelf-break-bellhop.nc"]


def test_grids_show_summarises_a_bearing_dependent_grid(shelf_grid_file, capsys):
    from tools import cli

    assert cli.main(["grids", "show", str(shelf_grid_file), "--json"]) == 0
    import json

    data = json.loads(capsys.readouterr().out)
    assert data["dims"]["bearing"] == 4
    k = data["k"]["TV/FB1"]["k_db"]
    assert len(k) == len(data["ranges_km"]) and all(v is None or v < 0 for v in k)
    assert cli.main(["grids", "show", str(shelf_grid_file)]) == 0
    text = capsys.readouterr().out
    assert "radials" in text and "median over bearings" in text
