-- A job computed already, stored finished in one statement (PostgreSQL):
-- what `SqlStore::store_done_in` writes in a transaction elsewhere. $1: the
-- job's (and computation's) id, $2 key, $3 kind, $4 spec, $5 numerics,
-- $6 created, $7 started, $8 finished, $9 tenant, $10 the task's payload,
-- $11 who computed it, $12 the result document, $13 1 when the
-- tenant is written as served (its row of `tenants` is then locked until
-- the commit). One row, `stored` 0 (and
-- nothing written) when a computation of the key exists.
WITH computation AS (
    INSERT INTO computations (id, key, kind, spec, status, numerics, created_at, started_at, finished_at, tenant, served_at)
    VALUES ($1, $2, $3, $4, 'succeeded', $5, $6, $7, $8, $9, $7) ON CONFLICT (key) DO NOTHING
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
SELECT COUNT(*) AS stored FROM job
