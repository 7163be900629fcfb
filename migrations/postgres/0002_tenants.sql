-- Tenants (PostgreSQL). A job now belongs to one tenant and stands for a computation that
-- identical specs share: `computations` holds the work (one per cache key),
-- its tasks and its result; `jobs` holds each tenant's request for it, with
-- its own life (a tenant cancels or deletes its job, not another's). Jobs that
-- existed before become tenant `default`'s, under the same ids.
ALTER TABLE jobs RENAME TO computations;
ALTER INDEX jobs_pkey RENAME TO computations_pkey;
ALTER INDEX jobs_key_key RENAME TO computations_key_key;
DROP INDEX jobs_status;
DROP INDEX jobs_kind;
ALTER TABLE computations ADD COLUMN tenant TEXT NOT NULL DEFAULT 'default';   -- whose turn its tasks take
ALTER TABLE computations ADD COLUMN served_at TEXT NOT NULL DEFAULT '';       -- when a task of it was last claimed
ALTER TABLE tasks RENAME COLUMN job_id TO computation_id;
ALTER TABLE results RENAME COLUMN job_id TO computation_id;
DROP INDEX tasks_claim;

CREATE TABLE jobs (
    id              TEXT PRIMARY KEY,        -- UUIDv7: time-ordered
    tenant          TEXT NOT NULL,
    computation_id  TEXT NOT NULL REFERENCES computations (id),
    status          TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'canceled')),
    error           TEXT,
    created_at      TEXT NOT NULL,           -- RFC 3339, UTC
    started_at      TEXT,
    finished_at     TEXT,
    UNIQUE (tenant, computation_id)
);
INSERT INTO jobs (id, tenant, computation_id, status, error, created_at, started_at, finished_at)
    SELECT id, 'default', id, status, error, created_at, started_at, finished_at FROM computations;
CREATE INDEX jobs_tenant ON jobs (tenant, id);
CREATE INDEX jobs_computation ON jobs (computation_id);
CREATE INDEX jobs_finished ON jobs (finished_at) WHERE finished_at IS NOT NULL;

-- Round robin: tenants take turns by when they were last served, and so do
-- the computations of one tenant.
CREATE TABLE tenants (
    name       TEXT PRIMARY KEY,
    served_at  TEXT NOT NULL DEFAULT ''
);
INSERT INTO tenants (name) SELECT DISTINCT tenant FROM computations;

CREATE INDEX computations_live ON computations (tenant, served_at, created_at) WHERE status IN ('queued', 'running');
CREATE INDEX computations_status ON computations (status);
CREATE INDEX tasks_queued ON tasks (computation_id, idx) WHERE status = 'queued';
CREATE INDEX tasks_leased ON tasks (lease_until) WHERE status = 'running';

-- The readiness probe's row, as on SQLite.
CREATE TABLE probe (
    id  INTEGER PRIMARY KEY CHECK (id = 1),
    at  TEXT NOT NULL
);
