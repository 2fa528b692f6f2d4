"""The tables in README and docs/ that quote a result file, generated from it: the one script.

A page holds each such table between two markers naming it,

    <!-- docfigures grids -->
    | figure | measured | target |
    ...
    <!-- /docfigures -->

``python -m bench.docfigures`` rewrites every block from its file; ``--check`` changes nothing and
exits 1 naming each block whose committed text differs from what its file gives (the test
tests/test_docfigures.py runs it in ``make test``). A table's caption names its file; a file
marked ``rerun_pending`` (bench.record) is quoted as it is, with the mark.

Figures quoted in prose are checked, not written: each page's ``QUOTES`` lists the result file,
the figure's place in it and how the page prints it, and ``--check`` names each whose printed
value the page no longer holds (a prose sentence is the author's; the check keeps it honest).

- ``engine``: the block syntax, the registry (a block name defined twice is refused), rendering,
  the quote check and the command;
- ``common``: reading a result file and its figures, the caption, the Markdown table;
- one module per page, each with its ``PAGE``, its tables' renderers in ``TABLES`` and its
  ``QUOTES`` (a quote's keys may end in a function of the value, for a figure the page derives:
  a ratio, the least of a file's cases); every page of README and docs/ has one
  (tests/test_docfigures.py), and one whose prose quotes nothing says why.
"""

from bench.docfigures.engine import RegistryError, main, page_modules, registry

__all__ = ["RegistryError", "main", "page_modules", "registry"]
