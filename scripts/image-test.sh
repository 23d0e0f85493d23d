#!/bin/bash
# Build the Dockerfile without a Docker engine and serve from the built image's file system.
#
# Usage: scripts/image-test.sh          (root; `make image-test` installs the tools first)
#
# 1. A stand-in for the Dockerfile's base image: where no image registry can be reached, the
#    FROM image (python:3.11-slim-bookworm) cannot be pulled, so a Debian bookworm root made by
#    `debootstrap --variant=minbase` with python3 (3.11 in bookworm), python3-venv,
#    python3-pip, python-is-python3 and ca-certificates is imported under that name. It is
#    NOT the official image: it has Debian's python3 in /usr/bin, not a python built into
#    /usr/local. The mirror is the one apt uses on this machine (/etc/apt/sources.list*),
#    or MIRROR. The root is cached as a tarball (BASE_CACHE) for the next run.
# 2. `buildah bud --isolation chroot --storage-driver vfs --format docker` builds the
#    Dockerfile (docker format keeps the HEALTHCHECK) into a storage of its own under WORKDIR;
#    pip in the build uses the host's CA bundle, mounted read-only.
# 3. The image's configuration is checked (user, health check, command), the image is mounted
#    (`podman image mount`) and its CMD runs there under `chroot --userspec=UID:GID` with the
#    image's ENV and WORKDIR (`podman run` cannot set rlimits in this sandbox): without
#    ALLOW_WEBSOCKET_ORIGIN it must refuse to start; with it (nginx in front of the server,
#    as the image runs), /liveness, /liveness?endpoint=/main and /main must answer.
# Everything (server, mounts, storage) is removed on exit, whatever the outcome; every long
# step has a time limit.
#
# Environment: IMAGE (default friction-explorer:image-test), PORT (default 5109),
#   WORKDIR (default a new directory under /var/tmp), BASE_CACHE (default
#   /var/cache/friction-explorer/standin-<FROM>.tar; BASE_CACHE= disables the cache),
#   MIRROR, BUILD_TIMEOUT (s, default 1800), KEEP_WORKDIR=1 (keep it for inspection).
set -euo pipefail

ROOT=$(CDPATH='' cd -- "$(dirname -- "$0")/.." && pwd)
cd "$ROOT"

IMAGE=${IMAGE:-friction-explorer:image-test}
PORT=${PORT:-5109}
BUILD_TIMEOUT=${BUILD_TIMEOUT:-1800}
CA_BUNDLE=/etc/ssl/certs/ca-certificates.crt
STANDIN_PACKAGES=python3,python3-venv,python3-pip,python-is-python3,ca-certificates

say() { echo "image-test: $*"; }
die() { echo "image-test: FAILED: $*" >&2; exit 1; }

[ "$(id -u)" = 0 ] || die "must run as root (debootstrap, chroot and mounts need it)"
for tool in buildah podman debootstrap chroot timeout curl tar; do
    command -v "$tool" >/dev/null 2>&1 ||
        die "$tool is missing: apt-get install -y buildah podman debootstrap curl (or: make image-tools)"
done
[ -r "$CA_BUNDLE" ] || die "no CA bundle at $CA_BUNDLE (apt-get install -y ca-certificates)"

# ---- the base image and its stand-in ----------------------------------------------------
FROM=$(awk 'toupper($1) == "FROM" { print $2; exit }' Dockerfile)
[ -n "$FROM" ] || die "no FROM line in Dockerfile"
case "$FROM" in
    python:3.11-slim-bookworm | python:3.11-slim | python:3.11-bookworm) ;;
    *) die "Dockerfile is FROM $FROM, but the stand-in is Debian bookworm with python 3.11:" \
           "update scripts/image-test.sh (suite and python version) together with the FROM" ;;
esac
SUITE=bookworm

