//! Sampled ground-motion records: a one-sine pulse given as samples reproduces
//! the analytic pulse (differences shrink as dt²), rocking starts between
//! samples where the linear interpolant crosses the threshold, specs with a
//! `ground_motion` are validated field by field, and a short near-fault-like
//! record runs to a finite answer. The exact linear solution, piece by piece,
//! agrees with dop853 at rtol 1e-12, is Housner's under a constant ground, and
//! copes with long records, stiff blocks and grazing exceedances.

use std::sync::Arc;

use crate::synthetic::synthetic;
use serde_json::json;
use topple::dynamics::exact::MAX_SEGMENT_PT;
use topple::dynamics::{
    Block, Formulation, Method, Options, OverturnMode, Problem, Pulse, PulseShape, Record,
    Response, Solver, simulate,
};
use topple::kinds::Job;
use topple::kinds::key::{cache_key, canonical_spec};

const G: f64 = 9.81;

fn block() -> Block {
    Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid block")
}

fn solver() -> Solver {
    Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-12,
        atol: 1e-14,
    }
}

/// The one-sine pulse a_p sin(ω_p t) sampled at t_k = k T/n, k = 0..n.
pub(crate) fn sampled(pulse: &Pulse, n: usize) -> Record {
    let dt = pulse.duration / n as f64;
    let acc: Vec<f64> = (0..=n)
        .map(|k| pulse.amplitude * (pulse.circular_frequency * k as f64 * dt).sin())
        .collect();
    Record::new(acc.into(), dt).expect("valid record")
}

fn options_with(solver: Solver, series_at: Vec<f64>) -> Options {
    let mut o = Options::history(solver);
    o.max_free_impacts = 10;
    o.series_at = Some(series_at);
    o
}

/// Largest difference between two histories: rocking start, impact times,
/// overturning time (s) and θ/α at the common series times.
fn difference(a: &Response, b: &Response) -> f64 {
    assert_eq!(a.overturned, b.overturned);
    assert_eq!(a.mode, b.mode);
    assert_eq!(a.impact_count, b.impact_count);
    assert_eq!(a.impacts.len(), b.impacts.len());
    let mut d = (a.rocking_start.expect("rocks") - b.rocking_start.expect("rocks")).abs();
    for (x, y) in a.impacts.iter().zip(&b.impacts) {
        d = d.max((x.time - y.time).abs());
    }
    if let (Some(x), Some(y)) = (a.overturn_time, b.overturn_time) {
        d = d.max((x - y).abs());
    }
    let (sa, sb) = (
        a.series.as_ref().expect("series"),
        b.series.as_ref().expect("series"),
    );
    assert_eq!(sa.t.len(), sb.t.len());
    let alpha = block().slenderness();
    for (x, y) in sa.theta.iter().zip(&sb.theta) {
        d = d.max((x - y).abs() / alpha);
    }
    d
}

/// The differences between the analytic pulse and its samples at dt = T/n for
/// each n.
fn convergence(formulation: Formulation, ratio: f64, level: f64, ns: &[usize]) -> Vec<f64> {
    convergence_with(solver(), formulation, ratio, level, ns)
}

/// [`convergence`] with both histories computed by `solver`.
fn convergence_with(
    solver: Solver,
    formulation: Formulation,
    ratio: f64,
    level: f64,
    ns: &[usize],
) -> Vec<f64> {
    let options = |times: Vec<f64>| options_with(solver, times);
    let b = block();
    let pulse = Pulse::new(
        PulseShape::OneSine,
        level * b.slenderness() * G,
        ratio * b.frequency_parameter(),
    )
    .expect("valid pulse");
    let analytic = Problem {
        block: b,
        pulse,
        formulation,
    };
    let first = simulate(&analytic, &options(Vec::new())).expect("simulates");
    let end = 0.95 * first.overturn_time.unwrap_or(first.end_time);
    let times: Vec<f64> = (0..400).map(|k| end * k as f64 / 399.0).collect();
    let reference = simulate(&analytic, &options(times.clone())).expect("simulates");
    assert!(reference.impact_count > 0, "the case has impacts");
    ns.iter()
        .map(|&n| {
            let record = Problem {
                block: b,
                pulse: sampled(&pulse, n),
                formulation,
            };
            let r = simulate(&record, &options(times.clone())).expect("simulates");
            assert!(r.numerics.error_estimate.is_finite());
            assert!(
                r.numerics.steps_accepted >= n as u64 / 2,
                "steps (or closed-form segments) stop at samples"
            );
            difference(&reference, &r)
        })
        .collect()
}

