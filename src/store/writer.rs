//! Where writes run: on connections of the store's own, kept open between
//! writes and taken in turns, outside the pool that serves reads.
//!
//! - SQLite (one writer at a time): one connection, so writes queue here
//!   rather than in SQLite's busy handler.
//! - PostgreSQL: a few connections, as many writes at once.
//!
//! A connection of its own keeps its statements prepared, and a write pays
//! no pool checkout. Nor does it pay the pool's check of each connection
//! given back (a round trip to the database after every write, whose
//! database work and wake-ups compete on a small machine with the next
//! request). What that check guards against is kept otherwise: a connection
//! whose write failed, or was abandoned midway (its request gone), is closed
//! rather than used again ([`Writing::keep`] is never reached), a transaction
//! dropped uncommitted is rolled back before the connection is given back,
//! and one idle
//! for longer than the ping period (the database may have restarted
//! meanwhile) is pinged first and replaced if it does not answer.

use std::sync::Mutex;
use std::time::{Duration, Instant};

use sqlx::{ConnectOptions, Connection, Database, Pool};
use tokio::sync::{Semaphore, SemaphorePermit};

/// The connections for writes: at most `size` open, each used by one write
/// at a time, opened at need and again after a write failed on one.
pub struct Writer<DB: Database> {
    /// Opened with this pool's options.
    pool: Pool<DB>,
    /// Connections open and not in use, the most recently used last, each
    /// with when it was given back.
    idle: Mutex<Vec<(DB::Connection, Instant)>>,
    /// A permit for each connection that may be in use.
    turns: Semaphore,
    /// How many connections.
    size: u32,
    /// A connection idle for longer is pinged before it is used.
    ping_idle: Option<Duration>,
    /// Longest wait for a turn: past it the write fails as the pool's
    /// acquisition does (`PoolTimedOut`: the service answers 503).
    wait: Option<Duration>,
}

impl<DB: Database> std::fmt::Debug for Writer<DB> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Writer").field("size", &self.size).finish()
    }
}

impl<DB: Database> Writer<DB> {
    /// Up to `size` (at least 1) connections with `pool`'s options; a
    /// connection idle for longer than `ping_idle` is pinged before use; a
    /// write waits at most `wait` for its turn.
    pub fn new(
        pool: Pool<DB>,
        size: u32,
        ping_idle: Option<Duration>,
        wait: Option<Duration>,
    ) -> Self {
        let size = size.max(1);
        Writer {
            pool,
            idle: Mutex::new(Vec::new()),
            turns: Semaphore::new(size as usize),
            size,
            ping_idle,
            wait,
        }
    }

    /// How many connections write at most at once.
    pub fn size(&self) -> u32 {
        self.size
    }

    /// Waits until no write runs and takes every turn: nothing writes until
    /// it is dropped.
    pub async fn all_turns(&self) -> Option<SemaphorePermit<'_>> {
        self.turns.acquire_many(self.size).await.ok()
    }

    fn idle(&self) -> std::sync::MutexGuard<'_, Vec<(DB::Connection, Instant)>> {
        self.idle.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// A write in progress, on its connection, in its turn.
pub struct Writing<'a, DB: Database> {
    writer: &'a Writer<DB>,
    /// Open until the write is dropped.
    conn: Option<DB::Connection>,
    /// Whether the write ended well: only then is the connection used again.
    kept: bool,
    _turn: SemaphorePermit<'a>,
}

