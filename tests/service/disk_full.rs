//! A full disk under a real `topple serve` on SQLite: the database lives on a
//! small tmpfs that the test fills. While writes fail, clients get 507 or 503
//! with `Retry-After` (never a 500, never a 2xx for a job that was not
//! saved), `/readyz` answers 503; once space is freed, writes recover by
//! themselves within seconds; every acknowledged job is on disk and ends; the
//! database passes `PRAGMA integrity_check`.
//!
//! Mounting a tmpfs needs root (CI has it); elsewhere the test says loudly
//! that it is skipped.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::common::server::{Server, http, wait_until};
use serde_json::{Value, json};
use sqlx::Connection;

/// A mounted tmpfs of `mib` MiB, unmounted (with its contents) on drop.
struct Tmpfs(PathBuf);

impl Tmpfs {
    fn mount(name: &str, mib: u32) -> Option<Tmpfs> {
        let dir = std::env::temp_dir().join(format!("topple-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).ok()?;
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={mib}m"), "tmpfs"])
            .arg(&dir)
            .status()
            .is_ok_and(|s| s.success());
        if ok {
            Some(Tmpfs(dir))
        } else {
            let _ = std::fs::remove_dir(&dir);
            None
        }
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg("-l").arg(&self.0).status();
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Fills the file system of `dir` with a file `filler` until writing fails.
fn fill(filler: &Path) {
    use std::io::Write;
    let mut f = std::fs::File::create(filler).expect("filler");
    let block = vec![0u8; 64 * 1024];
    while f.write_all(&block).is_ok() {}
    let _ = f.flush();
    // Whatever could not be written in whole blocks.
    let small = [0u8; 512];
    while f.write_all(&small).is_ok() {}
    let _ = f.sync_all();
}

/// A time history with a series of `series` samples (a result of about
/// 100 bytes a sample).
fn history(i: usize, series: usize) -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.2, "p": 2.0},
        "pulse": {"type": "one_sine", "omega_ratio": 2.0 + 0.001 * i as f64, "a_p_alpha_g": 3.0},
        "outputs": {"series": series}
    })
}

/// POST a job: (status, body, headers).
fn post(base: &str, spec: &Value) -> (u16, Value, String) {
    let (status, head, body) =
        http::request_full("POST", &format!("{base}/v1/jobs"), Some(&spec.to_string()))
            .expect("the server answers");
    (
        status,
        serde_json::from_str(&body).unwrap_or(Value::Null),
        head,
    )
}

/// Whether the job `j` has ended.
fn ended(j: &Value) -> bool {
    matches!(
        j["status"].as_str(),
        Some("succeeded" | "failed" | "canceled")
    )
}

#[test]
fn a_full_disk_is_507_or_503_then_recovers_by_itself_and_loses_nothing() {
    if not_root() {
        eprintln!("SKIPPED: disk-full test needs root to mount a tmpfs (CI runs it as root)");
        return;
    }
    let Some(fs) = Tmpfs::mount("disk-full", 64) else {
        eprintln!("SKIPPED: could not mount a tmpfs (mount -t tmpfs failed)");
        return;
    };
    let db = format!("sqlite://{}", fs.0.join("topple.db").display());
    let log = std::env::temp_dir().join(format!("topple-disk-full-{}.log", std::process::id()));
    eprintln!("server log: {}", log.display());
    let server = Server::start(&db, &["--workers", "1", "--lease", "2"], Some(&log));
    let base = server.base.clone();
    let filler = fs.0.join("filler");

    let mut acknowledged = large_jobs_stored(&base, &db);
    fill(&filler);
    refused_while_full(&base, &mut acknowledged);
    let starved = stored_but_not_done_with_little_space(&base, &filler);
    acknowledged.extend(starved);
    recovers_once_space_comes_back(&base, &filler, &mut acknowledged);

    // Every acknowledged job is there, always, and ends.
    for id in &acknowledged {
        let job = wait_until(&base, id, Duration::from_secs(120), ended);
        assert!(
            job["status"].is_string(),
            "acknowledged job {id} vanished: {job}"
        );
    }
    drop(server);
    let integrity = block_on(async {
        let mut conn = sqlx::SqliteConnection::connect(&db).await.expect("opens");
        let rows: Vec<String> = sqlx::query_scalar("PRAGMA integrity_check")
            .fetch_all(&mut conn)
            .await
            .expect("runs");
        rows
    });
    assert_eq!(integrity, ["ok"]);
}

