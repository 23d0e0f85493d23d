#!/bin/sh
# Start the Friction-Impact Explorer with `panel serve`, configured from environment variables.
# The Docker image's CMD runs this script; so does the deployment test.
#
#   APP_PATH                the Panel app to serve (default: app/main.py, page /main)
#   VENV                    virtual environment whose `panel` to use (default: .venv in the
#                           project root if it exists, else `panel` on PATH)
#   PORT                    port to listen on (default: 5006)
#   ADDRESS                 address to bind (default: 127.0.0.1; the image sets 0.0.0.0)
#   NUM_PROCS               server processes, 0 = one per core (default: 1)
#   PROXY                   nginx = serve through nginx with docs/nginx-example.conf
#                           (scripts/serve-behind-nginx.sh: compression, caching, sticky
#                           sessions, per-client limits), NUM_PROCS processes behind it;
#                           none = `panel serve` alone (--num-procs when NUM_PROCS > 1);
#                           auto = nginx when NUM_PROCS > 1 and nginx is installed
#                           (default: auto; the image sets nginx)
#   UPSTREAM_BASE_PORT      with nginx, the processes listen on 127.0.0.1 at this port + 1,
#                           + 2, ... (default: 15000)
#   ALLOW_WEBSOCKET_ORIGIN  comma- or space-separated host[:port] list allowed to open the
#                           websocket: what students type in the address bar, e.g.
#                           "explorer.school.example:5006,192.168.1.20:5006". Required when
#                           ADDRESS is not a loopback address (the server refuses to start
#                           without it); on loopback the default is
#                           localhost:$PORT,127.0.0.1:$PORT. "*" allows any origin (a warning
#                           is logged: a page of any web site may then open sessions here)
#   BOKEH_ALLOW_WS_ORIGIN   Bokeh's own setting, which would replace the list above inside
#                           the server, past the checks here: alone it is taken as
#                           ALLOW_WEBSOCKET_ORIGIN (same rules); beside a different
#                           ALLOW_WEBSOCKET_ORIGIN the server refuses to start; never passed on
#   BOKEH_SECRET_KEY        when set, session ids are signed with it (--session-ids signed):
#                           the server creates no session for an id it did not sign. Make one
#                           with `python -c "import secrets; print(secrets.token_urlsafe(32))"`
#                           (at least 32 characters); the same key for every process
#   SESSION_LIFETIME_MS     how long a session with no connection is kept (default: 6000)
#   CHECK_UNUSED_MS         how often unused sessions are looked for (default: 2000); a closed
#                           tab's session is discarded at most the sum of the two (8 s) after
#                           it closed: gone within 10 s, discarding a class's sessions included
#   KEEP_ALIVE_MS           websocket keep-alive ping interval (default: 37000, Bokeh's)
#   WARM                    1 = run the app once at start-up (--warm) (default: 1)
#   PREFIX                  URL prefix when served under a sub-path behind a proxy (default: none)
#   USE_XHEADERS            1 = trust X-Forwarded-* headers from a reverse proxy (default: 0)
#   STATIC_DIRS             --static-dirs mapping (default: assets=static)
#   LOG_LEVEL               panel/bokeh log level (default: info)
#   ALLOCATOR               the server's memory allocator: jemalloc = jemalloc (Debian's
#                           libjemalloc2, preloaded, with PYTHONMALLOC=malloc) for every
#                           object: a process gives back what a class that left used;
#                           pymalloc = Python's own: a process keeps its peak after a class;
#                           malloc = the C library's: gives it back, but each slider move
#                           and page costs more CPU; auto = jemalloc where installed, else
#                           pymalloc (default: auto; the image installs jemalloc)
#                           (docs/deploy.md "Memory")
#   HTTP_GZIP               1 = gzip the server's HTTP answers (app/serve_compressed.py);
#                           0 = plain `panel serve` (behind nginx, which compresses)
#                           (default: 1)
# Any arguments are passed on to `panel serve` unchanged.
set -eu

ROOT=$(CDPATH='' cd -- "$(dirname -- "$0")/.." && pwd)
cd "$ROOT"

