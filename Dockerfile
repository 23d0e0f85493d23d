# Friction-Impact Explorer: one image a teacher runs for a class.
#
#   docker build -t friction-explorer .
#   docker run --rm -p 5006:5006 -e NUM_PROCS=1 \
#       -e ALLOW_WEBSOCKET_ORIGIN=explorer.school.example friction-explorer
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
ENV PORT=5006 \
    ADDRESS=0.0.0.0 \
    NUM_PROCS=1 \
    ALLOW_WEBSOCKET_ORIGIN=localhost:5006 \
    SESSION_LIFETIME_MS=30000 \
    CHECK_UNUSED_MS=10000 \
    WARM=1

EXPOSE 5006

# Panel's liveness endpoint (panel serve --liveness) answers 200 while the server is up.
HEALTHCHECK --interval=30s --timeout=5s --start-period=60s --retries=3 \
    CMD ["python", "-c", "import os, urllib.request; urllib.request.urlopen('http://127.0.0.1:%s/liveness' % os.environ.get('PORT', '5006'), timeout=4)"]

# panel serve app/main.py --num-procs $NUM_PROCS --check-unused-sessions ... --warm
CMD ["scripts/serve.sh"]
