//! Rocking spectra of records (`record_spectrum`): a one-sine pulse sampled at
//! T/4000 has the pulse's spectrum; the axes may be given in any unit and make
//! one job; what cannot be computed is refused naming the field.

use serde_json::{Value, json};
use topple::kinds::Job;
use topple::kinds::key::cache_key;
use topple::spectrum::Control;

const G: f64 = 9.81;
const ALPHA: f64 = 0.25;

/// A one-sine pulse of amplitude αg at `hz`, sampled at T/n (PGA = αg, so a
/// scale factor is a level in αg).
fn one_sine_record(hz: f64, n: usize) -> Value {
    let w = std::f64::consts::TAU * hz;
    let dt = 1.0 / hz / n as f64;
    let acc: Vec<f64> = (0..=n)
        .map(|k| ALPHA * G * (w * k as f64 * dt).sin())
        .collect();
    json!({"dt": dt, "acc": acc, "unit": "m/s2"})
}

fn record_spectrum(extra: Value) -> Result<Job, topple::jobs::SpecError> {
    let mut spec = json!({"kind": "record_spectrum", "block": {"alpha": ALPHA, "eta": 0.9},
                          "ground_motion": one_sine_record(2.0, 400),
                          "p": [6.0], "scale": {"to": 6.0}});
    for (k, v) in extra.as_object().expect("object") {
        spec[k] = v.clone();
    }
    Job::from_value(&spec)
}

fn run(job: &Job) -> Value {
    job.run(&Control::new()).expect("runs")
}

fn transitions(line: &Value, key: &str) -> Vec<(f64, String, u64)> {
    line.pointer("/principal/transitions")
        .and_then(Value::as_array)
        .expect("principal transitions")
        .iter()
        .map(|t| {
            (
                t[key].as_f64().expect("level"),
                t["direction"].as_str().expect("direction").to_string(),
                t["mode"].as_u64().expect("mode"),
            )
        })
        .collect()
}

#[test]
fn a_sampled_one_sine_pulse_has_the_pulses_spectrum() {
    // ω_p/p = 2 and 4 for a 2 Hz pulse: p = 2π and π rad/s.
    let hz = 2.0;
    let w = std::f64::consts::TAU * hz;
    let ratios = [2.0, 4.0];
    for formulation in ["nonlinear", "linear"] {
        let record = Job::from_value(&json!({
            "kind": "record_spectrum", "block": {"alpha": ALPHA, "eta": 0.9},
            "ground_motion": one_sine_record(hz, 4000),
            "p": ratios.iter().map(|r| w / r).collect::<Vec<_>>(),
            "scale": {"to": 8.0}, "formulation": formulation,
            "scan_step": 0.05, "tolerance": 1e-4}))
        .expect("valid");
        let pulse = Job::from_value(&json!({
            "kind": "spectrum", "block": {"alpha": ALPHA, "p": 2.0, "eta": 0.9},
            "pulse": {"type": "one_sine"}, "omega_ratio": ratios, "a_max_alpha_g": 8.0,
            "formulation": formulation, "scan_step_alpha_g": 0.05, "tolerance": 1e-4,
            "solver": {"method": "dop853"}}))
        .expect("valid");
        let (r, p) = (run(&record), run(&pulse));
        assert!((r["record"]["pga_g"].as_f64().expect("pga") - ALPHA).abs() < 1e-12);
        for (k, ratio) in ratios.iter().enumerate() {
            let rl = &r["spectrum"][k];
            let pl = &p["spectrum"][k];
            let ours = transitions(rl, "scale");
            let theirs = transitions(pl, "a_alpha_g");
            assert!(
                !theirs.is_empty(),
                "{formulation} {ratio}: the pulse overturns"
            );
            assert_eq!(
                ours.len(),
                theirs.len(),
                "{formulation} {ratio}: {ours:?} vs {theirs:?}"
            );
            for (a, b) in ours.iter().zip(&theirs) {
                assert_eq!((&a.1, a.2), (&b.1, b.2), "{formulation} {ratio}");
                let rel = (a.0 - b.0).abs() / b.0;
                assert!(
                    rel < 2e-3,
                    "{formulation} {ratio}: {} vs {} ({rel:e})",
                    a.0,
                    b.0
                );
            }
            // The size and threshold are echoed in every unit.
            let p_val = rl["p"].as_f64().expect("p");
            assert!((p_val - w / ratio).abs() < 1e-12);
            let r_m = rl["R_m"].as_f64().expect("R");
            assert!((r_m - 3.0 * G / (4.0 * p_val * p_val)).abs() < 1e-12 * r_m);
            let threshold = rl["threshold_scale"].as_f64().expect("threshold");
            let expected = if formulation == "linear" {
                1.0
            } else {
                ALPHA.tan() / ALPHA
            };
            assert!((threshold - expected).abs() < 1e-12, "{threshold}");
            let min = rl["min_overturn_scale"].as_f64().expect("overturns");
            let min_g = rl["min_overturn_pga_g"].as_f64().expect("in g");
            assert!((min_g - min * ALPHA).abs() < 1e-12);
        }
    }
}

