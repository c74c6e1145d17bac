# Two commands do everything on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: run test lint bench clean generate

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

run: $(STAMP)
	$(BIN)/symkin show scara
	$(BIN)/symkin derive scara --out out/scara

generate: $(STAMP)
	$(BIN)/symkin generate

test: $(STAMP)
	sh scripts/install-latex.sh
	$(BIN)/ruff check src tests bench
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check src tests bench

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[test,bench]'
	$(BIN)/python bench/derivation_time.py
	$(BIN)/python bench/codegen_speed.py
	$(BIN)/python bench/dynamics_speed.py
	$(BIN)/python bench/inertial_parameters.py

clean:
	rm -rf $(VENV) build dist src/*.egg-info .pytest_cache
