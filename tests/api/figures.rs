//! `GET /v1/jobs/{id}/plot.svg?window=t0,t1`: a time history's figure over a
//! span of time, validated like every query parameter, each window a
//! representation of its own (its own bytes and entity tag).

use std::sync::Arc;

use serde_json::Value;

use super::helpers::*;

async fn get(app: &TestApp, path: &str, if_none_match: Option<&str>) -> reqwest::Response {
    let mut req = app.client.get(app.url(path));
    if let Some(tag) = if_none_match {
        req = req.header("if-none-match", tag);
    }
    req.send().await.expect("request")
}

fn etag(r: &reqwest::Response) -> String {
    r.headers()
        .get("etag")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string()
}

/// A 400 problem naming the query parameter `window`.
async fn assert_window_refused(r: reqwest::Response, words: &str) {
    let body = crate::assert_problem(r, 400, Some("#/window")).await;
    assert_eq!(body["parameter"], "window", "{body}");
    let detail = body["detail"].as_str().unwrap_or("");
    assert!(detail.contains(words), "{words:?} not in {body}");
}

#[tokio::test]
async fn a_bad_window_is_400_naming_window() {
    let app = spawn_app("window-bad").await;
    let (status, job, _) = app.post("/v1/jobs?wait=20", &time_history(4.0)).await;
    assert_eq!(status, 200, "{job}");
    let id = job["id"].as_str().expect("id");
    for (window, words) in [
        ("1.2,0", "before the end"),
        ("1,1", "before the end"),
        ("0", "two numbers"),
        ("0,1,2", "two numbers"),
        ("a,b", "not a number"),
        ("0,inf", "finite"),
        ("NaN,1", "finite"),
        ("", "two numbers"),
        // Finite but unplottable: refused at once, never a renderer spinning.
        ("-1e308,1e308", "within"),
        ("0,1e-9", "at least"),
    ] {
        let r = get(
            &app,
            &format!("/v1/jobs/{id}/plot.svg?window={window}"),
            None,
        )
        .await;
        assert_window_refused(r, words).await;
    }
    // An unknown parameter names the one it takes.
    let r = get(&app, &format!("/v1/jobs/{id}/plot.svg?zoom=2"), None).await;
    assert_eq!(r.status().as_u16(), 400);
    let body: Value = r.json().await.expect("problem json");
    assert!(
        body["detail"]
            .as_str()
            .is_some_and(|d| d.contains("window")),
        "{body}"
    );
    // A window of a result without time axis.
    let (status, job, _) = app.post("/v1/jobs?wait=20", &friction()).await;
    assert_eq!(status, 200, "{job}");
    let friction_id = job["id"].as_str().expect("id");
    let r = get(
        &app,
        &format!("/v1/jobs/{friction_id}/plot.svg?window=0,1"),
        None,
    )
    .await;
    assert_window_refused(r, "time histories").await;
    app.stop().await;
}

#[tokio::test]
async fn each_window_is_its_own_figure_with_its_own_etag() {
    let app = spawn_app("window-etag").await;
    let (status, job, _) = app.post("/v1/jobs?wait=20", &time_history(4.0)).await;
    assert_eq!(status, 200, "{job}");
    let id = job["id"].as_str().expect("id");
    let key = job["key"].as_str().expect("key");
    let mut seen: Vec<(String, String)> = Vec::new();
    for query in ["", "?window=0,1.2", "?window=0.5,2", "?window=0,1.2000"] {
        let path = format!("/v1/jobs/{id}/plot.svg{query}");
        let r = get(&app, &path, None).await;
        assert_eq!(r.status(), 200, "{path}");
        let tag = etag(&r);
        assert!(tag.contains(&key[..32]), "{tag}");
        let body = r.text().await.expect("svg");
        assert!(body.starts_with("<svg"), "{path}");
        // The tag it was given answers 304 for the same window only.
        let again = get(&app, &path, Some(&tag)).await;
        assert_eq!(again.status(), 304, "{path}");
        seen.push((tag, body));
    }
    let (whole, first, second, same) = (&seen[0], &seen[1], &seen[2], &seen[3]);
    assert!(first.1.contains("t = 0–1.2 s (the history runs"));
    assert!(second.1.contains("t = 0.5–2 s"));
    for (a, b) in [(whole, first), (whole, second), (first, second)] {
        assert_ne!(a.0, b.0);
        assert_ne!(a.1, b.1);
    }
    // 1.2000 is 1.2: one window, one tag.
    assert_eq!(first, same);
    let r = get(
        &app,
        &format!("/v1/jobs/{id}/plot.svg?window=0,1.2"),
        Some(&whole.0),
    )
    .await;
    assert_eq!(
        r.status(),
        200,
        "the whole figure's tag is not the window's"
    );
    app.stop().await;
}

/// A stored result that does not read as a result of its kind (a document
/// of another engine) is served as it is in JSON, and its table and figure
/// are a 409 naming the field at fault, never a table or figure drawn from
/// a guess.
#[tokio::test]
async fn an_unreadable_result_is_409_naming_the_field_for_csv_and_svg() {
    let engine: topple::service::Engine = Arc::new(|job, control| {
        let mut doc = job.run(control)?;
        doc["rocked"] = serde_json::json!("maybe");
        Ok(doc)
    });
    let app = spawn_app_with_engine("unreadable", |_| {}, Some(engine)).await;
    let (status, job, _) = app.post("/v1/jobs?wait=20", &time_history(4.0)).await;
    assert_eq!(status, 200, "{job}");
    assert_eq!(job["status"], "succeeded", "{job}");
    let id = job["id"].as_str().expect("id");
    let json = get(&app, &format!("/v1/jobs/{id}/result"), None).await;
    assert_eq!(json.status(), 200);
    let doc: Value = json.json().await.expect("json");
    assert_eq!(doc["rocked"], "maybe");
    for path in [
        format!("/v1/jobs/{id}/result?format=csv"),
        format!("/v1/jobs/{id}/result?format=svg"),
        format!("/v1/jobs/{id}/plot.svg"),
    ] {
        let r = get(&app, &path, None).await;
        let body = crate::assert_problem(r, 409, Some("/rocked")).await;
        assert!(
            body["type"]
                .as_str()
                .unwrap_or("")
                .ends_with("result-unreadable"),
            "{body}"
        );
        let detail = body["detail"].as_str().unwrap_or("");
        assert!(
            detail.contains("time_history") && detail.contains("submit its spec again"),
            "{detail}"
        );
    }
    app.stop().await;
}
