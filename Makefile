# Two commands do everything on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# pip's own notices (and a machine's index warnings) are not ours to show; errors still are.
PIP := $(BIN)/python -m pip --quiet --quiet --disable-pip-version-check
RUN_STAMP := $(VENV)/.installed-run
TEST_STAMP := $(VENV)/.installed-test
# The edit-test loop: everything but the slow, LaTeX and outside-oracle tests.
FAST := not slow and not needs_latex and not oracle
# `make bench`: QUICK is each script's short setting (QUICK= for the full runs, an hour or
# more); SCALING adds options to bench/derivation_scaling.py; SYMPYBOTICS is a SymPyBotics
# checkout (not on PyPI) for the scripts that run it (without it they say "not run").
QUICK ?= --quick
SCALING ?=
SYMPYBOTICS ?=
SB := $(if $(SYMPYBOTICS),--sympybotics $(SYMPYBOTICS))

.PHONY: run test test-fast lint bench clean generate

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip

# `make run` needs the runtime dependencies and plots only, not the test stack.
$(RUN_STAMP): $(BIN)/python pyproject.toml
	$(PIP) install -e '.[plot]'
	touch $(RUN_STAMP)

$(TEST_STAMP): $(BIN)/python pyproject.toml
	$(PIP) install -e '.[test]'
	touch $(RUN_STAMP) $(TEST_STAMP)

run: $(RUN_STAMP)
	$(BIN)/symkin show scara
	$(BIN)/symkin derive scara --out out/scara

generate: $(RUN_STAMP)
	$(BIN)/symkin generate

lint: $(TEST_STAMP)
	$(BIN)/ruff check src tests bench
	$(BIN)/lint-imports

test: $(TEST_STAMP)
	sh scripts/install-latex.sh
	$(MAKE) --no-print-directory lint
	$(BIN)/python -m pytest -q -n 2 --dist loadfile

test-fast: $(TEST_STAMP)
	$(BIN)/python -m pytest -q -n 2 --dist loadfile -m "$(FAST)"

# Every script in bench/ that writes a table into docs/benchmarks.md (each its own marked
# section, with the machine and the load average), one after the other: see bench/README.md.
bench: $(TEST_STAMP)
	$(PIP) install -e '.[test,bench]'
	$(BIN)/python bench/derivation_time.py $(QUICK) $(SB)
	$(BIN)/python bench/codegen_speed.py $(QUICK)
	$(BIN)/python bench/dynamics_speed.py $(QUICK)
	$(BIN)/python bench/inertial_parameters.py $(SB)
	$(BIN)/python bench/elastic_speed.py $(QUICK)
	$(BIN)/python bench/ik_speed.py $(QUICK)
	$(BIN)/python bench/trajopt_time.py $(QUICK)
	$(BIN)/python bench/trajopt_peers.py $(QUICK)
	$(BIN)/python bench/trajopt_guess.py $(QUICK)
	$(BIN)/python bench/derivation_scaling.py $(QUICK) $(SCALING) $(SB)
	$(BIN)/python bench/urdf_time.py
	$(BIN)/python bench/derivatives_speed.py $(QUICK)
	$(BIN)/python bench/identification_time.py
	$(BIN)/python bench/numpy_batch.py $(QUICK)

clean:
	rm -rf $(VENV) build dist src/*.egg-info .pytest_cache
