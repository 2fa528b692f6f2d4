"""The engine of the generated figures: the block syntax, the registry of the pages' tables and
quotes, rendering a page, the quote check, and the command (``python -m bench.docfigures
[--check] [--root DIR]``).

A page holds each generated table between two markers naming it,

    <!-- docfigures grids -->
    | figure | measured | target |
    ...
    <!-- /docfigures -->

and one module of this package per page (every module but the engine's, ``common`` and
``__main__``) says, in its ``TABLES``, which function makes each of its blocks from the result
files, and in its ``QUOTES`` the figures its prose quotes. A block name two modules define is
refused: the registry does not guess which one a page means.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import re
import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from types import ModuleType

from bench.docfigures.common import load_result
from bench.harness import REPO

DESCRIPTION = "The tables in README and docs/ that quote a result file, generated from it: the one script."
PAGES = ("README.md", "docs/*.md")
BLOCK = re.compile(r"(<!-- docfigures (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /docfigures -->)", re.S)
#: The package's modules that are not a page's.
NOT_PAGES = ("common", "engine", "__main__")

#: (page, result file, keys into it: a key or a function of the value so far, how the page prints it).
Quote = tuple[str, str, tuple[str | int | Callable, ...], str]


class RegistryError(ValueError):
    """The pages' modules define the same block twice, or one lacks what a page module holds."""


def page_modules() -> list[ModuleType]:
    """Every page's module of this package, by name."""
    package = importlib.import_module("bench.docfigures")
    names = sorted(m.name for m in pkgutil.iter_modules(package.__path__) if m.name not in NOT_PAGES)
    return [importlib.import_module(f"bench.docfigures.{name}") for name in names]


def registry(modules: Iterable[ModuleType]) -> tuple[dict[str, Callable[[Path], str]], list[Quote]]:
    """Block name -> the function that makes it, and the prose quotes as (page, result file, keys,
    how the page prints it), from the pages' modules; a name defined twice is refused."""
    tables: dict[str, Callable[[Path], str]] = {}
    owner: dict[str, str] = {}
    quotes: list[Quote] = []
    for module in modules:
        if not hasattr(module, "PAGE") or not hasattr(module, "TABLES"):
            raise RegistryError(f"docfigures: page module {module.__name__} defines no PAGE or no TABLES")
        for name, make in module.TABLES.items():
            if name in tables:
                raise RegistryError(f"docfigures: table {name!r} is defined twice, in {owner[name]} and "
                                    f"{module.__name__}")
            tables[name], owner[name] = make, module.__name__
        quotes += [(module.PAGE, *quote) for quote in getattr(module, "QUOTES", ())]
    return tables, quotes


def stale_quotes(root: Path, quotes: Iterable[Quote]) -> list[str]:
    """The quotes whose printed value the page no longer holds, as ``page: file key (printed)``."""
    out, texts = [], {}
    for page, file, keys, fmt in quotes:
        text = texts.setdefault(page, (root / page).read_text())
        value = load_result(root, file)
        for key in keys:  # a key, or a function of what the keys before it found (a ratio, a minimum)
            value = key(value) if callable(key) else value[key]
        printed = fmt.format(value)
        if " ".join(printed.split()) not in " ".join(text.split()):  # line breaks in prose are free
            named = ".".join(getattr(k, "__name__", str(k)) for k in keys)
            out.append(f"{page}: {file} {named} ({printed!r})")
    return out


def pages(root: Path) -> list[Path]:
    return [p for pattern in PAGES for p in sorted(root.glob(pattern))]


def render(text: str, root: Path, where: str, tables: dict[str, Callable[[Path], str]]) -> tuple[str, list[str]]:
    """The page with every block made anew, and the names of the blocks that changed."""
    changed = []

    def one(m: re.Match) -> str:
        name = m["name"]
        if name not in tables:
            raise SystemExit(f"{where}: unknown docfigures block {name!r} (known: {', '.join(tables)})")
        body = tables[name](root)
        if body != m["body"]:
            changed.append(name)
        return m.group(1) + body + m.group(4)

    return BLOCK.sub(one, text), changed


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if a page differs")
    parser.add_argument("--root", type=Path, default=REPO, help="the checkout whose pages and results to use")
    args = parser.parse_args(argv)
    try:
        tables, quotes = registry(page_modules())
    except RegistryError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    stale = []
    for page in pages(args.root):
        text = page.read_text()
        new, changed = render(text, args.root, str(page), tables)
        stale += [f"{page.relative_to(args.root)}: {name}" for name in changed]
        if changed and not args.check:
            page.write_text(new)
    for line in stale:
        print(("differs from its result file: " if args.check else "rewrote ") + line)
    quoted = stale_quotes(args.root, quotes)
    for line in quoted:  # prose is the author's to rewrite: named, never changed
        print(f"quoted in prose, not what its result file gives: {line}")
    return 1 if (stale and args.check) or quoted else 0
