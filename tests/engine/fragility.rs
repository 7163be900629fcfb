//! Fragility by Monte Carlo (`fragility`): with no spread it is the
//! deterministic outcome at every stripe; with one uncertain parameter each
//! stripe agrees with a quadrature over that parameter done with time
//! histories (within the binomial error); a seed reproduces a result.

use serde_json::{Value, json};
use topple::kinds::{Job, Task};
use topple::spectrum::Control;

fn run(spec: &Value) -> Value {
    Job::from_value(spec)
        .expect("valid")
        .run(&Control::new())
        .expect("runs")
}

fn overturns(alpha: f64, p: f64, hz: f64, a_g: f64) -> bool {
    let doc = run(&json!({"kind": "time_history",
        "block": {"alpha": alpha, "p": p},
        "pulse": {"type": "one_sine", "frequency_hz": hz, "a_p_g": a_g},
        "formulation": "nonlinear",
        "outputs": {"reactions": false, "impacts": false, "max_free_impacts": 0}}));
    doc["overturned"].as_bool().expect("flag")
}

#[test]
fn without_spread_it_is_the_deterministic_outcome_at_every_stripe() {
    let stripes = [0.2, 0.3, 0.4, 0.5, 0.7, 0.9, 1.2];
    let doc = run(
        &json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": 0.8},
        "stripes": stripes, "samples": 10, "seed": 7}),
    );
    for (s, &im) in doc["stripes"]
        .as_array()
        .expect("stripes")
        .iter()
        .zip(&stripes)
    {
        let expected = if overturns(0.2, 2.0, 0.8, im) { 10 } else { 0 };
        assert_eq!(s["overturned"].as_u64(), Some(expected), "{s}");
        assert_eq!(s["n"].as_u64(), Some(10));
    }
}

#[test]
fn on_a_coulomb_floor_each_sample_is_the_time_history_on_it() {
    // Without spread, each stripe is the Coulomb time history's outcome:
    // on μ = 0.3 the locomotive slides and rocks; below tan α (μ = 0.2)
    // it never overturns.
    let stripes = [0.3, 0.5, 0.7, 1.0];
    for mu in [0.2, 0.3] {
        let doc = run(
            &json!({"kind": "fragility", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine", "omega_ratio": 3.0},
            "contact": {"model": "coulomb", "mu": mu},
            "stripes": stripes, "samples": 4, "seed": 3}),
        );
        assert_eq!(doc["spec"]["contact"]["mu"], mu);
        for (s, &im) in doc["stripes"]
            .as_array()
            .expect("stripes")
            .iter()
            .zip(&stripes)
        {
            let th = run(&json!({"kind": "time_history",
                "block": {"alpha": 0.25, "p": 2.14},
                "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_g": im},
                "contact": {"model": "coulomb", "mu": mu}}));
            let over = th["overturned"].as_bool().expect("flag");
            assert!(!(mu < 0.25 && over), "{th}");
            assert_eq!(
                s["overturned"].as_u64(),
                Some(if over { 4 } else { 0 }),
                "μ {mu}: {s}"
            );
        }
    }
}

#[test]
fn one_uncertain_slenderness_agrees_with_a_quadrature_of_time_histories() {
    // α uniform on [0.15, 0.25]: P(topple | a) = the measure of the α that
    // topple, found with 400 time histories on a midpoint grid.
    let (lo, hi) = (0.15, 0.25);
    let stripes = [0.2, 0.25, 0.3];
    let samples = 1_000u64;
    let doc = run(&json!({"kind": "fragility",
        "block": {"alpha": {"dist": "uniform", "min": lo, "max": hi}, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": 0.8},
        "stripes": stripes, "samples": samples, "seed": 3}));
    let grid = 400;
    for (s, &im) in doc["stripes"]
        .as_array()
        .expect("stripes")
        .iter()
        .zip(&stripes)
    {
        let toppled = (0..grid)
            .filter(|&i| {
                overturns(
                    lo + (hi - lo) * (i as f64 + 0.5) / grid as f64,
                    2.0,
                    0.8,
                    im,
                )
            })
            .count();
        let q = toppled as f64 / grid as f64;
        let p = s["p"].as_f64().expect("p");
        // Four binomial standard errors, plus the grid's resolution.
        let se = (q * (1.0 - q) / samples as f64).sqrt();
        assert!(
            (p - q).abs() <= 4.0 * se + 1.0 / grid as f64,
            "{im} g: {p} vs {q} (se {se})"
        );
        let [a, b] = [
            s["interval_95"][0].as_f64().expect("lo"),
            s["interval_95"][1].as_f64().expect("hi"),
        ];
        assert!(a <= p && p <= b);
    }
}

#[test]
fn a_seed_reproduces_a_result_and_another_seed_differs() {
    let spec = |seed: u64| {
        json!({"kind": "fragility",
            "block": {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.4, "max": 0.8},
                      "h": {"dist": "lognormal", "median": 1.5, "beta": 0.1}},
            "pulse": {"type": "ricker", "frequency_hz": {"dist": "uniform", "min": 0.5, "max": 2.0}},
            "stripes": {"from": 0.3, "to": 1.2, "steps": 4}, "samples": 150, "seed": seed})
    };
    let (a, b, c) = (run(&spec(11)), run(&spec(11)), run(&spec(12)));
    assert_eq!(a["stripes"], b["stripes"]);
    assert_eq!(a["lognormal"], b["lognormal"]);
    assert_ne!(a["stripes"], c["stripes"]);
    let by_mode: u64 = a["stripes"]
        .as_array()
        .expect("stripes")
        .iter()
        .map(|s| s["mode_1"].as_u64().unwrap_or(0) + s["mode_2"].as_u64().unwrap_or(0))
        .sum();
    let total: u64 = a["stripes"]
        .as_array()
        .expect("stripes")
        .iter()
        .map(|s| s["overturned"].as_u64().unwrap_or(0))
        .sum();
    assert_eq!(by_mode, total);
}

