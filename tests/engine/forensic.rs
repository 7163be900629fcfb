//! The forensic query: the amplitudes it calls consistent are checked against
//! direct simulations of every observed block, inside each interval and in
//! every gap between them.

use serde_json::{Value, json};
use topple::kinds::Job;
use topple::spectrum::Control;

fn run(spec: &Value) -> Value {
    Job::parse(&spec.to_string())
        .expect("valid spec")
        .run(&Control::new())
        .expect("runs")
}

fn point_reyes() -> Value {
    json!({
        "kind": "forensic",
        "pulse": {"type": "one_sine"},
        "observations": [
            {"name": "locomotive", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": true},
            {"name": "transformer", "b": 0.6, "h": 1.2, "overturned": false}
        ],
        "frequency_hz": {"from": 0.5, "to": 2.5, "steps": 5},
        "a_p_g": {"from": 0.05, "to": 3.0},
        "formulation": "nonlinear"
    })
}

/// Whether the block of observation `o` overturns under a one-sine pulse of
/// `f` Hz and `a` g.
fn overturns(o: &Value, f: f64, a: f64) -> bool {
    let mut block = o["block"].clone();
    block.as_object_mut().map(|b| b.remove("mu"));
    let spec = json!({
        "kind": "time_history",
        "block": block,
        "pulse": {"type": "one_sine", "frequency_hz": f, "a_p_g": a},
        "formulation": "nonlinear",
        "outputs": {"reactions": false, "impacts": false, "max_free_impacts": 0}
    });
    run(&spec)["overturned"].as_bool().expect("overturned flag")
}

fn intervals(v: &Value) -> Vec<(f64, f64)> {
    v.as_array()
        .expect("intervals")
        .iter()
        .map(|p| (p[0].as_f64().expect("lo"), p[1].as_f64().expect("hi")))
        .collect()
}

#[test]
fn consistent_amplitudes_agree_with_direct_simulation_inside_and_between() {
    let result = run(&point_reyes());
    let observations = result["observations"].as_array().expect("observations");
    let tol = result["numerics"]["tolerance_g"]
        .as_f64()
        .expect("tolerance");
    let (from, to) = (0.05, 3.0);
    let mut checked = (0, 0);
    for line in result["frequencies"].as_array().expect("frequencies") {
        let f = line["frequency_hz"].as_f64().expect("f");
        let consistent = intervals(&line["consistent_g"]);
        // Points well inside each consistent interval: every observation holds.
        for &(lo, hi) in &consistent {
            if hi - lo < 4.0 * tol {
                continue;
            }
            let a = 0.5 * (lo + hi);
            for o in observations {
                let seen = o["overturned"].as_bool().expect("flag");
                assert_eq!(overturns(o, f, a), seen, "{f} Hz, {a} g: {}", o["name"]);
            }
            checked.0 += 1;
        }
        // Points well inside each gap: some observation is contradicted.
        let mut edges = vec![from];
        for &(lo, hi) in &consistent {
            edges.push(lo);
            edges.push(hi);
        }
        edges.push(to);
        for gap in edges.chunks(2) {
            let (lo, hi) = (gap[0], gap[1]);
            if hi - lo < 4.0 * tol {
                continue;
            }
            let a = 0.5 * (lo + hi);
            let contradicted = observations
                .iter()
                .any(|o| overturns(o, f, a) != o["overturned"].as_bool().expect("flag"));
            assert!(
                contradicted,
                "{f} Hz, {a} g lies in a gap yet fits every observation"
            );
            checked.1 += 1;
        }
        // Each observation's own set is a superset of the joint one.
        for own in line["per_observation"].as_array().expect("per observation") {
            let own = intervals(&own["consistent_g"]);
            for &(lo, hi) in &consistent {
                assert!(
                    own.iter().any(|&(a, b)| a <= lo && hi <= b),
                    "{f} Hz: [{lo}, {hi}] outside an observation's set {own:?}"
                );
            }
        }
    }
    assert!(checked.0 >= 5 && checked.1 >= 5, "checked {checked:?}");
    let bounds = &result["bounds"];
    assert!(bounds["min_g"].as_f64().expect("min") > 0.05);
}

#[test]
fn one_overturned_block_gives_exactly_its_overturning_spectrum() {
    let mut spec = point_reyes();
    spec["observations"] = json!([
        {"name": "locomotive", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": true}
    ]);
    spec["frequency_hz"] = json!([1.0, 2.0]);
    let forensic = run(&spec);
    for (k, f) in [1.0f64, 2.0].into_iter().enumerate() {
        let spectrum = run(&json!({
            "kind": "spectrum",
            "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
            "pulse": {"type": "one_sine"},
            "formulation": "nonlinear",
            "omega_ratio": [2.0 * std::f64::consts::PI * f / 2.14],
            "a_max_alpha_g": 3.0 / 0.25,
            "scan_step_alpha_g": 0.01 / 0.25,
            "tolerance": 1e-4 / 0.25
        }));
        // Overturning intervals from the spectrum's transitions, in g.
        let mut expected = Vec::new();
        let mut open = None;
        for t in spectrum["spectrum"][0]["transitions"]
            .as_array()
            .expect("transitions")
        {
            let at = t["a_alpha_g"].as_f64().expect("at") * 0.25;
            match t["direction"].as_str() {
                Some("up") => open = Some(at),
                _ => {
                    if let Some(lo) = open.take() {
                        expected.push((lo, at));
                    }
                }
            }
        }
        if let Some(lo) = open {
            expected.push((lo, 3.0));
        }
        let got = intervals(&forensic["frequencies"][k]["consistent_g"]);
        assert_eq!(got.len(), expected.len(), "{f} Hz: {got:?} vs {expected:?}");
        for (g, e) in got.iter().zip(&expected) {
            assert!(
                (g.0 - e.0).abs() < 1e-12 && (g.1 - e.1).abs() < 1e-12,
                "{g:?} {e:?}"
            );
        }
    }
}

#[test]
fn a_bad_query_names_its_field() {
    let cases = [
        (
            "/observations/0/overturned",
            json!({"name": "x", "b": 0.5, "h": 1.0}),
        ),
        (
            "/observations/0/block",
            json!({"b": 0.5, "block": {"b": 0.5, "h": 1.0}, "overturned": true}),
        ),
        (
            "/observations/0/block/alpha",
            json!({"block": {"alpha": 2.0, "p": 2.0}, "overturned": true}),
        ),
    ];
    for (pointer, observation) in cases {
        let mut spec = point_reyes();
        spec["observations"] = json!([observation]);
        let e = Job::parse(&spec.to_string()).expect_err("invalid");
        assert_eq!(e.pointer, pointer, "{e}");
    }
    let mut spec = point_reyes();
    spec["a_p_g"] = json!({"from": 2.0, "to": 1.0});
    assert_eq!(
        Job::parse(&spec.to_string()).expect_err("invalid").pointer,
        "/a_p_g"
    );
    let mut spec = point_reyes();
    spec["observations"] = json!([]);
    assert_eq!(
        Job::parse(&spec.to_string()).expect_err("invalid").pointer,
        "/observations"
    );
}
