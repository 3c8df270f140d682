# Developer shortcuts. Every target uses the project's virtual environment in .venv.
PY ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: setup demo test test-fast lint format type bench clean docs

$(BIN)/python:
	$(PY) -m venv $(VENV)

# The CPU build of torch first: a plain `torch` requirement would pull a multi-GB CUDA build.
setup: $(BIN)/python
	$(BIN)/pip install -q torch==2.13.0 -e ".[dev]"

demo: setup
	$(BIN)/radial-ibvs demo

test: setup
	$(BIN)/python -m pytest

test-fast:
	$(BIN)/python -m pytest -x -q -m "not slow"

lint:
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

format:
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .

type:
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
docs:
	$(BIN)/sphinx-build -E -W --keep-going -q -b html docs build/docs