fn assert_second_order(label: &str, d: &[f64]) {
    let shown: Vec<String> = d.iter().map(|x| format!("{x:.3e}")).collect();
    eprintln!(
        "{label}: differences at dt = T/1000, T/2000, T/4000: {}",
        shown.join(", ")
    );
    for w in d.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (3.0..=5.5).contains(&ratio),
            "{label}: halving dt divides the difference by {ratio} (expected ~4): {d:?}"
        );
    }
    assert!(d[d.len() - 1] < 1e-5, "{label}: {d:?}");
}

const NS: [usize; 3] = [1000, 2000, 4000];

#[test]
fn a_sampled_one_sine_rocks_like_the_pulse_nonlinear() {
    // ω_p/p = 5, a_p = 2 αg: rocks, one impact during the pulse, stays up.
    assert_second_order(
        "nonlinear, standing",
        &convergence(Formulation::Nonlinear, 5.0, 2.0, &NS),
    );
}

#[test]
fn a_sampled_one_sine_overturns_like_the_pulse_nonlinear() {
    // ω_p/p = 3, a_p = 2 αg: one impact during the pulse, then overturns.
    assert_second_order(
        "nonlinear, overturning",
        &convergence(Formulation::Nonlinear, 3.0, 2.0, &NS),
    );
}

#[test]
fn a_sampled_one_sine_rocks_like_the_pulse_linear() {
    assert_second_order(
        "linear, standing",
        &convergence(Formulation::Linear, 5.0, 2.0, &NS),
    );
}

#[test]
fn a_sampled_one_sine_overturns_like_the_pulse_linear() {
    assert_second_order(
        "linear, overturning",
        &convergence(Formulation::Linear, 3.0, 2.0, &NS),
    );
}

#[test]
fn the_exact_solution_of_a_sampled_one_sine_converges_to_the_pulses_as_dt_squared() {
    for (ratio, what) in [(5.0, "standing"), (3.0, "overturning")] {
        assert_second_order(
            &format!("linear exact, {what}"),
            &convergence_with(Solver::Exact, Formulation::Linear, ratio, 2.0, &NS),
        );
    }
}

#[test]
fn rocking_starts_where_the_interpolant_crosses_the_threshold() {
    let b = block();
    for formulation in [Formulation::Nonlinear, Formulation::Linear] {
        let c = formulation.rocking_threshold(&b);
        let dt = 0.01;
        // Crosses −c on [0.02, 0.03] at 0.02 + dt·0.8/1.5 (ü_g < 0: θ > 0).
        let acc = vec![
            0.0,
            -0.1 * c,
            -0.2 * c,
            -1.7 * c,
            -1.7 * c,
            -0.5 * c,
            0.0,
            0.0,
        ];
        let record = Record::new(acc.into(), dt).expect("valid");
        let r = simulate(
            &Problem {
                block: b,
                pulse: record,
                formulation,
            },
            &Options::history(solver()),
        )
        .expect("simulates");
        let expected = 0.02 + dt * 0.8 / 1.5;
        let start = r.rocking_start.expect("rocks");
        assert!(
            (start - expected).abs() < 1e-15,
            "{formulation:?}: {start} vs {expected}"
        );
        assert!(!r.overturned);
        assert!(r.peak_theta_over_alpha > 0.0);
    }
}

#[test]
fn below_the_threshold_a_record_leaves_the_block_at_rest() {
    let b = block();
    let c = Formulation::Nonlinear.rocking_threshold(&b);
    let record = Record::new(vec![0.0, c, -c, 0.5 * c].into(), 0.02).expect("valid");
    let r = simulate(
        &Problem {
            block: b,
            pulse: record,
            formulation: Formulation::Nonlinear,
        },
        &Options::history(solver()),
    )
    .expect("simulates");
    assert!(!r.rocked);
    assert!((r.end_time - 0.06).abs() < 1e-15);
    // At rest the demand is |ü_g|/g, largest at a sample.
    let f = r.friction.expect("reactions");
    assert!((f.peak.expect("bounded") - c / G).abs() < 1e-15);
}