#[test]
fn a_bad_fragility_spec_names_its_field() {
    let base = json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": 1.0}, "stripes": [0.3]});
    let cases = [
        (
            json!({"block": {"alpha": {"dist": "normal", "mean": 0.2, "sd": 0.05}, "p": 2.0}}),
            "/block/alpha/min",
        ),
        (json!({"block": {"alpha": 2.0, "p": 2.0}}), "/block/alpha"),
        (json!({"block": {"alpha": 0.2}}), "/block/p"),
        (
            json!({"block": {"alpha": 0.2, "p": 2.0, "b": 1.0}}),
            "/block",
        ),
        (
            json!({"block": {"alpha": 0.2, "p": 2.0, "eta": {"dist": "uniform", "min": 0.5, "max": 1.2}}}),
            "/block/eta/max",
        ),
        (json!({"pulse": {"type": "one_sine"}}), "/pulse/omega_p"),
        (
            json!({"pulse": {"type": "one_sine", "omega_p": 3.0, "frequency_hz": 1.0}}),
            "/pulse/frequency_hz",
        ),
        (json!({"pulse": null}), "/pulse"),
        (
            json!({"ground_motions": [{"dt": 0.01, "acc": [0.0, 0.1], "unit": "g"}]}),
            "/ground_motions",
        ),
        (json!({"im": "sa"}), "/im"),
        (json!({"stripes": [0.3, -0.1]}), "/stripes/1"),
        (json!({"samples": 0}), "/samples"),
        (json!({"samples": 200_000}), "/samples"),
    ];
    for (extra, pointer) in cases {
        let mut spec = base.clone();
        for (k, v) in extra.as_object().expect("object") {
            spec[k] = v.clone();
        }
        let e = Job::from_value(&spec).expect_err("refused");
        assert_eq!(e.pointer, pointer, "{extra}: {}", e.message);
    }
}

#[test]
fn the_monte_carlo_error_falls_as_one_over_root_n() {
    // One stripe of α uniform on [0.15, 0.25] at 0.25 g (P ≈ 0.4): the
    // spread of p over 24 seeds at N and 16N samples shrinks four times, and
    // each matches the binomial √(p(1 − p)/N).
    let spread = |n: u32| -> (f64, f64) {
        let ps: Vec<f64> = (0..24u64)
            .map(|seed| {
                run(&json!({"kind": "fragility",
                    "block": {"alpha": {"dist": "uniform", "min": 0.15, "max": 0.25}, "p": 2.0},
                    "pulse": {"type": "one_sine", "frequency_hz": 0.8},
                    "stripes": [0.25], "samples": n, "seed": seed}))["stripes"][0]["p"]
                    .as_f64()
                    .expect("p")
            })
            .collect();
        let mean = ps.iter().sum::<f64>() / ps.len() as f64;
        let var = ps.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (ps.len() - 1) as f64;
        (mean, var.sqrt())
    };
    let (p_small, sd_small) = spread(100);
    let (p_large, sd_large) = spread(1_600);
    let binomial = |p: f64, n: f64| (p * (1.0 - p) / n).sqrt();
    // 24 seeds estimate a deviation to about ±15 % (1σ): allow ±45 %.
    assert!(
        (sd_small / binomial(p_small, 100.0) - 1.0).abs() < 0.45,
        "{sd_small}"
    );
    assert!(
        (sd_large / binomial(p_large, 1600.0) - 1.0).abs() < 0.45,
        "{sd_large}"
    );
    let ratio = sd_small / sd_large;
    assert!(
        (2.4..=6.6).contains(&ratio),
        "σ(100)/σ(1600) = {ratio}, expected 4"
    );
}

