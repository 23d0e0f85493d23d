# Two entry points: `make serve` and `make test`. Each creates .venv on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
PORT ?= 5006

$(BIN)/.installed: pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -c constraints.txt -e ".[test]"
	touch $@

.PHONY: install serve test test-random browser bench lint

install: $(BIN)/.installed

serve: install
	$(BIN)/panel serve app/main.py --port $(PORT) --static-dirs assets=static

# Debian's chromium drives the real-browser tests; install it if missing (needs root).
browser:
	@command -v chromium >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq chromium; \
	  else echo "chromium missing: sudo apt-get install -y chromium"; exit 1; fi; }

test: install browser
	$(BIN)/ruff check core app tests benchmarks
	$(BIN)/python -m pytest

# The property tests with fresh random examples, ten times as many as in CI (the suite
# itself runs them derandomized; see tests/conftest.py).
test-random: install
	HYPOTHESIS_PROFILE=random $(BIN)/python -m pytest -m hypothesis -p no:cacheprovider tests

bench: install
	$(BIN)/python benchmarks/solver_speed.py
