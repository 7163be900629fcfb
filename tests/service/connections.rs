//! What clients may hold of a real `topple serve`, over raw sockets: a client
//! that never finishes its headers, an idle keep-alive connection, a body sent
//! a byte at a time, more connections than the server serves at once, more
//! than it has file descriptors for, and all of them at once during a
//! shutdown, which still ends within the grace period. Limits of zero are
//! refused at start.

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::common::server::{Server, cpu_time, http, sqlite_url, temp_dir, wait_until};
use serde_json::json;

/// A server with `args`, logging to its directory.
fn start(name: &str, args: &[&str]) -> (Server, PathBuf) {
    start_under(&[], name, args)
}

/// As [`start`], run by `wrapper`.
fn start_under(wrapper: &[&str], name: &str, args: &[&str]) -> (Server, PathBuf) {
    let dir = temp_dir(name);
    let log = dir.join("server.log");
    let server = Server::start_under(wrapper, &sqlite_url(&dir), args, Some(&log));
    (server, log)
}

fn log_of(log: &PathBuf) -> String {
    std::fs::read_to_string(log).unwrap_or_default()
}

fn address(server: &Server) -> SocketAddr {
    server
        .base
        .trim_start_matches("http://")
        .parse()
        .expect("a socket address")
}

fn connect(addr: SocketAddr) -> TcpStream {
    let s = TcpStream::connect_timeout(&addr, Duration::from_secs(5)).expect("connects");
    s.set_read_timeout(Some(Duration::from_secs(10)))
        .expect("read timeout");
    s.set_write_timeout(Some(Duration::from_secs(10)))
        .expect("write timeout");
    s
}

/// Reads one response (headers and a `Content-Length` body): status, head, body.
fn read_response(s: &mut TcpStream) -> std::io::Result<(u16, String, String)> {
    let mut head = Vec::new();
    let mut byte = [0u8; 1];
    while !head.ends_with(b"\r\n\r\n") {
        // A signal to this process (a child server exiting) interrupts the
        // read without ending the response: read again, as read_exact does.
        match s.read(&mut byte) {
            Ok(0) => return Err(ErrorKind::UnexpectedEof.into()),
            Ok(_) => head.push(byte[0]),
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        }
    }
    let head = String::from_utf8_lossy(&head).to_string();
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .ok_or(ErrorKind::InvalidData)?;
    let length = head
        .lines()
        .find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.trim()
                .eq_ignore_ascii_case("content-length")
                .then(|| v.trim().parse::<usize>().ok())?
        })
        .unwrap_or(0);
    let mut body = vec![0u8; length];
    s.read_exact(&mut body)?;
    Ok((status, head, String::from_utf8_lossy(&body).to_string()))
}

/// A GET on a kept-alive connection; its status.
fn get_on(s: &mut TcpStream, path: &str) -> u16 {
    write!(s, "GET {path} HTTP/1.1\r\nHost: topple\r\n\r\n").expect("request sent");
    read_response(s).expect("a response").0
}

/// Waits up to `limit` for the server to close `s` (a read returning end of
/// file, or a reset); returns how long that took, or `None` if `s` is still
/// open. Bytes the server sends meanwhile are skipped.
fn closed_within(s: &mut TcpStream, limit: Duration) -> Option<Duration> {
    let start = Instant::now();
    let mut buf = [0u8; 4096];
    loop {
        let left = limit.checked_sub(start.elapsed())?;
        s.set_read_timeout(Some(left.max(Duration::from_millis(1))))
            .expect("read timeout");
        match s.read(&mut buf) {
            Ok(0) => return Some(start.elapsed()),
            Ok(_) => {}
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                return None;
            }
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => return Some(start.elapsed()),
        }
    }
}

/// Sockets of process `pid` (its listener, connections and internal pairs).
fn sockets(pid: u32) -> usize {
    std::fs::read_dir(format!("/proc/{pid}/fd"))
        .expect("/proc/<pid>/fd")
        .filter_map(|e| std::fs::read_link(e.ok()?.path()).ok())
        .filter(|target| target.to_string_lossy().starts_with("socket:"))
        .count()
}

/// A value of the server's Prometheus text.
fn metric(server: &Server, name: &str) -> f64 {
    let (status, text) =
        http::request("GET", &format!("{}/metrics", server.base), None).expect("GET /metrics");
    assert_eq!(status, 200, "{text}");
    text.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.parse().ok())
        .unwrap_or_else(|| panic!("no {name} in\n{text}"))
}

/// Writes `body` after `head`, one byte every `every`, on a thread of its own
/// until the server stops reading or `stop` is set.
fn trickle(s: &TcpStream, head: &str, every: Duration, stop: Arc<AtomicBool>) {
    let mut s = s.try_clone().expect("a second handle");
    s.write_all(head.as_bytes()).expect("headers sent");
    std::thread::spawn(move || {
        while !stop.load(Ordering::Relaxed) {
            std::thread::sleep(every);
            if s.write_all(b" ").is_err() {
                break;
            }
        }
    });
}

