//! Records: accelerogram files uploaded as they are, named by jobs, owned by
//! tenants; and the guards that keep a record from being read wrongly.

use std::time::Duration;

use serde_json::{Value, json};

use super::helpers::*;

/// A two-cycle motion of `n` samples at `dt` (s), in g: 0.35 g at its peak,
/// with a slow tail, so that it rocks a slender block and ends at rest.
fn motion_g(n: usize, dt: f64) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            let env = (-((t - 2.0) / 1.2).powi(2)).exp();
            // Four decimals, as files carry them.
            (0.35 * env * (2.0 * std::f64::consts::PI * 1.1 * t).sin() * 1e4).round() / 1e4
        })
        .collect()
}

/// A PEER NGA-West2 AT2 file of `acc` (g) at `dt`, five values a line.
fn at2(acc: &[f64], dt: f64) -> String {
    let mut text = format!(
        "PEER NGA STRONG MOTION DATABASE RECORD\nTest Event 1999, Test Station, 090\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=  {}, DT=   {dt:.4} SEC\n",
        acc.len()
    );
    for line in acc.chunks(5) {
        for a in line {
            text.push_str(&format!("{a:>15.7E}"));
        }
        text.push('\n');
    }
    text
}

/// The same motion as a CSV with a comment and a header row.
fn csv(acc: &[f64], dt: f64) -> String {
    let mut text = String::from("# Test Event 1999, Test Station, 090\ntime_s,acc_g\n");
    for (k, a) in acc.iter().enumerate() {
        text.push_str(&format!("{:.4},{a}\n", k as f64 * dt));
    }
    text
}

/// POSTs `body` to /v1/records with `query`.
async fn upload(
    app: &TestApp,
    query: &str,
    body: String,
) -> (u16, Value, reqwest::header::HeaderMap) {
    let r = app
        .client
        .post(app.url(&format!("/v1/records{query}")))
        .header("content-type", "text/plain")
        .body(body)
        .send()
        .await
        .expect("request");
    let status = r.status().as_u16();
    let headers = r.headers().clone();
    let text = r.text().await.expect("body");
    (
        status,
        serde_json::from_str(&text).unwrap_or(Value::String(text)),
        headers,
    )
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300)
}

