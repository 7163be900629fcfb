//! A PostgreSQL database of its own for a test run, or a loud skip.
#![allow(dead_code)]

pub mod client;
pub mod server;

use sqlx::Connection;

/// The server to test against (trust auth on this machine kind).
pub fn admin_url() -> String {
    std::env::var("TOPPLE_TEST_POSTGRES")
        .unwrap_or_else(|_| "postgres://postgres@127.0.0.1:5432/postgres".into())
}

/// A fresh database; dropped with the guard.
pub struct PgDatabase {
    pub url: String,
    name: String,
}

/// Creates a database for this test, or returns `None` with a loud message
/// when no PostgreSQL answers. Under CI (`CI=true`) PostgreSQL is required.
pub async fn pg_database(tag: &str) -> Option<PgDatabase> {
    let admin = admin_url();
    let mut conn = match sqlx::PgConnection::connect(&admin).await {
        Ok(c) => c,
        Err(e) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("PostgreSQL is required under CI but {admin} does not answer: {e}");
            }
            eprintln!(
                "\n!!!!!!!! SKIPPING PostgreSQL test {tag}: no server at {admin} ({e}).\n!!!!!!!! Start one (see README) or set TOPPLE_TEST_POSTGRES.\n"
            );
            return None;
        }
    };
    let name = format!(
        "topple_test_{tag}_{}_{}",
        std::process::id(),
        uuid::Uuid::now_v7().simple()
    );
    sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE DATABASE {name}")))
        .execute(&mut conn)
        .await
        .expect("create database");
    let base = admin.rsplit_once('/').map_or(admin.as_str(), |(b, _)| b);
    Some(PgDatabase {
        url: format!("{base}/{name}"),
        name,
    })
}

impl PgDatabase {
    /// Drops the database (closing other connections first).
    pub async fn drop_now(self) {
        if let Ok(mut conn) = sqlx::PgConnection::connect(&admin_url()).await {
            let _ = sqlx::raw_sql(sqlx::AssertSqlSafe(format!(
                "DROP DATABASE IF EXISTS {} WITH (FORCE)",
                self.name
            )))
            .execute(&mut conn)
            .await;
        }
    }
}
