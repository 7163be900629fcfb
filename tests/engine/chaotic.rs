//! Where the outcome alternates finer than the scan resolves: under the
//! project's broadband record (specs/records/valley_station_000.at2) a
//! cabinet's forensic answer and a record spectrum claim certainty only
//! where time histories at random scales inside the certain intervals and
//! gaps agree, and report the chaotic stretch as mixed zones whose fraction
//! agrees with 60 evenly spaced time histories.

use serde_json::{Value, json};
use topple::kinds::Job;
use topple::records::{ReadOptions, read};
use topple::spectrum::Control;

/// The record's samples, m/s², and its dt.
fn valley() -> (f64, Vec<f64>) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/specs/records/valley_station_000.at2"
    );
    let text = std::fs::read_to_string(path).expect("the record ships with the project");
    let file = read(&text, &ReadOptions::default()).expect("reads");
    (file.dt, file.acc)
}

fn run(spec: &Value) -> Value {
    Job::from_value(spec)
        .expect("valid")
        .run(&Control::new())
        .expect("runs")
}

/// Whether the block overturns under the record scaled by `s`.
fn overturns(block: &Value, (dt, acc): &(f64, Vec<f64>), s: f64) -> bool {
    let acc: Vec<f64> = acc.iter().map(|a| a * s).collect();
    let spec = json!({"kind": "time_history", "block": block, "formulation": "nonlinear",
                      "ground_motion": {"dt": dt, "acc": acc, "unit": "m/s2"},
                      "outputs": {"reactions": false, "impacts": false}});
    run(&spec)["overturned"].as_bool().expect("flag")
}

fn pairs(v: &Value) -> Vec<[f64; 2]> {
    v.as_array()
        .expect("intervals")
        .iter()
        .map(|p| [p[0].as_f64().expect("lo"), p[1].as_f64().expect("hi")])
        .collect()
}

fn zones(v: &Value) -> Vec<(f64, f64, f64)> {
    v.as_array()
        .expect("zones")
        .iter()
        .map(|z| {
            (
                z["from"].as_f64().expect("from"),
                z["to"].as_f64().expect("to"),
                z["fraction"].as_f64().expect("fraction"),
            )
        })
        .collect()
}

/// `[lo, hi]` without `certain` and the zones: the certain gaps.
fn gaps(certain: &[[f64; 2]], mixed: &[(f64, f64, f64)], lo: f64, hi: f64) -> Vec<[f64; 2]> {
    let mut cuts: Vec<[f64; 2]> = certain.to_vec();
    cuts.extend(mixed.iter().map(|&(a, b, _)| [a, b]));
    cuts.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let (mut out, mut at) = (Vec::new(), lo);
    for [a, b] in cuts {
        if a > at {
            out.push([at, a]);
        }
        at = at.max(b);
    }
    if hi > at {
        out.push([at, hi]);
    }
    out
}

/// `n` points uniform over the total width of `set` (a fixed stream).
fn points(set: &[[f64; 2]], n: usize, seed: u64) -> Vec<f64> {
    let total: f64 = set.iter().map(|[a, b]| b - a).sum();
    let mut state = seed;
    (0..n)
        .filter_map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let mut x = total * ((state >> 11) as f64 / (1u64 << 53) as f64);
            for &[a, b] in set {
                if x <= b - a {
                    return Some(a + x);
                }
                x -= b - a;
            }
            None
        })
        .collect()
}

/// Checks `certain` (where the block does what `agrees` says) and its gaps
/// (where it does not) at random scales, and the widest zone's fraction of
/// `agrees` against 60 evenly spaced time histories.
fn check(
    record: &(f64, Vec<f64>),
    block: &Value,
    agrees: bool,
    certain: &[[f64; 2]],
    mixed: &[(f64, f64, f64)],
    range: [f64; 2],
) {
    let inside = points(certain, 24, 7);
    let outside = points(&gaps(certain, mixed, range[0], range[1]), 24, 11);
    for &s in &inside {
        assert_eq!(overturns(block, record, s), agrees, "scale {s} inside");
    }
    for &s in &outside {
        assert_ne!(overturns(block, record, s), agrees, "scale {s} in a gap");
    }
    let &(from, to, fraction) = mixed
        .iter()
        .max_by(|a, b| (a.1 - a.0).total_cmp(&(b.1 - b.0)))
        .expect("a chaotic stretch is a mixed zone");
    let n = 60;
    let seen = (0..n)
        .filter(|k| {
            let s = from + (*k as f64 + 0.5) * (to - from) / n as f64;
            overturns(block, record, s) == agrees
        })
        .count() as f64
        / n as f64;
    assert!(
        (seen - fraction).abs() <= 0.15,
        "zone [{from}, {to}]: fraction {fraction}, time histories {seen}"
    );
}

