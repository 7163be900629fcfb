//! The job store, once, over both SQL dialects: every statement is written in
//! the syntax SQLite and PostgreSQL share, with the few differences filled in
//! from [`Dialect`].

use std::sync::{Arc, Mutex};
use std::time::Duration;

use sqlx::{
    AssertSqlSafe, ColumnIndex, Connection, Decode, Encode, Executor, IntoArguments, Pool, Row,
    Type,
};
use tokio::sync::Notify;
use uuid::Uuid;

use super::deletions::{Deletion, Deletions};
use super::dialect::{Dialect, fill};
use super::finished::{Announcer, Finished};
use super::writer::{Writer, Writing};
use super::{
    Admission, BoxFuture, Canceled, Computation, Deleted, DoneJob, Failure, JobRecord, JobStore,
    ListQuery, NewJob, Status, StoreError, StoredDone, Submitted, TaskClaim,
};

/// A job's columns: its own life, with its computation's key, kind, spec,
/// progress (from the tasks) and numerics (once it succeeded).
/// The admission's reads ([`JobStore::admission`]), $1 the tenant and $2
/// the key: the tenant's own job for the key, the key's computation, the
/// tenant's live jobs and the queue's length. The own job is looked up
/// through the key's computation (a scalar subquery: an index lookup each),
/// never as a join the planner may order from the tenant's side: a plan
/// made while the tables were small (PostgreSQL keeps a prepared
/// statement's generic plan for the connection's life) then walked every
/// job of the tenant, 6.3 ms at 5,000 jobs against 0.08 ms.
pub const ADMISSION: &str = "SELECT \
     (SELECT j.status FROM jobs j WHERE j.tenant = $1 AND j.computation_id = (SELECT id FROM computations WHERE key = $2)) AS own, \
     (SELECT status FROM computations WHERE key = $2) AS computation, \
     (SELECT COUNT(*) FROM jobs WHERE tenant = $1 AND status IN ('queued', 'running')) AS live, \
     (SELECT COUNT(*) FROM computations WHERE status = 'queued') AS queued";

const JOB_SELECT: &str = "SELECT j.id, j.tenant, j.computation_id, c.key, c.kind, c.spec, j.status, \
     (SELECT COALESCE(AVG(CASE WHEN t.status = 'done' THEN CAST(1 AS DOUBLE PRECISION) ELSE t.progress END), CAST(0 AS DOUBLE PRECISION)) \
      FROM tasks t WHERE t.computation_id = c.id) AS progress, \
     j.error, CASE WHEN j.status = 'succeeded' THEN c.numerics END AS numerics, \
     j.created_at, j.started_at, j.finished_at \
     FROM jobs j JOIN computations c ON c.id = j.computation_id ";

/// Statements with dialect placeholders, filled once per store.
#[derive(Debug)]
struct Statements {
    job_by_id: String,
    job_list: String,
    lock_computation: String,
    lapsed_task: String,
    next_tenant: String,
    next_of_tenant: String,
    next_of_anyone: String,
    first_queued_task: String,
    take_task: String,
    heartbeat: String,
}

impl Statements {
    fn new<DB: Dialect>() -> Self {
        Statements {
            job_by_id: format!("{JOB_SELECT}WHERE j.id = $1 AND j.tenant = $2"),
            job_list: format!(
                "{JOB_SELECT}WHERE j.tenant = $1 AND ($2 IS NULL OR j.status = $2) AND ($3 IS NULL OR c.kind = $3) \
                 AND ($4 IS NULL OR j.id < $4) ORDER BY j.id DESC LIMIT $5"
            ),
            lock_computation: fill::<DB>(
                "SELECT id, status, tenant FROM computations WHERE id = $1{for_update}",
            ),
            lapsed_task: fill::<DB>(
                "SELECT computation_id, CAST(idx AS BIGINT) AS idx FROM tasks \
                 WHERE status = 'running' AND lease_until < {now} ORDER BY lease_until LIMIT 1{skip_locked}",
            ),
            // A scalar subquery with LIMIT 1 per tenant, which the planners
            // run as such (stopping at the tenant's first ready computation),
            // rather than EXISTS, which PostgreSQL flattens into a join over
            // every live computation.
            next_tenant: fill::<DB>(
                "SELECT n.name FROM tenants n WHERE (SELECT c.id FROM computations c \
                   WHERE c.tenant = n.name AND c.status IN ('queued', 'running') AND ($1 = 0 OR c.status = 'running') \
                   AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status = 'queued') LIMIT 1) IS NOT NULL \
                 ORDER BY n.served_at, n.name LIMIT 1",
            ),
            next_of_tenant: fill::<DB>(
                "SELECT c.id FROM computations c \
                 WHERE c.tenant = $1 AND c.status IN ('queued', 'running') AND ($2 = 0 OR c.status = 'running') \
                 AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status = 'queued') \
                 ORDER BY c.served_at, c.created_at LIMIT 1{skip_locked}",
            ),
            next_of_anyone: fill::<DB>(
                "SELECT c.id FROM computations c \
                 WHERE c.status IN ('queued', 'running') AND ($1 = 0 OR c.status = 'running') \
                 AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status = 'queued') \
                 ORDER BY c.served_at, c.created_at LIMIT 1{skip_locked}",
            ),
            first_queued_task: fill::<DB>(
                "SELECT CAST(idx AS BIGINT) AS idx FROM tasks WHERE computation_id = $1 AND status = 'queued' \
                 ORDER BY idx LIMIT 1{skip_locked}",
            ),
            take_task: fill::<DB>(
                "UPDATE tasks SET status = 'running', lease_owner = $3, lease_until = {now+$4}, attempts = attempts + 1 \
                 WHERE computation_id = $1 AND idx = $2 \
                 RETURNING payload, CAST(attempts AS BIGINT) AS attempts",
            ),
            heartbeat: fill::<DB>(
                "UPDATE tasks SET progress = $4, lease_until = {now+$5} \
                 WHERE computation_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
            ),
        }
    }
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

/// Jobs, computations, tasks and results in a SQL database of dialect `DB`.
#[derive(Debug)]
pub struct SqlStore<DB: Dialect> {
    pool: Pool<DB>,
    /// The connections writes run on, kept open and taken in turns (SQLite:
    /// one, so writes queue here rather than in the database's busy handler,
    /// whose growing sleeps show up as latency spikes).
    writer: Arc<Writer<DB>>,
    health: Arc<Mutex<WriteHealth>>,
    /// Notified when another instance queued work (PostgreSQL).
    elsewhere: Option<Arc<Notify>>,
    /// Announces the deletions of finished jobs.
    deletions: Arc<Deletions>,
    /// Announces the computations that ended.
    finished: Announcer,
    sql: Arc<Statements>,
}

impl<DB: Dialect> Clone for SqlStore<DB> {
    fn clone(&self) -> Self {
        SqlStore {
            pool: self.pool.clone(),
            writer: self.writer.clone(),
            health: self.health.clone(),
            elsewhere: self.elsewhere.clone(),
            deletions: self.deletions.clone(),
            finished: self.finished.clone(),
            sql: self.sql.clone(),
        }
    }
}

pub(super) fn parse_id(id: &str) -> Result<Uuid, StoreError> {
    Uuid::parse_str(id).map_err(|e| StoreError::Corrupt(e.to_string()))
}

fn parse_status(s: &str) -> Result<Status, StoreError> {
    Status::parse(s).ok_or_else(|| StoreError::Corrupt(format!("status {s:?}")))
}

impl<DB: Dialect> SqlStore<DB> {
    /// A store over `pool` (migrated already), writing on `writer`'s
    /// connections; `elsewhere` is notified when
    /// another instance queues work; deletions are announced on `deletions`,
    /// and computations that ended on `finished` (where the listener of
    /// other instances' announcements writes too).
    pub(super) fn new(
        pool: Pool<DB>,
        writer: Writer<DB>,
        elsewhere: Option<Arc<Notify>>,
        deletions: Arc<Deletions>,
        finished: Announcer,
    ) -> Self {
        SqlStore {
            pool,
            writer: Arc::new(writer),
            health: Default::default(),
            elsewhere,
            deletions,
            finished,
            sql: Arc::new(Statements::new::<DB>()),
        }
    }