/// Task `part` of the fragility job `spec`, run: its counts per stripe.
fn run_part(spec: &Value, part: [usize; 2]) -> Value {
    let mut task = spec.clone();
    task["part"] = json!(part);
    Task::from_spec(&task)
        .expect("a task")
        .run(&Control::new())
        .expect("runs")
}

/// The result of `spec` computed as tasks of `sizes` units each (cycled),
/// run in reverse order and assembled.
fn split_run(spec: &Value, sizes: &[usize]) -> Value {
    let whole = Job::from_value(spec).expect("valid");
    let Job::Fragility(f) = &whole else {
        panic!("a fragility job");
    };
    let units = f.units();
    let mut ranges = Vec::new();
    let (mut from, mut i) = (0, 0);
    while from < units {
        let to = (from + sizes[i % sizes.len()]).min(units);
        ranges.push([from, to]);
        (from, i) = (to, i + 1);
    }
    let parts: Vec<Value> = ranges.iter().rev().map(|&r| run_part(spec, r)).collect();
    let doc = whole.assemble(parts).expect("assembles");
    assert_eq!(doc["numerics"]["tasks"].as_u64(), Some(ranges.len() as u64));
    doc
}

#[test]
fn the_result_is_identical_whatever_the_split() {
    // 150 samples: chunks of 64, 64 and 22 per stripe, 4 stripes, 12 units.
    let spec = json!({"kind": "fragility",
        "block": {"alpha": {"dist": "normal", "mean": 0.2, "sd": 0.03, "min": 0.1, "max": 0.3}, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": {"dist": "lognormal", "median": 0.8, "beta": 0.3}},
        "stripes": [0.2, 0.3, 0.45, 0.7], "samples": 150, "seed": 11});
    let whole = run(&spec);
    assert_eq!(whole["numerics"]["tasks"].as_u64(), Some(1));
    assert!(whole["lognormal"].is_object(), "{}", whole["lognormal"]);
    for sizes in [&[1][..], &[2], &[5], &[3, 1, 7], &[11], &[12]] {
        let split = split_run(&spec, sizes);
        for field in ["stripes", "lognormal", "monotone", "falls_at", "spec", "im"] {
            assert_eq!(split[field], whole[field], "{field} split as {sizes:?}");
        }
        assert_eq!(
            split["numerics"]["simulations"],
            whole["numerics"]["simulations"]
        );
    }
    // The service's own split of a big job tiles its units.
    let mut big = spec.clone();
    big["samples"] = json!(100_000);
    let job = Job::from_value(&big).expect("valid");
    let tasks = job.split();
    assert!(
        tasks.len() > 20 && tasks.len() <= topple::jobs::split::MAX_TASKS,
        "{}",
        tasks.len()
    );
    let mut next = 0;
    for t in &tasks {
        let Task::Fragility(f) = t else {
            panic!("a fragility task");
        };
        let [from, to] = f.part.expect("a part");
        assert_eq!(from, next);
        next = to;
    }
    let Job::Fragility(f) = &job else {
        panic!("a fragility job");
    };
    assert_eq!(next, f.units());
    // A small job is one task: the job itself.
    assert_eq!(Job::from_value(&spec).expect("valid").split().len(), 1);
}

#[test]
fn a_record_suite_is_identical_whatever_the_split() {
    let dt = 0.01;
    let motion = |f: f64| -> Vec<f64> {
        (0..300)
            .map(|i| {
                let t = i as f64 * dt;
                (std::f64::consts::TAU * f * t).sin() * (-0.3 * t).exp()
            })
            .collect()
    };
    let spec = json!({"kind": "fragility",
        "block": {"b": {"dist": "uniform", "min": 0.15, "max": 0.25}, "h": 1.0},
        "ground_motions": [
            {"name": "a", "dt": dt, "unit": "g", "acc": motion(1.0)},
            {"name": "b", "dt": dt, "unit": "g", "acc": motion(1.7)}],
        "stripes": [0.25, 0.4, 0.6], "samples": 70, "seed": 5});
    let whole = run(&spec);
    let split = split_run(&spec, &[1, 2]);
    assert_eq!(split["stripes"], whole["stripes"]);
    assert_eq!(split["lognormal"], whole["lognormal"]);
}

#[test]
fn parts_that_do_not_tile_the_job_are_an_error_and_a_part_is_not_submitted() {
    let spec = json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": 0.8},
        "stripes": [0.3, 0.5], "samples": 100, "seed": 1});
    let job = Job::from_value(&spec).expect("valid");
    let part = |r: [usize; 2]| run_part(&spec, r);
    for (parts, says) in [
        (vec![[0, 1], [2, 4]], "unit 1 is missing"),
        (vec![[0, 3], [2, 4]], "unit 2 is counted twice"),
        (vec![[0, 1], [1, 3]], "units 3..4 are missing"),
    ] {
        let assembled = job.assemble(parts.iter().map(|&r| part(r)).collect());
        assert!(
            assembled
                .as_ref()
                .is_err_and(|e| e.to_string().contains(says)),
            "{parts:?}: {assembled:?}"
        );
    }
    // Submitted with a part, a spec is refused naming it; a task's part
    // out of range too.
    let mut task = spec.clone();
    task["part"] = json!([0, 1]);
    let e = Job::from_value(&task).expect_err("a part is the service's");
    assert_eq!(e.pointer, "/part");
    task["part"] = json!([2, 9]);
    let e = Task::from_spec(&task).expect_err("out of range");
    assert_eq!(e.pointer, "/part");
}