#[test]
fn a_forensic_answer_under_a_broadband_record_is_certain_only_where_verified() {
    let record = valley();
    let cabinet = json!({"alpha": 0.24497866312686414, "p": 2.6685, "eta": 0.9});
    let result = run(&json!({
        "kind": "forensic", "formulation": "nonlinear",
        "ground_motion": {"dt": record.0, "acc": record.1, "unit": "m/s2"},
        "observations": [{"name": "cabinet", "block": cabinet, "overturned": true}],
        "scale": {"from": 0.05, "to": 1.2}}));
    let per = &result["per_observation"][0];
    let certain = pairs(&per["consistent_scale"]);
    let mixed = zones(&per["mixed_scale"]);
    // The chaotic stretch above the lowest overturning is one or a few
    // zones, not a hundred slivers called certain.
    assert!(!mixed.is_empty(), "{result}");
    let below = certain.iter().filter(|i| i[0] < mixed[0].1).count();
    assert!(
        below <= 5,
        "{below} certain intervals below the first zone's end"
    );
    // The combined answer of one observation is the observation's.
    assert_eq!(pairs(&result["consistent_scale"]), certain);
    assert_eq!(zones(&result["mixed_scale"]), mixed);
    let cost = &result["numerics"];
    assert!(cost["verification_simulations"].as_u64().expect("count") > 0);
    check(&record, &cabinet, true, &certain, &mixed, [0.05, 1.2]);
}

#[test]
fn a_record_spectrum_under_a_broadband_record_is_certain_only_where_verified() {
    let record = valley();
    let result = run(&json!({
        "kind": "record_spectrum", "block": {"alpha": 0.245, "eta": 0.9},
        "R_m": [1.26], "scale": {"from": 0.0, "to": 1.3},
        "ground_motion": {"dt": record.0, "acc": record.1, "unit": "m/s2"}}));
    let size = &result["spectrum"][0];
    let block = json!({"alpha": 0.245, "p": size["p"], "eta": 0.9});
    // Certain overturning bands: the transitions' bands without the zones.
    let mut bands = Vec::new();
    let mut up = None;
    for t in size["transitions"].as_array().expect("transitions") {
        match t["direction"].as_str() {
            Some("up") => up = t["scale"].as_f64(),
            Some("down") => bands.extend(up.take().map(|u| [u, t["scale"].as_f64().unwrap_or(u)])),
            _ => {}
        }
    }
    bands.extend(up.map(|u| [u, 1.3]));
    let mixed = zones(&size["mixed"]);
    let certain = gaps(&[], &mixed, 0.0, 1.3)
        .into_iter()
        .flat_map(|[a, b]| {
            bands
                .iter()
                .map(move |&[c, d]| [a.max(c), b.min(d)])
                .filter(|[lo, hi]| hi > lo)
        })
        .collect::<Vec<_>>();
    let threshold = size["threshold_scale"].as_f64().expect("threshold");
    check(&record, &block, true, &certain, &mixed, [threshold, 1.3]);
    // The lowest overturning is named where it lies; the certain one is
    // at or above it, never inside a zone.
    let low = size["min_overturn_scale"].as_f64().expect("overturns");
    let sure = size["min_certain_overturn_scale"]
        .as_f64()
        .expect("certain");
    assert!(sure >= low);
    assert!(mixed.iter().all(|&(a, b, _)| !(a < sure && sure < b)));
    match size["min_overturn_in"].as_str() {
        Some("mixed") => assert!(size["min_overturn_zone"]["fraction"].is_f64()),
        Some("band") => assert!(size["min_overturn_zone"].is_null()),
        other => panic!("{other:?}"),
    }
}
