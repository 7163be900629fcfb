//! Memory of a real `topple serve` under large reads. One time history with a
//! 200,000-sample series (a result document of about 26 MB) is computed; then
//! sixteen clients download its CSV at once (some asking for gzip), and
//! sixteen read its JSON at once amid listings. The server's peak resident set
//! during the reads, read from `/proc/<pid>/status`, stays under 300 MiB.
//!
//! The computation itself stays under the same bound; its peak is printed,
//! then reset (`clear_refs`) before the reads, so that each bound is measured
//! on its own.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::common::server::{Server, http, sqlite_url, temp_dir, wait_status};
use serde_json::{Value, json};

/// The bound on the server's resident set during the reads.
const LIMIT_MIB: u64 = 300;
/// Samples of the record and of the series.
const SAMPLES: usize = 200_000;
/// Clients reading at once.
const CLIENTS: usize = 16;

/// A time history of a decaying 1.3 Hz record sampled at 2 kHz for 100 s, its
/// series sampled 200,000 times: the block rocks throughout.
fn spec() -> Value {
    let dt = 0.0005;
    let acc: Vec<f64> = (0..SAMPLES)
        .map(|k| {
            let t = k as f64 * dt;
            let a = 0.3 * (2.0 * std::f64::consts::PI * 1.3 * t).sin() * (-t / 30.0).exp();
            (a * 1e6).round() / 1e6
        })
        .collect();
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.2, "p": 2.0},
        "ground_motion": {"dt": dt, "unit": "g", "acc": acc},
        "outputs": {"series": SAMPLES, "duration": 100.0}
    })
}

/// A field of `/proc/<pid>/status`, KiB.
fn status_kib(pid: u32, field: &str) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(field)?.strip_prefix(':'))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

fn mib(kib: u64) -> f64 {
    kib as f64 / 1024.0
}

/// Polls the resident set of `pid` until stopped; its largest value, KiB.
struct Sampler {
    stop: Arc<AtomicBool>,
    peak: Arc<AtomicU64>,
    thread: Option<JoinHandle<()>>,
}

impl Sampler {
    fn start(pid: u32) -> Sampler {
        let stop = Arc::new(AtomicBool::new(false));
        let peak = Arc::new(AtomicU64::new(0));
        let thread = std::thread::spawn({
            let (stop, peak) = (stop.clone(), peak.clone());
            move || {
                while !stop.load(Ordering::Relaxed) {
                    peak.fetch_max(status_kib(pid, "VmRSS"), Ordering::Relaxed);
                    std::thread::sleep(Duration::from_millis(2));
                }
            }
        });
        Sampler {
            stop,
            peak,
            thread: Some(thread),
        }
    }

    /// Stops polling; the largest resident set seen, KiB.
    fn finish(mut self) -> u64 {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        self.peak.load(Ordering::Relaxed)
    }
}

/// A server holding the finished time history; its id. The peak of the
/// computation is printed and then reset, so that `VmHWM` counts from here.
fn finished(name: &str) -> (Server, String) {
    let dir = temp_dir(name);
    let server = Server::start(
        &sqlite_url(&dir),
        &["--max-body", "8000000", "--workers", "1"],
        Some(&dir.join("server.log")),
    );
    let (status, job) = http::post_json(&format!("{}/v1/jobs", server.base), &spec());
    assert_eq!(status, 202, "{job}");
    let id = job["id"].as_str().expect("id").to_string();
    let job = wait_status(&server.base, &id, "succeeded", Duration::from_secs(120));
    assert_eq!(job["status"], "succeeded", "{job}");
    let pid = server.child.id();
    let peak = status_kib(pid, "VmHWM");
    println!(
        "{name}: computing the job: peak {:.0} MiB; resident after it {:.0} MiB",
        mib(peak),
        mib(status_kib(pid, "VmRSS"))
    );
    assert!(
        mib(peak) < LIMIT_MIB as f64,
        "peak resident set {:.0} MiB while computing",
        mib(peak)
    );
    // 5 resets the peak resident set (proc(5)).
    std::fs::write(format!("/proc/{pid}/clear_refs"), "5").expect("clear_refs");
    (server, id)
}

