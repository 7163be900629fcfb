//! Load client of `bench/load.sh`: submits distinct small time-history jobs
//! with `POST /v1/jobs?wait=10` to a topple server on 127.0.0.1, from
//! `--concurrency` clients each on its own keep-alive connection, and
//! reports the service overhead (client latency minus the compute time the
//! result reports, `numerics.wall_time_s`), the jobs per second, and, given
//! the server's process id, the server's CPU time per job (utime + stime of
//! `/proc/<pid>/stat`) beside this client's own.
//!
//! ```text
//! cargo run --release --example load -- --port P [--n N] [--concurrency C]
//!     [--base A] [--warmup W] [--server-pid PID] [--label TEXT]
//! ```
//!
//! Job i has `a_p_alpha_g = base + i·1e-6`: no two are the same spec, so
//! none is answered from the cache. The last line of output is one JSON
//! object (prefixed `RESULT `) with every figure, for scripts.

use std::time::{Duration, Instant};

use serde::Deserialize;

const STEP: f64 = 1e-6;

/// Command-line options.
struct Options {
    port: u16,
    n: usize,
    concurrency: usize,
    base: f64,
    warmup: usize,
    server_pid: Option<u32>,
    label: String,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        port: 0,
        n: 1000,
        concurrency: 1,
        base: 3.0,
        warmup: 50,
        server_pid: None,
        label: String::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let bad = |e: &dyn std::fmt::Display| format!("{flag} {value:?}: {e}");
        match flag.as_str() {
            "--port" => o.port = value.parse().map_err(|e| bad(&e))?,
            "--n" => o.n = value.parse().map_err(|e| bad(&e))?,
            "--concurrency" => o.concurrency = value.parse().map_err(|e| bad(&e))?,
            "--base" => o.base = value.parse().map_err(|e| bad(&e))?,
            "--warmup" => o.warmup = value.parse().map_err(|e| bad(&e))?,
            "--server-pid" => o.server_pid = Some(value.parse().map_err(|e| bad(&e))?),
            "--label" => o.label = value,
            other => return Err(format!("unknown option {other}")),
        }
    }
    if o.port == 0 || o.concurrency == 0 {
        return Err("--port and a --concurrency of at least 1 are needed".into());
    }
    Ok(o)
}

fn spec(a_p_alpha_g: f64) -> String {
    serde_json::json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine", "omega_ratio": 5, "a_p_alpha_g": a_p_alpha_g},
        "formulation": "nonlinear",
    })
    .to_string()
}

/// The fields of the answer this client reads.
#[derive(Deserialize)]
struct Answer {
    status: String,
    result: Option<Inline>,
}

#[derive(Deserialize)]
struct Inline {
    numerics: Numerics,
}

#[derive(Deserialize)]
struct Numerics {
    wall_time_s: f64,
}

/// One request: its latency and the compute time its result reports, s.
struct Sample {
    latency: f64,
    compute: f64,
}

/// CPU time (user + system) of a process so far, s: `/proc/<pid>/stat`.
fn cpu_seconds(pid: &str) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command name (which may hold spaces), from field 3.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    // SAFETY: sysconf reads a constant of the system.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    Some(ticks / hz)
}

/// Posts a job of each amplitude in turn on one keep-alive connection
/// until `deadline`; their samples, and how many failed (anything but a
/// succeeded job with its result inline).
async fn client(
    port: u16,
    amplitudes: Vec<f64>,
    deadline: Instant,
) -> Result<(Vec<Sample>, usize), String> {
    let http = reqwest::Client::builder()
        .pool_max_idle_per_host(1)
        .timeout(Duration::from_secs(30))
        .build()
        .map_err(|e| e.to_string())?;
    let url = format!("http://127.0.0.1:{port}/v1/jobs?wait=10");
    let mut samples = Vec::with_capacity(amplitudes.len());
    let mut failed = 0;
    for a in amplitudes {
        if Instant::now() > deadline {
            break;
        }
        let body = spec(a);
        let t0 = Instant::now();
        let sent = http
            .post(&url)
            .header("content-type", "application/json")
            .body(body)
            .send()
            .await;
        let answer = match sent {
            Ok(r) if r.status().as_u16() == 200 => r.bytes().await.ok(),
            Ok(r) => {
                let _ = r.bytes().await;
                None
            }
            Err(_) => None,
        };
        let latency = t0.elapsed().as_secs_f64();
        let compute = answer
            .and_then(|b| serde_json::from_slice::<Answer>(&b).ok())
            .filter(|a| a.status == "succeeded")
            .and_then(|a| a.result)
            .map(|r| r.numerics.wall_time_s);
        match compute {
            Some(compute) => samples.push(Sample { latency, compute }),
            None => failed += 1,
        }
    }
    Ok((samples, failed))
}

