# Set-up and everyday commands. `make demo` and `make test` work on a fresh machine:
# they create .venv from a Python >= 3.12 and install the project into it.
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test lint format bench clean venv

venv: $(STAMP)

$(STAMP): pyproject.toml scripts/find_python.sh
	@PYTHON=$$(sh scripts/find_python.sh) && echo "using $$PYTHON ($$($$PYTHON --version))" && \
	  $$PYTHON -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev]"
	@touch $(STAMP)

demo: $(STAMP)
	$(PY) examples/beacon_explorer_demo.py

test: $(STAMP)
	$(PY) -m pytest

lint: $(STAMP)
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check .

format: $(STAMP)
	$(VENV)/bin/ruff format . && $(VENV)/bin/ruff check --fix .

bench: $(STAMP)
	$(PY) benchmarks/bench_beacon_explorer.py

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info
