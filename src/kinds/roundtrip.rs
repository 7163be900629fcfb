//! Result documents read back into their types: every kind's document, as
//! [`Job::run`] writes it, deserialises into its result type and serialises
//! back to the same JSON, key order included; a document with a field of
//! the wrong type is refused.

use serde_json::{Value, json};

use super::{Job, JobResult};
use crate::spectrum::Control;

/// The document of `spec`, run as the CLI and the service run it.
fn run(spec: &Value) -> (Job, Value) {
    let job = Job::from_value(spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
    let doc = job
        .run(&Control::default())
        .unwrap_or_else(|e| panic!("{spec}: {e}"));
    (job, doc)
}

/// `doc` read as the result type of its kind ([`JobResult::from_value`])
/// and written back: the same value and the same text.
fn same_after_roundtrip(doc: &Value) -> Result<(), String> {
    let typed = JobResult::from_value(doc.clone()).map_err(|e| format!("reading: {e}"))?;
    let back = serde_json::to_value(&typed).map_err(|e| format!("writing: {e}"))?;
    if &back != doc {
        return Err(format!("another value:\n{doc}\n{back}"));
    }
    // Key order too: what a client or a golden file sees.
    let (text, again) = (doc.to_string(), back.to_string());
    if text != again {
        return Err(format!("another text:\n{text}\n{again}"));
    }
    let read: Value = serde_json::from_str(&text).map_err(|e| format!("from text: {e}"))?;
    let from_text = JobResult::from_value(read).map_err(|e| format!("from text: {e}"))?;
    let again = serde_json::to_string(&from_text).map_err(|e| format!("writing: {e}"))?;
    if text != again {
        return Err(format!("another text from text:\n{text}\n{again}"));
    }
    Ok(())
}

fn spec_file(text: &str) -> Value {
    serde_json::from_str(text).expect("a spec of specs/ is JSON")
}

/// A small record: a one-sine pulse of 0.5 g, 1 s, sampled at 0.01 s.
fn record(unit_peak: f64) -> Vec<f64> {
    (0..=100)
        .map(|k| unit_peak * (std::f64::consts::TAU * k as f64 / 100.0).sin())
        .collect()
}

/// Specs of every kind: those of specs/, and variants (every pulse family,
/// both formulations, records, several rocks, distributions, warnings).
fn specs() -> Vec<Value> {
    let block = json!({"alpha": 0.25, "p": 2.14, "eta": 0.9});
    let mut out = vec![
        spec_file(include_str!("../../specs/fig7_linear_exact.json")),
        spec_file(include_str!("../../specs/locomotive_nonlinear.json")),
        spec_file(include_str!("../../specs/locomotive_friction.json")),
        spec_file(include_str!("../../specs/one_cosine_friction.json")),
        spec_file(include_str!("../../specs/point_reyes_forensic.json")),
        spec_file(include_str!("../../specs/point_reyes_forensic_record.json")),
        spec_file(include_str!("../../specs/record_spectrum_one_sine.json")),
        spec_file(include_str!("../../specs/survival_power_law.json")),
        spec_file(include_str!("../../specs/pbr_fragility.json")),
    ];
    let pulses = [
        json!({"type": "one_sine"}),
        json!({"type": "cn", "n": 2}),
        json!({"type": "ricker", "symmetric": false}),
        json!({"type": "mavroeidis_papageorgiou", "gamma": 2.5, "nu": 90}),
    ];
    for pulse in &pulses {
        let mut with_axes = pulse.clone();
        with_axes["omega_ratio"] = json!(3.0);
        with_axes["a_p_alpha_g"] = json!(2.5);
        out.push(
            json!({"kind": "time_history", "block": block, "pulse": with_axes,
                        "outputs": {"series": 20}}),
        );
        out.push(json!({"kind": "spectrum", "block": block, "pulse": pulse,
                        "omega_ratio": [1.0, 4.0], "a_max_alpha_g": 8}));
        out.push(
            json!({"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "mu": 0.4},
                        "pulse": pulse, "omega_ratio": 3.0, "a_alpha_g": [1.5, 6.0]}),
        );
    }
    out.extend([
        // Linear, closed form; no impacts listed; a duration.
        json!({"kind": "time_history", "block": block, "formulation": "linear",
               "pulse": {"type": "one_cosine", "omega_ratio": 2.0, "a_p_alpha_g": 1.5},
               "outputs": {"impacts": false, "reactions": false, "duration": 4.0}}),
        // Lift-off: a null friction demand.
        json!({"kind": "time_history", "block": block,
               "pulse": {"type": "one_cosine", "omega_ratio": 1.0, "a_p_alpha_g": 6.0},
               "outputs": {"series": 30}}),
        // A block in millimetres: an input warning.
        json!({"kind": "time_history", "block": {"b": 600, "h": 1200},
               "pulse": {"type": "rectangular", "duration_s": 0.5, "a_p_g": 0.5}}),
        // A record that never rocks the block: a motion warning.
        json!({"kind": "time_history", "block": block, "formulation": "linear",
               "ground_motion": {"dt": 0.01, "unit": "g", "acc": record(0.1)}}),
        json!({"kind": "time_history", "block": block,
               "ground_motion": {"dt": 0.01, "unit": "m/s2", "acc": record(6.0)},
               "solver": {"method": "dopri5", "rtol": 1e-8}}),
        // On a Coulomb floor, the pure-rocking spectrum beside it.
        json!({"kind": "spectrum", "block": block, "pulse": {"type": "one_sine"},
               "omega_ratio": [3.0], "a_max_alpha_g": 4, "tolerance": 1e-3,
               "scan_step_alpha_g": 0.05, "contact": {"model": "coulomb", "mu": 0.3},
               "no_sliding_beside": true}),
        // A tiny block: a spectrum with warnings.
        json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 300}, "formulation": "linear",
               "pulse": {"type": "half_sine"}, "omega_ratio": {"from": 1, "to": 3, "steps": 3}}),
        json!({"kind": "record_spectrum", "block": {"alpha": 0.2},
               "ground_motion": {"dt": 0.01, "unit": "g", "acc": record(0.5)},
               "R_m": [0.5, 2.0], "pga_g": {"to": 1.5}, "formulation": "linear"}),
        json!({"kind": "forensic", "pulse": {"type": "cn", "n": 2}, "formulation": "linear",
               "observations": [{"b": 0.3, "h": 1.2, "overturned": true},
                                {"name": "kiosk", "block": {"alpha": 0.3, "p": 2.0}, "overturned": false}],
               "omega_p": [3.0, 6.0], "a_p_g": {"from": 0.1, "to": 2.0}}),
        json!({"kind": "survival",
               "hazard": {"im": "pgv_m_s", "points": [[0.1, 0.01], [0.5, 1e-4], [1.0, 1e-5]]},
               "rocks": [{"name": "a", "fragility": {"median": 0.6, "beta": 0.3}, "age_years": 12000},
                         {"fragility": {"median": 0.4, "beta": 0.0},
                          "age_years": {"dist": "lognormal", "median": 8000, "beta": 0.2}}]}),
        json!({"kind": "survival", "hazard": {"im": "pga_g", "points": [[0.1, 0.01], [1.0, 1e-5]]},
               "fragility": {"median_g": 0.5, "beta": 0.4},
               "age_years": {"dist": "uniform", "min": 1000, "max": 5000}}),
        json!({"kind": "fragility",
               "block": {"alpha": {"dist": "uniform", "min": 0.2, "max": 0.3}, "p": 2.0, "eta": 0.85},
               "pulse": {"type": "ricker", "omega_ratio": {"dist": "normal", "mean": 3.0, "sd": 0.3, "min": 1.0}},
               "im": "pgv_m_s", "stripes": [0.2, 0.5, 1.0], "samples": 40, "seed": 7}),
        // A suite whose first record is strong: a warning on a fragility.
        json!({"kind": "fragility", "block": {"b": 0.4, "h": 1.2}, "formulation": "linear",
               "ground_motions": [{"name": "strong", "dt": 0.01, "unit": "g", "acc": record(2.5)},
                                  {"dt": 0.01, "unit": "g", "acc": record(0.3)}],
               "stripes": {"from": 0.1, "to": 0.6, "steps": 3}, "samples": 30}),
    ]);
    out
}

