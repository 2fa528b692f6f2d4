"""What a result file's provenance must hold for anyone to check it: the check behind
tests/test_provenance.py, and ``python -m bench.provenance [FILE ...]`` (every result file by
default; exit 1 and one line per problem when any has one).

A result file (a JSON file under docs/results, but the tables a study builds beside its results
in docs/results/STUDY/grids/, which git ignores) is traceable when

- its ``provenance`` has every field the harness writes (`bench.harness.provenance`);
- the commit it names is in the history of the checkout (an ancestor of HEAD): a commit that a
  rebase or an amend left behind names code no one can check out;
- the tree was clean when it was made (``tree_clean: true``): figures of uncommitted code name a
  commit that is not the code that made them. A file not yet made again (``rerun_pending``, from
  ``bench.record --pending``) says why instead, and names no dirty tree either;
- nothing in it (a key, a value, a line of a CSV beside it) is an absolute path of the machine
  that made it: a command is typed from the repository's root (`bench.harness.portable`), a file
  is named relative to the repository or the environment (`bench.harness.portable_path`).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

from bench.harness import REPO, RESULTS_DIR

FIELDS = ("command", "commit", "tree_clean", "date", "load_average", "machine", "versions")
#: An absolute path: ``/name`` where a token starts (POSIX), ``~/`` or ``C:\\`` (Windows).
ABSOLUTE_PATH = re.compile(r"(?:^|(?<=[\s\"'=:(,;\[{<]))(?:/[A-Za-z0-9._~-]|~/|[A-Za-z]:\\)")
#: The text files kept beside the JSON ones, checked for paths alone.
TEXT_SUFFIXES = (".csv", ".txt", ".md")


def result_files(results: Path = RESULTS_DIR) -> list[Path]:
    """The result files (module docstring): every JSON under ``results`` but a study's grids/."""
    return sorted(p for p in results.rglob("*.json") if "grids" not in p.relative_to(results).parts[1:2])


def text_files(results: Path = RESULTS_DIR) -> list[Path]:
    """The text files beside the result files (a study's CSV tables), but a study's grids/."""
    return sorted(p for p in results.rglob("*") if p.suffix in TEXT_SUFFIXES
                  and "grids" not in p.relative_to(results).parts[1:2])


def _strings(x) -> list[str]:
    """Every string of a JSON document, keys included."""
    if isinstance(x, dict):
        return [s for k, v in x.items() for s in (k, *_strings(v))]
    if isinstance(x, list):
        return [s for v in x for s in _strings(v)]
    return [x] if isinstance(x, str) else []


def machine_paths(strings) -> list[str]:
    """The strings that hold an absolute path."""
    return [s for s in strings if ABSOLUTE_PATH.search(s)]


def is_ancestor(commit: str, repo: Path = REPO) -> bool:
    """Whether ``commit`` is in the history of ``repo``'s HEAD (an unknown commit is not).

    Raises
    ------
    RuntimeError
        ``repo`` is no git checkout, or a shallow one (its history cut: nothing can be told).
    """
    shallow = subprocess.run(["git", "rev-parse", "--is-shallow-repository"], cwd=repo, capture_output=True,
                             text=True, timeout=30)
    if shallow.returncode != 0:
        raise RuntimeError(f"{repo} is not a git checkout: a result file's commit cannot be checked")
    if shallow.stdout.strip() == "true":
        raise RuntimeError(f"{repo} is a shallow clone: a result file's commit cannot be checked "
                           f"(git fetch --unshallow)")
    done = subprocess.run(["git", "merge-base", "--is-ancestor", commit, "HEAD"], cwd=repo,
                          capture_output=True, text=True, timeout=30)
    return done.returncode == 0


def problems(path: Path, repo: Path = REPO) -> list[str]:
    """What keeps the result file ``path`` from being checked (module docstring); [] if nothing."""
    if path.suffix != ".json":
        paths = machine_paths(path.read_text(errors="replace").splitlines())
        return [f"machine paths: {paths[:3]}"] if paths else []
    data = json.loads(path.read_text())
    prov = data.get("provenance") if isinstance(data, dict) else None
    if not isinstance(prov, dict):
        return ["no provenance"]
    out = []
    missing = [k for k in FIELDS if k not in prov]
    if missing:
        out.append(f"provenance lacks {missing}")
    paths = machine_paths(_strings(data))
    if paths:
        out.append(f"machine paths: {paths[:3]}")
    commit = prov.get("commit")
    if not commit:
        out.append("no commit")
    elif not is_ancestor(str(commit), repo):
        out.append(f"commit {commit} is not in the history of HEAD")
    if prov.get("tree_clean") is False:
        out.append("made from a tree with uncommitted changes (tree_clean: false)")
    if prov.get("rerun_pending"):
        if not prov.get("reason"):
            out.append("marked to be made again without a reason")
        return out
    if prov.get("tree_clean") is not True:
        out.append(f"tree_clean is {prov.get('tree_clean')!r}, not true")
    if not (prov.get("command") and prov.get("date") and prov.get("versions")
            and (prov.get("machine") or {}).get("cores")):
        out.append("command, date, versions or the machine's cores empty")
    load = prov.get("load_average") or {}
    if not (isinstance(load, dict) and load.get("before") and load.get("after")):
        out.append("no load average before and after")
    return out


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    files = [Path(a) for a in argv] or [*result_files(), *text_files()]
    bad = 0
    for f in files:
        for line in problems(f.resolve()):
            bad += 1
            print(f"{f}: {line}")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
