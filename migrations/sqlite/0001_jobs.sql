-- Jobs and their results. One row per distinct normalised spec (UNIQUE key):
-- the same work is never queued twice.
CREATE TABLE jobs (
    id           TEXT PRIMARY KEY,           -- UUIDv7: time-ordered
    key          TEXT NOT NULL UNIQUE,       -- blake3 of the canonical spec + engine version
    kind         TEXT NOT NULL,
    spec         TEXT NOT NULL,              -- normalised spec, JSON
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'canceled')),
    progress     REAL NOT NULL DEFAULT 0,
    error        TEXT,
    numerics     TEXT,                       -- JSON summary once done
    created_at   TEXT NOT NULL,              -- RFC 3339, UTC
    started_at   TEXT,
    finished_at  TEXT,
    lease_owner  TEXT,                       -- worker that runs it
    lease_until  TEXT                        -- the lease lapses after this instant
);
CREATE INDEX jobs_status_created ON jobs (status, created_at);
CREATE INDEX jobs_created ON jobs (created_at, id);

CREATE TABLE results (
    job_id  TEXT PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
    body    TEXT NOT NULL                    -- the result document, JSON
);
