//! PostgreSQL storage: several instances share jobs, tasks and the cache.
//! Tasks are claimed with `FOR UPDATE SKIP LOCKED` under leases on the
//! database clock; LISTEN/NOTIFY wakes idle workers everywhere.

use std::sync::Arc;
use std::time::Duration;

use sqlx::postgres::{PgListener, PgPoolOptions};
use sqlx::{PgPool, Row};
use tokio::sync::Notify;
use uuid::Uuid;

use super::sqlite::parse_id;
use super::{BoxFuture, JobRecord, JobStore, ListQuery, Status, StoreError, Submitted, TaskClaim};

/// The channel that announces queued work.
const CHANNEL: &str = "topple_tasks";

/// Longest wait for a connection: past it a request fails with 503.
const ACQUIRE_TIMEOUT: Duration = Duration::from_millis(1500);

/// Longest pause between attempts to listen again after the connection was
/// lost (the pauses double from 100 ms up to it).
const LISTEN_BACKOFF_MAX: Duration = Duration::from_secs(3);

/// Wakes idle workers at each notification on [`CHANNEL`], for as long as the
/// pool is open. A lost connection (the database restarted, or the network
/// failed) is listened on again, with a backoff, for as long as it takes; the
/// workers poll meanwhile, and are woken once listening resumes in case work
/// was queued while it was down.
async fn listen(pool: PgPool, mut listener: PgListener, wake: Arc<Notify>) {
    loop {
        match listener.recv().await {
            Ok(_) => wake.notify_waiters(),
            Err(e) => {
                if pool.is_closed() {
                    return;
                }
                tracing::warn!(error = %e, "lost the notification connection; listening again");
                let mut pause = Duration::from_millis(100);
                listener = loop {
                    tokio::time::sleep(pause).await;
                    if pool.is_closed() {
                        return;
                    }
                    match PgListener::connect_with(&pool).await {
                        Ok(mut l) => match l.listen(CHANNEL).await {
                            Ok(()) => break l,
                            Err(e) => tracing::debug!(error = %e, "listen failed"),
                        },
                        Err(e) => tracing::debug!(error = %e, "notification connection failed"),
                    }
                    pause = (pause * 2).min(LISTEN_BACKOFF_MAX);
                };
                tracing::info!("listening for queued tasks again");
                wake.notify_waiters();
            }
        }
    }
}

/// The job columns, with the progress taken from the tasks.
macro_rules! job_select {
    () => {
        "SELECT j.id, j.key, j.kind, j.spec, j.status, \
         (SELECT COALESCE(AVG(CASE WHEN t.status = 'done' THEN 1.0::float8 ELSE t.progress END), 0.0::float8) FROM tasks t WHERE t.job_id = j.id) AS progress, \
         j.error, j.numerics, j.created_at, j.started_at, j.finished_at FROM jobs j "
    };
}

/// Jobs in a PostgreSQL database.
#[derive(Clone, Debug)]
pub struct PgStore {
    pool: PgPool,
    queued: Arc<Notify>,
}

fn record(row: &sqlx::postgres::PgRow) -> Result<JobRecord, StoreError> {
    let id: String = row.try_get("id")?;
    let status: String = row.try_get("status")?;
    let status = Status::parse(&status).ok_or_else(|| StoreError::Corrupt(status.clone()))?;
    let progress: f64 = row.try_get("progress")?;
    Ok(JobRecord {
        id: parse_id(&id)?,
        key: row.try_get("key")?,
        kind: row.try_get("kind")?,
        spec: row.try_get("spec")?,
        status,
        progress: if status == Status::Succeeded {
            1.0
        } else {
            progress
        },
        error: row.try_get("error")?,
        numerics: row.try_get("numerics")?,
        created_at: row.try_get("created_at")?,
        started_at: row.try_get("started_at")?,
        finished_at: row.try_get("finished_at")?,
    })
}

