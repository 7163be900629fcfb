# syntax=docker/dockerfile:1
#
# topple HTTP service.
#
#   docker build -t topple .
#   docker run --rm -p 8080:8080 -v topple-data:/data topple
#
# The jobs database lives in the /data volume (sqlite:///data/topple.db).
# `docker run … topple run - < spec.json` runs one job spec without serving.

# ---- build ------------------------------------------------------------------
FROM rust:1-slim-bookworm AS build
WORKDIR /src
# The rust image already has gcc and libc6-dev, which is all the native code
# needs (bundled SQLite, ring). Migrations are embedded at compile time.
COPY . .
# Cache mounts keep the registry and target/ between builds, so a rebuild
# after a source change recompiles only topple. target/ is a cache mount, so
# the binary is copied out in the same step.
RUN --mount=type=cache,target=/usr/local/cargo/registry \
    --mount=type=cache,target=/usr/local/cargo/git \
    --mount=type=cache,target=/src/target \
    cargo build --release --locked \
    && install -m 0755 target/release/topple /usr/local/bin/topple

# ---- runtime ----------------------------------------------------------------
FROM debian:bookworm-slim
# hadolint ignore=DL3008
RUN apt-get update \
    && apt-get install -y --no-install-recommends ca-certificates \
    && rm -rf /var/lib/apt/lists/*
RUN groupadd --system --gid 10001 topple \
    && useradd --system --uid 10001 --gid topple --no-create-home \
       --home-dir /nonexistent --shell /usr/sbin/nologin topple \
    && mkdir -p /data \
    && chown topple:topple /data
COPY --from=build /usr/local/bin/topple /usr/local/bin/topple

# TOPPLE_SHUTDOWN_GRACE: on SIGTERM, running jobs get this long to finish
# before they are requeued (persisted in /data, resumed at the next start).
# 8 s keeps the whole shutdown inside `docker stop`'s default 10 s; raise both
# together (`docker stop -t`, compose `stop_grace_period`) for longer jobs.
ENV TOPPLE_ADDR=0.0.0.0:8080 \
    DATABASE_URL=sqlite:///data/topple.db \
    TOPPLE_SHUTDOWN_GRACE=8

WORKDIR /data
# Numeric, so that orchestrators can verify runAsNonRoot.
USER 10001:10001
EXPOSE 8080
VOLUME /data
# No HEALTHCHECK: the slim image has no HTTP client. Probe GET /healthz
# (liveness) and GET /readyz (readiness) from the orchestrator instead.
ENTRYPOINT ["/usr/local/bin/topple"]
CMD ["serve"]