#[tokio::test]
async fn one_motion_in_three_formats_is_one_record_with_its_metadata() {
    let app = spawn_app("records-formats").await;
    let dt = 0.01;
    let acc = motion_g(1500, dt);
    let pga = acc.iter().fold(0.0f64, |m, a| m.max(a.abs()));

    let (status, first, headers) = upload(&app, "", at2(&acc, dt)).await;
    assert_eq!(status, 201, "{first}");
    let id = first["id"].as_str().expect("id").to_string();
    assert_eq!(id.len(), 32);
    assert_eq!(headers["location"], format!("/v1/records/{id}").as_str());
    assert_eq!(first["format"], "at2");
    assert_eq!(first["unit"], "g");
    assert_eq!(first["name"], "Test Event 1999, Test Station, 090");
    assert_eq!(first["samples"], 1500);
    assert_eq!(first["dt"], 0.01);
    assert!(
        close(first["duration_s"].as_f64().unwrap_or(0.0), 14.99, 1e-12),
        "{first}"
    );
    assert!(
        close(first["pga_g"].as_f64().unwrap_or(0.0), pga, 1e-12),
        "{first}"
    );
    assert!(close(
        first["pga_m_s2"].as_f64().unwrap_or(0.0),
        pga * 9.81,
        1e-12
    ));
    assert!(first["pgv_m_s"].as_f64().unwrap_or(0.0) > 0.0);
    assert_eq!(first["warnings"], json!([]), "{first}");

    // The same motion as CSV with a header, and as JSON: the same record.
    let (status, again, _) = upload(&app, "", csv(&acc, dt)).await;
    assert_eq!(status, 200, "{again}");
    assert_eq!(again["id"], id.as_str());
    let body = json!({"name": "as json", "dt": dt, "unit": "g", "acc": acc}).to_string();
    let (status, again, _) = upload(&app, "", body).await;
    assert_eq!(status, 200, "{again}");
    assert_eq!(again["id"], id.as_str());

    // In cm/s², converted exactly: the same motion written in m/s² (the
    // same digits, the point moved) has the same id.
    let hundredths: Vec<i64> = acc.iter().map(|a| (a * 98_100.0).round() as i64).collect();
    let decimal = |n: i64, places: u32| {
        let scale = 10i64.pow(places);
        let sign = if n < 0 { "-" } else { "" };
        format!(
            "{sign}{}.{:0width$}",
            n.abs() / scale,
            n.abs() % scale,
            width = places as usize
        )
    };
    let cm: String = hundredths.iter().map(|n| decimal(*n, 2) + "\n").collect();
    let m: String = hundredths.iter().map(|n| decimal(*n, 4) + "\n").collect();
    let (status, in_cm, _) = upload(&app, "?unit=gal&dt=0.01", cm).await;
    assert_eq!(status, 201, "{in_cm}");
    assert_eq!(in_cm["unit"], "cm/s2");
    let (status, in_m, _) = upload(&app, "?unit=m/s2&dt=0.01&format=csv", m).await;
    assert_eq!(status, 200, "{in_m}");
    assert_eq!(in_m["id"], in_cm["id"]);
    assert_ne!(in_m["id"], id.as_str());

    // Metadata, samples as a ground_motion, CSV, listing.
    let (status, meta) = app.get(&format!("/v1/records/{id}")).await;
    assert_eq!(status, 200);
    assert_eq!(meta["id"], id.as_str());
    let (status, samples) = app.get(&format!("/v1/records/{id}?format=json")).await;
    assert_eq!(status, 200);
    assert_eq!(samples["unit"], "m/s2");
    assert_eq!(samples["acc"].as_array().map(Vec::len), Some(1500));
    assert_eq!(samples["acc"][200].as_f64(), Some(acc[200] * 9.81));
    let (status, ct, table) = app.get_text(&format!("/v1/records/{id}?format=csv")).await;
    assert_eq!(status, 200);
    assert!(ct.starts_with("text/csv"));
    assert!(table.starts_with("t_s,acc_m_s2\n0,"), "{}", &table[..40]);
    assert_eq!(table.lines().count(), 1501);
    let (status, list) = app.get("/v1/records").await;
    assert_eq!(status, 200);
    let ids: Vec<&str> = list["records"]
        .as_array()
        .expect("records")
        .iter()
        .filter_map(|r| r["id"].as_str())
        .collect();
    assert!(ids.contains(&id.as_str()), "{list}");
    app.stop().await;
}

#[tokio::test]
async fn a_spec_naming_a_record_is_the_spec_embedding_its_samples() {
    let app = spawn_app("records-same-job").await;
    let dt = 0.01;
    let acc = motion_g(1200, dt);
    let (status, rec, _) = upload(&app, "", at2(&acc, dt)).await;
    assert_eq!(status, 201, "{rec}");
    let id = rec["id"].as_str().expect("id").to_string();
    let (_, samples) = app.get(&format!("/v1/records/{id}?format=json")).await;
    let embedded = json!({"dt": samples["dt"], "acc": samples["acc"], "unit": "m/s2"});

    for spec in [
        json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
               "formulation": "nonlinear"}),
        json!({"kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
               "R_m": [0.5, 2.0], "scale": {"from": 0.2, "to": 3.0}}),
    ] {
        let mut named = spec.clone();
        named["ground_motion"] = json!({"record": id});
        let mut inline = spec.clone();
        inline["ground_motion"] = embedded.clone();
        let (status, a, _) = app.post("/v1/jobs?wait=30", &named).await;
        assert_eq!(status, 200, "{a}");
        let (status, b, _) = app.post("/v1/jobs?wait=30", &inline).await;
        assert_eq!(status, 200, "{b}");
        assert_eq!(a["key"], b["key"], "one computation");
        assert_eq!(a["id"], b["id"], "the tenant's one job");
        assert_eq!(b["cached"], true);
        assert_eq!(a["result"], b["result"]);
        assert_eq!(a["status"], "succeeded", "{a}");
    }
    // A time history's record keeps its vertical acceleration beside it.
    let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9}});
    let (mut named, mut inline) = (spec.clone(), spec);
    named["ground_motion"] = json!({"record": id, "vertical": {"ratio": -0.5}});
    inline["ground_motion"] = embedded.clone();
    inline["ground_motion"]["vertical"] = json!({"ratio": -0.5});
    let (status, a, _) = app.post("/v1/jobs?wait=30", &named).await;
    assert_eq!(status, 200, "{a}");
    let (status, b, _) = app.post("/v1/jobs?wait=30", &inline).await;
    assert_eq!(status, 200, "{b}");
    assert_eq!(a["key"], b["key"], "one computation");
    assert_eq!(
        a["result"]["spec"]["ground_motion"]["vertical"],
        json!({"ratio": -0.5})
    );
    assert!(
        a["result"]["ground_peaks"]["pga_v_m_s2"].as_f64().is_some(),
        "{a}"
    );
    // A fragility suite names records too.
    let suite = json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "ground_motions": [{"record": id}], "stripes": [0.3, 0.6], "samples": 64, "seed": 7});
    let (status, job, _) = app.post("/v1/jobs?wait=30", &suite).await;
    assert_eq!(status, 200, "{job}");
    assert_eq!(job["status"], "succeeded", "{job}");
    // An unknown record, a record beside samples, a file: named.
    for (gm, pointer) in [
        (json!({"record": "0".repeat(32)}), "/ground_motion/record"),
        (json!({"record": "nope"}), "/ground_motion/record"),
        (json!({"record": id, "dt": 0.01}), "/ground_motion/dt"),
        (json!({"file": "record.at2"}), "/ground_motion/file"),
    ] {
        let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
                          "ground_motion": gm});
        let (status, problem, _) = app.post("/v1/jobs", &spec).await;
        assert_eq!(status, 422, "{problem}");
        assert_eq!(problem["pointer"], pointer, "{problem}");
    }
    app.stop().await;
}

