//! Where writes run: on a dialect with one writer (SQLite), one connection
//! of its own, kept open between writes and taken in turns (its statements
//! stay prepared, and a write pays no pool checkout); elsewhere, a pooled
//! connection of its own for each write.

use std::sync::Arc;

use sqlx::pool::PoolConnection;
use sqlx::{ConnectOptions, Database, Pool};
use tokio::sync::{Mutex, MutexGuard};

/// The one writer connection, opened at the first write and again after a
/// write failed on it.
pub struct Writer<DB: Database>(Mutex<Option<DB::Connection>>);

impl<DB: Database> std::fmt::Debug for Writer<DB> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Writer")
    }
}

impl<DB: Database> Default for Writer<DB> {
    fn default() -> Self {
        Writer(Mutex::new(None))
    }
}

impl<DB: Database> Writer<DB> {
    /// Waits for the turn to write; nothing else writes until it is dropped.
    pub async fn turn(&self) -> MutexGuard<'_, Option<DB::Connection>> {
        self.0.lock().await
    }
}

/// A write in progress, on its connection.
pub enum Writing<'a, DB: Database> {
    /// The writer connection, in its turn.
    Own(MutexGuard<'a, Option<DB::Connection>>),
    /// A pooled connection.
    Pooled(PoolConnection<DB>),
}

impl<'a, DB: Database> Writing<'a, DB> {
    /// A connection to write on: `writer`'s in its turn (opened with the
    /// pool's options if it is not open), or one from `pool`.
    pub async fn start(
        writer: Option<&'a Arc<Writer<DB>>>,
        pool: &Pool<DB>,
    ) -> Result<Writing<'a, DB>, sqlx::Error> {
        let Some(writer) = writer else {
            return Ok(Writing::Pooled(pool.acquire().await?));
        };
        let mut turn = writer.turn().await;
        if turn.is_none() {
            *turn = Some(pool.connect_options().connect().await?);
        }
        Ok(Writing::Own(turn))
    }

    /// The connection.
    pub fn conn(&mut self) -> &mut DB::Connection {
        match self {
            Writing::Own(turn) => turn
                .as_mut()
                .expect("the writer connection is open during its turn"),
            Writing::Pooled(c) => c,
        }
    }

    /// After a failed write the connection is closed rather than used again:
    /// whatever state the failure left it in (a transaction rolled back by
    /// the database, or one still open and holding a lock after a full disk
    /// or an I/O error), no later write inherits it.
    pub fn discard(&mut self) {
        match self {
            Writing::Own(turn) => drop(turn.take()),
            Writing::Pooled(c) => c.close_on_drop(),
        }
    }
}