/// A GET over HTTP/1.0 (so the body ends with the connection) with `headers`:
/// the status, the response head and the body.
fn get(base: &str, path: &str, headers: &[(&str, &str)]) -> (u16, String, Vec<u8>) {
    let host = base.trim_start_matches("http://");
    let mut s = TcpStream::connect(host).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(120)))
        .expect("timeout");
    let extra: String = headers
        .iter()
        .map(|(k, v)| format!("{k}: {v}\r\n"))
        .collect();
    write!(s, "GET {path} HTTP/1.0\r\nHost: {host}\r\n{extra}\r\n").expect("request");
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).expect("response");
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a response head");
    let head = String::from_utf8_lossy(&raw[..split]).to_ascii_lowercase();
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .expect("a status");
    (status, head, raw[split + 4..].to_vec())
}

/// [`get`] as a client does it: a 503 "busy" (the memory for large
/// results stayed taken, as it may on a loaded machine) is a clean refusal
/// with a Retry-After, and the read is tried again after it, for up to two
/// minutes. Any other status is returned as it came.
fn get_retrying(base: &str, path: &str, headers: &[(&str, &str)]) -> (u16, String, Vec<u8>) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let (status, head, body) = get(base, path, headers);
        if status != 503 || Instant::now() >= deadline {
            return (status, head, body);
        }
        assert!(
            String::from_utf8_lossy(&body).contains("busy"),
            "a 503 other than busy: {head}"
        );
        let wait = head
            .lines()
            .find_map(|l| l.strip_prefix("retry-after:"))
            .and_then(|v| v.trim().parse::<u64>().ok())
            .expect("a busy 503 says when to retry");
        std::thread::sleep(Duration::from_secs(wait));
    }
}

fn gunzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .read_to_end(&mut out)
        .expect("gzip");
    out
}

/// The resident peak of `pid` while `work` runs, KiB: the larger of `VmHWM`
/// and the sampled `VmRSS`.
fn peak_during<T>(pid: u32, work: impl FnOnce() -> T) -> (u64, T) {
    let sampler = Sampler::start(pid);
    let out = work();
    let sampled = sampler.finish();
    (sampled.max(status_kib(pid, "VmHWM")), out)
}

#[test]
fn sixteen_concurrent_csv_downloads_of_a_200k_sample_result_stay_under_300_mib() {
    let (server, id) = finished("memory-csv");
    let pid = server.child.id();
    let base = server.base.clone();
    let before = status_kib(pid, "VmRSS");
    let started = Instant::now();
    let (peak, tables) = peak_during(pid, || {
        let clients: Vec<_> = (0..CLIENTS)
            .map(|n| {
                let (base, id) = (base.clone(), id.clone());
                std::thread::spawn(move || {
                    // A quarter ask for gzip; half negotiate by Accept.
                    let mut headers = vec![];
                    if n % 4 == 0 {
                        headers.push(("Accept-Encoding", "gzip"));
                    }
                    let path = if n % 2 == 0 {
                        headers.push(("Accept", "text/csv"));
                        format!("/v1/jobs/{id}/result")
                    } else {
                        format!("/v1/jobs/{id}/result?format=csv")
                    };
                    let (status, head, body) = get(&base, &path, &headers);
                    assert_eq!(status, 200, "{head}");
                    assert!(head.contains("content-type: text/csv"), "{head}");
                    let body = if head.contains("content-encoding: gzip") {
                        gunzip(&body)
                    } else {
                        assert!(n % 4 != 0, "gzip was asked for: {head}");
                        body
                    };
                    String::from_utf8(body).expect("UTF-8")
                })
            })
            .collect();
        clients
            .into_iter()
            .map(|c| c.join().expect("a client"))
            .collect::<Vec<_>>()
    });
    let elapsed = started.elapsed();
    let first = &tables[0];
    assert!(
        first.starts_with("t_s,theta_rad,theta_dot_rad_per_s,"),
        "{}",
        &first[..200]
    );
    let lines = first.lines().count();
    assert!(lines > SAMPLES, "{lines} lines");
    for t in &tables {
        assert!(t == first, "the tables differ");
    }
    println!(
        "{CLIENTS} concurrent CSV downloads ({lines} lines, {:.1} MB each) in {elapsed:.1?}: resident {:.0} MiB before, peak {:.0} MiB (bound {LIMIT_MIB} MiB)",
        first.len() as f64 / 1e6,
        mib(before),
        mib(peak)
    );
    assert!(
        mib(peak) < LIMIT_MIB as f64,
        "peak resident set {:.0} MiB",
        mib(peak)
    );
}

