//! Tenants: who may use the service with a tokens file, and what each
//! tenant's token lets it see.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use reqwest::Method;
use serde_json::Value;
use topple::service::tenants::digest;

use super::helpers::*;

/// Alice's and Bob's tokens, as `topple token` makes them.
const ALICE: &str = "tpl_a11ce00000000000000000000000000000000000000000000000000000000001";
const BOB: &str = "tpl_b0b0000000000000000000000000000000000000000000000000000000000002";

/// A tokens file in a directory of its own holding `tenants` (name, token).
fn tokens_file(name: &str, tenants: &[(&str, &str)]) -> PathBuf {
    let path = temp_dir(name).join("tokens");
    let mut text = String::from("# tenants of this test\n");
    for (tenant, token) in tenants {
        text.push_str(&format!("{tenant} {}\n", digest(token)));
    }
    std::fs::write(&path, text).expect("tokens file");
    path
}

/// Appends a token of `tenant` to the tokens file, as an operator would.
fn add_token(path: &Path, tenant: &str, token: &str) {
    use std::io::Write;
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .open(path)
        .expect("tokens file opens");
    writeln!(file, "{tenant} {}", digest(token)).expect("append");
}

/// A server whose tenants are Alice and Bob.
async fn spawn_tenants(
    name: &str,
    configure: impl FnOnce(&mut topple::service::ServeConfig),
) -> (TestApp, PathBuf) {
    let path = tokens_file(name, &[("alice", ALICE), ("bob", BOB)]);
    let tokens = path.clone();
    let app = spawn_app_with(name, move |c| {
        c.tokens_file = Some(tokens);
        configure(c);
    })
    .await;
    (app, path)
}

/// Sends `method path` with `token` (if any) and a job spec for a POST.
async fn send(app: &TestApp, method: Method, path: &str, token: Option<&str>) -> reqwest::Response {
    let mut request = app.client.request(method.clone(), app.url(path));
    if method == Method::POST {
        request = request.json(&time_history(4.0));
    }
    if let Some(token) = token {
        request = request.bearer_auth(token);
    }
    request.send().await.expect("an answer")
}

/// The 401 the service answers a request without a valid token.
async fn assert_unauthorized(r: reqwest::Response, what: &str) {
    assert_eq!(r.status().as_u16(), 401, "{what}");
    let header = |name: &str| {
        r.headers()
            .get(name)
            .and_then(|v| v.to_str().ok())
            .unwrap_or("")
            .to_string()
    };
    assert_eq!(
        header("www-authenticate"),
        "Bearer realm=\"topple\"",
        "{what}"
    );
    assert_eq!(header("content-type"), "application/problem+json", "{what}");
    let body: Value = r.json().await.expect("problem json");
    assert_eq!(body["status"], 401, "{what}");
    assert_eq!(body["header"], "authorization", "{what}");
}

// ------------------------------------------------------------------ access

#[tokio::test]
async fn with_a_tokens_file_every_route_needs_a_tenants_token_but_the_open_ones() {
    let (app, tokens) = spawn_tenants("tenants-access", |c| {
        c.cors_origins = vec!["https://tool.example".into()];
    })
    .await;
    for (method, path) in [
        (Method::GET, "/v1/jobs"),
        (Method::POST, "/v1/jobs"),
        (Method::GET, "/v1/jobs/0190c3a4-6d1e-7000-8000-000000000000"),
        (Method::GET, "/metrics"),
    ] {
        for token in [None, Some("tpl_nobody"), Some(&ALICE[..ALICE.len() - 1])] {
            let what = format!("{method} {path} with {token:?}");
            assert_unauthorized(send(&app, method.clone(), path, token).await, &what).await;
        }
        // Another scheme is no bearer token.
        let r = app
            .client
            .request(method.clone(), app.url(path))
            .header("authorization", format!("Basic {ALICE}"))
            .send()
            .await
            .expect("r");
        assert_unauthorized(r, &format!("{method} {path} Basic")).await;
    }
    for token in [ALICE, BOB] {
        let r = send(&app, Method::GET, "/v1/jobs", Some(token)).await;
        assert_eq!(r.status().as_u16(), 200);
        let r = send(&app, Method::POST, "/v1/jobs", Some(token)).await;
        assert!([200, 202].contains(&r.status().as_u16()), "{}", r.status());
        let r = send(&app, Method::GET, "/metrics", Some(token)).await;
        assert_eq!(r.status().as_u16(), 200);
    }
    // The scheme is case-insensitive, as with the single token.
    let r = app
        .client
        .get(app.url("/v1/jobs"))
        .header("authorization", format!("bearer {BOB}"))
        .send()
        .await
        .expect("r");
    assert_eq!(r.status().as_u16(), 200);
    // The probes, the description and the page stay open.
    for path in ["/healthz", "/readyz", "/openapi.yaml", "/"] {
        let r = send(&app, Method::GET, path, None).await;
        assert_eq!(r.status().as_u16(), 200, "{path}");
    }
    // So does a CORS preflight, which carries no token.
    let r = app
        .client
        .request(Method::OPTIONS, app.url("/v1/jobs"))
        .header("origin", "https://tool.example")
        .header("access-control-request-method", "POST")
        .header(
            "access-control-request-headers",
            "authorization,content-type",
        )
        .send()
        .await
        .expect("r");
    assert!(r.status().is_success(), "{}", r.status());
    assert!(r.headers().contains_key("access-control-allow-origin"));
    app.stop().await;
    let _ = std::fs::remove_dir_all(tokens.parent().unwrap_or(&tokens));
}

