//! The bad-input catalogue: one request the service must refuse per test.
//!
//! Every refusal is a specific 4xx answered as `application/problem+json`
//! whose `status`, `title` and `detail` are set, whose `pointer` (a JSON
//! pointer into the body, or `#/name` for a path or query parameter) or
//! `header` names what is wrong, and whose text reveals nothing of the
//! server's insides. After each refusal the server still answers `/healthz`.

use serde_json::{Value, json};

use crate::helpers::{TestApp, spawn_app, spawn_app_with, spectrum, time_history};

/// The default largest request body, bytes.
const MAX_BODY: usize = 1 << 20;

/// Text that must never reach a client: source paths, panic messages,
/// backtraces, SQL and driver names, Rust type descriptions.
const INTERNALS: [&str; 12] = [
    "src/",
    ".rs:",
    "panicked",
    "backtrace",
    "thread '",
    "SELECT",
    "INSERT",
    "UPDATE ",
    "sqlx",
    "sqlite",
    "struct ",
    "::",
];

/// What a problem names as the thing at fault.
#[derive(Clone, Copy, Debug)]
enum Names<'a> {
    /// A JSON pointer into the request body.
    Pointer(&'a str),
    /// A path or query parameter (`parameter`, and `pointer` as `#/name`).
    Parameter(&'a str),
    /// A request header.
    Header(&'a str),
    /// Nothing in the request body, parameters or headers.
    Nothing,
}

/// Checks the status, the content type, the body's `status`, `title` and
/// `detail`, and that nothing internal shows; returns the body.
async fn assert_problem(r: reqwest::Response, status: u16, title: &str) -> Value {
    assert_eq!(r.status().as_u16(), status, "status of {}", r.url());
    let ct = r
        .headers()
        .get("content-type")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string();
    assert_eq!(ct, "application/problem+json");
    let text = r.text().await.expect("problem body");
    let body: Value = serde_json::from_str(&text).expect("problem json");
    assert_eq!(body["status"], status, "{body}");
    assert_eq!(body["title"], title, "{body}");
    assert!(
        body["type"]
            .as_str()
            .is_some_and(|t| t.starts_with("https://")),
        "{body}"
    );
    let detail = body["detail"].as_str().unwrap_or("");
    assert!(!detail.trim().is_empty(), "empty detail: {body}");
    let lower = text.to_lowercase();
    for needle in INTERNALS {
        let found = if needle.chars().any(|c| c.is_ascii_uppercase()) {
            text.contains(needle)
        } else {
            lower.contains(needle)
        };
        assert!(!found, "{needle:?} leaks into {body}");
    }
    body
}

/// Checks which field the problem names.
fn assert_names(body: &Value, names: Names) {
    match names {
        Names::Pointer(p) => {
            assert_eq!(body["pointer"], p, "{body}");
            assert!(body.get("parameter").is_none(), "{body}");
        }
        Names::Parameter(name) => {
            assert_eq!(body["parameter"], name, "{body}");
            assert_eq!(body["pointer"], format!("#/{name}"), "{body}");
        }
        Names::Header(name) => assert_eq!(body["header"], name, "{body}"),
        Names::Nothing => {
            for field in ["pointer", "parameter", "header"] {
                assert!(body.get(field).is_none(), "{field} in {body}");
            }
        }
    }
}

/// The problem type ends with `kind`.
fn assert_kind(body: &Value, kind: &str) {
    assert!(
        body["type"]
            .as_str()
            .is_some_and(|t| t.ends_with(&format!("/{kind}"))),
        "expected type {kind}: {body}"
    );
}

/// The detail mentions every one of `words`.
fn assert_detail_mentions(body: &Value, words: &[&str]) {
    let detail = body["detail"].as_str().unwrap_or("");
    for w in words {
        assert!(detail.contains(w), "{w:?} not in detail of {body}");
    }
}

async fn assert_still_up(app: &TestApp) {
    let (status, body) = app.get("/healthz").await;
    assert_eq!(status, 200, "{body}");
    assert_eq!(body["status"], "ok");
}

/// POSTs `body` to /v1/jobs as JSON.
async fn post_raw(app: &TestApp, body: impl Into<reqwest::Body>) -> reqwest::Response {
    app.client
        .post(app.url("/v1/jobs"))
        .header("content-type", "application/json")
        .body(body)
        .send()
        .await
        .expect("request")
}

/// `spec` as JSON text with the value at `pointer` replaced by `token`, which
/// is written verbatim (so it can be anything, JSON or not).
fn with_raw(mut spec: Value, pointer: &str, token: &str) -> String {
    const MARK: &str = "__verbatim_token__";
    *spec.pointer_mut(pointer).expect("pointer exists") = json!(MARK);
    let text = spec.to_string();
    let quoted = format!("\"{MARK}\"");
    assert_eq!(text.matches(&quoted).count(), 1);
    text.replace(&quoted, token)
}

/// `spec` with the value at `pointer` set to `value`.
fn with(mut spec: Value, pointer: &str, value: Value) -> Value {
    *spec.pointer_mut(pointer).expect("pointer exists") = value;
    spec
}

/// Submits `body` and expects an invalid-spec problem with `status` naming
/// `pointer`, whose detail starts with that pointer and mentions `words`.
async fn refuse_spec(app: &TestApp, body: String, status: u16, pointer: &str, words: &[&str]) {
    let r = post_raw(app, body).await;
    let problem = assert_problem(r, status, "Invalid job spec").await;
    assert_kind(&problem, "invalid-spec");
    assert_names(&problem, Names::Pointer(pointer));
    let shown = if pointer.is_empty() { "/" } else { pointer };
    assert_detail_mentions(&problem, &[&format!("{shown}: ")]);
    assert_detail_mentions(&problem, words);
    assert_still_up(app).await;
}

/// A body of `n` bytes that is a job spec but for its size.
fn padded_spec(n: usize) -> String {
    let head = "{\"kind\":\"time_history\",\"pad\":\"";
    let tail = "\"}";
    let pad = n.saturating_sub(head.len() + tail.len());
    format!("{head}{}{tail}", "x".repeat(pad))
}

/// A too-large body is named as the document itself (or by its length).
fn assert_names_the_body(body: &Value) {
    let names_body = body["pointer"] == "" || body["header"] == "content-length";
    assert!(
        names_body,
        "a 413 should name the body (pointer \"\") or its content-length header: {body}"
    );
}

#[tokio::test]
async fn nan_token_is_422_naming_the_field() {
    let app = spawn_app("bi-nan").await;
    let body = with_raw(time_history(4.0), "/block/p", "NaN");
    refuse_spec(&app, body, 422, "/block/p", &["finite"]).await;
    app.stop().await;
}

#[tokio::test]
async fn infinity_token_is_422_naming_the_field() {
    let app = spawn_app("bi-inf").await;
    let body = with_raw(time_history(4.0), "/pulse/omega_ratio", "Infinity");
    refuse_spec(&app, body, 422, "/pulse/omega_ratio", &["finite"]).await;
    app.stop().await;
}

#[tokio::test]
async fn negative_infinity_token_is_422_naming_the_field() {
    let app = spawn_app("bi-ninf").await;
    let body = with_raw(time_history(4.0), "/pulse/a_p_alpha_g", "-Infinity");
    refuse_spec(&app, body, 422, "/pulse/a_p_alpha_g", &["finite"]).await;
    app.stop().await;
}

#[tokio::test]
async fn nan_as_a_string_is_422_naming_the_field() {
    let app = spawn_app("bi-nan-str").await;
    let body = with(time_history(4.0), "/block/alpha", json!("NaN")).to_string();
    refuse_spec(&app, body, 422, "/block/alpha", &["invalid type", "NaN"]).await;
    app.stop().await;
}

#[tokio::test]
async fn infinity_as_a_string_is_422_naming_the_field() {
    let app = spawn_app("bi-inf-str").await;
    for token in ["Infinity", "-Infinity"] {
        let body = with(time_history(4.0), "/block/p", json!(token)).to_string();
        refuse_spec(&app, body, 422, "/block/p", &["invalid type", token]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn huge_exponent_is_422_naming_the_field() {
    let app = spawn_app("bi-huge-exp").await;
    // Valid JSON numbers that no f64 holds: the field is as much at fault as
    // with NaN or Infinity, and is named the same way.
    for (pointer, token) in [("/block/p", "1e400"), ("/pulse/a_p_alpha_g", "-1e400")] {
        let body = with_raw(time_history(4.0), pointer, token);
        refuse_spec(&app, body, 422, pointer, &[]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn negative_p_is_422_naming_p() {
    let app = spawn_app("bi-neg-p").await;
    let body = with(time_history(4.0), "/block/p", json!(-2.14)).to_string();
    refuse_spec(&app, body, 422, "/block/p", &["positive", "-2.14"]).await;
    app.stop().await;
}

#[tokio::test]
async fn zero_p_is_422_naming_p() {
    let app = spawn_app("bi-zero-p").await;
    let body = with(time_history(4.0), "/block/p", json!(0.0)).to_string();
    refuse_spec(&app, body, 422, "/block/p", &["positive"]).await;
    app.stop().await;
}

#[tokio::test]
async fn alpha_not_positive_is_422_naming_alpha() {
    let app = spawn_app("bi-alpha-low").await;
    for alpha in [0.0, -0.1] {
        let body = with(time_history(4.0), "/block/alpha", json!(alpha)).to_string();
        refuse_spec(&app, body, 422, "/block/alpha", &["0 < alpha < pi/2"]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn alpha_at_or_above_half_pi_is_422_naming_alpha() {
    let app = spawn_app("bi-alpha-high").await;
    for alpha in [std::f64::consts::FRAC_PI_2, 2.0] {
        let body = with(time_history(4.0), "/block/alpha", json!(alpha)).to_string();
        refuse_spec(&app, body, 422, "/block/alpha", &["0 < alpha < pi/2"]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn negative_eta_is_422_naming_eta() {
    let app = spawn_app("bi-eta-neg").await;
    let body = with(time_history(4.0), "/block/eta", json!(-0.1)).to_string();
    refuse_spec(&app, body, 422, "/block/eta", &["0 <= eta <= 1", "-0.1"]).await;
    app.stop().await;
}

#[tokio::test]
async fn eta_above_one_is_422_naming_eta() {
    let app = spawn_app("bi-eta-high").await;
    let body = with(time_history(4.0), "/block/eta", json!(1.1)).to_string();
    refuse_spec(&app, body, 422, "/block/eta", &["0 <= eta <= 1", "1.1"]).await;
    app.stop().await;
}

#[tokio::test]
async fn two_amplitudes_are_422_naming_the_second() {
    let app = spawn_app("bi-two-amp").await;
    let mut spec = time_history(4.0);
    spec["pulse"]["a_p_g"] = json!(1.0);
    refuse_spec(
        &app,
        spec.to_string(),
        422,
        "/pulse/a_p_alpha_g",
        &["exactly one amplitude", "a_p_g"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn no_amplitude_is_422_naming_the_pulse() {
    let app = spawn_app("bi-no-amp").await;
    let mut spec = time_history(4.0);
    spec["pulse"]
        .as_object_mut()
        .expect("pulse")
        .remove("a_p_alpha_g");
    refuse_spec(
        &app,
        spec.to_string(),
        422,
        "/pulse",
        &["missing amplitude", "a_p_alpha_g"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn unknown_pulse_type_is_422_naming_type() {
    let app = spawn_app("bi-pulse-type").await;
    let body = with(time_history(4.0), "/pulse/type", json!("square")).to_string();
    refuse_spec(
        &app,
        body,
        422,
        "/pulse/type",
        &["unknown pulse type", "square", "one_sine"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn cn_pulse_with_zero_cycles_is_422_naming_n() {
    let app = spawn_app("bi-cn-n0").await;
    let mut spec = with(time_history(4.0), "/pulse/type", json!("cn"));
    spec["pulse"]["n"] = json!(0);
    refuse_spec(&app, spec.to_string(), 422, "/pulse/n", &["1 <= n"]).await;
    app.stop().await;
}

#[tokio::test]
async fn mavroeidis_papageorgiou_gamma_and_nu_are_422_naming_them() {
    let app = spawn_app("bi-mp-gamma").await;
    let mp = |gamma: Value| {
        let mut spec = with(
            time_history(4.0),
            "/pulse/type",
            json!("mavroeidis_papageorgiou"),
        );
        spec["formulation"] = json!("nonlinear");
        if !gamma.is_null() {
            spec["pulse"]["gamma"] = gamma;
        }
        spec
    };
    for gamma in [json!(1.0), json!(0.2), json!(21)] {
        refuse_spec(
            &app,
            mp(gamma).to_string(),
            422,
            "/pulse/gamma",
            &["1 < gamma <= 20"],
        )
        .await;
    }
    refuse_spec(
        &app,
        mp(Value::Null).to_string(),
        422,
        "/pulse/gamma",
        &["missing"],
    )
    .await;
    let mut other = time_history(4.0);
    other["pulse"]["gamma"] = json!(2.0);
    refuse_spec(
        &app,
        other.to_string(),
        422,
        "/pulse/gamma",
        &["mavroeidis_papageorgiou"],
    )
    .await;
    let mut other = time_history(4.0);
    other["pulse"]["nu"] = json!(0.5);
    refuse_spec(
        &app,
        other.to_string(),
        422,
        "/pulse/nu",
        &["mavroeidis_papageorgiou"],
    )
    .await;
    let mut exact = mp(json!(2.0));
    exact["formulation"] = json!("linear");
    exact["solver"] = json!({"method": "exact"});
    refuse_spec(
        &app,
        exact.to_string(),
        422,
        "/solver/method",
        &["sinusoidal"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn missing_block_is_422_naming_block() {
    let app = spawn_app("bi-no-block").await;
    let mut spec = time_history(4.0);
    spec.as_object_mut().expect("spec").remove("block");
    refuse_spec(&app, spec.to_string(), 422, "/block", &["missing"]).await;
    app.stop().await;
}

#[tokio::test]
async fn unknown_top_level_field_is_422_naming_it() {
    let app = spawn_app("bi-extra-top").await;
    let mut spec = time_history(4.0);
    spec["colour"] = json!("red");
    refuse_spec(
        &app,
        spec.to_string(),
        422,
        "/colour",
        &["unknown field", "colour"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn unknown_nested_field_is_422_naming_it() {
    let app = spawn_app("bi-extra-nested").await;
    let mut spec = time_history(4.0);
    spec["block"]["colour"] = json!("red");
    refuse_spec(
        &app,
        spec.to_string(),
        422,
        "/block/colour",
        &["unknown field", "colour"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn string_for_a_number_is_422_naming_the_field() {
    let app = spawn_app("bi-str-num").await;
    let body = with(time_history(4.0), "/block/p", json!("2.14")).to_string();
    refuse_spec(&app, body, 422, "/block/p", &["invalid type", "string"]).await;
    app.stop().await;
}

#[tokio::test]
async fn number_for_the_kind_is_422_naming_kind() {
    let app = spawn_app("bi-num-kind").await;
    let body = with(time_history(4.0), "/kind", json!(7)).to_string();
    refuse_spec(&app, body, 422, "/kind", &["must be a string"]).await;
    app.stop().await;
}

#[tokio::test]
async fn array_for_the_block_is_422_naming_block() {
    let app = spawn_app("bi-arr-block").await;
    let body = with(time_history(4.0), "/block", json!([0.25, 2.14, 0.9])).to_string();
    refuse_spec(&app, body, 422, "/block", &[]).await;
    // An array as long as the block has fields is no more an object.
    let seven = json!([0.25, 2.14, null, null, 0.9, null, null]);
    let body = with(time_history(4.0), "/block", seven).to_string();
    refuse_spec(&app, body, 422, "/block", &[]).await;
    app.stop().await;
}

#[tokio::test]
async fn deeply_nested_json_is_400_not_a_crash() {
    let app = spawn_app("bi-deep").await;
    for depth in [10_000, 100_000] {
        let nested = format!("{}{}", "[".repeat(depth), "]".repeat(depth));
        let body = with_raw(time_history(4.0), "/block/alpha", &nested);
        refuse_spec(&app, body, 400, "", &["not valid JSON", "recursion limit"]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn too_many_frequencies_under_the_body_limit_is_422_naming_omega_ratio() {
    let app = spawn_app("bi-many-freq").await;
    let list = vec![1.0; 200_000];
    let body = with(spectrum(3), "/omega_ratio", json!(list)).to_string();
    assert!(body.len() < MAX_BODY, "{} bytes", body.len());
    refuse_spec(
        &app,
        body,
        422,
        "/omega_ratio",
        &["between 1 and 10000 values"],
    )
    .await;
    app.stop().await;
}

#[tokio::test]
async fn frequency_list_over_the_body_limit_is_413() {
    let app = spawn_app("bi-freq-413").await;
    let list = vec![1.25; 300_000];
    let body = with(spectrum(3), "/omega_ratio", json!(list)).to_string();
    assert!(body.len() > MAX_BODY, "{} bytes", body.len());
    let r = post_raw(&app, body).await;
    let problem = assert_problem(r, 413, "Body too large").await;
    assert_kind(&problem, "body-too-large");
    assert_eq!(problem["limit"], "max_body_bytes");
    assert_detail_mentions(&problem, &["limit"]);
    assert_names_the_body(&problem);
    assert_still_up(&app).await;
    app.stop().await;
}

#[tokio::test]
async fn malformed_json_is_400_naming_the_document() {
    let app = spawn_app("bi-malformed").await;
    let text = time_history(4.0).to_string();
    for body in ["{not json".to_string(), text[..text.len() / 2].to_string()] {
        refuse_spec(&app, body, 400, "", &["not valid JSON"]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn text_plain_is_415_naming_content_type() {
    let app = spawn_app("bi-text-plain").await;
    let r = app
        .client
        .post(app.url("/v1/jobs"))
        .header("content-type", "text/plain")
        .body(time_history(4.0).to_string())
        .send()
        .await
        .expect("request");
    let problem = assert_problem(r, 415, "Unsupported media type").await;
    assert_kind(&problem, "unsupported-media-type");
    assert_names(&problem, Names::Header("content-type"));
    assert_detail_mentions(&problem, &["application/json", "text/plain"]);
    assert_still_up(&app).await;
    app.stop().await;
}

#[tokio::test]
async fn curls_default_form_type_and_no_type_are_read_as_json() {
    // `curl -d @spec.json` sends application/x-www-form-urlencoded.
    let app = spawn_app("bi-form").await;
    for ct in [Some("application/x-www-form-urlencoded"), None] {
        let mut r = app
            .client
            .post(app.url("/v1/jobs"))
            .body(time_history(4.0).to_string());
        if let Some(ct) = ct {
            r = r.header("content-type", ct);
        }
        let r = r.send().await.expect("request");
        assert!(r.status().is_success(), "{ct:?}: {}", r.status());
    }
    for ct in ["multipart/form-data; boundary=x", "application/xml"] {
        let r = app
            .client
            .post(app.url("/v1/jobs"))
            .header("content-type", ct)
            .body(time_history(4.0).to_string())
            .send()
            .await
            .expect("request");
        assert_eq!(r.status().as_u16(), 415, "{ct}");
    }
    app.stop().await;
}

#[tokio::test]
async fn empty_body_is_400_naming_the_document() {
    let app = spawn_app("bi-empty").await;
    refuse_spec(&app, String::new(), 400, "", &["not valid JSON"]).await;
    app.stop().await;
}

#[tokio::test]
async fn oversize_body_is_413() {
    let app = spawn_app("bi-oversize").await;
    let body = padded_spec(2 * MAX_BODY);
    let r = post_raw(&app, body).await;
    let problem = assert_problem(r, 413, "Body too large").await;
    assert_kind(&problem, "body-too-large");
    assert_eq!(problem["limit"], "max_body_bytes");
    assert_detail_mentions(&problem, &["limit"]);
    assert_names_the_body(&problem);
    assert_still_up(&app).await;
    app.stop().await;
}

/// A client that declares an over-limit body and waits for `100 Continue`
/// (as curl does for large uploads) gets the 413 at once, without sending a
/// byte of the body; so does one that does not wait.
#[tokio::test]
async fn over_limit_content_length_is_413_before_the_body() {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let app = spawn_app("bi-expect").await;
    let addr = app.base.trim_start_matches("http://").to_string();
    for expect in ["Expect: 100-continue\r\n", ""] {
        let mut socket = tokio::net::TcpStream::connect(&addr)
            .await
            .expect("connects");
        let head = format!(
            "POST /v1/jobs HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\n{expect}\r\n",
            50 * MAX_BODY
        );
        socket.write_all(head.as_bytes()).await.expect("sent");
        let mut answer = vec![0u8; 4096];
        let n = tokio::time::timeout(std::time::Duration::from_secs(5), socket.read(&mut answer))
            .await
            .expect("an answer without the body")
            .expect("reads");
        let text = String::from_utf8_lossy(&answer[..n]).to_string();
        assert!(text.starts_with("HTTP/1.1 413"), "{expect:?}: {text}");
        assert!(!text.contains("100 Continue"), "{text}");
        assert!(text.contains("max_body_bytes"), "{text}");
    }
    assert_still_up(&app).await;
    app.stop().await;
}

#[tokio::test]
async fn unknown_job_id_is_404_naming_id() {
    let app = spawn_app("bi-unknown-id").await;
    let missing = uuid::Uuid::now_v7();
    for (method, path) in [
        (reqwest::Method::GET, format!("/v1/jobs/{missing}")),
        (reqwest::Method::GET, format!("/v1/jobs/{missing}/result")),
        (reqwest::Method::DELETE, format!("/v1/jobs/{missing}")),
    ] {
        let r = app
            .client
            .request(method, app.url(&path))
            .send()
            .await
            .expect("request");
        let problem = assert_problem(r, 404, "Not found").await;
        assert_kind(&problem, "not-found");
        assert_detail_mentions(&problem, &[&missing.to_string()]);
        assert_names(&problem, Names::Parameter("id"));
        assert_still_up(&app).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn malformed_job_id_is_400_naming_id() {
    let app = spawn_app("bi-bad-id").await;
    for (method, path) in [
        (reqwest::Method::GET, "/v1/jobs/not-a-uuid"),
        (reqwest::Method::GET, "/v1/jobs/not-a-uuid/result"),
        (reqwest::Method::DELETE, "/v1/jobs/not-a-uuid"),
    ] {
        let r = app
            .client
            .request(method, app.url(path))
            .send()
            .await
            .expect("request");
        let problem = assert_problem(r, 400, "Bad request").await;
        assert_kind(&problem, "invalid-parameter");
        assert_names(&problem, Names::Parameter("id"));
        assert_detail_mentions(&problem, &["not-a-uuid", "UUID"]);
        assert_still_up(&app).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn unknown_route_is_404() {
    let app = spawn_app("bi-no-route").await;
    for path in ["/nowhere", "/v2/jobs", "/v1/jobs/a/b/c"] {
        let r = app.client.get(app.url(path)).send().await.expect("request");
        let problem = assert_problem(r, 404, "Not found").await;
        assert_kind(&problem, "not-found");
        assert_names(&problem, Names::Nothing);
        assert_detail_mentions(&problem, &["endpoint"]);
        assert_still_up(&app).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn put_on_jobs_is_405_with_allow() {
    let app = spawn_app("bi-put").await;
    let r = app
        .client
        .put(app.url("/v1/jobs"))
        .json(&time_history(4.0))
        .send()
        .await
        .expect("request");
    // A 405 names the methods it does take in `Allow` (RFC 9110, 15.5.6).
    let allow = r
        .headers()
        .get("allow")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string();
    let problem = assert_problem(r, 405, "Method not allowed").await;
    assert_kind(&problem, "method-not-allowed");
    assert_names(&problem, Names::Nothing);
    let allowed: Vec<&str> = allow.split(',').map(str::trim).collect();
    assert!(
        allowed.contains(&"GET") && allowed.contains(&"POST") && !allowed.contains(&"PUT"),
        "allow: {allow:?}"
    );
    assert_still_up(&app).await;
    app.stop().await;
}

#[tokio::test]
async fn spectrum_over_the_grid_limit_is_422_naming_the_limit() {
    let app = spawn_app_with("bi-limit", |c| c.limits.grid_points = 1000).await;
    let r = app
        .client
        .post(app.url("/v1/jobs"))
        .json(&spectrum(40))
        .send()
        .await
        .expect("request");
    let problem = assert_problem(r, 422, "Job exceeds a service limit").await;
    assert_kind(&problem, "limit-exceeded");
    assert_names(&problem, Names::Pointer("/omega_ratio"));
    assert_eq!(problem["limit"], "max_grid_points", "{problem}");
    assert_eq!(problem["maximum"], 1000.0, "{problem}");
    assert!(
        problem["value"].as_f64().is_some_and(|v| v > 1000.0),
        "{problem}"
    );
    assert_detail_mentions(&problem, &["/omega_ratio: ", "max_grid_points"]);
    assert_still_up(&app).await;
    app.stop().await;
}
