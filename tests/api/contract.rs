//! HTTP as clients expect it: entity tags and 304s, compression, content
//! negotiation, request ids, CORS, poll hints, long-poll, Server-Sent Events,
//! light listings and provenance.

use std::io::Read;
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::Value;

use super::helpers::*;

async fn finished_time_history(app: &TestApp) -> String {
    let (status, job, _) = app.post("/v1/jobs?wait=20", &time_history(4.0)).await;
    assert_eq!(status, 200, "{job}");
    job["id"].as_str().expect("id").to_string()
}

async fn get(app: &TestApp, path: &str, headers: &[(&str, &str)]) -> reqwest::Response {
    let mut req = app.client.get(app.url(path));
    for (k, v) in headers {
        req = req.header(*k, *v);
    }
    req.send().await.expect("request")
}

fn header(r: &reqwest::Response, name: &str) -> String {
    r.headers()
        .get(name)
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string()
}

#[tokio::test]
async fn results_carry_strong_etags_immutable_caching_and_answer_304() {
    let app = spawn_app("etag").await;
    let id = finished_time_history(&app).await;
    let mut tags = Vec::new();
    for path in [
        format!("/v1/jobs/{id}/result"),
        format!("/v1/jobs/{id}/result?format=csv"),
        format!("/v1/jobs/{id}/plot.svg"),
    ] {
        let r = get(&app, &path, &[]).await;
        assert_eq!(r.status(), 200, "{path}");
        let etag = header(&r, "etag");
        assert!(
            etag.starts_with('"') && etag.ends_with('"'),
            "strong: {etag}"
        );
        assert_eq!(
            header(&r, "cache-control"),
            "public, max-age=31536000, immutable"
        );
        let again = get(&app, &path, &[("if-none-match", &etag)]).await;
        assert_eq!(again.status(), 304, "{path}");
        assert_eq!(header(&again, "etag"), etag);
        assert!(again.bytes().await.expect("body").is_empty());
        let other = get(&app, &path, &[("if-none-match", "\"something-else\"")]).await;
        assert_eq!(other.status(), 200);
        tags.push(etag);
    }
    // One tag per representation, from the job key.
    let (_, job) = app.get(&format!("/v1/jobs/{id}")).await;
    let key = job["key"].as_str().expect("key");
    assert!(tags.iter().all(|t| t.contains(&key[..32])), "{tags:?}");
    assert_ne!(tags[0], tags[1]);
    assert_ne!(tags[1], tags[2]);
    app.stop().await;
}

#[tokio::test]
async fn results_are_private_when_reads_need_a_token() {
    let app = spawn_app_with("etag-private", |c| {
        c.api_token = Some("s3cret".into());
        c.auth_reads = true;
    })
    .await;
    let r = app
        .client
        .post(app.url("/v1/jobs?wait=20"))
        .bearer_auth("s3cret")
        .json(&time_history(4.0))
        .send()
        .await
        .expect("post");
    assert_eq!(r.status(), 200);
    let id = r.json::<Value>().await.expect("json")["id"]
        .as_str()
        .expect("id")
        .to_string();
    let r = app
        .client
        .get(app.url(&format!("/v1/jobs/{id}/result")))
        .bearer_auth("s3cret")
        .send()
        .await
        .expect("get");
    assert_eq!(
        header(&r, "cache-control"),
        "private, max-age=31536000, immutable"
    );
    app.stop().await;
}

#[tokio::test]
async fn status_polls_get_304_until_the_status_changes() {
    let app = spawn_app("status-etag").await;
    let id = finished_time_history(&app).await;
    let path = format!("/v1/jobs/{id}");
    let r = get(&app, &path, &[]).await;
    let etag = header(&r, "etag");
    assert!(etag.starts_with("W/\""), "{etag}");
    assert_eq!(header(&r, "cache-control"), "no-cache");
    let again = get(&app, &path, &[("if-none-match", &etag)]).await;
    assert_eq!(again.status(), 304);
    // A running spectrum: its tag moves with progress and status.
    let (status, job, _) = app.post("/v1/jobs", &spectrum(40)).await;
    assert_eq!(status, 202);
    let sid = job["id"].as_str().expect("id").to_string();
    let first = header(&get(&app, &format!("/v1/jobs/{sid}"), &[]).await, "etag");
    let done = app.finish(&sid, Duration::from_secs(60)).await;
    assert_eq!(done["status"], "succeeded");
    let last = get(
        &app,
        &format!("/v1/jobs/{sid}"),
        &[("if-none-match", &first)],
    )
    .await;
    assert_eq!(last.status(), 200);
    assert_ne!(header(&last, "etag"), first);
    app.stop().await;
}