/// A time history's vertical acceleration named as a stored record is the
/// spec holding its samples; its series and CSV carry it; an unknown record,
/// another dt, a field beside the id and a file are named.
#[tokio::test]
async fn a_vertical_record_named_by_id_is_the_spec_embedding_its_samples() {
    let app = spawn_app("records-vertical").await;
    let dt = 0.01;
    let h = motion_g(600, dt);
    // The vertical: shorter, another shape (padded with zeros).
    let v: Vec<f64> = motion_g(500, dt).iter().map(|a| -0.6 * a).collect();
    let (status, rh, _) = upload(&app, "", at2(&h, dt)).await;
    assert_eq!(status, 201, "{rh}");
    let (status, rv, _) = upload(&app, "", csv(&v, dt)).await;
    assert_eq!(status, 201, "{rv}");
    let (hid, vid) = (
        rh["id"].as_str().expect("id").to_string(),
        rv["id"].as_str().expect("id").to_string(),
    );
    let (_, samples) = app.get(&format!("/v1/records/{vid}?format=json")).await;
    let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
                      "outputs": {"series": 200}});
    let mut named = spec.clone();
    named["ground_motion"] = json!({"record": hid, "vertical": {"record": vid}});
    let mut inline = spec.clone();
    inline["ground_motion"] = json!({"record": hid,
        "vertical": {"dt": samples["dt"], "acc": samples["acc"], "unit": "m/s2"}});
    let (status, a, _) = app.post("/v1/jobs?wait=30", &named).await;
    assert_eq!(status, 200, "{a}");
    assert_eq!(a["status"], "succeeded", "{a}");
    let (status, b, _) = app.post("/v1/jobs?wait=30", &inline).await;
    assert_eq!(status, 200, "{b}");
    assert_eq!(a["key"], b["key"], "one computation");
    assert_eq!(b["cached"], true);
    assert_eq!(a["result"], b["result"]);
    let steps = assert_result_carries_vertical(&a["result"], &samples);
    let job = a["id"].as_str().expect("job id");
    assert_csv_carries_vertical(&app, job, steps).await;
    let horizontals = [
        json!({"record": hid}),
        json!({"dt": dt, "acc": h, "unit": "g"}),
    ];
    vertical_records_at_fault_are_named(&app, &spec, &vid, &horizontals).await;
    app.stop().await;
}

