# syntax=docker/dockerfile:1
# Footprint: the web service, the map page and the Dask workers, in one image.
#
#   docker build -t footprint .
#   docker run -p 8000:8000 footprint          # SQLite in /data, an in-process Dask cluster
#   docker compose up                          # Postgres, a Dask scheduler and two workers (docker-compose.yml)
#
# Stages: `frontend` runs npm ci for the map page (its postinstall copies the libraries and map data the
# page loads into frontend/vendor/), `builder` installs the package into a venv, `runtime` copies both,
# runs as a non-root user and compiles the numba kernels once at build time into that user's cache.
# tests/deploy/ checks this file against the code (settings, routes, CLI, Python version).

# ---- the map page's libraries (leaflet, d3-geo, world-atlas) from the npm registry; npm ci's postinstall
# copies what the page and the folium maps load into frontend/vendor/, so node_modules is not kept
FROM node:20-bookworm-slim AS frontend
WORKDIR /src/frontend
COPY frontend/ ./
RUN if [ -f package.json ]; then npm ci --no-audit --no-fund && npm run --if-present build && rm -rf node_modules; fi

# ---- the package and its dependencies, in a venv that the runtime stage copies whole
FROM python:3.11-slim-bookworm AS builder
ENV PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1
RUN python -m venv /opt/venv
ENV PATH=/opt/venv/bin:$PATH
WORKDIR /src
COPY pyproject.toml README.md ./
COPY backend/ backend/
RUN pip install .

# ---- what runs
FROM python:3.11-slim-bookworm AS runtime
RUN groupadd --system --gid 10001 footprint \
    && useradd --system --uid 10001 --gid footprint --home-dir /home/footprint --create-home footprint \
    && mkdir -p /data \
    && chown footprint:footprint /data
COPY --from=builder /opt/venv /opt/venv
COPY --from=frontend /src/frontend /app/frontend
COPY examples/ /app/examples/
# the package is installed into the venv, not run from the source tree: tell the service where the page
# (with the vendor/ copies that the page and the folium maps use) and the Alembic migrations are
# (FOOTPRINT_FRONTEND_DIR, FOOTPRINT_MIGRATIONS_DIR below)
COPY migrations/ /app/migrations/
# numba's on-disk cache: backend/footprint/core/_jit.py puts it in $XDG_CACHE_HOME/footprint/numba-<numba
# version>-<hash of the core's sources>/ (NUMBA_CACHE_DIR, when set, wins instead); here a folder the
# runtime user owns, filled below by that user, so the API and the Dask workers start warm.
ENV PATH=/opt/venv/bin:$PATH \
    PYTHONUNBUFFERED=1 \
    XDG_CACHE_HOME=/home/footprint/.cache \
    FOOTPRINT_DATABASE_URL=sqlite:////data/footprint.db \
    FOOTPRINT_FRONTEND_DIR=/app/frontend \
    FOOTPRINT_MIGRATIONS_DIR=/app/migrations \
    FOOTPRINT_PORT=8000
USER footprint
WORKDIR /app
# Warm the cache: the first flight compiles every kernel (about 20 s); later processes load them in
# well under a second. numba keys cached code on the CPU, so a host with another CPU model recompiles
# once at first use, into the same (writable) folder.
RUN footprint fly examples/table2_lod22.json > /dev/null \
    && find "$XDG_CACHE_HOME/footprint" -name '*.nbi' | grep -q .
VOLUME ["/data"]
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=5s --start-period=60s --retries=3 \
    CMD ["python", "-c", "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/api/health', timeout=4)"]
CMD ["footprint", "serve", "--host", "0.0.0.0"]
