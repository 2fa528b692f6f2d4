"""The package layers and the import graph: envdata -> acoustics -> tracker -> tools -> bench, no
circle (nothing below imports the benchmarks, which import no tests);
inside ``acoustics`` its sub-packages by role, inside ``acoustics.grid`` what a grid is and its
face below the atlas store below the one way in, inside ``tools`` the studies (which build
tables and run the trackers) below the commands that run them, the tracker never building
tables and reading them through the face alone.

Read from the source (every ``import`` statement, those inside functions too), so a lazy import
that closes a circle is caught as well as one at the top of a module.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
LAYERS = ("envdata", "acoustics", "tracker", "tools", "bench")
#: Inside ``acoustics``, by role, lowest first: the formulas at the root, the models (BELLHOP's
#: formats and running, RAM's), the grid (what a grid is and how it is read), the builders, the figures and the
#: BELLHOP3D Nx2D route (kept out of the build), the sensitivity studies on top. A module may
#: import its own sub-package and those ranked below it.
ACOUSTICS_RANKS = {"": 0, "bellhop": 1, "ram": 1, "grid": 2, "builder": 3, "plots": 4, "nx2d": 4,
                   "sensitivity": 5}
#: Inside ``tools``: the studies (``tmakit experiment``'s experiments; above both acoustics and
#: the tracker by the layers) below the command line and its command modules at the root.
TOOLS_RANKS = {"studies": 0, "": 1}
#: The optional Stone Soup plugin (the ``stonesoup`` extra, in the tracker's layer): the only
#: package of tmakit that imports Stone Soup.
STONESOUP_GLUE = "tracker.stonesoup"
#: The benchmark that runs Stone Soup's own filters beside tmakit's (not shipped; ``make bench``
#: installs the extra): the one other module that may import it.
STONESOUP_COMPARISON = "bench.bench_stonesoup"
#: Inside ``acoustics.grid``: what a grid is, its face and their kernels (rank 0, every module not
#: named), the atlas's store over them, and the one way in (``open_tables``) over both.
GRID_RANKS = {"atlas": 1, "opentables": 2}
#: What of ``acoustics.grid`` the tracker may import: the face and what it answers with (the level's
#: sd for P_D is the face's K error and the class's source level, read in one place).
FACE_MODULES = ("acoustics.grid.face", "acoustics.grid.levelprofile", "acoustics.grid.targetdepth",
                "acoustics.grid.detectionsigma")
#: What builds or computes tables: the tracker takes tables (the grid's face) and never these.
TABLE_MAKERS = ("acoustics.bellhop", "acoustics.ram", "acoustics.builder", "acoustics.nx2d",
                "acoustics.sensitivity")


def _modules() -> dict[str, Path]:
    mods = {}
    for layer in LAYERS:
        for path in (REPO / layer).rglob("*.py"):
            name = ".".join(path.relative_to(REPO).with_suffix("").parts)
            mods[name.removesuffix(".__init__")] = path
    return mods


def _lazy_tables(mods: dict[str, Path]) -> dict[str, dict[str, str]]:
    """package -> {name: module} of the re-exports its ``__init__`` declares with
    ``envdata.lazyexports.lazy_exports`` (imported on first use: arrows all the same)."""
    tables = {}
    for name, path in mods.items():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if (isinstance(node, ast.Call) and getattr(node.func, "id", None) == "lazy_exports"
                    and len(node.args) == 2 and isinstance(node.args[1], ast.Dict)):
                tables[name] = {ast.literal_eval(n): ast.literal_eval(k)
                                for k, v in zip(node.args[1].keys, node.args[1].values) for n in v.elts}
    return tables


def _graph(mods: dict[str, Path]) -> dict[str, set[str]]:
    """module -> the project modules it imports (``from pkg import submodule`` names the submodule,
    ``from pkg import name`` of a lazy re-export the module that defines it; a package's lazy
    re-export table counts as its imports)."""
    lazy = _lazy_tables(mods)
    graph: dict[str, set[str]] = {name: set(lazy.get(name, {}).values()) for name in mods}
    for name, path in mods.items():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                table = lazy.get(node.module, {})
                subs = [f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in mods else table[a.name]
                        for a in node.names if f"{node.module}.{a.name}" in mods or a.name in table]
                targets = subs if len(subs) == len(node.names) else [node.module, *subs]
            else:
                continue
            graph[name] |= {t for t in targets if t in mods and t != name}
    return graph


@functools.cache
def _project_graph() -> dict[str, frozenset[str]]:
    """The tree's import graph, read once for every test of this module (the checks only read it)."""
    return {name: frozenset(targets) for name, targets in _graph(_modules()).items()}


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []
    counter = 0
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        out.append(sorted(component))
    return out


