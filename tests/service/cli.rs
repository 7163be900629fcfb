//! The `topple` binary end to end: result documents on stdout, one-line errors
//! naming the offending field on stderr.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde_json::{Value, json};

const VALID: &str = r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14,"eta":0.9,"mu":0.7},"pulse":{"type":"one_sine","omega_ratio":5.0,"a_p_alpha_g":4.0},"formulation":"linear","solver":{"method":"exact"},"outputs":{"series":50,"reactions":true}}"#;

const VALID_NO_SERIES: &str = r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14,"eta":0.9,"mu":0.7},"pulse":{"type":"one_sine","omega_ratio":5.0,"a_p_alpha_g":4.0},"formulation":"linear","solver":{"method":"exact"}}"#;

fn topple() -> Command {
    Command::new(env!("CARGO_BIN_EXE_topple"))
}

/// A fresh path in the system temp dir, unique per process and call.
fn temp_path(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!("topple-cli-test-{}-{n}-{name}", std::process::id()))
}

/// Writes `spec` to a unique temp file and runs `topple run <file> <extra>`.
fn run_file(spec: &str, extra: &[&str]) -> Output {
    let path = temp_path("spec.json");
    std::fs::write(&path, spec).expect("write spec");
    let out = topple()
        .arg("run")
        .arg(&path)
        .args(extra)
        .output()
        .expect("run topple");
    let _ = std::fs::remove_file(&path);
    out
}

