"""Every result file in docs/results can be checked (``bench.provenance``): its commit is in the
history of HEAD, its tree was clean, and nothing in it is an absolute path of the machine that
made it; each rule with a planted counter-example, a file the test writes and no commit holds."""

from __future__ import annotations

import json
import subprocess

import pytest

from bench.harness import REPO, RESULTS_DIR
from bench.provenance import problems, result_files, text_files


@pytest.mark.parametrize("path", [*result_files(), *text_files()], ids=lambda p: str(p.relative_to(RESULTS_DIR)))
def test_every_result_file_can_be_checked(path):
    assert problems(path) == [], f"{path.relative_to(REPO)}: {problems(path)}"


def _git(repo, *args) -> str:
    return subprocess.run(["git", *args], cwd=repo, capture_output=True, text=True, check=True,
                          timeout=30).stdout.strip()


@pytest.fixture(scope="module")
def history(tmp_path_factory):
    """A repository of its own: HEAD on main, and a commit on a branch main does not hold (as a
    rebase leaves the commit a result file named)."""
    repo = tmp_path_factory.mktemp("history")
    _git(repo, "init", "-q", "-b", "main")
    for k, v in (("user.name", "test"), ("user.email", "test@example.org"), ("commit.gpgsign", "false")):
        _git(repo, "config", k, v)
    _git(repo, "commit", "-q", "--allow-empty", "-m", "first")
    first = _git(repo, "rev-parse", "--short", "HEAD")
    _git(repo, "checkout", "-q", "-b", "side")
    _git(repo, "commit", "-q", "--allow-empty", "-m", "left behind")
    side = _git(repo, "rev-parse", "--short", "HEAD")
    _git(repo, "checkout", "-q", "main")
    _git(repo, "commit", "-q", "--allow-empty", "-m", "second")
    return repo, first, side


def _planted(tmp_path, **change) -> "Path":  # noqa: F821 - pathlib's, returned by tmp_path
    """A result file as the harness writes it (the provenance of a real one), with ``change``."""
    data = json.loads((RESULTS_DIR / "grids.json").read_text())
    data["provenance"].update(change.pop("provenance", {}))
    data.update(change)
    path = tmp_path / "planted.json"
    path.write_text(json.dumps(data))
    return path


def test_a_file_of_the_history_passes(tmp_path, history):
    # the counter-examples below fail for their one fault: the same file naming a commit of
    # main's history passes
    repo, first, _ = history
    assert problems(_planted(tmp_path, provenance={"commit": first}), repo) == []


@pytest.mark.parametrize("commit", ["side", "b9429c0", ""], ids=["left-on-a-branch", "unknown", "none"])
def test_a_commit_outside_the_history_of_head_is_refused(tmp_path, history, commit):
    repo, _, side = history
    named = side if commit == "side" else commit
    found = problems(_planted(tmp_path, provenance={"commit": named}), repo)
    assert found == ([f"commit {named} is not in the history of HEAD"] if named else ["no commit"])


def test_a_dirty_tree_is_refused(tmp_path, history):
    repo, first, _ = history
    found = problems(_planted(tmp_path, provenance={"commit": first, "tree_clean": False}), repo)
    assert found == ["made from a tree with uncommitted changes (tree_clean: false)",
                     "tree_clean is False, not true"]
    # a file marked to be made again says why, and still names no dirty tree
    found = problems(_planted(tmp_path, provenance={"commit": first, "tree_clean": False, "rerun_pending": True,
                                                    "reason": "after the surface change"}), repo)
    assert found == ["made from a tree with uncommitted changes (tree_clean: false)"]


@pytest.mark.parametrize("where", [
    {"provenance": {"versions": {"bellhop": "/srv/build/aubellhop/bin/bellhop.exe"}}},
    {"grid": "/mnt/data/ocean-deep.nc"},
    {"note": "read from ~/areas/shelf.toml"},
    {"runs": [{"file": "out=/var/tmp/x.shd"}]},
    {"/opt/cache/run.json": 1.0},
    {"file": "C:\\data\\grid.nc"},
], ids=["version", "value", "home", "nested", "key", "windows"])
def test_an_absolute_path_anywhere_is_refused(tmp_path, history, where):
    # any absolute path, not a list of known roots: none of these is a root the machines here use
    repo, first, _ = history
    prov = {"commit": first, **where.pop("provenance", {})}
    found = problems(_planted(tmp_path, provenance=prov, **where), repo)
    assert len(found) == 1 and found[0].startswith("machine paths:"), found


def test_units_and_relative_paths_are_not_paths(tmp_path, history):
    # what result files do hold: units with a slash, paths from the repository's root
    repo, first, _ = history
    path = _planted(tmp_path, provenance={"commit": first},
                    units=["dB re 1 uPa^2/Hz", "1/s", "m/s", "dB / km"], grid="out/bench/ocean-deep.nc",
                    exe="VENV/share/tmakit/bellhop/aubellhop/bin/bellhop.exe")
    assert problems(path, repo) == []


def test_a_path_in_a_table_beside_the_files_is_refused(tmp_path, history):
    repo, _, _ = history
    table = tmp_path / "runs.csv"
    table.write_text("run,grid\n0,out/grids/a.nc\n")
    assert problems(table, repo) == []
    table.write_text("run,grid\n0,out/grids/a.nc\n1,/home/user/grids/a.nc\n")
    assert problems(table, repo) == ["machine paths: ['1,/home/user/grids/a.nc']"]


def test_a_shallow_clone_cannot_tell_and_says_so(tmp_path, history):
    # a clone whose history is cut cannot tell an old commit from a lost one: an error, not a pass
    repo, first, _ = history
    shallow = tmp_path / "shallow"
    subprocess.run(["git", "clone", "-q", "--depth", "1", f"file://{repo}", str(shallow)], check=True,
                   capture_output=True, timeout=60)
    with pytest.raises(RuntimeError, match=r"is a shallow clone: a result file's commit cannot be checked"):
        problems(_planted(tmp_path, provenance={"commit": first}), shallow)
