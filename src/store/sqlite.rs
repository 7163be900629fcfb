//! SQLite storage (the embedded default): WAL journal, one file.

use std::str::FromStr;
use std::time::Duration;

use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Row, SqlitePool};
use uuid::Uuid;

use super::{BoxFuture, JobRecord, JobStore, ListQuery, Status, StoreError, Submitted};

/// Jobs in a SQLite database.
#[derive(Clone, Debug)]
pub struct SqliteStore {
    pool: SqlitePool,
}

fn record(row: &sqlx::sqlite::SqliteRow) -> Result<JobRecord, StoreError> {
    let id: String = row.try_get("id")?;
    let status: String = row.try_get("status")?;
    Ok(JobRecord {
        id: Uuid::parse_str(&id).map_err(|e| StoreError::Corrupt(e.to_string()))?,
        key: row.try_get("key")?,
        kind: row.try_get("kind")?,
        spec: row.try_get("spec")?,
        status: Status::parse(&status).ok_or_else(|| StoreError::Corrupt(status.clone()))?,
        progress: row.try_get("progress")?,
        error: row.try_get("error")?,
        numerics: row.try_get("numerics")?,
        created_at: row.try_get("created_at")?,
        started_at: row.try_get("started_at")?,
        finished_at: row.try_get("finished_at")?,
    })
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
            .foreign_keys(true);
        let pool = SqlitePoolOptions::new()
            .max_connections(connections.max(2))
            .connect_with(options)
            .await?;
        sqlx::migrate!("./migrations/sqlite").run(&pool).await?;
        Ok(SqliteStore { pool })
    }

    async fn fetch(&self, id: Uuid) -> Result<Option<JobRecord>, StoreError> {
        let row = sqlx::query(
            "SELECT id, key, kind, spec, status, progress, error, numerics, created_at, started_at, finished_at FROM jobs WHERE id = ?1",
        )
        .bind(id.to_string())
        .fetch_optional(&self.pool)
        .await?;
        row.as_ref().map(record).transpose()
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
    ) -> BoxFuture<'a, Result<Submitted, StoreError>> {
        Box::pin(async move {
            let inserted = sqlx::query(
                "INSERT INTO jobs (id, key, kind, spec, status, progress, created_at) VALUES (?1, ?2, ?3, ?4, 'queued', 0, ?5) ON CONFLICT (key) DO NOTHING",
            )
            .bind(id.to_string())
            .bind(key)
            .bind(kind)
            .bind(spec)
            .bind(now)
            .execute(&self.pool)
            .await?
            .rows_affected();
            if inserted == 1 {
                let job = self
                    .fetch(id)
                    .await?
                    .ok_or_else(|| StoreError::Corrupt("inserted job vanished".into()))?;
                return Ok(Submitted { job, cached: false });
            }
            // The same work exists: queue it again only if it failed or was canceled.
            let requeued = sqlx::query(
                "UPDATE jobs SET status = 'queued', progress = 0, error = NULL, numerics = NULL, started_at = NULL, finished_at = NULL, lease_owner = NULL, lease_until = NULL WHERE key = ?1 AND status IN ('failed', 'canceled')",
            )
            .bind(key)
            .execute(&self.pool)
            .await?
            .rows_affected();
            let row = sqlx::query(
                "SELECT id, key, kind, spec, status, progress, error, numerics, created_at, started_at, finished_at FROM jobs WHERE key = ?1",
            )
            .bind(key)
            .fetch_one(&self.pool)
            .await?;
            Ok(Submitted {
                job: record(&row)?,
                cached: requeued == 0,
            })
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
            let rows = sqlx::query(
                "SELECT id, key, kind, spec, status, progress, error, numerics, created_at, started_at, finished_at FROM jobs \
                 WHERE (?1 IS NULL OR status = ?1) AND (?2 IS NULL OR kind = ?2) AND (?3 IS NULL OR id < ?3) \
                 ORDER BY id DESC LIMIT ?4",
            )
            .bind(q.status.map(|s| s.as_str()))
            .bind(q.kind.as_deref())
            .bind(q.before.map(|id| id.to_string()))
            .bind(i64::from(q.limit))
            .fetch_all(&self.pool)
            .await?;
            rows.iter().map(record).collect()
        })
    }

    fn claim<'a>(
        &'a self,
        owner: &'a str,
        now: &'a str,
        lease_until: &'a str,
    ) -> BoxFuture<'a, Result<Option<JobRecord>, StoreError>> {
        Box::pin(async move {
            let row = sqlx::query(
                "UPDATE jobs SET status = 'running', lease_owner = ?1, lease_until = ?3, started_at = COALESCE(started_at, MAX(?2, created_at)) \
                 WHERE id = (SELECT id FROM jobs WHERE status = 'queued' OR (status = 'running' AND lease_until < ?2) ORDER BY created_at LIMIT 1) \
                 RETURNING id, key, kind, spec, status, progress, error, numerics, created_at, started_at, finished_at",
            )
            .bind(owner)
            .bind(now)
            .bind(lease_until)
            .fetch_optional(&self.pool)
            .await?;
            row.as_ref().map(record).transpose()
        })
    }

    fn heartbeat<'a>(
        &'a self,
        id: Uuid,
        owner: &'a str,
        progress: f64,
        lease_until: &'a str,
    ) -> BoxFuture<'a, Result<Option<Status>, StoreError>> {
        Box::pin(async move {
            sqlx::query(
                "UPDATE jobs SET progress = ?3, lease_until = ?4 WHERE id = ?1 AND lease_owner = ?2 AND status = 'running'",
            )
            .bind(id.to_string())
            .bind(owner)
            .bind(progress)
            .bind(lease_until)
            .execute(&self.pool)
            .await?;
            let row = sqlx::query("SELECT status FROM jobs WHERE id = ?1")
                .bind(id.to_string())
                .fetch_optional(&self.pool)
                .await?;
            Ok(match row {
                Some(r) => Status::parse(&r.try_get::<String, _>("status")?),
                None => None,
            })
        })
    }

    fn succeed<'a>(
        &'a self,
        id: Uuid,
        owner: &'a str,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await?;
            let updated = sqlx::query(
                "UPDATE jobs SET status = 'succeeded', progress = 1, numerics = ?3, finished_at = ?4, lease_owner = NULL, lease_until = NULL \
                 WHERE id = ?1 AND lease_owner = ?2 AND status = 'running'",
            )
            .bind(id.to_string())
            .bind(owner)
            .bind(numerics)
            .bind(now)
            .execute(&mut *tx)
            .await?
            .rows_affected();
            if updated == 1 {
                sqlx::query("INSERT INTO results (job_id, body) VALUES (?1, ?2) ON CONFLICT (job_id) DO NOTHING")
                    .bind(id.to_string())
                    .bind(body)
                    .execute(&mut *tx)
                    .await?;
            }
            tx.commit().await?;
            Ok(updated == 1)
        })
    }

    fn fail<'a>(
        &'a self,
        id: Uuid,
        owner: &'a str,
        error: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let n = sqlx::query(
                "UPDATE jobs SET status = 'failed', error = ?3, finished_at = ?4, lease_owner = NULL, lease_until = NULL \
                 WHERE id = ?1 AND lease_owner = ?2 AND status = 'running'",
            )
            .bind(id.to_string())
            .bind(owner)
            .bind(error)
            .bind(now)
            .execute(&self.pool)
            .await?
            .rows_affected();
            Ok(n == 1)
        })
    }

    fn requeue<'a>(&'a self, id: Uuid, owner: &'a str) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let n = sqlx::query(
                "UPDATE jobs SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL \
                 WHERE id = ?1 AND lease_owner = ?2 AND status = 'running'",
            )
            .bind(id.to_string())
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
            sqlx::query(
                "UPDATE jobs SET status = 'canceled', finished_at = ?2, lease_owner = NULL, lease_until = NULL \
                 WHERE id = ?1 AND status IN ('queued', 'running')",
            )
            .bind(id.to_string())
            .bind(now)
            .execute(&self.pool)
            .await?;
            self.fetch(id).await
        })
    }

    fn recover(&self) -> BoxFuture<'_, Result<u64, StoreError>> {
        Box::pin(async move {
            // One process owns a SQLite database: whatever it was running when it
            // died runs again.
            let n = sqlx::query(
                "UPDATE jobs SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL WHERE status = 'running'",
            )
            .execute(&self.pool)
            .await?
            .rows_affected();
            Ok(n)
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
}