#[tokio::test]
async fn get_wait_long_polls_and_unknown_parameters_are_named() {
    let app = spawn_app("long-poll").await;
    let (_, job, headers) = app.post("/v1/jobs", &spectrum(20)).await;
    let id = job["id"].as_str().expect("id").to_string();
    // 202 says when to look again.
    let after: u64 = headers["retry-after"]
        .to_str()
        .expect("ascii")
        .parse()
        .expect("seconds");
    assert!((1..=30).contains(&after), "{after}");
    let started = Instant::now();
    let (status, done) = app.get(&format!("/v1/jobs/{id}?wait=60")).await;
    assert_eq!(status, 200);
    assert_eq!(done["status"], "succeeded", "{done}");
    assert!(started.elapsed() < Duration::from_secs(60));
    // With If-None-Match, ?wait returns at the first change, or 304 at the deadline.
    let r = get(&app, &format!("/v1/jobs/{id}"), &[]).await;
    let etag = header(&r, "etag");
    let started = Instant::now();
    let r = get(
        &app,
        &format!("/v1/jobs/{id}?wait=0.5"),
        &[("if-none-match", &etag)],
    )
    .await;
    assert_eq!(r.status(), 304);
    assert!(started.elapsed() >= Duration::from_millis(450));
    for path in [
        format!("/v1/jobs/{id}?wiat=3"),
        format!("/v1/jobs/{id}/result?formt=csv"),
        "/v1/jobs?limt=3".to_string(),
    ] {
        let (status, problem) = app.get(&path).await;
        assert_eq!(status, 400, "{path}: {problem}");
        let name = path.split('?').nth(1).and_then(|q| q.split('=').next());
        assert_eq!(problem["parameter"].as_str(), name, "{problem}");
        assert!(
            problem["detail"]
                .as_str()
                .unwrap_or("")
                .contains("unknown query parameter")
        );
    }
    app.stop().await;
}

#[tokio::test]
async fn a_result_asked_for_too_early_says_when_to_come_back() {
    let app = spawn_app("early").await;
    let (_, job, _) = app.post("/v1/jobs", &spectrum(60)).await;
    let id = job["id"].as_str().expect("id").to_string();
    let r = get(&app, &format!("/v1/jobs/{id}/result"), &[]).await;
    assert_eq!(r.status(), 409);
    let after: u64 = header(&r, "retry-after").parse().expect("seconds");
    assert!((1..=30).contains(&after));
    let problem: Value = r.json().await.expect("problem");
    assert_eq!(problem["retry_after"], after);
    let _ = app.delete(&format!("/v1/jobs/{id}")).await;
    app.stop().await;
}

fn gunzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .read_to_end(&mut out)
        .expect("gzip");
    out
}

#[tokio::test]
async fn json_csv_and_svg_are_compressed_with_gzip_and_br() {
    let app = spawn_app("compress").await;
    let mut spec = time_history(4.0);
    spec["outputs"]["series"] = 2000.into();
    let (status, job, _) = app.post("/v1/jobs?wait=20", &spec).await;
    assert_eq!(status, 200, "{job}");
    let id = job["id"].as_str().expect("id");
    for path in [
        format!("/v1/jobs/{id}/result"),
        format!("/v1/jobs/{id}/result?format=csv"),
        format!("/v1/jobs/{id}/plot.svg"),
    ] {
        let plain = get(&app, &path, &[]).await;
        assert_eq!(header(&plain, "content-encoding"), "");
        let plain = plain.bytes().await.expect("body");
        let gz = get(&app, &path, &[("accept-encoding", "gzip")]).await;
        assert_eq!(header(&gz, "content-encoding"), "gzip", "{path}");
        assert!(
            header(&gz, "vary")
                .to_lowercase()
                .contains("accept-encoding")
        );
        let gz = gz.bytes().await.expect("body");
        assert_eq!(gunzip(&gz), plain.to_vec(), "{path}");
        let br = get(&app, &path, &[("accept-encoding", "br")]).await;
        assert_eq!(header(&br, "content-encoding"), "br", "{path}");
        let br = br.bytes().await.expect("body");
        assert!(
            gz.len() * 2 < plain.len(),
            "{path}: {} of {}",
            gz.len(),
            plain.len()
        );
        assert!(
            br.len() * 2 < plain.len(),
            "{path}: {} of {}",
            br.len(),
            plain.len()
        );
        println!(
            "{path}: {} bytes, gzip {}, br {}",
            plain.len(),
            gz.len(),
            br.len()
        );
    }
    app.stop().await;
}

