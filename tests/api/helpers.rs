//! A real server on an ephemeral port with its own temporary database.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use topple::service::{AppState, ServeConfig};
use topple::startup::Application;

pub struct TestApp {
    pub base: String,
    pub client: reqwest::Client,
    pub state: AppState,
    pub dir: PathBuf,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    server: Option<tokio::task::JoinHandle<()>>,
}

pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "topple-test-{name}-{}-{}",
        std::process::id(),
        uuid::Uuid::now_v7()
    ));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

pub async fn spawn_app_with(name: &str, configure: impl FnOnce(&mut ServeConfig)) -> TestApp {
    spawn_app_with_engine(name, configure, None).await
}

/// A server computing jobs with `engine` (default: the real one).
pub async fn spawn_app_with_engine(
    name: &str,
    configure: impl FnOnce(&mut ServeConfig),
    engine: Option<topple::service::Engine>,
) -> TestApp {
    let dir = temp_dir(name);
    let mut config = ServeConfig {
        addr: "127.0.0.1:0".into(),
        database_url: format!("sqlite://{}", dir.join("topple.db").display()),
        workers: 2,
        ..Default::default()
    };
    configure(&mut config);
    let app = match engine {
        Some(engine) => Application::build_with_engine(config, engine).await,
        None => Application::build(config).await,
    }
    .expect("app builds");
    let base = format!("http://127.0.0.1:{}", app.port());
    let state = app.state().clone();
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(async move {
        app.run_until(async move {
            let _ = stopped.await;
        })
        .await
        .expect("serves");
    });
    TestApp {
        base,
        client: reqwest::Client::new(),
        state,
        dir,
        stop: Some(stop),
        server: Some(server),
    }
}

pub async fn spawn_app(name: &str) -> TestApp {
    spawn_app_with(name, |_| {}).await
}

impl TestApp {
    pub fn url(&self, path: &str) -> String {
        format!("{}{path}", self.base)
    }

    pub async fn post(&self, path: &str, body: &Value) -> (u16, Value, reqwest::header::HeaderMap) {
        let r = self
            .client
            .post(self.url(path))
            .json(body)
            .send()
            .await
            .expect("request");
        let status = r.status().as_u16();
        let headers = r.headers().clone();
        (status, r.json().await.expect("json body"), headers)
    }

    pub async fn get(&self, path: &str) -> (u16, Value) {
        let r = self
            .client
            .get(self.url(path))
            .send()
            .await
            .expect("request");
        let status = r.status().as_u16();
        (status, r.json().await.unwrap_or(Value::Null))
    }

    pub async fn get_text(&self, path: &str) -> (u16, String, String) {
        let r = self
            .client
            .get(self.url(path))
            .send()
            .await
            .expect("request");
        let status = r.status().as_u16();
        let ct = r
            .headers()
            .get("content-type")
            .and_then(|v| v.to_str().ok())
            .unwrap_or("")
            .to_string();
        (status, ct, r.text().await.expect("text"))
    }

    /// DELETE `path`.
    pub async fn delete(&self, path: &str) -> reqwest::Response {
        self.client
            .delete(self.url(path))
            .send()
            .await
            .expect("request")
    }

    /// Polls the job until it is final (or the time is up).
    pub async fn finish(&self, id: &str, limit: Duration) -> Value {
        let deadline = Instant::now() + limit;
        loop {
            let (status, job) = self.get(&format!("/v1/jobs/{id}")).await;
            assert_eq!(status, 200, "{job}");
            let s = job["status"].as_str().unwrap_or("");
            if ["succeeded", "failed", "canceled"].contains(&s) || Instant::now() > deadline {
                return job;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }

    pub async fn stop(mut self) {
        if let Some(s) = self.stop.take() {
            let _ = s.send(());
        }
        if let Some(h) = self.server.take() {
            let _ = tokio::time::timeout(Duration::from_secs(30), h).await;
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

pub fn time_history(level: f64) -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine", "omega_ratio": 5.0, "a_p_alpha_g": level},
        "formulation": "linear",
        "outputs": {"series": 20}
    })
}

pub fn spectrum(frequencies: usize) -> Value {
    json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "formulation": "nonlinear",
        "omega_ratio": {"from": 0.25, "to": 10.0, "steps": frequencies},
        "a_max_alpha_g": 20,
        "tolerance": 1e-4
    })
}

pub fn friction() -> Value {
    json!({
        "kind": "friction_spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "omega_ratio": 5.0,
        "a_alpha_g": {"from": 2, "to": 8, "steps": 4}
    })
}

/// The topple binary's `run` output for a spec, for comparison.
pub fn topple_run(spec: &Value) -> Value {
    use std::io::Write;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_topple"))
        .args(["run", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("topple runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(spec.to_string().as_bytes())
        .expect("writes");
    let out = child.wait_with_output().expect("finishes");
    assert!(out.status.success());
    serde_json::from_slice(&out.stdout).expect("json")
}

/// The document without its wall-clock times.
pub fn without_times(mut v: Value) -> Value {
    if let Some(n) = v.get_mut("numerics").and_then(|n| n.as_object_mut()) {
        n.remove("wall_time_s");
    }
    v
}
