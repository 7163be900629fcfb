//! Every kind of the registry: an example job of each validates, has a size
//! estimate, runs, and its result has a table and a figure. A kind added
//! without an example (`Kind::EXAMPLE`), a table or a figure does not
//! compile.

use serde_json::{Value, json};
use topple::kinds::{Job, JobKind, JobResult};
use topple::spectrum::Control;

/// A small job of `kind`: its `Kind::EXAMPLE`.
fn example(kind: JobKind) -> &'static str {
    kind.example()
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
        let figure = typed
            .figure(None)
            .unwrap_or_else(|e| panic!("{kind:?}: {e}"));
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
    let svg = typed.figure(None).expect("svg");
    assert!(svg.contains("lift-off (f_z → 0)"), "legend");
    assert!(
        !svg.contains("e9"),
        "a lift-off point drawn at its huge value"
    );
}
