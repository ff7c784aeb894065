# Quick start: `make demo` and `make test` on a machine with only python3.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: demo test test-fast fuzz lint bench bench-recognition clean venv

venv: $(STAMP)

EXTRAS := test,web,physics,outline,dask

# uv (from PyPI) downloads and installs in parallel: about 50 s against 2-3 minutes for
# pip on a fresh venv; pip installs instead wherever uv cannot be had or fails.
# Pre-releases are refused, as pip does, so both choose the same versions.
$(STAMP): pyproject.toml
	@echo "Installing tentaclass and its dependencies into $(VENV) (first run only)"
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	{ $(BIN)/python -m pip install --quiet uv \
	  && $(BIN)/uv pip install --quiet --prerelease disallow --python $(BIN)/python -e '.[$(EXTRAS)]'; } \
	|| $(BIN)/python -m pip install --quiet -e '.[$(EXTRAS)]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/tentaclass demo --out out

# every test, slow ones included, on two worker processes (pytest-xdist): the tests that
# share a costly set-up run on one worker, slow tests start first (conftest.py).
# PYTEST_PARALLEL= runs them in one process.
PYTEST_PARALLEL ?= -n 2 --dist loadgroup

test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/mypy src
	$(BIN)/python -m pytest -q $(PYTEST_PARALLEL)

# the slow tests (MPEG-7 sweeps, long simulations) left out
test-fast: $(STAMP)
	$(BIN)/python -m pytest -q $(PYTEST_PARALLEL) -m "not slow"

# the same properties with fresh random examples, many more of them (the hypothesis
# tests only: every other test is the same as in `make test`)
fuzz: $(STAMP)
	HYPOTHESIS_PROFILE=fuzz $(BIN)/python -m pytest -q -p no:cacheprovider $(PYTEST_PARALLEL) -m hypothesis tests

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/ruff format --check src tests benchmarks examples

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[test,bench]'
	$(BIN)/python benchmarks/run_all.py bench_fourier bench_dynamics bench_pnn bench_scanner bench_shift_nn bench_startup bench_wrap

# about an hour: every MPEG-7 setting against MiniRocket (needs ../shared/data)
bench-recognition: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[test,bench]'
	$(BIN)/python benchmarks/bench_recognition.py

clean:
	rm -rf $(VENV) out bench-results .pytest_cache
