# The two commands of the README: `make run` and `make test` do all the set-up.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: install lint run test unit bench soak clean

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	@# compat: the project folder on sys.path through a .pth, not an import hook (30 ms off every command's start)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e '.[test]' --config-settings editable_mode=compat
	touch $@

install: $(BIN)/.installed

ARGS ?=

run: install  ## start the whole system (Ctrl-C stops it); options with ARGS="--port 7448"
	$(BIN)/turtlectl launch $(ARGS)

lint: install  ## ruff: lint rules and formatting (configuration in pyproject.toml)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

test: lint  ## lint, then unit and multi-process integration tests
	$(BIN)/python -m pytest

unit: install  ## unit tests only
	$(BIN)/python -m pytest -m "not integration"

bench: install  ## benchmark figures (see README, Performance)
	$(BIN)/python bench/system.py
	$(BIN)/python bench/navigation.py
	$(BIN)/python bench/faults.py

soak: install  ## goals back to back for 30 minutes: zero errors, every node alive, RSS growth per process
	$(BIN)/python bench/system.py --minutes 30

clean:
	rm -rf $(VENV) *.egg-info .pytest_cache
