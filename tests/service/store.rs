//! One suite, run against both storage backends: SQLite and PostgreSQL.

use std::sync::Arc;
use std::time::Duration;

use topple::store::postgres::PgStore;
use topple::store::sqlite::SqliteStore;
use topple::store::{
    Admission, AdmitLimits, Deleted, DoneJob, Finished, JobRecord, JobStore, ListQuery, NewJob,
    Status, StoredDone, TaskClaim, now_rfc3339,
};
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

/// The tenant of the single-tenant cases.
const T: &str = "default";

async fn submit(store: &dyn JobStore, key: &str, n: usize) -> (Uuid, bool) {
    let s = submit_as(store, T, key, n).await;
    (s.job.id, s.cached)
}

async fn submit_as(
    store: &dyn JobStore,
    tenant: &str,
    key: &str,
    n: usize,
) -> topple::store::Submitted {
    store
        .submit(NewJob {
            tenant,
            id: Uuid::now_v7(),
            key,
            kind: "spectrum",
            spec: "{}",
            now: &now_rfc3339(),
            tasks: &tasks(n),
            records: &[],
        })
        .await
        .expect("submits")
}

/// The computation of the tenant's job.
async fn computation(store: &dyn JobStore, tenant: &str, id: Uuid) -> Uuid {
    store
        .get(tenant, id)
        .await
        .expect("reads")
        .expect("exists")
        .computation
}

async fn the_same_key_is_one_job(store: &dyn JobStore) {
    let (a, cached_a) = submit(store, "k1", 2).await;
    let (b, cached_b) = submit(store, "k1", 2).await;
    let (c, cached_c) = submit(store, "k2", 1).await;
    assert_eq!((cached_a, cached_b, cached_c), (false, true, false));
    assert_eq!(a, b);
    assert_ne!(a, c);
    let job = store.get(T, a).await.expect("reads").expect("exists");
    assert_eq!((job.status, job.progress), (Status::Queued, 0.0));
}

async fn tasks_are_claimed_once_completed_and_assembled(store: &dyn JobStore) {
    let (job, _) = submit(store, "k3", 3).await;
    let id = computation(store, T, job).await;
    let lease = Duration::from_secs(30);
    let mut claimed = Vec::new();
    while let Some(t) = store
        .claim("w1", &now_rfc3339(), lease)
        .await
        .expect("claims")
    {
        if t.computation == id {
            claimed.push(t.idx);
        }
        if claimed.len() == 3 {
            break;
        }
    }
    claimed.sort();
    assert_eq!(claimed, vec![0, 1, 2]);
    let running = store.get(T, job).await.expect("reads").expect("exists");
    assert_eq!(running.status, Status::Running);
    assert!(running.started_at.is_some());
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
    let done = store.get(T, job).await.expect("reads").expect("exists");
    assert_eq!((done.status, done.progress), (Status::Succeeded, 1.0));
}

