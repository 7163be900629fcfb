-- A job computed already, admitted and stored finished in one statement
-- (PostgreSQL): what `SqlStore::store_done_in` does in a transaction
-- elsewhere. $1: the job's (and computation's) id, $2 key, $3 kind, $4 spec,
-- $5 numerics, $6 created, $7 started, $8 finished, $9 tenant, $10 the task's
-- payload, $11 who computed it, $12 the result document, $13 1 when the
-- tenant is written as served (its row of `tenants` is then locked until
-- the commit), $14 the tenant's quota of live jobs and $15 the longest
-- queue (NULL: no limit).
--
-- The admission is read first, as `ADMISSION` (src/store/sql.rs) reads it,
-- and the job is stored only when its key has no computation and the limits
-- admit new work: what `AdmitLimits::admit_new` says. One row: `stored` 1,
-- or 0 (and nothing written), with what the admission read.
--
-- No part of it may hang on a parameter's value (such as counting only
-- under a limit): PostgreSQL then finds its custom plans cheaper than the
-- generic one and plans it anew at every execution, which costs about as
-- much as running it (tests/service/store.rs checks the two plans' costs).
WITH admission AS (
    SELECT
        (SELECT j.status FROM jobs j WHERE j.tenant = $9 AND j.computation_id = (SELECT id FROM computations WHERE key = $2)) AS own,
        (SELECT status FROM computations WHERE key = $2) AS computation,
        (SELECT COUNT(*) FROM jobs WHERE tenant = $9 AND status IN ('queued', 'running')) AS live,
        (SELECT COUNT(*) FROM computations WHERE status = 'queued') AS queued
), computation AS (
    INSERT INTO computations (id, key, kind, spec, status, numerics, created_at, started_at, finished_at, tenant, served_at)
    SELECT $1, $2, $3, $4, 'succeeded', $5, $6, $7, $8, $9, $7 FROM admission
    WHERE admission.computation IS NULL
      AND ($14::BIGINT IS NULL OR admission.live < $14::BIGINT)
      AND ($15::BIGINT IS NULL OR admission.queued < $15::BIGINT)
    ON CONFLICT (key) DO NOTHING
    RETURNING id
), task AS (
    INSERT INTO tasks (computation_id, idx, payload, status, progress, attempts, done_by, created_at)
    SELECT id, 0, $10, 'done', 1, 1, $11, $6 FROM computation
), result AS (
    INSERT INTO results (computation_id, body) SELECT id, $12 FROM computation
), served AS (
    INSERT INTO tenants (name, served_at) SELECT $9, $7 FROM computation WHERE $13 = 1
    ON CONFLICT (name) DO UPDATE SET served_at = excluded.served_at
), job AS (
    INSERT INTO jobs (id, tenant, computation_id, status, created_at, started_at, finished_at)
    SELECT id, $9, id, 'succeeded', $6, $7, $8 FROM computation
    RETURNING id
)
SELECT (SELECT COUNT(*) FROM job) AS stored, own, computation, live, queued FROM admission
