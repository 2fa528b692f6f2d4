"""The benchmarks: one module each, run from the repository's root as ``python -m bench.NAME``
(``make bench`` runs every ``bench_*`` module, ``bench/run.py``), all on one harness
(``bench.harness``: interleaved repeats, medians, the load average, the result file's provenance)."""