async fn a_lapsed_lease_is_taken_over_and_the_old_owner_writes_nothing(store: &dyn JobStore) {
    let (job, _) = submit(store, "k4", 1).await;
    let id = computation(store, T, job).await;
    let first = store
        .claim("dead", &now_rfc3339(), Duration::from_millis(200))
        .await
        .expect("claims")
        .expect("a task");
    assert_eq!((first.computation, first.attempts), (id, 1));
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
    assert_eq!(
        (second.computation, second.idx, second.attempts),
        (id, 0, 2)
    );
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
    let c = computation(store, T, id).await;
    let t = store
        .claim("w", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("task");
    let canceled = store
        .cancel(T, id, &now_rfc3339())
        .await
        .expect("cancels")
        .expect("exists");
    assert_eq!(
        (canceled.job.status, canceled.changed, canceled.stopped),
        (Status::Canceled, true, true)
    );
    assert_eq!(
        store
            .heartbeat(c, t.idx, "w", 0.1, Duration::from_secs(1))
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
    let job = store.get(T, id).await.expect("reads").expect("exists");
    assert_eq!(job.status, Status::Queued);
    // Failing a job cancels its other tasks.
    let t = store
        .claim("w", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("task");
    assert!(
        store
            .fail(t.computation, "boom", &now_rfc3339())
            .await
            .expect("fails")
    );
    let job = store.get(T, id).await.expect("reads").expect("exists");
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
            .list(
                T,
                &ListQuery {
                    status: Some(Status::Queued),
                    kind: Some("spectrum".into()),
                    limit: 2,
                    before,
                },
            )
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
    let (job, _) = submit(store, "k6", 1).await;
    let id = computation(store, T, job).await;
    let t = store
        .claim("w", &now_rfc3339(), Duration::from_secs(30))
        .await
        .expect("claims")
        .expect("task");
    assert_eq!((t.computation, t.tasks), (id, 1));
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
    let job = store.get(T, job).await.expect("reads").expect("exists");
    assert_eq!(
        (job.status, job.numerics.as_deref()),
        (Status::Succeeded, Some("{\"n\":1}"))
    );
    assert_eq!(
        store.result(id).await.expect("reads").as_deref(),
        Some("{\"r\":3}")
    );
}

/// A success is announced with its end, once it committed, to this store's
/// subscribers and to `other`'s (another instance on the same database):
/// the job read while running, with that end applied, is the job as stored.
async fn a_success_is_announced_with_its_end(store: &dyn JobStore, other: Option<&dyn JobStore>) {
    let mut here = store.finished().subscribe();
    let mut there = other.map(|o| o.finished().subscribe());
    let (job, _) = submit(store, "announced", 1).await;
    let id = computation(store, T, job).await;
    let t = claim(store, Duration::from_secs(30)).await.expect("task");
    assert_eq!(t.computation, id);
    let running = job_of(store, T, job).await;
    assert_eq!(running.status, Status::Running);
    let now = now_rfc3339();
    assert!(
        store
            .complete_only(id, 0, "w", "{\"r\":5}", "{\"n\":2}", &now)
            .await
            .expect("writes")
    );
    let stored = job_of(store, T, job).await;
    let heard = here.try_recv().expect("announced here at once");
    assert_eq!(heard, Finished::succeeded(id, "{\"n\":2}", &now));
    assert_eq!(heard.apply(&running).as_ref(), Some(&stored));
    if let Some(there) = there.as_mut() {
        let heard = tokio::time::timeout(Duration::from_secs(5), there.recv())
            .await
            .expect("announced to the other instance")
            .expect("received");
        assert_eq!(heard.apply(&running).as_ref(), Some(&stored));
        // A job canceled is announced without an end: its waiters there read
        // it again rather than take a later success for it.
        let (job, _) = submit(store, "announced-then-canceled", 1).await;
        let id = computation(store, T, job).await;
        let canceled = store
            .cancel(T, job, &now_rfc3339())
            .await
            .expect("cancels")
            .expect("the job");
        assert!(canceled.changed);
        let heard = tokio::time::timeout(Duration::from_secs(5), there.recv())
            .await
            .expect("announced to the other instance")
            .expect("received");
        assert_eq!(heard, Finished::ended(id));
    }
}

/// A claim by worker "w" (none when nothing is queued).
async fn claim(store: &dyn JobStore, lease: Duration) -> Option<TaskClaim> {
    store
        .claim("w", &now_rfc3339(), lease)
        .await
        .expect("claims")
}

/// The tenant's job `id`, which exists.
async fn job_of(store: &dyn JobStore, tenant: &str, id: Uuid) -> JobRecord {
    store.get(tenant, id).await.expect("reads").expect("exists")
}

async fn tenants_share_computations_not_jobs(store: &dyn JobStore) {
    let lease = Duration::from_secs(30);
    let a = submit_as(store, "alice", "shared", 2).await;
    let b = submit_as(store, "bob", "shared", 2).await;
    // Bob's job is his own, over the computation Alice's queued.
    assert_eq!((a.cached, b.cached), (false, true));
    assert_ne!(a.job.id, b.job.id);
    assert_eq!(a.job.computation, b.job.computation);
    let c = a.job.computation;
    let shared = Shared {
        c,
        alice: a.job.id,
        bob: b.job.id,
    };
    neither_reaches_the_others_job(store, shared).await;
    let tasks = computed_once(store, shared, lease).await;
    a_cancel_leaves_the_others_job(store, shared, &tasks[0], lease).await;
    a_canceled_job_gets_the_result_without_recomputing(store, shared, &tasks, lease).await;
    a_result_stays_while_any_job_refers_to_it(store, shared).await;
    // The same spec again is new work.
    let fresh = submit_as(store, "alice", "shared", 2).await;
    assert!(!fresh.cached);
    assert_ne!(fresh.job.computation, c);
    // The last live job canceled stops the computation.
    let stop = store
        .cancel("alice", fresh.job.id, &now_rfc3339())
        .await
        .expect("cancels")
        .expect("exists");
    assert!(stop.stopped);
    assert!(claim(store, lease).await.is_none());
}

/// Alice's and Bob's jobs over one computation, `c`.
#[derive(Clone, Copy)]
struct Shared {
    c: Uuid,
    alice: Uuid,
    bob: Uuid,
}

/// Neither tenant sees, lists, cancels or deletes the other's job.
async fn neither_reaches_the_others_job(store: &dyn JobStore, shared: Shared) {
    let Shared { alice, bob, .. } = shared;
    assert!(store.get("bob", alice).await.expect("reads").is_none());
    assert!(store.get("alice", bob).await.expect("reads").is_none());
    let listed = |tenant: &'static str| async move {
        store
            .list(
                tenant,
                &ListQuery {
                    limit: 10,
                    ..Default::default()
                },
            )
            .await
            .expect("lists")
            .iter()
            .map(|j| j.id)
            .collect::<Vec<_>>()
    };
    assert_eq!(listed("alice").await, vec![alice]);
    assert_eq!(listed("bob").await, vec![bob]);
    assert!(
        store
            .cancel("bob", alice, &now_rfc3339())
            .await
            .expect("cancels")
            .is_none()
    );
    assert_eq!(
        store.delete("alice", bob).await.expect("deletes"),
        Deleted::NotFound
    );
}

/// One computation, computed once: its two tasks claimed, then nothing;
/// both tenants' jobs running.
async fn computed_once(store: &dyn JobStore, shared: Shared, lease: Duration) -> [TaskClaim; 2] {
    let Shared { c, alice, bob } = shared;
    let t0 = claim(store, lease).await.expect("task");
    let t1 = claim(store, lease).await.expect("task");
    assert_eq!((t0.computation, t1.computation), (c, c));
    assert!(claim(store, lease).await.is_none());
    for tenant_job in [("alice", alice), ("bob", bob)] {
        let job = job_of(store, tenant_job.0, tenant_job.1).await;
        assert_eq!(job.status, Status::Running, "{tenant_job:?}");
    }
    [t0, t1]
}

/// Bob cancels: his job only; Alice's still needs the computation (its
/// task `t0` still beats), and is not deleted while live.
async fn a_cancel_leaves_the_others_job(
    store: &dyn JobStore,
    shared: Shared,
    t0: &TaskClaim,
    lease: Duration,
) {
    let Shared { c, alice, bob } = shared;
    let canceled = store
        .cancel("bob", bob, &now_rfc3339())
        .await
        .expect("cancels")
        .expect("his job");
    assert_eq!(
        (canceled.job.status, canceled.changed, canceled.stopped),
        (Status::Canceled, true, false)
    );
    assert_eq!(
        store
            .heartbeat(c, t0.idx, "w", 0.5, lease)
            .await
            .expect("beats"),
        Some(Status::Running)
    );
    // A deletion of a live job is refused; of Bob's canceled one, done.
    assert!(matches!(
        store.delete("alice", alice).await.expect("deletes"),
        Deleted::NotFinished(_)
    ));
}

/// The computation succeeds for Alice; Bob's canceled job stays
/// canceled, and submitting again gives it the result at once, without
/// recomputing.
async fn a_canceled_job_gets_the_result_without_recomputing(
    store: &dyn JobStore,
    shared: Shared,
    tasks: &[TaskClaim; 2],
    lease: Duration,
) {
    let Shared { c, alice, bob } = shared;
    for t in tasks {
        assert!(
            store
                .complete(c, t.idx, "w", "\"part\"")
                .await
                .expect("completes")
        );
    }
    assert!(
        store
            .succeed(c, "{\"r\":1}", "{\"n\":2}", &now_rfc3339())
            .await
            .expect("stores")
    );
    let done = job_of(store, "alice", alice).await;
    assert_eq!(
        (done.status, done.numerics.as_deref()),
        (Status::Succeeded, Some("{\"n\":2}"))
    );
    assert_eq!(job_of(store, "bob", bob).await.status, Status::Canceled);
    let again = submit_as(store, "bob", "shared", 2).await;
    assert_eq!(
        (again.job.id, again.job.status, again.cached),
        (bob, Status::Succeeded, true)
    );
    assert!(claim(store, lease).await.is_none());
}

/// A third tenant gets a job of its own, done already; deletions leave the
/// computation's result while any job refers to it.
async fn a_result_stays_while_any_job_refers_to_it(store: &dyn JobStore, shared: Shared) {
    let Shared { c, alice, bob } = shared;
    let carol = submit_as(store, "carol", "shared", 2).await;
    assert_eq!((carol.job.status, carol.cached), (Status::Succeeded, true));
    assert_ne!(carol.job.id, alice);
    assert_eq!(
        store.delete("bob", bob).await.expect("deletes"),
        Deleted::Gone
    );
    assert!(store.get("bob", bob).await.expect("reads").is_none());
    assert_eq!(
        store.delete("alice", alice).await.expect("deletes"),
        Deleted::Gone
    );
    assert!(store.result(c).await.expect("reads").is_some());
    assert_eq!(
        store.delete("carol", carol.job.id).await.expect("deletes"),
        Deleted::Gone
    );
    assert!(store.result(c).await.expect("reads").is_none());
    assert!(store.computation(c).await.expect("reads").is_none());
}

async fn retention_purges_old_finished_jobs_and_their_results(store: &dyn JobStore) {
    let lease = Duration::from_secs(30);
    let old = submit_as(store, "alice", "old", 1).await;
    let kept = submit_as(store, "bob", "old", 1).await;
    let t = store
        .claim("w", &now_rfc3339(), lease)
        .await
        .expect("claims")
        .expect("task");
    assert!(
        store
            .complete_only(t.computation, 0, "w", "{}", "{}", &now_rfc3339())
            .await
            .expect("stores")
    );
    let live = submit_as(store, "alice", "live", 1).await;
    let cutoff = now_rfc3339();
    // Jobs finished before the cutoff go; Bob's too; the live one stays.
    assert_eq!(store.purge(&cutoff).await.expect("purges"), 2);
    assert!(
        store
            .get("alice", old.job.id)
            .await
            .expect("reads")
            .is_none()
    );
    assert!(
        store
            .get("bob", kept.job.id)
            .await
            .expect("reads")
            .is_none()
    );
    assert!(
        store
            .result(old.job.computation)
            .await
            .expect("reads")
            .is_none()
    );
    let still = store
        .get("alice", live.job.id)
        .await
        .expect("reads")
        .expect("kept");
    assert_eq!(still.status, Status::Queued);
    assert_eq!(
        store
            .purge("1970-01-01T00:00:00.000000Z")
            .await
            .expect("purges"),
        0
    );
}

async fn claims_take_turns_across_tenants_and_computations(store: &dyn JobStore) {
    let lease = Duration::from_secs(30);
    let big1 = submit_as(store, "alice", "big1", 4).await.job.computation;
    let big2 = submit_as(store, "alice", "big2", 4).await.job.computation;
    let small = submit_as(store, "bob", "small", 1).await.job.computation;
    let mut order = Vec::new();
    while let Some(t) = store
        .claim("w", &now_rfc3339(), lease)
        .await
        .expect("claims")
    {
        order.push(if t.computation == big1 {
            "big1"
        } else if t.computation == big2 {
            "big2"
        } else {
            assert_eq!(t.computation, small);
            "small"
        });
    }
    // Bob's single task comes second, not ninth; Alice's two computations
    // alternate.
    assert_eq!(
        order,
        [
            "big1", "small", "big2", "big1", "big2", "big1", "big2", "big1", "big2"
        ]
    );
}

/// Records: the samples stored once and read back bit for bit, a row per
/// tenant, paged newest first, kept while a live job names them.
async fn records_are_stored_once_per_content_and_kept_while_in_use(store: &dyn JobStore) {
    use topple::store::records::{NewRecord, RecordDeleted};
    let acc = [0.0, -0.0, 1.0 / 3.0, -2.5e-7, 9.81];
    let put = |tenant: &'static str, id: &'static str| NewRecord {
        tenant,
        id,
        entry: Uuid::now_v7(),
        dt: 0.01,
        acc: &acc,
        name: "test record",
        meta: "{}",
        now: "2026-01-01T00:00:00.000000Z",
    };
    let (first, created) = store.put_record(put("alice", "a1")).await.expect("puts");
    assert!(created);
    let (again, created) = store.put_record(put("alice", "a1")).await.expect("puts");
    assert!(!created);
    assert_eq!(again, first);
    let (_, created) = store.put_record(put("bob", "a1")).await.expect("puts");
    assert!(created, "bob's own row over the same samples");
    store.put_record(put("alice", "a2")).await.expect("puts");
    let (dt, back) = store
        .record_samples("bob", "a1")
        .await
        .expect("reads")
        .expect("bob has it");
    assert_eq!(dt, 0.01);
    assert_eq!(
        back.iter().map(|a| a.to_bits()).collect::<Vec<_>>(),
        acc.map(f64::to_bits).to_vec()
    );
    assert!(
        store
            .get_record("carol", "a1")
            .await
            .expect("reads")
            .is_none()
    );
    let page = store.list_records("alice", 1, None).await.expect("lists");
    assert_eq!(
        page.iter().map(|r| r.id.as_str()).collect::<Vec<_>>(),
        ["a2"]
    );
    let next = store
        .list_records("alice", 1, Some(page[0].entry))
        .await
        .expect("lists");
    assert_eq!(
        next.iter().map(|r| r.id.as_str()).collect::<Vec<_>>(),
        ["a1"]
    );
    // A live job naming it keeps it; once canceled, it may go.
    let submitted = store
        .submit(NewJob {
            tenant: "alice",
            id: Uuid::now_v7(),
            key: "uses-a1",
            kind: "time_history",
            spec: "{}",
            now: &now_rfc3339(),
            tasks: &tasks(1),
            records: &["a1".to_string()],
        })
        .await
        .expect("submits");
    assert_eq!(
        store.delete_record("alice", "a1").await.expect("deletes"),
        RecordDeleted::InUse(vec![submitted.job.id])
    );
    assert_eq!(
        store.delete_record("bob", "a1").await.expect("deletes"),
        RecordDeleted::Gone,
        "bob's job list is empty"
    );
    store
        .cancel("alice", submitted.job.id, &now_rfc3339())
        .await
        .expect("cancels");
    assert_eq!(
        store.delete_record("alice", "a1").await.expect("deletes"),
        RecordDeleted::Gone
    );
    assert!(
        store
            .record_samples("alice", "a1")
            .await
            .expect("reads")
            .is_none()
    );
    assert_eq!(
        store.delete_record("alice", "a1").await.expect("deletes"),
        RecordDeleted::NotFound
    );
}

/// A job of one task computed already, of `tenant` and `key`, to store
/// under no limits (a fresh id each call).
fn done_job<'a>(tenant: &'a str, key: &'a str, payload: &'a [String]) -> DoneJob<'a> {
    DoneJob {
        new: NewJob {
            tenant,
            id: Uuid::now_v7(),
            key,
            kind: "time_history",
            spec: "{\"a\":1}",
            now: "2026-01-01T00:00:00.000000Z",
            tasks: payload,
            records: &[],
        },
        owner: "here#request",
        started: "2026-01-01T00:00:00.000100Z",
        finished: "2026-01-01T00:00:00.000900Z",
        body: "{\"result\":42}",
        numerics: "{\"wall_time_s\":0.0008}",
        serve: true,
        limits: AdmitLimits::default(),
    }
}

