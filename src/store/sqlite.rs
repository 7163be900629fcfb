//! SQLite storage (the embedded default): WAL journal, one file, one instance.

use std::str::FromStr;
use std::time::{Duration, SystemTime};

use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Row, SqlitePool};
use uuid::Uuid;

use super::{
    BoxFuture, JobRecord, JobStore, ListQuery, Status, StoreError, Submitted, TaskClaim, rfc3339,
};

/// The job columns, with the progress taken from the tasks.
macro_rules! job_select {
    () => {
        "SELECT j.id, j.key, j.kind, j.spec, j.status, \
         (SELECT COALESCE(AVG(CASE WHEN t.status = 'done' THEN 1.0 ELSE t.progress END), 0.0) FROM tasks t WHERE t.job_id = j.id) AS progress, \
         j.error, j.numerics, j.created_at, j.started_at, j.finished_at FROM jobs j "
    };
}

/// Jobs in a SQLite database.
///
/// SQLite has one writer at a time: writes queue on an in-process lock rather
/// than in SQLite's busy handler (whose growing sleeps show up as latency
/// spikes), and the WAL is checkpointed by a background task rather than by
/// whichever request crosses the checkpoint size.
#[derive(Clone, Debug)]
pub struct SqliteStore {
    pool: SqlitePool,
    writer: std::sync::Arc<tokio::sync::Mutex<()>>,
    /// Since when writes fail for want of space or of the database (none
    /// succeeded since), and when the last one failed.
    failing: std::sync::Arc<std::sync::Mutex<WriteHealth>>,
}

/// How writes have been going, for readiness.
#[derive(Debug, Default)]
struct WriteHealth {
    /// A write failed, and none has succeeded since.
    failing: bool,
    /// When the last write failed.
    last_failure: Option<std::time::Instant>,
}

/// After a failed write, readiness stays 503 this long even if a small write
/// gets through meanwhile: a nearly full disk takes some writes and not others.
const FAILURE_WINDOW: Duration = Duration::from_secs(2);

pub(super) fn parse_id(id: &str) -> Result<Uuid, StoreError> {
    Uuid::parse_str(id).map_err(|e| StoreError::Corrupt(e.to_string()))
}