#[test]
fn the_exact_solver_solves_the_linear_formulation_of_a_record_only() {
    let record = Record::new(vec![0.0, 1.0, 0.0].into(), 0.1).expect("valid");
    let problem = |formulation| Problem {
        block: block(),
        pulse: record.clone(),
        formulation,
    };
    let e = simulate(
        &problem(Formulation::Nonlinear),
        &Options::history(Solver::Exact),
    );
    assert_eq!(e.err(), Some(topple::dynamics::SimError::ExactNeedsLinear));
    let r = simulate(
        &problem(Formulation::Linear),
        &Options::history(Solver::Exact),
    )
    .expect("simulates");
    assert_eq!(r.numerics.method, "exact");
    assert!(!r.rocked);
}

/// Runs `problem` with the exact solver and with dop853 at rtol 1e-12, checks
/// that they tell the same story (outcome, mode, every impact within 1e-8 s)
/// and that θ agrees to `theta_tol` rad along the history; returns the
/// largest difference in impact (and overturning) times.
fn exact_against_dop853(problem: &Problem<Record>, what: &str, theta_tol: f64) -> f64 {
    let history = |solver, times: Option<Vec<f64>>| {
        let mut o = Options::history(solver);
        o.max_free_impacts = 20;
        o.series_at = times;
        simulate(problem, &o).expect("simulates")
    };
    let (exact, numeric) = (history(Solver::Exact, None), history(solver(), None));
    assert_eq!(exact.numerics.method, "exact");
    assert_eq!(exact.overturned, numeric.overturned, "{what}");
    assert_eq!(exact.mode, numeric.mode, "{what}");
    assert_eq!(exact.impact_count, numeric.impact_count, "{what}");
    assert_eq!(exact.rocking_starts, numeric.rocking_starts, "{what}");
    assert_eq!(exact.impacts.len(), numeric.impacts.len(), "{what}");
    let mut d: f64 = 0.0;
    for (x, y) in exact.impacts.iter().zip(&numeric.impacts) {
        d = d.max((x.time - y.time).abs());
    }
    if let (Some(x), Some(y)) = (exact.overturn_time, numeric.overturn_time) {
        d = d.max((x - y).abs());
    }
    assert!(d <= 1e-8, "{what}: impact times differ by {d:e} s");
    // θ along the whole history, short of the fall of a block already bound
    // to overturn (there any difference grows as e^{pt}, whatever the solver).
    let end = if exact.overturned {
        exact.decided_at.min(exact.end_time)
    } else {
        exact.end_time.min(numeric.end_time)
    };
    let times: Vec<f64> = (0..500).map(|k| end * k as f64 / 500.0).collect();
    let a = history(Solver::Exact, Some(times.clone()));
    let b = history(solver(), Some(times));
    let (sa, sb) = (a.series.expect("series"), b.series.expect("series"));
    let dtheta = sa
        .theta
        .iter()
        .zip(&sb.theta)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(dtheta <= theta_tol, "{what}: θ differs by {dtheta:e} rad");
    eprintln!(
        "{what}: {} impacts, overturned {}, mode {:?}: impact times within {d:.1e} s, θ within {dtheta:.1e} rad",
        exact.impact_count, exact.overturned, exact.mode
    );
    d
}

#[test]
fn the_exact_solution_of_a_sampled_one_sine_agrees_with_dop853() {
    let b = block();
    // ω_p/p and a_p/(αg): standing (one impact during the pulse, then free
    // rocking), overturning after one impact (mode 1), overturning without
    // impact (mode 2).
    for (ratio, level, overturns, impacts) in [
        (5.0, 2.0, false, true),
        (3.0, 2.0, true, true),
        (1.0, 3.0, true, false),
    ] {
        let pulse = Pulse::new(
            PulseShape::OneSine,
            level * b.slenderness() * G,
            ratio * b.frequency_parameter(),
        )
        .expect("valid pulse");
        for n in [100, 1000, 10_000] {
            let problem = Problem {
                block: b,
                pulse: sampled(&pulse, n),
                formulation: Formulation::Linear,
            };
            let what = format!("one-sine ω_p/p = {ratio}, a_p = {level} αg, dt = T/{n}");
            exact_against_dop853(&problem, &what, 1e-8);
            let r = simulate(&problem, &Options::history(Solver::Exact)).expect("simulates");
            assert_eq!(r.overturned, overturns, "{what}");
            assert_eq!(
                matches!(r.mode, Some(OverturnMode::WithoutImpact)),
                overturns && !impacts,
                "{what}: {:?}",
                r.mode
            );
        }
    }
}

