//! Vertical ground motion: a constant vertical acceleration a_v is the same
//! block under gravity g + a_v (α kept, p scaled by √((g + a_v)/g)); rocking
//! starts where |ü_g| = (g + ü_v)·k, known in closed form on linear ramps
//! and under a proportional pulse; a ground falling away faster than g ends
//! the history with lift-off at that time; and no vertical motion (a ratio
//! of 0, a record of zeros) is the job without one, result and cache key.

use crate::synthetic::synthetic;
use serde_json::{Value, json};
use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, Record, RecordPair, Response,
    Solver, simulate,
};
use topple::kinds::Job;
use topple::kinds::key::{cache_key, canonical_spec};

const G: f64 = 9.81;

fn block() -> Block {
    Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid block")
}

/// The same block under gravity g + a_v.
fn under_gravity(b: &Block, a_v: f64) -> Block {
    let g2 = b.gravity() + a_v;
    Block::new(
        b.slenderness(),
        b.frequency_parameter() * (g2 / b.gravity()).sqrt(),
        Some(b.restitution()),
        b.friction(),
        Some(g2),
    )
    .expect("valid block")
}

fn dop853() -> Solver {
    Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-12,
        atol: 1e-14,
    }
}

/// The one-sine pulse a_p sin(ω_p t) sampled at t_k = k T/n, k = 0..n.
fn sampled(pulse: &Pulse, n: usize) -> Record {
    let dt = pulse.duration / n as f64;
    let acc: Vec<f64> = (0..=n)
        .map(|k| pulse.amplitude * (pulse.circular_frequency * k as f64 * dt).sin())
        .collect();
    Record::new(acc.into(), dt).expect("valid record")
}

/// The impacts of `r` faster than `v_min`, rad/s: those of the rocking, not
/// of a chattering tail (whose summation starts at a speed that scales with p).
fn rocking_impacts(r: &Response, v_min: f64) -> Vec<f64> {
    r.impacts
        .iter()
        .filter(|i| i.velocity_before.abs() > v_min)
        .map(|i| i.time)
        .collect()
}

#[test]
fn a_constant_vertical_acceleration_is_another_gravity() {
    let b = block();
    let one_sine = |level: f64, ratio: f64| {
        let a = level * b.slenderness() * G;
        sampled(
            &Pulse::new(PulseShape::OneSine, a, ratio * b.frequency_parameter()).expect("valid"),
            400,
        )
    };
    // (Ending at rest: padded with zeros, a record ending elsewhere would
    // ramp down to zero over one more interval.)
    let mut noisy = synthetic(7, 1200, 0.01, 0.6 * G, 0.5, 5.0);
    noisy.push(0.0);
    let noisy = Record::new(noisy.into(), 0.01).expect("valid record");
    // (name, horizontal record): a pulse as a record, overturning or not, and a record.
    let cases = [
        ("one-sine 3 αg, ω/p = 2", one_sine(3.0, 2.0)),
        ("one-sine 8 αg, ω/p = 4", one_sine(8.0, 4.0)),
        ("one-sine 1.6 αg, ω/p = 1", one_sine(1.6, 1.0)),
        ("synthetic record", noisy),
    ];
    let mut compared = 0;
    let mut overturned = 0;
    for (name, h) in &cases {
        for formulation in [Formulation::Linear, Formulation::Nonlinear] {
            for a_v in [0.3 * G, -0.3 * G] {
                // A constant vertical record far longer than the motion.
                let n = (120.0 / h.dt()) as usize;
                let v = Record::new(vec![a_v; n].into(), h.dt()).expect("valid");
                let pair = RecordPair::new(h.clone(), v).expect("same dt");
                let mut options = Options::history(dop853());
                options.max_free_impacts = 200;
                let with = simulate(
                    &Problem {
                        block: b,
                        pulse: pair,
                        formulation,
                    },
                    &options,
                )
                .expect("runs");
                let heavier = under_gravity(&b, a_v);
                let reference = simulate(
                    &Problem {
                        block: heavier,
                        pulse: h.clone(),
                        formulation,
                    },
                    &options,
                )
                .expect("runs");
                let what = format!("{name}, {formulation:?}, a_v = {a_v}");
                assert_eq!(with.rocked, reference.rocked, "{what}");
                assert_eq!(with.overturned, reference.overturned, "{what}");
                assert_eq!(with.mode, reference.mode, "{what}");
                assert!(with.lift_off.is_none(), "{what}");
                let (s0, s1) = (with.rocking_start, reference.rocking_start);
                assert!(
                    (s0.unwrap_or(0.0) - s1.unwrap_or(0.0)).abs() < 1e-9,
                    "{what}: {s0:?} {s1:?}"
                );
                let p_max = heavier.frequency_parameter().max(b.frequency_parameter());
                let v_min = 1e-3 * p_max * b.slenderness();
                let (i0, i1) = (
                    rocking_impacts(&with, v_min),
                    rocking_impacts(&reference, v_min),
                );
                assert_eq!(i0.len(), i1.len(), "{what}: {i0:?} {i1:?}");
                for (x, y) in i0.iter().zip(&i1) {
                    assert!((x - y).abs() < 1e-9, "{what}: impact at {x} vs {y}");
                }
                if let (Some(x), Some(y)) = (with.overturn_time, reference.overturn_time) {
                    assert!((x - y).abs() < 1e-9, "{what}: overturn at {x} vs {y}");
                }
                // The friction demand, f_x/f_z, is the heavier block's.
                let demand = |r: &Response| r.friction.as_ref().and_then(|f| f.peak);
                if !with.overturned {
                    let (d0, d1) = (demand(&with), demand(&reference));
                    let (d0, d1) = (d0.expect("followed"), d1.expect("followed"));
                    assert!((d0 - d1).abs() < 1e-9 * d1.max(1.0), "{what}: {d0} {d1}");
                    let (p0, p1) = (with.peak_theta_over_alpha, reference.peak_theta_over_alpha);
                    assert!((p0 - p1).abs() < 1e-9, "{what}: {p0} {p1}");
                }
                // The motion ended before the vertical record did.
                assert!(with.end_time < 119.0, "{what}: {}", with.end_time);
                compared += i0.len();
                overturned += usize::from(with.overturned);
            }
        }
    }
    assert!(compared > 20, "{compared} impacts compared");
    assert!((2..16).contains(&overturned), "{overturned} overturned");
}

