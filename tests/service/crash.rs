//! Crash safety of a real `topple serve`: killed with SIGKILL in the middle of
//! a long spectrum, or again and again while a stream of jobs is submitted and
//! their results written, then restarted on the same database, it finishes
//! every accepted job with the result of an uninterrupted computation, lists
//! every one of them, and leaves an intact database (SQLite and PostgreSQL).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::str::FromStr;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::common::server::{Server, http, list_all, sqlite_url, status, temp_dir, wait_until};
use serde_json::{Value, json};
use sqlx::Connection;
use topple::kinds::Job;
use topple::spectrum::Control;

/// Points of the series of every time history: results of about 250 kB.
const SERIES: usize = 2000;

fn block_on<F: std::future::Future>(f: F) -> F::Output {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("a tokio runtime")
        .block_on(f)
}

/// xorshift64*: kill timings that vary from run to run yet can be replayed
/// (`TOPPLE_CRASH_SEED`).
struct Rng(u64);

impl Rng {
    fn seeded() -> Rng {
        let seed = std::env::var("TOPPLE_CRASH_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| {
                SystemTime::now()
                    .duration_since(UNIX_EPOCH)
                    .map_or(1, |d| d.as_nanos() as u64)
            })
            .max(1);
        eprintln!("kill timings: TOPPLE_CRASH_SEED={seed}");
        Rng(seed)
    }

    /// A number in `lo..=hi`.
    fn between(&mut self, lo: u64, hi: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        lo + self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % (hi - lo + 1)
    }
}

fn spectrum(frequencies: usize) -> Value {
    json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": frequencies}
    })
}

/// Time history number `i`: a pulse of its own, with a sampled series.
fn history(i: usize, series: usize) -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.2, "p": 2.0},
        "pulse": {
            "type": if i.is_multiple_of(2) { "one_sine" } else { "one_cosine" },
            "omega_ratio": 2.0 + 0.01 * i as f64,
            "a_p_alpha_g": 1.5 + 0.05 * (i % 10) as f64
        },
        "outputs": {"series": series}
    })
}

/// What a result document says about the physics: the document as read back
/// from its text, without the wall time of the run and, for an assembled
/// spectrum, its number of tasks.
fn physics(text: &str) -> Value {
    let mut doc: Value = serde_json::from_str(text).expect("a JSON result document");
    if let Some(n) = doc.get_mut("numerics").and_then(Value::as_object_mut) {
        n.remove("wall_time_s");
        n.remove("tasks");
    }
    doc
}

/// The result of `spec` computed in this process, in one piece.
fn offline(spec: &Value) -> Value {
    let job = Job::parse(&spec.to_string()).expect("a valid spec");
    let doc = job.run(&Control::new()).expect("the job runs");
    physics(&doc.to_string())
}

/// The number of tasks the service splits `spec` into.
fn tasks_of(spec: &Value) -> usize {
    Job::parse(&spec.to_string())
        .expect("a valid spec")
        .split()
        .len()
}

fn result_text(base: &str, id: &str) -> String {
    let (code, body) =
        http::request("GET", &format!("{base}/v1/jobs/{id}/result"), None).expect("GET result");
    assert_eq!(code, 200, "result of {id}: {body}");
    body
}

fn assert_same(id: &str, got: &Value, want: &Value) {
    if got == want {
        return;
    }
    let differ: Vec<String> = match (got.as_object(), want.as_object()) {
        (Some(g), Some(w)) => g
            .keys()
            .chain(w.keys())
            .collect::<BTreeSet<_>>()
            .into_iter()
            .filter(|k| g.get(*k) != w.get(*k))
            .cloned()
            .collect(),
        _ => vec!["<document>".into()],
    };
    panic!("job {id}: the stored result differs from an uninterrupted computation in {differ:?}");
}

fn submit(base: &str, spec: &Value) -> String {
    let (code, job) = http::post_json(&format!("{base}/v1/jobs"), spec);
    assert_eq!(code, 202, "{job}");
    job["id"].as_str().expect("a job id").to_string()
}