#[tokio::test]
async fn accept_chooses_csv_or_svg_and_format_overrides_it() {
    let app = spawn_app("negotiate").await;
    let id = finished_time_history(&app).await;
    let path = format!("/v1/jobs/{id}/result");
    let csv = get(&app, &path, &[("accept", "text/csv")]).await;
    assert!(header(&csv, "content-type").starts_with("text/csv"));
    assert_eq!(
        header(&csv, "content-disposition"),
        format!("attachment; filename=\"time_history-{id}.csv\"")
    );
    assert!(csv.text().await.expect("csv").starts_with("t_s,theta_rad"));
    let svg = get(&app, &path, &[("accept", "image/svg+xml")]).await;
    assert_eq!(header(&svg, "content-type"), "image/svg+xml");
    assert!(svg.text().await.expect("svg").contains("<svg"));
    let json = get(&app, &path, &[("accept", "text/html, */*;q=0.1")]).await;
    assert_eq!(header(&json, "content-type"), "application/json");
    let forced = get(
        &app,
        &format!("{path}?format=json"),
        &[("accept", "text/csv")],
    )
    .await;
    assert_eq!(header(&forced, "content-type"), "application/json");
    let svg = get(&app, &format!("{path}?format=svg"), &[]).await;
    assert_eq!(header(&svg, "content-type"), "image/svg+xml");
    app.stop().await;
}

#[tokio::test]
async fn request_ids_are_echoed_generated_and_named_in_problems() {
    let app = spawn_app_with("request-id", |c| c.cors_origins = vec!["*".into()]).await;
    let r = get(&app, "/healthz", &[("x-request-id", "forensic-42")]).await;
    assert_eq!(header(&r, "x-request-id"), "forensic-42");
    assert_eq!(
        header(&r, "server"),
        format!("topple/{}", env!("CARGO_PKG_VERSION"))
    );
    let r = get(&app, "/healthz", &[]).await;
    let generated = header(&r, "x-request-id");
    assert!(uuid::Uuid::parse_str(&generated).is_ok(), "{generated}");
    let long = "x".repeat(500);
    let r = get(&app, "/healthz", &[("x-request-id", &long)]).await;
    let replaced = header(&r, "x-request-id");
    assert!(uuid::Uuid::parse_str(&replaced).is_ok(), "{replaced}");
    let r = get(&app, "/v1/jobs/not-an-id", &[("x-request-id", "case-7")]).await;
    assert_eq!(r.status(), 400);
    assert_eq!(header(&r, "x-request-id"), "case-7");
    let problem: Value = r.json().await.expect("problem");
    assert_eq!(problem["instance"], "urn:topple:request:case-7");
    assert_eq!(problem["request_id"], "case-7");
    // A page on another origin may send and read what it needs.
    let pre = app
        .client
        .request(reqwest::Method::OPTIONS, app.url("/v1/jobs"))
        .header("origin", "https://forensics.example")
        .header("access-control-request-method", "GET")
        .header(
            "access-control-request-headers",
            "x-request-id, traceparent, tracestate, if-none-match",
        )
        .send()
        .await
        .expect("preflight");
    assert!(pre.status().is_success());
    let allowed = header(&pre, "access-control-allow-headers").to_lowercase();
    for h in ["x-request-id", "traceparent", "tracestate", "if-none-match"] {
        assert!(allowed.contains(h), "{h} not in {allowed}");
    }
    let r = get(&app, "/healthz", &[("origin", "https://forensics.example")]).await;
    let exposed = header(&r, "access-control-expose-headers").to_lowercase();
    for h in [
        "etag",
        "location",
        "retry-after",
        "x-request-id",
        "content-disposition",
        "www-authenticate",
    ] {
        assert!(exposed.contains(h), "{h} not in {exposed}");
    }
    app.stop().await;
}