#[test]
fn the_demand_under_a_pair_of_records_is_their_densest_sample_and_no_more() {
    // Both components linear between samples: the pieces are followed with
    // the demand's exact rate, the peak located inside a piece. Checked
    // against the demand sampled every 1e-4 s (the series' own reaction
    // ratio, evaluated from the state): never above the reported peak, and
    // within what a 1e-4-s grid can miss of it.
    let b = Block::new(0.2, 2.0, Some(0.9), None, None).expect("valid");
    let h = Record::new(synthetic(3, 1000, 0.01, 0.5 * G, 0.5, 6.0).into(), 0.01).expect("valid");
    for (v_seed, v_peak) in [(5, 0.4 * G), (9, 0.6 * G)] {
        let v = Record::new(
            synthetic(v_seed, 1000, 0.01, v_peak, 1.0, 12.0).into(),
            0.01,
        )
        .expect("valid");
        for formulation in [Formulation::Linear, Formulation::Nonlinear] {
            let problem = Problem {
                block: b,
                pulse: RecordPair::new(h.clone(), v.clone()).expect("same dt"),
                formulation,
            };
            let mut options = Options::history(dop853());
            options.max_free_impacts = 0;
            let coarse = simulate(&problem, &options).expect("runs");
            let end = coarse.end_time;
            options.series_at = Some(
                (0..=(end / 1e-4) as usize)
                    .map(|k| k as f64 * 1e-4)
                    .collect(),
            );
            let fine = simulate(&problem, &options).expect("runs");
            let what = format!("seed {v_seed}, {formulation:?}");
            assert!(coarse.rocked && coarse.lift_off.is_none(), "{what}");
            let f = coarse.friction.as_ref().expect("followed");
            let peak = f.peak.unwrap_or_else(|| {
                panic!("{what}: {f:?} {:?} {}", coarse.overturned, coarse.end_time)
            });
            let series = fine.series.as_ref().expect("a series");
            let sampled = series
                .reaction_ratio
                .as_ref()
                .expect("reactions")
                .iter()
                .flatten()
                .fold(0.0_f64, |m, d| m.max(d.abs()));
            assert!(sampled <= peak * (1.0 + 1e-9), "{what}: {sampled} > {peak}");
            assert!(sampled >= peak * (1.0 - 1e-3), "{what}: {sampled} ≪ {peak}");
        }
    }
}

/// The result of a time-history spec.
fn run(spec: &Value) -> Value {
    let job = Job::from_value(spec).expect("valid spec");
    let Job::TimeHistory(h) = job else {
        panic!("a time history")
    };
    serde_json::to_value(h.run().expect("runs")).expect("serialises")
}

fn history(extra: Value) -> Value {
    let mut spec = json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}});
    for (k, v) in extra.as_object().expect("an object") {
        spec[k] = v.clone();
    }
    spec
}

#[test]
fn rocking_starts_where_the_ground_beats_g_plus_the_vertical() {
    let alpha: f64 = 0.25;
    for (formulation, k) in [("nonlinear", alpha.tan()), ("linear", alpha)] {
        // A ramp ü_g = 2kg·t under a ramp ü_v = −g t/2 on [0, 1] (dt = 1):
        // 2kg t = k(g − g t/2) at t = 0.4, where without the vertical
        // it is 0.5.
        let spec = history(json!({
            "formulation": formulation,
            "ground_motion": {"dt": 1.0, "unit": "m/s2", "acc": [0.0, 2.0 * k * G, 0.0],
                              "vertical": {"acc": [0.0, -0.5 * G], "unit": "m/s2"}}
        }));
        let doc = run(&spec);
        let start = doc["rocking_start"].as_f64().expect("rocks");
        assert!((start - 0.4).abs() < 1e-14, "{formulation}: {start}");
        // A one-sine a sin(ω t) with ü_v = r ü_g: a sin(ω t)(1 − k r) = k g.
        for r in [-1.0, -0.5, 0.5, 1.0] {
            let a = 5.0 * k * G;
            let spec = history(json!({
                "formulation": formulation,
                "pulse": {"type": "one_sine", "omega_p": 6.0, "a_p": a},
                "vertical": {"ratio": r}
            }));
            let doc = run(&spec);
            let start = doc["rocking_start"].as_f64().expect("rocks");
            let expect = (k * G / (1.0 - k * r) / a).asin() / 6.0;
            assert!(
                (start - expect).abs() < 1e-13,
                "{formulation} r = {r}: {start} vs {expect}"
            );
            assert_eq!(
                doc["ground_peaks"]["pga_v_m_s2"].as_f64(),
                Some(a * r.abs())
            );
        }
    }
}

#[test]
fn a_ground_falling_faster_than_g_lifts_the_block_off() {
    // ü_v falls from 0 to −2g over [0, 1]: g + ü_v = 0 at t = 0.5.
    let spec = history(json!({
        "ground_motion": {"dt": 0.25, "unit": "m/s2", "acc": [0.0, 0.5, 1.0, 0.5, 0.0],
                          "vertical": {"acc": [0.0, -0.5 * G, -G, -1.5 * G, -2.0 * G], "unit": "m/s2"}}
    }));
    let doc = run(&spec);
    assert_eq!(doc["lift_off"], json!(true));
    let t = doc["lift_off_time"].as_f64().expect("a time");
    assert!((t - 0.5).abs() < 1e-15, "{t}");
    assert_eq!(doc["overturned"], json!(false));
    assert_eq!(doc["mode"], Value::Null);
    assert_eq!(doc["end_time"].as_f64(), Some(t));
    assert_eq!(doc["peak_friction_demand"], Value::Null);
    let warnings = doc["warnings"].as_array().expect("warnings");
    assert!(
        warnings
            .iter()
            .any(|w| w["kind"] == "lift_off" && w["t"].as_f64() == Some(t)),
        "{warnings:?}"
    );
    // A vertical pulse of its own, −1.5 g cos(ω t'), from t = 0.3: below −g
    // from its start, while the block rocks under the horizontal pulse.
    let spec = history(json!({
        "pulse": {"type": "one_sine", "omega_p": 8.0, "a_p_alpha_g": 6.0},
        "vertical": {"type": "one_cosine", "omega_p": 4.0, "a_p_g": -1.5, "delay_s": 0.3},
        "outputs": {"reactions": false}
    }));
    let doc = run(&spec);
    assert_eq!(doc["rocked"], json!(true));
    assert_eq!(doc["lift_off"], json!(true));
    assert_eq!(doc["lift_off_time"].as_f64(), Some(0.3));
    assert_eq!(doc["overturned"], json!(false));
}

/// `doc` without what varies from run to run (wall times).
fn steady(mut doc: Value) -> Value {
    doc["numerics"]["wall_time_s"] = Value::Null;
    doc["engine"] = Value::Null;
    doc
}

