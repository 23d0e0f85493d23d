#!/bin/sh
# Run the core and app tests on the declared minimum versions of the runtime dependencies.
#
# Usage: scripts/test-min-versions.sh [PYTEST_ARGS...]
#        (default: tests/core tests/app tests/ui/test_page_patches.py)
#
# Creates a fresh virtual environment (MIN_VENV, default $TMPDIR/friction-explorer-min-venv,
# removed first), installs exactly the lower bounds of pyproject.toml's [project]
# dependencies (scripts/min_versions.py: numpy==X, scipy==Y, ...), the test tools at the
# versions in constraints.txt and the project itself without dependencies, then runs pytest:
# the core and app tests (the notebook included) and one page in Chromium with the page's
# patches active (Debian's chromium: `make browser`).
# Dependencies of the dependencies (pandas, tornado, ...) are whatever pip resolves for those
# floors. Needs python3 >= 3.11 (tomllib) with venv.
set -eu

ROOT=$(CDPATH='' cd -- "$(dirname -- "$0")/.." && pwd)
cd "$ROOT"
PYTHON=${PYTHON:-python3}
MIN_VENV=${MIN_VENV:-${TMPDIR:-/tmp}/friction-explorer-min-venv}

PINS=$("$PYTHON" scripts/min_versions.py pyproject.toml)
echo "test-min-versions: declared minimums: $(echo "$PINS" | tr '\n' ' ')"

rm -rf "$MIN_VENV"
"$PYTHON" -m venv "$MIN_VENV"
PY=$MIN_VENV/bin/python
PIP="$PY -m pip --disable-pip-version-check"

# The test tools keep their pins from constraints.txt; the runtime dependencies' pins there
# (the newest tested versions) are left out, since the floors replace them.
TOOLS_CONSTRAINTS=$MIN_VENV/tools-constraints.txt
NAMES=$(echo "$PINS" | sed 's/==.*//' | paste -sd '|' -)
grep -v -i -E "^($NAMES)==" constraints.txt > "$TOOLS_CONSTRAINTS"

# shellcheck disable=SC2086  # word splitting of $PIP and $PINS is intended
$PIP install --quiet -c "$TOOLS_CONSTRAINTS" $PINS pytest pytest-timeout hypothesis mpmath radon \
    playwright nbclient nbformat ipykernel
# shellcheck disable=SC2086
$PIP install --quiet --no-deps --editable .

# What was installed is what was asked for (pip would have failed otherwise; say it anyway).
"$PY" - "$PINS" <<'PYEOF'
import sys
from importlib.metadata import version

from packaging.version import Version

wrong = []
for pin in sys.argv[1].split():
    name, wanted = pin.split("==")
    have = version(name)
    print(f"test-min-versions: {name} {have}")
    if Version(have) != Version(wanted):
        wrong.append(f"{name} {have} installed, {wanted} declared")
if wrong:
    sys.exit("test-min-versions: " + "; ".join(wrong))
PYEOF

if [ $# -eq 0 ]; then
    set -- tests/core tests/app tests/ui/test_page_patches.py
fi
exec "$PY" -m pytest -q -p no:cacheprovider "$@"