/// The result of a time history under the vertical record of `samples`
/// holds it in its spec, its peaks and its series; the series' length.
fn assert_result_carries_vertical(result: &Value, samples: &Value) -> usize {
    assert_eq!(
        result["spec"]["ground_motion"]["vertical"]["acc"], samples["acc"],
        "{result}"
    );
    let pga_v = samples["acc"]
        .as_array()
        .expect("samples")
        .iter()
        .filter_map(Value::as_f64)
        .fold(0.0f64, |m, a| m.max(a.abs()));
    assert_eq!(result["ground_peaks"]["pga_v_m_s2"].as_f64(), Some(pga_v));
    // The series carries ü_v: at t = 0 the record's first sample, and
    // zero once both records are over.
    let series = &result["series"];
    let uv = series["ground_vertical_acceleration"]
        .as_array()
        .expect("ü_v in the series");
    let t = series["t"].as_array().expect("t");
    assert_eq!(uv.len(), t.len());
    assert_eq!(uv[0], samples["acc"][0]);
    assert!(uv.iter().filter_map(Value::as_f64).any(|a| a != 0.0));
    t.len()
}

/// The CSV of `job`, a series of `steps` rows, adds the vertical's columns
/// at the end: m/s², and g.
async fn assert_csv_carries_vertical(app: &TestApp, job: &str, steps: usize) {
    let (status, _, table) = app
        .get_text(&format!("/v1/jobs/{job}/result?format=csv"))
        .await;
    assert_eq!(status, 200);
    let header = table.lines().next().unwrap_or("");
    assert!(
        header.ends_with(",ground_vertical_acceleration_m_per_s2,ug_v_g"),
        "{header}"
    );
    assert_eq!(table.lines().count(), steps + 1);
}

/// A vertical record on another dt, an unknown one, fields beside the
/// stored record `vid`, and a file are named, under each of `horizontals`
/// in `spec`.
async fn vertical_records_at_fault_are_named(
    app: &TestApp,
    spec: &Value,
    vid: &str,
    horizontals: &[Value],
) {
    let (status, other, _) = upload(app, "", at2(&motion_g(800, 0.005), 0.005)).await;
    assert_eq!(status, 201, "{other}");
    let other = other["id"].as_str().expect("id").to_string();
    for (vertical, pointer) in [
        (json!({"record": other}), "/ground_motion/vertical/dt"),
        (
            json!({"record": "0".repeat(32)}),
            "/ground_motion/vertical/record",
        ),
        (json!({"record": "nope"}), "/ground_motion/vertical/record"),
        (
            json!({"record": vid, "unit": "g"}),
            "/ground_motion/vertical/unit",
        ),
        (
            json!({"record": vid, "ratio": 0.5}),
            "/ground_motion/vertical/ratio",
        ),
        (json!({"file": "v.at2"}), "/ground_motion/vertical/file"),
    ] {
        for horizontal in horizontals {
            let mut spec = spec.clone();
            spec["ground_motion"] = horizontal.clone();
            spec["ground_motion"]["vertical"] = vertical.clone();
            let (status, problem, _) = app.post("/v1/jobs", &spec).await;
            assert_eq!(status, 422, "{problem}");
            assert_eq!(problem["pointer"], pointer, "{problem}");
        }
    }
}

#[tokio::test]
async fn a_record_in_use_by_a_live_job_is_not_deleted() {
    let app = spawn_app_with("records-delete", |c| c.workers = 1).await;
    let dt = 0.01;
    let acc = motion_g(3000, dt);
    let (_, rec, _) = upload(&app, "", at2(&acc, dt)).await;
    let id = rec["id"].as_str().expect("id").to_string();
    // A record spectrum long enough to be live when the DELETE comes.
    let spec = json!({"kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
        "R_m": {"from": 0.3, "to": 3.0, "steps": 120}, "scale": {"from": 0.2, "to": 6.0},
        "ground_motion": {"record": id}});
    let (status, job, _) = app.post("/v1/jobs", &spec).await;
    assert_eq!(status, 202, "{job}");
    let job_id = job["id"].as_str().expect("job id").to_string();
    let r = app.delete(&format!("/v1/records/{id}")).await;
    assert_eq!(r.status().as_u16(), 409);
    let problem: Value = r.json().await.expect("problem");
    assert!(
        problem["detail"].as_str().unwrap_or("").contains(&job_id),
        "{problem}"
    );
    let r = app.delete(&format!("/v1/jobs/{job_id}")).await;
    assert_eq!(r.status().as_u16(), 200, "canceled");
    let canceled = app.finish(&job_id, Duration::from_secs(10)).await;
    assert_eq!(canceled["status"], "canceled");
    let r = app.delete(&format!("/v1/records/{id}")).await;
    assert_eq!(r.status().as_u16(), 204);
    let (status, _) = app.get(&format!("/v1/records/{id}")).await;
    assert_eq!(status, 404);
    app.stop().await;
}

