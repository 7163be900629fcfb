//! What the tables' tests share: the specs whose results they tabulate,
//! and ways to read a table.

use crate::kinds::JobResult;
use crate::kinds::time_history::TimeHistoryResult;
use crate::plot::tests::typed;

pub(crate) const TIME_HISTORY: &str = r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":3,"a_p_alpha_g":2.5},"outputs":{"series":20}}"#;
pub(crate) const SPECTRUM: &str = r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":[2,4],"a_max_alpha_g":6}"#;
pub(crate) const FRICTION: &str = r#"{"kind":"friction_spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"omega_ratio":3,"a_alpha_g":[1.5,3]}"#;
pub(crate) const FORENSIC: &str = r#"{"kind":"forensic","pulse":{"type":"one_sine"},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false}],"frequency_hz":{"from":0.5,"to":2,"steps":3},"a_p_g":{"from":0.05,"to":2.0}}"#;
pub(crate) const FORENSIC_RECORD: &str = r#"{"kind":"forensic","ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false}],"pga_g":{"from":0.05,"to":2.0}}"#;
pub(crate) const RECORD_SPECTRUM: &str = r#"{"kind":"record_spectrum","block":{"alpha":0.2},"p":[1.5,3],"scale":{"from":0.5,"to":3},"ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]}}"#;
pub(crate) const SURVIVAL: &str = r#"{"kind":"survival","hazard":{"im":"pga_g","points":[[0.1,0.01],[0.5,0.0005],[1.0,0.00005]]},"fragility":{"median_g":0.4,"beta":0.4},"age_years":[1000]}"#;
pub(crate) const FRAGILITY: &str = r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","omega_ratio":3},"stripes":[0.2,0.4],"samples":8,"seed":1}"#;

pub(crate) fn lines(csv: &str) -> Vec<&str> {
    csv.lines().collect()
}

/// `x` as serde_json writes it.
pub(crate) fn json_text<T: serde::Serialize>(x: &T) -> String {
    serde_json::to_string(x).expect("json")
}

/// The table of `result`.
pub(crate) fn csv_of(result: &JobResult) -> String {
    super::to_csv(result).expect("a table")
}

/// `x` as a table writes it.
pub(crate) fn cell(x: &f64) -> String {
    super::number(*x)
}

/// The time history of [`TIME_HISTORY`].
pub(crate) fn time_history_result() -> TimeHistoryResult {
    match typed(TIME_HISTORY) {
        JobResult::TimeHistory(r) => *r,
        other => panic!("not a time history: {:?}", other.job_kind()),
    }
}

/// The table of time history `r`.
pub(crate) fn th_table(r: &TimeHistoryResult) -> String {
    csv_of(&JobResult::TimeHistory(Box::new(r.clone())))
}

#[test]
fn unknown_kinds_have_no_table() {
    // A table is made of a result of a known kind; a document of another
    // kind is not read into one.
    assert!(JobResult::from_value(serde_json::json!({"kind": "teapot"})).is_err());
}
