#!/bin/sh
# Start the Friction-Impact Explorer with `panel serve`, configured from environment variables.
# The Docker image's CMD runs this script; so does the deployment test.
#
#   APP_PATH                the Panel app to serve (default: app/main.py, page /main)
#   VENV                    virtual environment whose `panel` to use (default: .venv in the
#                           project root if it exists, else `panel` on PATH)
#   PORT                    port to listen on (default: 5006)
#   ADDRESS                 address to bind (default: 127.0.0.1; the image sets 0.0.0.0)
#   NUM_PROCS               worker processes, 0 = one per core (default: 1)
#   ALLOW_WEBSOCKET_ORIGIN  comma- or space-separated host[:port] list allowed to open the
#                           websocket, e.g. "explorer.school.example,10.0.0.5:5006"
#                           (default: localhost:$PORT,127.0.0.1:$PORT; "*" allows any)
#   SESSION_LIFETIME_MS     how long a session with no connection is kept (default: 30000)
#   CHECK_UNUSED_MS         how often unused sessions are looked for (default: 10000)
#   KEEP_ALIVE_MS           websocket keep-alive ping interval (default: 37000, Bokeh's)
#   WARM                    1 = run the app once at start-up (--warm) (default: 1)
#   PREFIX                  URL prefix when served under a sub-path behind a proxy (default: none)
#   USE_XHEADERS            1 = trust X-Forwarded-* headers from a reverse proxy (default: 0)
#   STATIC_DIRS             --static-dirs mapping (default: assets=static)
#   LOG_LEVEL               panel/bokeh log level (default: info)
# Any arguments are passed on to `panel serve` unchanged.
set -eu

ROOT=$(CDPATH='' cd -- "$(dirname -- "$0")/.." && pwd)
cd "$ROOT"

APP_PATH=${APP_PATH:-app/main.py}
PORT=${PORT:-5006}
ADDRESS=${ADDRESS:-127.0.0.1}
NUM_PROCS=${NUM_PROCS:-1}
ALLOW_WEBSOCKET_ORIGIN=${ALLOW_WEBSOCKET_ORIGIN:-localhost:$PORT,127.0.0.1:$PORT}
SESSION_LIFETIME_MS=${SESSION_LIFETIME_MS:-30000}
CHECK_UNUSED_MS=${CHECK_UNUSED_MS:-10000}
KEEP_ALIVE_MS=${KEEP_ALIVE_MS:-37000}
WARM=${WARM:-1}
PREFIX=${PREFIX:-}
USE_XHEADERS=${USE_XHEADERS:-0}
STATIC_DIRS=${STATIC_DIRS:-assets=static}
LOG_LEVEL=${LOG_LEVEL:-info}

if [ -n "${VENV:-}" ]; then
    PANEL=$VENV/bin/panel
elif [ -x "$ROOT/.venv/bin/panel" ]; then
    PANEL=$ROOT/.venv/bin/panel
else
    PANEL=panel
fi

if [ ! -f "$APP_PATH" ]; then
    echo "serve.sh: no app at $APP_PATH (set APP_PATH)" >&2
    exit 1
fi

# The app imports `core` from the project root, whichever directory it is served from.
PYTHONPATH="$ROOT${PYTHONPATH:+:$PYTHONPATH}"
export PYTHONPATH

# Build the argument list in "$@" (POSIX sh has no arrays): options are put in front of the
# caller's arguments, which therefore come last and can override them.
set -f  # no globbing: ALLOW_WEBSOCKET_ORIGIN may be "*"
if [ "$USE_XHEADERS" = 1 ]; then
    set -- --use-xheaders "$@"
fi
if [ -n "$PREFIX" ]; then
    set -- --prefix "$PREFIX" "$@"
fi
if [ "$WARM" = 1 ]; then
    set -- --warm "$@"
fi
if [ -n "$STATIC_DIRS" ]; then
    # Skip a mapping whose directory is missing (static/ may be empty and so absent from git).
    if [ -d "${STATIC_DIRS#*=}" ]; then
        set -- --static-dirs "$STATIC_DIRS" "$@"
    else
        echo "serve.sh: no directory ${STATIC_DIRS#*=}, not serving static files" >&2
    fi
fi
for origin in $(echo "$ALLOW_WEBSOCKET_ORIGIN" | tr ',' ' '); do
    set -- --allow-websocket-origin "$origin" "$@"
done
set -- "$APP_PATH" \
    --port "$PORT" \
    --address "$ADDRESS" \
    --num-procs "$NUM_PROCS" \
    --check-unused-sessions "$CHECK_UNUSED_MS" \
    --unused-session-lifetime "$SESSION_LIFETIME_MS" \
    --keep-alive "$KEEP_ALIVE_MS" \
    --log-level "$LOG_LEVEL" \
    --liveness \
    "$@"

echo "serve.sh: $PANEL serve $*"
exec "$PANEL" serve "$@"