#[test]
fn the_exact_solution_of_a_random_record_agrees_with_dop853() {
    // A slender block (α = 0.15, p = 1.5 rad/s) under 30 s of random-like
    // motion: it survives after dozens of impacts, overturns after a few, or
    // chatters to rest hundreds of times before overturning.
    let b = Block::new(0.15, 1.5, Some(0.9), None, None).expect("valid block");
    let mut outcomes = Vec::new();
    for (seed, level) in [(3, 2.0), (1, 3.0), (2, 4.0)] {
        let acc = synthetic(seed, 3000, 0.01, level * b.slenderness() * G, 0.3, 5.0);
        let problem = Problem {
            block: b,
            pulse: Record::new(acc.into(), 0.01).expect("valid record"),
            formulation: Formulation::Linear,
        };
        exact_against_dop853(&problem, &format!("seed {seed}, peak {level} αg"), 1e-8);
        let r = simulate(&problem, &Options::history(Solver::Exact)).expect("simulates");
        outcomes.push((r.overturned, r.impact_count));
    }
    assert!(outcomes.iter().any(|&(o, n)| !o && n >= 50), "{outcomes:?}");
    assert!(outcomes.iter().any(|&(o, n)| o && n >= 300), "{outcomes:?}");
}

/// The linear formulation under `ground`, solved exactly, with θ at `times`.
fn linear_exact<G: topple::dynamics::Forcing>(b: Block, ground: G, times: Vec<f64>) -> Response {
    let problem = Problem {
        block: b,
        pulse: ground,
        formulation: Formulation::Linear,
    };
    simulate(&problem, &options_with(Solver::Exact, times)).expect("simulates")
}

#[test]
fn a_constant_ground_acceleration_rocks_the_block_as_housners_rectangular_pulse() {
    // Every sample equal: one line with u1 = 0 on each piece, re-anchored at
    // each sample, against the closed form of the rectangular pulse.
    let b = block();
    for (level, n) in [(1.5, 400), (3.0, 1000)] {
        let pulse = Pulse::new(
            PulseShape::Rectangular,
            level * b.slenderness() * G,
            2.0 * b.frequency_parameter(),
        )
        .expect("valid pulse");
        let dt = pulse.duration / n as f64;
        let record = Record::new(vec![pulse.amplitude; n + 1].into(), dt).expect("valid");
        let first = simulate(
            &Problem {
                block: b,
                pulse,
                formulation: Formulation::Linear,
            },
            &options_with(Solver::Exact, Vec::new()),
        )
        .expect("simulates");
        let end = 0.95 * first.overturn_time.unwrap_or(first.end_time);
        let times: Vec<f64> = (0..300).map(|k| end * k as f64 / 299.0).collect();
        let housner = linear_exact(b, pulse, times.clone());
        let sampled = linear_exact(b, record, times);
        let d = difference(&housner, &sampled);
        eprintln!("rectangular a_p = {level} αg over {n} pieces: differs by {d:.1e}");
        assert!(d < 1e-12, "a_p = {level} αg: {d:e}");
        assert!(sampled.numerics.steps_accepted >= n as u64);
    }
}

#[test]
fn a_200000_sample_record_runs_piece_by_piece_to_a_finite_answer() {
    let b = Block::new(0.15, 1.5, Some(0.9), None, None).expect("valid block");
    let n = 200_000;
    let acc = synthetic(11, n, 0.005, 1.5 * b.slenderness() * G, 0.3, 5.0);
    let problem = Problem {
        block: b,
        pulse: Record::new(acc.into(), 0.005).expect("valid record"),
        formulation: Formulation::Linear,
    };
    let mut o = Options::history(Solver::Exact);
    o.reactions = false;
    let r = simulate(&problem, &o).expect("simulates");
    assert!(r.rocked && r.impact_count > 100, "{:?}", r.impact_count);
    assert!(r.end_time.is_finite() && r.end_time >= 0.9 * (n - 1) as f64 * 0.005);
    assert!(r.peak_theta_over_alpha.is_finite());
    let e = r.numerics.error_estimate;
    assert!(e.is_finite() && e > 0.0 && e < 1e-9, "{e:e}");
}