def upward_layers(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Arrows from a layer to a higher one (`LAYERS`)."""
    rank = {layer: i for i, layer in enumerate(LAYERS)}
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if rank[b.split(".")[0]] > rank[a.split(".")[0]])


def test_no_layer_imports_a_higher_one():
    assert upward_layers(_project_graph()) == []


def test_the_layer_check_finds_an_upward_arrow():
    # planted: the tracker importing a study (the studies rank above it, in tools/), the formulas
    # importing the tracker, and a module of tools importing the benchmarks' harness (the circle
    # tools/stonesoup/example.py once drew); the studies' and the benchmarks' downward arrows stay
    # unflagged
    graph = {"tracker.track": {"tools.studies.gm", "acoustics.grid.face"},
             "acoustics.kcurve": {"tracker.ranging"},
             "tools.studies.gm": {"tracker.mltma.batch", "acoustics.grid.io", "envdata.area"},
             "tools.stonesoup.example": {"bench.harness", "tools.studies.idm"},
             "bench.bench_gm": {"tools.studies.gm", "bench.harness", "tracker.track"}}
    assert upward_layers(graph) == [("acoustics.kcurve", "tracker.ranging"),
                                    ("tools.stonesoup.example", "bench.harness"),
                                    ("tracker.track", "tools.studies.gm")]


def test_the_benchmarks_are_a_layer():
    # bench/ is scanned like the others (the check above then covers every arrow into it)
    mods = _modules()
    assert {"bench.harness", "bench.bench_rpf", "bench.bench_stonesoup"} <= set(mods)
    assert not [(a, b) for a, targets in _project_graph().items() for b in targets
                if b.startswith("bench") and not a.startswith("bench")]


def acoustics_rank(module: str) -> int:
    """Rank of an ``acoustics`` module's sub-package (`ACOUSTICS_RANKS`; a root module is 0)."""
    parts = module.split(".")
    sub = parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in ACOUSTICS_RANKS) else ""
    return ACOUSTICS_RANKS[sub] if module != "acoustics" else max(ACOUSTICS_RANKS.values()) + 1


def upward_in_acoustics(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Arrows from a lower sub-package of ``acoustics`` to a higher one."""
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if a.startswith("acoustics") and b.startswith("acoustics")
                  and acoustics_rank(b) > acoustics_rank(a))


def test_every_acoustics_subpackage_has_a_rank():
    subs = {p.name for p in (REPO / "acoustics").iterdir() if (p / "__init__.py").exists()}
    assert subs == set(ACOUSTICS_RANKS) - {""}


def test_no_acoustics_subpackage_imports_a_higher_one():
    assert upward_in_acoustics(_project_graph()) == []


def test_the_rank_check_finds_an_upward_arrow():
    # the check above could pass by finding nothing: a planted arrow from BELLHOP's package up to
    # the builders, and one from the root formulas up to the figures, are found; downward ones not
    graph = {"acoustics.bellhop.runner": {"acoustics.builder.executor", "acoustics.errors"},
             "acoustics.kcurve": {"acoustics.plots.figures"},
             "acoustics.plots.figures": {"acoustics.grid.face", "acoustics.kcurve"}}
    assert upward_in_acoustics(graph) == [("acoustics.bellhop.runner", "acoustics.builder.executor"),
                                          ("acoustics.kcurve", "acoustics.plots.figures")]


def grid_rank(module: str) -> int:
    """Rank of an ``acoustics.grid`` module (`GRID_RANKS`; 0 for what a grid is and its face)."""
    parts = module.split(".")
    return GRID_RANKS.get(parts[2], 0) if len(parts) > 2 else max(GRID_RANKS.values()) + 1


def upward_in_grid(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Arrows inside ``acoustics.grid`` from a lower rank to a higher one."""
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if a.startswith("acoustics.grid.") and b.startswith("acoustics.grid.")
                  and grid_rank(b) > grid_rank(a))