APP_PATH=${APP_PATH:-app/main.py}
PORT=${PORT:-5006}
ADDRESS=${ADDRESS:-127.0.0.1}
NUM_PROCS=${NUM_PROCS:-1}
PROXY=${PROXY:-auto}
UPSTREAM_BASE_PORT=${UPSTREAM_BASE_PORT:-15000}
ALLOW_WEBSOCKET_ORIGIN=${ALLOW_WEBSOCKET_ORIGIN:-}
SESSION_LIFETIME_MS=${SESSION_LIFETIME_MS:-6000}
CHECK_UNUSED_MS=${CHECK_UNUSED_MS:-2000}
KEEP_ALIVE_MS=${KEEP_ALIVE_MS:-37000}
WARM=${WARM:-1}
PREFIX=${PREFIX:-}
USE_XHEADERS=${USE_XHEADERS:-0}
STATIC_DIRS=${STATIC_DIRS:-assets=static}
LOG_LEVEL=${LOG_LEVEL:-info}
HTTP_GZIP=${HTTP_GZIP:-1}

if [ -n "${VENV:-}" ]; then
    PANEL=$VENV/bin/panel
    PYTHON=$VENV/bin/python
elif [ -x "$ROOT/.venv/bin/panel" ]; then
    PANEL=$ROOT/.venv/bin/panel
    PYTHON=$ROOT/.venv/bin/python
else
    PANEL=panel
    PYTHON=python
fi

if [ ! -f "$APP_PATH" ]; then
    echo "serve.sh: no app at $APP_PATH (set APP_PATH)" >&2
    exit 1
fi

# Bokeh reads BOKEH_ALLOW_WS_ORIGIN at every websocket and lets it replace the list given on
# the command line: passed on, it would skip the rules below (a "*" without the warning).
# Here it is one more name for the same list, and it never reaches the server.
BOKEH_ALLOW_WS_ORIGIN=${BOKEH_ALLOW_WS_ORIGIN:-}
if [ -n "$BOKEH_ALLOW_WS_ORIGIN" ]; then
    if [ -z "$ALLOW_WEBSOCKET_ORIGIN" ]; then
        echo "serve.sh: taking BOKEH_ALLOW_WS_ORIGIN=$BOKEH_ALLOW_WS_ORIGIN as" \
            "ALLOW_WEBSOCKET_ORIGIN" >&2
        ALLOW_WEBSOCKET_ORIGIN=$BOKEH_ALLOW_WS_ORIGIN
    elif [ "$BOKEH_ALLOW_WS_ORIGIN" != "$ALLOW_WEBSOCKET_ORIGIN" ]; then
        cat >&2 <<EOF
serve.sh: BOKEH_ALLOW_WS_ORIGIN=$BOKEH_ALLOW_WS_ORIGIN and
ALLOW_WEBSOCKET_ORIGIN=$ALLOW_WEBSOCKET_ORIGIN differ; inside the server Bokeh would let the
first replace the second. Set ALLOW_WEBSOCKET_ORIGIN only (docs/deploy.md).
EOF
        exit 2
    fi
fi
unset BOKEH_ALLOW_WS_ORIGIN

# Students' browsers open the websocket from the address they typed; the server accepts only
# the origins listed. A server for other machines without that list would serve blank pages,
# so it does not start: the one who starts it sees why, not a class of students.
case "$ADDRESS" in
    127.*|localhost|::1) LOOPBACK=1 ;;
    *) LOOPBACK=0 ;;
esac
if [ -z "$ALLOW_WEBSOCKET_ORIGIN" ]; then
    if [ "$LOOPBACK" = 0 ]; then
        cat >&2 <<EOF
serve.sh: ALLOW_WEBSOCKET_ORIGIN is not set, and the server listens on $ADDRESS for other
machines. Set it to every host:port students type in the address bar, comma-separated, e.g.
    docker run ... -e ALLOW_WEBSOCKET_ORIGIN=explorer.school.example:$PORT,192.168.1.20:$PORT ...
    ALLOW_WEBSOCKET_ORIGIN=192.168.1.20:$PORT scripts/serve.sh
(without it their pages would load but stay blank). See docs/deploy.md.
EOF
        exit 2
    fi
    ALLOW_WEBSOCKET_ORIGIN=localhost:$PORT,127.0.0.1:$PORT
fi
case ",$(echo "$ALLOW_WEBSOCKET_ORIGIN" | tr ' ' ','),"  in
    *,\*,*)
        echo "serve.sh: WARNING: ALLOW_WEBSOCKET_ORIGIN=* accepts websockets from any origin:" \
            "a page of any web site a student visits may open sessions on this server." \
            "List the host:port students type instead." >&2 ;;
