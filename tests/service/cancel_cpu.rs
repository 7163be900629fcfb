//! Canceling a running spectrum gives its cores back: the CPU time of a real
//! `topple serve` process, read from /proc, stops growing once the DELETE is
//! answered. (The latency itself is measured by `benches/spectrum.rs`.)

use std::time::{Duration, Instant};

use crate::common::server::{Server, cpu_time, http, temp_db, wait_until};
use serde_json::json;

/// Share of one core the process used over `window`.
fn usage(pid: u32, window: Duration) -> f64 {
    let before = cpu_time(pid);
    std::thread::sleep(window);
    (cpu_time(pid) - before).as_secs_f64() / window.as_secs_f64()
}

#[test]
fn deleting_a_running_spectrum_returns_the_cpu_to_idle() {
    let db = temp_db("cancel-cpu");
    let server = Server::start(&db, &["--workers", "2"], None);
    let pid = server.child.id();
    let spec = json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": 2000}
    });
    let (status, job) = http::post_json(&format!("{}/v1/jobs", server.base), &spec);
    assert_eq!(status, 202, "{job}");
    let id = job["id"].as_str().expect("id").to_string();
    let running = wait_until(&server.base, &id, Duration::from_secs(10), |j| {
        j["status"] == "running" && j["progress"].as_f64().unwrap_or(0.0) > 0.0
    });
    assert_eq!(running["status"], "running");
    // (On a loaded machine a window may find the server waiting for a core:
    // the best of a few windows, and half a core is busy enough to tell a
    // running spectrum from an idle server, which the check below needs.)
    let mut busy = 0.0_f64;
    for _ in 0..10 {
        busy = busy.max(usage(pid, Duration::from_millis(300)));
        if busy > 0.8 {
            break;
        }
    }
    assert!(
        busy > 0.5,
        "the spectrum should keep a core busy, used {busy:.2}"
    );

    let asked = Instant::now();
    let (status, body) =
        http::request("DELETE", &format!("{}/v1/jobs/{id}", server.base), None).expect("DELETE");
    assert_eq!(status, 200, "{body}");
    // 100 ms is the promise; the measuring window starts there and is long
    // enough for the clock-tick resolution of /proc (10 ms).
    std::thread::sleep(Duration::from_millis(100).saturating_sub(asked.elapsed()));
    let after = usage(pid, Duration::from_millis(500));
    assert!(
        after < 0.1,
        "from 100 ms after the DELETE the server still used {after:.2} of a core (before: {busy:.2})"
    );
    let job = http::get_json(&format!("{}/v1/jobs/{id}", server.base));
    assert_eq!(job["status"], "canceled");
}