#[test]
fn a_client_that_never_finishes_its_headers_is_disconnected() {
    let (server, log) = start("conn-headers", &["--header-read-timeout", "1"]);
    let mut slow = connect(address(&server));
    slow.write_all(b"GET / HTTP/1.1\r\nHost: x\r\n")
        .expect("half a request sent");
    let sent = Instant::now();

    // Others are served meanwhile.
    assert_eq!(
        http::get_status(&format!("{}/healthz", server.base)).expect("GET /healthz"),
        200
    );

    let closed = closed_within(&mut slow, Duration::from_secs(4));
    let waited = sent.elapsed();
    assert!(
        closed.is_some(),
        "the connection is still open {waited:?} after half a request\n{}",
        log_of(&log)
    );
    assert!(
        waited >= Duration::from_millis(500),
        "closed after {waited:?}, before the 1 s header timeout"
    );
    assert_eq!(
        metric(
            &server,
            "topple_connections_closed_total{reason=\"header_timeout\"}"
        ),
        1.0
    );
}

#[test]
fn an_idle_keep_alive_connection_is_closed_after_the_idle_timeout() {
    let (server, log) = start(
        "conn-idle",
        &["--header-read-timeout", "1", "--idle-timeout", "3"],
    );
    let mut s = connect(address(&server));
    assert_eq!(get_on(&mut s, "/healthz"), 200);
    // Longer than the header timeout: an idle spell is timed by the idle
    // timeout alone, and the connection serves again.
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(get_on(&mut s, "/healthz"), 200);
    let answered = Instant::now();
    let closed = closed_within(&mut s, Duration::from_secs(6));
    assert!(
        closed.is_some(),
        "an idle connection still open {:?} after its last answer\n{}",
        answered.elapsed(),
        log_of(&log)
    );
    assert!(
        answered.elapsed() >= Duration::from_secs(2),
        "closed {:?} after the answer, before the 3 s idle timeout",
        answered.elapsed()
    );
    assert_eq!(
        metric(
            &server,
            "topple_connections_closed_total{reason=\"idle_timeout\"}"
        ),
        1.0
    );
}

#[test]
fn connections_beyond_the_limit_wait_in_the_backlog_until_timeouts_free_slots() {
    let (server, log) = start(
        "conn-max",
        &["--max-connections", "20", "--header-read-timeout", "1"],
    );
    let pid = server.child.id();
    let addr = address(&server);
    std::thread::sleep(Duration::from_millis(200));
    let at_rest = sockets(pid);

    // All connect (the kernel queues them); the server takes 20 at a time.
    let mut idle: Vec<TcpStream> = (0..100).map(|_| connect(addr)).collect();
    let mut most = 0;
    let sampling = Instant::now();
    while sampling.elapsed() < Duration::from_millis(1500) {
        most = most.max(sockets(pid).saturating_sub(at_rest));
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        (10..=20).contains(&most),
        "with 100 clients waiting the server held {most} connections, the limit being 20\n{}",
        log_of(&log)
    );

    // A real request behind them is served once the header timeout has
    // closed the idle ones ahead of it.
    let asked = Instant::now();
    let mut probe = connect(addr);
    probe
        .set_read_timeout(Some(Duration::from_secs(20)))
        .expect("read timeout");
    assert_eq!(get_on(&mut probe, "/healthz"), 200);
    eprintln!(
        "served after {:?} behind 100 idle connections",
        asked.elapsed()
    );
    for s in &mut idle {
        assert!(
            closed_within(s, Duration::from_secs(5)).is_some(),
            "an idle connection was never closed"
        );
    }
}

#[test]
fn out_of_file_descriptors_the_server_waits_without_spinning_and_recovers() {
    let (mut server, log) = start_under(
        &["sh", "-c", "ulimit -n 64 && exec \"$0\" \"$@\""],
        "conn-fds",
        &["--header-read-timeout", "1", "--workers", "1"],
    );
    let pid = server.child.id();
    let addr = address(&server);
    let mut idle: Vec<TcpStream> = (0..100).map(|_| connect(addr)).collect();
    std::thread::sleep(Duration::from_millis(300));

    let before = cpu_time(pid);
    std::thread::sleep(Duration::from_secs(2));
    let used = cpu_time(pid) - before;
    assert!(
        matches!(server.child.try_wait(), Ok(None)),
        "the server died\n{}",
        log_of(&log)
    );
    assert!(
        used < Duration::from_millis(500),
        "out of file descriptors the server used {used:?} of CPU in 2 s"
    );

    // The idle connections stay open on the client's side: the server frees
    // its descriptors itself (header timeout) and serves a request again.
    let mut probe = connect(addr);
    probe
        .set_read_timeout(Some(Duration::from_secs(20)))
        .expect("read timeout");
    assert_eq!(get_on(&mut probe, "/healthz"), 200, "{}", log_of(&log));
    drop(probe);
    for s in &mut idle {
        assert!(
            closed_within(s, Duration::from_secs(5)).is_some(),
            "an idle connection was never closed"
        );
    }
    assert!(
        metric(&server, "topple_accept_errors_total") > 0.0,
        "the server never ran out of file descriptors\n{}",
        log_of(&log)
    );
    let logged = log_of(&log);
    let warnings = logged.matches("accepting a connection failed").count();
    assert!(
        (1..=3).contains(&warnings),
        "failed accepts logged {warnings} times, not at most every 10 s\n{logged}"
    );
}