/// The verdict of a time history of the block (α, p) under a one-sine of
/// `hz` and `a_g` g with ü_v = `ratio` ü_g: `None` for a lift-off.
fn verdict_under_ratio(alpha: f64, p: f64, hz: f64, a_g: f64, ratio: f64) -> Option<bool> {
    let doc = run(&json!({"kind": "time_history",
        "block": {"alpha": alpha, "p": p},
        "pulse": {"type": "one_sine", "frequency_hz": hz, "a_p_g": a_g},
        "vertical": {"ratio": ratio},
        "formulation": "nonlinear",
        "outputs": {"reactions": false, "impacts": false, "max_free_impacts": 0}}));
    if doc["lift_off"] == json!(true) {
        None
    } else {
        Some(doc["overturned"].as_bool().expect("flag"))
    }
}

/// Without spread, under ü_v = r ü_g every sample of a stripe does what the
/// time history of the pair does: topples, stands, or lifts off — counted
/// apart, left out of p (null when every sample lifted off) and of the fit.
#[test]
fn a_fixed_vertical_ratio_counts_each_stripe_as_its_time_history_and_lift_offs_apart() {
    let stripes = [0.2, 0.3, 0.4, 0.5, 0.7, 0.9, 1.2, 2.2, 3.0];
    for ratio in [0.5, -0.5] {
        let doc = run(
            &json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
            "pulse": {"type": "one_sine", "frequency_hz": 0.8},
            "vertical": {"ratio": ratio},
            "stripes": stripes, "samples": 10, "seed": 7}),
        );
        let mut lifted = 0;
        for (s, &im) in doc["stripes"]
            .as_array()
            .expect("stripes")
            .iter()
            .zip(&stripes)
        {
            assert_eq!(s["n"].as_u64(), Some(10));
            match verdict_under_ratio(0.2, 2.0, 0.8, im, ratio) {
                None => {
                    lifted += 1;
                    assert_eq!(s["lift_off"].as_u64(), Some(10), "{s}");
                    assert_eq!(s["overturned"].as_u64(), Some(0), "{s}");
                    assert_eq!(s["p"], Value::Null, "{s}");
                    assert_eq!(s["interval_95"], json!([null, null]), "{s}");
                }
                Some(topples) => {
                    assert_eq!(s["lift_off"].as_u64(), Some(0), "{s}");
                    let k = if topples { 10 } else { 0 };
                    assert_eq!(
                        s["overturned"].as_u64(),
                        Some(k),
                        "{im} g, r = {ratio}: {s}"
                    );
                    assert_eq!(s["p"].as_f64(), Some(k as f64 / 10.0), "{s}");
                }
            }
        }
        // Under r < 0 the ground falls as the pulse's first half pushes:
        // from 2 g on it falls faster than g before the block can topple.
        if ratio < 0.0 {
            assert!(lifted >= 1, "r = {ratio}: no stripe lifted off");
        }
        // Reads back into its type (p null included).
        let typed = topple::kinds::JobResult::from_value(doc.clone()).expect("reads");
        let topple::kinds::JobResult::Fragility(f) = typed else {
            panic!("a fragility")
        };
        assert_eq!(
            f.stripes.iter().filter(|s| s.decided() == 0).count(),
            lifted
        );
    }
}

