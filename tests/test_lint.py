"""The linter the project configured (ruff, ``[tool.ruff]`` in pyproject.toml) finds nothing."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _ruff() -> list[str]:
    beside = Path(sys.executable).with_name("ruff")  # the test extra installs it into the venv
    if beside.exists():
        return [str(beside)]
    found = shutil.which("ruff")
    assert found is not None, "ruff is not installed: it is in the test extra (pip install -e '.[test]')"
    return [found]


def test_ruff_finds_nothing():
    done = subprocess.run([*_ruff(), "check", "--no-cache", "--output-format", "concise", str(REPO)],
                          capture_output=True, text=True, cwd=REPO, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr


def test_ruff_would_find_an_unused_import(tmp_path):
    # the check above could pass by checking nothing: a planted unused import is found
    bad = tmp_path / "bad.py"
    bad.write_text("import os\n")
    done = subprocess.run([*_ruff(), "check", "--no-cache", "--isolated", "--select", "F401", str(bad)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 1 and "F401" in done.stdout