fn record(row: &sqlx::sqlite::SqliteRow) -> Result<JobRecord, StoreError> {
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

/// WAL frames past which a checkpoint waits for its turn among writers and
/// for readers to move on, so that the log restarts (16 MiB at 4 KiB pages).
const WAL_RESTART_FRAMES: i64 = 4096;

/// Checkpoints the WAL every half second: PASSIVE (never waits) as a rule, and
/// TRUNCATE, holding the writer lock, once the log has grown past
/// [`WAL_RESTART_FRAMES`], which a steady stream of readers would otherwise
/// let grow without bound.
async fn checkpoint_loop(pool: SqlitePool, writer: std::sync::Arc<tokio::sync::Mutex<()>>) {
    let mut tick = tokio::time::interval(Duration::from_millis(500));
    loop {
        tick.tick().await;
        if pool.is_closed() {
            break;
        }
        let frames = sqlx::query("PRAGMA wal_checkpoint(PASSIVE)")
            .fetch_optional(&pool)
            .await
            .ok()
            .flatten()
            .and_then(|row| row.try_get::<i64, _>(1).ok())
            .unwrap_or(0);
        if frames > WAL_RESTART_FRAMES {
            let _write = writer.lock().await;
            let _ = sqlx::query("PRAGMA wal_checkpoint(TRUNCATE)")
                .execute(&pool)
                .await;
        }
    }
}

impl SqliteStore {
    /// Opens (creating if missing) the database at `url` (`sqlite://path` or a
    /// plain path) and applies the migrations.
    pub async fn open(url: &str, connections: u32) -> Result<Self, StoreError> {
        let url = if url.starts_with("sqlite:") {
            url.to_string()
        } else {
            format!("sqlite://{url}")
        };
        let options = SqliteConnectOptions::from_str(&url)?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Normal)
            .busy_timeout(Duration::from_secs(10))
            .foreign_keys(true)
            .pragma("wal_autocheckpoint", "0")
            .pragma("journal_size_limit", "67108864");
        let pool = SqlitePoolOptions::new()
            .max_connections(connections.max(2))
            .connect_with(options)
            .await?;
        sqlx::migrate!("./migrations/sqlite").run(&pool).await?;
        let writer = std::sync::Arc::new(tokio::sync::Mutex::new(()));
        tokio::spawn(checkpoint_loop(pool.clone(), writer.clone()));
        Ok(SqliteStore {
            pool,
            writer,
            failing: Default::default(),
        })
    }

    async fn fetch(&self, id: Uuid) -> Result<Option<JobRecord>, StoreError> {
        fetch_with(&self.pool, id).await
    }

    async fn insert_tasks(
        tx: &mut sqlx::Transaction<'_, sqlx::Sqlite>,
        id: Uuid,
        now: &str,
        tasks: &[String],
    ) -> Result<(), StoreError> {
        for (idx, payload) in tasks.iter().enumerate() {
            sqlx::query(
                "INSERT INTO tasks (job_id, idx, payload, status, created_at) VALUES (?1, ?2, ?3, 'queued', ?4)",
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

/// One job, read with `executor` (the pool, or a transaction).
async fn fetch_with<'e, E>(executor: E, id: Uuid) -> Result<Option<JobRecord>, StoreError>
where
    E: sqlx::Executor<'e, Database = sqlx::Sqlite>,
{
    let row = sqlx::query(concat!(job_select!(), "WHERE j.id = ?1"))
        .bind(id.to_string())
        .fetch_optional(executor)
        .await?;
    row.as_ref().map(record).transpose()
}

/// Marks a running or queued job succeeded with its result, in `tx`; returns
/// whether it was (a job already finished or canceled is left alone).
async fn store_result(
    tx: &mut sqlx::Transaction<'_, sqlx::Sqlite>,
    job: Uuid,
    body: &str,
    numerics: &str,
    now: &str,
) -> Result<bool, StoreError> {
    let updated = sqlx::query(
        "UPDATE jobs SET status = 'succeeded', numerics = ?2, finished_at = ?3 WHERE id = ?1 AND status IN ('queued', 'running')",
    )
    .bind(job.to_string())
    .bind(numerics)
    .bind(now)
    .execute(&mut **tx)
    .await?
    .rows_affected();
    if updated == 1 {
        // The result is kept once, in `results`; task parts are no longer needed.
        sqlx::query("UPDATE tasks SET result = NULL WHERE job_id = ?1")
            .bind(job.to_string())
            .execute(&mut **tx)
            .await?;
        sqlx::query(
            "INSERT INTO results (job_id, body) VALUES (?1, ?2) ON CONFLICT (job_id) DO NOTHING",
        )
        .bind(job.to_string())
        .bind(body)
        .execute(&mut **tx)
        .await?;
    }
    Ok(updated == 1)
}

/// After a failed write the connection is closed instead of going back to
/// the pool: whatever state the failure left it in (a transaction SQLite rolled
/// back by itself, or one still open and holding the write lock after a full
/// disk or an I/O error), no later request inherits it.
fn discard_on_error<T>(
    conn: &mut sqlx::pool::PoolConnection<sqlx::Sqlite>,
    result: &Result<T, StoreError>,
) {
    if result.is_err() {
        conn.close_on_drop();
    }
}

impl SqliteStore {
    /// Records how a write that changes data ended, for readiness.
    fn note<T>(&self, result: &Result<T, StoreError>) {
        let mut health = self.failing.lock().unwrap_or_else(|e| e.into_inner());
        match result {
            Ok(_) => health.failing = false,
            Err(e) if e.failure() != super::Failure::Other => {
                health.failing = true;
                health.last_failure = Some(std::time::Instant::now());
            }
            Err(_) => {}
        }
    }
}

impl JobStore for SqliteStore {
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
            let _write = self.writer.lock().await;
            let mut conn = self.pool.acquire().await?;
            let result: Result<_, StoreError> = async {
                let mut tx = sqlx::Connection::begin(&mut *conn).await?;
                let inserted = sqlx::query(
                    "INSERT INTO jobs (id, key, kind, spec, status, created_at) VALUES (?1, ?2, ?3, ?4, 'queued', ?5) ON CONFLICT (key) DO NOTHING",
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
                    let row = sqlx::query("SELECT id, status FROM jobs WHERE key = ?1")
                        .bind(key)
                        .fetch_one(&mut *tx)
                        .await?;
                    let existing = parse_id(&row.try_get::<String, _>("id")?)?;
                    let status: String = row.try_get("status")?;
                    if status == "failed" || status == "canceled" {
                        // The same work failed or was canceled before: queue it again.
                        sqlx::query(
                            "UPDATE jobs SET status = 'queued', error = NULL, numerics = NULL, started_at = NULL, finished_at = NULL WHERE id = ?1",
                        )
                        .bind(existing.to_string())
                        .execute(&mut *tx)
                        .await?;
                        sqlx::query("DELETE FROM tasks WHERE job_id = ?1")
                            .bind(existing.to_string())
                            .execute(&mut *tx)
                            .await?;
                        Self::insert_tasks(&mut tx, existing, now, tasks).await?;
                        (existing, false)
                    } else {
                        (existing, true)
                    }
                };
                // The answer is read inside the transaction and returned only
                // once it committed: a 2xx always stands for a stored job.
                let job = fetch_with(&mut *tx, job_id)
                    .await?
                    .ok_or_else(|| StoreError::Corrupt("submitted job vanished".into()))?;
                tx.commit().await?;
                Ok(Submitted { job, cached })
            }
            .await;
            discard_on_error(&mut conn, &result);
            self.note(&result);
            result
        })
    }

    fn get(&self, id: Uuid) -> BoxFuture<'_, Result<Option<JobRecord>, StoreError>> {
        Box::pin(self.fetch(id))
    }

    fn result(&self, id: Uuid) -> BoxFuture<'_, Result<Option<String>, StoreError>> {
        Box::pin(async move {
            let row = sqlx::query("SELECT body FROM results WHERE job_id = ?1")
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
                "WHERE (?1 IS NULL OR j.status = ?1) AND (?2 IS NULL OR j.kind = ?2) AND (?3 IS NULL OR j.id < ?3) \
                 ORDER BY j.id DESC LIMIT ?4"
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
            let _write = self.writer.lock().await;
            let until = rfc3339(SystemTime::now() + lease);
            let mut conn = self.pool.acquire().await?;
            let result: Result<_, StoreError> = async {
                let mut tx = sqlx::Connection::begin(&mut *conn).await?;
                let row = sqlx::query(
                    "UPDATE tasks SET status = 'running', lease_owner = ?1, lease_until = ?3, attempts = attempts + 1 \
                     WHERE rowid = (SELECT t.rowid FROM tasks t JOIN jobs j ON j.id = t.job_id \
                       WHERE (t.status = 'queued' OR (t.status = 'running' AND t.lease_until < ?2)) \
                       AND j.status IN ('queued', 'running') AND (?4 = 0 OR j.status = 'running') \
                       ORDER BY t.created_at, t.idx LIMIT 1) \
                     RETURNING job_id, idx, payload, attempts",
                )
                .bind(owner)
                .bind(now)
                .bind(&until)
                .bind(started_only)
                .fetch_optional(&mut *tx)
                .await?;
                let Some(row) = row else {
                    tx.commit().await?;
                    return Ok(None);
                };
                let job_id: String = row.try_get("job_id")?;
                sqlx::query(
                    "UPDATE jobs SET status = 'running', started_at = COALESCE(started_at, MAX(?2, created_at)) WHERE id = ?1 AND status = 'queued'",
                )
                .bind(&job_id)
                .bind(now)
                .execute(&mut *tx)
                .await?;
                let job_row = sqlx::query(
                    "SELECT kind, (SELECT COUNT(*) FROM tasks WHERE job_id = ?1) AS n FROM jobs WHERE id = ?1",
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
            }
            .await;
            discard_on_error(&mut conn, &result);
            result
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
            let _write = self.writer.lock().await;
            let until = rfc3339(SystemTime::now() + lease);
            let held = sqlx::query(
                "UPDATE tasks SET progress = ?4, lease_until = ?5 WHERE job_id = ?1 AND idx = ?2 AND lease_owner = ?3 AND status = 'running'",
            )
            .bind(job.to_string())
            .bind(idx)
            .bind(owner)
            .bind(progress)
            .bind(&until)
            .execute(&self.pool)
            .await?
            .rows_affected();
            if held == 0 {
                return Ok(None);
            }
            let row = sqlx::query("SELECT status FROM jobs WHERE id = ?1")
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
            let _write = self.writer.lock().await;
            let n = sqlx::query(
                "UPDATE tasks SET status = 'done', progress = 1, result = ?4, done_by = lease_owner, lease_owner = NULL, lease_until = NULL \
                 WHERE job_id = ?1 AND idx = ?2 AND lease_owner = ?3 AND status = 'running'",
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
            let _write = self.writer.lock().await;
            let mut conn = self.pool.acquire().await?;
            let result: Result<_, StoreError> = async {
                let mut tx = sqlx::Connection::begin(&mut *conn).await?;
                let held = sqlx::query(
                    "UPDATE tasks SET status = 'done', progress = 1, done_by = lease_owner, lease_owner = NULL, lease_until = NULL \
                     WHERE job_id = ?1 AND idx = ?2 AND lease_owner = ?3 AND status = 'running'",
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
            }
            .await;
            discard_on_error(&mut conn, &result);
            self.note(&result);
            result
        })
    }

    fn parts(&self, job: Uuid) -> BoxFuture<'_, Result<Option<Vec<String>>, StoreError>> {
        Box::pin(async move {
            let rows =
                sqlx::query("SELECT status, result FROM tasks WHERE job_id = ?1 ORDER BY idx")
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
            let _write = self.writer.lock().await;
            let mut conn = self.pool.acquire().await?;
            let result: Result<_, StoreError> = async {
                let mut tx = sqlx::Connection::begin(&mut *conn).await?;
                let stored = store_result(&mut tx, job, body, numerics, now).await?;
                tx.commit().await?;
                Ok(stored)
            }
            .await;
            discard_on_error(&mut conn, &result);
            self.note(&result);
            result
        })
    }

    fn fail<'a>(
        &'a self,
        job: Uuid,
        error: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let _write = self.writer.lock().await;
            let mut conn = self.pool.acquire().await?;
            let result: Result<_, StoreError> = async {
                let mut tx = sqlx::Connection::begin(&mut *conn).await?;
                let n = sqlx::query(
                    "UPDATE jobs SET status = 'failed', error = ?2, finished_at = ?3 WHERE id = ?1 AND status IN ('queued', 'running')",
                )
                .bind(job.to_string())
                .bind(error)
                .bind(now)
                .execute(&mut *tx)
                .await?
                .rows_affected();
                sqlx::query(
                    "UPDATE tasks SET status = 'canceled', lease_owner = NULL, lease_until = NULL WHERE job_id = ?1 AND status IN ('queued', 'running')",
                )
                .bind(job.to_string())
                .execute(&mut *tx)
                .await?;
                tx.commit().await?;
                Ok(n == 1)
            }
            .await;
            discard_on_error(&mut conn, &result);
            result
        })
    }

    fn requeue<'a>(
        &'a self,
        job: Uuid,
        idx: i64,
        owner: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let _write = self.writer.lock().await;
            let n = sqlx::query(
                "UPDATE tasks SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL \
                 WHERE job_id = ?1 AND idx = ?2 AND lease_owner = ?3 AND status = 'running'",
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
            let _write = self.writer.lock().await;
            let mut conn = self.pool.acquire().await?;
            let result: Result<_, StoreError> = async {
                let mut tx = sqlx::Connection::begin(&mut *conn).await?;
                sqlx::query(
                    "UPDATE jobs SET status = 'canceled', finished_at = ?2 WHERE id = ?1 AND status IN ('queued', 'running')",
                )
                .bind(id.to_string())
                .bind(now)
                .execute(&mut *tx)
                .await?;
                sqlx::query(
                    "UPDATE tasks SET status = 'canceled', lease_owner = NULL, lease_until = NULL WHERE job_id = ?1 AND status IN ('queued', 'running')",
                )
                .bind(id.to_string())
                .execute(&mut *tx)
                .await?;
                let job = fetch_with(&mut *tx, id).await?;
                tx.commit().await?;
                Ok(job)
            }
            .await;
            discard_on_error(&mut conn, &result);
            result
        })
    }

    fn recover(&self) -> BoxFuture<'_, Result<u64, StoreError>> {
        Box::pin(async move {
            let _write = self.writer.lock().await;
            // One process owns a SQLite database: whatever it was running when it
            // died runs again.
            let n = sqlx::query(
                "UPDATE tasks SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL WHERE status = 'running'",
            )
            .execute(&self.pool)
            .await?
            .rows_affected();
            Ok(n)
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
            let row = sqlx::query(concat!(job_select!(), "WHERE j.key = ?1"))
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

    fn writable(&self) -> BoxFuture<'_, Result<(), StoreError>> {
        Box::pin(async move {
            {
                let health = self.failing.lock().unwrap_or_else(|e| e.into_inner());
                if let Some(at) = health.last_failure
                    && at.elapsed() < FAILURE_WINDOW
                {
                    return Err(StoreError::WritesFailing(format!(
                        "a write failed {:.1} s ago",
                        at.elapsed().as_secs_f64()
                    )));
                }
                if !health.failing {
                    return Ok(());
                }
            }
            let _write = self.writer.lock().await;
            let result = sqlx::query(
                "INSERT INTO probe (id, at) VALUES (1, ?1) ON CONFLICT (id) DO UPDATE SET at = excluded.at",
            )
            .bind(super::now_rfc3339())
            .execute(&self.pool)
            .await
            .map(|_| ())
            .map_err(StoreError::from);
            self.note(&result);
            result
        })
    }
}
