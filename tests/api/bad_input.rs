//! The bad-input catalogue: one request the service must refuse per test.
//!
//! Every refusal is a specific 4xx answered as `application/problem+json`
//! whose `status`, `title` and `detail` are set, whose `pointer` (a JSON
//! pointer into the body, or `#/name` for a path or query parameter) or
//! `header` names what is wrong, and whose text reveals nothing of the
//! server's insides, in a body of at most [`MAX_PROBLEM_BYTES`] however long
//! the input: a string of a megabyte, an array of ten million numbers, JSON
//! nested ten thousand deep. After each refusal the server still answers
//! `/healthz`.

use serde_json::{Value, json};

use crate::helpers::{TestApp, spawn_app, spawn_app_with, spectrum, time_history};

/// The default largest request body, bytes.
const MAX_BODY: usize = 1 << 20;

/// Longest problem body, bytes: a refusal quotes little of its input.
const MAX_PROBLEM_BYTES: usize = 2000;

/// A megabyte, the length of the long strings below.
const MB: usize = 1_000_000;

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

/// Checks the status, the content type, the body's length, its `status`,
/// `title` and `detail`, and that nothing internal shows; returns the body.
async fn assert_problem(r: reqwest::Response, status: u16, title: &str) -> Value {
    let what = r.url().to_string();
    let got = r.status().as_u16();
    let ct = r
        .headers()
        .get("content-type")
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_string();
    let text = r.text().await.expect("problem body");
    check_problem(&what, got, &ct, &text, status, Some(title))
}

/// [`assert_problem`] of an answer already read (`what` says which): `got`
/// with content type `ct` and body `text`; any title when `title` is `None`.
fn check_problem(
    what: &str,
    got: u16,
    ct: &str,
    text: &str,
    status: u16,
    title: Option<&str>,
) -> Value {
    assert_eq!(got, status, "status of {what}: {}", excerpt(text));
    assert_eq!(ct, "application/problem+json", "{what}: {}", excerpt(text));
    assert!(
        text.len() <= MAX_PROBLEM_BYTES,
        "a problem of {} bytes: {}",
        text.len(),
        excerpt(text)
    );
    let body: Value = serde_json::from_str(text).expect("problem json");
    assert_eq!(body["status"], status, "{body}");
    match title {
        Some(title) => assert_eq!(body["title"], title, "{body}"),
        None => assert!(
            body["title"].as_str().is_some_and(|t| !t.is_empty()),
            "{body}"
        ),
    }
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

/// The start of `text`, for a failure message.
fn excerpt(text: &str) -> String {
    let mut cut: String = text.chars().take(300).collect();
    if cut.len() < text.len() {
        cut.push_str(&format!("… ({} bytes)", text.len()));
    }
    cut
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
        refuse_spec(
            &app,
            body,
            400,
            "",
            &["not valid JSON", "recursion limit", "at most 128 levels"],
        )
        .await;
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

// Long strings, long arrays, deep nesting: of job specs and of record files.

/// A time history on a short record of samples.
fn on_record() -> Value {
    json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
           "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, -0.2, 0.1, 0.0]}})
}

/// A fragility campaign on a suite of one record of samples.
fn suite() -> Value {
    json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
           "ground_motions": [{"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, -0.2, 0.1, 0.0]}],
           "stripes": [0.3, 0.6], "samples": 64, "seed": 7})
}

/// `n` numbers as a JSON array, `[0,1,0,1,…]`: two bytes a number.
fn json_numbers(n: usize) -> String {
    let mut text = String::with_capacity(2 * n + 1);
    text.push('[');
    for k in 0..n {
        text.push(if k % 2 == 0 { '0' } else { '1' });
        text.push(',');
    }
    text.pop();
    text.push(']');
    text
}

/// `n` samples (g), one a line, 0 and 1 in turn: two bytes a sample.
fn sample_lines(n: usize) -> String {
    let mut text = "0\n1\n".repeat(n / 2);
    if n % 2 == 1 {
        text.push_str("0\n");
    }
    text
}

/// JSON nested `depth` deep: arrays around nothing, or objects around 1.
fn nested(depth: usize, objects: bool) -> String {
    if objects {
        format!("{}1{}", "{\"a\":".repeat(depth), "}".repeat(depth))
    } else {
        format!("{}{}", "[".repeat(depth), "]".repeat(depth))
    }
}

/// An answer read off the wire.
struct Answer {
    status: u16,
    content_type: String,
    body: String,
}

impl Answer {
    /// Checks the answer is a problem as [`assert_problem`] does.
    fn problem(&self, status: u16, title: Option<&str>) -> Value {
        check_problem(
            "the answer",
            self.status,
            &self.content_type,
            &self.body,
            status,
            title,
        )
    }
}

/// The answer in `raw` when it is all there: its head and, by its
/// Content-Length or its chunks, its whole body.
fn whole_answer(raw: &[u8]) -> Option<Answer> {
    let end = raw.windows(4).position(|w| w == b"\r\n\r\n")?;
    let head = String::from_utf8_lossy(&raw[..end]).to_string();
    let rest = &raw[end + 4..];
    let status = head.split_whitespace().nth(1)?.parse().ok()?;
    let header = |name: &str| {
        head.lines().skip(1).find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.trim()
                .eq_ignore_ascii_case(name)
                .then(|| v.trim().to_string())
        })
    };
    let body = if header("transfer-encoding").is_some_and(|v| v.contains("chunked")) {
        let mut body = Vec::new();
        let mut at = rest;
        loop {
            let line = at.windows(2).position(|w| w == b"\r\n")?;
            let size = std::str::from_utf8(&at[..line]).ok()?.split(';').next()?;
            let size = usize::from_str_radix(size.trim(), 16).ok()?;
            at = &at[line + 2..];
            if size == 0 {
                break body;
            }
            if at.len() < size + 2 {
                return None;
            }
            body.extend_from_slice(&at[..size]);
            at = &at[size + 2..];
        }
    } else {
        let length: usize = header("content-length")?.parse().ok()?;
        if rest.len() < length {
            return None;
        }
        rest[..length].to_vec()
    };
    Some(Answer {
        status,
        content_type: header("content-type").unwrap_or_default(),
        body: String::from_utf8(body).expect("a UTF-8 answer"),
    })
}

