//! The survival of rocks under a hazard model (`survival`): Cornell et al.'s
//! closed form for a power-law hazard and a lognormal fragility; uncertain
//! ages; several rocks; what cannot be computed is refused naming the field.

use serde_json::{Value, json};
use topple::kinds::Job;
use topple::spectrum::Control;

/// H(x) = 1e-4·(x/0.4)^(−k), tabulated at `xs` (g).
fn power_law(k: f64, xs: &[f64]) -> Value {
    let points: Vec<[f64; 2]> = xs
        .iter()
        .map(|&x| [x, 1e-4 * (x / 0.4f64).powf(-k)])
        .collect();
    json!({"im": "pga_g", "points": points})
}

fn run(spec: Value) -> Value {
    Job::from_value(&spec)
        .expect("valid")
        .run(&Control::new())
        .expect("runs")
}

#[test]
fn cornells_closed_form_and_the_published_survival() {
    let doc = run(json!({"kind": "survival",
        "hazard": power_law(2.5, &[0.05, 0.1, 0.2, 0.4, 0.8, 1.6]),
        "fragility": {"median_g": 0.38, "beta": 0.38},
        "age_years": [1000, 10000, 30000]}));
    // λ_t = H(θ)·exp(k²β²/2).
    let expected =
        1e-4 * (0.38f64 / 0.4).powf(-2.5) * (2.5f64.powi(2) * 0.38f64.powi(2) / 2.0).exp();
    let rate = doc["annual_toppling_rate"].as_f64().expect("rate");
    assert!(
        (rate / expected - 1.0).abs() < 1e-12,
        "{rate} vs {expected}"
    );
    assert!((rate - 1.785e-4).abs() < 5e-8);
    // 0.837, 0.168, 0.0047 at 1, 10, 30 kyr (to the digits published).
    for (age, (p, half_digit)) in doc["ages"].as_array().expect("ages").iter().zip([
        (0.837, 5e-4),
        (0.168, 5e-4),
        (0.0047, 5e-5),
    ]) {
        let ps = age["survival_probability"].as_f64().expect("P_s");
        assert!((ps - p).abs() <= half_digit, "{age}");
        // The rate scale brings P_s to 5 %: exp(−s λ_t T) = 0.05.
        let s = age["rate_scale_at_5_percent"].as_f64().expect("s");
        let t = age["age_years"].as_f64().expect("T");
        assert!(((-s * rate * t).exp() - 0.05).abs() < 1e-12, "{age}");
    }
    let rock = &doc["rocks"][0];
    assert!(rock["extrapolated_share"].as_f64().expect("share") < 1e-3);
    assert!(
        (rock["mean_years_between_topplings"]
            .as_f64()
            .expect("years")
            * rate
            - 1.0)
            .abs()
            < 1e-12
    );
}

#[test]
fn an_uncertain_age_and_several_rocks() {
    let hazard = power_law(2.5, &[0.05, 0.1, 0.2, 0.4, 0.8, 1.6]);
    // A uniform age: E[exp(−λT)] = (e^(−λa) − e^(−λb))/(λ(b − a)).
    let doc = run(json!({"kind": "survival", "hazard": hazard,
        "fragility": {"median_g": 0.38, "beta": 0.38},
        "age_years": {"dist": "uniform", "min": 5000, "max": 15000}}));
    let rate = doc["annual_toppling_rate"].as_f64().expect("rate");
    let expected = ((-rate * 5e3).exp() - (-rate * 15e3).exp()) / (rate * 1e4);
    let d = &doc["age_distribution"];
    let ps = d["survival_probability"].as_f64().expect("P_s");
    assert!((ps / expected - 1.0).abs() < 1e-10, "{ps} vs {expected}");
    assert_eq!(d["median_age_years"].as_f64(), Some(10_000.0));
    assert!(doc.get("ages").is_none());
    // Two rocks: each its own figures, the joint probability their product.
    let doc = run(
        json!({"kind": "survival", "hazard": power_law(2.5, &[0.05, 0.4, 1.6]),
        "rocks": [
            {"name": "Grass Valley", "fragility": {"median_g": 0.38, "beta": 0.38}, "age_years": 10000},
            {"name": "Lovejoy", "fragility": {"median_g": 0.6, "beta": 0.3},
             "age_years": {"dist": "lognormal", "median": 15000, "beta": 0.2}}]}),
    );
    let rocks = doc["rocks"].as_array().expect("rocks");
    assert_eq!(rocks.len(), 2);
    let p0 = rocks[0]["ages"][0]["survival_probability"]
        .as_f64()
        .expect("p0");
    let p1 = rocks[1]["age_distribution"]["survival_probability"]
        .as_f64()
        .expect("p1");
    let joint = doc["joint"]["survival_probability"]
        .as_f64()
        .expect("joint");
    assert!((joint - p0 * p1).abs() < 1e-15);
    // The stronger rock (higher median) topples less often.
    assert!(rocks[1]["annual_toppling_rate"].as_f64() < rocks[0]["annual_toppling_rate"].as_f64());
    let s = doc["joint"]["rate_scale_at_5_percent"].as_f64().expect("s");
    assert!(
        s > 0.0
            && s < rocks[0]["ages"][0]["rate_scale_at_5_percent"]
                .as_f64()
                .expect("s0")
    );
    assert!(doc.get("annual_toppling_rate").is_none());
}