/// A fixed ratio draws no uniform of its own: a ratio of 0 is the job
/// without one (bit for bit, spec and all), and a distributed ratio whose
/// every value lifts the block off at a stripe counts every sample there.
#[test]
fn a_vertical_ratio_of_zero_is_no_vertical_motion_and_a_distributed_one_is_drawn() {
    let base = json!({"kind": "fragility",
        "block": {"alpha": {"dist": "uniform", "min": 0.15, "max": 0.25}, "p": 2.0},
        "pulse": {"type": "one_sine", "frequency_hz": 0.8},
        "stripes": [0.3, 0.6], "samples": 70, "seed": 5});
    let mut zero = base.clone();
    zero["vertical"] = json!({"ratio": 0.0});
    let (a, b) = (run(&base), run(&zero));
    assert_eq!(a["stripes"], b["stripes"]);
    assert_eq!(a["spec"], b["spec"]);
    assert!(a["stripes"][0].get("lift_off").is_none());

    // Every |r| in [0.7, 0.9] lifts the block off at 2.5 g (|r| ü_g < −g
    // once per sine), every one in [0.05, 0.1] never does.
    for (range, lifts) in [([0.7, 0.9], true), ([0.05, 0.1], false)] {
        let mut spec = base.clone();
        spec["vertical"] = json!({"ratio": {"dist": "uniform", "min": range[0], "max": range[1]}});
        spec["stripes"] = json!([2.5]);
        let doc = run(&spec);
        let s = &doc["stripes"][0];
        let lift_off = s["lift_off"].as_u64().expect("counted");
        let overturned = s["overturned"].as_u64().expect("counted");
        if lifts {
            // Each sample lifts off unless it toppled first.
            assert_eq!(lift_off + overturned, 70, "{s}");
            assert!(lift_off > 0, "{s}");
        } else {
            assert_eq!(lift_off, 0, "{s}");
        }
        // Drawn from the spec alone: the same again.
        assert_eq!(run(&spec)["stripes"], doc["stripes"]);
    }
}

/// A suite's records may carry their own vertical component, scaled with
/// them: a record whose vertical is its horizontal times r is the suite
/// under `"vertical": {"ratio": r}`, and both at once are refused.
#[test]
fn a_suite_record_with_its_own_vertical_is_scaled_with_it() {
    let acc: Vec<f64> = (0..400)
        .map(|k| {
            let t = f64::from(k) * 0.01;
            (std::f64::consts::TAU * 1.3 * t).sin() * (-0.5 * t).exp()
        })
        .collect();
    let ratio = -0.4;
    let vertical: Vec<f64> = acc.iter().map(|a| ratio * a).collect();
    let with_ratio = json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "ground_motions": [{"name": "a", "dt": 0.01, "acc": acc, "unit": "g"}],
        "vertical": {"ratio": ratio},
        "stripes": [0.3, 0.6, 1.5, 3.0], "samples": 4, "seed": 2});
    let own = json!({"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "ground_motions": [{"name": "a", "dt": 0.01, "acc": acc, "unit": "g",
            "vertical": {"acc": vertical, "unit": "g"}}],
        "stripes": [0.3, 0.6, 1.5, 3.0], "samples": 4, "seed": 2});
    let (a, b) = (run(&with_ratio), run(&own));
    assert_eq!(a["stripes"], b["stripes"]);
    assert!(
        a["stripes"][3]["lift_off"].as_u64().is_some_and(|n| n > 0),
        "{}",
        a["stripes"][3]
    );
    let mut both = own.clone();
    both["vertical"] = json!({"ratio": 0.3});
    let err = Job::from_value(&both).expect_err("refused");
    assert_eq!(err.pointer, "/ground_motions/0/vertical", "{err}");
    let mut exact = with_ratio.clone();
    exact["solver"] = json!({"method": "exact"});
    exact["formulation"] = json!("linear");
    let err = Job::from_value(&exact).expect_err("refused");
    assert_eq!(err.pointer, "/solver/method", "{err}");
    let mut bad = with_ratio.clone();
    bad["vertical"] = json!({"ratio": {"dist": "uniform", "min": -200.0, "max": 0.5}});
    let err = Job::from_value(&bad).expect_err("refused");
    assert_eq!(err.pointer, "/vertical/ratio/min", "{err}");
}