/// Runs `n` jobs from `concurrency` clients; their samples, failures and
/// the wall time, s.
async fn batch(o: &Options, base: f64, n: usize) -> Result<(Vec<Sample>, usize, f64), String> {
    let deadline = Instant::now() + Duration::from_secs(600);
    let t0 = Instant::now();
    let mut handles = Vec::new();
    for c in 0..o.concurrency {
        let amplitudes: Vec<f64> = (c..n)
            .step_by(o.concurrency)
            .map(|i| base + i as f64 * STEP)
            .collect();
        handles.push(tokio::spawn(client(o.port, amplitudes, deadline)));
    }
    let mut samples = Vec::with_capacity(n);
    let mut failed = 0;
    for h in handles {
        let (s, f) = h.await.map_err(|e| e.to_string())??;
        samples.extend(s);
        failed += f;
    }
    Ok((samples, failed, t0.elapsed().as_secs_f64()))
}

/// Nearest-rank percentile of ascending `v`, q in 0..100.
fn pct(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let k = ((q / 100.0 * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1;
    v[k]
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let o = match options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("load: {e}");
            std::process::exit(2);
        }
    };
    // Warm-up jobs: other amplitudes than the measured ones.
    if o.warmup > 0
        && let Err(e) = batch(&o, o.base + 0.5, o.warmup).await
    {
        eprintln!("load: warm-up failed: {e}");
    }
    let server = o.server_pid.map(|p| p.to_string());
    let server_cpu0 = server.as_deref().and_then(cpu_seconds);
    let client_cpu0 = cpu_seconds("self");
    let (samples, failed, wall) = match batch(&o, o.base, o.n).await {
        Ok(r) => r,
        Err(e) => {
            eprintln!("load: {e}");
            std::process::exit(1);
        }
    };
    let server_cpu = server
        .as_deref()
        .and_then(cpu_seconds)
        .zip(server_cpu0)
        .map(|(b, a)| b - a);
    let client_cpu = cpu_seconds("self").zip(client_cpu0).map(|(b, a)| b - a);
    let done = samples.len();
    let latency = sorted(samples.iter().map(|s| s.latency).collect());
    let compute = sorted(samples.iter().map(|s| s.compute).collect());
    let overhead = sorted(samples.iter().map(|s| s.latency - s.compute).collect());
    let per_job = |cpu: Option<f64>| cpu.map_or(f64::NAN, |c| c / done.max(1) as f64 * 1e3);
    let ms = |v: &[f64], q: f64| pct(v, q) * 1e3;
    let rate = done as f64 / wall;
    println!(
        "{label} concurrency {c}: {done} jobs ({failed} failed) in {wall:.2} s = {rate:.0} jobs/s; \
         overhead p50 {o50:.3} p99 {o99:.3} ms; latency p50 {l50:.3} p99 {l99:.3} ms; \
         compute p50 {c50:.3} ms; CPU/job server {s:.3} ms, client {k:.3} ms",
        label = o.label,
        c = o.concurrency,
        o50 = ms(&overhead, 50.0),
        o99 = ms(&overhead, 99.0),
        l50 = ms(&latency, 50.0),
        l99 = ms(&latency, 99.0),
        c50 = ms(&compute, 50.0),
        s = per_job(server_cpu),
        k = per_job(client_cpu),
    );
    let result = serde_json::json!({
        "label": o.label,
        "concurrency": o.concurrency,
        "jobs": done,
        "failed": failed,
        "seconds": wall,
        "jobs_per_s": rate,
        "overhead_p50_ms": ms(&overhead, 50.0),
        "overhead_p99_ms": ms(&overhead, 99.0),
        "latency_p50_ms": ms(&latency, 50.0),
        "latency_p99_ms": ms(&latency, 99.0),
        "compute_p50_ms": ms(&compute, 50.0),
        "server_cpu_ms_per_job": per_job(server_cpu),
        "client_cpu_ms_per_job": per_job(client_cpu),
    });
    println!("RESULT {result}");
    if failed > 0 {
        std::process::exit(1);
    }
}
