"""Cross-checks against other programs, and the result files they write.

The measuring code, shared by the tests (tests/acoustics/, which assert the bounds) and by the
writers of docs/results (run by hand, ``python -m bench.crosscheck.NAME``; not by ``make bench``:
they take minutes to hours and the side venvs ``make test`` makes):

- ``sidevenv``: the side venvs' interpreters; ``run_arlpy`` with ``arlpy_tl.py`` (arlpy 1.9.3 in
  .venv-arlpy, ``requirements-arlpy.txt``), ``kraken`` with ``kraken_tl.py`` (pelagic's KRAKEN in
  .venv-kraken, ``requirements-kraken.txt``; GPL-3.0, run as its own process, never imported),
  pyram's reference data (.venv-ref, ``requirements-ref.txt``);
- the cases: ``ram_cases`` (Pekeris, the ASA wedge, the deep Munk area), ``surface`` (the sea
  surface's references), ``radial`` (one shelf-break radial through tmakit's and arlpy's inputs),
  ``ram_wedge`` (the wedge benchmark);
- the writers: ``kraken_study`` (kraken.json), ``surface_study`` (surface.json), ``radial``
  (arlpy-radial.json), ``ram_wedge`` (ram-wedge.json), ``ram_band`` (ram-band.json),
  ``ram_convergence`` (ram-convergence.json), ``models_study`` (models-areas.json,
  ram-crossover.json).

This is bench's, not tests': the benchmarks import no tests, and the tests may import what they
measure with.
"""