#[test]
fn no_vertical_motion_is_the_job_without_one() {
    let pulse = json!({"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0});
    let acc = synthetic(3, 500, 0.01, 0.5, 0.5, 4.0);
    let record = json!({"dt": 0.01, "unit": "g", "acc": acc});
    let mut zero_record = record.clone();
    zero_record["vertical"] = json!({"acc": vec![0.0; 800], "unit": "g"});
    let mut zero_ratio = record.clone();
    zero_ratio["vertical"] = json!({"ratio": 0.0});
    let pairs = [
        (
            history(json!({"pulse": pulse, "outputs": {"series": 50}})),
            history(json!({"pulse": pulse, "vertical": {"ratio": 0}, "outputs": {"series": 50}})),
        ),
        (
            history(json!({"ground_motion": record})),
            history(json!({"ground_motion": zero_record})),
        ),
        (
            history(json!({"ground_motion": record, "formulation": "linear"})),
            history(json!({"ground_motion": zero_ratio, "formulation": "linear"})),
        ),
    ];
    for (plain, zero) in &pairs {
        let (a, b) = (
            Job::from_value(plain).expect("valid"),
            Job::from_value(zero).expect("valid"),
        );
        assert_eq!(canonical_spec(&a), canonical_spec(&b));
        assert_eq!(cache_key(&a), cache_key(&b));
        assert_eq!(steady(run(plain)), steady(run(zero)));
    }
    // With a vertical motion the key differs and the canonical spec holds it.
    let with = history(json!({"pulse": pulse, "vertical": {"ratio": 0.5}}));
    let job = Job::from_value(&with).expect("valid");
    assert_ne!(
        cache_key(&job),
        cache_key(&Job::from_value(&pairs[0].0).expect("valid"))
    );
    assert!(canonical_spec(&job).contains(r#""vertical":{"ratio":0.5}"#));
}

/// The JSON pointer of the error a spec is refused with.
fn refused_at(spec: &Value) -> String {
    match Job::from_value(spec) {
        Ok(_) => panic!("accepted: {spec}"),
        Err(e) => e.pointer,
    }
}

#[test]
fn vertical_specs_are_checked_field_by_field() {
    let pulse = json!({"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0});
    let record = |vertical: Value| {
        history(
            json!({"ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, 0.0],
                                         "vertical": vertical}}),
        )
    };
    let cases = [
        (
            record(json!({"dt": 0.02, "acc": [0.0, 0.1], "unit": "g"})),
            "/ground_motion/vertical/dt",
        ),
        (
            record(json!({"ratio": 0.5, "acc": [0.0, 0.1]})),
            "/ground_motion/vertical/acc",
        ),
        (
            record(json!({"acc": [0.0, 0.1]})),
            "/ground_motion/vertical/unit",
        ),
        (
            record(json!({"ratio": 1e9})),
            "/ground_motion/vertical/ratio",
        ),
        (
            history(
                json!({"pulse": pulse, "vertical": {"ratio": 0.5}, "formulation": "linear",
                           "solver": {"method": "exact"}}),
            ),
            "/solver/method",
        ),
        (
            history(json!({"pulse": pulse, "vertical": {"ratio": 0.5, "omega_p": 3.0}})),
            "/vertical/omega_p",
        ),
        (
            history(json!({"pulse": pulse, "vertical": {"type": "one_sine", "a_p_g": 0.5}})),
            "/vertical",
        ),
        (
            history(
                json!({"pulse": pulse, "vertical": {"type": "one_sine", "omega_p": 3.0,
                                                        "a_p_g": 0.5, "delay_s": -1}}),
            ),
            "/vertical/delay_s",
        ),
        (
            history(
                json!({"ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3]},
                           "vertical": {"ratio": 0.5}}),
            ),
            "/vertical",
        ),
        (
            json!({"kind": "record_spectrum", "block": {"alpha": 0.2},
                   "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, 0.0],
                                     "vertical": {"ratio": 0.5}},
                   "vertical": {"ratio": 0.5},
                   "R_m": [1.0], "pga_g": {"to": 1.0}}),
            "/ground_motion/vertical",
        ),
    ];
    for (spec, pointer) in &cases {
        let at = refused_at(spec);
        assert!(at.starts_with(pointer), "{spec}: {at} vs {pointer}");
    }
    // The linear formulation with vertical motion defaults to dop853.
    let Job::TimeHistory(h) = Job::from_value(&history(
        json!({"pulse": pulse, "vertical": {"ratio": 0.5}, "formulation": "linear"}),
    ))
    .expect("valid") else {
        panic!("a time history")
    };
    assert_eq!(h.solver.solver().name(), "dop853");
}

/// A spectrum job's result.
fn spectrum(extra: Value) -> Value {
    let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"}, "omega_ratio": [2.0, 5.0], "a_max_alpha_g": 12,
        "scan_step_alpha_g": 0.05, "tolerance": 1e-6});
    for (k, v) in extra.as_object().expect("an object") {
        spec[k] = v.clone();
    }
    let Job::Spectrum(s) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a spectrum")
    };
    serde_json::to_value(s.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises")
}

#[test]
fn a_spectrum_under_a_vertical_ratio_scans_from_the_lowered_threshold_to_lift_off() {
    use topple::dynamics::PulsePair;
    let b = block();
    let alpha = b.slenderness();
    for r in [0.5, -0.5] {
        let doc = spectrum(json!({"vertical": {"ratio": r}}));
        assert_eq!(doc["spec"]["vertical"], json!({"ratio": r}));
        for line in doc["spectrum"].as_array().expect("lines") {
            // Rocking can start where ü_v = r ü_g lightens the block:
            // a_p (1 + |r| tan α) = g tan α.
            let from = line["threshold_alpha_g"].as_f64().expect("threshold");
            let expected = alpha.tan() / alpha / (1.0 + 0.5 * alpha.tan());
            assert!((from - expected).abs() < 1e-12, "{from} {expected}");
            // A one-sine reaches −a_p and +a_p: ü_v = −g at a_p = g/|r|, 8 αg.
            let lift = line["lift_off_above_alpha_g"].as_f64().expect("lift-off");
            assert!((lift - 1.0 / (0.5 * alpha)).abs() < 1e-9, "{lift}");
            assert!(line["eq21_alpha_g"].is_null());
            // Every transition separates what a time history of the pair
            // finds on either side of its bracket.
            let ratio = line["omega_ratio"].as_f64().expect("ratio");
            let transitions = line["transitions"].as_array().expect("transitions");
            assert!(!transitions.is_empty(), "r = {r}, ω_p/p = {ratio}");
            for t in transitions {
                let lo = t["bracket"][0].as_f64().expect("lo");
                let hi = t["bracket"][1].as_f64().expect("hi");
                assert!(hi < lift);
                let outcome = |level: f64| {
                    let h = Pulse::new(
                        PulseShape::OneSine,
                        level * alpha * G,
                        ratio * b.frequency_parameter(),
                    )
                    .expect("valid");
                    let problem = Problem {
                        block: b,
                        pulse: PulsePair::proportional(h, r).expect("non-zero"),
                        formulation: Formulation::Nonlinear,
                    };
                    simulate(&problem, &Options::outcome(dop853()))
                        .expect("runs")
                        .overturned
                };
                assert_ne!(outcome(lo), outcome(hi), "r = {r}, ω_p/p = {ratio}: {t}");
            }
        }
    }
    // A ratio of 0 is the spectrum without one, to the bit.
    let none = spectrum(json!({}));
    let zero = spectrum(json!({"vertical": {"ratio": 0.0}}));
    assert_eq!(none["spectrum"], zero["spectrum"]);
    assert!(none["spectrum"][0].get("lift_off_above_alpha_g").is_none());
    // The exact solver is refused, naming the field.
    let bad = Job::from_value(
        &json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_sine"}, "formulation": "linear", "omega_ratio": [2.0],
        "solver": {"method": "exact"}, "vertical": {"ratio": 0.3}}),
    )
    .expect_err("refused");
    assert_eq!(bad.pointer, "/solver/method", "{bad}");
    let own = Job::from_value(
        &json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_sine"}, "omega_ratio": [2.0],
        "vertical": {"type": "one_sine", "omega_p": 3.0, "a_p_g": 0.2}}),
    )
    .expect_err("refused");
    assert_eq!(own.pointer, "/vertical/a_p_g", "{own}");
}