/// A job computed already is stored finished in one write: read back as
/// succeeded with its result, listed, nothing left to claim; a second
/// one of its key stores nothing (it is joined instead), and neither does
/// one of a key submitted meanwhile.
async fn a_job_computed_already_is_stored_finished(store: &dyn JobStore) {
    let id = Uuid::now_v7();
    let payload = tasks(1);
    let done = |id: Uuid, tenant: &'static str, key: &'static str| {
        let mut job = done_job(tenant, key, &payload);
        job.new.id = id;
        job
    };
    let StoredDone::Stored(stored) = store
        .store_done(done(id, "carol", "done-1"))
        .await
        .expect("stores")
    else {
        panic!("a new key is stored");
    };
    let stored = *stored;
    let read = store
        .get("carol", id)
        .await
        .expect("reads")
        .expect("exists");
    assert_eq!(stored, read, "the job returned is the job stored");
    assert_eq!((read.status, read.progress), (Status::Succeeded, 1.0));
    assert_eq!(read.computation, id);
    assert_eq!(read.numerics.as_deref(), Some("{\"wall_time_s\":0.0008}"));
    assert_eq!(
        read.started_at.as_deref(),
        Some("2026-01-01T00:00:00.000100Z")
    );
    assert_eq!(
        store.result(id).await.expect("reads").as_deref(),
        Some("{\"result\":42}")
    );
    assert_eq!(
        store.parts(id).await.expect("reads"),
        None,
        "parts are not kept"
    );
    assert!(claim(store, Duration::from_secs(30)).await.is_none());
    let listed = store
        .list(
            "carol",
            &ListQuery {
                limit: 10,
                ..Default::default()
            },
        )
        .await
        .expect("lists");
    assert_eq!(listed.iter().map(|j| j.id).collect::<Vec<_>>(), vec![id]);
    // The same key again (another tenant computed it too): nothing stored,
    // and what its admission read says why.
    let StoredDone::NotStored(read) = store
        .store_done(done(Uuid::now_v7(), "dave", "done-1"))
        .await
        .expect("stores")
    else {
        panic!("a known key is not stored again");
    };
    assert_eq!(
        (read.own, read.computation),
        (None, Some(Status::Succeeded))
    );
    assert!(
        store
            .list(
                "dave",
                &ListQuery {
                    limit: 10,
                    ..Default::default()
                }
            )
            .await
            .expect("lists")
            .is_empty()
    );
    // A submission of its key joins it, done.
    let joined = submit_as(store, "dave", "done-1", 1).await;
    assert!(joined.cached);
    assert_eq!(joined.job.status, Status::Succeeded);
    assert_eq!(joined.job.computation, id);
    // A key queued meanwhile is left to its queue.
    let queued = submit_as(store, "dave", "done-2", 1).await;
    assert!(matches!(
        store
            .store_done(done(Uuid::now_v7(), "carol", "done-2"))
            .await
            .expect("stores"),
        StoredDone::NotStored(Admission {
            computation: Some(Status::Queued),
            ..
        })
    ));
    let t = claim(store, Duration::from_secs(30))
        .await
        .expect("its task");
    assert_eq!(t.computation, queued.job.computation);
    store
        .cancel("dave", queued.job.id, &now_rfc3339())
        .await
        .expect("cancels");
    // A finished job is deleted as any other.
    assert_eq!(
        store.delete("carol", id).await.expect("deletes"),
        Deleted::Gone
    );
    assert!(store.get("carol", id).await.expect("reads").is_none());
}

