#!/bin/bash
# Serve the explorer as several `panel serve` processes behind nginx with sticky sessions.
#
# Usage: scripts/serve-behind-nginx.sh [PANEL_SERVE_ARGS...]
#
# Starts one scripts/serve.sh process per port in UPSTREAM_PORTS and nginx (Debian's package)
# on PROXY_ADDRESS:PROXY_PORT with docs/nginx-example.conf, its `listen` line, its upstream's
# `server` lines and its sticky map's lines replaced by these ports (scripts/serve.sh does
# this by itself when NUM_PROCS > 1 or PROXY=nginx, as in the image). Students open
# http://PROXY_ADDRESS:PROXY_PORT/main. Runs in the foreground until stopped (Ctrl-C,
# SIGTERM) or until one of its processes exits; then it stops the others.
# tests/deploy/test_nginx.py runs it.
#
# Environment:
#   PROXY_ADDRESS   nginx's address (default 127.0.0.1)
#   PROXY_PORT      nginx's port (default 8086)
#   UPSTREAM_PORTS  the processes' ports, space-separated (default "5107 5108")
#   ORIGINS         host[:port] list students type, for --allow-websocket-origin
#                   (default PROXY_ADDRESS:PROXY_PORT and localhost:PROXY_PORT)
#   RUN_DIR         nginx's configuration, logs and the processes' logs (default: a new
#                   directory under /tmp, printed)
#   NGINX           the nginx binary (default: nginx on PATH, else /usr/sbin/nginx)
# and scripts/serve.sh's variables (VENV, SESSION_LIFETIME_MS, WARM, ...) for the processes.
# The processes bind 127.0.0.1, trust nginx's X-Forwarded-* headers (USE_XHEADERS=1) and leave
# compression to nginx (HTTP_GZIP=0).
set -euo pipefail

ROOT=$(CDPATH='' cd -- "$(dirname -- "$0")/.." && pwd)
PROXY_ADDRESS=${PROXY_ADDRESS:-127.0.0.1}
PROXY_PORT=${PROXY_PORT:-8086}
UPSTREAM_PORTS=${UPSTREAM_PORTS:-5107 5108}
ORIGINS=${ORIGINS:-$PROXY_ADDRESS:$PROXY_PORT,localhost:$PROXY_PORT}
RUN_DIR=${RUN_DIR:-$(mktemp -d /tmp/explorer-nginx.XXXXXX)}
NGINX=${NGINX:-$(command -v nginx || echo /usr/sbin/nginx)}
EXAMPLE=$ROOT/docs/nginx-example.conf

[ -x "$NGINX" ] || { echo "serve-behind-nginx: nginx is missing (apt-get install -y nginx)" >&2; exit 1; }
[ -f "$EXAMPLE" ] || { echo "serve-behind-nginx: $EXAMPLE is missing" >&2; exit 1; }
mkdir -p "$RUN_DIR"

PIDS=()
# shellcheck disable=SC2329  # run by the EXIT trap
cleanup() {
    local rc=$?
    trap - EXIT INT TERM
    for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

SERVERS=""
ROUTES=""
for port in $UPSTREAM_PORTS; do
    SERVERS="$SERVERS    server 127.0.0.1:$port max_fails=3 fail_timeout=30s;\n"
    ROUTES="$ROUTES    127.0.0.1:$port  127.0.0.1:$port;\n"
    PORT=$port ADDRESS=127.0.0.1 NUM_PROCS=1 PROXY=none USE_XHEADERS=1 HTTP_GZIP=0 \
        ALLOW_WEBSOCKET_ORIGIN=$ORIGINS \
        "$ROOT/scripts/serve.sh" "$@" \
        > >(tee "$RUN_DIR/serve-$port.log" | sed -u "s/^/[$port] /") 2>&1 &
    PIDS+=($!)
    echo "serve-behind-nginx: process $! on 127.0.0.1:$port (log $RUN_DIR/serve-$port.log," \
        "and here with [$port] in front)"
done

# The example's http-level snippet with these ports (the upstream's `server` lines and the
# sticky map's lines), inside a complete configuration whose paths are all under RUN_DIR (no
# root needed, nothing of the system's nginx touched).
SNIPPET=$(awk -v servers="$SERVERS" -v routes="$ROUTES" -v listen="$PROXY_ADDRESS:$PROXY_PORT" '
    /^[ \t]*server[ \t]+[0-9.]+:[0-9]+[^;]*;/ { next }
    /^[ \t]*[0-9.]+:[0-9]+[ \t]+[0-9.]+:[0-9]+;/ { next }
    /^[ \t]*least_conn;/ { print; printf "%s", servers; next }
    /^[ \t]*default[ \t]+explorer;/ { print; printf "%s", routes; next }
    { sub(/listen 80;/, "listen " listen ";"); print }' "$EXAMPLE")
cat >"$RUN_DIR/nginx.conf" <<EOF
pid $RUN_DIR/nginx.pid;
error_log $RUN_DIR/error.log warn;
worker_processes 1;
events { worker_connections 1024; }
http {
    client_body_temp_path $RUN_DIR/body;
    proxy_temp_path $RUN_DIR/proxy;
    fastcgi_temp_path $RUN_DIR/fastcgi;
    uwsgi_temp_path $RUN_DIR/uwsgi;
    scgi_temp_path $RUN_DIR/scgi;
    # Which upstream served each request, and the sticky cookie it carried.
    log_format upstream '\$request_uri \$status \$upstream_addr \$cookie_explorer_upstream';
    access_log $RUN_DIR/access.log upstream;
$SNIPPET
}
EOF
grep -q "listen $PROXY_ADDRESS:$PROXY_PORT;" "$RUN_DIR/nginx.conf" &&
    [ "$(grep -c '^ *server 127.0.0.1:' "$RUN_DIR/nginx.conf")" = "$(echo "$UPSTREAM_PORTS" | wc -w)" ] &&
    [ "$(grep -c '^ *127.0.0.1:[0-9]*  127.0.0.1:[0-9]*;' "$RUN_DIR/nginx.conf")" = "$(echo "$UPSTREAM_PORTS" | wc -w)" ] ||
    { echo "serve-behind-nginx: $EXAMPLE has changed shape (listen/least_conn/map/server lines)" >&2; exit 1; }
# -e: the error log from the start, before the configuration is read (the default path,
# /var/log/nginx, is not writable by an unprivileged user such as the image's).
"$NGINX" -t -q -e "$RUN_DIR/error.log" -p "$RUN_DIR" -c "$RUN_DIR/nginx.conf"
"$NGINX" -e "$RUN_DIR/error.log" -p "$RUN_DIR" -c "$RUN_DIR/nginx.conf" -g 'daemon off;' &
PIDS+=($!)
echo "serve-behind-nginx: nginx $! on http://$PROXY_ADDRESS:$PROXY_PORT/main (config and logs in $RUN_DIR)"
echo "serve-behind-nginx: pids ${PIDS[*]}"

# Stop everything as soon as any one of them exits.
wait -n
echo "serve-behind-nginx: a process exited; stopping the others" >&2
exit 1