/// The friction spectrum of the locomotive's one-sine family at ω_p/p = 4
/// over `levels` (αg) under `vertical`, each point checked against the time
/// history of the pair at its amplitude (`history_vertical(level)`): the
/// same peak |f_x/f_z| (1e-6), or lift-off in both. Returns the points.
fn friction_points_are_their_histories(
    levels: &[f64],
    vertical: Value,
    history_vertical: impl Fn(f64) -> Value,
) -> Vec<Value> {
    let spec = json!({"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"}, "omega_ratio": 4.0, "a_alpha_g": levels,
        "vertical": vertical});
    let Job::FrictionSpectrum(f) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a friction spectrum")
    };
    let doc = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    let points = doc["points"].as_array().expect("points").clone();
    for (point, &level) in points.iter().zip(levels) {
        let history = run(&history(json!({
            "pulse": {"type": "one_sine", "omega_ratio": 4.0, "a_p_alpha_g": level},
            "vertical": history_vertical(level),
            "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9, "mu": 10.0}
        })));
        let peak = point["peak_friction_demand"].as_f64();
        let expected = history["peak_friction_demand"].as_f64();
        // Lifted off (the ground falling away, or f_z → 0⁺ while rocking)
        // in both, or in neither with the same demand.
        let lifted = history["lift_off"] == true || history["lift_off_time"].is_number();
        assert_eq!(point["lift_off"], lifted, "{level}: {point} {history}");
        match (peak, expected) {
            (None, None) => assert!(lifted, "{level}: {point}"),
            (Some(peak), Some(expected)) => assert!(
                (peak - expected).abs() <= 1e-6 * expected,
                "{level}: {peak} vs {expected}"
            ),
            _ => panic!("{level}: {point} vs {history}"),
        }
    }
    points
}

#[test]
fn a_friction_spectrum_under_a_vertical_pulse_of_its_own_is_its_time_histories_demand() {
    // A one-sine vertical at twice the frequency, half the amplitude, 0.1 s
    // late: it reaches −g from 8 αg (0.5 × 8 × 0.25 g = g).
    let levels = [1.5, 3.0, 7.5, 8.5];
    let points = friction_points_are_their_histories(
        &levels,
        json!({"type": "one_sine", "amplitude_ratio": 0.5, "frequency_ratio": 2.0, "delay_s": 0.1}),
        |level| {
            json!({"type": "one_sine", "omega_ratio": 8.0, "a_p_alpha_g": 0.5 * level,
                   "delay_s": 0.1})
        },
    );
    // Below, bounded demands; at 7.5 αg f_z reaches 0 while the block rocks
    // (at 0.33 s), before the ground itself falls away faster than g.
    assert!(
        points[..2]
            .iter()
            .all(|p| p["peak_friction_demand"].is_number())
    );
    for p in &points[2..] {
        assert_eq!(p["lift_off"], true, "{p}");
    }
    // A pulse of its own identical to ü_v = 0.5 ü_g is that ratio.
    let same = friction_points_are_their_histories(
        &levels[..2],
        json!({"type": "one_sine", "amplitude_ratio": 0.5, "frequency_ratio": 1.0}),
        |_| json!({"ratio": 0.5}),
    );
    let ratio = friction_points_are_their_histories(
        &levels[..3],
        json!({"ratio": 0.5}),
        |_| json!({"ratio": 0.5}),
    );
    for (a, b) in same.iter().zip(&ratio) {
        let (a, b) = (
            a["peak_friction_demand"].as_f64().expect("bounded"),
            b["peak_friction_demand"].as_f64().expect("bounded"),
        );
        assert!((a - b).abs() <= 1e-7 * b, "{a} vs {b}");
    }
}

#[test]
fn a_friction_spectrum_under_a_vertical_ratio_is_its_time_histories_demand() {
    // Each amplitude's demand is the peak |f_x/f_z| of the time history of
    // the pair at that amplitude; from the amplitude where ü_v reaches −g
    // (8 αg for r = 0.5 and a one-sine) the block leaves the ground: lift-off,
    // no finite demand.
    let levels = [1.5, 3.0, 7.5, 8.5];
    let points = friction_points_are_their_histories(
        &levels,
        json!({"ratio": 0.5}),
        |_| json!({"ratio": 0.5}),
    );
    assert_eq!(points[3]["lift_off"], true, "{}", points[3]);
    assert!(
        points
            .iter()
            .filter(|p| p["peak_friction_demand"].is_number())
            .count()
            >= 2
    );
    // Without a vertical motion the demand at 3 αg is another.
    let plain = json!({"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_sine"}, "omega_ratio": 4.0, "a_alpha_g": [3.0]});
    let Job::FrictionSpectrum(f) = Job::from_value(&plain).expect("valid spec") else {
        panic!("a friction spectrum")
    };
    let plain = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    assert_ne!(
        plain["points"][0]["peak_friction_demand"],
        points[1]["peak_friction_demand"]
    );
}

#[test]
fn a_forensic_query_under_a_vertical_ratio_answers_below_lift_off_only() {
    use topple::dynamics::PulsePair;
    // A block seen overturned and one seen standing, one-sine pulses at
    // 1 Hz with ü_v = 0.5 ü_g: the ground falls away faster than gravity
    // from a_p = 2 g (ü_v = −g), which ends the range asked (to 3 g).
    let spec = json!({"kind": "forensic", "pulse": {"type": "one_sine"},
        "observations": [
            {"name": "down", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": true},
            {"name": "up", "block": {"alpha": 0.4, "p": 2.0, "eta": 0.9}, "overturned": false}],
        "frequency_hz": [1.0], "a_p_g": {"from": 0.05, "to": 3.0},
        "vertical": {"ratio": 0.5}});
    let Job::Forensic(f) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a forensic query")
    };
    let doc = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    let lift = doc["lift_off_above_g"].as_f64().expect("lift-off");
    assert!((lift - 2.0).abs() < 1e-9, "{lift}");
    let to = doc["a_p_g"]["to"].as_f64().expect("range");
    assert!(to < 2.0 && to > 2.0 - 1e-9, "{to}");
    let consistent = doc["frequencies"][0]["consistent_g"]
        .as_array()
        .expect("intervals");
    assert!(!consistent.is_empty(), "{doc}");
    // Every consistent interval holds what time histories of the pair say
    // of both blocks at its middle, and none reaches the lift-off.
    for iv in consistent {
        let (lo, hi) = (iv[0].as_f64().expect("lo"), iv[1].as_f64().expect("hi"));
        assert!(hi <= to, "{iv}");
        let a_g = 0.5 * (lo + hi);
        for (alpha, p, seen) in [(0.25, 2.14, true), (0.4, 2.0, false)] {
            let b = Block::new(alpha, p, Some(0.9), None, None).expect("valid");
            let h = Pulse::new(PulseShape::OneSine, a_g * G, std::f64::consts::TAU).expect("valid");
            let r = simulate(
                &Problem {
                    block: b,
                    pulse: PulsePair::proportional(h, 0.5).expect("non-zero"),
                    formulation: Formulation::Nonlinear,
                },
                &Options::outcome(dop853()),
            )
            .expect("runs");
            assert_eq!(r.overturned, seen, "α = {alpha} at {a_g} g");
        }
    }
    // Without the vertical the answer is another.
    let mut plain = spec.clone();
    plain.as_object_mut().expect("object").remove("vertical");
    let Job::Forensic(f) = Job::from_value(&plain).expect("valid spec") else {
        panic!("a forensic query")
    };
    let plain = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    assert!(plain.get("lift_off_above_g").is_none());
    assert_ne!(
        plain["frequencies"][0]["consistent_g"],
        doc["frequencies"][0]["consistent_g"]
    );
}

