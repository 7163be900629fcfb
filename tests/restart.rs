//! A real `topple serve` process: killed with SIGKILL mid-job, restarted on the
//! same database, it loses nothing; stopped with SIGTERM, it finishes its work
//! in flight and exits cleanly.

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

struct Server {
    child: Child,
    base: String,
}

fn start(db: &str, extra: &[&str]) -> Server {
    let port = free_port();
    let mut child = Command::new(env!("CARGO_BIN_EXE_topple"))
        .args([
            "serve",
            "--addr",
            &format!("127.0.0.1:{port}"),
            "--database",
            db,
        ])
        .args(extra)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("server starts");
    let base = format!("http://127.0.0.1:{port}");
    let deadline = Instant::now() + Duration::from_secs(20);
    while Instant::now() < deadline {
        if let Ok(r) = reqwest::blocking_get(&format!("{base}/readyz"))
            && r == 200
        {
            return Server { child, base };
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let _ = child.kill();
    let _ = child.wait();
    panic!("server at {base} never became ready");
}

mod reqwest {
    //! A tiny blocking HTTP client over std (the tests need no async here).
    use std::io::{Read, Write};
    use std::net::TcpStream;

    fn request(method: &str, url: &str, body: Option<&str>) -> std::io::Result<(u16, String)> {
        let rest = url.trim_start_matches("http://");
        let (host, path) = rest
            .split_once('/')
            .map_or((rest, "/".to_string()), |(h, p)| (h, format!("/{p}")));
        let mut s = TcpStream::connect(host)?;
        s.set_read_timeout(Some(std::time::Duration::from_secs(30)))?;
        let body = body.unwrap_or("");
        write!(
            s,
            "{method} {path} HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )?;
        let mut out = String::new();
        s.read_to_string(&mut out)?;
        let status = out
            .split_whitespace()
            .nth(1)
            .and_then(|c| c.parse().ok())
            .unwrap_or(0);
        let body = out
            .split_once("\r\n\r\n")
            .map(|(_, b)| b.to_string())
            .unwrap_or_default();
        Ok((status, body))
    }

    pub fn blocking_get(url: &str) -> std::io::Result<u16> {
        request("GET", url, None).map(|r| r.0)
    }

    pub fn get_json(url: &str) -> serde_json::Value {
        let (_, body) = request("GET", url, None).expect("GET");
        serde_json::from_str(&body).unwrap_or(serde_json::Value::Null)
    }

    pub fn post_json(url: &str, body: &serde_json::Value) -> (u16, serde_json::Value) {
        let (status, text) = request("POST", url, Some(&body.to_string())).expect("POST");
        (
            status,
            serde_json::from_str(&text).unwrap_or(serde_json::Value::Null),
        )
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

fn history() -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_cosine", "omega_ratio": 3.0, "a_p_alpha_g": 2.5}
    })
}

fn status(base: &str, id: &str) -> Value {
    reqwest::get_json(&format!("{base}/v1/jobs/{id}"))
}

fn wait_status(base: &str, id: &str, want: &str, limit: Duration) -> Value {
    let deadline = Instant::now() + limit;
    loop {
        let job = status(base, id);
        if job["status"] == want || Instant::now() > deadline {
            return job;
        }
        std::thread::sleep(Duration::from_millis(25));
    }
}

fn temp_db(name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("topple-restart-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    format!("sqlite://{}", dir.join("topple.db").display())
}

#[test]
fn a_killed_server_loses_no_job_queued_or_running() {
    let db = temp_db("kill");
    let mut first = start(&db, &["--workers", "1"]);
    let (s1, running) = reqwest::post_json(&format!("{}/v1/jobs", first.base), &spectrum(120));
    let (s2, queued) = reqwest::post_json(&format!("{}/v1/jobs", first.base), &history());
    assert_eq!((s1, s2), (202, 202), "{running} {queued}");
    let running_id = running["id"].as_str().expect("id").to_string();
    let queued_id = queued["id"].as_str().expect("id").to_string();
    let job = wait_status(&first.base, &running_id, "running", Duration::from_secs(10));
    assert_eq!(job["status"], "running");
    assert_eq!(status(&first.base, &queued_id)["status"], "queued");
    first.child.kill().expect("SIGKILL");
    let _ = first.child.wait();

    let mut second = start(&db, &["--workers", "1"]);
    for id in [&running_id, &queued_id] {
        let job = wait_status(&second.base, id, "succeeded", Duration::from_secs(60));
        assert_eq!(job["status"], "succeeded", "{job}");
    }
    let result = reqwest::get_json(&format!("{}/v1/jobs/{running_id}/result", second.base));
    assert_eq!(result["spectrum"].as_array().map(|a| a.len()), Some(120));
    let _ = second.child.kill();
    let _ = second.child.wait();
}

#[test]
fn sigterm_lets_the_running_job_finish_and_exits_cleanly() {
    let db = temp_db("term");
    let mut server = start(&db, &["--workers", "1", "--shutdown-grace", "30"]);
    let (_, job) = reqwest::post_json(&format!("{}/v1/jobs", server.base), &spectrum(30));
    let id = job["id"].as_str().expect("id").to_string();
    let job = wait_status(&server.base, &id, "running", Duration::from_secs(10));
    assert_eq!(job["status"], "running");
    let pid = server.child.id().to_string();
    let killed = Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .expect("kill");
    assert!(killed.success());
    let deadline = Instant::now() + Duration::from_secs(30);
    let exit = loop {
        if let Some(s) = server.child.try_wait().expect("wait") {
            break s;
        }
        assert!(Instant::now() < deadline, "server did not stop");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(exit.success(), "{exit:?}");
    // The task in flight finished before the process left; the job's other
    // tasks stayed queued and finish after the restart.
    let again = start(&db, &["--workers", "1"]);
    let job = wait_status(&again.base, &id, "succeeded", Duration::from_secs(60));
    assert_eq!(job["status"], "succeeded", "{job}");
    let result = reqwest::get_json(&format!("{}/v1/jobs/{id}/result", again.base));
    assert_eq!(result["spectrum"].as_array().map(|a| a.len()), Some(30));
    let mut again = again;
    let _ = again.child.kill();
    let _ = again.child.wait();
}
