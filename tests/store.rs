//! One suite, run against both storage backends: SQLite and PostgreSQL.

mod common;

use std::sync::Arc;
use std::time::Duration;

use topple::store::postgres::PgStore;
use topple::store::sqlite::SqliteStore;
use topple::store::{JobStore, ListQuery, Status, now_rfc3339};
use uuid::Uuid;

async fn sqlite() -> Arc<dyn JobStore> {
    let dir = std::env::temp_dir().join(format!(
        "topple-store-{}-{}",
        std::process::id(),
        Uuid::now_v7()
    ));
    std::fs::create_dir_all(&dir).expect("dir");
    Arc::new(
        SqliteStore::open(&format!("sqlite://{}", dir.join("t.db").display()), 4)
            .await
            .expect("opens"),
    )
}

fn tasks(n: usize) -> Vec<String> {
    (0..n).map(|i| format!("{{\"task\":{i}}}")).collect()
}

async fn submit(store: &dyn JobStore, key: &str, n: usize) -> (Uuid, bool) {
    let s = store
        .submit(
            Uuid::now_v7(),
            key,
            "spectrum",
            "{}",
            &now_rfc3339(),
            &tasks(n),
        )
        .await
        .expect("submits");
    (s.job.id, s.cached)
}

async fn the_same_key_is_one_job(store: &dyn JobStore) {
    let (a, cached_a) = submit(store, "k1", 2).await;
    let (b, cached_b) = submit(store, "k1", 2).await;
    let (c, cached_c) = submit(store, "k2", 1).await;
    assert_eq!((cached_a, cached_b, cached_c), (false, true, false));
    assert_eq!(a, b);
    assert_ne!(a, c);
    let job = store.get(a).await.expect("reads").expect("exists");
    assert_eq!((job.status, job.progress), (Status::Queued, 0.0));
}

async fn tasks_are_claimed_once_completed_and_assembled(store: &dyn JobStore) {
    let (id, _) = submit(store, "k3", 3).await;
    let lease = Duration::from_secs(30);
    let mut claimed = Vec::new();
    while let Some(t) = store
        .claim("w1", &now_rfc3339(), lease)
        .await
        .expect("claims")
    {
        if t.job_id == id {
            claimed.push(t.idx);
        }
        if claimed.len() == 3 {
            break;
        }
    }
    claimed.sort();
    assert_eq!(claimed, vec![0, 1, 2]);
    let job = store.get(id).await.expect("reads").expect("exists");
    assert_eq!(job.status, Status::Running);
    assert!(job.started_at.is_some());
    assert_eq!(
        store
            .heartbeat(id, 1, "w1", 0.5, lease)
            .await
            .expect("beats"),
        Some(Status::Running)
    );
    // Someone who does not hold the lease cannot beat or write.
    assert_eq!(
        store
            .heartbeat(id, 1, "w2", 0.5, lease)
            .await
            .expect("beats"),
        None
    );
    assert!(!store.complete(id, 1, "w2", "\"x\"").await.expect("writes"));
    for idx in 0..3 {
        assert!(store.parts(id).await.expect("reads").is_none());
        assert!(
            store
                .complete(id, idx, "w1", &format!("\"part{idx}\""))
                .await
                .expect("writes")
        );
        // Completing twice writes once.
        assert!(
            !store
                .complete(id, idx, "w1", "\"again\"")
                .await
                .expect("writes")
        );
    }
    let parts = store.parts(id).await.expect("reads").expect("all done");
    assert_eq!(parts, vec!["\"part0\"", "\"part1\"", "\"part2\""]);
    assert!(
        store
            .succeed(id, "{\"r\":1}", "{}", &now_rfc3339())
            .await
            .expect("stores")
    );
    assert!(
        !store
            .succeed(id, "{\"r\":2}", "{}", &now_rfc3339())
            .await
            .expect("stores")
    );
    assert_eq!(
        store.result(id).await.expect("reads").as_deref(),
        Some("{\"r\":1}")
    );
    let job = store.get(id).await.expect("reads").expect("exists");
    assert_eq!((job.status, job.progress), (Status::Succeeded, 1.0));
}