#[test]
fn a_record_forensic_query_under_a_vertical_ratio_stops_at_the_lift_off_scale() {
    // ü_v = −0.5 ü_g: the ground falls away faster than gravity at the
    // scale s where 0.5 s max(ü_g) = g, the record's largest positive sample.
    let acc: Vec<f64> = (0..300)
        .map(|k| {
            let t = k as f64 * 0.01;
            0.4 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp()
        })
        .collect();
    let largest = acc.iter().copied().fold(f64::MIN, f64::max);
    let pga = acc.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let spec = json!({"kind": "forensic",
        "observations": [
            {"name": "tall", "overturned": true, "block": {"alpha": 0.2, "p": 2.2}},
            {"name": "squat", "overturned": false, "block": {"alpha": 0.3, "p": 1.6}}],
        "scale": {"to": 8}, "scan_step_g": 0.02,
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc},
        "vertical": {"ratio": -0.5}});
    let Job::Forensic(f) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a forensic query")
    };
    let doc = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    let scale = 1.0 / (0.5 * largest);
    let lift = doc["lift_off_above_g"].as_f64().expect("lift-off");
    assert!(
        (lift - scale * pga).abs() < 1e-9,
        "{lift} vs {}",
        scale * pga
    );
    let to = doc["scale"]["to"].as_f64().expect("scale range");
    assert!(to < scale && to > scale * (1.0 - 1e-9), "{to} vs {scale}");
    for iv in doc["consistent_scale"].as_array().expect("intervals") {
        assert!(iv[1].as_f64().expect("hi") <= to, "{iv}");
    }
}

#[test]
fn a_record_spectrum_under_a_vertical_ratio_scans_below_lift_off() {
    use topple::dynamics::RecordPair;
    // A decaying 2-Hz sine; ü_v = 0.5 ü_g falls to −g at the scale where
    // 0.5 s |min ü_g| = g.
    let acc: Vec<f64> = (0..300)
        .map(|k| {
            let t = k as f64 * 0.01;
            0.4 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp()
        })
        .collect();
    let lowest = acc.iter().copied().fold(f64::MAX, f64::min);
    let spec = json!({"kind": "record_spectrum", "block": {"alpha": 0.2, "eta": 0.9},
        "p": [1.5, 2.5], "scale": {"from": 0.5, "to": 8},
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc},
        "vertical": {"ratio": 0.5}});
    let Job::RecordSpectrum(job) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a record spectrum")
    };
    let result = job.run(&topple::spectrum::Control::new()).expect("runs");
    let doc = serde_json::to_value(&result).expect("serialises");
    let lift = doc["lift_off_above_scale"].as_f64().expect("lift-off");
    let expected = 1.0 / (0.5 * -lowest);
    assert!(
        (lift - expected).abs() < 1e-9 * expected,
        "{lift} vs {expected}"
    );
    // Every transition below it, and each separates what time histories of
    // the pair find on either side of its bracket.
    let record = job.record().expect("a record");
    let mut checked = 0;
    for (size, p) in doc["spectrum"]
        .as_array()
        .expect("sizes")
        .iter()
        .zip([1.5, 2.5])
    {
        let b = Block::new(0.2, p, Some(0.9), None, None).expect("valid");
        for t in size["transitions"].as_array().expect("transitions") {
            let (lo, hi) = (
                t["bracket"][0].as_f64().expect("lo"),
                t["bracket"][1].as_f64().expect("hi"),
            );
            assert!(hi < lift, "{t}");
            let outcome = |s: f64| {
                let problem = Problem {
                    block: b,
                    pulse: RecordPair::proportional(record.scaled(s), 0.5).expect("non-zero"),
                    formulation: Formulation::Nonlinear,
                };
                simulate(&problem, &Options::outcome(dop853()))
                    .expect("runs")
                    .overturned
            };
            assert_ne!(outcome(lo), outcome(hi), "p = {p}: {t}");
            checked += 1;
        }
    }
    assert!(checked > 0);
    // The figure shades the lift-off and says so.
    let svg = topple::kinds::record_spectrum::figure::svg(&result).expect("a figure");
    assert!(svg.contains("lift-off"), "no lift-off in the legend");
}

/// A decaying 2-Hz sine in g (the horizontal record of the record tests).
fn decaying_sine() -> Vec<f64> {
    (0..300)
        .map(|k| {
            let t = k as f64 * 0.01;
            0.4 * (std::f64::consts::TAU * 2.0 * t).sin() * (-t / 1.5).exp()
        })
        .collect()
}

/// A vertical record of its own in g: a 5-Hz cosine, shorter than the
/// horizontal one (padded with zeros), falling lower than it rises.
fn own_vertical() -> Vec<f64> {
    (0..250)
        .map(|k| {
            let t = k as f64 * 0.01;
            0.25 * (std::f64::consts::TAU * 5.0 * t).cos() * (-t).exp() - 0.05
        })
        .collect()
}

/// The scale from which a block of slenderness α can rock under the pair
/// of records (g): k / max_j(|h_j| − k v_j), k = tan α, the shorter padded.
fn rocking_scale(h: &[f64], v: &[f64], alpha: f64) -> f64 {
    let k = alpha.tan();
    let n = h.len().max(v.len());
    let at = |x: &[f64], j: usize| x.get(j).copied().unwrap_or(0.0);
    k / (0..n)
        .map(|j| at(h, j).abs() - k * at(v, j))
        .fold(f64::MIN, f64::max)
}

/// The pair of records (g, converted to m/s²) scaled by `s`.
fn record_pair_at(h: &[f64], v: &[f64], s: f64) -> RecordPair {
    let of = |x: &[f64]| {
        Record::new(x.iter().map(|a| a * G * s).collect::<Vec<_>>().into(), 0.01).expect("a record")
    };
    RecordPair::new(of(h), of(v)).expect("a pair")
}