/// POSTs `body` to `path` over a connection of its own, with its
/// Content-Length, or without one in chunks of 64 KiB when `chunked`, reading
/// the answer while it sends: an answer that comes before the body is all
/// sent (a 413 for the declared length) is read all the same.
async fn post_wire(
    app: &TestApp,
    path: &str,
    content_type: &str,
    body: Vec<u8>,
    chunked: bool,
) -> Answer {
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let addr = app.base.trim_start_matches("http://").to_string();
    let socket = tokio::net::TcpStream::connect(&addr)
        .await
        .expect("connects");
    let (mut reader, mut writer) = socket.into_split();
    let length = if chunked {
        "Transfer-Encoding: chunked\r\n".to_string()
    } else {
        format!("Content-Length: {}\r\n", body.len())
    };
    let head = format!(
        "POST {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: {content_type}\r\n{length}Connection: close\r\n\r\n"
    );
    let sender = tokio::spawn(async move {
        writer.write_all(head.as_bytes()).await?;
        for piece in body.chunks(64 * 1024) {
            if chunked {
                writer
                    .write_all(format!("{:x}\r\n", piece.len()).as_bytes())
                    .await?;
                writer.write_all(piece).await?;
                writer.write_all(b"\r\n").await?;
            } else {
                writer.write_all(piece).await?;
            }
        }
        if chunked {
            writer.write_all(b"0\r\n\r\n").await?;
        }
        writer.flush().await?;
        // Kept open until the answer is read: a closed write side ends the
        // request.
        Ok::<_, std::io::Error>(writer)
    });
    let mut raw = Vec::new();
    let mut buffer = vec![0u8; 64 * 1024];
    let answer = tokio::time::timeout(std::time::Duration::from_secs(60), async {
        loop {
            if let Some(answer) = whole_answer(&raw) {
                return answer;
            }
            let n = reader.read(&mut buffer).await.expect("reads the answer");
            assert!(
                n > 0,
                "the connection closed before a whole answer: {}",
                excerpt(&String::from_utf8_lossy(&raw))
            );
            raw.extend_from_slice(&buffer[..n]);
        }
    })
    .await
    .expect("an answer within 60 s");
    sender.abort();
    answer
}