#[test]
fn a_bad_survival_spec_names_its_field() {
    let base = json!({"kind": "survival", "hazard": {"im": "pga_g", "points": [[0.1, 1e-2], [1.0, 1e-5]]},
                      "fragility": {"median_g": 0.4, "beta": 0.3}, "age_years": 1e4});
    let with = |path: &str, v: Value| {
        let mut s = base.clone();
        match s.pointer_mut(path) {
            Some(slot) => *slot = v,
            None => {
                let (parent, key) = path.rsplit_once('/').expect("path");
                s.pointer_mut(if parent.is_empty() { "" } else { parent })
                    .and_then(Value::as_object_mut)
                    .expect("parent")
                    .insert(key.to_string(), v);
            }
        }
        s
    };
    let cases = [
        (with("/hazard/im", json!("sa_g")), "/hazard/im"),
        (
            with("/hazard/points", json!([[0.1, 1e-2]])),
            "/hazard/points",
        ),
        (
            with("/hazard/points", json!([[0.1, 1e-2], [0.2, 2e-2]])),
            "/hazard/points/1",
        ),
        (
            with("/hazard/points", json!([[0.1, 1e-2], [-0.2, 1e-3]])),
            "/hazard/points/1",
        ),
        (with("/fragility/beta", json!(-0.1)), "/fragility/beta"),
        (
            with("/fragility/median_g", json!(0.0)),
            "/fragility/median_g",
        ),
        (with("/fragility/median", json!(0.4)), "/fragility/median"),
        (
            with(
                "/fragility",
                json!({"job": "01a20c35-0ff0-7eab-bb8e-86d14f37f92a"}),
            ),
            "/fragility/job",
        ),
        (with("/age_years", json!(-5)), "/age_years"),
        (with("/age_years", json!([1000, 0])), "/age_years/1"),
        (
            with(
                "/age_years",
                json!({"dist": "normal", "mean": 1e4, "sd": 2e3}),
            ),
            "/age_years/min",
        ),
        (with("/age_years", json!("old")), "/age_years"),
        (with("/rocks", json!([])), "/fragility"),
        (
            json!({"kind": "survival", "hazard": base["hazard"].clone(),
                   "rocks": [{"fragility": {"median_g": 0.4, "beta": 0.3}, "age_years": [1e3, 1e4]},
                             {"fragility": {"median_g": 0.5, "beta": 0.3}, "age_years": 1e4}]}),
            "/rocks/0/age_years",
        ),
        (
            json!({"kind": "survival", "hazard": {"im": "pgv_m_s", "points": [[0.1, 1e-2], [1.0, 1e-5]]},
                   "fragility": {"median_g": 0.4, "beta": 0.3}, "age_years": 1e4}),
            "/fragility/median_g",
        ),
    ];
    for (spec, pointer) in cases {
        let e = Job::from_value(&spec).expect_err("refused");
        assert_eq!(e.pointer, pointer, "{spec}: {}", e.message);
    }
}
