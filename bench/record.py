"""Provenance for result files that a command other than a benchmark writes (a study, a
cross-check), and the marker of a file not yet made again.

    python -m bench.record docs/results/locate.json -- python -m tools.studies.schmidt --out docs/results/locate.json
    python -m bench.record --pending docs/results/grids.json --command "python -m bench.bench_grids" \\
        --reason "reads BELLHOP tables: rerun after the sea-surface change"

The first form takes the load average, runs the command from the repository's root, and puts
the harness's ``provenance`` (the command, commit, tree state, date, load average before and
after, machine, versions) at the head of each JSON file named before ``--``, which the command
must have written anew. The second stamps a file whose figures were made before result files
carried their provenance: what the file itself says of how it was made (its commit, date and
load average, under their old names), the command that makes it again, and
``"rerun_pending": true`` with the reason; its figures are quoted as they are until then.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

from bench.harness import REPO, git_state, load_average, provenance

#: Old names of provenance fields a result file carried in its body.
_OLD_FIELDS = {"commit": "commit", "date": "date", "bench": "bench", "script": "script",
               "written_by": "written_by"}


def _stamp(path: Path, prov: dict) -> None:
    data = json.loads(path.read_text())
    if not isinstance(data, dict):
        data = {"results": data}
    data.pop("provenance", None)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps({"provenance": prov, **data}, indent=1, default=str) + "\n")
    tmp.replace(path)


def record(files: list[Path], command: list[str]) -> int:
    before, git = load_average(), git_state()  # the code that makes the files, before they are written
    mtimes = {f: f.stat().st_mtime if f.exists() else None for f in files}
    status = subprocess.run(command, cwd=REPO).returncode
    if status != 0:
        return status
    stale = [str(f) for f in files if not f.exists() or f.stat().st_mtime == mtimes[f]]
    if stale:
        raise SystemExit(f"record: the command did not write {', '.join(stale)}")
    prov = provenance(command=" ".join(command), load_before=before, git=git)
    for f in files:
        _stamp(f, prov)
        print(f"# provenance: {f.relative_to(REPO) if f.is_relative_to(REPO) else f}", flush=True)
    return 0


def mark_pending(path: Path, command: str, reason: str) -> None:
    """Stamp ``path`` as made before provenance was recorded, to be made again (module docstring)."""
    data = json.loads(path.read_text())
    body = data if isinstance(data, dict) else {}
    old = body.get("provenance") if isinstance(body.get("provenance"), dict) else {}
    found = {k: body[k] for k in _OLD_FIELDS if k in body}
    load = {"before": body.get("load_average_at_start", body.get("load_average_1min_at_start",
                                                                 body.get("load_average_1min"))),
            "after": body.get("load_average_at_end", body.get("load_average_1min_at_end"))}
    prov = {"command": command, "commit": old.get("commit", found.get("commit")),
            "tree_clean": old.get("tree_clean"), "date": old.get("date", found.get("date")),
            "load_average": old.get("load_average", load if any(v is not None for v in load.values()) else None),
            "machine": old.get("machine", {"cores": body["cores"]} if "cores" in body else None),
            "versions": old.get("versions"), "rerun_pending": True, "reason": reason,
            "as_written": {k: v for k, v in found.items() if k not in ("commit", "date")} or None}
    _stamp(path, prov)


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = []
    if "--" in argv:
        i = argv.index("--")
        argv, command = argv[:i], argv[i + 1:]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", type=Path)
    parser.add_argument("--pending", action="store_true", help="stamp the files as to be made again")
    parser.add_argument("--command", help="with --pending: the command that makes them again")
    parser.add_argument("--reason", help="with --pending: why they are not made again now")
    args = parser.parse_args(argv)
    files = [(f if f.is_absolute() else Path.cwd() / f).resolve() for f in args.files]
    if args.pending:
        if not (args.command and args.reason) or command:
            parser.error("--pending takes --command and --reason, and no command after --")
        for f in files:
            mark_pending(f, args.command, args.reason)
        return 0
    if not command:
        parser.error("give the command that writes the files after --")
    return record(files, command)


if __name__ == "__main__":
    sys.exit(main())