fn is_final(job: &Value) -> bool {
    matches!(
        job["status"].as_str(),
        Some("succeeded" | "failed" | "canceled")
    )
}

/// Counts that must all be zero in a consistent database (the same SQL for
/// SQLite and PostgreSQL).
const CONSISTENCY: [(&str, &str); 9] = [
    (
        "tasks without their computation",
        "SELECT COUNT(*) FROM tasks t WHERE NOT EXISTS (SELECT 1 FROM computations c WHERE c.id = t.computation_id)",
    ),
    (
        "results without their computation",
        "SELECT COUNT(*) FROM results r WHERE NOT EXISTS (SELECT 1 FROM computations c WHERE c.id = r.computation_id)",
    ),
    (
        "computations without tasks",
        "SELECT COUNT(*) FROM computations c WHERE NOT EXISTS (SELECT 1 FROM tasks t WHERE t.computation_id = c.id)",
    ),
    (
        "succeeded computations without a result",
        "SELECT COUNT(*) FROM computations c WHERE c.status = 'succeeded' AND NOT EXISTS (SELECT 1 FROM results r WHERE r.computation_id = c.id)",
    ),
    (
        "results of computations that did not succeed",
        "SELECT COUNT(*) FROM results r JOIN computations c ON c.id = r.computation_id WHERE c.status <> 'succeeded'",
    ),
    (
        "tasks of succeeded computations not done",
        "SELECT COUNT(*) FROM tasks t JOIN computations c ON c.id = t.computation_id WHERE c.status = 'succeeded' AND t.status <> 'done'",
    ),
    (
        "jobs without their computation",
        "SELECT COUNT(*) FROM jobs j WHERE NOT EXISTS (SELECT 1 FROM computations c WHERE c.id = j.computation_id)",
    ),
    (
        "jobs whose status is not their computation's",
        "SELECT COUNT(*) FROM jobs j JOIN computations c ON c.id = j.computation_id WHERE j.status <> c.status",
    ),
    (
        "jobs not finished",
        "SELECT COUNT(*) FROM jobs WHERE status IN ('queued', 'running')",
    ),
];

/// Tasks claimed more than once: interrupted by a kill and run again.
const RERUN: &str = "SELECT COUNT(*) FROM tasks WHERE attempts > 1";

/// `PRAGMA integrity_check` and `foreign_key_check` of a SQLite database whose
/// server is stopped, and the consistency of its rows.
async fn sqlite_integrity(url: &str) {
    let options = sqlx::sqlite::SqliteConnectOptions::from_str(url)
        .expect("a SQLite URL")
        .create_if_missing(false);
    let mut conn = sqlx::SqliteConnection::connect_with(&options)
        .await
        .expect("the database opens");
    let integrity: Vec<String> = sqlx::query_scalar("PRAGMA integrity_check")
        .fetch_all(&mut conn)
        .await
        .expect("integrity_check runs");
    assert_eq!(integrity, ["ok"], "PRAGMA integrity_check");
    let foreign = sqlx::query("PRAGMA foreign_key_check")
        .fetch_all(&mut conn)
        .await
        .expect("foreign_key_check runs");
    assert!(
        foreign.is_empty(),
        "PRAGMA foreign_key_check: {} rows violate a foreign key",
        foreign.len()
    );
    for (what, sql) in CONSISTENCY {
        let n: i64 = sqlx::query_scalar(sql)
            .fetch_one(&mut conn)
            .await
            .expect("consistency query runs");
        assert_eq!(n, 0, "{what}");
    }
    let rerun: i64 = sqlx::query_scalar(RERUN)
        .fetch_one(&mut conn)
        .await
        .expect("count of tasks run again");
    eprintln!("{rerun} tasks ran again after a kill");
    conn.close().await.expect("closes");
}

