//! Forensic queries on a recorded motion (`ground_motion` with a scale axis):
//! a one-sine pulse sampled at T/4000 gives the pulse query's answer; the
//! scales called consistent are checked by time histories of the scaled
//! record, inside each interval and in every gap; the axes in either unit make
//! one job; what cannot be computed is refused naming the field.

use serde_json::{Value, json};
use topple::kinds::Job;
use topple::kinds::key::cache_key;
use topple::spectrum::Control;

/// A one-sine pulse of `hz` and peak `a_g` g, sampled at T/n.
fn one_sine_record(hz: f64, a_g: f64, n: usize) -> Value {
    let w = std::f64::consts::TAU * hz;
    let dt = 1.0 / hz / n as f64;
    let acc: Vec<f64> = (0..=n).map(|k| a_g * (w * k as f64 * dt).sin()).collect();
    json!({"dt": dt, "acc": acc, "unit": "g"})
}

fn observations() -> Value {
    json!([
        {"name": "locomotive", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": true},
        {"name": "transformer", "b": 0.6, "h": 1.2, "overturned": false}
    ])
}

fn query(extra: Value) -> Result<Job, topple::jobs::SpecError> {
    let mut spec = json!({"kind": "forensic", "observations": observations(),
                          "ground_motion": one_sine_record(1.0, 0.5, 4000),
                          "pga_g": {"from": 0.05, "to": 3.0}});
    for (k, v) in extra.as_object().expect("object") {
        spec[k] = v.clone();
    }
    Job::from_value(&spec)
}

fn run(job: &Job) -> Value {
    job.run(&Control::new()).expect("runs")
}

fn intervals(v: &Value) -> Vec<(f64, f64)> {
    v.as_array()
        .expect("intervals")
        .iter()
        .map(|p| (p[0].as_f64().expect("lo"), p[1].as_f64().expect("hi")))
        .collect()
}

#[test]
fn a_sampled_pulse_gives_the_pulse_querys_answer() {
    for (hz, formulation) in [(1.0, "nonlinear"), (2.0, "nonlinear"), (1.0, "linear")] {
        let from_record = run(&query(json!({
            "ground_motion": one_sine_record(hz, 0.5, 4000),
            "formulation": formulation}))
        .expect("valid"));
        let from_pulse = run(&Job::from_value(&json!({
            "kind": "forensic", "pulse": {"type": "one_sine"}, "observations": observations(),
            "frequency_hz": [hz], "a_p_g": {"from": 0.05, "to": 3.0},
            "formulation": formulation}))
        .expect("valid"));
        assert_eq!(from_record["excitation"], "ground_motion");
        assert_eq!(from_pulse["excitation"], "pulse");
        let record = intervals(&from_record["consistent_pga_g"]);
        let pulse = intervals(&from_pulse["frequencies"][0]["consistent_g"]);
        assert!(
            !record.is_empty(),
            "{hz} Hz {formulation}: something is consistent"
        );
        assert_eq!(record.len(), pulse.len(), "{record:?} vs {pulse:?}");
        for (r, p) in record.iter().zip(&pulse) {
            for (x, y) in [(r.0, p.0), (r.1, p.1)] {
                assert!(
                    (x - y).abs() <= 2e-3 * y,
                    "{hz} Hz {formulation}: {x} g from the record, {y} g from the pulse"
                );
            }
        }
        // PGA 0.5 g: scale s is a PGA of 0.5 s g.
        let scale = intervals(&from_record["consistent_scale"]);
        for (s, g) in scale.iter().zip(&record) {
            assert!((s.0 * 0.5 - g.0).abs() < 1e-12 && (s.1 * 0.5 - g.1).abs() < 1e-12);
        }
        assert_eq!(from_record["record"]["pga_g"].as_f64(), Some(0.5));
        assert!(
            from_record["frequencies"]
                .as_array()
                .expect("list")
                .is_empty()
        );
        assert!(from_record["bounds"]["frequency_hz"].is_null());
        assert_eq!(
            from_record["bounds"]["min_scale"].as_f64(),
            scale.first().map(|s| s.0)
        );
    }
}

/// `record` with its samples scaled by `s`.
fn scaled(record: &Value, s: f64) -> Value {
    let mut gm = record.clone();
    let acc: Vec<f64> = gm["acc"]
        .as_array()
        .expect("samples")
        .iter()
        .map(|a| a.as_f64().expect("number") * s)
        .collect();
    gm["acc"] = json!(acc);
    gm
}

/// Whether `block` overturns under `record` scaled by `s`.
fn overturns(block: &Value, record: &Value, s: f64) -> bool {
    let gm = scaled(record, s);
    let spec = json!({"kind": "time_history", "block": block, "ground_motion": gm,
                      "formulation": "nonlinear",
                      "outputs": {"reactions": false, "impacts": false, "max_free_impacts": 0}});
    run(&Job::from_value(&spec).expect("valid"))["overturned"]
        .as_bool()
        .expect("flag")
}

/// Two cycles of 1.3 Hz over 2 s, the second stronger (0.3 g, then 0.5 g
/// under a triangular envelope), in `n` steps: not a pulse the library holds.
fn two_cycle_record(n: usize) -> Value {
    let dt = 2.0 / n as f64;
    let acc: Vec<f64> = (0..=n)
        .map(|k| {
            let t = k as f64 * dt;
            let a = if t < 1.0 { 0.3 } else { 0.5 };
            a * (std::f64::consts::TAU * 1.3 * t).sin() * (1.0 - (t - 1.0).abs()).max(0.0)
        })
        .collect();
    let record = json!({"dt": dt, "acc": acc, "unit": "g"});
    record
}

#[test]
fn consistent_scales_agree_with_time_histories_inside_and_between() {
    // A two-cycle record with a stronger second cycle: not a pulse the
    // library holds.
    let record = two_cycle_record(2000);
    let result = run(&query(json!({"ground_motion": record, "pga_g": null,
                                   "scale": {"from": 0.2, "to": 8.0}}))
    .expect("valid"));
    let blocks: Vec<(Value, bool)> = result["observations"]
        .as_array()
        .expect("observations")
        .iter()
        .map(|o| (o["block"].clone(), o["overturned"].as_bool().expect("flag")))
        .collect();
    let blocks: Vec<(Value, bool)> = blocks
        .into_iter()
        .map(|(mut b, seen)| {
            b.as_object_mut().map(|b| b.remove("mu"));
            (b, seen)
        })
        .collect();
    let record = &result["spec"]["ground_motion"];
    let tol = result["numerics"]["tolerance_g"].as_f64().expect("tol")
        / result["record"]["pga_g"].as_f64().expect("pga");
    let consistent = intervals(&result["consistent_scale"]);
    assert!(!consistent.is_empty(), "{result}");
    let mut checked = (0, 0);
    for &(lo, hi) in &consistent {
        if hi - lo > 4.0 * tol {
            let s = 0.5 * (lo + hi);
            for (b, seen) in &blocks {
                assert_eq!(overturns(b, record, s), *seen, "scale {s}");
            }
            checked.0 += 1;
        }
    }
    let mut edges = vec![0.2];
    for &(lo, hi) in &consistent {
        edges.push(lo);
        edges.push(hi);
    }
    edges.push(8.0);
    for gap in edges.chunks(2) {
        let (lo, hi) = (gap[0], gap[1]);
        if hi - lo > 4.0 * tol {
            let s = 0.5 * (lo + hi);
            let contradicted = blocks
                .iter()
                .any(|(b, seen)| overturns(b, record, s) != *seen);
            assert!(contradicted, "scale {s} lies in a gap, yet all hold");
            checked.1 += 1;
        }
    }
    assert!(checked.0 >= 1 && checked.1 >= 1, "{checked:?}");
    // Each observation's sets, and their intersection.
    let per = result["per_observation"]
        .as_array()
        .expect("per observation");
    assert_eq!(per.len(), 2);
    let over = intervals(&per[0]["overturning_scale"]);
    assert_eq!(intervals(&per[0]["consistent_scale"]), over);
    let threshold = per[0]["threshold_scale"].as_f64().expect("threshold");
    let pga = result["record"]["pga_g"].as_f64().expect("pga");
    assert!((threshold * pga - 0.25f64.tan()).abs() < 1e-12);
}

#[test]
fn the_scale_axis_in_either_unit_makes_one_job() {
    let a = query(json!({"pga_g": null, "scale": {"from": 0.1, "to": 6.0},
                         "tolerance": 2e-4, "scan_step": 0.02}))
    .expect("valid");
    let b = query(json!({"pga_g": {"from": 0.05, "to": 3.0},
                         "tolerance_g": 1e-4, "scan_step_g": 0.01}))
    .expect("valid");
    assert_eq!(cache_key(&a), cache_key(&b));
    // The normalised spec, as stored and run by a worker, is the same job.
    let Job::Forensic(stored) = &a else {
        panic!("forensic")
    };
    let again = Job::from_value(&serde_json::to_value(stored).expect("json")).expect("re-reads");
    assert_eq!(cache_key(&again), cache_key(&a));
    // Defaults in g, as for pulse queries.
    let Job::Forensic(c) = query(json!({})).expect("valid") else {
        panic!("forensic")
    };
    assert_eq!((c.tolerance_g, c.scan_step_g), (1e-4, 0.01));
    let s = c.scale().expect("scale");
    assert!((s.from - 0.1).abs() < 1e-15 && (s.to - 6.0).abs() < 1e-15);
}

#[test]
fn a_record_query_refuses_what_it_cannot_compute_naming_the_field() {
    let zero = json!({"dt": 0.01, "acc": [0.0, 0.0, 0.0], "unit": "g"});
    let cases = [
        (json!({"pulse": {"type": "one_sine"}}), "/ground_motion"),
        (json!({"frequency_hz": [1.0]}), "/frequency_hz"),
        (json!({"a_p_g": {"from": 0.1, "to": 1.0}}), "/a_p_g"),
        (json!({"pga_g": null}), "/scale"),
        (json!({"scale": {"to": 2.0}}), "/pga_g"),
        (json!({"pga_g": {"from": 0.5}}), "/pga_g/to"),
        (json!({"pga_g": {"from": 2.0, "to": 1.0}}), "/pga_g/to"),
        (json!({"pga_g": {"to": 200.0}}), "/pga_g/to"),
        (json!({"pga_g": {"from": -1.0, "to": 1.0}}), "/pga_g/from"),
        (
            json!({"tolerance": 1e-3, "tolerance_g": 1e-4}),
            "/tolerance",
        ),
        (json!({"scan_step_g": 5.0}), "/scan_step_g"),
        (json!({"ground_motion": zero}), "/ground_motion/acc"),
        (
            json!({"ground_motion": {"dt": 0.01, "acc": [0.1, 0.2]}}),
            "/ground_motion/unit",
        ),
        (
            json!({"observations": [
                {"block": {"alpha": 0.2, "p": 2.0}, "overturned": true},
                {"block": {"alpha": 0.2, "p": 2.0, "g": 1.62}, "overturned": false}]}),
            "/observations",
        ),
        (json!({"observations": []}), "/observations"),
    ];
    for (extra, pointer) in cases {
        let e = query(extra.clone()).expect_err("refused");
        assert_eq!(e.pointer, pointer, "{extra}: {}", e.message);
    }
    // A pulse query refuses the record's axis.
    let e = Job::from_value(&json!({"kind": "forensic", "pulse": {"type": "one_sine"},
        "observations": observations(), "frequency_hz": [1.0],
        "a_p_g": {"from": 0.1, "to": 1.0}, "scale": {"to": 2.0}}))
    .expect_err("refused");
    assert_eq!(e.pointer, "/scale");
    let e = Job::from_value(&json!({"kind": "forensic", "observations": observations()}))
        .expect_err("refused");
    assert_eq!(e.pointer, "/pulse");
    assert!(e.message.contains("ground_motion"), "{}", e.message);
}

#[test]
fn the_exact_linear_solution_is_the_default_and_agrees_with_dop853() {
    let exact = run(&query(json!({"formulation": "linear"})).expect("valid"));
    assert_eq!(exact["spec"]["solver"]["method"], "exact");
    let numerical = run(&query(json!({"formulation": "linear",
                                      "solver": {"method": "dop853", "rtol": 1e-10}}))
    .expect("valid"));
    let (a, b) = (
        intervals(&exact["consistent_pga_g"]),
        intervals(&numerical["consistent_pga_g"]),
    );
    assert_eq!(a.len(), b.len(), "{a:?} {b:?}");
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (x.0 - y.0).abs() <= 2e-4 && (x.1 - y.1).abs() <= 2e-4,
            "{x:?} {y:?}"
        );
    }
}