#[tokio::test]
async fn a_job_view_links_everything_and_a_submission_estimates_its_cost() {
    let app = spawn_app("links").await;
    let (status, job, _) = app.post("/v1/jobs", &spectrum(10)).await;
    assert_eq!(status, 202);
    let id = job["id"].as_str().expect("id");
    let base = format!("/v1/jobs/{id}");
    let links = &job["links"];
    assert_eq!(links["self"], base.as_str());
    assert_eq!(links["result"], format!("{base}/result").as_str());
    assert_eq!(links["csv"], format!("{base}/result?format=csv").as_str());
    assert_eq!(links["plot"], format!("{base}/plot.svg").as_str());
    assert_eq!(links["events"], format!("{base}/events").as_str());
    assert_eq!(links["cancel"], base.as_str());
    // 10 frequencies × (1000 scan points + 6 transitions × 8 bisections).
    let estimate = &job["estimate"];
    assert_eq!(estimate["simulations"], 10.0 * (1000.0 + 48.0));
    let per = estimate["seconds_per_simulation"].as_f64().expect("rate");
    let seconds = estimate["seconds"].as_f64().expect("seconds");
    assert!(per > 0.0 && (seconds - per * 10480.0).abs() < 1e-9 * seconds.max(1.0));
    app.finish(id, Duration::from_secs(60)).await;
    // Once jobs have run, the rate is the measured one.
    let (_, next, _) = app.post("/v1/jobs", &spectrum(11)).await;
    let measured = next["estimate"]["seconds_per_simulation"]
        .as_f64()
        .expect("rate");
    assert_ne!(measured, per, "the rate was not updated");
    app.stop().await;
}

#[tokio::test]
async fn post_wait_answers_200_with_a_failed_job() {
    let engine: topple::service::Engine = Arc::new(|_, _| {
        Err(topple::jobs::JobError::AtLevel {
            level: 4.0,
            source: topple::dynamics::SimError::ExactNeedsLinear,
        })
    });
    let app = spawn_app_with_engine("wait-failed", |_| {}, Some(engine)).await;
    let (status, job, _) = app.post("/v1/jobs?wait=10", &time_history(4.0)).await;
    assert_eq!(status, 200, "{job}");
    assert_eq!(job["status"], "failed");
    assert!(
        job["error"]
            .as_str()
            .unwrap_or("")
            .contains("at a_p = 4 αg"),
        "{job}"
    );
    assert!(job.get("result").is_none());
    app.stop().await;
}

#[tokio::test]
async fn listings_are_light_unless_asked_and_link_the_next_page() {
    let app = spawn_app("light-list").await;
    for level in [3.0, 3.5, 4.0] {
        let (status, _, _) = app.post("/v1/jobs?wait=20", &time_history(level)).await;
        assert_eq!(status, 200);
    }
    let r = get(&app, "/v1/jobs?limit=2", &[]).await;
    let link = header(&r, "link");
    let page: Value = r.json().await.expect("page");
    let jobs = page["jobs"].as_array().expect("jobs");
    assert_eq!(jobs.len(), 2);
    assert!(
        jobs.iter()
            .all(|j| j.get("spec").is_none() && j.get("result").is_none())
    );
    let cursor = page["next_cursor"].as_str().expect("cursor");
    assert_eq!(
        link,
        format!("</v1/jobs?limit=2&cursor={cursor}>; rel=\"next\"")
    );
    let url = link
        .trim_start_matches('<')
        .split('>')
        .next()
        .expect("url")
        .to_string();
    let (_, rest) = app.get(&url).await;
    assert_eq!(rest["jobs"].as_array().expect("jobs").len(), 1);
    assert!(rest["next_cursor"].is_null());
    let (_, full) = app.get("/v1/jobs?limit=2&include=spec").await;
    assert!(full["jobs"][0]["spec"]["kind"] == "time_history");
    app.stop().await;
}

/// Reads a Server-Sent Events stream until it ends (or `limit` passes): the
/// events' names and data.
async fn read_events(r: reqwest::Response, limit: Duration) -> Vec<(String, Value)> {
    let mut r = r;
    let deadline = Instant::now() + limit;
    let mut text = String::new();
    while Instant::now() < deadline {
        match tokio::time::timeout_at(deadline.into(), r.chunk()).await {
            Ok(Ok(Some(chunk))) => text.push_str(&String::from_utf8_lossy(&chunk)),
            _ => break,
        }
    }
    text.split("\n\n")
        .filter_map(|block| {
            let mut name = None;
            let mut data = None;
            for line in block.lines() {
                if let Some(n) = line.strip_prefix("event: ") {
                    name = Some(n.to_string());
                }
                if let Some(d) = line.strip_prefix("data: ") {
                    data = serde_json::from_str(d).ok();
                }
            }
            Some((name?, data?))
        })
        .collect()
}