#[test]
fn a_record_spectrum_under_its_own_vertical_samples_scans_from_their_threshold_to_lift_off() {
    let (acc, vertical) = (decaying_sine(), own_vertical());
    let lowest = vertical.iter().copied().fold(f64::MAX, f64::min);
    let spec = json!({"kind": "record_spectrum", "block": {"alpha": 0.2, "eta": 0.9},
        "p": [1.5, 2.5], "scale": {"from": 0.5, "to": 8},
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc,
                          "vertical": {"acc": vertical, "unit": "g"}}});
    let Job::RecordSpectrum(job) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a record spectrum")
    };
    let result = job.run(&topple::spectrum::Control::new()).expect("runs");
    let doc = serde_json::to_value(&result).expect("serialises");
    // Lift-off where g + s·min(v) = 0.
    let lift = doc["lift_off_above_scale"].as_f64().expect("lift-off");
    let expected = 1.0 / -lowest;
    assert!(
        (lift - expected).abs() < 1e-12 * expected,
        "{lift} vs {expected}"
    );
    // The threshold in closed form, and time histories of the pair agree:
    // no rocking just below it, rocking just above.
    let threshold = rocking_scale(&acc, &vertical, 0.2);
    let at = doc["spectrum"][0]["threshold_scale"]
        .as_f64()
        .expect("threshold");
    assert!(
        (at - threshold).abs() < 1e-12 * threshold,
        "{at} vs {threshold}"
    );
    let plain_threshold = 0.2_f64.tan() / acc.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    assert!(
        threshold < plain_threshold,
        "the vertical lightens the block"
    );
    let b = Block::new(0.2, 1.5, Some(0.9), None, None).expect("valid");
    let rocked = |s: f64| {
        let problem = Problem {
            block: b,
            pulse: record_pair_at(&acc, &vertical, s),
            formulation: Formulation::Nonlinear,
        };
        simulate(&problem, &Options::outcome(dop853()))
            .expect("runs")
            .rocked
    };
    assert!(!rocked(threshold * (1.0 - 1e-6)) && rocked(threshold * (1.0 + 1e-6)));
    // Every transition below the lift-off, and each separates what time
    // histories of the pair find on either side of its bracket.
    let mut checked = 0;
    for (size, p) in doc["spectrum"]
        .as_array()
        .expect("sizes")
        .iter()
        .zip([1.5, 2.5])
    {
        let b = Block::new(0.2, p, Some(0.9), None, None).expect("valid");
        for t in size["transitions"].as_array().expect("transitions") {
            let (lo, hi) = (
                t["bracket"][0].as_f64().expect("lo"),
                t["bracket"][1].as_f64().expect("hi"),
            );
            assert!(hi < lift, "{t}");
            let outcome = |s: f64| {
                let problem = Problem {
                    block: b,
                    pulse: record_pair_at(&acc, &vertical, s),
                    formulation: Formulation::Nonlinear,
                };
                simulate(&problem, &Options::outcome(dop853()))
                    .expect("runs")
                    .overturned
            };
            assert_ne!(outcome(lo), outcome(hi), "p = {p}: {t}");
            checked += 1;
        }
    }
    assert!(checked > 0);
    // The figure names the record's own vertical motion and the lift-off.
    let svg = topple::kinds::record_spectrum::figure::svg(&result).expect("a figure");
    assert!(svg.contains("own vertical"), "no vertical in the figure");
    assert!(svg.contains("lift-off"), "no lift-off in the legend");
}