async fn a_lapsed_lease_is_taken_over_and_the_old_owner_writes_nothing(store: &dyn JobStore) {
    let (id, _) = submit(store, "k4", 1).await;
    let first = store
        .claim("dead", &now_rfc3339(), Duration::from_millis(200))
        .await
        .expect("claims")
        .expect("a task");
    assert_eq!((first.job_id, first.attempts), (id, 1));
    assert!(
        store
            .claim("other", &now_rfc3339(), Duration::from_secs(30))
            .await
            .expect("claims")
            .is_none()
    );
    tokio::time::sleep(Duration::from_millis(1200)).await;
    let second = store
        .claim("alive", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("taken over");
    assert_eq!((second.job_id, second.idx, second.attempts), (id, 0, 2));
    assert!(
        !store
            .complete(id, 0, "dead", "\"stale\"")
            .await
            .expect("writes")
    );
    assert!(
        store
            .complete(id, 0, "alive", "\"fresh\"")
            .await
            .expect("writes")
    );
    assert_eq!(
        store.parts(id).await.expect("reads"),
        Some(vec!["\"fresh\"".to_string()])
    );
}

async fn cancel_stops_every_task_and_resubmission_requeues(store: &dyn JobStore) {
    let (id, _) = submit(store, "k5", 2).await;
    let t = store
        .claim("w", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("task");
    let job = store
        .cancel(id, &now_rfc3339())
        .await
        .expect("cancels")
        .expect("exists");
    assert_eq!(job.status, Status::Canceled);
    assert_eq!(
        store
            .heartbeat(id, t.idx, "w", 0.1, Duration::from_secs(1))
            .await
            .expect("beats"),
        None
    );
    assert!(
        store
            .claim("w", &now_rfc3339(), Duration::from_secs(30))
            .await
            .expect("claims")
            .is_none()
    );
    let (again, cached) = submit(store, "k5", 2).await;
    assert_eq!((again, cached), (id, false));
    let job = store.get(id).await.expect("reads").expect("exists");
    assert_eq!(job.status, Status::Queued);
    // Failing a job cancels its other tasks.
    let t = store
        .claim("w", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("task");
    assert!(
        store
            .fail(t.job_id, "boom", &now_rfc3339())
            .await
            .expect("fails")
    );
    let job = store.get(id).await.expect("reads").expect("exists");
    assert_eq!(
        (job.status, job.error.as_deref()),
        (Status::Failed, Some("boom"))
    );
    assert!(
        store
            .claim("w", &now_rfc3339(), Duration::from_secs(30))
            .await
            .expect("claims")
            .is_none()
    );
}

async fn listing_pages_newest_first(store: &dyn JobStore) {
    let mut ids = Vec::new();
    for k in 0..5 {
        ids.push(submit(store, &format!("list{k}"), 1).await.0);
    }
    ids.reverse();
    let mut seen = Vec::new();
    let mut before = None;
    loop {
        let page = store
            .list(&ListQuery {
                status: Some(Status::Queued),
                kind: Some("spectrum".into()),
                limit: 2,
                before,
            })
            .await
            .expect("lists");
        seen.extend(page.iter().map(|j| j.id));
        if page.len() < 2 {
            break;
        }
        before = page.last().map(|j| j.id);
    }
    assert_eq!(seen, ids);
    let counts = store.counts().await.expect("counts");
    assert!(counts.iter().any(|(s, n)| *s == Status::Queued && *n == 5));
    store.ping().await.expect("pings");
}

async fn a_single_task_job_completes_in_one_write(store: &dyn JobStore) {
    let (id, _) = submit(store, "k6", 1).await;
    let t = store
        .claim("w", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("task");
    assert_eq!((t.job_id, t.tasks), (id, 1));
    assert!(
        !store
            .complete_only(id, 0, "intruder", "{}", "{}", &now_rfc3339())
            .await
            .expect("writes")
    );
    assert!(
        store
            .complete_only(id, 0, "w", "{\"r\":3}", "{\"n\":1}", &now_rfc3339())
            .await
            .expect("writes")
    );
    assert!(
        !store
            .complete_only(id, 0, "w", "{\"r\":4}", "{}", &now_rfc3339())
            .await
            .expect("writes")
    );
    let job = store.get(id).await.expect("reads").expect("exists");
    assert_eq!(
        (job.status, job.numerics.as_deref()),
        (Status::Succeeded, Some("{\"n\":1}"))
    );
    assert_eq!(
        store.result(id).await.expect("reads").as_deref(),
        Some("{\"r\":3}")
    );
}

async fn suite(store: Arc<dyn JobStore>) {
    a_single_task_job_completes_in_one_write(store.as_ref()).await;
    the_same_key_is_one_job(store.as_ref()).await;
    tasks_are_claimed_once_completed_and_assembled(store.as_ref()).await;
    a_lapsed_lease_is_taken_over_and_the_old_owner_writes_nothing(store.as_ref()).await;
    cancel_stops_every_task_and_resubmission_requeues(store.as_ref()).await;
}

#[tokio::test]
async fn sqlite_store_keeps_its_contract() {
    suite(sqlite().await).await;
    listing_pages_newest_first(sqlite().await.as_ref()).await;
}

#[tokio::test]
async fn postgres_store_keeps_its_contract() {
    let Some(db) = common::pg_database("store").await else {
        return;
    };
    let store: Arc<dyn JobStore> = Arc::new(PgStore::open(&db.url, 4).await.expect("opens"));
    suite(store.clone()).await;
    drop(store);
    let fresh = common::pg_database("store_list")
        .await
        .expect("second database");
    let store: Arc<dyn JobStore> = Arc::new(PgStore::open(&fresh.url, 4).await.expect("opens"));
    listing_pages_newest_first(store.as_ref()).await;
    drop(store);
    db.drop_now().await;
    fresh.drop_now().await;
}