/// amcheck's `bt_index_check` (with `heapallindexed`) on every btree index of
/// the service's tables, when the extension is available, and the consistency
/// of the rows.
async fn pg_integrity(url: &str) {
    let mut conn = sqlx::PgConnection::connect(url)
        .await
        .expect("PostgreSQL connects");
    match sqlx::raw_sql("CREATE EXTENSION IF NOT EXISTS amcheck")
        .execute(&mut conn)
        .await
    {
        Ok(_) => {
            let indexes: Vec<String> = sqlx::query_scalar(
                "SELECT c.relname::TEXT FROM pg_index i \
                 JOIN pg_class c ON c.oid = i.indexrelid \
                 JOIN pg_class t ON t.oid = i.indrelid \
                 JOIN pg_am am ON am.oid = c.relam \
                 WHERE am.amname = 'btree' AND t.relname IN ('jobs', 'computations', 'tasks', 'results', 'tenants') \
                 AND t.relnamespace = current_schema()::regnamespace ORDER BY 1",
            )
            .fetch_all(&mut conn)
            .await
            .expect("index list");
            for table in [
                "jobs_pkey",
                "computations_pkey",
                "tasks_pkey",
                "results_pkey",
            ] {
                assert!(indexes.iter().any(|i| i == table), "{table} in {indexes:?}");
            }
            for index in &indexes {
                sqlx::query("SELECT bt_index_check($1::TEXT::regclass, true)")
                    .bind(index)
                    .execute(&mut conn)
                    .await
                    .unwrap_or_else(|e| panic!("bt_index_check({index}): {e}"));
            }
        }
        Err(e) => eprintln!(
            "\n!!!!!!!! amcheck is unavailable ({e}): checking the rows' references only.\n"
        ),
    }
    for (what, sql) in CONSISTENCY {
        let n: i64 = sqlx::query_scalar(sql)
            .fetch_one(&mut conn)
            .await
            .expect("consistency query runs");
        assert_eq!(n, 0, "{what}");
    }
    let rerun: i64 = sqlx::query_scalar(RERUN)
        .fetch_one(&mut conn)
        .await
        .expect("count of tasks run again");
    eprintln!("{rerun} tasks ran again after a kill");
    conn.close().await.expect("closes");
}

/// Runs `test` on a PostgreSQL database of its own (or skips loudly without
/// a server), and drops the database afterwards, even when `test` fails.
fn with_postgres(tag: &str, test: impl FnOnce(&str)) {
    let Some(pg) = block_on(crate::common::pg_database(tag)) else {
        return;
    };
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| test(&pg.url)));
    block_on(pg.drop_now());
    if let Err(panic) = outcome {
        std::panic::resume_unwind(panic);
    }
}

/// Submits `specs` one after the other from a thread of their own (each
/// retried until a server acknowledges it) while the server is killed with
/// SIGKILL `kills` times, 50–300 ms after each start, and restarted on `db`.
/// Returns the ids acknowledged, in the order of `specs`, and the last server.
fn storm(
    db: &str,
    log: &Path,
    args: &[&str],
    specs: &[Value],
    kills: usize,
) -> (Vec<String>, Server) {
    eprintln!("server log: {}", log.display());
    let mut rng = Rng::seeded();
    let mut server = Server::start(db, args, Some(log));
    let base = Arc::new(Mutex::new(server.base.clone()));
    let accepted = Arc::new(AtomicUsize::new(0));
    let submitter = {
        let specs = specs.to_vec();
        let base = base.clone();
        let accepted = accepted.clone();
        std::thread::spawn(move || {
            let deadline = Instant::now() + Duration::from_secs(60);
            let mut ids = Vec::with_capacity(specs.len());
            let mut retried = 0;
            for spec in &specs {
                let id = loop {
                    let url = format!("{}/v1/jobs", base.lock().expect("base URL").clone());
                    match http::try_post_json(&url, spec) {
                        Ok((200 | 202, job)) => {
                            break job["id"].as_str().expect("an id").to_string();
                        }
                        Ok((code, body)) if (400..500).contains(&code) && code != 429 => {
                            panic!("submission refused ({code}): {body}")
                        }
                        // Refused connection, a response cut short, or a
                        // server not ready: the same spec again.
                        _ => {
                            assert!(Instant::now() < deadline, "no server accepted {spec}");
                            retried += 1;
                            std::thread::sleep(Duration::from_millis(10));
                        }
                    }
                };
                ids.push(id);
                accepted.fetch_add(1, Ordering::Relaxed);
                std::thread::sleep(Duration::from_millis(4));
            }
            (ids, retried)
        })
    };
    for k in 0..kills {
        let pause = rng.between(50, 300);
        std::thread::sleep(Duration::from_millis(pause));
        server.kill();
        eprintln!(
            "kill {}: {pause} ms after start, {} jobs acknowledged",
            k + 1,
            accepted.load(Ordering::Relaxed)
        );
        server = Server::start(db, args, Some(log));
        *base.lock().expect("base URL") = server.base.clone();
    }
    let (ids, retried) = submitter.join().expect("the submitter finishes");
    eprintln!("{retried} submissions retried");
    (ids, server)
}