#[test]
fn axes_in_any_unit_make_one_job() {
    let g = G;
    let base = record_spectrum(json!({"p": [3.0, 6.0], "scale": {"from": 0.5, "to": 4.0}}))
        .expect("valid");
    let r = |p: f64| 3.0 * g / (4.0 * p * p);
    // PGA = αg = 0.25 g: scale s is a PGA of 0.25 s g.
    let same = record_spectrum(json!({"p": null, "R_m": [r(3.0), r(6.0)],
                                      "scale": null, "pga_g": {"from": 0.125, "to": 1.0}}))
    .expect("valid");
    let (Job::RecordSpectrum(a), Job::RecordSpectrum(b)) = (&base, &same) else {
        panic!("record spectra");
    };
    for (x, y) in a.p.iter().zip(&b.p) {
        assert!((x - y).abs() < 1e-12 * x, "{x} {y}");
    }
    assert!((a.scale.to - b.scale.to).abs() < 1e-12);
    assert!((a.scale.from - b.scale.from).abs() < 1e-12);
    // Defaults in scale units: 0.02 and 1e-4 of αg/PGA (= 1 here).
    assert!((a.scan_step - 0.02).abs() < 1e-15 && (a.tolerance - 1e-4).abs() < 1e-18);
    assert_ne!(
        cache_key(&base),
        cache_key(&record_spectrum(json!({})).expect("valid"))
    );
}

#[test]
fn what_cannot_be_computed_is_refused_naming_the_field() {
    let cases = [
        (json!({"block": {"alpha": ALPHA, "p": 2.0}}), "/block/p"),
        (json!({"block": {"alpha": ALPHA, "mu": 0.5}}), "/block/mu"),
        (json!({"p": null}), "/p"),
        (json!({"R_m": [1.0]}), "/R_m"),
        (json!({"p": [0.0]}), "/p/0"),
        (json!({"scale": null}), "/scale"),
        (json!({"pga_g": {"to": 1.0}}), "/pga_g"),
        (json!({"scale": {"from": 1.0}}), "/scale/to"),
        (json!({"scale": {"from": 2.0, "to": 1.0}}), "/scale/to"),
        // Scaled by 1 the PGA is αg, below g tan α: nothing rocks.
        (json!({"scale": {"to": 1.0}}), "/scale/to"),
        (json!({"scale": {"to": 1e5}}), "/scale/to"),
        (json!({"tolerance": 0.5}), "/tolerance"),
        (json!({"scan_step": 1e-6}), "/scan_step"),
        (
            json!({"ground_motion": {"dt": 0.01, "acc": [0.0, 0.0, 0.0], "unit": "g"}}),
            "/ground_motion/acc",
        ),
        (json!({"ground_motion": null}), "/ground_motion"),
        (json!({"solver": {"method": "exact"}}), "/solver/method"),
    ];
    for (extra, pointer) in cases {
        let e = record_spectrum(extra.clone()).expect_err(&extra.to_string());
        assert_eq!(e.pointer, pointer, "{extra}: {}", e.message);
    }
    let e = record_spectrum(json!({"scale": {"to": 1.0}})).expect_err("below threshold");
    assert!(e.message.contains("rocking threshold"), "{}", e.message);
}