/// Runs `topple run -` with `spec` on standard input.
fn run_stdin(spec: &str) -> Output {
    let mut child = topple()
        .args(["run", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn topple");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(spec.as_bytes())
        .expect("write stdin");
    child.wait_with_output().expect("wait topple")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn result_json(out: &Output) -> Value {
    assert!(
        out.status.success(),
        "exit {:?}, stderr: {}",
        out.status,
        stderr(out)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON document")
}

/// A failed run: non-zero exit (not a signal), no panic, nothing on stdout and
/// exactly one non-empty line on stderr, which is returned.
fn one_line_failure(out: &Output) -> String {
    let err = stderr(out);
    eprintln!("exit {:?}; stderr: {err:?}", out.status.code());
    let code = out.status.code().expect("exited, not killed by a signal");
    assert_ne!(code, 0, "must fail");
    assert!(!err.contains("panicked"), "panicked: {err}");
    assert!(
        out.stdout.is_empty(),
        "nothing on stdout on failure, got {}",
        String::from_utf8_lossy(&out.stdout)
    );
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "exactly one line on stderr: {err:?}");
    assert!(!lines[0].trim().is_empty(), "the line is not empty");
    lines[0].to_string()
}

/// The spec is refused by both ways in (file and stdin) with one line on
/// stderr naming `pointer` (followed by ':' so "/pulse" does not match
/// "/pulse/type").
fn assert_rejected_at(spec: &str, pointer: &str) -> String {
    let by_file = one_line_failure(&run_file(spec, &[]));
    let by_stdin = one_line_failure(&run_stdin(spec));
    assert_eq!(by_file, by_stdin, "same message from a file and stdin");
    assert!(
        by_file.contains(&format!("{pointer}:")),
        "the error must name {pointer}: {by_file}"
    );
    by_file
}

fn spec_with(block: &str, pulse: &str, rest: &str) -> String {
    format!(r#"{{"kind":"time_history","block":{block},"pulse":{pulse}{rest}}}"#)
}

const BLOCK: &str = r#"{"alpha":0.25,"p":2.14}"#;
const PULSE: &str = r#"{"type":"one_sine","omega_ratio":5.0,"a_p_alpha_g":4.0}"#;

// ---------------------------------------------------------------- valid runs

#[test]
fn valid_spec_file_prints_a_complete_result_document() {
    let doc = result_json(&run_file(VALID, &[]));
    assert!(doc["overturned"].is_boolean(), "{doc}");
    assert!(doc["rocked"].is_boolean());
    assert_eq!(doc["rocked"], true, "4 alpha g rocks the block");
    assert!(doc["mode"].is_null() || doc["mode"].is_u64());
    if doc["overturned"] == true {
        assert!(matches!(doc["mode"].as_u64(), Some(1 | 2)));
    }
    let impacts = doc["impacts"].as_array().expect("impacts is an array");
    assert_eq!(
        impacts.len() as u64,
        doc["impact_count"].as_u64().expect("impact_count")
    );
    for i in impacts {
        for key in ["t", "theta_dot_before", "theta_dot_after"] {
            assert!(i[key].as_f64().is_some_and(f64::is_finite), "{key} in {i}");
        }
    }
    let peak = doc["peak_theta_over_alpha"].as_f64().expect("peak");
    assert!(peak.is_finite() && peak >= 0.0);
    let demand = doc["peak_friction_demand"]
        .as_f64()
        .expect("reactions asked for: peak_friction_demand is a number");
    assert!(demand.is_finite() && demand >= 0.0);

    let n = doc["numerics"].as_object().expect("numerics is an object");
    for key in [
        "method",
        "rtol",
        "atol",
        "steps_accepted",
        "steps_rejected",
        "rhs_evaluations",
        "events",
        "error_estimate",
        "wall_time_s",
    ] {
        assert!(n.contains_key(key), "numerics.{key} missing: {n:?}");
    }
    assert_eq!(n["method"], "exact");
    assert!(
        n["rtol"].is_null() && n["atol"].is_null(),
        "no tolerances for exact"
    );
    for key in [
        "steps_accepted",
        "steps_rejected",
        "rhs_evaluations",
        "events",
    ] {
        assert!(n[key].is_u64(), "numerics.{key} is a count: {}", n[key]);
    }
    assert!(n["steps_accepted"].as_u64() > Some(0));
    assert!(n["events"].as_u64() >= Some(1));
    for key in ["error_estimate", "wall_time_s"] {
        let v = n[key].as_f64().expect(key);
        assert!(v.is_finite() && v >= 0.0, "numerics.{key} = {v}");
    }
}

#[test]
fn series_of_50_points_has_50_samples_in_every_column() {
    let doc = result_json(&run_file(VALID, &[]));
    let series = doc["series"].as_object().expect("series asked for");
    for key in [
        "t",
        "theta",
        "theta_dot",
        "ground_acceleration",
        "fx_over_fz",
    ] {
        let col = series[key].as_array().unwrap_or_else(|| panic!("{key}"));
        assert_eq!(col.len(), 50, "series.{key}");
        // f_x/f_z is null where f_z ≤ 0: here late in the fall of the
        // overturning block, never before a number.
        let numbers = if key == "fx_over_fz" {
            col.iter().take_while(|v| !v.is_null()).count()
        } else {
            col.len()
        };
        assert!(numbers > 40, "series.{key}: {numbers} numbers");
        assert!(
            col[..numbers]
                .iter()
                .all(|v| v.as_f64().is_some_and(f64::is_finite)),
            "series.{key} all finite"
        );
        assert!(col[numbers..].iter().all(Value::is_null), "series.{key}");
    }
    let t: Vec<f64> = series["t"]
        .as_array()
        .expect("t")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect();
    assert_eq!(t[0], 0.0);
    assert!(
        t.windows(2).all(|w| w[1] > w[0]),
        "uniform increasing times"
    );
    let end = doc["end_time"].as_f64().expect("end_time");
    assert!(
        (t[49] - end).abs() <= 1e-12 * end,
        "series spans [0, end_time]"
    );
}

#[test]
fn without_outputs_series_the_result_has_no_series_key() {
    let doc = result_json(&run_file(VALID_NO_SERIES, &[]));
    assert!(doc.get("series").is_none(), "unexpected series: {doc}");
}

#[test]
fn without_reactions_the_result_has_no_friction_demand_and_no_reaction_series() {
    let spec = VALID.replace(r#""reactions":true"#, r#""reactions":false"#);
    let doc = result_json(&run_file(&spec, &[]));
    assert!(doc["peak_friction_demand"].is_null(), "{doc}");
    assert!(doc["series"].get("fx_over_fz").is_none());
    assert_eq!(doc["series"]["t"].as_array().map(Vec::len), Some(50));
}

#[test]
fn runge_kutta_job_reports_its_tolerances_and_cost() {
    let spec = spec_with(
        BLOCK,
        PULSE,
        r#","formulation":"nonlinear","solver":{"method":"dop853","rtol":1e-8,"atol":1e-10}"#,
    );
    let doc = result_json(&run_file(&spec, &[]));
    let n = &doc["numerics"];
    assert_eq!(n["method"], "dop853");
    assert_eq!(n["rtol"].as_f64(), Some(1e-8));
    assert_eq!(n["atol"].as_f64(), Some(1e-10));
    assert!(n["steps_accepted"].as_u64() > Some(0));
    assert!(n["rhs_evaluations"].as_u64() > Some(0));
}

#[test]
fn spec_read_from_stdin_gives_the_same_result_as_from_a_file() {
    let from_stdin = result_json(&run_stdin(VALID));
    let from_file = result_json(&run_file(VALID, &[]));
    let strip = |mut v: Value| {
        v["numerics"]
            .as_object_mut()
            .expect("numerics")
            .remove("wall_time_s");
        v
    };
    assert_eq!(strip(from_stdin), strip(from_file));
}

#[test]
fn plot_option_writes_an_svg_file_when_a_series_is_asked_for() {
    let svg = temp_path("out.svg");
    let svg_arg = svg.to_str().expect("utf-8 temp path");
    let doc = result_json(&run_file(VALID, &["--plot", svg_arg]));
    assert!(doc["series"].is_object());
    let text = std::fs::read_to_string(&svg).expect("the SVG file exists");
    let _ = std::fs::remove_file(&svg);
    let head = text.trim_start();
    assert!(
        head.starts_with("<svg") || head.starts_with("<?xml"),
        "not an SVG: {}",
        &head[..head.len().min(80)]
    );
    assert!(text.contains("</svg>"), "complete SVG document");
}

#[test]
fn plot_option_without_a_series_draws_what_there_is_and_says_how_to_get_more() {
    let svg = temp_path("none.svg");
    let svg_arg = svg.to_str().expect("utf-8 temp path");
    let result = result_json(&run_file(VALID_NO_SERIES, &["--plot", svg_arg]));
    assert!(result.get("series").is_none());
    let text = std::fs::read_to_string(&svg).expect("SVG written");
    assert!(text.contains("</svg>"), "complete SVG document");
    // The figure names the option that adds the full series.
    assert!(text.contains("outputs"), "hint at outputs.series");
}

// ------------------------------------------------------------- invalid specs

#[test]
fn nan_and_infinity_literals_are_refused_at_their_field() {
    // JSON has no NaN or Infinity; users still type them. The error names the
    // field that holds them.
    for (block, pulse, pointer) in [
        (
            r#"{"alpha":NaN,"p":2.14}"#,
            PULSE.to_string(),
            "/block/alpha",
        ),
        (
            r#"{"alpha":0.25,"p":2.14}"#,
            r#"{"type":"one_sine","omega_ratio":-Infinity,"a_p_alpha_g":4.0}"#.to_string(),
            "/pulse/omega_ratio",
        ),
    ] {
        let spec = spec_with(block, &pulse, "");
        let by_file = one_line_failure(&run_file(&spec, &[]));
        let by_stdin = one_line_failure(&run_stdin(&spec));
        assert_eq!(by_file, by_stdin);
        assert!(
            by_file.contains(&format!("{pointer}:")),
            "names {pointer}: {by_file}"
        );
        assert!(by_file.contains("finite"), "says why: {by_file}");
    }
}

#[test]
fn nan_string_as_alpha_is_refused_at_block_alpha() {
    assert_rejected_at(
        &spec_with(r#"{"alpha":"NaN","p":2.14}"#, PULSE, ""),
        "/block/alpha",
    );
}

#[test]
fn alpha_of_1_6_rad_beyond_half_pi_is_refused_at_block_alpha() {
    assert_rejected_at(
        &spec_with(r#"{"alpha":1.6,"p":2.14}"#, PULSE, ""),
        "/block/alpha",
    );
}

#[test]
fn alpha_of_exactly_half_pi_is_refused_at_block_alpha() {
    let block = format!(r#"{{"alpha":{},"p":2.14}}"#, std::f64::consts::FRAC_PI_2);
    assert_rejected_at(&spec_with(&block, PULSE, ""), "/block/alpha");
}

#[test]
fn restitution_above_one_is_refused_at_block_eta() {
    assert_rejected_at(
        &spec_with(r#"{"alpha":0.25,"p":2.14,"eta":1.01}"#, PULSE, ""),
        "/block/eta",
    );
}

#[test]
fn two_amplitudes_are_refused_at_the_second_one() {
    let line = assert_rejected_at(
        &spec_with(
            BLOCK,
            r#"{"type":"one_sine","omega_ratio":5.0,"a_p":3.0,"a_p_g":0.5}"#,
            "",
        ),
        "/pulse/a_p_g",
    );
    assert!(line.contains("a_p"), "{line}");
}

#[test]
fn two_frequencies_are_refused_at_one_of_them() {
    let spec = spec_with(
        BLOCK,
        r#"{"type":"one_sine","omega_p":10.0,"omega_ratio":5.0,"a_p_g":0.5}"#,
        "",
    );
    let line = one_line_failure(&run_file(&spec, &[]));
    assert!(
        line.contains("/pulse/omega_p:") || line.contains("/pulse/omega_ratio:"),
        "names one of the two frequencies: {line}"
    );
    assert_eq!(line, one_line_failure(&run_stdin(&spec)));
}

#[test]
fn unknown_pulse_type_is_refused_at_pulse_type() {
    let line = assert_rejected_at(
        &spec_with(
            BLOCK,
            r#"{"type":"triangle","omega_ratio":5.0,"a_p_g":0.5}"#,
            "",
        ),
        "/pulse/type",
    );
    assert!(line.contains("triangle"), "quotes the bad value: {line}");
}

#[test]
fn missing_block_is_refused_at_block() {
    assert_rejected_at(
        &format!(r#"{{"kind":"time_history","pulse":{PULSE}}}"#),
        "/block",
    );
}

#[test]
fn empty_block_is_refused_at_block() {
    assert_rejected_at(&spec_with("{}", PULSE, ""), "/block");
}

#[test]
fn missing_pulse_is_refused_at_pulse() {
    assert_rejected_at(
        &format!(r#"{{"kind":"time_history","block":{BLOCK}}}"#),
        "/pulse",
    );
}

#[test]
fn missing_amplitude_is_refused_at_pulse_and_lists_the_choices() {
    let line = assert_rejected_at(
        &spec_with(BLOCK, r#"{"type":"one_sine","omega_ratio":5.0}"#, ""),
        "/pulse",
    );
    assert!(
        line.contains("a_p_g") && line.contains("a_p_alpha_g"),
        "{line}"
    );
}

#[test]
fn unknown_block_field_is_refused_at_that_field() {
    assert_rejected_at(
        &spec_with(r#"{"alpha":0.25,"p":2.14,"colour":"red"}"#, PULSE, ""),
        "/block/colour",
    );
}

#[test]
fn unknown_top_level_field_is_refused_at_that_field() {
    assert_rejected_at(&spec_with(BLOCK, PULSE, r#","speed":1"#), "/speed");
}

#[test]
fn exact_solver_with_nonlinear_formulation_is_refused_at_solver_method() {
    assert_rejected_at(
        &spec_with(
            BLOCK,
            PULSE,
            r#","formulation":"nonlinear","solver":{"method":"exact"}"#,
        ),
        "/solver/method",
    );
}

#[test]
fn exact_solver_with_the_default_nonlinear_formulation_is_refused_at_solver_method() {
    assert_rejected_at(
        &spec_with(BLOCK, PULSE, r#","solver":{"method":"exact"}"#),
        "/solver/method",
    );
}

#[test]
fn geometry_mixed_with_parameters_is_refused_at_block() {
    let line = assert_rejected_at(
        &spec_with(r#"{"alpha":0.25,"p":2.14,"b":0.5,"h":2.0}"#, PULSE, ""),
        "/block",
    );
    assert!(line.contains("not both"), "{line}");
}

#[test]
fn nonexistent_spec_file_fails_with_one_line_naming_the_path() {
    let path = temp_path("does-not-exist.json");
    let out = topple().arg("run").arg(&path).output().expect("run topple");
    let line = one_line_failure(&out);
    assert!(
        line.contains(path.to_str().expect("utf-8")),
        "names the path: {line}"
    );
}

#[test]
fn format_csv_prints_a_table_with_units_in_its_header() {
    let out = run_file(VALID_NO_SERIES, &["--format", "csv"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let header = text.lines().next().expect("header");
    // Without a series: the impacts table, or a one-row summary.
    assert!(
        header.starts_with("impact,t_s,") || header.starts_with("rocked,overturned,"),
        "{header}"
    );
    let columns = header.split(',').count();
    assert!(text.lines().count() >= 2);
    assert!(text.lines().all(|l| l.split(',').count() == columns));
    let bad = run_file(VALID_NO_SERIES, &["--format", "xml"]);
    assert!(!bad.status.success());
}

// ------------------------------------------------------------ serve settings

/// `topple serve` with `args` on a database of its own; it is expected to
/// refuse them before serving.
fn serve_refused(args: &[&str]) -> String {
    let db = temp_path("refused.db");
    let out = topple()
        .args(["serve", "--addr", "127.0.0.1:0", "--database"])
        .arg(format!("sqlite://{}", db.display()))
        .args(args)
        .env_remove("TOPPLE_TOKENS_FILE")
        .env_remove("TOPPLE_API_TOKEN")
        .output()
        .expect("run topple serve");
    let _ = std::fs::remove_file(&db);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
    one_line_failure(&out)
}

#[test]
fn retention_and_per_tenant_quota_must_be_positive() {
    for days in ["0", "-1", "NaN", "inf", "-0.5"] {
        let line = serve_refused(&[&format!("--retention-days={days}")]);
        assert!(line.contains("--retention-days"), "{days}: {line}");
    }
    let line = serve_refused(&["--max-queued-per-tenant", "0"]);
    assert!(line.contains("--max-queued-per-tenant"), "{line}");
}

// ------------------------------------------------------------------ tenants

#[test]
fn token_prints_a_fresh_token_and_the_line_that_admits_it() {
    let mint = || {
        let out = topple().args(["token", "lab-2.ops"]).output().expect("run");
        assert!(out.status.success(), "{}", stderr(&out));
        let text = String::from_utf8(out.stdout).expect("utf-8");
        assert_eq!(text.lines().count(), 1, "one line: {text}");
        serde_json::from_str::<Value>(&text).expect("one JSON document")
    };
    let first = mint();
    assert_eq!(first["name"], "lab-2.ops");
    let token = first["token"].as_str().expect("token");
    let hex = token.strip_prefix("tpl_").expect("tpl_ prefix");
    assert_eq!(hex.len(), 64);
    assert!(hex.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f')));
    let line = first["line"].as_str().expect("line");
    assert_eq!(
        line,
        format!(
            "lab-2.ops blake3:{}",
            blake3::hash(token.as_bytes()).to_hex()
        )
    );
    // The line, appended to a tokens file, admits the token as the tenant.
    let file = format!("# tenants\nother blake3:{}\n{line}\n", "0".repeat(64));
    let tenants = topple::service::tenants::Tenants::parse(&file).expect("parses");
    assert_eq!(tenants.lookup(token).map(|t| &**t), Some("lab-2.ops"));
    // Every token is new.
    assert_ne!(mint()["token"], first["token"]);
}

#[test]
fn token_refuses_a_bad_tenant_name_naming_it() {
    for bad in ["-x", "a b", "a/b", &"n".repeat(65)] {
        let out = topple().args(["token", "--", bad]).output().expect("run");
        assert_eq!(out.status.code(), Some(2), "{bad}");
        let line = one_line_failure(&out);
        assert!(line.contains(bad), "{bad}: {line}");
    }
}

#[test]
fn serve_refuses_a_malformed_tokens_file_naming_the_file_and_line() {
    let good = format!("alice blake3:{}", blake3::hash(b"tpl_a").to_hex());
    let cases = [
        (
            format!("{good}\n\n{good}\n"),
            "line 3",
            "same digest as line 1",
        ),
        (
            format!("# x\nbob tpl_{}\n", "ab".repeat(32)),
            "line 2",
            "token",
        ),
        (format!("{good} extra\n"), "line 1", "3 fields"),
        ("-bob blake3:00\n".to_string(), "line 1", "tenant name"),
    ];
    for (text, at, says) in cases {
        let path = temp_path("tokens");
        std::fs::write(&path, &text).expect("write");
        let line = serve_refused(&["--tokens-file", &path.display().to_string()]);
        let _ = std::fs::remove_file(&path);
        assert!(line.contains(&path.display().to_string()), "{line}");
        assert!(line.contains(at) && line.contains(says), "{text}: {line}");
        // Neither a digest nor a token.
        let digest = blake3::hash(b"tpl_a").to_hex();
        assert!(
            !line.contains(&digest[..16]) && !line.contains(&"ab".repeat(8)),
            "{line}"
        );
    }
    let missing = temp_path("no-such-tokens");
    let line = serve_refused(&["--tokens-file", &missing.display().to_string()]);
    assert!(line.contains(&missing.display().to_string()), "{line}");
}

/// `topple` with `args` and `env`, in a fresh empty directory; returns the
/// output and the directory's entries afterwards.
fn in_empty_dir(args: &[&str], env: &[(&str, &str)]) -> (Output, Vec<String>) {
    let dir = temp_path("empty");
    std::fs::create_dir_all(&dir).expect("dir");
    let out = topple()
        .args(args)
        .envs(env.iter().copied())
        .current_dir(&dir)
        .stdin(Stdio::null())
        .output()
        .expect("topple runs");
    let entries = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().to_string()))
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    (out, entries)
}

#[test]
fn a_bad_environment_variable_is_an_error_naming_it_never_a_fallback() {
    for (var, value, flag) in [
        ("TOPPLE_WORKERS", "two", "--workers"),
        ("TOPPLE_MAX_BODY", "abc", "--max-body"),
        ("TOPPLE_AUTH_READS", "maybe", "--auth-reads"),
    ] {
        let (out, created) = in_empty_dir(&[], &[(var, value)]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{var}: {stderr}");
        assert!(
            stderr.contains(var) && stderr.contains(flag),
            "{var}: {stderr}"
        );
        // Nothing printed as if it had worked, nothing created.
        assert!(out.stdout.is_empty(), "{var}");
        assert!(created.is_empty(), "{var}: {created:?}");
    }
}

#[test]
fn bare_topple_takes_serves_flags() {
    // A bad value of a serve flag given without `serve` is refused as serve
    // would refuse it: the flag is known.
    let (out, _) = in_empty_dir(&["--workers", "0"], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--workers"), "{stderr}");
    let (out, _) = in_empty_dir(&["--no-such-flag"], &[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--no-such-flag"));
}

#[test]
fn a_taken_port_names_the_address_and_creates_nothing() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
    let addr = taken.local_addr().expect("addr").to_string();
    let (out, created) = in_empty_dir(&["--addr", &addr], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(&addr), "{stderr}");
    assert!(created.is_empty(), "{created:?}");
}

#[test]
fn version_names_the_engine() {
    let out = topple().arg("--version").output().expect("runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(text.contains(topple::kinds::key::ENGINE_VERSION), "{text}");
}

#[test]
fn half_width_m_and_half_height_m_name_b_and_h() {
    let by_letters = r#"{"kind":"time_history","block":{"b":0.2,"h":0.8},"pulse":{"type":"one_sine","omega_ratio":5.0,"a_p_alpha_g":4.0},"formulation":"linear"}"#;
    let by_names = by_letters
        .replace("\"b\"", "\"half_width_m\"")
        .replace("\"h\"", "\"half_height_m\"");
    let a: Value = serde_json::from_slice(&run_file(by_letters, &[]).stdout).expect("json");
    let b: Value = serde_json::from_slice(&run_file(&by_names, &[]).stdout).expect("json");
    assert!(
        a["spec"]["block"]["p"].as_f64().is_some_and(|p| p > 0.0),
        "{a}"
    );
    assert_eq!(a["spec"]["block"], b["spec"]["block"]);
}

/// `topple record` prints a file as a `ground_motion`; `topple run` reads the
/// same file named in a spec (`{"file": …}`, relative to the spec's folder)
/// as the same computation as the samples written out.
#[test]
fn a_record_file_read_offline_is_the_same_computation_as_its_samples() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let at2 = root.join("specs/records/ridge_station_090.at2");
    let out = topple().arg("record").arg(&at2).output().expect("runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let motion: Value = serde_json::from_slice(&out.stdout).expect("a ground_motion");
    assert_eq!(motion["unit"], "m/s2");
    assert_eq!(motion["dt"], 0.01);
    assert_eq!(motion["acc"].as_array().map(Vec::len), Some(3000));
    // Its metadata on stderr, as one line of JSON.
    let meta: Value =
        serde_json::from_str(stderr(&out).lines().next().unwrap_or("")).expect("metadata line");
    assert_eq!(meta["samples"], 3000);
    assert_eq!(meta["unit"], "g");
    assert_eq!(meta["pga_g"], 0.342797);

    let named = root.join("specs/records/record_spectrum_ridge.json");
    let by_file = topple().arg("run").arg(&named).output().expect("runs");
    assert!(by_file.status.success(), "{}", stderr(&by_file));
    let mut spec: Value =
        serde_json::from_str(&std::fs::read_to_string(&named).expect("spec")).expect("json");
    spec["ground_motion"] = motion;
    let by_samples = run_file(&spec.to_string(), &[]);
    assert!(by_samples.status.success(), "{}", stderr(&by_samples));
    let strip = |mut v: Value| {
        v["numerics"]["wall_time_s"] = Value::Null;
        v
    };
    assert_eq!(
        strip(result_json(&by_file)),
        strip(result_json(&by_samples))
    );
}

/// What `topple record` cannot read is named as the flag to give or the
/// file's line; a spec naming a stored record is refused offline.
#[test]
fn a_record_file_that_cannot_be_read_names_the_flag_or_the_line() {
    let path = temp_path("one-column.txt");
    std::fs::write(&path, "0.01\n0.02\n-0.01\n0.03\n").expect("write");
    let out = topple()
        .arg("record")
        .arg(&path)
        .args(["--dt", "0.01"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        one_line_failure(&out).contains("--unit"),
        "{}",
        stderr(&out)
    );
    let out = topple()
        .arg("record")
        .arg(&path)
        .args(["--unit", "g", "--dt", "0.01"])
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::write(&path, "t,acc_g\n0,0.1\n0.01,0.2\n0.03,0.1\n0.04,0.0\n").expect("write");
    let out = topple().arg("record").arg(&path).output().expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        one_line_failure(&out).contains("line 4"),
        "{}",
        stderr(&out)
    );
    let _ = std::fs::remove_file(&path);
    assert_rejected_at(
        r#"{"kind":"time_history","block":{"alpha":0.2,"p":2.0},"ground_motion":{"record":"0123456789abcdef0123456789abcdef"}}"#,
        "/ground_motion/record",
    );
}

/// A CSV of `n` vertical samples (g) every `dt` s, with a time column.
fn vertical_csv(n: usize, dt: f64) -> String {
    let mut text = String::from("t,acc_g\n");
    for k in 0..n {
        let t = k as f64 * dt;
        let a = -0.2 * (-((t - 3.0) / 1.5).powi(2)).exp() * (7.0 * t).sin();
        text.push_str(&format!("{t:.4},{a:.5}\n"));
    }
    text
}

/// `topple record H --vertical V` prints both components as one
/// `ground_motion`; `topple run` reads the same two files named in a spec
/// as the same computation; another dt is one line naming both.
#[test]
fn a_three_component_set_is_read_as_a_record_with_its_vertical() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let at2 = root.join("specs/records/ridge_station_090.at2");
    let v_path = temp_path("vertical.csv");
    std::fs::write(&v_path, vertical_csv(2000, 0.01)).expect("write");
    let out = topple()
        .arg("record")
        .arg(&at2)
        .arg("--vertical")
        .arg(&v_path)
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let motion: Value = serde_json::from_slice(&out.stdout).expect("a ground_motion");
    assert_eq!(motion["dt"], 0.01);
    assert_eq!(motion["acc"].as_array().map(Vec::len), Some(3000));
    let vertical = &motion["vertical"];
    assert_eq!(vertical["unit"], "m/s2");
    assert_eq!(vertical["dt"], 0.01);
    let acc = vertical["acc"].as_array().expect("vertical samples");
    assert_eq!(acc.len(), 2000);
    // In m/s², from g.
    let text = vertical_csv(2000, 0.01);
    let third: f64 = text
        .lines()
        .nth(3)
        .and_then(|l| l.split(',').nth(1))
        .and_then(|a| a.parse().ok())
        .expect("a sample");
    assert!((acc[2].as_f64().expect("a number") - third * 9.81).abs() < 1e-12);
    // One metadata line per file, the horizontal first.
    let err = stderr(&out);
    let metas: Vec<Value> = err
        .lines()
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect();
    assert_eq!(metas.len(), 2, "{err}");
    assert_eq!(metas[0]["samples"], 3000);
    assert_eq!(metas[1]["samples"], 2000);

    // The same files named in a spec: the same computation.
    let base = json!({"kind": "time_history", "block": {"alpha": 0.2, "p": 2.0, "eta": 0.9},
                      "outputs": {"series": 100}});
    let mut by_files = base.clone();
    by_files["ground_motion"] = json!({"file": at2, "vertical": {"file": v_path}});
    let mut by_samples = base;
    by_samples["ground_motion"] = motion;
    let strip = |mut v: Value| {
        v["numerics"]["wall_time_s"] = Value::Null;
        v
    };
    let a = strip(result_json(&run_file(&by_files.to_string(), &[])));
    let b = strip(result_json(&run_file(&by_samples.to_string(), &[])));
    assert_eq!(a, b);
    assert!(
        a["series"]["ground_vertical_acceleration"].is_array(),
        "{a}"
    );

    // Another dt: one line naming it.
    std::fs::write(&v_path, vertical_csv(2000, 0.005)).expect("write");
    let out = topple()
        .arg("record")
        .arg(&at2)
        .arg("--vertical")
        .arg(&v_path)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let line = one_line_failure(&out);
    assert!(
        line.contains("dt (0.005 s)") && line.contains("(0.01 s"),
        "{line}"
    );
    // … and so in a spec, at the vertical record's dt.
    let mut spec = json!({"kind": "time_history", "block": {"alpha": 0.2, "p": 2.0}});
    spec["ground_motion"] = json!({"file": at2, "vertical": {"file": v_path}});
    assert_rejected_at(&spec.to_string(), "/ground_motion/vertical/dt");
    let _ = std::fs::remove_file(&v_path);
    // A stored record is the service's to read.
    assert_rejected_at(
        r#"{"kind":"time_history","block":{"alpha":0.2,"p":2.0},"ground_motion":{"dt":0.01,"unit":"g","acc":[0,0.1,0.2],"vertical":{"record":"0123456789abcdef0123456789abcdef"}}}"#,
        "/ground_motion/vertical/record",
    );
}
