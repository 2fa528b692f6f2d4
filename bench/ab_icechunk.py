"""Plain Zarr 3 against icechunk (transactional Zarr) for the atlas's way of writing: one table at a time.

    make .venv-icechunk/.installed && .venv-icechunk/bin/python -m bench.ab_icechunk [--name icechunk]

An atlas writes each (month, origin) table into its own chunks and then sets its ``done`` flag
(acoustics/builder/atlas.py); a reader trusts only tables whose flag is set and whose chunks pass
their checksums, so a half-written table is never read as numbers. icechunk would give the same
guarantee by a transaction per table (the chunks and the flag in one commit). This measures what
each costs per table, side by side in one run, interleaved, medians of repeats:

- ``zarr``: region write of the table's chunk, then the flag's element (what the atlas does);
- ``icechunk``: a session per table, the same two writes, one commit;

and whether two writers can commit tables at once: icechunk rebases a commit onto the other
writer's; two commits that touch the same chunk (the ``done`` array is one small chunk) conflict,
and the loser must rebase with a conflict solver or retry. icechunk on a local or shared POSIX
file system also warns, as it runs, that such storage "is not safe for concurrent commits" from
several threads or processes (it wants an object store), which is the atlas's case: Dask workers
on a batch cluster writing to a shared file system. Not part of ``make bench``: icechunk is not
a tmakit dependency (its own venv, like Stone Soup's).
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import zarr

from bench.harness import git_state, load_average, provenance, write_result

#: One table: class x band x bearing x depth x range, float32 (about 4 MiB, a small atlas's).
TABLE = (3, 3, 12, 101, 300)
TABLES = 24


def plain_zarr(folder: Path, tables: np.ndarray) -> float:
    root = zarr.open_group(str(folder / "plain.zarr"), mode="w", zarr_format=3)
    _template(root)
    tl, done = root["tl_db"], root["done"]
    start = time.perf_counter()
    for i in range(TABLES):
        tl[i] = tables[i]
        done[i] = True
    return (time.perf_counter() - start) / TABLES


def _template(group) -> None:
    """The atlas-like layout: one chunk per table, the ``done`` flags in one chunk."""
    group.create_array("tl_db", shape=(TABLES, *TABLE), chunks=(1, *TABLE), dtype="float32",
                       fill_value=np.nan)
    group.create_array("done", shape=(TABLES,), chunks=(TABLES,), dtype="bool", fill_value=False)


def _ice_repository(folder: Path):
    """A new icechunk repository in ``folder`` with the template committed."""
    import icechunk

    repo = icechunk.Repository.create(icechunk.local_filesystem_storage(str(folder)))
    session = repo.writable_session("main")
    _template(zarr.open_group(session.store, mode="w", zarr_format=3))
    session.commit("template")
    return repo


def with_icechunk(folder: Path, tables: np.ndarray) -> float:
    repo = _ice_repository(folder / "ice")
    start = time.perf_counter()
    for i in range(TABLES):
        session = repo.writable_session("main")
        root = zarr.open_group(session.store, mode="r+")
        root["tl_db"][i] = tables[i]
        root["done"][i] = True
        session.commit(f"table {i}")
    return (time.perf_counter() - start) / TABLES


def two_writers(folder: Path, tables: np.ndarray) -> dict:
    """Two sessions from the same snapshot, each writing one table and its flag; both commit."""
    import icechunk

    repo = _ice_repository(folder / "ice2")
    a, b = repo.writable_session("main"), repo.writable_session("main")
    for s, i in ((a, 0), (b, 1)):
        r = zarr.open_group(s.store, mode="r+")
        r["tl_db"][i] = tables[i]
        r["done"][i] = True
    a.commit("table 0")
    outcome = {}
    try:
        b.commit("table 1")
        outcome["second_commit"] = "accepted"
    except icechunk.ConflictError as exc:
        outcome["second_commit"] = f"conflict: {type(exc).__name__}"
        try:
            b.rebase(icechunk.BasicConflictSolver())
            b.commit("table 1")
            outcome["after_rebase_with_basic_solver"] = "accepted"
        except Exception as exc2:  # noqa: BLE001 - what icechunk says is the finding
            outcome["after_rebase_with_basic_solver"] = f"{type(exc2).__name__}: {str(exc2)[:120]}"
    return outcome


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--name", default="icechunk", help="docs/results/NAME.json (default %(default)s)")
    args = parser.parse_args(argv)
    import icechunk

    load_before, git = load_average(), git_state()
    rng = np.random.default_rng(0)
    tables = rng.normal(80.0, 10.0, (TABLES, *TABLE)).astype(np.float32)
    times = {"zarr": [], "icechunk": []}
    for k in range(args.repeats):
        for name in (("zarr", "icechunk") if k % 2 == 0 else ("icechunk", "zarr")):
            folder = Path(tempfile.mkdtemp(prefix="ab-icechunk-"))
            try:
                times[name].append((plain_zarr if name == "zarr" else with_icechunk)(folder, tables))
            finally:
                shutil.rmtree(folder, ignore_errors=True)
    folder = Path(tempfile.mkdtemp(prefix="ab-icechunk-"))
    try:
        writers = two_writers(folder, tables)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    med = {k: statistics.median(v) for k, v in times.items()}
    result = {"table_shape": list(TABLE), "table_mib": tables[0].nbytes / 2**20, "tables": TABLES,
              "repeats": args.repeats,
              "seconds_per_table": times, "median_seconds_per_table": med,
              "icechunk_over_zarr": med["icechunk"] / med["zarr"], "two_writers": writers,
              "local_filesystem_storage": "icechunk warns at run time: not safe for concurrent commits "
                                          "from several threads or processes; prefer object stores"}
    for name, value in med.items():
        print(f"{name}_seconds_per_table: {value:.4f} s")
    print(f"icechunk_over_zarr: {result['icechunk_over_zarr']:.2f}")
    print(f"two_writers: {writers}")
    write_result(args.name, result, provenance_data=provenance(
        load_before=load_before, git=git, extra_versions={"zarr": zarr.__version__, "icechunk": icechunk.__version__}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