#[test]
fn a_record_forensic_query_under_its_own_vertical_samples_stops_at_their_lift_off() {
    let (acc, vertical) = (decaying_sine(), own_vertical());
    let lowest = vertical.iter().copied().fold(f64::MAX, f64::min);
    let pga = acc.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let spec = json!({"kind": "forensic",
        "observations": [
            {"name": "tall", "overturned": true, "block": {"alpha": 0.2, "p": 2.2}},
            {"name": "squat", "overturned": false, "block": {"alpha": 0.3, "p": 1.6}}],
        "scale": {"to": 8}, "scan_step_g": 0.02, "tolerance_g": 1e-6,
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc,
                          "vertical": {"acc": vertical, "unit": "g"}}});
    let Job::Forensic(f) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a forensic query")
    };
    let doc = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    let scale = 1.0 / -lowest;
    let lift = doc["lift_off_above_g"].as_f64().expect("lift-off");
    assert!(
        (lift - scale * pga).abs() < 1e-12 * scale * pga,
        "{lift} vs {}",
        scale * pga
    );
    let to = doc["scale"]["to"].as_f64().expect("scale range");
    assert!(to < scale && to > scale * (1.0 - 1e-9), "{to} vs {scale}");
    // Each observation's threshold in closed form; its overturning scales
    // end at transitions bracketed within the tolerance (1e-6 g of PGA):
    // time histories of the pair differ on either side.
    let step = 2e-6 / pga;
    let mut checked = 0;
    for (o, (alpha, p)) in [(0.2, 2.2), (0.3, 1.6)].into_iter().enumerate() {
        let set = &doc["per_observation"][o];
        let threshold = rocking_scale(&acc, &vertical, alpha);
        let at = set["threshold_scale"].as_f64().expect("threshold");
        assert!(
            (at - threshold).abs() < 1e-12 * threshold,
            "{at} vs {threshold}"
        );
        let b = Block::new(alpha, p, None, None, None).expect("valid");
        let outcome = |s: f64| {
            let problem = Problem {
                block: b,
                pulse: record_pair_at(&acc, &vertical, s),
                formulation: Formulation::Nonlinear,
            };
            simulate(&problem, &Options::outcome(dop853()))
                .expect("runs")
                .overturned
        };
        for iv in set["overturning_scale"].as_array().expect("intervals") {
            let (a, z) = (iv[0].as_f64().expect("from"), iv[1].as_f64().expect("to"));
            assert!(z <= to, "{iv}");
            for end in [a, z] {
                if end < to * (1.0 - 1e-9) {
                    assert_ne!(
                        outcome(end - step),
                        outcome(end + step),
                        "{o}: {iv} at {end}"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 0, "{doc}");
}

#[test]
fn record_kinds_without_vertical_motion_are_the_jobs_without_one() {
    let acc = decaying_sine();
    let record = json!({"dt": 0.01, "unit": "g", "acc": acc});
    let mut zeros = record.clone();
    zeros["vertical"] = json!({"acc": vec![0.0; 400], "unit": "g"});
    let mut zero_ratio = record.clone();
    zero_ratio["vertical"] = json!({"ratio": 0});
    let spectrum = |gm: &Value| {
        json!({"kind": "record_spectrum", "block": {"alpha": 0.2, "eta": 0.9},
            "p": [2.5], "scale": {"to": 4}, "ground_motion": gm})
    };
    let forensic = |gm: &Value| {
        json!({"kind": "forensic", "scale": {"to": 4}, "scan_step_g": 0.02,
            "observations": [{"name": "a", "overturned": true,
                              "block": {"alpha": 0.2, "p": 2.2}}],
            "ground_motion": gm})
    };
    let result = |job: &Job| {
        match job {
            Job::RecordSpectrum(j) => {
                serde_json::to_value(j.run(&topple::spectrum::Control::new()).expect("runs"))
            }
            Job::Forensic(j) => {
                serde_json::to_value(j.run(&topple::spectrum::Control::new()).expect("runs"))
            }
            _ => panic!("a record kind"),
        }
        .expect("serialises")
    };
    for kind in [spectrum, forensic] {
        let plain = Job::from_value(&kind(&record)).expect("valid");
        for zero in [&zeros, &zero_ratio] {
            let zero = Job::from_value(&kind(zero)).expect("valid");
            assert_eq!(canonical_spec(&plain), canonical_spec(&zero));
            assert_eq!(cache_key(&plain), cache_key(&zero));
            assert_eq!(steady(result(&plain)), steady(result(&zero)));
        }
        // The record's own ratio is the top-level one; samples are a
        // different job.
        let mut own = record.clone();
        own["vertical"] = json!({"ratio": 0.5});
        let mut top = kind(&record);
        top["vertical"] = json!({"ratio": 0.5});
        let (own, top) = (
            Job::from_value(&kind(&own)).expect("valid"),
            Job::from_value(&top).expect("valid"),
        );
        assert_eq!(canonical_spec(&own), canonical_spec(&top));
        assert_eq!(cache_key(&own), cache_key(&top));
        let mut samples = record.clone();
        samples["vertical"] = json!({"acc": own_vertical(), "unit": "g"});
        let samples = Job::from_value(&kind(&samples)).expect("valid");
        assert_ne!(cache_key(&samples), cache_key(&plain));
        assert_ne!(cache_key(&samples), cache_key(&top));
    }
}

#[test]
fn record_kinds_check_their_vertical_samples_field_by_field() {
    let acc = decaying_sine();
    let with = |kind: &str, vertical: Value, extra: Value| {
        let mut spec = match kind {
            "record_spectrum" => json!({"kind": "record_spectrum",
                "block": {"alpha": 0.2}, "p": [2.5], "scale": {"to": 4}}),
            _ => json!({"kind": "forensic", "scale": {"to": 4},
                "observations": [{"name": "a", "overturned": true,
                                  "block": {"alpha": 0.2, "p": 2.2}}]}),
        };
        spec["ground_motion"] = json!({"dt": 0.01, "unit": "g", "acc": acc, "vertical": vertical});
        for (k, v) in extra.as_object().expect("an object") {
            spec[k] = v.clone();
        }
        spec
    };
    let samples = json!({"acc": [0.0, -0.1, 0.0], "unit": "g"});
    for kind in ["record_spectrum", "forensic"] {
        let cases = [
            (
                with(kind, samples.clone(), json!({"vertical": {"ratio": 0.5}})),
                "/ground_motion/vertical",
            ),
            (
                with(
                    kind,
                    json!({"dt": 0.02, "acc": [0.0, 0.1], "unit": "g"}),
                    json!({}),
                ),
                "/ground_motion/vertical/dt",
            ),
            (
                with(kind, json!({"acc": [0.0, 0.1]}), json!({})),
                "/ground_motion/vertical/unit",
            ),
            (
                with(kind, json!({"unit": "g"}), json!({})),
                "/ground_motion/vertical/acc",
            ),
            (
                with(kind, json!({"acc": [0.0, 1e9], "unit": "g"}), json!({})),
                "/ground_motion/vertical/acc/1",
            ),
            (
                with(kind, json!({"ratio": 0.5, "unit": "g"}), json!({})),
                "/ground_motion/vertical/unit",
            ),
            (
                with(
                    kind,
                    samples.clone(),
                    json!({"formulation": "linear", "solver": {"method": "exact"}}),
                ),
                "/solver/method",
            ),
        ];
        for (spec, pointer) in &cases {
            assert_eq!(&refused_at(spec), pointer, "{kind}: {spec}");
        }
    }
}

#[test]
fn a_spectrum_under_a_vertical_pulse_of_its_own_scans_from_its_bound_to_lift_off() {
    let b = block();
    let alpha = b.slenderness();
    // A one-sine twice as fast as each horizontal pulse, a_v = −0.4 a_p,
    // 0.1 s later.
    let vertical = json!({"type": "one_sine", "amplitude_ratio": -0.4,
                          "frequency_ratio": 2.0, "delay_s": 0.1});
    let doc = spectrum(json!({ "vertical": vertical }));
    assert_eq!(doc["spec"]["vertical"], vertical);
    let pair = |level: f64, ratio: f64| {
        let w = ratio * b.frequency_parameter();
        let h = Pulse::new(PulseShape::OneSine, level * alpha * G, w).expect("valid");
        let v = Pulse::new(PulseShape::OneSine, -0.4 * level * alpha * G, 2.0 * w).expect("valid");
        topple::dynamics::PulsePair::new(h, v, 0.1)
    };
    for line in doc["spectrum"].as_array().expect("lines") {
        // The scan starts at the bound a_p (1 + 0.4 tan α) = g tan α.
        let from = line["threshold_alpha_g"].as_f64().expect("threshold");
        let expected = alpha.tan() / alpha / (1.0 + 0.4 * alpha.tan());
        assert!((from - expected).abs() < 1e-12, "{from} {expected}");
        // The vertical one-sine reaches −|a_v|: ü_v = −g at a_p = g/0.4.
        let lift = line["lift_off_above_alpha_g"].as_f64().expect("lift-off");
        assert!((lift - 1.0 / (0.4 * alpha)).abs() < 1e-9, "{lift}");
        let ratio = line["omega_ratio"].as_f64().expect("ratio");
        let transitions = line["transitions"].as_array().expect("transitions");
        assert!(!transitions.is_empty(), "ω_p/p = {ratio}");
        for t in transitions {
            let lo = t["bracket"][0].as_f64().expect("lo");
            let hi = t["bracket"][1].as_f64().expect("hi");
            assert!(hi < lift);
            let outcome = |level: f64| {
                let problem = Problem {
                    block: b,
                    pulse: pair(level, ratio),
                    formulation: Formulation::Nonlinear,
                };
                simulate(&problem, &Options::outcome(dop853()))
                    .expect("runs")
                    .overturned
            };
            assert_ne!(outcome(lo), outcome(hi), "ω_p/p = {ratio}: {t}");
        }
    }
    // The same vertical motion as a ratio is another job.
    let spec = |vertical: Value| {
        json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine"}, "omega_ratio": [2.0], "vertical": vertical})
    };
    let as_pulse = Job::from_value(&spec(json!({"type": "one_sine", "amplitude_ratio": 0.5,
        "frequency_ratio": 1.0})))
    .expect("valid");
    let as_ratio = Job::from_value(&spec(json!({"ratio": 0.5}))).expect("valid");
    assert_ne!(cache_key(&as_pulse), cache_key(&as_ratio));
    assert_ne!(canonical_spec(&as_pulse), canonical_spec(&as_ratio));
    // An amplitude ratio of 0 is the spectrum without one, to the bit.
    let none = spectrum(json!({}));
    let zero = spectrum(
        json!({"vertical": {"type": "ricker", "amplitude_ratio": 0.0,
                                            "omega_p": 5.0}}),
    );
    assert_eq!(steady(none.clone()), steady(zero));
    let plain = Job::from_value(&spec(Value::Null)).expect("valid");
    let zero = Job::from_value(&spec(json!({"type": "one_sine", "amplitude_ratio": 0,
        "frequency_hz": 2.0})))
    .expect("valid");
    assert_eq!(canonical_spec(&plain), canonical_spec(&zero));
    assert_eq!(cache_key(&plain), cache_key(&zero));
}

#[test]
fn a_pulse_forensic_query_under_a_vertical_pulse_of_its_own_answers_below_lift_off() {
    // One-sine pulses at 1 Hz under a falling vertical half-sine at 3 rad/s,
    // a_v = −0.4 a_p: the ground falls away faster than gravity from
    // a_p = g/0.4 = 2.5 g, inside the range asked (to 3 g).
    let spec = json!({"kind": "forensic", "pulse": {"type": "one_sine"},
        "observations": [
            {"name": "down", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": true},
            {"name": "up", "block": {"alpha": 0.4, "p": 2.0, "eta": 0.9}, "overturned": false}],
        "frequency_hz": [1.0], "a_p_g": {"from": 0.05, "to": 3.0},
        "vertical": {"type": "half_sine", "amplitude_ratio": -0.4, "omega_p": 3.0}});
    let Job::Forensic(f) = Job::from_value(&spec).expect("valid spec") else {
        panic!("a forensic query")
    };
    let doc = serde_json::to_value(f.run(&topple::spectrum::Control::new()).expect("runs"))
        .expect("serialises");
    let lift = doc["lift_off_above_g"].as_f64().expect("lift-off");
    assert!((lift - 2.5).abs() < 1e-9, "{lift}");
    let to = doc["a_p_g"]["to"].as_f64().expect("range");
    assert!(to < 2.5 && to > 2.5 - 1e-9, "{to}");
    let consistent = doc["frequencies"][0]["consistent_g"]
        .as_array()
        .expect("intervals");
    assert!(!consistent.is_empty(), "{doc}");
    for iv in consistent {
        let (lo, hi) = (iv[0].as_f64().expect("lo"), iv[1].as_f64().expect("hi"));
        assert!(hi <= to, "{iv}");
        let a_g = 0.5 * (lo + hi);
        for (alpha, p, seen) in [(0.25, 2.14, true), (0.4, 2.0, false)] {
            let b = Block::new(alpha, p, Some(0.9), None, None).expect("valid");
            let h = Pulse::new(PulseShape::OneSine, a_g * G, std::f64::consts::TAU).expect("valid");
            let v = Pulse::new(PulseShape::HalfSine, -0.4 * a_g * G, 3.0).expect("valid");
            let r = simulate(
                &Problem {
                    block: b,
                    pulse: topple::dynamics::PulsePair::new(h, v, 0.0),
                    formulation: Formulation::Nonlinear,
                },
                &Options::outcome(dop853()),
            )
            .expect("runs");
            assert_eq!(r.overturned, seen, "α = {alpha} at {a_g} g");
        }
    }
    // An amplitude ratio of 0 is the query without one.
    let mut zero = spec.clone();
    zero["vertical"]["amplitude_ratio"] = json!(0);
    let mut plain = spec.clone();
    plain.as_object_mut().expect("object").remove("vertical");
    let (zero, plain) = (
        Job::from_value(&zero).expect("valid"),
        Job::from_value(&plain).expect("valid"),
    );
    assert_eq!(canonical_spec(&zero), canonical_spec(&plain));
    assert_eq!(cache_key(&zero), cache_key(&plain));
}

#[test]
fn a_vertical_pulse_of_its_own_in_scaled_kinds_is_checked_field_by_field() {
    let spectrum = |vertical: Value, extra: Value| {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine"}, "omega_ratio": [2.0], "vertical": vertical});
        for (k, v) in extra.as_object().expect("an object") {
            spec[k] = v.clone();
        }
        spec
    };
    let forensic = |vertical: Value| {
        json!({"kind": "forensic", "pulse": {"type": "one_sine"},
            "observations": [{"name": "a", "overturned": true,
                              "block": {"alpha": 0.25, "p": 2.14}}],
            "frequency_hz": [1.0], "a_p_g": {"from": 0.05, "to": 1.0}, "vertical": vertical})
    };
    let own = |extra: Value| {
        let mut v = json!({"type": "one_sine", "amplitude_ratio": 0.3, "frequency_ratio": 2.0});
        for (k, x) in extra.as_object().expect("an object") {
            v[k] = x.clone();
        }
        v
    };
    let mut no_amplitude = own(json!({}));
    no_amplitude
        .as_object_mut()
        .expect("object")
        .remove("amplitude_ratio");
    let mut no_frequency = own(json!({}));
    no_frequency
        .as_object_mut()
        .expect("object")
        .remove("frequency_ratio");
    let cases = [
        (own(json!({"a_p": 2.0})), "/vertical/a_p"),
        (own(json!({"a_p_g": 0.2})), "/vertical/a_p_g"),
        (own(json!({"a_p_alpha_g": 1.0})), "/vertical/a_p_alpha_g"),
        (own(json!({"omega_ratio": 1.0})), "/vertical/omega_ratio"),
        (own(json!({"omega_p": 3.0})), "/vertical/frequency_ratio"),
        (
            own(json!({"amplitude_ratio": 1e9})),
            "/vertical/amplitude_ratio",
        ),
        (
            own(json!({"frequency_ratio": 0.0})),
            "/vertical/frequency_ratio",
        ),
        (own(json!({"delay_s": -1.0})), "/vertical/delay_s"),
        (own(json!({"type": "sawtooth"})), "/vertical/type"),
        (no_amplitude, "/vertical/amplitude_ratio"),
        (no_frequency, "/vertical/frequency_ratio"),
        (
            json!({"ratio": 0.5, "amplitude_ratio": 0.5}),
            "/vertical/amplitude_ratio",
        ),
    ];
    for (vertical, pointer) in &cases {
        let friction = json!({"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine"}, "omega_ratio": 2.0, "a_alpha_g": [2.0],
            "vertical": vertical});
        for spec in [
            spectrum(vertical.clone(), json!({})),
            forensic(vertical.clone()),
            friction,
        ] {
            assert_eq!(&refused_at(&spec), pointer, "{spec}");
        }
    }
    let exact = spectrum(
        own(json!({})),
        json!({"formulation": "linear", "solver": {"method": "exact"}}),
    );
    assert_eq!(refused_at(&exact), "/solver/method");
    // A time history's vertical pulse has its own amplitude and frequency.
    let history = history(json!({"pulse": {"type": "one_sine", "omega_ratio": 3.0,
        "a_p_alpha_g": 4.0}, "vertical": own(json!({}))}));
    assert_eq!(refused_at(&history), "/vertical/amplitude_ratio");
}
