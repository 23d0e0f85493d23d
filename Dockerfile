# Friction-Impact Explorer: one image a teacher runs for a class.
#
#   docker build -t friction-explorer .
#   docker run -d --restart unless-stopped -p 5006:5006 \
#       -e ALLOW_WEBSOCKET_ORIGIN=explorer.school.example:5006 friction-explorer
#
# It does not start without ALLOW_WEBSOCKET_ORIGIN (the host:port students type); the log
# says what to set. nginx, inside the image, serves the page compressed in front of NUM_PROCS
# server processes (0 = one per core). See docs/deploy.md.
#
# The install and start steps live in scripts/install.sh and scripts/serve.sh, which CI also
# runs in a fresh virtual environment (tests/deploy/). CI builds this file with buildah, no
# Docker engine, on a stand-in for the base image, and serves from the built image
# (`make image-test`, scripts/image-test.sh). See docs/deploy.md.
FROM python:3.11-slim-bookworm

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    VENV=/opt/venv \
    PATH=/opt/venv/bin:$PATH

# nginx in front of the server processes (scripts/serve-behind-nginx.sh with
# docs/nginx-example.conf): compression, caching of the versioned static files, sticky
# sessions, per-client limits. jemalloc: the server's allocator, which gives a class's memory
# back once it has left (scripts/serve.sh, ALLOCATOR; docs/deploy.md "Memory"). Debian's own
# packages, the release's current versions.
# hadolint ignore=DL3008
RUN apt-get update \
    && apt-get install -y --no-install-recommends nginx libjemalloc2 \
    && rm -rf /var/lib/apt/lists/*

# An unprivileged user runs the server.
RUN groupadd --system --gid 10001 explorer \
    && useradd --system --uid 10001 --gid explorer --create-home --home-dir /home/explorer explorer

WORKDIR /srv/explorer

# Dependencies first (pinned by constraints.txt), so this layer is reused while the source changes.
COPY pyproject.toml constraints.txt ./
COPY scripts/install.sh scripts/
RUN scripts/install.sh --deps-only /opt/venv

# Then the project itself (.dockerignore keeps tests, docs, .git and .venv out).
COPY . .
RUN scripts/install.sh /opt/venv

USER 10001:10001

# Settings for scripts/serve.sh; override with `docker run -e NAME=value`.
# ALLOW_WEBSOCKET_ORIGIN has no default: the server refuses to start without it.
# BOKEH_SECRET_KEY, when set, signs the session ids. The classroom setup: nginx in front of
# one server process per core (NUM_PROCS=0; docs/deploy.md, "More than one process").
ENV PORT=5006 \
    ADDRESS=0.0.0.0 \
    NUM_PROCS=0 \
    PROXY=nginx \
    SESSION_LIFETIME_MS=6000 \
    CHECK_UNUSED_MS=2000 \
    WARM=1

EXPOSE 5006

# Panel's liveness endpoint (panel serve --liveness) answers 200 while the server is up.
HEALTHCHECK --interval=30s --timeout=5s --start-period=60s --retries=3 \
    CMD ["python", "-c", "import os, urllib.request; urllib.request.urlopen('http://127.0.0.1:%s/liveness' % os.environ.get('PORT', '5006'), timeout=4)"]

# nginx on $PORT in front of NUM_PROCS `panel serve app/main.py ... --warm` processes
CMD ["scripts/serve.sh"]
