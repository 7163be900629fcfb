//! What guards the service: the token, CORS, panics caught, the queue limit,
//! the compute-time limit.

use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::routing::get;
use serde_json::{Value, json};

use super::helpers::*;

fn history(a: f64) -> Value {
    json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_cosine", "omega_ratio": 3.0, "a_p_alpha_g": a}
    })
}

fn spectrum(steps: usize) -> Value {
    json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"},
        "omega_ratio": {"from": 0.5, "to": 10.0, "steps": steps}
    })
}

async fn problem_of(r: reqwest::Response) -> (u16, reqwest::header::HeaderMap, Value) {
    let status = r.status().as_u16();
    let headers = r.headers().clone();
    assert_eq!(
        headers.get("content-type").and_then(|v| v.to_str().ok()),
        Some("application/problem+json")
    );
    (status, headers, r.json().await.expect("problem json"))
}

#[tokio::test]
async fn with_a_token_writes_need_it_and_reads_stay_open() {
    let app = spawn_app_with("token", |c| c.api_token = Some("s3cret".into())).await;
    let post = |auth: Option<&str>| {
        let mut r = app.client.post(app.url("/v1/jobs")).json(&history(3.0));
        if let Some(a) = auth {
            r = r.header("authorization", a);
        }
        r.send()
    };
    for auth in [
        None,
        Some("Bearer wrong"),
        Some("s3cret"),
        Some("Basic s3cret"),
    ] {
        let (status, headers, body) = problem_of(post(auth).await.expect("r")).await;
        assert_eq!(status, 401, "{auth:?}");
        assert_eq!(body["header"], "authorization");
        assert!(
            headers
                .get("www-authenticate")
                .is_some_and(|v| v.as_bytes().starts_with(b"Bearer"))
        );
    }
    // The scheme is case-insensitive.
    for auth in ["bearer s3cret", "BEARER s3cret"] {
        let r = post(Some(auth)).await.expect("r");
        assert!(r.status().is_success(), "{auth}: {}", r.status());
    }
    let r = app
        .client
        .post(app.url("/v1/jobs"))
        .header("authorization", "Bearer s3cret")
        .json(&history(3.5))
        .send()
        .await
        .expect("r");
    assert_eq!(r.status().as_u16(), 202);
    let job: Value = r.json().await.expect("json");
    let id = job["id"].as_str().expect("id");
    // Reads are open by default.
    let (status, _) = app.get(&format!("/v1/jobs/{id}")).await;
    assert_eq!(status, 200);
    let (status, _) = app.get("/v1/jobs").await;
    assert_eq!(status, 200);
    // Deleting is a write.
    let r = app.delete(&format!("/v1/jobs/{id}")).await;
    assert_eq!(r.status().as_u16(), 401);
    app.stop().await;
}

#[tokio::test]
async fn with_reads_protected_only_the_probes_and_the_description_stay_open() {
    let app = spawn_app_with("token-reads", |c| {
        c.api_token = Some("s3cret".into());
        c.auth_reads = true;
    })
    .await;
    for path in [
        "/v1/jobs",
        "/metrics",
        "/v1/jobs/0190c3a4-6d1e-7000-8000-000000000000",
    ] {
        let r = app.client.get(app.url(path)).send().await.expect("r");
        assert_eq!(r.status().as_u16(), 401, "{path}");
        let r = app
            .client
            .get(app.url(path))
            .bearer_auth("s3cret")
            .send()
            .await
            .expect("r");
        assert_ne!(r.status().as_u16(), 401, "{path}");
    }
    for path in ["/healthz", "/readyz", "/openapi.yaml"] {
        let (status, _, _) = app.get_text(path).await;
        assert_eq!(status, 200, "{path}");
    }
    app.stop().await;
}