#[test]
fn a_stiff_block_on_second_long_pieces_is_re_anchored_and_agrees_with_dop853() {
    // p = 50 rad/s on 1-s pieces: p·dt = 50, past the closed form's reach of
    // p τ = 20 before re-anchoring.
    let b = Block::new(0.25, 50.0, Some(0.9), None, None).expect("valid block");
    let c = b.slenderness() * G;
    // The slight exceedance grows by more than e^20 ≈ 5e8 before the fall:
    // the 1e-16 to which ü_g/g is known becomes a relative 1e-8 in θ (whatever
    // the solver), so θ is compared to 1e-7 rad there.
    for (acc, what, theta_tol) in [
        (
            vec![0.0, 0.6 * c, -1.01 * c, 0.3 * c, 0.0],
            "a brief exceedance",
            1e-8,
        ),
        (vec![0.0, 1.2 * c, 0.0], "a long exceedance", 1e-8),
        (
            vec![0.0, -0.999 * c, 0.999 * c, 0.0],
            "below the threshold",
            1e-8,
        ),
        (
            vec![0.0, (1.0 + 1e-8) * c, (1.0 + 1e-8) * c, 0.0],
            "a slight exceedance",
            1e-7,
        ),
    ] {
        let problem = Problem {
            block: b,
            pulse: Record::new(acc.into(), 1.0).expect("valid"),
            formulation: Formulation::Linear,
        };
        exact_against_dop853(&problem, what, theta_tol);
        let r = simulate(&problem, &Options::history(Solver::Exact)).expect("simulates");
        assert!(r.end_time.is_finite() && r.peak_theta_over_alpha.is_finite());
        if what == "a slight exceedance" {
            // Lifted by 1e-8 α just before the sample at t = 1, the block
            // leaves the unstable equilibrium as e^{pt}: it falls within the
            // next piece, more than 20/p after its start, so on a segment
            // re-anchored on the way.
            let start = r.rocking_start.expect("rocks");
            let fall = r.overturn_time.expect("overturns");
            assert!(start < 1.0 && fall < 2.0, "{start} to {fall}");
            assert!(fall - 1.0 > MAX_SEGMENT_PT / 50.0, "{start} to {fall}");
        }
    }
}

#[test]
fn a_record_grazing_the_threshold_lifts_the_block_by_a_hair() {
    // The record exceeds g α by a relative 1e-12 over 0.1 s: the block rocks,
    // by about 1e-12 α, and settles.
    let b = block();
    let c = Formulation::Linear.rocking_threshold(&b);
    let peak = (1.0 + 1e-12) * c;
    let record = Record::new(vec![0.0, peak, peak, 0.0, 0.0].into(), 0.1).expect("valid");
    let problem = Problem {
        block: b,
        pulse: record,
        formulation: Formulation::Linear,
    };
    let mut peaks = Vec::new();
    for s in [Solver::Exact, solver()] {
        let r = simulate(&problem, &Options::history(s)).expect("simulates");
        assert!(r.rocked, "{}", s.name());
        assert!(!r.overturned, "{}", s.name());
        assert!(r.peak_theta_over_alpha > 0.0, "{}", s.name());
        assert!(r.peak_theta_over_alpha < 1e-9, "{}", s.name());
        peaks.push(r.peak_theta_over_alpha);
    }
    eprintln!(
        "grazing record: peak θ/α exact {:e}, dop853 {:e}",
        peaks[0], peaks[1]
    );
}

/// Two pulses, the second longer and reversed, overlapping: a near-fault-like
/// record, in g.
fn near_fault(dt: f64) -> Vec<f64> {
    let n = (2.5 / dt).round() as usize;
    (0..=n)
        .map(|k| {
            let t = k as f64 * dt;
            let one = |t0: f64, tp: f64, a: f64| {
                let s = t - t0;
                if (0.0..=tp).contains(&s) {
                    a * (2.0 * std::f64::consts::PI * s / tp).sin()
                } else {
                    0.0
                }
            };
            one(0.1, 0.6, 0.45) + one(0.5, 1.4, -0.3)
        })
        .collect()
}

