//! The schema's migrations, compiled into the binary.
//!
//! This is what `sqlx::migrate!` embeds — the same versions and the same
//! SHA-384 checksums of the same files, so databases migrated by either agree —
//! without building sqlx's macro crate, which compiles a second SQLite and both
//! drivers for the host.

use std::borrow::Cow;

use sqlx::SqlSafeStr;
use sqlx::migrate::{Migration, MigrationType, Migrator};

/// One file of `migrations/<backend>/`: its version, description (the file
/// name's words) and SQL.
type File = (i64, &'static str, &'static str);

const SQLITE: [File; 6] = [
    (
        1,
        "jobs",
        include_str!("../../migrations/sqlite/0001_jobs.sql"),
    ),
    (
        2,
        "probe",
        include_str!("../../migrations/sqlite/0002_probe.sql"),
    ),
    (
        3,
        "tenants",
        include_str!("../../migrations/sqlite/0003_tenants.sql"),
    ),
    (
        4,
        "task state",
        include_str!("../../migrations/sqlite/0004_task_state.sql"),
    ),
    (
        5,
        "records",
        include_str!("../../migrations/sqlite/0005_records.sql"),
    ),
    (
        6,
        "live jobs",
        include_str!("../../migrations/sqlite/0006_live_jobs.sql"),
    ),
];

const POSTGRES: [File; 6] = [
    (
        1,
        "jobs",
        include_str!("../../migrations/postgres/0001_jobs.sql"),
    ),
    (
        2,
        "tenants",
        include_str!("../../migrations/postgres/0002_tenants.sql"),
    ),
    (
        3,
        "task state",
        include_str!("../../migrations/postgres/0003_task_state.sql"),
    ),
    (
        4,
        "records",
        include_str!("../../migrations/postgres/0004_records.sql"),
    ),
    (
        5,
        "live jobs",
        include_str!("../../migrations/postgres/0005_live_jobs.sql"),
    ),
    (
        6,
        "lz4",
        include_str!("../../migrations/postgres/0006_lz4.sql"),
    ),
];

fn migrator(files: &[File]) -> Migrator {
    Migrator::with_migrations(
        files
            .iter()
            .map(|&(version, description, sql)| {
                Migration::new(
                    version,
                    Cow::Borrowed(description),
                    MigrationType::Simple,
                    sql.into_sql_str(),
                    sql.starts_with("-- no-transaction"),
                )
            })
            .collect(),
    )
}

/// The SQLite schema (`migrations/sqlite`).
pub fn sqlite() -> Migrator {
    migrator(&SQLITE)
}

/// The PostgreSQL schema (`migrations/postgres`).
pub fn postgres() -> Migrator {
    migrator(&POSTGRES)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every file of each directory is listed, in order, under its number.
    #[test]
    fn every_migration_file_is_embedded() {
        for (dir, files) in [("sqlite", &SQLITE[..]), ("postgres", &POSTGRES[..])] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("migrations")
                .join(dir);
            let mut names: Vec<String> = std::fs::read_dir(&path)
                .expect("migrations directory")
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".sql"))
                .collect();
            names.sort();
            let listed: Vec<String> = files
                .iter()
                .map(|(v, d, _)| format!("{v:04}_{}.sql", d.replace(' ', "_")))
                .collect();
            assert_eq!(names, listed, "migrations/{dir}");
            for (name, (_, _, sql)) in names.iter().zip(files) {
                let on_disk = std::fs::read_to_string(path.join(name)).expect("reads");
                assert_eq!(&on_disk, sql, "{dir}/{name}");
            }
        }
    }
}