#[tokio::test]
async fn events_stream_the_status_then_progress_then_the_finished_job() {
    let app = spawn_app("sse").await;
    let (_, job, _) = app.post("/v1/jobs", &spectrum(40)).await;
    let id = job["id"].as_str().expect("id").to_string();
    let started = Instant::now();
    let r = get(&app, &format!("/v1/jobs/{id}/events"), &[]).await;
    assert_eq!(r.status(), 200);
    assert!(header(&r, "content-type").starts_with("text/event-stream"));
    let events = read_events(r, Duration::from_secs(60)).await;
    let elapsed = started.elapsed().as_secs_f64();
    assert!(events.len() >= 2, "{events:?}");
    let (first, _) = &events[0];
    assert_eq!(first, "status");
    let (last, done) = events.last().expect("events");
    assert_eq!(last, "done");
    assert_eq!(done["status"], "succeeded");
    assert_eq!(done["spec"]["kind"], "spectrum");
    assert_eq!(events.iter().filter(|(n, _)| n == "done").count(), 1);
    // Progress only grows, at most 10 events a second.
    let progress: Vec<f64> = events
        .iter()
        .filter_map(|(_, d)| d["progress"].as_f64())
        .collect();
    assert!(progress.windows(2).all(|w| w[1] >= w[0]), "{progress:?}");
    assert!(
        events.len() as f64 <= 10.0 * elapsed + 2.0,
        "{} in {elapsed} s",
        events.len()
    );
    // A finished job: its final state at once, then the end.
    let r = get(&app, &format!("/v1/jobs/{id}/events"), &[]).await;
    let events = read_events(r, Duration::from_secs(5)).await;
    assert_eq!(events.len(), 1);
    assert_eq!(events[0].0, "done");
    // Resuming after the last event seen: a finished job still ends with
    // `done`, at once.
    let (_, finished) = app.get(&format!("/v1/jobs/{id}")).await;
    let etag = header(&get(&app, &format!("/v1/jobs/{id}"), &[]).await, "etag");
    let r = get(
        &app,
        &format!("/v1/jobs/{id}/events"),
        &[("last-event-id", etag.as_str())],
    )
    .await;
    let events = read_events(r, Duration::from_secs(5)).await;
    assert_eq!(events.len(), 1, "{events:?}");
    assert_eq!(events[0].0, "done");
    assert_eq!(events[0].1["status"], finished["status"]);
    let (status, problem) = app
        .get(&format!("/v1/jobs/{}/events", uuid::Uuid::now_v7()))
        .await;
    assert_eq!(status, 404, "{problem}");
    app.stop().await;
}

#[tokio::test]
async fn every_result_says_what_computed_it() {
    let app = spawn_app("provenance").await;
    let id = finished_time_history(&app).await;
    let (_, result) = app.get(&format!("/v1/jobs/{id}/result")).await;
    assert_eq!(result["engine"]["name"], "topple");
    assert_eq!(result["engine"]["version"], env!("CARGO_PKG_VERSION"));
    assert!(
        result["engine"]["numerics"]
            .as_str()
            .unwrap_or("")
            .starts_with("topple-engine/")
    );
    let (_, job, _) = app.post("/v1/jobs?wait=60", &spectrum(40)).await;
    assert_eq!(job["status"], "succeeded");
    assert_eq!(
        job["result"]["engine"]["name"], "topple",
        "assembled spectrum"
    );
    app.stop().await;
}

#[tokio::test]
async fn user_text_reaches_csv_as_text_never_as_a_formula() {
    let app = spawn_app("csv-injection").await;
    let evil = "=HYPERLINK(\"http://evil\",\"x\")";
    let spec = serde_json::json!({"kind": "forensic", "pulse": {"type": "one_sine"},
        "observations": [{"name": evil, "b": 0.5, "h": 1.5, "overturned": true}],
        "frequency_hz": [1.0], "a_p_g": {"from": 0.1, "to": 0.6}});
    let (status, job, _) = app.post("/v1/jobs?wait=60", &spec).await;
    assert_eq!(status, 200, "{job}");
    let id = job["id"].as_str().expect("id");
    let (status, _, csv) = app
        .get_text(&format!("/v1/jobs/{id}/result?format=csv"))
        .await;
    assert_eq!(status, 200);
    let rows: Vec<&str> = csv.lines().filter(|l| l.contains("HYPERLINK")).collect();
    assert!(!rows.is_empty(), "{csv}");
    for row in rows {
        let cells: Vec<&str> = row.splitn(3, ',').collect();
        assert!(
            cells[2].starts_with("\"'=HYPERLINK("),
            "the name must be inert text: {row}"
        );
    }
    app.stop().await;
}
