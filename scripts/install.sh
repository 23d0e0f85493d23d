#!/bin/sh
# Install the Friction-Impact Explorer with the versions pinned in constraints.txt.
#
# Usage: scripts/install.sh [--deps-only] [TARGET]
#
#   TARGET         a directory for a virtual environment (created if missing, reused if
#                  present), or "system" to install into the python found on PATH.
#                  Default: $VENV if set, else .venv in the project root.
#   --deps-only    install only the runtime dependencies listed in pyproject.toml, not the
#                  project itself (the Docker image does this first so that the layer with
#                  numpy/scipy/panel is cached while the source changes).
#
# Environment:
#   PYTHON   interpreter used to create the virtual environment (default: python3)
#   EXTRAS   optional extras to install with the project, e.g. "test" (default: none)
#   PIP_NO_CACHE_DIR etc. are honoured by pip as usual.
#
# The Docker image runs this script; CI runs it into a fresh virtual environment
# (tests/deploy/test_install_and_serve.py), so both install the same thing the same way.
set -eu

ROOT=$(CDPATH='' cd -- "$(dirname -- "$0")/.." && pwd)
PYTHON=${PYTHON:-python3}
EXTRAS=${EXTRAS:-}
DEPS_ONLY=0

while [ $# -gt 0 ]; do
    case "$1" in
        --deps-only) DEPS_ONLY=1; shift ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        -*) echo "install.sh: unknown option $1" >&2; exit 2 ;;
        *) break ;;
    esac
done
TARGET=${1:-${VENV:-$ROOT/.venv}}

if [ "$TARGET" = "system" ]; then
    PY=$PYTHON
else
    if [ ! -x "$TARGET/bin/python" ]; then
        echo "install.sh: creating virtual environment $TARGET"
        "$PYTHON" -m venv "$TARGET"
    fi
    PY=$TARGET/bin/python
fi

PIP="$PY -m pip --disable-pip-version-check"
CONSTRAINTS=$ROOT/constraints.txt

if [ "$DEPS_ONLY" = 1 ]; then
    # The runtime dependencies, read from pyproject.toml (needs Python >= 3.11 for tomllib).
    DEPS=$("$PY" - "$ROOT/pyproject.toml" <<'PYEOF'
import sys
import tomllib

with open(sys.argv[1], "rb") as f:
    print("\n".join(tomllib.load(f)["project"]["dependencies"]))
PYEOF
)
    echo "install.sh: installing dependencies only"
    # shellcheck disable=SC2086  # word splitting of $PIP and $DEPS is intended
    echo "$DEPS" | xargs $PIP install --quiet -c "$CONSTRAINTS"
else
    SPEC=$ROOT
    if [ -n "$EXTRAS" ]; then
        SPEC="${ROOT}[${EXTRAS}]"
    fi
    # Editable: the environment runs the source tree in place (as `make install` does), and no
    # build/ copy of the sources is left behind to go stale.
    echo "install.sh: installing $SPEC (editable)"
    # shellcheck disable=SC2086  # word splitting of $PIP is intended
    $PIP install --quiet -c "$CONSTRAINTS" --editable "$SPEC"
fi

"$PY" -c "import bokeh, panel; print('install.sh: panel', panel.__version__, 'bokeh', bokeh.__version__)"