#[tokio::test]
async fn cors_answers_the_configured_origins_only() {
    let app = spawn_app_with("cors", |c| {
        c.cors_origins = vec!["https://forensic.example".into()];
    })
    .await;
    let preflight = |origin: &'static str| {
        app.client
            .request(reqwest::Method::OPTIONS, app.url("/v1/jobs"))
            .header("origin", origin)
            .header("access-control-request-method", "POST")
            .header(
                "access-control-request-headers",
                "content-type,authorization",
            )
            .send()
    };
    let r = preflight("https://forensic.example").await.expect("r");
    assert!(r.status().is_success());
    assert_eq!(
        r.headers()
            .get("access-control-allow-origin")
            .and_then(|v| v.to_str().ok()),
        Some("https://forensic.example")
    );
    let methods = r
        .headers()
        .get("access-control-allow-methods")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string();
    assert!(
        methods.contains("POST") && methods.contains("DELETE"),
        "{methods}"
    );
    let r = preflight("https://elsewhere.example").await.expect("r");
    assert!(r.headers().get("access-control-allow-origin").is_none());
    // A simple request from the origin is answered with the header too.
    let r = app
        .client
        .get(app.url("/v1/jobs"))
        .header("origin", "https://forensic.example")
        .send()
        .await
        .expect("r");
    assert_eq!(
        r.headers()
            .get("access-control-allow-origin")
            .and_then(|v| v.to_str().ok()),
        Some("https://forensic.example")
    );
    app.stop().await;
    // Without origins configured, no CORS headers at all.
    let plain = spawn_app("no-cors").await;
    let r = plain
        .client
        .get(plain.url("/v1/jobs"))
        .header("origin", "https://forensic.example")
        .send()
        .await
        .expect("r");
    assert!(r.headers().get("access-control-allow-origin").is_none());
    plain.stop().await;
}

#[tokio::test]
async fn a_panicking_handler_answers_500_problem_json_and_the_server_stays_up() {
    let app = spawn_app("panic-handler").await;
    let routes = Router::new().route(
        "/boom",
        get(|| async {
            let secret = "/srv/topple/src/secret.rs";
            panic!("handler failed at {secret}");
            #[allow(unreachable_code)]
            ""
        }),
    );
    let router = topple::api::with_layers(routes, app.state.clone());
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let base = format!("http://{}", listener.local_addr().expect("addr"));
    let server = tokio::spawn(async move { axum::serve(listener, router).await });
    for _ in 0..3 {
        let r = app
            .client
            .get(format!("{base}/boom"))
            .send()
            .await
            .expect("an answer, not a dropped connection");
        let (status, _, body) = problem_of(r).await;
        assert_eq!(status, 500);
        let text = body.to_string();
        assert!(
            !text.contains("secret") && !text.contains("panicked"),
            "{text}"
        );
    }
    let r = app
        .client
        .get(format!("{base}/nowhere"))
        .send()
        .await
        .expect("still serving");
    assert_eq!(r.status().as_u16(), 404);
    server.abort();
    app.stop().await;
}

#[tokio::test]
async fn a_panicking_job_fails_with_a_plain_reason_and_the_next_one_runs() {
    // The real engine, except for one amplitude where it panics.
    let engine: topple::service::Engine = Arc::new(|job, control| {
        let spec = serde_json::to_value(job.job()).unwrap_or_default();
        let level = |p: &str| spec.pointer(p).and_then(Value::as_f64).unwrap_or(f64::NAN);
        if (level("/pulse/a_p") / (level("/block/alpha") * level("/block/g")) - 6.5).abs() < 1e-9 {
            panic!("engine failed at /srv/topple/src/dynamics/secret.rs");
        }
        job.run(control)
    });
    let app = spawn_app_with_engine("panic-job", |_| {}, Some(engine)).await;
    let (_, bad, _) = app.post("/v1/jobs", &history(6.5)).await;
    let done = app
        .finish(bad["id"].as_str().expect("id"), Duration::from_secs(10))
        .await;
    assert_eq!(done["status"], "failed", "{done}");
    let error = done["error"].as_str().unwrap_or("");
    assert!(error.contains("internal error"), "{error}");
    assert!(
        !error.contains("secret") && !error.contains("src/"),
        "{error}"
    );
    // The pool and the worker survived: the next jobs compute.
    for a in [2.5, 3.5] {
        let (status, good, _) = app.post("/v1/jobs?wait=10", &history(a)).await;
        assert_eq!(status, 200, "{good}");
        assert_eq!(good["status"], "succeeded");
    }
    app.stop().await;
}