#[test]
fn shutdown_ends_within_the_grace_period_whatever_the_clients_do() {
    let (mut server, log) = start(
        "conn-shutdown",
        &[
            "--shutdown-grace",
            "2",
            "--workers",
            "1",
            "--header-read-timeout",
            "60",
            "--body-read-timeout",
            "60",
        ],
    );
    let addr = address(&server);
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
        j["status"] == "running"
    });
    assert_eq!(running["status"], "running");

    let mut half = connect(addr);
    half.write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n")
        .expect("half a request sent");
    let slow = connect(addr);
    let stop = Arc::new(AtomicBool::new(false));
    trickle(
        &slow,
        "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 1000\r\n\r\n{",
        Duration::from_millis(500),
        stop.clone(),
    );
    let mut events = connect(addr);
    write!(
        events,
        "GET /v1/jobs/{id}/events HTTP/1.1\r\nHost: x\r\nAccept: text/event-stream\r\n\r\n"
    )
    .expect("stream asked");
    let mut poll = connect(addr);
    write!(
        poll,
        "GET /v1/jobs/{id}?wait=60 HTTP/1.1\r\nHost: x\r\n\r\n"
    )
    .expect("poll sent");
    std::thread::sleep(Duration::from_millis(700));

    let asked = Instant::now();
    let exit = server.terminate(Duration::from_secs(15));
    let took = asked.elapsed();
    stop.store(true, Ordering::Relaxed);
    assert!(
        took <= Duration::from_secs(3),
        "SIGTERM with a grace of 2 s took {took:?} to stop the server\n{}",
        log_of(&log)
    );
    assert!(exit.success(), "{exit:?}\n{}", log_of(&log));
    assert!(closed_within(&mut half, Duration::from_secs(1)).is_some());
}

#[test]
fn a_body_sent_too_slowly_is_answered_408() {
    let (server, log) = start("conn-body", &["--body-read-timeout", "1"]);
    let mut s = connect(address(&server));
    let stop = Arc::new(AtomicBool::new(false));
    let sent = Instant::now();
    trickle(
        &s,
        "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 1000\r\n\r\n{",
        Duration::from_millis(200),
        stop.clone(),
    );
    s.set_read_timeout(Some(Duration::from_secs(4)))
        .expect("read timeout");
    let answer = read_response(&mut s);
    let took = sent.elapsed();
    stop.store(true, Ordering::Relaxed);
    match answer {
        Ok((status, head, body)) => {
            assert_eq!(status, 408, "{head}{body}");
            assert!(
                head.to_ascii_lowercase()
                    .contains("content-type: application/problem+json"),
                "{head}"
            );
            let problem: serde_json::Value = serde_json::from_str(&body).expect("JSON");
            assert_eq!(problem["limit"], "body_read_timeout", "{problem}");
            assert!(
                closed_within(&mut s, Duration::from_secs(2)).is_some(),
                "the connection stays open after the 408"
            );
        }
        Err(e) => {
            eprintln!("no 408 read, the connection closed after {took:?}: {e}");
            assert!(
                !matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut),
                "no answer and the connection still open {took:?} into a body sent a byte every 200 ms\n{}",
                log_of(&log)
            );
        }
    }
    assert!(took < Duration::from_secs(4), "{took:?}");
    assert_eq!(metric(&server, "topple_request_body_timeouts_total"), 1.0);
    assert_eq!(
        http::get_status(&format!("{}/healthz", server.base)).expect("GET /healthz"),
        200
    );
}

#[test]
fn zero_connection_limits_are_refused_at_start() {
    let dir = temp_dir("conn-zero");
    let db = sqlite_url(&dir);
    for (flag, message) in [
        ("--max-connections", "--max-connections must be at least 1"),
        (
            "--header-read-timeout",
            "--header-read-timeout must be a positive number of seconds",
        ),
        (
            "--idle-timeout",
            "--idle-timeout must be a positive number of seconds",
        ),
        (
            "--body-read-timeout",
            "--body-read-timeout must be a positive number of seconds",
        ),
    ] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_topple"))
            .args([
                "serve",
                "--addr",
                "127.0.0.1:0",
                "--database",
                &db,
                flag,
                "0",
            ])
            .output()
            .expect("topple runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flag} 0: {stderr}");
        assert!(stderr.contains(message), "{flag} 0: {stderr}");
    }
}