impl<'a, DB: Database> Writing<'a, DB> {
    /// A connection to write on, in its turn: the one given back last, or a
    /// new one. Waiting for the turn, pinging and connecting take at most
    /// the writer's `wait` together: a database that does not answer (down,
    /// or stopped midway) fails the write with `PoolTimedOut`, not a hang.
    pub async fn start(writer: &'a Writer<DB>) -> Result<Writing<'a, DB>, sqlx::Error> {
        let started = Self::start_now(writer);
        match writer.wait {
            Some(wait) => tokio::time::timeout(wait, started)
                .await
                .map_err(|_| sqlx::Error::PoolTimedOut)?,
            None => started.await,
        }
    }

    async fn start_now(writer: &'a Writer<DB>) -> Result<Writing<'a, DB>, sqlx::Error> {
        let turn = writer
            .turns
            .acquire()
            .await
            .map_err(|_| sqlx::Error::PoolClosed)?;
        let taken = writer.idle().pop();
        let conn = match taken {
            Some((mut conn, since)) => {
                let stale = writer.ping_idle.is_some_and(|p| since.elapsed() > p);
                if stale && conn.ping().await.is_err() {
                    // Gone (the database restarted): a new one instead.
                    drop(conn);
                    writer.pool.connect_options().connect().await?
                } else {
                    conn
                }
            }
            None => writer.pool.connect_options().connect().await?,
        };
        Ok(Writing {
            writer,
            conn: Some(conn),
            kept: false,
            _turn: turn,
        })
    }

    /// The connection.
    pub fn conn(&mut self) -> &mut DB::Connection {
        self.conn
            .as_mut()
            .expect("a write's connection is open until the write is dropped")
    }

    /// The write ended well: the connection is given back for the next,
    /// once what the write left queued on it is sent and answered — the
    /// rollback of a transaction dropped uncommitted, which PostgreSQL's
    /// driver only queues (until the next use of the connection, which the
    /// pool's check used to be): so a connection goes back with no
    /// transaction open and no lock held. If that fails, it is closed.
    ///
    /// Without this (a failed write, or one abandoned midway) it is closed
    /// rather than used again: whatever state the failure left it in (a
    /// transaction rolled back by the database, one still open and holding
    /// a lock after a full disk or an I/O error, a statement sent and not
    /// answered), no later write inherits it.
    pub async fn keep(&mut self) {
        // `flush` sends what is queued and reads the answers pending; with
        // nothing queued it does no I/O (and on SQLite, whose rollbacks run
        // at once, nothing at all).
        if let Some(conn) = self.conn.as_mut() {
            self.kept = conn.flush().await.is_ok();
        }
    }
}

impl<DB: Database> Drop for Writing<'_, DB> {
    fn drop(&mut self) {
        if let Some(conn) = self.conn.take().filter(|_| self.kept) {
            self.writer.idle().push((conn, Instant::now()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sqlx::sqlite::{SqliteConnectOptions, SqlitePoolOptions};
    use sqlx::{Sqlite, SqlitePool};

    async fn pool(name: &str) -> (SqlitePool, std::path::PathBuf) {
        let path =
            std::env::temp_dir().join(format!("topple-writer-{name}-{}.db", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let options = SqliteConnectOptions::new()
            .filename(&path)
            .create_if_missing(true);
        let pool = SqlitePoolOptions::new()
            .max_connections(2)
            .connect_with(options)
            .await
            .expect("opens");
        (pool, path)
    }

    /// Whether the write's connection holds the temporary table (one
    /// connection's own) that an earlier write on it made.
    async fn marked(w: &mut Writing<'_, Sqlite>) -> bool {
        sqlx::query("SELECT 1 FROM temp.mark")
            .fetch_optional(w.conn())
            .await
            .is_ok()
    }

    async fn mark(w: &mut Writing<'_, Sqlite>) {
        sqlx::query("CREATE TEMP TABLE mark (x)")
            .execute(w.conn())
            .await
            .expect("creates");
    }

    #[tokio::test]
    async fn a_connection_is_used_again_only_after_a_write_that_ended_well() {
        let (pool, path) = pool("kept").await;
        let writer = Writer::new(pool, 1, None, None);
        let mut w = Writing::start(&writer).await.expect("starts");
        mark(&mut w).await;
        w.keep().await;
        drop(w);
        let mut w = Writing::start(&writer).await.expect("starts");
        assert!(marked(&mut w).await, "a kept connection is used again");
        // Not kept (a write that failed, or was abandoned): closed.
        drop(w);
        let mut w = Writing::start(&writer).await.expect("starts");
        assert!(!marked(&mut w).await, "a new connection after one not kept");
        drop(w);
        let _ = std::fs::remove_file(path);
    }

    #[tokio::test]
    async fn writes_take_turns_and_a_bounded_wait_fails_as_a_pool_timeout() {
        let (pool, path) = pool("turns").await;
        let writer = Writer::new(pool, 2, None, Some(Duration::from_millis(50)));
        assert_eq!(writer.size(), 2);
        let one = Writing::start(&writer).await.expect("first turn");
        let two = Writing::start(&writer).await.expect("second turn");
        let third = Writing::start(&writer).await;
        assert!(
            matches!(third, Err(sqlx::Error::PoolTimedOut)),
            "a third write waits at most the wait"
        );
        drop(one);
        let three = Writing::start(&writer).await.expect("a turn freed");
        // Every turn: only once no write runs.
        let all = tokio::time::timeout(Duration::from_millis(50), writer.all_turns()).await;
        assert!(all.is_err(), "all turns wait for the writes running");
        drop((two, three));
        let all = tokio::time::timeout(Duration::from_secs(5), writer.all_turns())
            .await
            .expect("all turns once no write runs");
        assert!(all.is_some());
        let _ = std::fs::remove_file(path);
    }
}