#[tokio::test]
async fn metrics_open_serves_the_metrics_without_a_token_and_nothing_else() {
    let (app, tokens) = spawn_tenants("tenants-metrics", |c| c.metrics_open = true).await;
    let r = send(&app, Method::GET, "/metrics", None).await;
    assert_eq!(r.status().as_u16(), 200);
    assert!(r.text().await.expect("text").contains("topple_queue_depth"));
    assert_unauthorized(send(&app, Method::GET, "/v1/jobs", None).await, "jobs").await;
    app.stop().await;
    let _ = std::fs::remove_dir_all(tokens.parent().unwrap_or(&tokens));
}

#[tokio::test]
async fn the_api_token_is_one_more_token_of_tenant_default() {
    let (app, tokens) = spawn_tenants("tenants-api-token", |c| {
        c.api_token = Some("s3cret".into());
    })
    .await;
    // With a tokens file, reads need a token too.
    assert_unauthorized(send(&app, Method::GET, "/v1/jobs", None).await, "read").await;
    for token in ["s3cret", ALICE] {
        let r = send(&app, Method::GET, "/v1/jobs", Some(token)).await;
        assert_eq!(r.status().as_u16(), 200, "{token}");
    }
    app.stop().await;
    let _ = std::fs::remove_dir_all(tokens.parent().unwrap_or(&tokens));
}

#[tokio::test]
async fn a_tenant_added_to_the_file_while_serving_is_accepted_within_two_seconds() {
    let (app, tokens) = spawn_tenants("tenants-reload", |_| {}).await;
    const CAROL: &str = "tpl_ca201000000000000000000000000000000000000000000000000000000000003";
    assert_unauthorized(
        send(&app, Method::GET, "/v1/jobs", Some(CAROL)).await,
        "before",
    )
    .await;
    add_token(&tokens, "carol", CAROL);
    let added = Instant::now();
    loop {
        let r = send(&app, Method::GET, "/v1/jobs", Some(CAROL)).await;
        if r.status().as_u16() == 200 {
            break;
        }
        assert_eq!(r.status().as_u16(), 401);
        assert!(
            added.elapsed() < Duration::from_millis(2500),
            "carol still refused after {:?}",
            added.elapsed()
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    // The others' tokens still work.
    let r = send(&app, Method::GET, "/v1/jobs", Some(ALICE)).await;
    assert_eq!(r.status().as_u16(), 200);
    // A line that does not parse is refused; what was read stays valid.
    add_token(&tokens, "-bad-name", "tpl_whatever");
    tokio::time::sleep(Duration::from_millis(1200)).await;
    for token in [ALICE, CAROL] {
        let r = send(&app, Method::GET, "/v1/jobs", Some(token)).await;
        assert_eq!(r.status().as_u16(), 200);
    }
    app.stop().await;
    let _ = std::fs::remove_dir_all(tokens.parent().unwrap_or(&tokens));
}
