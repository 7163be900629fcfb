-- Jobs, the tasks they are split into, and their results. One job per distinct
-- normalised spec (UNIQUE key): the same work is never queued twice.
CREATE TABLE jobs (
    id           TEXT PRIMARY KEY,           -- UUIDv7: time-ordered
    key          TEXT NOT NULL UNIQUE,       -- blake3 of the canonical spec + engine version
    kind         TEXT NOT NULL,
    spec         TEXT NOT NULL,              -- normalised spec, JSON
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'canceled')),
    error        TEXT,
    numerics     TEXT,                       -- JSON summary once done
    created_at   TEXT NOT NULL,              -- RFC 3339, UTC
    started_at   TEXT,
    finished_at  TEXT
);
CREATE INDEX jobs_status ON jobs (status);
CREATE INDEX jobs_kind ON jobs (kind);

-- A job's work: one task, or for a spectrum one per chunk of frequencies. Any
-- worker may claim a queued task, or a running one whose lease lapsed.
CREATE TABLE tasks (
    job_id       TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    idx          INTEGER NOT NULL,
    payload      TEXT NOT NULL,              -- the task's own job spec, JSON
    status       TEXT NOT NULL CHECK (status IN ('queued', 'running', 'done', 'canceled')),
    progress     REAL NOT NULL DEFAULT 0,
    result       TEXT,                       -- the task's result document, JSON
    lease_owner  TEXT,
    lease_until  TEXT,                       -- RFC 3339; the lease lapses after it
    attempts     INTEGER NOT NULL DEFAULT 0,
    done_by      TEXT,                       -- the worker whose result was kept
    created_at   TEXT NOT NULL,
    PRIMARY KEY (job_id, idx)
);
CREATE INDEX tasks_claim ON tasks (status, created_at, idx);

CREATE TABLE results (
    job_id  TEXT PRIMARY KEY REFERENCES jobs (id) ON DELETE CASCADE,
    body    TEXT NOT NULL                    -- the result document, JSON
);