#[test]
fn a_split_record_spectrum_assembles_to_the_whole() {
    let job = record_spectrum(
        json!({"p": {"from": 3.0, "to": 9.0, "steps": 7}, "scan_step": 0.1, "tolerance": 1e-3}),
    )
    .expect("valid");
    let tasks = job.split();
    assert!(tasks.len() > 1, "{} tasks", tasks.len());
    let control = Control::new();
    let parts: Vec<Value> = tasks
        .iter()
        .map(|t| t.run(&control).expect("runs"))
        .collect();
    let assembled = job.assemble(parts).expect("assembles");
    let whole = run(&job);
    assert_eq!(assembled["spectrum"], whole["spectrum"]);
    assert_eq!(assembled["record"], whole["record"]);
    assert_eq!(assembled["spec"], whole["spec"]);
    assert_eq!(assembled["kind"], "record_spectrum");
    // The same bisections: only levels where tasks or chunks of 48 levels
    // meet are simulated twice.
    let (a, w) = (
        assembled["numerics"]["simulations"]
            .as_u64()
            .expect("a count"),
        whole["numerics"]["simulations"].as_u64().expect("a count"),
    );
    let topple::kinds::Job::RecordSpectrum(j) = &job else {
        panic!("a record spectrum");
    };
    let meeting = 2 * (tasks.len() + 7 * (j.grid().points() / 48 + 1)) as u64;
    assert!(a >= w && a - w <= meeting, "{a} vs {w}");
    assert_eq!(assembled["numerics"]["tasks"], tasks.len());
    // A figure and a CSV table of it.
    let typed = topple::kinds::JobResult::from_value(whole).expect("a record spectrum");
    let svg = typed.figure(None).expect("a figure");
    assert!(svg.contains("block size R (m)") && svg.contains("scale factor"));
}

#[test]
fn a_long_record_is_split_into_few_tasks_and_its_size_is_limited() {
    use topple::kinds::limits::Limits;
    let mut gm = one_sine_record(0.02, 100_000);
    gm["dt"] = json!(0.0005);
    let job =
        record_spectrum(json!({"ground_motion": gm, "p": {"from": 1.0, "to": 9.0, "steps": 200}}))
            .expect("valid");
    // The record is stored once, with the job: a task names its part.
    let tasks = job.split();
    assert!(
        tasks.len() > 200 && tasks.len() <= topple::jobs::split::MAX_PART_TASKS,
        "{} tasks",
        tasks.len()
    );
    for t in &tasks {
        let payload = t.payload();
        assert!(
            payload.len() < 100 && payload.contains("levels"),
            "{payload}"
        );
    }
    let e = job
        .check_limits(&Limits::default())
        .expect_err("too much work");
    assert_eq!((e.pointer.as_str(), e.limit), ("/p", "max_record_work"));
    let written = json!({"R_m": [1.0]});
    assert_eq!(e.as_written(&written).pointer, "/R_m");
}

#[test]
fn a_range_starting_inside_an_overturning_band_still_locates_where_it_begins() {
    let whole = run(&record_spectrum(json!({})).expect("valid"));
    let line = &whole["spectrum"][0];
    let min = line["min_overturn_scale"].as_f64().expect("overturns");
    // From just above the lowest overturning scale, inside the band.
    let inside =
        run(&record_spectrum(json!({"scale": {"from": min + 0.01, "to": 6.0}})).expect("valid"));
    let same = &inside["spectrum"][0];
    assert_eq!(same["min_overturn_scale"].as_f64(), Some(min));
    assert_eq!(same["transitions"], line["transitions"]);
    assert_eq!(same["safe_intervals"], line["safe_intervals"]);
}
