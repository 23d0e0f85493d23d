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

.PHONY: install serve test test-random browser bench lint nginx jemalloc test-min image-tools image-test

install: $(BIN)/.installed

serve: install
	$(BIN)/panel serve app/main.py --port $(PORT) --static-dirs assets=static

# Debian's chromium drives the real-browser tests; install it if missing (needs root).
browser:
	@command -v chromium >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq chromium; \
	  else echo "chromium missing: sudo apt-get install -y chromium"; exit 1; fi; }

test: install browser nginx jemalloc
	$(BIN)/ruff check core app tests benchmarks
	$(BIN)/python -m pytest
	# Once more without the patches of library internals (app/perf, static/perf).
	EXPLORER_PERF_PATCHES=off $(BIN)/python -m pytest tests/app tests/ui

# The property tests with fresh random examples, ten times as many as in CI (the suite
# itself runs them derandomized; see tests/conftest.py).
test-random: install
	HYPOTHESIS_PROFILE=random $(BIN)/python -m pytest -m hypothesis -p no:cacheprovider tests

bench: install
	$(BIN)/python benchmarks/solver_speed.py

# Debian's nginx fronts two server processes in tests/deploy/test_nginx.py; install it if
# missing (needs root).
nginx:
	@command -v nginx >/dev/null 2>&1 || [ -x /usr/sbin/nginx ] || { \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq nginx; \
	  else echo "nginx missing: sudo apt-get install -y nginx"; exit 1; fi; }

# Debian's jemalloc is the served processes' allocator (scripts/serve.sh, ALLOCATOR), tested
# in tests/app/test_memory.py and tests/deploy/; install it if missing (needs root).
jemalloc:
	@[ -n "$$(ls /usr/lib/*/libjemalloc.so.2 /usr/lib/libjemalloc.so.2 2>/dev/null)" ] || { \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq libjemalloc2; \
	  else echo "jemalloc missing: sudo apt-get install -y libjemalloc2"; exit 1; fi; }

# The core and app tests and one page in Chromium on the lowest versions pyproject.toml
# allows, in a fresh venv (scripts/test-min-versions.sh; needs python3 >= 3.11).
test-min: browser jemalloc
	PYTHON=$(PYTHON) scripts/test-min-versions.sh

# Debian's buildah, podman and debootstrap build and mount the image; install them if missing.
IMAGE_TOOLS := buildah podman debootstrap curl
image-tools:
	@missing=""; for t in $(IMAGE_TOOLS); do \
	  command -v $$t >/dev/null 2>&1 || [ -x /usr/sbin/$$t ] || missing="$$missing $$t"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && apt-get install -y -qq $(IMAGE_TOOLS); \
	  else echo "missing:$$missing: sudo apt-get install -y $(IMAGE_TOOLS)"; exit 1; fi; fi

# Build the Dockerfile with buildah (no Docker engine) and serve from the built image
# (scripts/image-test.sh; root).
image-test: image-tools
	scripts/image-test.sh