#[test]
fn every_kind_of_result_reads_back_into_its_type_unchanged() {
    let mut kinds = std::collections::BTreeSet::new();
    let mut warned = std::collections::BTreeSet::new();
    for spec in specs() {
        let (job, doc) = run(&spec);
        kinds.insert(job.kind());
        if doc
            .get("warnings")
            .and_then(Value::as_array)
            .is_some_and(|w| !w.is_empty())
        {
            warned.insert(job.kind());
        }
        assert!(doc.get("engine").is_some(), "{spec}");
        if let Err(e) = same_after_roundtrip(&doc) {
            panic!("{spec}: {e}");
        }
    }
    assert_eq!(kinds.len(), super::KINDS.len(), "{kinds:?}");
    for kind in ["time_history", "spectrum", "fragility"] {
        assert!(warned.contains(kind), "no {kind} with warnings: {warned:?}");
    }
}

#[test]
fn a_normalised_spec_reads_back_into_its_job_type() {
    for spec in specs() {
        let job = Job::from_value(&spec).expect("valid");
        let value = serde_json::to_value(&job).expect("serialises");
        let same = |back: Value| {
            assert_eq!(back, value, "{spec}");
            assert_eq!(back.to_string(), value.to_string());
        };
        let read = Job::from_normalised(job.job_kind(), value.clone())
            .unwrap_or_else(|e| panic!("{spec}: {e}"));
        assert_eq!(read, job);
        same(serde_json::to_value(read).unwrap_or_default());
    }
}

