# The two commands of the README: `make run` and `make test` do all the set-up.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin

.PHONY: install ros2-side browser bytecode lint run test unit bench soak docs clean

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	@# compat: src/ (only the turtlectl package) on sys.path through a .pth, not an import hook (30 ms off every command's start)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e '.[test,ros2]' --config-settings editable_mode=compat
	touch $@

install: $(BIN)/.installed

# A student's ROS 2 side for the tests: the real rclpy wheels from PyPI (Fast DDS), in a venv of their
# own (their bootstrapper re-executes every Python of its venv to set LD_LIBRARY_PATH, which turtlectl's
# processes need not pay). tests/integration/ros2_side.py runs its processes.
ROS2_VENV ?= .venv-ros2
ROS2_WHEELS := ros-rclpy ros-geometry-msgs ros-sensor-msgs ros-std-msgs ros-std-srvs ros-nav-msgs \
	ros-rosgraph-msgs ros-rcl-interfaces ros-rmw-fastrtps-cpp
$(ROS2_VENV)/.installed:
	$(PYTHON) -m venv $(ROS2_VENV)
	$(ROS2_VENV)/bin/python -m pip install --quiet --disable-pip-version-check $(ROS2_WHEELS)
	touch $@

ros2-side: $(ROS2_VENV)/.installed

# The browser tests (tests/integration/browser.py) drive a Chromium through Playwright, whose pip package brings
# no browser: Debian's from apt (about 40 s, once), as root or through sudo, when none is on PATH.
# TURTLECTL_CHROMIUM names another Chromium executable instead (the tests then use it; nothing is installed).
CHROMIUM_INSTALL := apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium
browser:
	@if [ -n "$$TURTLECTL_CHROMIUM" ] || command -v chromium >/dev/null; then exit 0; \
	elif ! command -v apt-get >/dev/null; then \
		echo "make test needs Chromium: install it, or set TURTLECTL_CHROMIUM to its executable" >&2; exit 1; \
	elif [ "$$(id -u)" = 0 ]; then $(CHROMIUM_INSTALL); \
	elif command -v sudo >/dev/null; then sudo sh -c '$(CHROMIUM_INSTALL)'; \
	else echo "make test needs Chromium: run \`$(CHROMIUM_INSTALL)\` as root (or set TURTLECTL_CHROMIUM)" >&2; exit 1; fi

# Our packages' bytecode, compiled where it is stale (pip does this for what it installs, not for an
# editable project): Python reads __pycache__ even where PYTHONDONTWRITEBYTECODE forbids writing it,
# and a launch otherwise compiles every module it imports each time (~100 ms of 0.4 s).
bytecode: install
	@$(BIN)/python -m compileall -q src messages runtime sim nodes cli

ARGS ?=
# the web page's port (`launch --web`): open http://127.0.0.1:8080/ while it runs; WEB= serves none
WEB ?= 8080

run: bytecode  ## start the whole system and its web page (Ctrl-C stops it); options with ARGS="--port 7448", WEB=8081
	TURTLECTL_MAKE_RUN=1 TURTLECTL_MAKE_WEB=$(WEB) $(BIN)/turtlectl launch $(ARGS) $(if $(WEB),--web $(WEB))

lint: install  ## ruff: lint rules and formatting (configuration in pyproject.toml)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

# the tests include a strict build of the documentation site (tests/unit/docs/test_site.py)
test: lint bytecode ros2-side browser  ## lint, then unit and multi-process integration tests
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
	rm -rf $(VENV) $(ROS2_VENV) *.egg-info .pytest_cache site
