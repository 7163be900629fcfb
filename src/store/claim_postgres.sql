-- A claim in one statement (PostgreSQL): the rules of the claim made step by
-- step elsewhere (`SqlStore::next_task`), each step a CTE. $1: the owner,
-- $2: the lease, s; $3: 1 to take only tasks of computations already
-- running; $4: now (RFC 3339). No row when there is nothing to claim.
WITH lapsed AS MATERIALIZED (
    -- A task whose lease lapsed, first.
    SELECT computation_id, idx FROM tasks
    WHERE status = 'running' AND lease_until < now()
    ORDER BY lease_until LIMIT 1 FOR UPDATE SKIP LOCKED
), tenant AS MATERIALIZED (
    -- Else the tenant served longest ago that has a task ready.
    SELECT n.name FROM tenants n
    WHERE NOT EXISTS (SELECT 1 FROM lapsed)
    AND (SELECT c.id FROM computations c
         WHERE c.tenant = n.name AND c.status IN ('queued', 'running') AND ($3 = 0 OR c.status = 'running')
         AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status = 'queued') LIMIT 1) IS NOT NULL
    ORDER BY n.served_at, n.name LIMIT 1
), own AS MATERIALIZED (
    -- Its computation served longest ago.
    SELECT c.id FROM computations c
    WHERE c.tenant = (SELECT name FROM tenant) AND c.status IN ('queued', 'running') AND ($3 = 0 OR c.status = 'running')
    AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status = 'queued')
    ORDER BY c.served_at, c.created_at LIMIT 1 FOR UPDATE SKIP LOCKED
), anyone AS MATERIALIZED (
    -- Another instance is claiming from each of them at this moment: anyone's.
    SELECT c.id FROM computations c
    WHERE EXISTS (SELECT 1 FROM tenant) AND NOT EXISTS (SELECT 1 FROM own)
    AND c.status IN ('queued', 'running') AND ($3 = 0 OR c.status = 'running')
    AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status = 'queued')
    ORDER BY c.served_at, c.created_at LIMIT 1 FOR UPDATE SKIP LOCKED
), queued AS MATERIALIZED (
    -- Its first queued task.
    SELECT t.computation_id, t.idx FROM tasks t
    WHERE t.computation_id = (SELECT id FROM own UNION ALL SELECT id FROM anyone LIMIT 1)
    AND t.status = 'queued'
    ORDER BY t.idx LIMIT 1 FOR UPDATE SKIP LOCKED
), pick AS MATERIALIZED (
    SELECT computation_id, idx FROM lapsed
    UNION ALL SELECT computation_id, idx FROM queued
    LIMIT 1
), took AS (
    UPDATE tasks t SET status = 'running', lease_owner = $1, lease_until = now() + make_interval(secs => $2),
        attempts = t.attempts + 1
    FROM pick WHERE t.computation_id = pick.computation_id AND t.idx = pick.idx
    RETURNING t.computation_id, t.idx, t.payload, t.attempts
), computation AS (
    UPDATE computations c SET status = 'running', served_at = $4,
        started_at = COALESCE(c.started_at, CASE WHEN $4 > c.created_at THEN $4 ELSE c.created_at END)
    FROM took WHERE c.id = took.computation_id
    RETURNING c.id, c.kind, c.tenant
), jobs_running AS (
    UPDATE jobs j SET status = 'running', started_at = COALESCE(j.started_at, $4)
    FROM took WHERE j.computation_id = took.computation_id AND j.status = 'queued'
), served AS (
    UPDATE tenants n SET served_at = $4 FROM computation WHERE n.name = computation.tenant
)
SELECT took.computation_id, CAST(took.idx AS BIGINT) AS idx, took.payload,
    CAST(took.attempts AS BIGINT) AS attempts, computation.kind,
    (SELECT COUNT(*) FROM tasks WHERE computation_id = took.computation_id) AS tasks
FROM took JOIN computation ON computation.id = took.computation_id
