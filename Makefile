# Quick start: `make demo` and `make test` on a machine with only python3.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: demo test test-fast fuzz lint bench bench-recognition clean venv

venv: $(STAMP)

$(STAMP): pyproject.toml
	@echo "Installing tentaclass and its dependencies into $(VENV) (first run only; takes a few minutes)"
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,web,physics,outline,dask]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/tentaclass demo --out out

# every test, slow ones included, in one process; PYTEST_PARALLEL="-n auto --dist loadgroup"
# spreads them over all cores (pytest-xdist; slow tests start first)
PYTEST_PARALLEL ?=

test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/mypy src
	$(BIN)/python -m pytest -q $(PYTEST_PARALLEL)

# the slow tests (MPEG-7 sweeps, long simulations) left out
test-fast: $(STAMP)
	$(BIN)/python -m pytest -q $(PYTEST_PARALLEL) -m "not slow"

# the same properties with fresh random examples, many more of them
fuzz: $(STAMP)
	HYPOTHESIS_PROFILE=fuzz $(BIN)/python -m pytest -q -p no:cacheprovider tests

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
