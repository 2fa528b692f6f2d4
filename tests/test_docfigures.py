"""The figures quoted from result files: every generated table in README and docs/ is what its file
gives, and every figure quoted in prose is what it gives (``python -m bench.docfigures``); the result
files' provenance is tests/test_provenance.py's."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
RESULTS = REPO / "docs" / "results"


def _docfigures(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "bench.docfigures", *args], cwd=REPO, capture_output=True,
                          text=True, timeout=120)


def test_every_committed_table_is_what_its_result_file_gives():
    done = _docfigures("--check")
    assert done.returncode == 0, done.stdout + done.stderr


def _copied_pages(folder: Path) -> Path:
    """README and docs/ (the result files with them) copied into ``folder``; the copy's README."""
    for part in ("README.md", "docs"):
        src = REPO / part
        (shutil.copytree if src.is_dir() else shutil.copy)(src, folder / part)
    return folder / "README.md"


def test_a_table_that_differs_from_its_file_is_found(tmp_path):
    # the check above could pass by comparing nothing: a page copied with one figure changed fails
    readme = _copied_pages(tmp_path)
    text = readme.read_text()
    start = text.index("<!-- docfigures grids -->")
    row = text.index("| 2 workers vs 1 |", start)
    end = text.index("\n", row)
    readme.write_text(text[:row] + "| 2 workers vs 1 | 9.99x | >= 1.7 |" + text[end:])
    done = _docfigures("--check", "--root", str(tmp_path))
    assert done.returncode == 1 and "README.md: grids" in done.stdout, done.stdout + done.stderr


def test_a_figure_quoted_in_prose_that_differs_from_its_file_is_found(tmp_path):
    # prose is checked, not rewritten: the atlas's store size ratio changed in a copied README
    readme = _copied_pages(tmp_path)
    text = readme.read_text()
    ratio = json.loads((RESULTS / "atlas.json").read_text())["store"]["store_over_raw"]
    quoted, wrong = f"the store is {ratio:.2f} of its raw", f"the store is {ratio + 0.5:.2f} of its raw"
    assert quoted in text
    readme.write_text(text.replace(quoted, wrong))
    done = _docfigures("--check", "--root", str(tmp_path))
    assert done.returncode == 1 and "atlas.json store.store_over_raw" in done.stdout, done.stdout + done.stderr
    # and a rewrite leaves the prose to its author
    _docfigures("--root", str(tmp_path))
    assert wrong in readme.read_text()


def test_every_page_module_registers_and_a_table_defined_twice_is_refused():
    # the pages' modules of bench/docfigures/ register their blocks; two defining one name are
    # refused (the registry does not guess which a page means), and the command says so in one line
    from types import SimpleNamespace

    from bench.docfigures import RegistryError, page_modules, registry

    modules = page_modules()
    tables, quotes = registry(modules)
    assert {"grids", "stonesoup", "stonesoup-speed", "rpf-speed", "depth-check"} <= set(tables)
    assert {page for page, *_ in quotes} >= {"README.md", "docs/depth.md"}
    twice = SimpleNamespace(__name__="bench.docfigures.planted", PAGE="docs/x.md", TABLES={"grids": lambda root: ""})
    with pytest.raises(RegistryError, match=r"table 'grids' is defined twice, in bench\.docfigures\.readme and "
                                            r"bench\.docfigures\.planted"):
        registry([*modules, twice])
    with pytest.raises(RegistryError, match="planted defines no PAGE or no TABLES"):
        registry([SimpleNamespace(__name__="bench.docfigures.planted", TABLES={})])


def test_the_command_refuses_a_table_defined_twice(tmp_path):
    # the command itself, on a copy of the package with one page module that repeats a block name
    shutil.copytree(REPO / "bench", tmp_path / "bench", ignore=shutil.ignore_patterns("__pycache__"))
    (tmp_path / "bench" / "docfigures" / "zz_planted.py").write_text(
        'PAGE = "docs/x.md"\nTABLES = {"stonesoup": lambda root: ""}\n')
    done = subprocess.run([sys.executable, "-m", "bench.docfigures", "--check", "--root", str(REPO)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stderr.strip() == ("error: docfigures: table 'stonesoup' is defined twice, in "
                                   "bench.docfigures.stonesoup and bench.docfigures.zz_planted")


def test_every_page_has_a_module_that_says_what_its_prose_quotes():
    # README and every docs/ page: a module of bench/docfigures/ names it and lists the figures
    # its prose quotes (an empty list says why in the module)
    from bench.docfigures import page_modules
    from bench.docfigures.engine import pages

    modules = {m.PAGE: m for m in page_modules()}
    missing = [str(p.relative_to(REPO)) for p in pages(REPO) if str(p.relative_to(REPO)) not in modules]
    assert not missing, f"pages without a bench/docfigures module: {missing}"
    assert all(hasattr(m, "QUOTES") for m in modules.values()), [n for n, m in modules.items() if not hasattr(m, "QUOTES")]


def test_a_figure_computed_from_its_file_is_checked_too(tmp_path):
    # a quote may compute its figure (docs/models.md: RAM's wall time over BELLHOP's, the least of
    # a file's cases): the page's ratio changed in a copy is found, named by the function
    readme = _copied_pages(tmp_path)
    models = tmp_path / "docs" / "models.md"
    text = models.read_text()
    assert "and 31 to 208 times its wall time" in " ".join(text.split())
    models.write_text(text.replace("and 31 to", "and 57 to"))
    done = _docfigures("--check", "--root", str(tmp_path))
    assert done.returncode == 1 and "models-areas.json _least_wall_ratio ('and 31 to')" in done.stdout, done.stdout
    assert readme.exists()