#[tokio::test]
async fn a_full_queue_answers_429_with_retry_after_but_known_work_is_still_answered() {
    let app = spawn_app_with("queue", |c| {
        c.workers = 1;
        c.max_queued = 2;
    })
    .await;
    // One long job occupies the only worker; two more wait.
    let (_, running, _) = app.post("/v1/jobs", &spectrum(400)).await;
    let running_id = running["id"].as_str().expect("id").to_string();
    let uuid = uuid::Uuid::parse_str(&running_id).expect("uuid");
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while !app.state.computing(uuid) {
        assert!(std::time::Instant::now() < deadline, "never started");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    let (s1, first, _) = app.post("/v1/jobs", &history(2.0)).await;
    let (s2, _, _) = app.post("/v1/jobs", &history(2.5)).await;
    assert_eq!((s1, s2), (202, 202));
    let r = app
        .client
        .post(app.url("/v1/jobs"))
        .json(&history(3.0))
        .send()
        .await
        .expect("r");
    let (status, headers, body) = problem_of(r).await;
    assert_eq!(status, 429, "{body}");
    assert_eq!(
        headers.get("retry-after").and_then(|v| v.to_str().ok()),
        Some("2")
    );
    assert_eq!(body["retry_after"], 2);
    // The same spec as a queued job is not new work: it is answered.
    let (status, again, _) = app.post("/v1/jobs", &history(2.0)).await;
    assert_eq!(status, 202);
    assert_eq!(again["id"], first["id"]);
    assert_eq!(again["cached"], true);
    let (_, _, metrics) = app.get_text("/metrics").await;
    assert!(
        metrics.contains("topple_jobs_rejected_queue_full_total 1"),
        "{metrics}"
    );
    // Once the queue drains, new work is accepted again.
    let _ = app
        .client
        .delete(app.url(&format!("/v1/jobs/{running_id}")))
        .send()
        .await;
    let done = app
        .finish(first["id"].as_str().expect("id"), Duration::from_secs(10))
        .await;
    assert_eq!(done["status"], "succeeded");
    let (status, _, _) = app.post("/v1/jobs?wait=10", &history(3.0)).await;
    assert_eq!(status, 200);
    app.stop().await;
}

#[tokio::test]
async fn a_job_past_the_compute_time_limit_fails_saying_so() {
    let app = spawn_app_with("timeout", |c| {
        c.workers = 1;
        c.job_timeout = Duration::from_millis(300);
    })
    .await;
    // One frequency on a fine amplitude grid: a task of a few seconds.
    let mut long = spectrum(2);
    long["omega_ratio"] = serde_json::json!({"from": 0.3, "to": 0.31, "steps": 2});
    long["scan_step_alpha_g"] = serde_json::json!(0.0005);
    let (_, job, _) = app.post("/v1/jobs", &long).await;
    let done = app
        .finish(job["id"].as_str().expect("id"), Duration::from_secs(10))
        .await;
    assert_eq!(done["status"], "failed", "{done}");
    let error = done["error"].as_str().unwrap_or("");
    assert!(
        error.contains("0.3 s") && error.contains("job_timeout"),
        "{error}"
    );
    // Short work still runs.
    let (status, _, _) = app.post("/v1/jobs?wait=10", &history(3.0)).await;
    assert_eq!(status, 200);
    app.stop().await;
}