    /// The connection pool.
    pub fn pool(&self) -> &Pool<DB> {
        &self.pool
    }

    /// The connections writes run on.
    pub(super) fn writer(&self) -> Arc<Writer<DB>> {
        self.writer.clone()
    }

    /// A connection to write on, in its turn.
    pub(super) async fn writing(&self) -> Result<Writing<'_, DB>, StoreError> {
        Ok(Writing::start(&self.writer).await?)
    }

    /// Records how a write that changes data ended, for readiness; only
    /// after a write that succeeded is its connection used again
    /// ([`Writing::keep`]).
    pub(super) async fn settle<T>(
        &self,
        writing: &mut Writing<'_, DB>,
        result: &Result<T, StoreError>,
    ) {
        if result.is_ok() {
            writing.keep().await;
        }
        let mut health = self.health.lock().unwrap_or_else(|e| e.into_inner());
        match result {
            Ok(_) => health.failing = false,
            Err(e) if e.failure() != Failure::Other => {
                health.failing = true;
                health.last_failure = Some(std::time::Instant::now());
            }
            Err(_) => {}
        }
    }
}

impl<DB> SqlStore<DB>
where
    DB: Dialect,
    DB::QueryResult: RowsAffected,
    for<'c> &'c mut DB::Connection: Executor<'c, Database = DB>,
    DB::Arguments: IntoArguments<DB>,
    String: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    Option<String>: for<'q> Encode<'q, DB>,
    Option<i64>: for<'q> Encode<'q, DB>,
    i64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    f64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    for<'n> &'n str: ColumnIndex<DB::Row>,
    usize: ColumnIndex<DB::Row>,
{
    /// What an admission read, from a row with its columns `own`,
    /// `computation`, `live` and `queued` ([`ADMISSION`]).
    fn admission_of(row: &DB::Row) -> Result<Admission, StoreError> {
        let status = |name: &str| -> Result<Option<Status>, StoreError> {
            row.try_get::<Option<String>, _>(name)?
                .map(|s| parse_status(&s))
                .transpose()
        };
        Ok(Admission {
            own: status("own")?,
            computation: status("computation")?,
            live: row.try_get("live")?,
            queued: row.try_get("queued")?,
        })
    }

    fn record(row: &DB::Row) -> Result<JobRecord, StoreError> {
        let status = parse_status(&row.try_get::<String, _>("status")?)?;
        let progress: f64 = row.try_get("progress")?;
        Ok(JobRecord {
            id: parse_id(&row.try_get::<String, _>("id")?)?,
            tenant: row.try_get("tenant")?,
            computation: parse_id(&row.try_get::<String, _>("computation_id")?)?,
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

    /// The tenant's job, read on `conn`.
    async fn job(
        &self,
        conn: &mut DB::Connection,
        tenant: &str,
        id: Uuid,
    ) -> Result<Option<JobRecord>, StoreError> {
        let row = sqlx::query(AssertSqlSafe(self.sql.job_by_id.as_str()))
            .bind(id.to_string())
            .bind(tenant.to_string())
            .fetch_optional(conn)
            .await?;
        row.as_ref().map(Self::record).transpose()
    }

    async fn insert_tasks(
        conn: &mut DB::Connection,
        computation: Uuid,
        now: &str,
        tasks: &[String],
    ) -> Result<(), StoreError> {
        for (idx, payload) in tasks.iter().enumerate() {
            sqlx::query(
                "INSERT INTO tasks (computation_id, idx, payload, status, created_at) VALUES ($1, $2, $3, 'queued', $4)",
            )
            .bind(computation.to_string())
            .bind(idx as i64)
            .bind(payload.clone())
            .bind(now.to_string())
            .execute(&mut *conn)
            .await?;
        }
        Ok(())
    }

    /// Locks the computation's row until the transaction ends (PostgreSQL):
    /// joining, cancelling and deleting jobs of one computation take turns.
    /// Returns its status and tenant.
    async fn lock_computation(
        &self,
        conn: &mut DB::Connection,
        id: &str,
    ) -> Result<Option<(Status, String)>, StoreError> {
        let row = sqlx::query(AssertSqlSafe(self.sql.lock_computation.as_str()))
            .bind(id.to_string())
            .fetch_optional(conn)
            .await?;
        match row {
            Some(r) => Ok(Some((
                parse_status(&r.try_get::<String, _>("status")?)?,
                r.try_get("tenant")?,
            ))),
            None => Ok(None),
        }
    }

    async fn submit_in(
        &self,
        conn: &mut DB::Connection,
        new: NewJob<'_>,
    ) -> Result<Submitted, StoreError> {
        let mut tx = conn.begin().await?;
        sqlx::query("INSERT INTO tenants (name) VALUES ($1) ON CONFLICT (name) DO NOTHING")
            .bind(new.tenant.to_string())
            .execute(&mut *tx)
            .await?;
        let (computation, status, queued) = self.computation_for(&mut tx, &new).await?;
        let (job_id, cached) = Self::job_for(&mut tx, &new, &computation, status, queued).await?;
        // The records it names: while it is live, they are not deleted.
        for record in new.records {
            sqlx::query(
                "INSERT INTO job_records (job_id, record_id) VALUES ($1, $2) ON CONFLICT (job_id, record_id) DO NOTHING",
            )
            .bind(job_id.clone())
            .bind(record.clone())
            .execute(&mut *tx)
            .await?;
        }
        // The answer is read inside the transaction and returned only once it
        // committed: a 2xx always stands for a stored job.
        let job = self
            .job(&mut tx, new.tenant, parse_id(&job_id)?)
            .await?
            .ok_or_else(|| StoreError::Corrupt("submitted job vanished".into()))?;
        tx.commit().await?;
        Ok(Submitted { job, cached })
    }

    /// Stores `done` in one transaction on `conn` (see [`JobStore::store_done`]).
    async fn store_done_in(
        &self,
        conn: &mut DB::Connection,
        done: DoneJob<'_>,
    ) -> Result<StoredDone, StoreError> {
        let new = &done.new;
        let [payload] = new.tasks else {
            return Err(StoreError::Corrupt(
                "a finished job of more than one task".into(),
            ));
        };
        let id = new.id.to_string();
        let record = done_record(&done);
        if let Some(sql) = DB::STORE_DONE {
            let row = sqlx::query(sql)
                .bind(id)
                .bind(new.key.to_string())
                .bind(new.kind.to_string())
                .bind(new.spec.to_string())
                .bind(done.numerics.to_string())
                .bind(new.now.to_string())
                .bind(done.started.to_string())
                .bind(done.finished.to_string())
                .bind(new.tenant.to_string())
                .bind(payload.clone())
                .bind(done.owner.to_string())
                .bind(done.body.to_string())
                .bind(i64::from(done.serve))
                .bind(done.limits.quota)
                .bind(done.limits.max_queued)
                .fetch_one(&mut *conn)
                .await?;
            let stored: i64 = row.try_get("stored")?;
            return Ok(if stored == 1 {
                StoredDone::Stored(Box::new(record))
            } else {
                StoredDone::NotStored(Self::admission_of(&row)?)
            });
        }
        self.store_done_in_steps(conn, &done, id, payload, record)
            .await
    }

    /// [`Self::store_done_in`] where the dialect has no one statement for
    /// it: the admission read, then each row written, in one transaction.
    async fn store_done_in_steps(
        &self,
        conn: &mut DB::Connection,
        done: &DoneJob<'_>,
        id: String,
        payload: &str,
        record: JobRecord,
    ) -> Result<StoredDone, StoreError> {
        let new = &done.new;
        let mut tx = conn.begin().await?;
        let row = sqlx::query(ADMISSION)
            .bind(new.tenant.to_string())
            .bind(new.key.to_string())
            .fetch_one(&mut *tx)
            .await?;
        let admission = Self::admission_of(&row)?;
        if !done.limits.admit_new(&admission) {
            tx.rollback().await?;
            return Ok(StoredDone::NotStored(admission));
        }
        let inserted = sqlx::query(
            "INSERT INTO computations (id, key, kind, spec, status, numerics, created_at, started_at, finished_at, tenant, served_at) \
             VALUES ($1, $2, $3, $4, 'succeeded', $5, $6, $7, $8, $9, $7) ON CONFLICT (key) DO NOTHING",
        )
        .bind(id.clone())
        .bind(new.key.to_string())
        .bind(new.kind.to_string())
        .bind(new.spec.to_string())
        .bind(done.numerics.to_string())
        .bind(new.now.to_string())
        .bind(done.started.to_string())
        .bind(done.finished.to_string())
        .bind(new.tenant.to_string())
        .execute(&mut *tx)
        .await?
        .rows();
        if inserted == 0 {
            tx.rollback().await?;
            return Ok(StoredDone::NotStored(admission));
        }
        sqlx::query(
            "INSERT INTO tasks (computation_id, idx, payload, status, progress, attempts, done_by, created_at) \
             VALUES ($1, 0, $2, 'done', 1, 1, $3, $4)",
        )
        .bind(id.clone())
        .bind(payload.to_string())
        .bind(done.owner.to_string())
        .bind(new.now.to_string())
        .execute(&mut *tx)
        .await?;
        sqlx::query("INSERT INTO results (computation_id, body) VALUES ($1, $2)")
            .bind(id.clone())
            .bind(done.body.to_string())
            .execute(&mut *tx)
            .await?;
        // Its tenant was served now, as by a claim: its queued work, if any,
        // comes after the other tenants' in the next turns.
        if done.serve {
            sqlx::query(
                "INSERT INTO tenants (name, served_at) VALUES ($1, $2) \
                 ON CONFLICT (name) DO UPDATE SET served_at = excluded.served_at",
            )
            .bind(new.tenant.to_string())
            .bind(done.started.to_string())
            .execute(&mut *tx)
            .await?;
        }
        sqlx::query(
            "INSERT INTO jobs (id, tenant, computation_id, status, created_at, started_at, finished_at) \
             VALUES ($1, $2, $1, 'succeeded', $3, $4, $5)",
        )
        .bind(id)
        .bind(new.tenant.to_string())
        .bind(new.now.to_string())
        .bind(done.started.to_string())
        .bind(done.finished.to_string())
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        Ok(StoredDone::Stored(Box::new(record)))
    }

    /// The computation `new` asks for, in the transaction on `conn`: a new
    /// one, its tasks queued, or the one of its key, queued again if it
    /// failed or was canceled. Its id, its status, and whether work is
    /// queued by this submission.
    async fn computation_for(
        &self,
        conn: &mut DB::Connection,
        new: &NewJob<'_>,
    ) -> Result<(String, Status, bool), StoreError> {
        // A new computation takes the id of the job that asks for it first.
        let fresh = new.id.to_string();
        let inserted = sqlx::query(
            "INSERT INTO computations (id, key, kind, spec, status, created_at, tenant) \
             VALUES ($1, $2, $3, $4, 'queued', $5, $6) ON CONFLICT (key) DO NOTHING",
        )
        .bind(fresh.clone())
        .bind(new.key.to_string())
        .bind(new.kind.to_string())
        .bind(new.spec.to_string())
        .bind(new.now.to_string())
        .bind(new.tenant.to_string())
        .execute(&mut *conn)
        .await?
        .rows();
        if inserted == 1 {
            Self::insert_tasks(conn, parse_id(&fresh)?, new.now, new.tasks).await?;
            return Ok((fresh, Status::Queued, true));
        }
        let id: String = sqlx::query_scalar("SELECT id FROM computations WHERE key = $1")
            .bind(new.key.to_string())
            .fetch_one(&mut *conn)
            .await?;
        let (status, _) = self
            .lock_computation(conn, &id)
            .await?
            .ok_or_else(|| StoreError::Corrupt("computation vanished".into()))?;
        if !matches!(status, Status::Failed | Status::Canceled) {
            return Ok((id, status, false));
        }
        sqlx::query(
            "UPDATE computations SET status = 'queued', error = NULL, numerics = NULL, started_at = NULL, \
             finished_at = NULL, tenant = $2, served_at = '' WHERE id = $1",
        )
        .bind(id.clone())
        .bind(new.tenant.to_string())
        .execute(&mut *conn)
        .await?;
        sqlx::query("DELETE FROM tasks WHERE computation_id = $1")
            .bind(id.clone())
            .execute(&mut *conn)
            .await?;
        Self::insert_tasks(conn, parse_id(&id)?, new.now, new.tasks).await?;
        Ok((id, Status::Queued, true))
    }

    /// The tenant's job of `computation` (at `status`; `queued`: this
    /// submission queued work), in the transaction on `conn`: a new job, or
    /// its own job again (revived if it failed or was canceled). Its id,
    /// and whether it is answered from what was computed before.
    async fn job_for(
        conn: &mut DB::Connection,
        new: &NewJob<'_>,
        computation: &str,
        status: Status,
        queued: bool,
    ) -> Result<(String, bool), StoreError> {
        // The job's own status follows its computation's from here on.
        let started = matches!(status, Status::Running | Status::Succeeded).then_some(new.now);
        let finished = (status == Status::Succeeded).then_some(new.now);
        let own =
            sqlx::query("SELECT id, status FROM jobs WHERE tenant = $1 AND computation_id = $2")
                .bind(new.tenant.to_string())
                .bind(computation.to_string())
                .fetch_optional(&mut *conn)
                .await?;
        if let Some(row) = own {
            let id: String = row.try_get("id")?;
            let own_status = parse_status(&row.try_get::<String, _>("status")?)?;
            if matches!(own_status, Status::Failed | Status::Canceled) {
                sqlx::query(
                    "UPDATE jobs SET status = $2, error = NULL, started_at = $3, finished_at = $4 WHERE id = $1",
                )
                .bind(id.clone())
                .bind(status.as_str().to_string())
                .bind(started.map(str::to_string))
                .bind(finished.map(str::to_string))
                .execute(&mut *conn)
                .await?;
            }
            return Ok((id, !queued));
        }
        sqlx::query(
            "INSERT INTO jobs (id, tenant, computation_id, status, created_at, started_at, finished_at) \
             VALUES ($1, $2, $3, $4, $5, $6, $7)",
        )
        .bind(new.id.to_string())
        .bind(new.tenant.to_string())
        .bind(computation.to_string())
        .bind(status.as_str().to_string())
        .bind(new.now.to_string())
        .bind(started.map(str::to_string))
        .bind(finished.map(str::to_string))
        .execute(&mut *conn)
        .await?;
        Ok((new.id.to_string(), !queued))
    }

    async fn cancel_in(
        &self,
        conn: &mut DB::Connection,
        tenant: &str,
        id: Uuid,
        now: &str,
    ) -> Result<Option<Canceled>, StoreError> {
        let mut tx = conn.begin().await?;
        let computation: Option<String> =
            sqlx::query_scalar("SELECT computation_id FROM jobs WHERE id = $1 AND tenant = $2")
                .bind(id.to_string())
                .bind(tenant.to_string())
                .fetch_optional(&mut *tx)
                .await?;
        let Some(computation) = computation else {
            return Ok(None);
        };
        let (_, owner) = self
            .lock_computation(&mut tx, &computation)
            .await?
            .ok_or_else(|| StoreError::Corrupt("computation vanished".into()))?;
        let canceled = sqlx::query(
            "UPDATE jobs SET status = 'canceled', finished_at = $2 WHERE id = $1 AND status IN ('queued', 'running')",
        )
        .bind(id.to_string())
        .bind(now.to_string())
        .execute(&mut *tx)
        .await?
        .rows();
        let mut stopped = false;
        if canceled == 1 {
            let next: Option<String> = sqlx::query_scalar(
                "SELECT tenant FROM jobs WHERE computation_id = $1 AND status IN ('queued', 'running') \
                 ORDER BY created_at LIMIT 1",
            )
            .bind(computation.clone())
            .fetch_optional(&mut *tx)
            .await?;
            match next {
                None => {
                    // No live job needs it any more.
                    stopped = sqlx::query(
                        "UPDATE computations SET status = 'canceled', finished_at = $2 WHERE id = $1 AND status IN ('queued', 'running')",
                    )
                    .bind(computation.clone())
                    .bind(now.to_string())
                    .execute(&mut *tx)
                    .await?
                    .rows()
                        == 1;
                    sqlx::query(
                        "UPDATE tasks SET status = 'canceled', lease_owner = NULL, lease_until = NULL \
                         WHERE computation_id = $1 AND status IN ('queued', 'running')",
                    )
                    .bind(computation.clone())
                    .execute(&mut *tx)
                    .await?;
                }
                Some(next) if owner == tenant && next != tenant => {
                    // Its tasks now take the turns of a tenant that still wants it.
                    sqlx::query("UPDATE computations SET tenant = $2 WHERE id = $1")
                        .bind(computation.clone())
                        .bind(next)
                        .execute(&mut *tx)
                        .await?;
                }
                Some(_) => {}
            }
        }
        if canceled == 1 {
            // Waiters on other instances read the job again: they must not
            // take a later success of its computation (for other tenants'
            // jobs) for this job's. Both lock the computation's row, so they
            // commit, and are announced, in order.
            Self::announce_finished(&mut tx, &Finished::ended(parse_id(&computation)?)).await?;
        }
        let job = self
            .job(&mut tx, tenant, id)
            .await?
            .ok_or_else(|| StoreError::Corrupt("canceled job vanished".into()))?;
        tx.commit().await?;
        Ok(Some(Canceled {
            job,
            changed: canceled == 1,
            stopped,
        }))
    }

    async fn delete_in(
        &self,
        conn: &mut DB::Connection,
        tenant: &str,
        id: Uuid,
    ) -> Result<Deleted, StoreError> {
        let mut tx = conn.begin().await?;
        let Some(job) = self.job(&mut tx, tenant, id).await? else {
            return Ok(Deleted::NotFound);
        };
        if !job.status.is_final() {
            return Ok(Deleted::NotFinished(Box::new(job)));
        }
        let computation = job.computation.to_string();
        self.lock_computation(&mut tx, &computation).await?;
        sqlx::query("DELETE FROM jobs WHERE id = $1")
            .bind(id.to_string())
            .execute(&mut *tx)
            .await?;
        sqlx::query(
            "DELETE FROM computations WHERE id = $1 AND status NOT IN ('queued', 'running') \
             AND NOT EXISTS (SELECT 1 FROM jobs j WHERE j.computation_id = computations.id)",
        )
        .bind(computation)
        .execute(&mut *tx)
        .await?;
        Self::announce_deleted(&mut tx, Deletion::Job(id)).await?;
        tx.commit().await?;
        self.deletions.announce(Deletion::Job(id));
        Ok(Deleted::Gone)
    }

    /// Tells the other instances `payload` by the dialect's `statement`
    /// (one of its announcements, `$1` the payload) when `tx` commits (and
    /// only then), where there are others.
    async fn tell_others(
        tx: &mut DB::Connection,
        statement: Option<&'static str>,
        payload: String,
    ) -> Result<(), StoreError> {
        if let Some(sql) = statement {
            sqlx::query(sql).bind(payload).execute(&mut *tx).await?;
        }
        Ok(())
    }

    /// Tells the other instances of `deletion` when `tx` commits.
    async fn announce_deleted(
        tx: &mut DB::Connection,
        deletion: Deletion,
    ) -> Result<(), StoreError> {
        Self::tell_others(tx, DB::ANNOUNCE_DELETED, deletion.payload()).await
    }

    async fn purge_in(&self, conn: &mut DB::Connection, before: &str) -> Result<u64, StoreError> {
        let mut tx = conn.begin().await?;
        let jobs = sqlx::query(
            "DELETE FROM jobs WHERE finished_at IS NOT NULL AND finished_at < $1 \
             AND status IN ('succeeded', 'failed', 'canceled')",
        )
        .bind(before.to_string())
        .execute(&mut *tx)
        .await?
        .rows();
        if jobs > 0 {
            sqlx::query(
                "DELETE FROM computations WHERE status NOT IN ('queued', 'running') \
                 AND NOT EXISTS (SELECT 1 FROM jobs j WHERE j.computation_id = computations.id)",
            )
            .execute(&mut *tx)
            .await?;
            Self::announce_deleted(&mut tx, Deletion::Any).await?;
        }
        tx.commit().await?;
        if jobs > 0 {
            self.deletions.announce(Deletion::Any);
        }
        Ok(jobs)
    }

    /// The next task to claim and its computation: a lapsed lease first, then
    /// round robin over tenants and over each tenant's computations.
    async fn next_task(
        &self,
        tx: &mut DB::Connection,
        started_only: bool,
    ) -> Result<Option<(String, i64)>, StoreError> {
        let lapsed = sqlx::query(AssertSqlSafe(self.sql.lapsed_task.as_str()))
            .fetch_optional(&mut *tx)
            .await?;
        if let Some(row) = lapsed {
            return Ok(Some((row.try_get("computation_id")?, row.try_get("idx")?)));
        }
        let only = i64::from(started_only);
        let tenant: Option<String> =
            sqlx::query_scalar(AssertSqlSafe(self.sql.next_tenant.as_str()))
                .bind(only)
                .fetch_optional(&mut *tx)
                .await?;
        let Some(tenant) = tenant else {
            return Ok(None);
        };
        let mut computation: Option<String> =
            sqlx::query_scalar(AssertSqlSafe(self.sql.next_of_tenant.as_str()))
                .bind(tenant)
                .bind(only)
                .fetch_optional(&mut *tx)
                .await?;
        if computation.is_none() && !DB::SINGLE_INSTANCE {
            // Another instance is claiming from each of this tenant's
            // computations at this moment: take anyone's.
            computation = sqlx::query_scalar(AssertSqlSafe(self.sql.next_of_anyone.as_str()))
                .bind(only)
                .fetch_optional(&mut *tx)
                .await?;
        }
        let Some(computation) = computation else {
            return Ok(None);
        };
        let idx: Option<i64> =
            sqlx::query_scalar(AssertSqlSafe(self.sql.first_queued_task.as_str()))
                .bind(computation.clone())
                .fetch_optional(&mut *tx)
                .await?;
        Ok(idx.map(|idx| (computation, idx)))
    }

    async fn claim_in_tx(
        &self,
        conn: &mut DB::Connection,
        owner: &str,
        now: &str,
        lease: Duration,
        started_only: bool,
    ) -> Result<Option<TaskClaim>, StoreError> {
        if let Some(sql) = DB::CLAIM {
            let row = sqlx::query(sql)
                .bind(owner.to_string())
                .bind(lease.as_secs_f64())
                .bind(i64::from(started_only))
                .bind(now.to_string())
                .fetch_optional(&mut *conn)
                .await?;
            let Some(row) = row else {
                return Ok(None);
            };
            return Ok(Some(TaskClaim {
                computation: parse_id(&row.try_get::<String, _>("computation_id")?)?,
                idx: row.try_get("idx")?,
                kind: row.try_get("kind")?,
                payload: row.try_get("payload")?,
                attempts: row.try_get("attempts")?,
                tasks: row.try_get("tasks")?,
            }));
        }
        let mut tx = conn.begin().await?;
        let Some((computation, idx)) = self.next_task(&mut tx, started_only).await? else {
            tx.commit().await?;
            return Ok(None);
        };
        let task = sqlx::query(AssertSqlSafe(self.sql.take_task.as_str()))
            .bind(computation.clone())
            .bind(idx)
            .bind(owner.to_string())
            .bind(lease.as_secs_f64())
            .fetch_one(&mut *tx)
            .await?;
        let row = sqlx::query(
            "UPDATE computations SET status = 'running', served_at = $2, \
             started_at = COALESCE(started_at, CASE WHEN $2 > created_at THEN $2 ELSE created_at END) \
             WHERE id = $1 RETURNING kind, tenant",
        )
        .bind(computation.clone())
        .bind(now.to_string())
        .fetch_one(&mut *tx)
        .await?;
        let kind: String = row.try_get("kind")?;
        let tenant: String = row.try_get("tenant")?;
        sqlx::query(
            "UPDATE jobs SET status = 'running', started_at = COALESCE(started_at, $2) \
             WHERE computation_id = $1 AND status = 'queued'",
        )
        .bind(computation.clone())
        .bind(now.to_string())
        .execute(&mut *tx)
        .await?;
        let tasks: i64 = sqlx::query_scalar("SELECT COUNT(*) FROM tasks WHERE computation_id = $1")
            .bind(computation.clone())
            .fetch_one(&mut *tx)
            .await?;
        sqlx::query("UPDATE tenants SET served_at = $2 WHERE name = $1")
            .bind(tenant)
            .bind(now.to_string())
            .execute(&mut *tx)
            .await?;
        tx.commit().await?;
        Ok(Some(TaskClaim {
            computation: parse_id(&computation)?,
            idx,
            kind,
            payload: task.try_get("payload")?,
            attempts: task.try_get("attempts")?,
            tasks,
        }))
    }

    /// Marks a live computation and its live jobs succeeded with its result,
    /// in `tx`; returns whether it was (one already finished or canceled is
    /// left alone).
    async fn store_result(
        tx: &mut DB::Connection,
        computation: Uuid,
        body: &str,
        numerics: &str,
        now: &str,
    ) -> Result<bool, StoreError> {
        let id = computation.to_string();
        let updated = sqlx::query(
            "UPDATE computations SET status = 'succeeded', numerics = $2, finished_at = $3 \
             WHERE id = $1 AND status IN ('queued', 'running')",
        )
        .bind(id.clone())
        .bind(numerics.to_string())
        .bind(now.to_string())
        .execute(&mut *tx)
        .await?
        .rows();
        if updated == 1 {
            // The result is kept once, in `results`; task parts are no longer needed.
            sqlx::query("UPDATE tasks SET result = NULL WHERE computation_id = $1")
                .bind(id.clone())
                .execute(&mut *tx)
                .await?;
            sqlx::query(
                "INSERT INTO results (computation_id, body) VALUES ($1, $2) ON CONFLICT (computation_id) DO NOTHING",
            )
            .bind(id.clone())
            .bind(body.to_string())
            .execute(&mut *tx)
            .await?;
            sqlx::query(
                "UPDATE jobs SET status = 'succeeded', finished_at = $2, started_at = COALESCE(started_at, $2) \
                 WHERE computation_id = $1 AND status IN ('queued', 'running')",
            )
            .bind(id)
            .bind(now.to_string())
            .execute(&mut *tx)
            .await?;
            Self::announce_finished(tx, &Finished::succeeded(computation, numerics, now)).await?;
        }
        Ok(updated == 1)
    }

    /// Tells the other instances that a computation ended when `tx` commits.
    async fn announce_finished(
        tx: &mut DB::Connection,
        finished: &Finished,
    ) -> Result<(), StoreError> {
        Self::tell_others(tx, DB::ANNOUNCE_FINISHED, finished.payload()).await
    }

    /// `done` is the result document, its numerics and the time.
    async fn complete_only_in(
        &self,
        conn: &mut DB::Connection,
        computation: Uuid,
        idx: i64,
        owner: &str,
        (body, numerics, now): (&str, &str, &str),
    ) -> Result<bool, StoreError> {
        let mut tx = conn.begin().await?;
        let held = sqlx::query(
            "UPDATE tasks SET status = 'done', progress = 1, done_by = lease_owner, lease_owner = NULL, lease_until = NULL \
             WHERE computation_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
        )
        .bind(computation.to_string())
        .bind(idx)
        .bind(owner.to_string())
        .execute(&mut *tx)
        .await?
        .rows();
        let stored =
            held == 1 && Self::store_result(&mut tx, computation, body, numerics, now).await?;
        tx.commit().await?;
        if stored {
            self.finished
                .announce(Finished::succeeded(computation, numerics, now));
        }
        Ok(stored)
    }

    async fn succeed_in(
        &self,
        conn: &mut DB::Connection,
        computation: Uuid,
        body: &str,
        numerics: &str,
        now: &str,
    ) -> Result<bool, StoreError> {
        let mut tx = conn.begin().await?;
        let stored = Self::store_result(&mut tx, computation, body, numerics, now).await?;
        tx.commit().await?;
        if stored {
            self.finished
                .announce(Finished::succeeded(computation, numerics, now));
        }
        Ok(stored)
    }

    async fn fail_in(
        &self,
        conn: &mut DB::Connection,
        computation: Uuid,
        error: &str,
        now: &str,
    ) -> Result<bool, StoreError> {
        let id = computation.to_string();
        let mut tx = conn.begin().await?;
        let n = sqlx::query(
            "UPDATE computations SET status = 'failed', error = $2, finished_at = $3 WHERE id = $1 AND status IN ('queued', 'running')",
        )
        .bind(id.clone())
        .bind(error.to_string())
        .bind(now.to_string())
        .execute(&mut *tx)
        .await?
        .rows();
        sqlx::query(
            "UPDATE tasks SET status = 'canceled', lease_owner = NULL, lease_until = NULL \
             WHERE computation_id = $1 AND status IN ('queued', 'running')",
        )
        .bind(id.clone())
        .execute(&mut *tx)
        .await?;
        sqlx::query(
            "UPDATE jobs SET status = 'failed', error = $2, finished_at = $3 \
             WHERE computation_id = $1 AND status IN ('queued', 'running')",
        )
        .bind(id)
        .bind(error.to_string())
        .bind(now.to_string())
        .execute(&mut *tx)
        .await?;
        if n == 1 {
            Self::announce_finished(&mut tx, &Finished::ended(computation)).await?;
        }
        tx.commit().await?;
        Ok(n == 1)
    }

    /// A write of one statement (no transaction needed), with its effect on
    /// readiness noted.
    async fn write_one(
        &self,
        query: sqlx::query::Query<'_, DB, DB::Arguments>,
    ) -> Result<u64, StoreError> {
        let mut writing = self.writing().await?;
        let result = query
            .execute(writing.conn())
            .await
            .map(|r| r.rows())
            .map_err(StoreError::from);
        self.settle(&mut writing, &result).await;
        result
    }
}

/// The rows a statement changed, whatever the database.
pub trait RowsAffected {
    /// How many rows the statement changed.
    fn rows(&self) -> u64;
}

impl RowsAffected for sqlx::sqlite::SqliteQueryResult {
    fn rows(&self) -> u64 {
        self.rows_affected()
    }
}

impl RowsAffected for sqlx::postgres::PgQueryResult {
    fn rows(&self) -> u64 {
        self.rows_affected()
    }
}

impl<DB> JobStore for SqlStore<DB>
where
    DB: Dialect,
    DB::QueryResult: RowsAffected,
    for<'c> &'c mut DB::Connection: Executor<'c, Database = DB>,
    DB::Arguments: IntoArguments<DB>,
    String: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    Option<String>: for<'q> Encode<'q, DB>,
    Option<i64>: for<'q> Encode<'q, DB>,
    Vec<u8>: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    i64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    f64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    for<'n> &'n str: ColumnIndex<DB::Row>,
    usize: ColumnIndex<DB::Row>,
{
    fn submit<'a>(&'a self, job: NewJob<'a>) -> BoxFuture<'a, Result<Submitted, StoreError>> {
        Box::pin(async move { in_write_turn!(self, |conn| self.submit_in(conn, job)) })
    }

    fn store_done<'a>(
        &'a self,
        done: DoneJob<'a>,
    ) -> BoxFuture<'a, Result<StoredDone, StoreError>> {
        Box::pin(async move { in_write_turn!(self, |conn| self.store_done_in(conn, done)) })
    }

    fn get<'a>(
        &'a self,
        tenant: &'a str,
        id: Uuid,
    ) -> BoxFuture<'a, Result<Option<JobRecord>, StoreError>> {
        Box::pin(async move {
            let mut conn = self.pool.acquire().await?;
            self.job(&mut conn, tenant, id).await
        })
    }

    fn result(&self, computation: Uuid) -> BoxFuture<'_, Result<Option<String>, StoreError>> {
        Box::pin(async move {
            let body: Option<String> =
                sqlx::query_scalar("SELECT body FROM results WHERE computation_id = $1")
                    .bind(computation.to_string())
                    .fetch_optional(&self.pool)
                    .await?;
            Ok(body)
        })
    }

    fn list<'a>(
        &'a self,
        tenant: &'a str,
        q: &'a ListQuery,
    ) -> BoxFuture<'a, Result<Vec<JobRecord>, StoreError>> {
        Box::pin(async move {
            // UUIDv7 ids sort by creation time: newest first is id descending.
            let rows = sqlx::query(AssertSqlSafe(self.sql.job_list.as_str()))
                .bind(tenant.to_string())
                .bind(q.status.map(|s| s.as_str().to_string()))
                .bind(q.kind.clone())
                .bind(q.before.map(|id| id.to_string()))
                .bind(i64::from(q.limit))
                .fetch_all(&self.pool)
                .await?;
            rows.iter().map(Self::record).collect()
        })
    }

    fn cancel<'a>(
        &'a self,
        tenant: &'a str,
        id: Uuid,
        now: &'a str,
    ) -> BoxFuture<'a, Result<Option<Canceled>, StoreError>> {
        Box::pin(async move { in_write_turn!(self, |conn| self.cancel_in(conn, tenant, id, now)) })
    }

    fn delete<'a>(
        &'a self,
        tenant: &'a str,
        id: Uuid,
    ) -> BoxFuture<'a, Result<Deleted, StoreError>> {
        Box::pin(async move { in_write_turn!(self, |conn| self.delete_in(conn, tenant, id)) })
    }

    fn purge<'a>(&'a self, before: &'a str) -> BoxFuture<'a, Result<u64, StoreError>> {
        Box::pin(async move { in_write_turn!(self, |conn| self.purge_in(conn, before)) })
    }

    fn admission<'a>(
        &'a self,
        tenant: &'a str,
        key: &'a str,
    ) -> BoxFuture<'a, Result<Admission, StoreError>> {
        Box::pin(async move {
            let row = sqlx::query(ADMISSION)
                .bind(tenant.to_string())
                .bind(key.to_string())
                .fetch_one(&self.pool)
                .await?;
            Self::admission_of(&row)
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
            in_write_turn!(self, |conn| self.claim_in_tx(
                conn,
                owner,
                now,
                lease,
                started_only
            ))
        })
    }

    fn heartbeat<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
        progress: f64,
        lease: Duration,
    ) -> BoxFuture<'a, Result<Option<Status>, StoreError>> {
        Box::pin(async move {
            let held = self
                .write_one(
                    sqlx::query(AssertSqlSafe(self.sql.heartbeat.as_str()))
                        .bind(computation.to_string())
                        .bind(idx)
                        .bind(owner.to_string())
                        .bind(progress)
                        .bind(lease.as_secs_f64()),
                )
                .await?;
            if held == 0 {
                return Ok(None);
            }
            let status: Option<String> =
                sqlx::query_scalar("SELECT status FROM computations WHERE id = $1")
                    .bind(computation.to_string())
                    .fetch_optional(&self.pool)
                    .await?;
            Ok(status.and_then(|s| Status::parse(&s)))
        })
    }

    fn complete<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
        result: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let n = self
                .write_one(
                    sqlx::query(
                        "UPDATE tasks SET status = 'done', progress = 1, result = $4, done_by = lease_owner, \
                         lease_owner = NULL, lease_until = NULL \
                         WHERE computation_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
                    )
                    .bind(computation.to_string())
                    .bind(idx)
                    .bind(owner.to_string())
                    .bind(result.to_string()),
                )
                .await?;
            Ok(n == 1)
        })
    }

    fn complete_only<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            in_write_turn!(self, |conn| self.complete_only_in(
                conn,
                computation,
                idx,
                owner,
                (body, numerics, now)
            ))
        })
    }

    fn parts(&self, computation: Uuid) -> BoxFuture<'_, Result<Option<Vec<String>>, StoreError>> {
        Box::pin(async move {
            // Whether all are done, from the index (not the rows, whose
            // payloads may be long); the results are read once.
            let undone: i64 = sqlx::query_scalar(
                "SELECT COUNT(*) FROM tasks WHERE computation_id = $1 AND status <> 'done'",
            )
            .bind(computation.to_string())
            .fetch_one(&self.pool)
            .await?;
            if undone > 0 {
                return Ok(None);
            }
            let rows = sqlx::query(
                "SELECT status, result FROM tasks WHERE computation_id = $1 ORDER BY idx",
            )
            .bind(computation.to_string())
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
        computation: Uuid,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            in_write_turn!(self, |conn| self.succeed_in(
                conn,
                computation,
                body,
                numerics,
                now
            ))
        })
    }

    fn fail<'a>(
        &'a self,
        computation: Uuid,
        error: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(
            async move { in_write_turn!(self, |conn| self.fail_in(conn, computation, error, now)) },
        )
    }

    fn requeue<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>> {
        Box::pin(async move {
            let n = self
                .write_one(
                    sqlx::query(
                        "UPDATE tasks SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL \
                         WHERE computation_id = $1 AND idx = $2 AND lease_owner = $3 AND status = 'running'",
                    )
                    .bind(computation.to_string())
                    .bind(idx)
                    .bind(owner.to_string()),
                )
                .await?;
            Ok(n == 1)
        })
    }

    fn recover(&self) -> BoxFuture<'_, Result<u64, StoreError>> {
        Box::pin(async move {
            if !DB::SINGLE_INSTANCE {
                // Other instances may be running tasks: lapsed leases are
                // taken over by whoever claims next, so nothing is forced here.
                return Ok(0);
            }
            // One process owns the database: whatever it was running when it
            // died runs again.
            self.write_one(sqlx::query(
                "UPDATE tasks SET status = 'queued', progress = 0, lease_owner = NULL, lease_until = NULL WHERE status = 'running'",
            ))
            .await
        })
    }

    fn stranded(&self) -> BoxFuture<'_, Result<Vec<Uuid>, StoreError>> {
        Box::pin(async move {
            let ids: Vec<String> = sqlx::query_scalar(
                "SELECT c.id FROM computations c WHERE c.status IN ('queued', 'running') \
                 AND EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id) \
                 AND NOT EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id AND t.status <> 'done') \
                 LIMIT 100",
            )
            .fetch_all(&self.pool)
            .await?;
            ids.iter().map(|id| parse_id(id)).collect()
        })
    }

    fn computation(&self, id: Uuid) -> BoxFuture<'_, Result<Option<Computation>, StoreError>> {
        Box::pin(async move {
            let row =
                sqlx::query("SELECT id, key, kind, spec, status FROM computations WHERE id = $1")
                    .bind(id.to_string())
                    .fetch_optional(&self.pool)
                    .await?;
            let Some(row) = row else {
                return Ok(None);
            };
            Ok(Some(Computation {
                id: parse_id(&row.try_get::<String, _>("id")?)?,
                key: row.try_get("key")?,
                kind: row.try_get("kind")?,
                spec: row.try_get("spec")?,
                status: parse_status(&row.try_get::<String, _>("status")?)?,
            }))
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
                let health = self.health.lock().unwrap_or_else(|e| e.into_inner());
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
            self.write_one(
                sqlx::query(
                    "INSERT INTO probe (id, at) VALUES (1, $1) ON CONFLICT (id) DO UPDATE SET at = excluded.at",
                )
                .bind(super::now_rfc3339()),
            )
            .await
            .map(|_| ())
        })
    }

    fn queued_elsewhere(&self) -> BoxFuture<'_, ()> {
        let elsewhere = self.elsewhere.clone();
        Box::pin(async move {
            match elsewhere {
                Some(n) => n.notified().await,
                None => std::future::pending().await,
            }
        })
    }

    fn deletions(&self) -> Arc<Deletions> {
        self.deletions.clone()
    }

    fn finished(&self) -> Announcer {
        self.finished.clone()
    }

    fn announce_queued(&self) -> BoxFuture<'_, ()> {
        Box::pin(async move {
            if let Some(sql) = DB::ANNOUNCE {
                let _ = sqlx::query(sql).execute(&self.pool).await;
            }
        })
    }
}

/// The job `done` stores, as read back once stored: its own computation,
/// succeeded.
fn done_record(done: &DoneJob<'_>) -> JobRecord {
    let new = &done.new;
    JobRecord {
        id: new.id,
        tenant: new.tenant.to_string(),
        computation: new.id,
        key: new.key.to_string(),
        kind: new.kind.to_string(),
        spec: new.spec.to_string(),
        status: Status::Succeeded,
        progress: 1.0,
        error: None,
        numerics: Some(done.numerics.to_string()),
        created_at: new.now.to_string(),
        started_at: Some(done.started.to_string()),
        finished_at: Some(done.finished.to_string()),
    }
}