def tracker_past_the_face(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Arrows from the tracker into ``acoustics.grid`` beyond the face (`FACE_MODULES`)."""
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if a.split(".")[0] == "tracker" and b.startswith("acoustics.grid") and b not in FACE_MODULES)


def test_the_grid_core_the_atlas_and_the_way_in_stand_in_order():
    assert upward_in_grid(_project_graph()) == []
    mods = _modules()
    assert {"acoustics.grid.face", "acoustics.grid.opentables", "acoustics.grid.atlas.store",
            "acoustics.grid.atlas.follow", "acoustics.grid.atlas.format"} <= set(mods)


def test_the_tracker_reads_tables_through_the_face():
    assert tracker_past_the_face(_project_graph()) == []


def test_the_grid_and_face_checks_find_their_arrows():
    # planted: the face importing the atlas's following tables, the store importing the way in, the
    # tracker opening a store; allowed arrows (the atlas on the face, the way in on the store) unflagged
    graph = {"acoustics.grid.face": {"acoustics.grid.atlas.follow", "acoustics.grid.lookup"},
             "acoustics.grid.atlas.store": {"acoustics.grid.opentables", "acoustics.grid.checked"},
             "acoustics.grid.opentables": {"acoustics.grid.atlas.store", "acoustics.grid.face"},
             "tracker.track": {"acoustics.grid.atlas.store", "acoustics.grid.face"},
             "tracker.simulate": {"acoustics.grid.levelprofile", "acoustics.errors"}}
    assert upward_in_grid(graph) == [("acoustics.grid.atlas.store", "acoustics.grid.opentables"),
                                     ("acoustics.grid.face", "acoustics.grid.atlas.follow")]
    assert tracker_past_the_face(graph) == [("tracker.track", "acoustics.grid.atlas.store")]


def tools_rank(module: str) -> int:
    """Rank of a ``tools`` module (`TOOLS_RANKS`; a module at the root is a command's)."""
    parts = module.split(".")
    return TOOLS_RANKS[parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in TOOLS_RANKS) else ""]


def upward_in_tools(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Arrows from a study up to the command line."""
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if a.startswith("tools") and b.startswith("tools") and tools_rank(b) > tools_rank(a))


def tracker_table_makers(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Arrows from the tracker to a module that builds or computes tables."""
    return sorted((a, b) for a, targets in graph.items() for b in targets
                  if a.split(".")[0] == "tracker" and b.startswith(TABLE_MAKERS))


def test_the_studies_rank_below_the_commands():
    assert upward_in_tools(_project_graph()) == []


def test_the_tracker_never_builds_tables():
    assert tracker_table_makers(_project_graph()) == []


def test_the_studies_stand_above_the_tracker():
    # the studies build tables and run the trackers: they live in tools/, above both
    mods = _modules()
    assert not any(name.startswith("tracker.studies") for name in mods)
    assert "tools.studies.gm" in mods and "tools.studies.follow" in mods


def test_the_tools_and_tracker_checks_find_their_arrows():
    # planted: a study importing a command module, the tracker importing a builder (the arrow
    # the studies used to draw from tracker/), and allowed arrows that must stay unflagged
    graph = {"tools.studies.shelf": {"tools.experiment_cmd", "tools.studies.shelf_plot", "tracker.track"},
             "tools.experiment_cmd": {"tools.studies.shelf", "tools.report"},
             "tracker.studies.depth": {"acoustics.builder.gridfile", "acoustics.grid.face"},
             "tracker.simulate": {"acoustics.grid.face", "acoustics.levelrange"}}
    assert upward_in_tools(graph) == [("tools.studies.shelf", "tools.experiment_cmd")]
    assert tracker_table_makers(graph) == [("tracker.studies.depth", "acoustics.builder.gridfile")]


def external_imports(path: Path) -> set[str]:
    """The top-level names of every module ``path`` imports (those inside functions too)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module.split(".")[0])
    return out


def stonesoup_importers(mods: dict[str, Path]) -> list[str]:
    """Modules outside the Stone Soup plugin (and the benchmark comparing with it) that import Stone
    Soup."""
    return sorted(name for name, path in mods.items()
                  if not (name in (STONESOUP_GLUE, STONESOUP_COMPARISON) or name.startswith(STONESOUP_GLUE + "."))
                  and "stonesoup" in external_imports(path))


def test_only_the_glue_imports_stone_soup():
    # the core runs without the optional extra; `make demo` does not install it
    mods = _modules()
    assert stonesoup_importers(mods) == []
    assert "stonesoup" in external_imports(mods["tracker.stonesoup.model"])  # the scan sees the glue's


def test_the_stone_soup_check_finds_an_importer(tmp_path):
    planted = tmp_path / "face.py"
    planted.write_text("def f():\n    from stonesoup.types.state import State\n")
    assert stonesoup_importers({"acoustics.grid.face": planted, "tracker.stonesoup.x": planted,
                                "tracker.stonesoupish": planted, "bench.bench_stonesoup": planted,
                                "bench.bench_rpf": planted}) == ["acoustics.grid.face", "bench.bench_rpf",
                                                                 "tracker.stonesoupish"]


def test_the_import_graph_has_no_circle():
    assert _cycles(_project_graph()) == []


def test_the_cycle_finder_finds_a_circle():
    # the check above could pass by finding nothing at all: show it finds a planted circle
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert _cycles(graph) == [["a", "b", "c"]]


def bench_problems(sources: dict[str, str]) -> list[str]:
    """A benchmark importing from tests/ or editing sys.path (bench/ is a package run with -m)."""
    out = []
    for name, text in sources.items():
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.Import) and any(a.name.split(".")[0] == "tests" for a in node.names):
                out.append(f"{name}: imports tests")
            elif isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "tests":
                out.append(f"{name}: imports tests")
            elif isinstance(node, ast.Attribute) and node.attr == "path" and getattr(node.value, "id", "") == "sys":
                out.append(f"{name}: sys.path")
        out += [f"{name}: sys.path in code it runs" for line in text.splitlines()
                if "sys.path" in line and not line.lstrip().startswith("#")
                and ("insert(" in line or "[:0]" in line or "append(" in line)]
    return sorted(set(out))


def test_the_benchmarks_import_no_tests_and_edit_no_path():
    sources = {str(p.relative_to(REPO)): p.read_text() for p in (REPO / "bench").rglob("*.py")}
    assert bench_problems(sources) == []
    planted = {"a.py": "import sys\nsys.path.insert(0, 'bench')\n", "b.py": "from tests.x import y\n",
               "c.py": "CHILD = '''\nsys.path[:0] = ['x']\n'''\n"}
    assert bench_problems(planted) == ["a.py: sys.path", "a.py: sys.path in code it runs", "b.py: imports tests",
                                       "c.py: sys.path in code it runs"]
