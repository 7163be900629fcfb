//! Every kind of the registry: an example job of each validates, has a size
//! estimate, runs, and its result has a table and a figure. A kind added
//! without an example, a table or a figure does not compile.

use serde_json::{Value, json};
use topple::jobs::{Job, JobKind, JobResult};
use topple::spectrum::Control;

/// A small job of `kind` (exhaustive: a new kind needs one).
fn example(kind: JobKind) -> &'static str {
    match kind {
        JobKind::TimeHistory => {
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":3,"a_p_alpha_g":2.5},"outputs":{"series":20}}"#
        }
        JobKind::Spectrum => {
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":[2,4],"a_max_alpha_g":6}"#
        }
        JobKind::FrictionSpectrum => {
            r#"{"kind":"friction_spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"omega_ratio":3,"a_alpha_g":[1.5,3]}"#
        }
        JobKind::Forensic => {
            r#"{"kind":"forensic","pulse":{"type":"one_sine"},"observations":[{"b":0.6,"h":1.2,"overturned":false}],"frequency_hz":{"from":0.5,"to":2,"steps":3},"a_p_g":{"from":0.05,"to":2.0}}"#
        }
        JobKind::RecordSpectrum => {
            r#"{"kind":"record_spectrum","block":{"alpha":0.2},"p":[1.5,3],"scale":{"from":0.5,"to":3},"ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]}}"#
        }
        JobKind::Survival => {
            r#"{"kind":"survival","hazard":{"im":"pga_g","points":[[0.1,0.01],[0.5,0.0005],[1.0,0.00005]]},"fragility":{"median_g":0.4,"beta":0.4},"age_years":[1000]}"#
        }
        JobKind::Fragility => {
            r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","omega_ratio":3},"stripes":[0.2,0.4],"samples":8,"seed":1}"#
        }
    }
}

/// Every kind validates, is sized (a positive estimate), runs, and its
/// result has a table and a figure.
#[test]
fn every_kind_has_an_estimate_a_table_and_a_figure() {
    for kind in JobKind::ALL {
        let job = Job::parse(example(*kind)).unwrap_or_else(|e| panic!("{kind:?}: {e}"));
        assert_eq!(job.job_kind(), *kind);
        assert!(job.size().work > 0.0, "{kind:?} has no estimate");
        let doc = job
            .run(&Control::default())
            .unwrap_or_else(|e| panic!("{kind:?}: {e}"));
        assert_eq!(doc["kind"], kind.name());
        let typed = JobResult::from_value(doc).unwrap_or_else(|e| panic!("{kind:?}: {e}"));
        assert_eq!(typed.job_kind(), *kind);
        let table = topple::api::csv::to_csv(&typed).expect("a table");
        assert!(table.lines().count() >= 2, "{kind:?}: {table}");
        let figure = topple::plot::svg(&typed).unwrap_or_else(|e| panic!("{kind:?}: {e}"));
        assert!(figure.starts_with("<svg"), "{kind:?}");
    }
}

fn run(spec: &Value) -> Value {
    Job::from_value(spec)
        .expect("valid")
        .run(&Control::default())
        .expect("runs")
}

/// A friction spectrum's lift-off point: null demand, flagged, and marked in
/// its table and figure.
#[test]
fn a_lift_off_point_is_null_flagged_and_marked_in_csv_and_svg() {
    let doc = run(&json!({"kind": "friction_spectrum",
        "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_cosine"}, "omega_ratio": 1.0,
        "a_alpha_g": [2.0, 6.0]}));
    let lifted = &doc["points"][1];
    assert_eq!(lifted["peak_friction_demand"], Value::Null, "{lifted}");
    assert_eq!(lifted["peak_over_tan_alpha"], Value::Null);
    assert_eq!(lifted["lift_off"], json!(true));
    let tl = lifted["lift_off_time"].as_f64().expect("time");
    assert!((tl - 0.410_511_6).abs() < 1e-6, "{tl}");
    let typed = JobResult::from_value(doc).expect("a friction spectrum");
    let csv = topple::api::csv::to_csv(&typed).expect("a table");
    let header: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    let row: Vec<&str> = csv.lines().nth(2).expect("row").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    assert_eq!(row[col("peak_friction_demand")], "");
    assert_eq!(row[col("lift_off")], "true");
    let svg = topple::plot::svg(&typed).expect("svg");
    assert!(svg.contains("lift-off (f_z → 0)"), "legend");
    assert!(
        !svg.contains("e9"),
        "a lift-off point drawn at its huge value"
    );
}