/// POSTs `body` to /v1/records`query` as text.
async fn upload(app: &TestApp, query: &str, body: impl Into<reqwest::Body>) -> reqwest::Response {
    app.client
        .post(app.url(&format!("/v1/records{query}")))
        .header("content-type", "text/plain")
        .body(body)
        .send()
        .await
        .expect("request")
}

/// Uploads `body` and expects a record problem with `status` naming
/// `names`, whose detail mentions `words`.
async fn refuse_record(
    app: &TestApp,
    query: &str,
    body: impl Into<reqwest::Body>,
    status: u16,
    names: Names<'_>,
    words: &[&str],
) -> Value {
    let r = upload(app, query, body).await;
    let problem = assert_problem(r, status, "Record not readable as given").await;
    assert_kind(&problem, "invalid-record");
    assert_names(&problem, names);
    assert_detail_mentions(&problem, words);
    assert_still_up(app).await;
    problem
}

/// Uploads `body` and expects it stored: returns the record.
async fn store_record(app: &TestApp, query: &str, body: impl Into<reqwest::Body>) -> Value {
    let r = upload(app, query, body).await;
    let status = r.status().as_u16();
    let text = r.text().await.expect("body");
    assert_eq!(status, 201, "{}", excerpt(&text));
    serde_json::from_str(&text).expect("a record")
}