impl PgStore {
    /// Connects to `url` (`postgres://…`), applies the migrations and starts
    /// listening for work queued by other instances.
    pub async fn open(url: &str, connections: u32) -> Result<Self, StoreError> {
        let pool = PgPoolOptions::new()
            .max_connections(connections.max(2))
            // A database that is down fails requests fast (503), not after 10 s.
            .acquire_timeout(ACQUIRE_TIMEOUT)
            .connect(url)
            .await?;
        sqlx::migrate!("./migrations/postgres").run(&pool).await?;
        let queued = Arc::new(Notify::new());
        let mut listener = PgListener::connect_with(&pool).await?;
        listener.listen(CHANNEL).await?;
        tokio::spawn(listen(pool.clone(), listener, queued.clone()));
        Ok(PgStore { pool, queued })
    }

    /// The connection pool (tests create and drop databases with it).
    pub fn pool(&self) -> &PgPool {
        &self.pool
    }

    async fn fetch(&self, id: Uuid) -> Result<Option<JobRecord>, StoreError> {
        let row = sqlx::query(concat!(job_select!(), "WHERE j.id = $1"))
            .bind(id.to_string())
            .fetch_optional(&self.pool)
            .await?;
        row.as_ref().map(record).transpose()
    }

    async fn insert_tasks(
        tx: &mut sqlx::Transaction<'_, sqlx::Postgres>,
        id: Uuid,
        now: &str,
        tasks: &[String],
    ) -> Result<(), StoreError> {
        for (idx, payload) in tasks.iter().enumerate() {
            sqlx::query(
                "INSERT INTO tasks (job_id, idx, payload, status, created_at) VALUES ($1, $2, $3, 'queued', $4)",
            )
            .bind(id.to_string())
            .bind(idx as i64)
            .bind(payload)
            .bind(now)
            .execute(&mut **tx)
            .await?;
        }
        Ok(())
    }
}

/// Marks a running or queued job succeeded with its result, in `tx`; returns
/// whether it was (a job already finished or canceled is left alone).
async fn store_result(
    tx: &mut sqlx::Transaction<'_, sqlx::Postgres>,
    job: Uuid,
    body: &str,
    numerics: &str,
    now: &str,
) -> Result<bool, StoreError> {
    let updated = sqlx::query(
        "UPDATE jobs SET status = 'succeeded', numerics = $2, finished_at = $3 WHERE id = $1 AND status IN ('queued', 'running')",
    )
    .bind(job.to_string())
    .bind(numerics)
    .bind(now)
    .execute(&mut **tx)
    .await?
    .rows_affected();
    if updated == 1 {
        // The result is kept once, in `results`; task parts are no longer needed.
        sqlx::query("UPDATE tasks SET result = NULL WHERE job_id = $1")
            .bind(job.to_string())
            .execute(&mut **tx)
            .await?;
        sqlx::query(
            "INSERT INTO results (job_id, body) VALUES ($1, $2) ON CONFLICT (job_id) DO NOTHING",
        )
        .bind(job.to_string())
        .bind(body)
        .execute(&mut **tx)
        .await?;
    }
    Ok(updated == 1)
}