/// A job computed already is admitted as it is stored: over its tenant's
/// quota or the queue's limit nothing is stored, and what the admission
/// read says why; under them it is stored.
async fn a_job_computed_already_is_admitted_as_it_is_stored(store: &dyn JobStore) {
    let queued = submit_as(store, "erin", "admitted-queued", 1).await;
    let read = store
        .admission("erin", "admitted-new")
        .await
        .expect("reads");
    assert!(read.live >= 1 && read.queued >= 1, "{read:?}");
    let payload = tasks(1);
    let done = |quota, max_queued| DoneJob {
        serve: false,
        limits: AdmitLimits { quota, max_queued },
        ..done_job("erin", "admitted-new", &payload)
    };
    let (live, length) = (Some(read.live), Some(read.queued));
    for (quota, max_queued) in [(live, None), (None, length), (live, Some(read.queued + 1))] {
        let StoredDone::NotStored(refused) = store
            .store_done(done(quota, max_queued))
            .await
            .expect("stores")
        else {
            panic!("over a limit ({quota:?}, {max_queued:?}), nothing is stored");
        };
        // What the refusing limit counts is read (a count without a limit
        // may be skipped).
        assert_eq!(refused.computation, None, "{refused:?}");
        assert!(quota.is_none() || refused.live == read.live, "{refused:?}");
        assert!(
            max_queued.is_none() || refused.queued == read.queued,
            "{refused:?}"
        );
    }
    assert_eq!(
        store
            .admission("erin", "admitted-new")
            .await
            .expect("reads"),
        read,
        "a refused job is not stored"
    );
    let StoredDone::Stored(under) = store
        .store_done(done(Some(read.live + 1), Some(read.queued + 1)))
        .await
        .expect("stores")
    else {
        panic!("under its limits, a new key is stored");
    };
    assert_eq!(under.status, Status::Succeeded);
    store.delete("erin", under.id).await.expect("deletes");
    store
        .cancel("erin", queued.job.id, &now_rfc3339())
        .await
        .expect("cancels");
}