#[tokio::test]
async fn a_megabyte_string_in_a_string_field_is_422_naming_the_field() {
    let app = spawn_app("bi-mb-string").await;
    let x = json!("x".repeat(MB));
    let mut with_solver = time_history(4.0);
    with_solver["solver"] = json!({"method": "dop853"});
    let named = |mut spec: Value, at: &str, slot: Value| {
        *spec.pointer_mut(at).expect("slot") = slot;
        spec
    };
    let cases = [
        (time_history(4.0), "/kind", "unknown kind"),
        (time_history(4.0), "/pulse/type", "unknown pulse type"),
        (time_history(4.0), "/formulation", "unknown formulation"),
        (with_solver, "/solver/method", "unknown method"),
        (on_record(), "/ground_motion/unit", "unknown unit"),
        (
            named(on_record(), "/ground_motion", json!({"record": "r"})),
            "/ground_motion/record",
            "record id",
        ),
        (
            named(on_record(), "/ground_motion", json!({"file": "f"})),
            "/ground_motion/file",
            "POST /v1/records",
        ),
        (
            named(suite(), "/ground_motions/0", json!({"record": "r"})),
            "/ground_motions/0/record",
            "record id",
        ),
        (
            named(suite(), "/ground_motions/0", json!({"file": "f"})),
            "/ground_motions/0/file",
            "POST /v1/records",
        ),
    ];
    for (spec, pointer, words) in cases {
        let body = with(spec, pointer, x.clone()).to_string();
        assert!(body.len() < MAX_BODY, "{} bytes", body.len());
        refuse_spec(&app, body, 422, pointer, &[words]).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn a_megabyte_string_for_a_number_an_array_or_the_spec_is_422_naming_it() {
    let app = spawn_app("bi-mb-type").await;
    let x = json!("x".repeat(MB));
    for (spec, pointer) in [
        (time_history(4.0), "/block/p"),
        (on_record(), "/ground_motion/dt"),
        (on_record(), "/ground_motion/acc"),
        (suite(), "/ground_motions"),
    ] {
        let body = with(spec, pointer, x.clone()).to_string();
        refuse_spec(&app, body, 422, pointer, &["invalid type", "string"]).await;
    }
    let body = with(on_record(), "/ground_motion", x.clone()).to_string();
    refuse_spec(&app, body, 422, "/ground_motion", &["JSON object"]).await;
    refuse_spec(&app, x.to_string(), 422, "", &["JSON object"]).await;
    app.stop().await;
}

#[tokio::test]
async fn a_megabyte_key_is_422_naming_it_in_a_bounded_pointer() {
    let app = spawn_app("bi-mb-key").await;
    let key = "k".repeat(MB);
    let by_id = with(
        on_record(),
        "/ground_motion",
        json!({"record": "0".repeat(32)}),
    );
    for (mut spec, at) in [
        (time_history(4.0), ""),
        (time_history(4.0), "/block"),
        (on_record(), "/ground_motion"),
        (by_id, "/ground_motion"),
        (suite(), "/ground_motions/0"),
    ] {
        spec.pointer_mut(at)
            .and_then(Value::as_object_mut)
            .expect("an object")
            .insert(key.clone(), json!(1));
        let r = post_raw(&app, spec.to_string()).await;
        let problem = assert_problem(r, 422, "Invalid job spec").await;
        assert_kind(&problem, "invalid-spec");
        let start = format!("{at}/kkkk");
        let pointer = problem["pointer"].as_str().unwrap_or("");
        assert!(pointer.starts_with(&start), "{problem}");
        assert!(pointer.chars().count() <= 201, "{problem}");
        let detail = problem["detail"].as_str().unwrap_or("");
        assert!(detail.starts_with(&start), "{problem}");
        assert_still_up(&app).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn ten_million_numbers_in_a_job_spec_are_413_naming_max_body_bytes() {
    let app = spawn_app("bi-1e7-numbers").await;
    let numbers = json_numbers(10_000_000);
    for (spec, pointer) in [(on_record(), "/ground_motion/acc"), (suite(), "/stripes")] {
        let body = with_raw(spec, pointer, &numbers).into_bytes();
        assert!(body.len() > 20 * MB);
        // With a Content-Length, and in chunks without one.
        for chunked in [false, true] {
            let answer =
                post_wire(&app, "/v1/jobs", "application/json", body.clone(), chunked).await;
            let problem = answer.problem(413, Some("Body too large"));
            assert_kind(&problem, "body-too-large");
            assert_eq!(problem["limit"], "max_body_bytes", "{problem}");
            assert_eq!(problem["maximum"], MAX_BODY as f64, "{problem}");
            assert_names_the_body(&problem);
            assert_still_up(&app).await;
        }
    }
    app.stop().await;
}

#[tokio::test]
async fn json_nested_ten_thousand_deep_is_400_wherever_it_is() {
    let app = spawn_app("bi-deep-anywhere").await;
    let by_id = with(on_record(), "/ground_motion", json!({"record": "r"}));
    for objects in [false, true] {
        let deep = nested(10_000, objects);
        for body in [
            deep.clone(),
            with_raw(time_history(4.0), "/block", &deep),
            with_raw(time_history(4.0), "/pulse/type", &deep),
            with_raw(on_record(), "/ground_motion", &deep),
            with_raw(on_record(), "/ground_motion/acc", &deep),
            with_raw(on_record(), "/ground_motion/acc/2", &deep),
            with_raw(by_id.clone(), "/ground_motion/record", &deep),
            with_raw(suite(), "/ground_motions/0", &deep),
        ] {
            refuse_spec(
                &app,
                body,
                400,
                "",
                &["not valid JSON", "recursion limit", "at most 128 levels"],
            )
            .await;
        }
    }
    app.stop().await;
}

/// Nesting within the parser's limit is read, and refused where it is.
#[tokio::test]
async fn json_nested_a_hundred_deep_is_422_naming_the_field() {
    let app = spawn_app("bi-deep-100").await;
    let by_id = with(on_record(), "/ground_motion", json!({"record": "r"}));
    for objects in [false, true] {
        let deep = nested(100, objects);
        let acc = if objects {
            "/ground_motion/acc"
        } else {
            "/ground_motion/acc/0"
        };
        for (spec, at, named) in [
            (on_record(), "/ground_motion/acc", acc),
            (on_record(), "/ground_motion/acc/2", "/ground_motion/acc/2"),
            (on_record(), "/ground_motion/unit", "/ground_motion/unit"),
            (
                by_id.clone(),
                "/ground_motion/record",
                "/ground_motion/record",
            ),
            (time_history(4.0), "/block/alpha", "/block/alpha"),
        ] {
            let body = with_raw(spec, at, &deep);
            refuse_spec(&app, body, 422, named, &[]).await;
        }
    }
    app.stop().await;
}

#[tokio::test]
async fn a_megabyte_record_file_of_letters_or_of_one_line_is_422_naming_what_to_change() {
    let app = spawn_app("bi-rec-mb").await;
    let query = "?unit=g&dt=0.01";
    refuse_record(
        &app,
        query,
        "x".repeat(MB),
        422,
        Names::Pointer(""),
        &["no rows of numbers"],
    )
    .await;
    // One line of 250,000 numbers: which column holds the acceleration?
    refuse_record(
        &app,
        query,
        "0.1 ".repeat(MB / 4),
        422,
        Names::Parameter("acc_column"),
        &["250000 columns"],
    )
    .await;
    // One number of a million digits.
    let digits = format!("{}\n0.1\n-0.2\n", "1".repeat(MB));
    refuse_record(&app, query, digits, 422, Names::Pointer(""), &["line 1"]).await;
    // A header row naming its acceleration column with a megabyte.
    let header = format!("time_s,{}\n0,0.1\n0.01,-0.2\n0.02,0.05\n", "h".repeat(MB));
    refuse_record(&app, "", header, 422, Names::Parameter("unit"), &["unit"]).await;
    let (status, list) = app.get("/v1/records").await;
    assert_eq!((status, &list["records"]), (200, &json!([])), "{list}");
    app.stop().await;
}

#[tokio::test]
async fn a_megabyte_header_line_is_read_past_and_names_are_cut_to_200_characters() {
    let app = spawn_app("bi-rec-header").await;
    let short = |rec: &Value| {
        let name = rec["name"].as_str().expect("a name");
        assert!(!name.is_empty() && name.chars().count() <= 200, "{rec}");
    };
    // A comment line of a megabyte above the samples.
    let text = format!("# {}\n0.1\n-0.2\n0.05\n-0.01\n", "c".repeat(MB));
    let rec = store_record(&app, "?unit=g&dt=0.01", text).await;
    assert_eq!(rec["samples"], 4, "{rec}");
    short(&rec);
    // A PEER AT2 file whose title line is a megabyte.
    let at2 = format!(
        "PEER NGA STRONG MOTION DATABASE RECORD\n{}\nACCELERATION TIME SERIES IN UNITS OF G\n\
         NPTS=    4, DT=   0.0100 SEC\n  0.1000000E+00 -0.3000000E+00  0.5000000E-01 -0.2000000E-01\n",
        "t".repeat(MB)
    );
    let rec = store_record(&app, "", at2).await;
    assert_eq!(
        (rec["format"].as_str(), rec["samples"].as_u64()),
        (Some("at2"), Some(4))
    );
    short(&rec);
    // A JSON record whose name is a megabyte.
    let body =
        json!({"name": "n".repeat(MB), "dt": 0.01, "unit": "g", "acc": [0.2, -0.1, 0.3, -0.05]});
    let rec = store_record(&app, "", body.to_string()).await;
    short(&rec);
    let (status, _, list) = app.get_text("/v1/records").await;
    assert_eq!(status, 200);
    assert!(list.len() < 10_000, "{} bytes", list.len());
    app.stop().await;
}

#[tokio::test]
async fn a_json_record_with_a_megabyte_string_is_422_naming_the_field() {
    let app = spawn_app("bi-rec-json-mb").await;
    let x = json!("x".repeat(MB));
    let base = json!({"dt": 0.01, "unit": "g", "acc": [0.2, -0.1, 0.3, -0.05]});
    for (pointer, words) in [
        ("/unit", "unknown unit"),
        ("/dt", "must be a number"),
        ("/acc", "array of numbers"),
        ("/acc/1", "must be a number"),
    ] {
        let body = with(base.clone(), pointer, x.clone()).to_string();
        refuse_record(&app, "", body, 422, Names::Pointer(pointer), &[words]).await;
    }
    let mut body = base.clone();
    body["k".repeat(MB)] = json!(1);
    let r = upload(&app, "", body.to_string()).await;
    let problem = assert_problem(r, 422, "Record not readable as given").await;
    let pointer = problem["pointer"].as_str().unwrap_or("");
    assert!(pointer.starts_with("/kkkk"), "{problem}");
    assert!(pointer.chars().count() <= 201, "{problem}");
    assert_detail_mentions(&problem, &["unknown field"]);
    assert_still_up(&app).await;
    app.stop().await;
}

#[tokio::test]
async fn a_json_record_nested_ten_thousand_deep_is_422_naming_the_field() {
    let app = spawn_app("bi-rec-deep").await;
    for objects in [false, true] {
        let deep = nested(10_000, objects);
        let acc = if objects { "/acc" } else { "/acc/0" };
        for (body, names) in [
            (format!(r#"{{"dt":0.01,"unit":"g","acc":{deep}}}"#), acc),
            (
                format!(r#"{{"dt":0.01,"unit":"g","acc":[0.1,{deep}]}}"#),
                "/acc/1",
            ),
            (
                format!(r#"{{"dt":{deep},"unit":"g","acc":[0.1,-0.2]}}"#),
                "/dt",
            ),
            (
                format!(r#"{{"dt":0.01,"unit":{deep},"acc":[0.1,-0.2]}}"#),
                "/unit",
            ),
            (
                format!(r#"{{"name":{deep},"dt":0.01,"unit":"g","acc":[0.1,-0.2]}}"#),
                "/name",
            ),
        ] {
            refuse_record(&app, "", body, 422, Names::Pointer(names), &[]).await;
        }
        // The nesting as the whole file.
        let whole = if objects { "/a" } else { "" };
        refuse_record(&app, "", deep, 422, Names::Pointer(whole), &[]).await;
    }
    app.stop().await;
}

/// Ten million samples, one a line (20 MB, within max_record_bytes): refused
/// by their count, with or without a Content-Length, and nothing stored.
#[tokio::test]
async fn ten_million_samples_within_max_record_bytes_are_422() {
    let app = spawn_app("bi-rec-1e7").await;
    let body = sample_lines(10_000_000).into_bytes();
    assert_eq!(body.len(), 20 * MB);
    for chunked in [false, true] {
        let answer = post_wire(
            &app,
            "/v1/records?unit=g&dt=0.01",
            "text/plain",
            body.clone(),
            chunked,
        )
        .await;
        let problem = answer.problem(422, None);
        assert_names(&problem, Names::Pointer(""));
        assert_detail_mentions(&problem, &["1000000"]);
        assert_still_up(&app).await;
    }
    let (status, list) = app.get("/v1/records").await;
    assert_eq!((status, &list["records"]), (200, &json!([])), "{list}");
    app.stop().await;
}

/// The same, refused naming the limit exceeded as a smaller count is.
#[tokio::test]
async fn ten_million_samples_are_422_naming_max_record_samples() {
    for samples_limit in [None, Some(5000)] {
        let app = spawn_app_with("bi-rec-1e7-limit", |c| {
            if let Some(n) = samples_limit {
                c.max_record_samples = n;
            }
        })
        .await;
        let maximum = samples_limit.unwrap_or(1_000_000);
        let r = upload(&app, "?unit=g&dt=0.01", sample_lines(10_000_000)).await;
        let problem = assert_problem(r, 422, "Record exceeds a service limit").await;
        assert_kind(&problem, "limit-exceeded");
        assert_eq!(problem["limit"], "max_record_samples", "{problem}");
        assert_eq!(problem["maximum"], maximum as f64, "{problem}");
        assert_still_up(&app).await;
        app.stop().await;
    }
}

#[tokio::test]
async fn a_record_of_max_record_samples_is_stored_and_one_more_is_422_naming_the_limit() {
    let app = spawn_app_with("bi-rec-5000", |c| c.max_record_samples = 5000).await;
    let rec = store_record(&app, "?unit=g&dt=0.01", sample_lines(5000)).await;
    assert_eq!(rec["samples"], 5000, "{rec}");
    let acc: Vec<f64> = (0..5001).map(|k| (k % 3) as f64 * 0.1).collect();
    for (query, body) in [
        ("?unit=g&dt=0.01", sample_lines(5001)),
        ("", json!({"dt": 0.01, "unit": "g", "acc": acc}).to_string()),
    ] {
        let r = upload(&app, query, body).await;
        let problem = assert_problem(r, 422, "Record exceeds a service limit").await;
        assert_kind(&problem, "limit-exceeded");
        assert_names(&problem, Names::Pointer(""));
        assert_eq!(problem["limit"], "max_record_samples", "{problem}");
        assert_eq!(problem["maximum"], 5000.0, "{problem}");
        assert_eq!(problem["value"], 5001.0, "{problem}");
        assert_detail_mentions(&problem, &["max_record_samples"]);
        assert_still_up(&app).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn a_record_over_max_record_bytes_is_413_naming_the_limit_with_or_without_a_length() {
    let app = spawn_app_with("bi-rec-bytes", |c| c.max_record_bytes = MB).await;
    let one_over = format!("{}1", "0\n".repeat(MB / 2));
    assert_eq!(one_over.len(), MB + 1);
    for body in [sample_lines(10_000_000), one_over] {
        for chunked in [false, true] {
            let answer = post_wire(
                &app,
                "/v1/records?unit=g&dt=0.01",
                "text/plain",
                body.clone().into_bytes(),
                chunked,
            )
            .await;
            let problem = answer.problem(413, Some("Body too large"));
            assert_kind(&problem, "body-too-large");
            assert_eq!(problem["limit"], "max_record_bytes", "{problem}");
            assert_eq!(problem["maximum"], MB as f64, "{problem}");
            assert_detail_mentions(&problem, &["max_record_bytes"]);
            assert_names_the_body(&problem);
            assert_still_up(&app).await;
        }
    }
    // A file of exactly max_record_bytes is read.
    let rec = store_record(&app, "?unit=g&dt=0.01", sample_lines(MB / 2)).await;
    assert_eq!(rec["samples"], MB / 2, "{rec}");
    app.stop().await;
}

#[tokio::test]
async fn long_record_query_values_and_ids_are_400_naming_them() {
    let app = spawn_app("bi-rec-query").await;
    let long = "q".repeat(60_000);
    for (query, name) in [
        (format!("?name={}", "n".repeat(201)), "name"),
        (format!("?unit={long}"), "unit"),
        (format!("?format={long}"), "format"),
        (format!("?time_column={long}"), "time_column"),
        (format!("?acc_column={long}"), "acc_column"),
        (format!("?dt={}", "1".repeat(60_000)), "dt"),
    ] {
        let r = upload(&app, &query, "0.1\n-0.2\n0.05\n").await;
        let problem = assert_problem(r, 400, "Bad request").await;
        assert_kind(&problem, "invalid-parameter");
        assert_names(&problem, Names::Parameter(name));
        assert_still_up(&app).await;
    }
    let r = upload(&app, &format!("?{long}=1"), "0.1\n-0.2\n0.05\n").await;
    let problem = assert_problem(r, 400, "Bad request").await;
    assert!(
        problem["parameter"]
            .as_str()
            .is_some_and(|p| p.starts_with("qqqq")),
        "{problem}"
    );
    for method in [reqwest::Method::GET, reqwest::Method::DELETE] {
        let r = app
            .client
            .request(method, app.url(&format!("/v1/records/{long}")))
            .send()
            .await
            .expect("request");
        let problem = assert_problem(r, 400, "Bad request").await;
        assert_names(&problem, Names::Parameter("id"));
        assert_detail_mentions(&problem, &["record id"]);
    }
    let r = app
        .client
        .get(app.url(&format!("/v1/records?cursor={long}")))
        .send()
        .await
        .expect("request");
    let problem = assert_problem(r, 400, "Bad request").await;
    assert_names(&problem, Names::Parameter("cursor"));
    assert_still_up(&app).await;
    app.stop().await;
}

/// A query value that is not a boolean is named as the parameter it is.
#[tokio::test]
async fn a_bad_boolean_in_the_query_is_400_naming_its_parameter() {
    let app = spawn_app("bi-rec-bool").await;
    let r = upload(&app, "?allow_large_pga=maybe", "0.1\n-0.2\n0.05\n").await;
    let problem = assert_problem(r, 400, "Bad request").await;
    assert_names(&problem, Names::Parameter("allow_large_pga"));
    app.stop().await;
}

/// A refusal quotes at most 40 characters of a value it is about, and says
/// what is wrong however long the value or the key.
#[tokio::test]
async fn refusals_quote_at_most_40_characters_of_the_input() {
    let app = spawn_app("bi-quote-40").await;
    let x = "x".repeat(MB);
    let quotes_little = |problem: &Value| {
        let detail = problem["detail"].as_str().unwrap_or("");
        assert!(!detail.contains(&"x".repeat(41)), "{problem}");
    };
    for (spec, pointer) in [
        (time_history(4.0), "/kind"),
        (time_history(4.0), "/pulse/type"),
        (time_history(4.0), "/formulation"),
        (on_record(), "/ground_motion/unit"),
    ] {
        let r = post_raw(&app, with(spec, pointer, json!(x)).to_string()).await;
        quotes_little(&assert_problem(r, 422, "Invalid job spec").await);
    }
    let mut spec = time_history(4.0);
    spec["block"][x.as_str()] = json!(1);
    let r = post_raw(&app, spec.to_string()).await;
    let problem = assert_problem(r, 422, "Invalid job spec").await;
    quotes_little(&problem);
    assert_detail_mentions(&problem, &["unknown field"]);
    let base = json!({"dt": 0.01, "unit": "g", "acc": [0.2, -0.1, 0.3, -0.05]});
    for body in [
        with(base.clone(), "/unit", json!(x)).to_string(),
        with(base.clone(), "/acc", json!(x)).to_string(),
        format!("time_s,{x}\n0,0.1\n0.01,-0.2\n"),
        format!("x{x}1\n0.1\n-0.2\n"),
    ] {
        let r = upload(&app, "?dt=0.01", body).await;
        quotes_little(&assert_problem(r, 422, "Record not readable as given").await);
    }
    let r = upload(&app, &format!("?format={}", "x".repeat(60_000)), "0.1\n").await;
    quotes_little(&assert_problem(r, 400, "Bad request").await);
    app.stop().await;
}

/// A request line over 64 KiB is refused by the HTTP layer before any route
/// (hyper answers 414 with an empty body, not a problem), and the server
/// stays up.
#[tokio::test]
async fn a_request_line_over_64_kib_is_414_and_the_server_stays_up() {
    let app = spawn_app("bi-long-uri").await;
    let path = format!("/v1/records?unit={}", "g".repeat(70_000));
    let answer = post_wire(&app, &path, "text/plain", b"0.1\n-0.2\n".to_vec(), false).await;
    assert_eq!(answer.status, 414);
    assert_still_up(&app).await;
    app.stop().await;
}

/// A query parameter without a name (`?=true`) is unknown, and named so.
#[tokio::test]
async fn a_query_parameter_with_no_name_is_400_naming_it() {
    let app = spawn_app("bi-empty-param").await;
    let r = upload(&app, "?=true", "0.1\n-0.2\n0.05\n").await;
    let problem = assert_problem(r, 400, "Bad request").await;
    assert_eq!(problem["parameter"], "", "{problem}");
    assert_detail_mentions(&problem, &["unknown query parameter"]);
    assert_still_up(&app).await;
    app.stop().await;
}
