//! Per-task queue overhead — claim, one heartbeat, completion (and a job's
//! assembly after its last task) — on SQLite and
//! on PostgreSQL (skipped with a message when no PostgreSQL answers): with a
//! short queue (one job of 200 tasks at a time), and with a deep one (5,000
//! single-task jobs of three tenants waiting).

use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use sqlx::Connection;
use topple::store::postgres::PgStore;
use topple::store::sqlite::SqliteStore;
use topple::store::{JobStore, NewJob, now_rfc3339};
use uuid::Uuid;

const TASKS: usize = 200;

async fn cycle(store: &dyn JobStore, iters: u64) -> Duration {
    let mut total = Duration::ZERO;
    let mut left = iters as usize;
    while left > 0 {
        let n = left.min(TASKS);
        let payloads: Vec<String> = (0..n).map(|i| format!("{{\"t\":{i}}}")).collect();
        let key = Uuid::now_v7().to_string();
        submit(store, "default", &key, &payloads).await;
        total += claim_beat_complete(store, n).await;
        left -= n;
    }
    total
}

async fn submit(store: &dyn JobStore, tenant: &str, key: &str, payloads: &[String]) {
    store
        .submit(NewJob {
            tenant,
            id: Uuid::now_v7(),
            key,
            kind: "spectrum",
            spec: "{}",
            now: &now_rfc3339(),
            tasks: payloads,
            records: &[],
        })
        .await
        .expect("submits");
}

/// The time `n` tasks take to be claimed, beaten once and completed.
async fn claim_beat_complete(store: &dyn JobStore, n: usize) -> Duration {
    let lease = Duration::from_secs(30);
    let start = Instant::now();
    for _ in 0..n {
        let t = store
            .claim("bench", &now_rfc3339(), lease)
            .await
            .expect("claims")
            .expect("a task");
        store
            .heartbeat(t.computation, t.idx, "bench", 0.5, lease)
            .await
            .expect("beats");
        // As a worker: a job of one task is completed with its result in one
        // write; the last task of a larger one is followed by its assembly.
        if t.tasks == 1 {
            store
                .complete_only(t.computation, t.idx, "bench", "{}", "{}", &now_rfc3339())
                .await
                .expect("completes");
        } else {
            store
                .complete(t.computation, t.idx, "bench", "{\"spectrum\":[]}")
                .await
                .expect("completes");
            if t.idx + 1 == t.tasks {
                store
                    .succeed(t.computation, "{}", "{}", &now_rfc3339())
                    .await
                    .expect("assembles");
            }
        }
    }
    start.elapsed()
}

/// Jobs waiting in the deep case.
const DEPTH: usize = 5_000;

/// As [`cycle`], with at least [`DEPTH`] single-task jobs of three tenants
/// waiting at every claim.
async fn deep(store: &dyn JobStore, iters: u64, waiting: &mut usize) -> Duration {
    let n = iters as usize;
    let payload = vec!["{\"t\":0}".to_string()];
    while *waiting < DEPTH + n {
        let tenant = ["alice", "bob", "carol"][*waiting % 3];
        submit(store, tenant, &Uuid::now_v7().to_string(), &payload).await;
        *waiting += 1;
    }
    let took = claim_beat_complete(store, n).await;
    *waiting -= n;
    took
}

fn queue(c: &mut Criterion) {
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let mut g = c.benchmark_group("queue_per_task");
    g.measurement_time(Duration::from_secs(5));
    let dir = std::env::temp_dir().join(format!("topple-queue-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let sqlite: Arc<dyn JobStore> = Arc::new(
        rt.block_on(SqliteStore::open(
            &format!("sqlite://{}", dir.join("q.db").display()),
            4,
        ))
        .expect("sqlite"),
    );
    g.bench_function("sqlite", |b| {
        b.iter_custom(|iters| rt.block_on(cycle(sqlite.as_ref(), iters)))
    });
    let mut waiting = 0;
    g.bench_function("sqlite_deep", |b| {
        b.iter_custom(|iters| rt.block_on(deep(sqlite.as_ref(), iters, &mut waiting)))
    });
    let admin = std::env::var("TOPPLE_TEST_POSTGRES")
        .unwrap_or_else(|_| "postgres://postgres@127.0.0.1:5432/postgres".into());
    let name = format!("topple_bench_{}", std::process::id());
    let created = rt.block_on(async {
        let mut conn = sqlx::PgConnection::connect(&admin).await.ok()?;
        sqlx::raw_sql(sqlx::AssertSqlSafe(format!("CREATE DATABASE {name}")))
            .execute(&mut conn)
            .await
            .ok()
    });
    if created.is_some() {
        let base = admin.rsplit_once('/').map_or(admin.as_str(), |(b, _)| b);
        let pg: Arc<dyn JobStore> = Arc::new(
            rt.block_on(PgStore::open(&format!("{base}/{name}"), 4))
                .expect("postgres"),
        );
        g.bench_function("postgres", |b| {
            b.iter_custom(|iters| rt.block_on(cycle(pg.as_ref(), iters)))
        });
        let mut waiting = 0;
        g.bench_function("postgres_deep", |b| {
            b.iter_custom(|iters| rt.block_on(deep(pg.as_ref(), iters, &mut waiting)))
        });
        drop(pg);
        rt.block_on(async {
            if let Ok(mut conn) = sqlx::PgConnection::connect(&admin).await {
                let _ = sqlx::raw_sql(sqlx::AssertSqlSafe(format!(
                    "DROP DATABASE IF EXISTS {name} WITH (FORCE)"
                )))
                .execute(&mut conn)
                .await;
            }
        });
    } else {
        eprintln!("no PostgreSQL at {admin}: the postgres case is skipped");
    }
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, queue);
criterion_main!(benches);