/// `doc` with the value at JSON pointer `at` replaced by `v`.
fn with(doc: &Value, at: &str, v: Value) -> Value {
    let mut doc = doc.clone();
    match doc.pointer_mut(at) {
        Some(slot) => *slot = v,
        None => panic!("no {at} in {doc}"),
    }
    doc
}

/// A result document of `kind`, from `spec`, and changes that give one of
/// its fields a value of the wrong type: (pointer, wrong value).
struct WrongTypes {
    kind: &'static str,
    spec: Value,
    changes: Vec<(&'static str, Value)>,
}

/// The wrong types tried on the results of the pulse kinds.
fn wrong_types_of_pulse_kinds() -> Vec<WrongTypes> {
    vec![
        WrongTypes {
            kind: "time_history",
            spec: json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
                         "pulse": {"type": "cn", "n": 2, "omega_ratio": 3.0, "a_p_alpha_g": 2.5}}),
            changes: vec![
                ("/kind", json!("spectrum")),
                ("/rocked", json!("yes")),
                ("/impact_count", json!(-1)),
                ("/numerics/steps_accepted", json!(1.5)),
                ("/ground_peaks", Value::Null),
                ("/spec/formulation", json!("quadratic")),
                ("/spec/formulation", json!("Linear")),
                ("/spec/solver/method", json!("euler")),
                ("/spec/pulse/type", json!("square")),
                ("/spec/pulse/n", json!("two")),
                ("/spec/block/alpha", json!("0.25")),
                ("/engine/name", json!(1)),
            ],
        },
        WrongTypes {
            kind: "spectrum",
            spec: json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14}, "pulse": {"type": "one_sine"},
                         "formulation": "linear", "omega_ratio": [2.0], "a_max_alpha_g": 6}),
            changes: vec![
                ("/kind", json!("time_history")),
                ("/spectrum/0/transitions/0/bracket", json!([1.0])),
                ("/spectrum/0/min_overturn_alpha_g", json!("none")),
                ("/numerics/simulations", json!(null)),
                ("/spec/pulse", json!({"type": "one_sine", "n": 1})),
            ],
        },
        WrongTypes {
            kind: "friction_spectrum",
            spec: json!({"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14},
                         "pulse": {"type": "one_cosine"}, "omega_ratio": 4.0, "a_alpha_g": [2.0]}),
            changes: vec![
                ("/kind", json!(7)),
                ("/points/0/overturned", json!(0)),
                ("/spec/a_alpha_g", json!(2.0)),
            ],
        },
        WrongTypes {
            kind: "forensic",
            spec: json!({"kind": "forensic", "pulse": {"type": "one_sine"},
                         "observations": [{"b": 0.3, "h": 1.2, "overturned": true}],
                         "frequency_hz": [1.0], "a_p_g": {"from": 0.1, "to": 1.0}}),
            changes: vec![
                ("/excitation", json!("record")),
                ("/formulation", json!(true)),
                ("/bounds/min_g", json!([0.1])),
                ("/observations/0/overturned", json!("true")),
            ],
        },
    ]
}