async fn suite(store: Arc<dyn JobStore>) {
    a_job_computed_already_is_stored_finished(store.as_ref()).await;
    a_job_computed_already_is_admitted_as_it_is_stored(store.as_ref()).await;
    a_single_task_job_completes_in_one_write(store.as_ref()).await;
    the_same_key_is_one_job(store.as_ref()).await;
    tasks_are_claimed_once_completed_and_assembled(store.as_ref()).await;
    a_lapsed_lease_is_taken_over_and_the_old_owner_writes_nothing(store.as_ref()).await;
    cancel_stops_every_task_and_resubmission_requeues(store.as_ref()).await;
    records_are_stored_once_per_content_and_kept_while_in_use(store.as_ref()).await;
}

#[tokio::test]
async fn sqlite_store_keeps_its_contract() {
    suite(sqlite().await).await;
    a_success_is_announced_with_its_end(sqlite().await.as_ref(), None).await;
    listing_pages_newest_first(sqlite().await.as_ref()).await;
    tenants_share_computations_not_jobs(sqlite().await.as_ref()).await;
    retention_purges_old_finished_jobs_and_their_results(sqlite().await.as_ref()).await;
    claims_take_turns_across_tenants_and_computations(sqlite().await.as_ref()).await;
}

#[tokio::test]
async fn postgres_store_keeps_its_contract() {
    let mut dbs = Vec::new();
    for (n, case) in [
        "store",
        "store_list",
        "store_tenants",
        "store_retention",
        "store_turns",
        "store_announce",
    ]
    .into_iter()
    .enumerate()
    {
        let Some(db) = crate::common::pg_database(case).await else {
            return;
        };
        let store: Arc<dyn JobStore> = Arc::new(PgStore::open(&db.url, 4).await.expect("opens"));
        match n {
            0 => suite(store.clone()).await,
            1 => listing_pages_newest_first(store.as_ref()).await,
            2 => tenants_share_computations_not_jobs(store.as_ref()).await,
            3 => retention_purges_old_finished_jobs_and_their_results(store.as_ref()).await,
            4 => claims_take_turns_across_tenants_and_computations(store.as_ref()).await,
            _ => {
                let other = PgStore::open(&db.url, 2).await.expect("opens");
                // This server has lz4: result documents are compressed with it.
                let method: String = sqlx::query_scalar(
                    "SELECT attcompression::text FROM pg_attribute \
                     WHERE attrelid = 'results'::regclass AND attname = 'body'",
                )
                .fetch_one(other.pool())
                .await
                .expect("reads the catalog");
                assert_eq!(method, "l", "results.body compressed with lz4");
                a_success_is_announced_with_its_end(store.as_ref(), Some(&other)).await;
            }
        }
        drop(store);
        dbs.push(db);
    }
    for db in dbs {
        db.drop_now().await;
    }
}