esac

case "$NUM_PROCS" in
    ''|*[!0-9]*) echo "serve.sh: NUM_PROCS must be a whole number >= 0, got '$NUM_PROCS'" >&2
                 exit 2 ;;
esac
case "${ALLOCATOR:-auto}" in
    auto|jemalloc|pymalloc|malloc) ;;
    *) echo "serve.sh: ALLOCATOR must be auto, jemalloc, pymalloc or malloc, got '$ALLOCATOR'" >&2
       exit 2 ;;
esac
if [ "$NUM_PROCS" = 0 ]; then
    NUM_PROCS=$(nproc 2>/dev/null || echo 1)
fi
if [ "$PROXY" = auto ]; then
    PROXY=none
    if [ "$NUM_PROCS" -gt 1 ] && { command -v nginx >/dev/null 2>&1 || [ -x /usr/sbin/nginx ]; }
    then
        PROXY=nginx
    fi
fi
case "$PROXY" in
    nginx)
        # One process per port behind nginx with sticky sessions (docs/deploy.md); each runs
        # this script again with PROXY=none and NUM_PROCS=1.
        UPSTREAM_PORTS=""
        i=1
        while [ "$i" -le "$NUM_PROCS" ]; do
            UPSTREAM_PORTS="$UPSTREAM_PORTS $((UPSTREAM_BASE_PORT + i))"
            i=$((i + 1))
        done
        PROXY_ADDRESS=$ADDRESS PROXY_PORT=$PORT ORIGINS=$ALLOW_WEBSOCKET_ORIGIN \
            UPSTREAM_PORTS=${UPSTREAM_PORTS# } \
            SESSION_LIFETIME_MS=$SESSION_LIFETIME_MS CHECK_UNUSED_MS=$CHECK_UNUSED_MS \
            exec "$ROOT/scripts/serve-behind-nginx.sh" "$@" ;;
    none) ;;
    *) echo "serve.sh: PROXY must be auto, nginx or none, got '$PROXY'" >&2
       exit 2 ;;
esac

# The app imports `core` from the project root, whichever directory it is served from.
PYTHONPATH="$ROOT${PYTHONPATH:+:$PYTHONPATH}"
export PYTHONPATH
# The allocator (docs/deploy.md "Memory"): the server's objects come from jemalloc where it
# is installed, which app/memory.py asks to give freed pages back after a class has left.
ALLOCATOR=${ALLOCATOR:-auto}
JEMALLOC=""
for lib in /usr/lib/*/libjemalloc.so.2 /usr/lib/libjemalloc.so.2; do
    if [ -f "$lib" ]; then JEMALLOC=$lib; break; fi
done
if [ "$ALLOCATOR" = auto ]; then
    ALLOCATOR=pymalloc
    if [ -n "$JEMALLOC" ]; then ALLOCATOR=jemalloc; fi
fi
case "$ALLOCATOR" in
    jemalloc)
        if [ -z "$JEMALLOC" ]; then
            echo "serve.sh: ALLOCATOR=jemalloc, but libjemalloc.so.2 is not installed" \
                "(Debian: apt-get install libjemalloc2)" >&2
            exit 2
        fi
        PYTHONMALLOC=malloc
        LD_PRELOAD="$JEMALLOC${LD_PRELOAD:+ $LD_PRELOAD}"
        export LD_PRELOAD ;;
    *) PYTHONMALLOC=$ALLOCATOR ;;  # pymalloc or malloc (checked above)
esac
export PYTHONMALLOC
echo "serve.sh: allocator $ALLOCATOR" >&2

# Build the argument list in "$@" (POSIX sh has no arrays): options are put in front of the
# caller's arguments, which therefore come last and can override them.
set -f  # no globbing: ALLOW_WEBSOCKET_ORIGIN may be "*"
if [ -n "${BOKEH_SECRET_KEY:-}" ]; then
    # Bokeh reads the key from the environment; ids it did not sign are refused.
    set -- --session-ids signed "$@"
fi
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

if [ "$HTTP_GZIP" = 1 ]; then
    # `panel serve` with Tornado's compress_response (app/serve_compressed.py).
    echo "serve.sh: $PYTHON -m app.serve_compressed (panel serve, gzip) $*"
    exec "$PYTHON" -m app.serve_compressed "$@"
fi
echo "serve.sh: $PANEL serve $*"
exec "$PANEL" serve "$@"
