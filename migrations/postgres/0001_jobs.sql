-- Jobs, the tasks they are split into, and their results (PostgreSQL: several
-- instances share them). One job per distinct normalised spec (UNIQUE key).
CREATE TABLE jobs (
    id           TEXT PRIMARY KEY,           -- UUIDv7: time-ordered
    key          TEXT NOT NULL UNIQUE,       -- blake3 of the canonical spec + engine version
    kind         TEXT NOT NULL,
    spec         TEXT NOT NULL,              -- normalised spec, JSON
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'canceled')),
    error        TEXT,
    numerics     TEXT,
    created_at   TEXT NOT NULL,              -- RFC 3339, UTC
    started_at   TEXT,
    finished_at  TEXT
);
CREATE INDEX jobs_status ON jobs (status);
CREATE INDEX jobs_kind ON jobs (kind);

CREATE TABLE tasks (
    job_id       TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    idx          INTEGER NOT NULL,
    payload      TEXT NOT NULL,
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'done', 'canceled')),
    progress     DOUBLE PRECISION NOT NULL DEFAULT 0,
    result       TEXT,
    lease_owner  TEXT,
    lease_until  TIMESTAMPTZ,                -- database clock: instances may disagree
    attempts     INTEGER NOT NULL DEFAULT 0,
    done_by      TEXT,                       -- the worker whose result was kept
    created_at   TEXT NOT NULL,
    PRIMARY KEY (job_id, idx)
);
CREATE INDEX tasks_claim ON tasks (status, created_at, idx);

CREATE TABLE results (
    job_id  TEXT PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
    body    TEXT NOT NULL
);
