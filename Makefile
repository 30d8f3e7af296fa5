# The two commands of the README: `make run` and `make test` do all the set-up.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: install bytecode lint run test unit bench soak docs clean

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	@# compat: src/ (only the turtlectl package) on sys.path through a .pth, not an import hook (30 ms off every command's start)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e '.[test]' --config-settings editable_mode=compat
	touch $@

install: $(BIN)/.installed

# Our packages' bytecode, compiled where it is stale (pip does this for what it installs, not for an
# editable project): Python reads __pycache__ even where PYTHONDONTWRITEBYTECODE forbids writing it,
# and a launch otherwise compiles every module it imports each time (~100 ms of 0.4 s).
bytecode: install
	@$(BIN)/python -m compileall -q src messages runtime sim nodes cli

ARGS ?=

run: bytecode  ## start the whole system (Ctrl-C stops it); options with ARGS="--port 7448"
	TURTLECTL_MAKE_RUN=1 $(BIN)/turtlectl launch $(ARGS)

lint: install  ## ruff: lint rules and formatting (configuration in pyproject.toml)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

# the tests include a strict build of the documentation site (tests/unit/docs/test_site.py)
test: lint bytecode  ## lint, then unit and multi-process integration tests
	$(BIN)/python -m pytest

unit: bytecode  ## unit tests only
	$(BIN)/python -m pytest -m "not integration"

bench: bytecode  ## benchmark figures (see docs/explanation/performance.md)
	$(BIN)/python bench/system.py
	$(BIN)/python bench/navigation.py
	$(BIN)/python bench/faults.py

soak: bytecode  ## the capstone's five minutes without errors (tests marked soak), then goals back to back for 30 minutes: errors, nodes alive, RSS growth
	$(BIN)/python -m pytest -m soak
	$(BIN)/python bench/system.py --minutes 30

docs: install  ## the documentation site (mkdocs.yml, docs/) into site/
	$(BIN)/python -m mkdocs build --strict --site-dir site

clean:
	rm -rf $(VENV) *.egg-info .pytest_cache site