impl JobStore for PgStore {
    fn submit<'a>(
        &'a self,
        id: Uuid,
        key: &'a str,
        kind: &'a str,
        spec: &'a str,
        now: &'a str,
        tasks: &'a [String],
    ) -> BoxFuture<'a, Result<Submitted, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            let inserted = sqlx::query(
                "INSERT INTO jobs (id, key, kind, spec, status, created_at) VALUES ($1, $2, $3, $4, 'queued', $5) ON CONFLICT (key) DO NOTHING",
            )
            .bind(id.to_string())
            .bind(key)
            .bind(kind)
            .bind(spec)
            .bind(now)
            .execute(&mut *tx)
            .await?
            .rows_affected();
            let (job_id, cached) = if inserted == 1 {
                Self::insert_tasks(&mut tx, id, now, tasks).await?;
                (id, false)
            } else {
                let row = sqlx::query("SELECT id, status FROM jobs WHERE key = $1")
                    .bind(key)
                    .fetch_one(&mut *tx)
                    .await?;
                let existing = parse_id(&row.try_get::<String, _>("id")?)?;
                let status: String = row.try_get("status")?;
                if status == "failed" || status == "canceled" {
                    // The same work failed or was canceled before: queue it again.
                    sqlx::query(
                        "UPDATE jobs SET status = 'queued', error = NULL, numerics = NULL, started_at = NULL, finished_at = NULL WHERE id = $1",
                    )
                    .bind(existing.to_string())
                    .execute(&mut *tx)
                    .await?;
                    sqlx::query("DELETE FROM tasks WHERE job_id = $1")
                        .bind(existing.to_string())
                        .execute(&mut *tx)
                        .await?;
                    Self::insert_tasks(&mut tx, existing, now, tasks).await?;
                    (existing, false)
                } else {
                    (existing, true)
                }
            };
            tx.commit().await?;
            let job = self
                .fetch(job_id)
                .await?
                .ok_or_else(|| StoreError::Corrupt("submitted job vanished".into()))?;
            Ok(Submitted { job, cached })
        })
    }

    fn get(&self, id: Uuid) -> BoxFuture<'_, Result<Option<JobRecord>, StoreError>> {
        Box::pin(self.fetch(id))
    }

    fn result(&self, id: Uuid) -> BoxFuture<'_, Result<Option<String>, StoreError>> {
        Box::pin(async move {
            let row = sqlx::query("SELECT body FROM results WHERE job_id = $1")
                .bind(id.to_string())
                .fetch_optional(&self.pool)
                .await?;
            Ok(row.map(|r| r.try_get("body")).transpose()?)
        })
    }

    fn list<'a>(&'a self, q: &'a ListQuery) -> BoxFuture<'a, Result<Vec<JobRecord>, StoreError>> {
        Box::pin(async move {
            // UUIDv7 ids sort by creation time: newest first is id descending.
            let rows = sqlx::query(concat!(
                job_select!(),
                "WHERE ($1 IS NULL OR j.status = $1) AND ($2 IS NULL OR j.kind = $2) AND ($3 IS NULL OR j.id < $3) \
                 ORDER BY j.id DESC LIMIT $4"
            ))
            .bind(q.status.map(|s| s.as_str()))
            .bind(q.kind.as_deref())
            .bind(q.before.map(|id| id.to_string()))
            .bind(i64::from(q.limit))
            .fetch_all(&self.pool)
            .await?;
            rows.iter().map(record).collect()
        })
    }

    fn claim_in<'a>(
        &'a self,
        owner: &'a str,
        now: &'a str,
        lease: Duration,
        started_only: bool,
    ) -> BoxFuture<'a, Result<Option<TaskClaim>, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            // Whoever gets the row lock first takes the task; others skip it.
            let row = sqlx::query(
                "WITH next AS ( \
                   SELECT t.job_id, t.idx FROM tasks t JOIN jobs j ON j.id = t.job_id \
                   WHERE (t.status = 'queued' OR (t.status = 'running' AND t.lease_until < now())) \
                   AND j.status IN ('queued', 'running') AND (NOT $3 OR j.status = 'running') \
                   ORDER BY t.created_at, t.idx LIMIT 1 FOR UPDATE OF t SKIP LOCKED) \
                 UPDATE tasks SET status = 'running', lease_owner = $1, \
                   lease_until = now() + make_interval(secs => $2), attempts = tasks.attempts + 1 \
                 FROM next WHERE tasks.job_id = next.job_id AND tasks.idx = next.idx \
                 RETURNING tasks.job_id, tasks.idx::BIGINT AS idx, tasks.payload, tasks.attempts::BIGINT AS attempts",
            )
            .bind(owner)
            .bind(lease.as_secs_f64())
            .bind(started_only)
            .fetch_optional(&mut *tx)
            .await?;
            let Some(row) = row else {
                tx.commit().await?;
                return Ok(None);
            };
            let job_id: String = row.try_get("job_id")?;
            sqlx::query(
                "UPDATE jobs SET status = 'running', started_at = COALESCE(started_at, GREATEST($2, created_at)) WHERE id = $1 AND status = 'queued'",
            )
            .bind(&job_id)
            .bind(now)
            .execute(&mut *tx)
            .await?;
            let job_row = sqlx::query(
                "SELECT kind, (SELECT COUNT(*) FROM tasks WHERE job_id = $1) AS n FROM jobs WHERE id = $1",
            )
            .bind(&job_id)
            .fetch_one(&mut *tx)
            .await?;
            let kind: String = job_row.try_get("kind")?;
            let tasks: i64 = job_row.try_get("n")?;
            tx.commit().await?;
            Ok(Some(TaskClaim {
                job_id: parse_id(&job_id)?,
                idx: row.try_get("idx")?,
                kind,
                payload: row.try_get("payload")?,
                attempts: row.try_get("attempts")?,
                tasks,
            }))
        })
    }

    fn heartbeat<'a>(
        &'a self,
        job: Uuid,
        idx: i64,
        owner: &'a str,
        progress: f64,
        lease: Duration,
    ) -> BoxFuture<'a, Result<Option<Status>, StoreError>> {
        Box::pin(async move {
            let held = sqlx::query(
                "UPDATE tasks SET progress = $4, lease_until = now() + make_interval(secs => $5) \
                 WHERE job_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
            )
            .bind(job.to_string())
            .bind(idx)
            .bind(owner)
            .bind(progress)
            .bind(lease.as_secs_f64())
            .execute(&self.pool)
            .await?
            .rows_affected();
            if held == 0 {
                return Ok(None);
            }
            let row = sqlx::query("SELECT status FROM jobs WHERE id = $1")
                .bind(job.to_string())
                .fetch_optional(&self.pool)
                .await?;
            Ok(match row {
                Some(r) => Status::parse(&r.try_get::<String, _>("status")?),
                None => None,
            })
        })
    }

    fn complete<'a>(
        &'a self,
        job: Uuid,
        idx: i64,
        owner: &'a str,
        result: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let n = sqlx::query(
                "UPDATE tasks SET status = 'done', progress = 1, result = $4, done_by = lease_owner, lease_owner = NULL, lease_until = NULL \
                 WHERE job_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
            )
            .bind(job.to_string())
            .bind(idx)
            .bind(owner)
            .bind(result)
            .execute(&self.pool)
            .await?
            .rows_affected();
            Ok(n == 1)
        })
    }

    fn complete_only<'a>(
        &'a self,
        job: Uuid,
        idx: i64,
        owner: &'a str,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            let held = sqlx::query(
                "UPDATE tasks SET status = 'done', progress = 1, done_by = lease_owner, lease_owner = NULL, lease_until = NULL \
                 WHERE job_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
            )
            .bind(job.to_string())
            .bind(idx)
            .bind(owner)
            .execute(&mut *tx)
            .await?
            .rows_affected();
            let stored = held == 1 && store_result(&mut tx, job, body, numerics, now).await?;
            tx.commit().await?;
            Ok(stored)
        })
    }

    fn parts(&self, job: Uuid) -> BoxFuture<'_, Result<Option<Vec<String>>, StoreError>> {
        Box::pin(async move {
            let rows =
                sqlx::query("SELECT status, result FROM tasks WHERE job_id = $1 ORDER BY idx")
                    .bind(job.to_string())
                    .fetch_all(&self.pool)
                    .await?;
            let mut parts = Vec::with_capacity(rows.len());
            for r in &rows {
                let status: String = r.try_get("status")?;
                let result: Option<String> = r.try_get("result")?;
                match (status.as_str(), result) {
                    ("done", Some(body)) => parts.push(body),
                    _ => return Ok(None),
                }
            }
            Ok((!parts.is_empty()).then_some(parts))
        })
    }

    fn succeed<'a>(
        &'a self,
        job: Uuid,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            let stored = store_result(&mut tx, job, body, numerics, now).await?;
            tx.commit().await?;
            Ok(stored)
        })
    }

    fn fail<'a>(
        &'a self,
        job: Uuid,
        error: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            let n = sqlx::query(
                "UPDATE jobs SET status = 'failed', error = $2, finished_at = $3 WHERE id = $1 AND status IN ('queued', 'running')",
            )
            .bind(job.to_string())
            .bind(error)
            .bind(now)
            .execute(&mut *tx)
            .await?
            .rows_affected();
            sqlx::query(
                "UPDATE tasks SET status = 'canceled', lease_owner = NULL, lease_until = NULL WHERE job_id = $1 AND status IN ('queued', 'running')",
            )
            .bind(job.to_string())
            .execute(&mut *tx)
            .await?;
            tx.commit().await?;
            Ok(n == 1)
        })
    }

    fn requeue<'a>(
        &'a self,
        job: Uuid,
        idx: i64,
        owner: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let n = sqlx::query(
                "UPDATE tasks SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL \
                 WHERE job_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
            )
            .bind(job.to_string())
            .bind(idx)
            .bind(owner)
            .execute(&self.pool)
            .await?
            .rows_affected();
            Ok(n == 1)
        })
    }

    fn cancel<'a>(
        &'a self,
        id: Uuid,
        now: &'a str,
    ) -> BoxFuture<'a, Result<Option<JobRecord>, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            sqlx::query(
                "UPDATE jobs SET status = 'canceled', finished_at = $2 WHERE id = $1 AND status IN ('queued', 'running')",
            )
            .bind(id.to_string())
            .bind(now)
            .execute(&mut *tx)
            .await?;
            sqlx::query(
                "UPDATE tasks SET status = 'canceled', lease_owner = NULL, lease_until = NULL WHERE job_id = $1 AND status IN ('queued', 'running')",
            )
            .bind(id.to_string())
            .execute(&mut *tx)
            .await?;
            tx.commit().await?;
            self.fetch(id).await
        })
    }

    fn recover(&self) -> BoxFuture<'_, Result<u64, StoreError>> {
        Box::pin(async move {
            // Other instances may be running tasks: lapsed leases are taken over
            // by whoever claims next, so nothing is forced here.
            Ok(0)
        })
    }

    fn stranded(&self) -> BoxFuture<'_, Result<Vec<Uuid>, StoreError>> {
        Box::pin(async move {
            let ids: Vec<String> = sqlx::query_scalar(
                "SELECT j.id FROM jobs j WHERE j.status IN ('queued', 'running') \
                 AND EXISTS (SELECT 1 FROM tasks t WHERE t.job_id = j.id) \
                 AND NOT EXISTS (SELECT 1 FROM tasks t WHERE t.job_id = j.id AND t.status <> 'done') \
                 LIMIT 100",
            )
            .fetch_all(&self.pool)
            .await?;
            ids.iter().map(|id| parse_id(id)).collect()
        })
    }

    fn queued(&self) -> BoxFuture<'_, Result<i64, StoreError>> {
        Box::pin(async move {
            let n: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM jobs WHERE status = 'queued'")
                .fetch_one(&self.pool)
                .await?;
            Ok(n)
        })
    }

    fn by_key<'a>(&'a self, key: &'a str) -> BoxFuture<'a, Result<Option<JobRecord>, StoreError>> {
        Box::pin(async move {
            let row = sqlx::query(concat!(job_select!(), "WHERE j.key = $1"))
                .bind(key)
                .fetch_optional(&self.pool)
                .await?;
            row.as_ref().map(record).transpose()
        })
    }

    fn counts(&self) -> BoxFuture<'_, Result<Vec<(Status, i64)>, StoreError>> {
        Box::pin(async move {
            let rows = sqlx::query("SELECT status, COUNT(*) AS n FROM jobs GROUP BY status")
                .fetch_all(&self.pool)
                .await?;
            let mut out = Vec::new();
            for r in rows {
                let s: String = r.try_get("status")?;
                if let Some(status) = Status::parse(&s) {
                    out.push((status, r.try_get("n")?));
                }
            }
            Ok(out)
        })
    }

    fn ping(&self) -> BoxFuture<'_, Result<(), StoreError>> {
        Box::pin(async move {
            sqlx::query("SELECT 1").execute(&self.pool).await?;
            Ok(())
        })
    }

    fn queued_elsewhere(&self) -> BoxFuture<'_, ()> {
        let queued = self.queued.clone();
        Box::pin(async move { queued.notified().await })
    }

    fn announce_queued(&self) -> BoxFuture<'_, ()> {
        Box::pin(async move {
            let _ = sqlx::query("SELECT pg_notify($1, '')")
                .bind(CHANNEL)
                .execute(&self.pool)
                .await;
        })
    }
}