#[tokio::test]
async fn long_scans_under_a_record_are_estimated_on_a_sample_of_their_brackets() {
    let app = spawn_app_with("records-sampled-estimate", |c| c.workers = 1).await;
    let dt = 0.01;
    let (_, rec, _) = upload(&app, "", at2(&motion_g(3000, dt), dt)).await;
    let id = rec["id"].as_str().expect("id").to_string();
    let spec = |sizes: usize| {
        json!({"kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
            "R_m": {"from": 0.3, "to": 3.0, "steps": sizes}, "scale": {"from": 0.2, "to": 6.0},
            "ground_motion": {"record": id}})
    };
    // One size to 1.5 times the record: a few model CPU seconds, estimated
    // by the model.
    let one = json!({"kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
        "R_m": [1.0], "scale": {"from": 0.2, "to": 1.5}, "ground_motion": {"record": id}});
    let (status, small, _) = app.post("/v1/jobs", &one).await;
    assert!(status == 202 || status == 200, "{}", small["estimate"]);
    assert_eq!(small["estimate"]["basis"], "model", "{}", small["estimate"]);
    // 120 sizes: minutes of work, measured on a sample of its brackets
    // before it is queued; its simulations are more than its scan points
    // (each bracket is bisected where its ends differ) and cost what the
    // sample's steps cost.
    let (status, big, _) = app.post("/v1/jobs", &spec(120)).await;
    assert_eq!(status, 202, "{}", big["estimate"]);
    let e = &big["estimate"];
    assert_eq!(e["basis"], "sample", "{e}");
    let simulations = e["simulations"].as_f64().expect("simulations");
    let points = 120.0 * ((6.0 - 0.2) / 0.01f64).floor();
    assert!(simulations > points && simulations < 256.0 * points, "{e}");
    assert!(e["seconds"].as_f64().expect("seconds") > 0.0, "{e}");
    // Submitted again while it is queued or running: nothing is sampled.
    let (status, again, _) = app.post("/v1/jobs", &spec(120)).await;
    assert_eq!(status, 202, "{}", again["estimate"]);
    assert_eq!(again["cached"], true);
    assert_eq!(again["estimate"]["basis"], "model", "{}", again["estimate"]);
    // A forensic query under the record, its observations' lines sampled.
    // A sample still running at its deadline (1 s plus twice its budget,
    // wall time) is stopped and the model's estimate kept: on a machine as
    // busy as a parallel test run, a few distinct queries are tried.
    let query = |tolerance: f64| {
        json!({"kind": "forensic", "ground_motion": {"record": id},
        "observations": [{"name": "cabinet", "b": 0.1, "h": 1.0, "overturned": true},
                         {"name": "pedestal", "b": 0.3, "h": 0.9, "overturned": false}],
        "pga_g": {"from": 0.05, "to": 6.0}, "tolerance_g": tolerance})
    };
    let mut queries = Vec::new();
    for tolerance in [1e-5, 2e-5, 3e-5] {
        let (status, forensic, _) = app.post("/v1/jobs", &query(tolerance)).await;
        assert_eq!(status, 202, "{}", forensic["estimate"]);
        queries.push(forensic);
        if queries
            .last()
            .is_some_and(|f| f["estimate"]["basis"] == "sample")
        {
            break;
        }
    }
    let forensic = queries.last().expect("a query").clone();
    assert_eq!(
        forensic["estimate"]["basis"], "sample",
        "{}",
        forensic["estimate"]
    );
    // While another sample holds the instance's one turn, a new job waits
    // for it at most `SAMPLE_WAIT`, then keeps its model's estimate.
    let turn = app
        .state
        .sampling
        .clone()
        .acquire_owned()
        .await
        .expect("the turn");
    let asked = std::time::Instant::now();
    let (status, waited, _) = app.post("/v1/jobs", &spec(110)).await;
    let took = asked.elapsed();
    drop(turn);
    assert_eq!(status, 202, "{}", waited["estimate"]);
    assert_eq!(
        waited["estimate"]["basis"], "model",
        "{}",
        waited["estimate"]
    );
    assert!(
        took >= topple::service::submit::SAMPLE_WAIT,
        "answered in {took:?}, before the wait for the turn ended"
    );
    for job in [&small, &big, &waited].into_iter().chain(&queries) {
        let job_id = job["id"].as_str().expect("job id");
        app.delete(&format!("/v1/jobs/{job_id}")).await;
    }
    app.stop().await;
}