/// A job, its task and result as the schema before tenants held them.
const OLD_ROWS: [&str; 3] = [
    "INSERT INTO jobs (id, key, kind, spec, status, numerics, created_at, started_at, finished_at) \
     VALUES ('0190f0e4-0000-7000-8000-000000000001', 'oldkey', 'time_history', '{}', 'succeeded', '{\"n\":1}', \
     '2026-01-01T00:00:00.000000Z', '2026-01-01T00:00:01.000000Z', '2026-01-01T00:00:02.000000Z')",
    "INSERT INTO tasks (job_id, idx, payload, status, progress, created_at) \
     VALUES ('0190f0e4-0000-7000-8000-000000000001', 0, '{}', 'done', 1, '2026-01-01T00:00:00.000000Z')",
    "INSERT INTO results (job_id, body) VALUES ('0190f0e4-0000-7000-8000-000000000001', '{\"old\":true}')",
];

/// After the migration, the job is tenant `default`'s, under its id, with
/// its result; the same spec submitted again is answered from it.
async fn migrated_job_is_the_default_tenants(store: &dyn JobStore) {
    let id = Uuid::parse_str("0190f0e4-0000-7000-8000-000000000001").expect("uuid");
    let job = store
        .get("default", id)
        .await
        .expect("reads")
        .expect("kept");
    assert_eq!(
        (job.status, job.computation, job.numerics.as_deref()),
        (Status::Succeeded, id, Some("{\"n\":1}"))
    );
    assert_eq!(
        store.result(id).await.expect("reads").as_deref(),
        Some("{\"old\":true}")
    );
    let again = submit_as(store, "default", "oldkey", 1).await;
    assert_eq!((again.job.id, again.cached), (id, true));
    let other = submit_as(store, "alice", "oldkey", 1).await;
    assert_eq!((other.job.status, other.cached), (Status::Succeeded, true));
}

