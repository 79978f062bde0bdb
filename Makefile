# Set-up and everyday commands. `make demo` and `make test` work on a fresh machine:
# they create .venv from a Python >= 3.12 and install the project into it.
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

VIZ_STAMP := $(VENV)/.viz-installed
DOCS_STAMP := $(VENV)/.docs-installed

.PHONY: demo test test-all test-slow lint format bench clean venv viz viz-setup docs docs-setup

venv: $(STAMP)

$(STAMP): pyproject.toml scripts/find_python.sh
	@PYTHON=$$(sh scripts/find_python.sh) && echo "using $$PYTHON ($$($$PYTHON --version))" && \
	  $$PYTHON -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[dev,calibrate]"
	@touch $(STAMP)

# The live browser view: Solara with its front-end assets fetched from npm (offline-safe).
viz-setup: $(VIZ_STAMP)

$(VIZ_STAMP): $(STAMP) scripts/solara_assets.sh
	$(PY) -m pip install --quiet -e ".[dev,viz]"
	sh scripts/solara_assets.sh $(PY) || echo "note: Solara's browser assets could not be fetched; the browser test will skip"
	@command -v chromium >/dev/null || echo "note: the browser test needs Debian's chromium (apt-get install -y chromium); it skips without it"
	@touch $(VIZ_STAMP)

viz: $(VIZ_STAMP)
	$(VENV)/bin/abm viz beacon-explorer

# The documentation site: tools from the `docs` extra, then a strict build into site/.
docs-setup: $(DOCS_STAMP)

$(DOCS_STAMP): $(STAMP)
	$(PY) -m pip install --quiet -e ".[dev,docs]"
	@touch $(DOCS_STAMP)

# NO_MKDOCS_2_WARNING / DISABLE_MKDOCS_2_WARNING silence two plugins' banners about MkDocs 2.
docs: $(DOCS_STAMP)
	NO_MKDOCS_2_WARNING=1 DISABLE_MKDOCS_2_WARNING=true $(VENV)/bin/mkdocs build --strict
	@echo "wrote site/ (open site/index.html)"

demo: $(STAMP)
	$(PY) examples/beacon_explorer.py

# The quick tier: every unit, property, contract and bad-input test, each model once.
test: $(VIZ_STAMP)
	$(PY) -m pytest -m "not slow"

# Everything: the quick tier and the slow one (browser pages, kill -9 recovery, long statistics,
# the documentation site's strict build).
test-all: $(VIZ_STAMP) $(DOCS_STAMP)
	$(PY) -m pytest

# Only what the quick tier leaves out (CI runs `make test` then this, so nothing runs twice).
test-slow: $(VIZ_STAMP) $(DOCS_STAMP)
	$(PY) -m pytest -m slow

lint: $(STAMP)
	$(VENV)/bin/ruff check . && $(VENV)/bin/ruff format --check .

format: $(STAMP)
	$(VENV)/bin/ruff format . && $(VENV)/bin/ruff check --fix .

bench: $(STAMP)
	$(PY) benchmarks/bench_beacon_explorer.py

clean:
	rm -rf $(VENV) .pytest_cache build site *.egg-info