#[tokio::test]
async fn records_belong_to_their_tenant_and_their_samples_are_stored_once() {
    let alice = "tpl_a11ce00000000000000000000000000000000000000000000000000000000001";
    let bob = "tpl_b0b0000000000000000000000000000000000000000000000000000000000002";
    let path = temp_dir("records-tenants").join("tokens");
    std::fs::write(
        &path,
        format!(
            "alice {}\nbob {}\n",
            topple::service::tenants::digest(alice),
            topple::service::tenants::digest(bob)
        ),
    )
    .expect("tokens");
    let app = spawn_app_with("records-tenants", move |c| c.tokens_file = Some(path)).await;
    let body = at2(&motion_g(800, 0.01), 0.01);
    let send =
        |token: &'static str, method: reqwest::Method, path: String, body: Option<String>| {
            let mut r = app
                .client
                .request(method, app.url(&path))
                .bearer_auth(token);
            if let Some(b) = body {
                r = r.body(b);
            }
            r.send()
        };
    let r = send(
        alice,
        reqwest::Method::POST,
        "/v1/records".into(),
        Some(body.clone()),
    )
    .await
    .expect("upload");
    assert_eq!(r.status().as_u16(), 201);
    let rec: Value = r.json().await.expect("json");
    let id = rec["id"].as_str().expect("id").to_string();
    // Bob sees nothing of it: not by id, not in his list, not in a job.
    for path in [
        format!("/v1/records/{id}"),
        format!("/v1/records/{id}?format=json"),
    ] {
        let r = send(bob, reqwest::Method::GET, path, None)
            .await
            .expect("get");
        assert_eq!(r.status().as_u16(), 404);
    }
    let r = send(bob, reqwest::Method::GET, "/v1/records".into(), None)
        .await
        .expect("list");
    let list: Value = r.json().await.expect("json");
    assert_eq!(list["records"], json!([]));
    let r = send(
        bob,
        reqwest::Method::DELETE,
        format!("/v1/records/{id}"),
        None,
    )
    .await
    .expect("delete");
    assert_eq!(r.status().as_u16(), 404);
    let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
                      "ground_motion": {"record": id}});
    let r = app
        .client
        .post(app.url("/v1/jobs"))
        .bearer_auth(bob)
        .json(&spec)
        .send()
        .await
        .expect("submit");
    assert_eq!(r.status().as_u16(), 422);
    // Bob uploads the same file: his own record, the same id, one copy of
    // the samples.
    let r = send(bob, reqwest::Method::POST, "/v1/records".into(), Some(body))
        .await
        .expect("upload");
    assert_eq!(r.status().as_u16(), 201);
    let his: Value = r.json().await.expect("json");
    assert_eq!(his["id"], id.as_str());
    let db =
        sqlx::SqlitePool::connect(&format!("sqlite://{}", app.dir.join("topple.db").display()))
            .await
            .expect("database");
    let rows: (i64, i64) = sqlx::query_as(
        "SELECT (SELECT COUNT(*) FROM record_samples), (SELECT COUNT(*) FROM records)",
    )
    .fetch_one(&db)
    .await
    .expect("counts");
    assert_eq!(rows, (1, 2), "samples once, a record row per tenant");
    db.close().await;
    app.stop().await;
}