#[tokio::test]
async fn migrations_keep_jobs_made_before_tenants() {
    let dir = std::env::temp_dir().join(format!("topple-migrate-{}", Uuid::now_v7()));
    std::fs::create_dir_all(&dir).expect("dir");
    let url = format!("sqlite://{}?mode=rwc", dir.join("old.db").display());
    {
        let pool = sqlx::SqlitePool::connect(&url).await.expect("opens");
        topple::store::migrations::sqlite()
            .run_to(2, &pool)
            .await
            .expect("old schema");
        for sql in OLD_ROWS {
            sqlx::query(sql).execute(&pool).await.expect("old rows");
        }
        pool.close().await;
    }
    let store = SqliteStore::open(&url, 4).await.expect("migrates");
    migrated_job_is_the_default_tenants(&store).await;
    let _ = std::fs::remove_dir_all(&dir);
    let Some(db) = crate::common::pg_database("store_migrate").await else {
        return;
    };
    {
        let pool = sqlx::PgPool::connect(&db.url).await.expect("connects");
        topple::store::migrations::postgres()
            .run_to(1, &pool)
            .await
            .expect("old schema");
        for sql in OLD_ROWS {
            sqlx::query(sql).execute(&pool).await.expect("old rows");
        }
        pool.close().await;
    }
    let store = PgStore::open(&db.url, 4).await.expect("migrates");
    migrated_job_is_the_default_tenants(&store).await;
    drop(store);
    db.drop_now().await;
}

/// Rows the plan of an `EXPLAIN (ANALYZE, FORMAT JSON)` read: every node's
/// actual rows times its loops.
fn rows_read(plan: &serde_json::Value) -> f64 {
    let own =
        plan["Actual Rows"].as_f64().unwrap_or(0.0) * plan["Actual Loops"].as_f64().unwrap_or(1.0);
    own + plan["Plans"]
        .as_array()
        .map_or(0.0, |plans| plans.iter().map(rows_read).sum())
}

/// The estimated cost of the plan of the prepared statement `store_done`
/// under `plan_cache_mode` `mode`.
async fn store_done_cost(conn: &mut sqlx::PgConnection, mode: &str) -> f64 {
    sqlx::raw_sql(sqlx::AssertSqlSafe(format!("SET plan_cache_mode = {mode}")))
        .execute(&mut *conn)
        .await
        .expect("sets");
    let doc: serde_json::Value = sqlx::query_scalar(
        "EXPLAIN (FORMAT JSON) EXECUTE store_done(md5('k'), 'k', 'time_history', '{}', '{}', \
         't0', 't1', 't2', 'default', '{}', 'here#request', '{}', 0, NULL, 10000)",
    )
    .fetch_one(&mut *conn)
    .await
    .expect("explains");
    doc[0]["Plan"]["Total Cost"].as_f64().expect("a cost")
}

/// The admission reads a handful of rows whatever the tenant's history, even
/// with the generic plan PostgreSQL keeps for a connection's prepared
/// statement, made while the tables were empty (the plan of a join of jobs
/// and computations was then ordered from the tenant's jobs, and walked all
/// of them: 5,000 rows and 6 ms at 5,000 jobs); so does the statement that
/// stores a small job, which reads the admission too.
#[tokio::test]
async fn postgres_admission_reads_a_few_rows_whatever_the_tenants_history() {
    use sqlx::Connection;
    let Some(db) = crate::common::pg_database("admission_plan").await else {
        return;
    };
    drop(PgStore::open(&db.url, 2).await.expect("migrates"));
    let mut conn = sqlx::PgConnection::connect(&db.url)
        .await
        .expect("connects");
    let prepare = format!(
        "PREPARE admission(text, text) AS {}",
        topple::store::sql::ADMISSION
    );
    for sql in [
        "SET plan_cache_mode = force_generic_plan",
        prepare.as_str(),
        // Planned now, on empty tables.
        "EXECUTE admission('default', 'k')",
        "INSERT INTO computations (id, key, kind, spec, status, created_at, tenant) \
         SELECT md5(g::text), 'key' || g, 'time_history', '{}', 'succeeded', '2026-01-01T00:00:00Z', 'default' \
         FROM generate_series(1, 3000) g",
        "INSERT INTO jobs (id, tenant, computation_id, status, created_at) \
         SELECT md5(g::text), 'default', md5(g::text), 'succeeded', '2026-01-01T00:00:00Z' \
         FROM generate_series(1, 3000) g",
    ] {
        sqlx::raw_sql(sqlx::AssertSqlSafe(sql.to_string()))
            .execute(&mut conn)
            .await
            .unwrap_or_else(|e| panic!("{sql}: {e}"));
    }
    for key in ["key77", "unknown"] {
        let doc: serde_json::Value = sqlx::query_scalar(sqlx::AssertSqlSafe(format!(
            "EXPLAIN (ANALYZE, FORMAT JSON) EXECUTE admission('default', '{key}')"
        )))
        .fetch_one(&mut conn)
        .await
        .expect("explains");
        let read = rows_read(&doc[0]["Plan"]);
        assert!(read <= 10.0, "{key}: {read} rows read\n{doc:#}");
    }
    // The statement that stores a small job reads its admission too: a known
    // key (nothing written), a new one (its five rows written), and a tenant
    // over its quota (nothing written).
    let store_done = <sqlx::Postgres as topple::store::dialect::Dialect>::STORE_DONE
        .expect("PostgreSQL stores a finished job in one statement");
    sqlx::raw_sql(sqlx::AssertSqlSafe(format!(
        "PREPARE store_done(text, text, text, text, text, text, text, text, text, text, text, text, bigint, bigint, bigint) AS {store_done}"
    )))
    .execute(&mut conn)
    .await
    .expect("prepares");
    for (key, quota, most) in [
        ("key77", "5", 20.0),
        ("new", "5", 30.0),
        ("over", "0", 10.0),
    ] {
        let doc: serde_json::Value = sqlx::query_scalar(sqlx::AssertSqlSafe(format!(
            "EXPLAIN (ANALYZE, FORMAT JSON) EXECUTE store_done(md5('{key}'), '{key}', 'time_history', '{{}}', '{{}}', \
             't0', 't1', 't2', 'default', '{{}}', 'here#request', '{{}}', 1, {quota}, 10000)"
        )))
        .fetch_one(&mut conn)
        .await
        .expect("explains");
        let read = rows_read(&doc[0]["Plan"]);
        eprintln!("store_done {key}: {read} rows");
        assert!(read <= most, "{key}: {read} rows read\n{doc:#}");
    }
    // PostgreSQL plans a prepared statement anew at each of its first five
    // executions, then keeps its generic plan only if that costs no more
    // than those custom plans did; planning this statement costs about
    // 0.4 ms, as much as running it. So its generic plan must not cost more
    // than a custom one: no branch that a known parameter would prune.
    let generic = store_done_cost(&mut conn, "force_generic_plan").await;
    let custom = store_done_cost(&mut conn, "force_custom_plan").await;
    assert!(
        generic <= custom * 1.001,
        "the generic plan costs {generic}, a custom one {custom}"
    );
    drop(conn);
    db.drop_now().await;
}