/// The wrong types tried on the results of record spectra, survival and
/// fragility.
fn wrong_types_of_record_and_probability_kinds() -> Vec<WrongTypes> {
    vec![
        WrongTypes {
            kind: "record_spectrum",
            spec: json!({"kind": "record_spectrum", "block": {"alpha": 0.2},
                         "ground_motion": {"dt": 0.01, "unit": "g", "acc": record(0.5)},
                         "p": [2.0], "scale": {"to": 3.0}}),
            changes: vec![
                ("/spec/ground_motion/unit", json!("g")),
                ("/spec/ground_motion/acc/3", json!("0.1")),
                ("/record/samples", json!(-3)),
            ],
        },
        WrongTypes {
            kind: "survival",
            spec: json!({"kind": "survival", "hazard": {"im": "pga_g", "points": [[0.1, 0.01], [1.0, 1e-5]]},
                         "fragility": {"median_g": 0.5, "beta": 0.4}, "age_years": 1000}),
            changes: vec![
                ("/im", json!("pga")),
                ("/spec/hazard/im", json!("PGA_G")),
                ("/spec/rocks/0/age_years", json!("old")),
                ("/rocks/0/ages/0/survival_probability", json!({})),
            ],
        },
        WrongTypes {
            kind: "fragility",
            spec: json!({"kind": "fragility", "block": {"alpha": 0.25, "p": 2.0},
                         "pulse": {"type": "one_sine", "omega_ratio": 3.0}, "stripes": [0.3, 0.6],
                         "samples": 10}),
            changes: vec![
                ("/kind", json!("Fragility")),
                ("/im", Value::Null),
                ("/stripes/0/n", json!(-10)),
                ("/spec/block/alpha", json!({"dist": "cauchy"})),
                ("/spec/seed", json!("1")),
            ],
        },
    ]
}

#[test]
fn a_result_with_a_field_of_the_wrong_type_is_refused() {
    let cases = wrong_types_of_pulse_kinds()
        .into_iter()
        .chain(wrong_types_of_record_and_probability_kinds());
    for WrongTypes {
        kind,
        spec,
        changes,
    } in cases
    {
        let (job, doc) = run(&spec);
        assert_eq!(job.kind(), kind);
        assert_eq!(same_after_roundtrip(&doc), Ok(()), "{kind}");
        for (at, v) in changes {
            let bad = with(&doc, at, v.clone());
            let read = same_after_roundtrip(&bad);
            assert!(
                read.as_ref().is_err_and(|e| e.starts_with("reading: ")),
                "{kind}: {at} = {v} was read: {read:?}"
            );
        }
        // Another kind's document is not this kind's.
        for other in super::KINDS.iter().filter(|k| **k != kind) {
            let as_other = with(&doc, "/kind", json!(other));
            assert!(
                JobResult::from_value(as_other).is_err(),
                "{kind} read as {other}"
            );
        }
    }
}