/// Jobs with large results (about 2 MB each) before the disk fills, stored
/// and ended; then the write-ahead log of the database `db` truncated, so
/// that the filled disk leaves it no slack to reuse. Their ids.
fn large_jobs_stored(base: &str, db: &str) -> Vec<String> {
    let mut acknowledged: Vec<String> = Vec::new();
    for i in 0..6 {
        let (status, job, _) = post(base, &history(i, 20_000));
        assert!(status == 202 || status == 200, "{status} {job}");
        acknowledged.push(job["id"].as_str().expect("id").to_string());
    }
    for id in &acknowledged {
        wait_until(base, id, Duration::from_secs(60), ended);
    }
    block_on(async {
        let mut conn = sqlx::SqliteConnection::connect(db).await.expect("opens");
        for _ in 0..50 {
            let busy: i64 = sqlx::query_scalar("PRAGMA wal_checkpoint(TRUNCATE)")
                .fetch_one(&mut conn)
                .await
                .expect("checkpoint runs");
            if busy == 0 {
                break;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        conn.close().await.expect("closes");
    });
    acknowledged
}

/// Writes fail now: every answer is a 2xx for a stored job (its id added
/// to `acknowledged`), or 507/503 with Retry-After; never a 500. `/readyz`
/// answers 503.
fn refused_while_full(base: &str, acknowledged: &mut Vec<String>) {
    let mut refused = 0;
    let mut codes = std::collections::BTreeMap::new();
    for i in 3..40 {
        let (status, job, head) = post(base, &history(i, 20_000));
        *codes.entry(status).or_insert(0) += 1;
        match status {
            200 | 202 => acknowledged.push(job["id"].as_str().expect("id").to_string()),
            507 | 503 => {
                refused += 1;
                assert!(
                    http::header(&head, "retry-after").is_some(),
                    "{status} without Retry-After"
                );
                assert_eq!(
                    http::header(&head, "content-type").as_deref(),
                    Some("application/problem+json")
                );
            }
            other => panic!("POST answered {other} with the disk full: {job}"),
        }
    }
    eprintln!("with the disk full: {codes:?}");
    assert!(refused > 0, "the disk never filled: {codes:?}");
    assert_eq!(
        http::get_status(&format!("{base}/readyz")).expect("answers"),
        503,
        "/readyz while writes fail"
    );
}

/// A little space (the `filler` shrunk): submissions and claims fit,
/// results of 2 MB do not; the jobs acknowledged are not lost, not done.
/// Their ids.
fn stored_but_not_done_with_little_space(base: &str, filler: &Path) -> Vec<String> {
    let size = std::fs::metadata(filler).expect("filler").len();
    std::fs::OpenOptions::new()
        .write(true)
        .open(filler)
        .and_then(|f| f.set_len(size.saturating_sub(768 * 1024)))
        .expect("filler shrunk");
    let mut starved = Vec::new();
    for i in 100..104 {
        let (status, job, head) = post(base, &history(i, 20_000));
        match status {
            200 | 202 => starved.push(job["id"].as_str().expect("id").to_string()),
            507 | 503 => assert!(http::header(&head, "retry-after").is_some()),
            other => panic!("POST answered {other} with little space: {job}"),
        }
    }
    eprintln!("with little space: {} acknowledged", starved.len());
    std::thread::sleep(Duration::from_secs(2));
    for id in &starved {
        // Their results cannot be stored yet: they are not lost, not done.
        let job = http::get_json(&format!("{base}/v1/jobs/{id}"));
        assert!(
            matches!(job["status"].as_str(), Some("queued" | "running")),
            "{job}"
        );
    }
    starved
}

/// Space comes back (the `filler` removed): writes recover by themselves
/// within seconds (the job then acknowledged added to `acknowledged`), and
/// `/readyz` answers 200 again.
fn recovers_once_space_comes_back(base: &str, filler: &Path, acknowledged: &mut Vec<String>) {
    std::fs::remove_file(filler).expect("filler removed");
    let freed = Instant::now();
    let recovered = loop {
        let (status, job, _) = post(base, &history(1000, 100));
        if status == 202 || status == 200 {
            acknowledged.push(job["id"].as_str().expect("id").to_string());
            break freed.elapsed();
        }
        assert!(
            freed.elapsed() < Duration::from_secs(15),
            "writes did not recover within 15 s of space coming back: {status} {job}"
        );
        std::thread::sleep(Duration::from_millis(200));
    };
    eprintln!("writes recovered {recovered:?} after space came back");
    let deadline = Instant::now() + Duration::from_secs(10);
    while http::get_status(&format!("{base}/readyz")).unwrap_or(0) != 200 {
        assert!(
            Instant::now() < deadline,
            "/readyz stayed 503 after recovery"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn block_on<F: std::future::Future>(f: F) -> F::Output {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("a runtime")
        .block_on(f)
}

fn not_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() != "0")
        .unwrap_or(true)
}
