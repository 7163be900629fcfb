//! PostgreSQL stopped and started under a real `topple serve`: a private
//! cluster (initdb in a temporary directory, on a free port) that the test
//! stops and starts. While the database is down, requests fail fast (within
//! about 2 s) with 503 and `Retry-After`, and `/readyz` answers 503; once it
//! is back, the service recovers by itself: ready again, jobs accepted and
//! computed, and the notification channel listened on again.
//!
//! A private cluster needs root (to run initdb as the `postgres` user) and the
//! PostgreSQL binaries; elsewhere the test says loudly that it is skipped.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::common::server::{Server, free_port, http, wait_until};
use serde_json::json;

/// A PostgreSQL cluster of the test's own, stopped and removed on drop.
struct Cluster {
    dir: PathBuf,
    bin: PathBuf,
    port: u16,
}

impl Cluster {
    fn bin() -> Option<PathBuf> {
        let mut found: Vec<PathBuf> = std::fs::read_dir("/usr/lib/postgresql")
            .ok()?
            .filter_map(|e| e.ok().map(|e| e.path().join("bin")))
            .filter(|p| p.join("initdb").exists() && p.join("pg_ctl").exists())
            .collect();
        found.sort();
        found.pop()
    }

    fn as_postgres(&self, program: &str, args: &[&str]) -> bool {
        Command::new("runuser")
            .args(["-u", "postgres", "--"])
            .arg(self.bin.join(program))
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    }

    fn create() -> Option<Cluster> {
        let bin = Cluster::bin()?;
        let dir = std::env::temp_dir().join(format!("topple-pg-{}", std::process::id()));
        std::fs::create_dir_all(&dir).ok()?;
        Command::new("chown")
            .args(["-R", "postgres:postgres"])
            .arg(&dir)
            .status()
            .ok()
            .filter(|s| s.success())?;
        let cluster = Cluster {
            dir,
            bin,
            port: free_port(),
        };
        let data = cluster.data();
        cluster
            .as_postgres(
                "initdb",
                &["-D", &data, "-A", "trust", "-U", "postgres", "--no-sync"],
            )
            .then_some(())?;
        cluster.start().then_some(cluster)
    }

    fn data(&self) -> String {
        self.dir.join("data").display().to_string()
    }

    fn start(&self) -> bool {
        let options = format!(
            "-p {} -k {} -c listen_addresses=127.0.0.1 -c fsync=off",
            self.port,
            self.dir.display()
        );
        let log = self.dir.join("postgres.log").display().to_string();
        self.as_postgres(
            "pg_ctl",
            &[
                "-D",
                &self.data(),
                "-o",
                &options,
                "-l",
                &log,
                "-w",
                "start",
            ],
        )
    }

    fn stop(&self) -> bool {
        self.as_postgres("pg_ctl", &["-D", &self.data(), "-m", "fast", "-w", "stop"])
    }

    fn url(&self) -> String {
        format!("postgres://postgres@127.0.0.1:{}/postgres", self.port)
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = self.stop();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn history(a: f64) -> serde_json::Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.2, "p": 2.0},
        "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": a}
    })
}

/// A request's status, head and how long it took.
fn timed(method: &str, url: &str, body: Option<&str>) -> (u16, String, Duration) {
    let started = Instant::now();
    let (status, head, _) = http::request_full(method, url, body).expect("the server answers");
    (status, head, started.elapsed())
}

fn log_has(log: &Path, needle: &str) -> bool {
    std::fs::read_to_string(log).is_ok_and(|text| text.contains(needle))
}

#[test]
fn a_stopped_database_is_503_fast_and_a_restarted_one_is_used_again() {
    if Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() != "0")
        .unwrap_or(true)
    {
        eprintln!("SKIPPED: the PostgreSQL restart test needs root for a private cluster");
        return;
    }
    let Some(cluster) = Cluster::create() else {
        eprintln!("SKIPPED: no PostgreSQL binaries under /usr/lib/postgresql, or initdb failed");
        return;
    };
    let log = cluster.dir.join("topple.log");
    eprintln!("server log: {}", log.display());
    let server = Server::start(&cluster.url(), &["--workers", "1"], Some(&log));
    let base = server.base.clone();
    let (status, job) = http::post_json(&format!("{base}/v1/jobs?wait=30"), &history(2.0));
    assert_eq!(status, 200, "{job}");
    let id = job["id"].as_str().expect("id").to_string();

    assert!(cluster.stop(), "PostgreSQL stops");
    // Down: every request that needs the database fails fast, 503, with
    // Retry-After; readiness says so.
    for (method, path, body) in [
        (
            "POST",
            "/v1/jobs".to_string(),
            Some(history(2.5).to_string()),
        ),
        ("GET", format!("/v1/jobs/{id}"), None),
        ("GET", "/v1/jobs".to_string(), None),
        ("GET", "/readyz".to_string(), None),
    ] {
        let (status, head, took) = timed(method, &format!("{base}{path}"), body.as_deref());
        eprintln!("{method} {path} with the database down: {status} in {took:?}");
        assert_eq!(status, 503, "{method} {path}: {head}");
        assert!(
            http::header(&head, "retry-after").is_some(),
            "{method} {path}: {head}"
        );
        assert!(
            took < Duration::from_millis(2500),
            "{method} {path} took {took:?}"
        );
    }

    assert!(cluster.start(), "PostgreSQL starts again");
    let back = Instant::now();
    while http::get_status(&format!("{base}/readyz")).unwrap_or(0) != 200 {
        assert!(
            back.elapsed() < Duration::from_secs(15),
            "not ready 15 s after the database came back"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    eprintln!("ready {:?} after the database came back", back.elapsed());
    // The notification channel is listened on again (with a backoff of at most
    // a few seconds), and work goes on.
    while !log_has(&log, "listening for queued tasks again") {
        assert!(
            back.elapsed() < Duration::from_secs(15),
            "LISTEN was not re-established"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    eprintln!(
        "listening again {:?} after the database came back",
        back.elapsed()
    );
    let (status, job) = http::post_json(&format!("{base}/v1/jobs"), &history(3.0));
    assert!(status == 202 || status == 200, "{status} {job}");
    let id = job["id"].as_str().expect("id");
    let job = wait_until(&base, id, Duration::from_secs(30), |j| {
        j["status"] == "succeeded"
    });
    assert_eq!(job["status"], "succeeded", "{job}");
    drop(server);
}
