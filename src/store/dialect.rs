//! What differs between the SQL dialects, in one place: the database clock,
//! row locks that other instances skip, and whether one process owns the
//! database. Statements are written once, in the syntax both share (`$N`
//! parameters, `ON CONFLICT`, `RETURNING`, partial indexes), with the
//! placeholders below filled per dialect.

use sqlx::{Postgres, Sqlite};

/// A SQL dialect.
pub trait Dialect: sqlx::Database {
    /// The database clock as a value comparable with `lease_until`.
    const NOW: &'static str;
    /// The database clock plus `{secs}` seconds (a placeholder of the statement).
    const NOW_PLUS: &'static str;
    /// Appended to a `SELECT` that picks work: rows another instance is
    /// claiming at this moment are skipped rather than waited for.
    const SKIP_LOCKED: &'static str;
    /// Appended to a `SELECT` of a row about to change: it is locked until
    /// the transaction ends (SQLite's writes are serialised already).
    const FOR_UPDATE: &'static str;
    /// One process owns the database: writes queue on an in-process lock
    /// (SQLite has one writer), and at start-up whatever was running is
    /// requeued rather than left to its lease.
    const SINGLE_INSTANCE: bool;
    /// A claim in one statement, where the dialect can write it so (data-
    /// modifying CTEs); else it is made step by step in a transaction.
    const CLAIM: Option<&'static str>;
    /// A job computed already stored in one statement (see
    /// [`crate::store::JobStore::store_done`]), where the dialect can write
    /// it so; else it is stored in a transaction of several.
    const STORE_DONE: Option<&'static str>;
    /// The statement that wakes other instances' idle workers, if any.
    const ANNOUNCE: Option<&'static str>;
    /// The statement that tells other instances, when its transaction
    /// commits, that finished jobs were deleted (`$1`: a job id, or `*`), if
    /// there are others.
    const ANNOUNCE_DELETED: Option<&'static str>;
    /// The statement that tells other instances, when its transaction
    /// commits, that a computation ended (`$1`: a
    /// [`crate::store::Finished`]'s payload), if there are others.
    const ANNOUNCE_FINISHED: Option<&'static str>;
}

impl Dialect for Sqlite {
    const NOW: &'static str = "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')";
    const NOW_PLUS: &'static str =
        "strftime('%Y-%m-%dT%H:%M:%fZ', 'now', printf('%+.3f seconds', {secs}))";
    const SKIP_LOCKED: &'static str = "";
    const FOR_UPDATE: &'static str = "";
    const SINGLE_INSTANCE: bool = true;
    const CLAIM: Option<&'static str> = None;
    const STORE_DONE: Option<&'static str> = None;
    const ANNOUNCE: Option<&'static str> = None;
    const ANNOUNCE_DELETED: Option<&'static str> = None;
    const ANNOUNCE_FINISHED: Option<&'static str> = None;
}

impl Dialect for Postgres {
    const NOW: &'static str = "now()";
    const NOW_PLUS: &'static str = "now() + make_interval(secs => {secs})";
    const SKIP_LOCKED: &'static str = " FOR UPDATE SKIP LOCKED";
    const FOR_UPDATE: &'static str = " FOR UPDATE";
    const SINGLE_INSTANCE: bool = false;
    const CLAIM: Option<&'static str> = Some(include_str!("claim_postgres.sql"));
    const STORE_DONE: Option<&'static str> = Some(include_str!("store_done_postgres.sql"));
    const ANNOUNCE: Option<&'static str> = Some("SELECT pg_notify('topple_tasks', '')");
    const ANNOUNCE_DELETED: Option<&'static str> = Some("SELECT pg_notify('topple_deleted', $1)");
    const ANNOUNCE_FINISHED: Option<&'static str> = Some("SELECT pg_notify('topple_finished', $1)");
}

/// `sql` with `{now}`, `{now+$N}` (the clock plus parameter `$N` seconds),
/// `{skip_locked}` and `{for_update}` filled for dialect `D`.
pub fn fill<D: Dialect>(sql: &str) -> String {
    let mut out = sql
        .replace("{now}", D::NOW)
        .replace("{skip_locked}", D::SKIP_LOCKED)
        .replace("{for_update}", D::FOR_UPDATE);
    while let Some(start) = out.find("{now+") {
        let Some(len) = out[start..].find('}') else {
            break;
        };
        let param = out[start + 5..start + len].to_string();
        let expr = D::NOW_PLUS.replace("{secs}", &param);
        out.replace_range(start..=start + len, &expr);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholders_are_filled_per_dialect() {
        let sql = "UPDATE t SET until = {now+$2} WHERE until < {now}{skip_locked}";
        assert_eq!(
            fill::<Postgres>(sql),
            "UPDATE t SET until = now() + make_interval(secs => $2) WHERE until < now() FOR UPDATE SKIP LOCKED"
        );
        assert_eq!(
            fill::<Sqlite>(sql),
            "UPDATE t SET until = strftime('%Y-%m-%dT%H:%M:%fZ', 'now', printf('%+.3f seconds', $2)) WHERE until < strftime('%Y-%m-%dT%H:%M:%fZ', 'now')"
        );
    }
}