/// |residual slide|, m, of `block` on `contact` under `record` scaled by `s`;
/// `None` when it overturns.
fn slid(block: &Value, contact: &Value, record: &Value, s: f64) -> Option<f64> {
    let gm = scaled(record, s);
    let spec = json!({"kind": "time_history", "block": block, "ground_motion": gm,
                      "contact": contact});
    let r = run(&Job::from_value(&spec).expect("valid"));
    assert_ne!(r["lift_off"], json!(true), "{r}");
    (!r["overturned"].as_bool().expect("flag"))
        .then(|| r["residual_slide_m"].as_f64().expect("m").abs())
}

#[test]
fn a_seen_slide_under_a_record_is_consistent_where_its_time_history_slides_that_far() {
    // The locomotive on μ = 0.2 (below tan α: it only slides) under a
    // two-cycle record: the scales called consistent with a standing block
    // that slid 5–20 cm are those whose time history ends with a slide of
    // that size; at the middle of each interval and gap, and one tolerance
    // either side of each end found.
    let record = two_cycle_record(1000);
    let block = json!({"alpha": 0.25, "p": 2.14});
    let contact = json!({"model": "coulomb", "mu": 0.2});
    let band = [0.05, 0.2];
    let result = run(&query(json!({
        "ground_motion": record, "pga_g": null, "scale": {"from": 0.2, "to": 6.0},
        "tolerance": 1e-3, "contact": contact,
        "observations": [{"name": "locomotive", "block": block, "overturned": false, "slid_m": band}]}))
    .expect("valid"));
    let record = &result["spec"]["ground_motion"];
    let inside = |s: Option<f64>| s.is_some_and(|s| band[0] <= s && s <= band[1]);
    let consistent = intervals(&result["consistent_scale"]);
    assert!(!consistent.is_empty(), "{result}");
    let tol = 1e-3;
    let mut lo = 0.2;
    let mut edges = 0;
    for &(a, b) in &consistent {
        if a > lo {
            let s = 0.5 * (lo + a);
            assert!(!inside(slid(&block, &contact, record, s)), "gap at {s}");
        }
        let s = 0.5 * (a + b);
        assert!(inside(slid(&block, &contact, record, s)), "scale {s}");
        for (edge, opens) in [(a, true), (b, false)] {
            if edge > 0.2 && edge < 6.0 {
                let below = inside(slid(&block, &contact, record, edge - tol));
                let above = inside(slid(&block, &contact, record, edge + tol));
                assert_eq!((below, above), (!opens, opens), "edge {edge}");
                edges += 1;
            }
        }
        lo = b;
    }
    assert!(edges >= 1, "{result}");
    assert_eq!(
        result["per_observation"][0]["consistent_scale"],
        result["consistent_scale"]
    );
}
