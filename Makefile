# Developer shortcuts. Every target uses the project's virtual environment in .venv.
PY ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: setup demo test test-fast test-random lint format type bench clean docs

$(BIN)/python:
	$(PY) -m venv $(VENV)

# The CPU build of torch first: a plain `torch` requirement would pull a multi-GB CUDA build.
setup: $(BIN)/python
	$(BIN)/pip install -q torch==2.13.0 -e ".[dev]"

# the tools of the targets below, installed on first use (a fresh clone has none of them)
$(BIN)/pytest $(BIN)/ruff $(BIN)/mypy: $(BIN)/python
	$(BIN)/pip install -q torch==2.13.0 -e ".[dev]"

$(BIN)/sphinx-build: $(BIN)/python
	$(BIN)/pip install -q torch==2.13.0 -e ".[docs]"

demo: setup
	$(BIN)/radial-ibvs demo

test: setup
	$(BIN)/python -m pytest

# the fast subset (no training, no notebooks, no wheel build): a few minutes
test-fast: $(BIN)/pytest
	$(BIN)/python -m pytest -q -m "not slow"

# the property tests with new random draws, HYPOTHESIS_RUNS times over (CI draws the same
# examples every run: derandomised); a failure prints the draw to pin with @example
HYPOTHESIS_RUNS ?= 10
test-random: $(BIN)/pytest
	for i in $$(seq $(HYPOTHESIS_RUNS)); do \
		HYPOTHESIS_PROFILE=random $(BIN)/python -m pytest -q -p no:cacheprovider \
			$$(grep -rl "from hypothesis" tests --include="*.py") || exit 1; \
	done

lint: $(BIN)/ruff
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

format: $(BIN)/ruff
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .

type: $(BIN)/mypy
	$(BIN)/mypy

bench:
	$(BIN)/python benchmarks/bench_maths.py
	$(BIN)/python benchmarks/bench_envs.py
	$(BIN)/python benchmarks/bench_controllers.py
	$(BIN)/python benchmarks/bench_final_approach.py
	$(BIN)/python benchmarks/bench_pixels.py
	$(BIN)/python benchmarks/bench_training.py

clean:
	rm -rf $(VENV) build dist *.egg-info .pytest_cache .mypy_cache .ruff_cache .hypothesis outputs

# The documentation site: Sphinx, furo, MyST; warnings are errors. Built into build/docs.
docs: $(BIN)/sphinx-build
	$(BIN)/sphinx-build -E -W --keep-going -q -b html docs build/docs