/// Every job of `ids` is listed and ends succeeded, with the result of its
/// spec computed here without interruption; the listing shows no other job.
fn verify(base: &str, specs: &[Value], ids: &[String]) {
    let wanted: BTreeSet<&str> = ids.iter().map(String::as_str).collect();
    assert_eq!(wanted.len(), specs.len(), "distinct specs, distinct jobs");
    let deadline = Instant::now() + Duration::from_secs(60);
    let listed = loop {
        let jobs = list_all(base);
        let shown: BTreeSet<&str> = jobs.iter().filter_map(|j| j["id"].as_str()).collect();
        let missing: Vec<&&str> = wanted.difference(&shown).collect();
        assert!(missing.is_empty(), "accepted jobs not listed: {missing:?}");
        assert_eq!(
            jobs.len(),
            wanted.len(),
            "the listing shows only the jobs submitted, once each"
        );
        if jobs.iter().all(is_final) {
            break jobs;
        }
        if Instant::now() > deadline {
            let mut by_status = BTreeMap::new();
            for j in &jobs {
                *by_status.entry(j["status"].to_string()).or_insert(0) += 1;
            }
            panic!("jobs still unfinished after 60 s: {by_status:?}");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let failed: Vec<String> = listed
        .iter()
        .filter(|j| j["status"] != "succeeded")
        .map(|j| format!("{} {} {}", j["id"], j["status"], j["error"]))
        .collect();
    assert!(failed.is_empty(), "jobs that did not succeed: {failed:?}");
    for (spec, id) in specs.iter().zip(ids) {
        assert_same(id, &physics(&result_text(base, id)), &offline(spec));
    }
}

#[test]
fn a_spectrum_killed_twice_mid_run_ends_with_the_uninterrupted_result() {
    let dir = temp_dir("crash-spectrum");
    let db = sqlite_url(&dir);
    let log = dir.join("server.log");
    eprintln!("server log: {}", log.display());
    let args = ["--workers", "1"];
    let spectrum = spectrum(200);
    let histories: Vec<Value> = (0..5).map(|i| history(i, 500)).collect();
    let reference = {
        let spec = spectrum.clone();
        std::thread::spawn(move || offline(&spec))
    };

    let mut server = Server::start(&db, &args, Some(&log));
    let spectrum_id = submit(&server.base, &spectrum);
    let history_ids: Vec<String> = histories.iter().map(|h| submit(&server.base, h)).collect();
    for fraction in [0.25, 0.6] {
        let job = wait_until(&server.base, &spectrum_id, Duration::from_secs(60), |j| {
            j["progress"].as_f64().unwrap_or(0.0) >= fraction || is_final(j)
        });
        assert_eq!(
            job["status"], "running",
            "the spectrum must still run at {fraction}: {job}"
        );
        server.kill();
        eprintln!("killed at progress {}", job["progress"]);
        server = Server::start(&db, &args, Some(&log));
    }
    for id in std::iter::once(&spectrum_id).chain(&history_ids) {
        let job = wait_until(&server.base, id, Duration::from_secs(60), is_final);
        assert_eq!(job["status"], "succeeded", "{job}");
    }

    let text = result_text(&server.base, &spectrum_id);
    let stored: Value = serde_json::from_str(&text).expect("JSON");
    assert_eq!(
        stored["numerics"]["tasks"],
        tasks_of(&spectrum),
        "one part per task"
    );
    let reference = reference.join().expect("the reference computes");
    assert_eq!(reference["spectrum"].as_array().map(Vec::len), Some(200));
    assert_same(&spectrum_id, &physics(&text), &reference);
    for (spec, id) in histories.iter().zip(&history_ids) {
        assert_same(id, &physics(&result_text(&server.base, id)), &offline(spec));
    }
    server.kill();
    block_on(sqlite_integrity(&db));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sqlite_kills_during_result_writes_lose_no_job_and_corrupt_nothing() {
    let dir = temp_dir("crash-writes");
    let db = sqlite_url(&dir);
    let specs: Vec<Value> = (0..200).map(|i| history(i, SERIES)).collect();
    let (ids, mut server) = storm(&db, &dir.join("server.log"), &["--workers", "1"], &specs, 5);
    verify(&server.base, &specs, &ids);
    server.kill();
    block_on(sqlite_integrity(&db));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn postgres_kills_during_result_writes_lose_no_job_and_corrupt_nothing() {
    with_postgres("crash", |url| {
        let dir = temp_dir("crash-postgres");
        let specs: Vec<Value> = (0..200).map(|i| history(i, SERIES)).collect();
        // Leases of a killed instance lapse after a second; its successor
        // takes their tasks over.
        let args = ["--workers", "1", "--lease", "1"];
        let (ids, mut server) = storm(url, &dir.join("server.log"), &args, &specs, 4);
        verify(&server.base, &specs, &ids);
        server.kill();
        block_on(pg_integrity(url));
        let _ = std::fs::remove_dir_all(&dir);
    });
}

/// The part of a task, as a worker computes and stores it.
fn part(payload: &str) -> String {
    Job::parse(payload)
        .expect("a task spec")
        .run(&Control::new())
        .expect("the task runs")
        .to_string()
}

/// Stores the part of every task of job `id` not done yet as a worker does
/// when it completes a task; returns how many it stored.
async fn store_missing_parts_sqlite(db: &str, id: &str) -> usize {
    let mut conn = sqlx::SqliteConnection::connect(db)
        .await
        .expect("the database opens");
    let rest: Vec<(i64, String)> =
        sqlx::query_as("SELECT idx, payload FROM tasks WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = ?1) AND status <> 'done'")
            .bind(id)
            .fetch_all(&mut conn)
            .await
            .expect("tasks");
    for (idx, payload) in &rest {
        sqlx::query(
            "UPDATE tasks SET status = 'done', progress = 1, result = ?3, done_by = 'crash#0', \
             lease_owner = NULL, lease_until = NULL WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = ?1) AND idx = ?2",
        )
        .bind(id)
        .bind(idx)
        .bind(part(payload))
        .execute(&mut conn)
        .await
        .expect("part stored");
    }
    conn.close().await.expect("closes");
    rest.len()
}

/// [`store_missing_parts_sqlite`] on PostgreSQL.
async fn store_missing_parts_pg(db: &str, id: &str) -> usize {
    let mut conn = sqlx::PgConnection::connect(db)
        .await
        .expect("PostgreSQL connects");
    let rest: Vec<(i64, String)> = sqlx::query_as(
        "SELECT idx::BIGINT, payload FROM tasks WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = $1) AND status <> 'done'",
    )
    .bind(id)
    .fetch_all(&mut conn)
    .await
    .expect("tasks");
    for (idx, payload) in &rest {
        sqlx::query(
            "UPDATE tasks SET status = 'done', progress = 1, result = $3, done_by = 'crash#0', \
             lease_owner = NULL, lease_until = NULL WHERE computation_id = (SELECT computation_id FROM jobs WHERE id = $1) AND idx = $2",
        )
        .bind(id)
        .bind(idx)
        .bind(part(payload))
        .execute(&mut conn)
        .await
        .expect("part stored");
    }
    conn.close().await.expect("closes");
    rest.len()
}

/// A kill after the last task of a job stored its part but before the job's
/// result was assembled from the parts: the restarted server must still
/// assemble them, at once, even with a queue of long jobs behind it
/// (`queue` of them). The state is reproduced exactly: the server is killed
/// mid-spectrum, then `store` stores the remaining parts as a worker does.
fn crash_before_assembly(
    db: &str,
    log: &Path,
    args: &[&str],
    queue: usize,
    store: impl FnOnce(&str) -> usize,
) {
    eprintln!("server log: {}", log.display());
    let spec = spectrum(48);
    let mut server = Server::start(db, args, Some(log));
    let id = submit(&server.base, &spec);
    // Long jobs queued behind it (one worker): each takes seconds.
    let queued: Vec<String> = (0..queue)
        .map(|i| submit(&server.base, &spectrum(40 + i)))
        .collect();
    let job = wait_until(&server.base, &id, Duration::from_secs(60), |j| {
        j["progress"].as_f64().unwrap_or(0.0) >= 0.2 || is_final(j)
    });
    assert_eq!(job["status"], "running", "{job}");
    server.kill();
    assert!(store(&id) > 0, "parts left to store");

    let mut server = Server::start(db, args, Some(log));
    let limit = if queue > 0 { 3 } else { 15 };
    let job = wait_until(&server.base, &id, Duration::from_secs(limit), is_final);
    assert_eq!(
        job["status"], "succeeded",
        "every task of job {id} is done, yet {limit} s after a restart the job is {} \
         ({queue} long jobs queued): a kill between the last task's result and the job's \
         assembly leaves it unfinished, or waiting for the queue to drain",
        job["status"]
    );
    if let Some(last) = queued.last() {
        // The queue was not drained first.
        assert!(
            !is_final(&status(&server.base, last)),
            "the queue drained first"
        );
    }
    for q in &queued {
        http::request("DELETE", &format!("{}/v1/jobs/{q}", server.base), None).expect("cancel");
        wait_until(&server.base, q, Duration::from_secs(30), is_final);
    }
    assert_same(
        &id,
        &physics(&result_text(&server.base, &id)),
        &offline(&spec),
    );
    server.kill();
}

#[test]
fn sqlite_a_crash_between_the_last_part_and_the_assembly_still_finishes_the_job() {
    let dir = temp_dir("crash-assembly");
    let db = sqlite_url(&dir);
    crash_before_assembly(&db, &dir.join("server.log"), &["--workers", "1"], 0, |id| {
        block_on(store_missing_parts_sqlite(&db, id))
    });
    block_on(sqlite_integrity(&db));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sqlite_a_stranded_job_is_assembled_at_once_whatever_the_queue() {
    let dir = temp_dir("crash-assembly-queue");
    let db = sqlite_url(&dir);
    crash_before_assembly(&db, &dir.join("server.log"), &["--workers", "1"], 6, |id| {
        block_on(store_missing_parts_sqlite(&db, id))
    });
    block_on(sqlite_integrity(&db));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn postgres_a_crash_between_the_last_part_and_the_assembly_still_finishes_the_job() {
    with_postgres("crash_asm", |url| {
        let dir = temp_dir("crash-assembly-postgres");
        let args = ["--workers", "1", "--lease", "1"];
        crash_before_assembly(url, &dir.join("server.log"), &args, 0, |id| {
            block_on(store_missing_parts_pg(url, id))
        });
        block_on(pg_integrity(url));
        let _ = std::fs::remove_dir_all(&dir);
    });
}