fn history(ground_motion: serde_json::Value, extra: serde_json::Value) -> serde_json::Value {
    let mut spec = json!({
        "kind": "time_history",
        "block": {"alpha": 0.25, "p": 2.14},
        "ground_motion": ground_motion,
    });
    if let (Some(o), Some(e)) = (spec.as_object_mut(), extra.as_object()) {
        for (k, v) in e {
            o.insert(k.clone(), v.clone());
        }
    }
    spec
}

fn run(spec: &serde_json::Value) -> serde_json::Value {
    let job = Job::from_value(spec).expect("valid spec");
    let Job::TimeHistory(h) = job else {
        panic!("a time history")
    };
    serde_json::to_value(h.run().expect("runs")).expect("serialises")
}

#[test]
fn a_near_fault_like_record_ends_in_a_finite_answer() {
    for formulation in ["nonlinear", "linear"] {
        let spec = history(
            json!({"dt": 0.005, "acc": near_fault(0.005), "unit": "g"}),
            json!({"formulation": formulation, "outputs": {"series": 200}}),
        );
        let r = run(&spec);
        assert_eq!(r["kind"], "time_history");
        assert_eq!(r["rocked"], true, "{formulation}");
        assert!(r["overturned"].is_boolean());
        assert!(r["impact_count"].as_u64().is_some());
        for key in ["end_time", "decided_at", "peak_theta_over_alpha"] {
            assert!(r[key].as_f64().is_some_and(f64::is_finite), "{key}: {r}");
        }
        let method = if formulation == "linear" {
            "exact"
        } else {
            "dop853"
        };
        assert_eq!(r["numerics"]["method"], method, "{formulation}");
        assert!(
            r["numerics"]["error_estimate"]
                .as_f64()
                .is_some_and(f64::is_finite)
        );
        assert!(r["numerics"]["wall_time_s"].as_f64().is_some());
        let series = &r["series"];
        assert_eq!(series["t"].as_array().map(Vec::len), Some(200));
        // The series' ground acceleration is the record's, in m/s².
        let t5 = series["t"][5].as_f64().expect("t");
        let a5 = series["ground_acceleration"][5].as_f64().expect("a");
        let record = Record::new(
            near_fault(0.005)
                .iter()
                .map(|a| a * G)
                .collect::<Vec<_>>()
                .into(),
            0.005,
        )
        .expect("valid");
        use topple::dynamics::Forcing;
        assert!((a5 - record.acceleration(t5)).abs() < 1e-12);
        // The spec echoed is the normalised one: samples in m/s², no pulse.
        assert_eq!(r["spec"]["ground_motion"]["unit"], "m/s2");
        assert!(r["spec"].get("pulse").is_none());
        assert!(
            (r["spec"]["ground_motion"]["acc"][40].as_f64().expect("a")
                - near_fault(0.005)[40] * G)
                .abs()
                < 1e-12
        );
    }
}

#[test]
fn a_record_job_reproduces_the_pulse_job() {
    let (alpha, p, ratio, level) = (0.25, 2.14, 3.0, 2.0);
    let (w, a) = (ratio * p, level * alpha * G);
    let t = 2.0 * std::f64::consts::PI / w;
    let n = 2000;
    let dt = t / n as f64;
    let acc: Vec<f64> = (0..=n).map(|k| a * (w * k as f64 * dt).sin()).collect();
    let record = run(&history(
        json!({"dt": dt, "acc": acc, "unit": "m/s2"}),
        json!({}),
    ));
    let pulse = run(&json!({
        "kind": "time_history",
        "block": {"alpha": alpha, "p": p},
        "pulse": {"type": "one_sine", "omega_p": w, "a_p": a},
    }));
    for key in ["overturned", "mode", "impact_count", "rocking_starts"] {
        assert_eq!(record[key], pulse[key], "{key}");
    }
    for key in ["rocking_start", "overturn_time"] {
        let (x, y) = (
            record[key].as_f64().expect("number"),
            pulse[key].as_f64().expect("number"),
        );
        assert!((x - y).abs() < 1e-5, "{key}: {x} vs {y}");
    }
}