# The Debian mirror apt uses here: deb822 (.sources) paragraphs or one-line (.list) entries
# whose suite is $SUITE exactly (not bookworm-security or -updates).
find_mirror() {
    local f
    for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
        [ -r "$f" ] || continue
        awk -v s="$SUITE" '$1 == "deb" { i = 2; if ($2 ~ /^\[/) { while ($i !~ /\]$/) i++; i++ }
                                        if ($(i + 1) == s) { print $i; exit } }' "$f"
    done
    for f in /etc/apt/sources.list.d/*.sources; do
        [ -r "$f" ] || continue
        awk -v s="$SUITE" 'BEGIN { RS = ""; FS = "\n" }
            { uri = ""; hit = 0
              for (i = 1; i <= NF; i++) {
                  if ($i ~ /^URIs:/) { split($i, a, " "); uri = a[2] }
                  if ($i ~ /^Suites:/) { n = split($i, b, " ");
                                         for (j = 2; j <= n; j++) if (b[j] == s) hit = 1 } }
              if (hit && uri != "") { print uri; exit } }' "$f"
    done
}
MIRROR=${MIRROR:-$(find_mirror | sed -n 1p)}  # sed reads to the end: no SIGPIPE under pipefail
[ -n "$MIRROR" ] || die "no $SUITE entry in /etc/apt/sources.list*: set MIRROR to a Debian mirror"

WORKDIR=${WORKDIR:-$(mktemp -d /var/tmp/friction-image-test.XXXXXX)}
mkdir -p "$WORKDIR"
STORE=(--root "$WORKDIR/storage" --runroot "$WORKDIR/run" --storage-driver vfs)
BASE_CACHE=${BASE_CACHE-/var/cache/friction-explorer/standin-${FROM//[:\/]/_}.tar}

SERVER_PID=
MOUNTED=
cleanup() {
    local rc=$?
    set +e
    if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
        kill -TERM -- "-$SERVER_PID" 2>/dev/null
        for _ in $(seq 1 20); do kill -0 "$SERVER_PID" 2>/dev/null || break; sleep 0.5; done
        kill -KILL -- "-$SERVER_PID" 2>/dev/null
    fi
    if [ -n "$MOUNTED" ]; then
        umount "$MOUNTED/dev/shm" "$MOUNTED/proc" 2>/dev/null
        podman "${STORE[@]}" image unmount --all >/dev/null 2>&1
    fi
    buildah "${STORE[@]}" rm --all >/dev/null 2>&1
    if [ "${KEEP_WORKDIR:-0}" = 1 ]; then
        say "kept $WORKDIR"
    else
        # Never follow a mount left behind into the host's /proc or /dev.
        if ! grep -q " $WORKDIR/" /proc/mounts; then
            rm -rf "$WORKDIR"
        else
            echo "image-test: mounts left under $WORKDIR, not removed:" >&2
            grep " $WORKDIR/" /proc/mounts >&2
        fi
    fi
    [ "$rc" = 0 ] && say "OK" || echo "image-test: FAILED (exit $rc), see above" >&2
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

t0=$(date +%s)
STANDIN_TAR=$WORKDIR/standin.tar
if [ -n "$BASE_CACHE" ] && [ -s "$BASE_CACHE" ]; then
    say "stand-in base from the cache $BASE_CACHE"
    cp "$BASE_CACHE" "$STANDIN_TAR"
else
    say "making the stand-in base: debootstrap --variant=minbase $SUITE from $MIRROR"
    timeout 900 debootstrap --variant=minbase --include="$STANDIN_PACKAGES" \
        "$SUITE" "$WORKDIR/rootfs" "$MIRROR" >"$WORKDIR/debootstrap.log" 2>&1 ||
        { tail -n 30 "$WORKDIR/debootstrap.log" >&2; die "debootstrap failed or timed out"; }
    chroot "$WORKDIR/rootfs" apt-get clean
    rm -rf "$WORKDIR/rootfs/var/lib/apt/lists/"*
    tar -C "$WORKDIR/rootfs" --numeric-owner -cf "$STANDIN_TAR" .
    rm -rf "$WORKDIR/rootfs"
    if [ -n "$BASE_CACHE" ]; then
        mkdir -p "$(dirname "$BASE_CACHE")"
        cp "$STANDIN_TAR" "$BASE_CACHE.tmp" && mv "$BASE_CACHE.tmp" "$BASE_CACHE"
    fi
fi
# The configuration the official python images have: PATH, LANG and python3 as the command.
timeout 300 podman "${STORE[@]}" import \
    --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
    --change 'ENV LANG=C.UTF-8' --change 'CMD ["python3"]' \
    --message "stand-in for $FROM: Debian $SUITE minbase with python3, made by image-test.sh" \
    "$STANDIN_TAR" "$FROM" >/dev/null || die "podman import of the stand-in base failed"
rm -f "$STANDIN_TAR"
py=$(podman "${STORE[@]}" image inspect --format '{{.Comment}}' "$FROM" 2>/dev/null || true)
say "stand-in $FROM ready after $(($(date +%s) - t0)) s ${py:+($py)}"

# ---- build ---------------------------------------------------------------------------------
t1=$(date +%s)
say "building $IMAGE (buildah bud --isolation chroot --storage-driver vfs --format docker)"
timeout "$BUILD_TIMEOUT" buildah "${STORE[@]}" bud \
    --isolation chroot --format docker --pull=never --layers=false \
    -v "$CA_BUNDLE:$CA_BUNDLE:ro" \
    -t "$IMAGE" -f Dockerfile . >"$WORKDIR/build.log" 2>&1 ||
    { tail -n 40 "$WORKDIR/build.log" >&2; die "buildah bud failed or took over $BUILD_TIMEOUT s"; }
grep -E "install.sh: panel" "$WORKDIR/build.log" | tail -n 1 | sed 's/^/image-test: built with /'
say "build took $(($(date +%s) - t1)) s"

# ---- the image's configuration -------------------------------------------------------------
CONFIG=$WORKDIR/config.json
podman "${STORE[@]}" image inspect "$IMAGE" >"$CONFIG"
eval "$(python3 - "$CONFIG" <<'PYEOF'
import json
import shlex
import sys

image = json.load(open(sys.argv[1]))[0]
cfg = image["Config"]


def healthchecks(node):
    """Every health check test in the inspect output (its place differs between versions)."""
    if isinstance(node, dict):
        for key, value in node.items():
            if key.lower() == "healthcheck" and isinstance(value, dict):
                yield value.get("Test") or []
            else:
                yield from healthchecks(value)
    elif isinstance(node, list):
        for item in node:
            yield from healthchecks(item)


hc = [part for test in healthchecks(image) for part in test]
problems = []
if cfg.get("User") != "10001:10001":
    problems.append(f"USER is {cfg.get('User')!r}, not 10001:10001")
if not any("/liveness" in part for part in hc):
    problems.append(f"no HEALTHCHECK on /liveness (is the format docker?): {hc}")
if cfg.get("Cmd") != ["scripts/serve.sh"]:
    problems.append(f"CMD is {cfg.get('Cmd')}")
print(f"PROBLEMS={shlex.quote('; '.join(problems))}")
print(f"IMG_ENV=({' '.join(shlex.quote(e) for e in cfg.get('Env') or [])})")
print(f"IMG_WORKDIR={shlex.quote(cfg.get('WorkingDir') or '/')}")
print(f"IMG_USER={shlex.quote(cfg.get('User') or '0:0')}")
print(f"IMG_CMD=({' '.join(shlex.quote(c) for c in cfg.get('Cmd') or [])})")
PYEOF
)"
[ -z "$PROBLEMS" ] || die "image configuration: $PROBLEMS"
say "image config: USER $IMG_USER, WORKDIR $IMG_WORKDIR, CMD ${IMG_CMD[*]}, HEALTHCHECK on /liveness"

# ---- serve from the image's file system ----------------------------------------------------
MNT=$(podman "${STORE[@]}" image mount "$IMAGE")
MOUNTED=$MNT
[ -d "$MNT$IMG_WORKDIR" ] || die "WORKDIR $IMG_WORKDIR is not in the image"
# Python's multiprocessing (the app's worker pool) needs /proc and a writable /dev/shm.
mkdir -p "$MNT/proc" "$MNT/dev/shm"
mount -t proc proc "$MNT/proc"
mount -t tmpfs -o size=256m,mode=1777 tmpfs "$MNT/dev/shm"
for dev in null zero random urandom; do
    [ -e "$MNT/dev/$dev" ] || cp -a "/dev/$dev" "$MNT/dev/$dev"
done

# Without ALLOW_WEBSOCKET_ORIGIN the image's CMD must refuse to start, saying what to set.
# shellcheck disable=SC2016  # $1 and $@ are the inner shell's
if timeout 60 chroot --userspec="$IMG_USER" "$MNT" /usr/bin/env -i "${IMG_ENV[@]}" \
        "HOME=/home/explorer" "PORT=$PORT" \
        /bin/sh -c 'cd "$1" && shift && exec "$@"' sh "$IMG_WORKDIR" "${IMG_CMD[@]}" \
        >"$WORKDIR/refused.log" 2>&1; then
    die "the image started without ALLOW_WEBSOCKET_ORIGIN"
fi
grep -q "ALLOW_WEBSOCKET_ORIGIN is not set" "$WORKDIR/refused.log" ||
    { cat "$WORKDIR/refused.log" >&2; die "no word of ALLOW_WEBSOCKET_ORIGIN from the image"; }
say "without ALLOW_WEBSOCKET_ORIGIN the image refuses to start and says what to set"

# The image's ENV, then what `docker run -e` would override: a loopback port of ours.
SERVE_ENV=("${IMG_ENV[@]}" "HOME=/home/explorer" "PORT=$PORT" "ADDRESS=127.0.0.1"
           "ALLOW_WEBSOCKET_ORIGIN=127.0.0.1:$PORT,localhost:$PORT")
say "serving: chroot --userspec=$IMG_USER $MNT, cd $IMG_WORKDIR, ${IMG_CMD[*]} on port $PORT"
# shellcheck disable=SC2016  # $1 and $@ are the inner shell's
setsid chroot --userspec="$IMG_USER" "$MNT" /usr/bin/env -i "${SERVE_ENV[@]}" \
    /bin/sh -c 'cd "$1" && shift && exec "$@"' sh "$IMG_WORKDIR" "${IMG_CMD[@]}" \
    >"$WORKDIR/serve.log" 2>&1 &
SERVER_PID=$!

BASE=http://127.0.0.1:$PORT
deadline=$(($(date +%s) + 180))
until curl -fs -o /dev/null --max-time 5 "$BASE/liveness"; do
    kill -0 "$SERVER_PID" 2>/dev/null || { cat "$WORKDIR/serve.log" >&2; die "the server exited"; }
    [ "$(date +%s)" -lt "$deadline" ] || { cat "$WORKDIR/serve.log" >&2; die "no /liveness in 180 s"; }
    sleep 1
done
say "/liveness answers"
curl -fsS --max-time 60 "$BASE/liveness?endpoint=/main" >/dev/null ||
    { cat "$WORKDIR/serve.log" >&2; die "/liveness?endpoint=/main failed (the app does not build)"; }
PAGE=$(curl -fsS --max-time 60 "$BASE/main") || { cat "$WORKDIR/serve.log" >&2; die "GET /main failed"; }
# Here-strings, not `echo | grep -q`: under pipefail a grep that quits at its first match
# makes echo die of SIGPIPE on a page larger than the pipe's buffer, and the check fails
# on a page that passes it. The same holds for `head`, so sed keeps reading to the end.
for needle in data-root-id bokeh; do
    grep -q "$needle" <<<"$PAGE" ||
        { sed -n 1,40p <<<"$PAGE" >&2; die "/main (${#PAGE} bytes, first lines above) has no '$needle'"; }
done
# BokehJS comes from the image too: the page's first script answers.
SCRIPT=$(grep -o 'src="[^"]*\.js[^"]*"' <<<"$PAGE" | sed -n '1{s/^src="//; s/"$//; p;}')
[ -n "$SCRIPT" ] || die "/main names no script"
case "$SCRIPT" in
    "$BASE"/*) ;;
    http*) die "the page loads its script from $SCRIPT, not from the server" ;;
    /*) SCRIPT=$BASE$SCRIPT ;;
    *) SCRIPT=$BASE/$SCRIPT ;;
esac
curl -fsS --max-time 60 -o /dev/null "$SCRIPT" || die "the page's script $SCRIPT does not load"
# The server runs as the image's user, not as root.
uid=$(awk '/^Uid:/ { print $2 }' "/proc/$SERVER_PID/status")
[ "$uid" = "${IMG_USER%%:*}" ] || die "the server runs as uid $uid, not ${IMG_USER%%:*}"
if grep -E "Traceback| ERROR" "$WORKDIR/serve.log" >&2; then die "errors in the server log"; fi
# Its processes' allocator is the image's jemalloc (ALLOCATOR=auto).
grep -q "serve.sh: allocator jemalloc" "$WORKDIR/serve.log" ||
    { cat "$WORKDIR/serve.log" >&2; die "the server does not run on jemalloc"; }
say "/liveness?endpoint=/main, /main (${#PAGE} bytes) and ${SCRIPT#"$BASE"} answer; server uid $uid"
say "total $(($(date +%s) - t0)) s"
