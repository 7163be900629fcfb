//! Per-task queue overhead — claim, one heartbeat, completion — on SQLite and
//! on PostgreSQL (skipped with a message when no PostgreSQL answers).

use std::sync::Arc;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use sqlx::Connection;
use topple::store::postgres::PgStore;
use topple::store::sqlite::SqliteStore;
use topple::store::{JobStore, now_rfc3339};
use uuid::Uuid;

const TASKS: usize = 200;

async fn cycle(store: &dyn JobStore, iters: u64) -> Duration {
    let mut total = Duration::ZERO;
    let mut left = iters as usize;
    let lease = Duration::from_secs(30);
    while left > 0 {
        let n = left.min(TASKS);
        let payloads: Vec<String> = (0..n).map(|i| format!("{{\"t\":{i}}}")).collect();
        let key = Uuid::now_v7().to_string();
        store
            .submit(
                Uuid::now_v7(),
                &key,
                "spectrum",
                "{}",
                &now_rfc3339(),
                &payloads,
            )
            .await
            .expect("submits");
        let start = Instant::now();
        for _ in 0..n {
            let t = store
                .claim("bench", &now_rfc3339(), lease)
                .await
                .expect("claims")
                .expect("a task");
            store
                .heartbeat(t.job_id, t.idx, "bench", 0.5, lease)
                .await
                .expect("beats");
            store
                .complete(t.job_id, t.idx, "bench", "{\"spectrum\":[]}")
                .await
                .expect("completes");
        }
        total += start.elapsed();
        left -= n;
    }
    total
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