fn pointer_of(spec: &serde_json::Value) -> String {
    match Job::from_value(spec) {
        Ok(_) => panic!("accepted: {spec}"),
        Err(e) => e.pointer,
    }
}

#[test]
fn invalid_records_are_refused_at_the_field() {
    let ok = || json!({"dt": 0.01, "acc": vec![0.1; 40], "unit": "g"});
    let with = |field: &str, v: serde_json::Value| {
        let mut g = ok();
        g[field] = v;
        history(g, json!({}))
    };
    let mut acc = vec![0.1; 40];
    acc[17] = 1e12;
    assert_eq!(
        pointer_of(&with("acc", json!(acc))),
        "/ground_motion/acc/17"
    );
    assert_eq!(pointer_of(&with("dt", json!(0.0))), "/ground_motion/dt");
    assert_eq!(pointer_of(&with("dt", json!(2.0))), "/ground_motion/dt");
    assert_eq!(pointer_of(&with("dt", json!(1e-6))), "/ground_motion/dt");
    assert_eq!(
        pointer_of(&with("unit", json!("ft/s2"))),
        "/ground_motion/unit"
    );
    assert_eq!(pointer_of(&with("acc", json!([0.1]))), "/ground_motion/acc");
    assert_eq!(
        pointer_of(&with(
            "acc",
            json!(vec![0.0; topple::jobs::spec::MAX_RECORD_SAMPLES + 1])
        )),
        "/ground_motion/acc"
    );
    assert_eq!(
        pointer_of(&with("acc", json!([0.1, "x", 0.2]))),
        "/ground_motion/acc/1"
    );
    let mut g = ok();
    g.as_object_mut().expect("object").remove("unit");
    assert_eq!(pointer_of(&history(g, json!({}))), "/ground_motion/unit");
    let mut g = ok();
    g.as_object_mut().expect("object").remove("dt");
    assert_eq!(pointer_of(&history(g, json!({}))), "/ground_motion/dt");
    let mut g = ok();
    g["extra"] = json!(1);
    assert!(pointer_of(&history(g, json!({}))).starts_with("/ground_motion"));
    // Exactly one of pulse / ground_motion.
    let both = history(
        ok(),
        json!({"pulse": {"type": "one_sine", "omega_p": 10.0, "a_p_g": 0.5}}),
    );
    assert_eq!(pointer_of(&both), "/ground_motion");
    let neither = json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14}});
    assert_eq!(pointer_of(&neither), "/pulse");
    // The closed form is for the linear formulation only.
    let exact = history(
        ok(),
        json!({"formulation": "nonlinear", "solver": {"method": "exact"}}),
    );
    assert_eq!(pointer_of(&exact), "/solver/method");
    let exact = history(
        ok(),
        json!({"formulation": "linear", "solver": {"method": "exact", "rtol": 1e-9}}),
    );
    assert_eq!(pointer_of(&exact), "/solver/rtol");
    // Spectra keep pulses only.
    let spectrum = json!({
        "kind": "spectrum",
        "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_sine"},
        "omega_ratio": {"from": 1, "to": 3, "steps": 3},
        "ground_motion": ok(),
    });
    assert!(Job::from_value(&spectrum).is_err());
}