#[test]
fn sixteen_concurrent_json_reads_amid_listings_stay_under_300_mib() {
    let (server, id) = finished("memory-json");
    let pid = server.child.id();
    let base = server.base.clone();
    let before = status_kib(pid, "VmRSS");
    let started = Instant::now();
    let (peak, (documents, listings)) = peak_during(pid, || {
        let readers: Vec<_> = (0..CLIENTS)
            .map(|n| {
                let (base, id) = (base.clone(), id.clone());
                std::thread::spawn(move || {
                    let headers: &[(&str, &str)] = if n % 4 == 0 {
                        &[("Accept-Encoding", "gzip")]
                    } else {
                        &[]
                    };
                    let (status, head, body) =
                        get_retrying(&base, &format!("/v1/jobs/{id}/result"), headers);
                    assert_eq!(status, 200, "{head}");
                    assert!(head.contains("content-type: application/json"), "{head}");
                    if head.contains("content-encoding: gzip") {
                        gunzip(&body)
                    } else {
                        body
                    }
                })
            })
            .collect();
        let listers: Vec<_> = (0..4)
            .map(|n| {
                let base = base.clone();
                std::thread::spawn(move || {
                    let path = if n == 0 {
                        "/v1/jobs?limit=500&include=spec"
                    } else {
                        "/v1/jobs?limit=500"
                    };
                    (0..5)
                        .map(|_| {
                            let (status, head, body) = get_retrying(&base, path, &[]);
                            assert_eq!(status, 200, "{head}");
                            body.len()
                        })
                        .max()
                        .unwrap_or(0)
                })
            })
            .collect();
        let documents: Vec<Vec<u8>> = readers
            .into_iter()
            .map(|r| r.join().expect("a reader"))
            .collect();
        let listings: Vec<usize> = listers
            .into_iter()
            .map(|l| l.join().expect("a lister"))
            .collect();
        (documents, listings)
    });
    let elapsed = started.elapsed();
    let first = &documents[0];
    let doc: Value = serde_json::from_slice(first).expect("a JSON result");
    assert_eq!(
        doc["series"]["t"].as_array().map(Vec::len),
        Some(SAMPLES),
        "the series"
    );
    for d in &documents {
        assert!(d == first, "the documents differ");
    }
    // A light listing holds no spec: it stays small whatever the records.
    assert!(listings[1] < 4096, "a listing of {} bytes", listings[1]);
    println!(
        "{CLIENTS} concurrent JSON reads ({:.1} MB each) and 20 listings in {elapsed:.1?}: resident {:.0} MiB before, peak {:.0} MiB (bound {LIMIT_MIB} MiB)",
        first.len() as f64 / 1e6,
        mib(before),
        mib(peak)
    );
    assert!(
        mib(peak) < LIMIT_MIB as f64,
        "peak resident set {:.0} MiB",
        mib(peak)
    );
}

#[test]
fn a_result_memory_of_zero_is_refused_at_start() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_topple"))
        .args(["serve", "--addr", "127.0.0.1:0", "--result-memory", "0"])
        .output()
        .expect("topple runs");
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("--result-memory"),
        "{out:?}"
    );
}