#[tokio::test]
async fn uploads_are_refused_or_warned_about_naming_what_to_change() {
    let app = spawn_app_with("records-guards", |c| c.max_record_samples = 250_000).await;
    // No unit stated or given.
    let (status, p, _) = upload(&app, "?dt=0.01", "0.1\n0.2\n-0.1\n0.05\n".into()).await;
    assert_eq!(status, 422, "{p}");
    assert_eq!(p["parameter"], "unit", "{p}");
    // One column without dt.
    let (status, p, _) = upload(&app, "?unit=g", "0.1\n0.2\n-0.1\n0.05\n".into()).await;
    assert_eq!(status, 422, "{p}");
    assert_eq!(p["parameter"], "dt", "{p}");
    // Time that is not uniform: the line named.
    let text = "t,acc_g\n0.00,0.1\n0.01,0.2\n0.02,-0.1\n0.04,0.05\n0.05,0.0\n";
    let (status, p, _) = upload(&app, "", text.into()).await;
    assert_eq!(status, 422, "{p}");
    assert!(p["detail"].as_str().unwrap_or("").contains("line 5"), "{p}");
    // A record in cm/s² uploaded as m/s²: PGA 61.6 g refused with the hint.
    let cm: String = motion_g(600, 0.01)
        .iter()
        .map(|a| format!("{}\n", a * 981.0 * 1.8))
        .collect();
    let (status, p, _) = upload(&app, "?unit=m/s2&dt=0.01", cm.clone()).await;
    assert_eq!(status, 422, "{p}");
    assert_eq!(p["parameter"], "unit", "{p}");
    assert!(p["detail"].as_str().unwrap_or("").contains("cm/s"), "{p}");
    // As intended: stored, with a warning.
    let (status, rec, _) = upload(&app, "?unit=m/s2&dt=0.01&allow_large_pga=true", cm).await;
    assert_eq!(status, 201, "{rec}");
    assert_eq!(rec["warnings"][0]["kind"], "large_pga", "{rec}");
    // 200,000 samples, within the limit; 250,001 beyond it.
    let long: Vec<f64> = (0..200_000)
        .map(|k| 0.2 * (k as f64 * 0.013).sin())
        .collect();
    let (status, rec, _) = upload(&app, "", at2(&long, 0.005)).await;
    assert_eq!(status, 201, "{rec}");
    assert_eq!(rec["samples"], 200_000);
    let longer: String = (0..250_001)
        .map(|k| format!("{}\n", 0.1 * (k as f64 * 0.01).sin()))
        .collect();
    let (status, p, _) = upload(&app, "?unit=g&dt=0.01", longer).await;
    assert_eq!(status, 422, "{p}");
    assert_eq!(p["limit"], "max_record_samples", "{p}");
    app.stop().await;
}

#[tokio::test]
async fn a_record_read_wrongly_is_refused_in_a_job_spec_and_warnings_reach_results() {
    let app = spawn_app("records-spec-guards").await;
    let acc = motion_g(600, 0.01);
    // (time, acceleration) pairs flattened into `acc`.
    let pairs: Vec<f64> = acc
        .iter()
        .enumerate()
        .flat_map(|(k, a)| [k as f64 * 0.01, *a])
        .collect();
    let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": pairs}});
    let (status, p, _) = app.post("/v1/jobs", &spec).await;
    assert_eq!(status, 422, "{p}");
    assert_eq!(p["pointer"], "/ground_motion/acc");
    assert!(
        p["detail"]
            .as_str()
            .unwrap_or("")
            .contains("(time, acceleration) pairs"),
        "{p}"
    );
    // cm/s² given as m/s²: PGA 61.6 g, refused at unit with the hint.
    let cm: Vec<f64> = acc.iter().map(|a| a * 981.0 * 1.8).collect();
    let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
        "ground_motion": {"dt": 0.01, "unit": "m/s2", "acc": cm}});
    let (status, p, _) = app.post("/v1/jobs", &spec).await;
    assert_eq!(status, 422, "{p}");
    assert_eq!(p["pointer"], "/ground_motion/unit");
    assert!(p["detail"].as_str().unwrap_or("").contains("cm/s"), "{p}");
    // The same in cm/s²: computed.
    let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
        "ground_motion": {"dt": 0.01, "unit": "cm/s2", "acc": cm}});
    let (status, job, _) = app.post("/v1/jobs?wait=20", &spec).await;
    assert_eq!(status, 200, "{job}");
    // 3 g: computed, warned about; too weak to rock: warned about.
    let strong: Vec<f64> = acc.iter().map(|a| a * 3.0 / 0.35).collect();
    let weak: Vec<f64> = acc.iter().map(|a| a * 0.1).collect();
    for (samples, kind) in [(strong, "large_pga"), (weak, "never_rocks")] {
        let spec = json!({"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
            "ground_motion": {"dt": 0.01, "unit": "g", "acc": samples}});
        let (status, job, _) = app.post("/v1/jobs?wait=20", &spec).await;
        assert_eq!(status, 200, "{job}");
        let kinds: Vec<&str> = job["result"]["warnings"]
            .as_array()
            .map(|w| w.iter().filter_map(|w| w["kind"].as_str()).collect())
            .unwrap_or_default();
        assert!(kinds.contains(&kind), "{kind}: {kinds:?}");
    }
    app.stop().await;
}