#[test]
fn non_finite_samples_are_named_by_their_index() {
    let mut text = String::from(
        r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"ground_motion":{"dt":0.01,"unit":"g","acc":["#,
    );
    for k in 0..30 {
        if k > 0 {
            text.push(',');
        }
        text.push_str(if k == 17 { "NaN" } else { "0.1" });
    }
    text.push_str("]}}");
    let e = Job::parse(&text).expect_err("refused");
    assert_eq!(e.pointer, "/ground_motion/acc/17", "{e}");
    let e = Job::parse(&text.replace("NaN", "1e400")).expect_err("refused");
    assert_eq!(e.pointer, "/ground_motion/acc/17", "{e}");
}

#[test]
fn the_linear_formulation_of_a_record_defaults_to_the_exact_solver() {
    let spec = |formulation: &str| {
        history(
            json!({"dt": 0.01, "acc": near_fault(0.01), "unit": "g"}),
            json!({"formulation": formulation}),
        )
    };
    let method = |formulation| match Job::from_value(&spec(formulation)).expect("valid") {
        Job::TimeHistory(h) => h.solver.method.name(),
        _ => panic!("a time history"),
    };
    assert_eq!(method("linear"), "exact");
    assert_eq!(method("nonlinear"), "dop853");
    // The normalised spec says so, and runs with it.
    let r = run(&spec("linear"));
    assert_eq!(r["spec"]["solver"]["method"], "exact", "{}", r["spec"]);
    assert_eq!(r["numerics"]["method"], "exact");
    let explicit = history(
        json!({"dt": 0.01, "acc": near_fault(0.01), "unit": "g"}),
        json!({"formulation": "linear", "solver": {"method": "dop853"}}),
    );
    let Job::TimeHistory(h) = Job::from_value(&explicit).expect("valid") else {
        panic!("a time history")
    };
    assert_eq!(h.solver.method.name(), "dop853");
}

#[test]
fn the_canonical_spec_carries_the_record() {
    let acc = near_fault(0.01);
    let in_g = Job::from_value(&history(
        json!({"dt": 0.01, "acc": acc, "unit": "g"}),
        json!({}),
    ))
    .expect("valid");
    let in_si: Vec<f64> = acc.iter().map(|a| a * G).collect();
    let same = Job::from_value(&history(
        json!({"dt": 0.01, "acc": in_si, "unit": "m/s2"}),
        json!({}),
    ))
    .expect("valid");
    assert_eq!(cache_key(&in_g), cache_key(&same));
    let canonical = canonical_spec(&in_g);
    assert!(canonical.contains("\"ground_motion\""), "{canonical}");
    assert!(!canonical.contains("\"pulse\""));
    let mut changed = acc.clone();
    changed[100] += 1e-3;
    let other = Job::from_value(&history(
        json!({"dt": 0.01, "acc": changed, "unit": "g"}),
        json!({}),
    ))
    .expect("valid");
    assert_ne!(cache_key(&in_g), cache_key(&other));
    // The normalised spec validates to itself.
    let again = Job::from_value(&serde_json::to_value(&in_g).expect("serialises")).expect("valid");
    assert_eq!(in_g, again);
    let _: Arc<[f64]> = match &again {
        Job::TimeHistory(h) => h.ground_motion.as_ref().expect("record").acc.clone(),
        _ => panic!("a time history"),
    };
}

#[test]
fn a_record_starting_above_the_threshold_needs_the_friction_of_the_matching_pulse() {
    // A one-cosine pulse sampled at T/4000 starts at a_p = 6 αg, above g tan α:
    // rocking starts at t = 0 and the demand there is eq. 51, as for the pulse
    // itself, not the at-rest a_p/g.
    let b = block();
    let pulse = Pulse::new(PulseShape::OneCosine, 6.0 * 0.25 * G, 4.0 * 2.14).expect("valid");
    let n = 4000;
    let dt = pulse.duration / n as f64;
    let acc: Vec<f64> = (0..=n)
        .map(|k| pulse.amplitude * (pulse.circular_frequency * k as f64 * dt).cos())
        .collect();
    let record = Record::new(acc.into(), dt).expect("valid record");
    let demand = |r: &Response| {
        let f = r.friction.expect("reactions followed");
        (
            f.peak.expect("bounded"),
            f.peak_time.expect("time"),
            f.initiation.expect("rocks"),
        )
    };
    let analytic = simulate(
        &Problem {
            block: b,
            pulse,
            formulation: Formulation::Nonlinear,
        },
        &Options::history(solver()),
    )
    .expect("simulates");
    let sampled = simulate(
        &Problem {
            block: b,
            pulse: record,
            formulation: Formulation::Nonlinear,
        },
        &Options::history(solver()),
    )
    .expect("simulates");
    let (pa, ta, ia) = demand(&analytic);
    let (ps, ts, is) = demand(&sampled);
    assert_eq!(sampled.rocking_start, Some(0.0));
    assert!(ta < 1e-6 && ts < 1e-6, "peak times {ta}, {ts}");
    assert!(
        (pa - ps).abs() < 1e-10 && (ia - is).abs() < 1e-12,
        "{pa} vs {ps}"
    );
    assert!((ps - 0.5096).abs() < 5e-4, "{ps}");
    assert!(ps < 0.6 * 6.0 * 0.25, "at-rest a_p/g = 1.5 counted: {ps}");
}