/// The backend process of the writer connection `w`.
async fn backend(
    w: &mut topple::store::writer::Writing<'_, sqlx::Postgres>,
) -> Result<i32, sqlx::Error> {
    sqlx::query_scalar("SELECT pg_backend_pid()")
        .fetch_one(w.conn())
        .await
}

#[tokio::test]
async fn postgres_writes_replace_a_connection_the_database_dropped() {
    use topple::store::writer::{Writer, Writing};
    let Some(db) = crate::common::pg_database("writer").await else {
        return;
    };
    let pool = sqlx::PgPool::connect(&db.url).await.expect("connects");
    let ping = Duration::from_millis(300);
    let writer = Writer::new(pool.clone(), 2, Some(ping), Some(Duration::from_secs(5)));
    let terminate = async |pid: i32| {
        sqlx::query("SELECT pg_terminate_backend($1)")
            .bind(pid)
            .execute(&pool)
            .await
            .expect("terminates");
    };
    // One connection, used again while its writes end well.
    let mut w = Writing::start(&writer).await.expect("starts");
    let first = backend(&mut w).await.expect("writes");
    w.keep().await;
    drop(w);
    let mut w = Writing::start(&writer).await.expect("starts");
    assert_eq!(backend(&mut w).await.expect("writes"), first, "used again");
    w.keep().await;
    drop(w);
    // A transaction dropped uncommitted (as a write that found nothing to
    // do drops it): its rollback is sent before the connection is given
    // back, so no lock outlives the write.
    sqlx::query("CREATE TABLE held (x INT)")
        .execute(&pool)
        .await
        .expect("creates");
    let mut w = Writing::start(&writer).await.expect("starts");
    {
        let mut tx = sqlx::Connection::begin(w.conn()).await.expect("begins");
        sqlx::query("LOCK TABLE held")
            .execute(&mut *tx)
            .await
            .expect("locks");
    }
    w.keep().await;
    drop(w);
    let locks: i64 = sqlx::query_scalar(
        "SELECT COUNT(*) FROM pg_locks WHERE pid = $1 AND relation = 'held'::regclass",
    )
    .bind(first)
    .fetch_one(&pool)
    .await
    .expect("reads locks");
    assert_eq!(locks, 0, "the dropped transaction's lock is released");
    // Its backend gone (as in a database restart) and the connection used
    // again within the ping period: that write fails, and its connection is
    // not used again.
    terminate(first).await;
    let mut w = Writing::start(&writer).await.expect("starts");
    assert!(
        backend(&mut w).await.is_err(),
        "the dropped connection fails"
    );
    drop(w);
    let mut w = Writing::start(&writer).await.expect("starts");
    let second = backend(&mut w).await.expect("a new connection writes");
    assert_ne!(second, first);
    w.keep().await;
    drop(w);
    // Gone again, and idle past the ping period: pinged first, replaced,
    // and the write goes through.
    terminate(second).await;
    tokio::time::sleep(ping + Duration::from_millis(200)).await;
    let mut w = Writing::start(&writer).await.expect("starts");
    let third = backend(&mut w).await.expect("written after a long idle");
    assert_ne!(third, second);
    drop(w);
    drop(writer);
    pool.close().await;
    db.drop_now().await;
}
