# Two commands on a fresh machine: `make run` (the default pipeline) and `make test`.
# Both create .venv with the machine's python3 when it is missing and install the project
# into it; the install is redone only when pyproject.toml changes (stamp file).

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
CORES ?= all
CONFIG ?= config/config.yaml
# optional extras tried one by one after the required ones (`make test OPTIONAL="cholmod
# cluster"`); one that does not install is reported and its tests skip
OPTIONAL ?=
# The Snakemake rules call the `cloth` CLI: put the venv first on PATH for them.
export PATH := $(CURDIR)/$(BIN):$(PATH)
export MPLBACKEND := Agg

.PHONY: run test test-slow test-cluster test-browser test-all lint unit bench clean install mutate

install: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,dev,view]'
	$(foreach extra,$(OPTIONAL),$(BIN)/python -m pip install --quiet -e '.[$(extra)]' || echo "make: the extra $(extra) did not install; its tests skip" >&2;)
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/snakemake --cores $(CORES) --configfile $(CONFIG)

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check cloth tests benchmarks
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/snakemake --lint --cores 1

# the fast suite on both cores (pytest-xdist; a module's tests stay on one worker, so its
# module-scoped fixtures are built once): every behaviour, no large grid (about 5 minutes)
unit: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadscope

test: lint unit

# large grids, full-size scans, the pipeline killed and resumed (tens of minutes; .ci/run)
test-slow: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadscope -m slow

# the pipeline through a single-node SLURM started by the test (root, Debian's slurmctld, slurmd
# and munge; the cluster extra); skipped with one line where it cannot start
test-cluster: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[cluster]' || echo "make: the extra cluster did not install; the cluster test skips" >&2
	$(BIN)/python -m pytest -q -rs -m cluster

# the interactive view drawn by a real Chromium (Debian's chromium); skipped without it
test-browser: $(STAMP)
	$(BIN)/python -m pytest -q -rs -m browser

# everything CI runs
test-all: test test-slow test-cluster test-browser

# mutation testing of the reporting modules with their tests (pyproject [tool.mutmut]); slow (CI
# does not run it): the survivors and why each is harmless or which test kills it are in
# docs/testing.md
mutate: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[mutate]'
	rm -rf mutants
	$(BIN)/mutmut run --max-children 2 || true
	$(BIN)/mutmut results

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[bench]'
	$(BIN)/python benchmarks/bench_mechanics.py
	$(BIN)/python benchmarks/bench_bodies.py

clean:
	rm -rf results results-* .snakemake
