//! Extreme but valid inputs: every run must end in a finite answer with a sane
//! numerics report, for both formulations and every applicable solver.

use std::f64::consts::FRAC_PI_2;

use topple::dynamics::response::Warning;
use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, Response, Solver, simulate,
};

const G: f64 = 9.81;
const ALPHA: f64 = 0.25;
const P: f64 = 2.14;
const RTOL: f64 = 1e-8;
const ATOL: f64 = 1e-10;

/// Every (formulation, solver) pair that makes sense: exact for linear only,
/// dopri5 and dop853 for both.
fn configurations() -> Vec<(Formulation, Solver)> {
    let rk = |method| Solver::RungeKutta {
        method,
        rtol: RTOL,
        atol: ATOL,
    };
    vec![
        (Formulation::Linear, Solver::Exact),
        (Formulation::Linear, rk(Method::Dopri5)),
        (Formulation::Linear, rk(Method::Dop853)),
        (Formulation::Nonlinear, rk(Method::Dopri5)),
        (Formulation::Nonlinear, rk(Method::Dop853)),
    ]
}

fn block(alpha: f64, p: f64, eta: Option<f64>) -> Block {
    Block::new(alpha, p, eta, None, None).expect("valid block")
}

fn pulse(shape: PulseShape, a_p: f64, omega_p: f64) -> Pulse {
    Pulse::new(shape, a_p, omega_p).expect("valid pulse")
}

fn label(problem: &Problem, solver: &Solver) -> String {
    format!(
        "{:?} {} {} alpha={} p={} eta={} a_p/(alpha g)={} omega_p/p={}",
        problem.pulse.shape,
        problem.formulation.name(),
        solver.name(),
        problem.block.slenderness(),
        problem.block.frequency_parameter(),
        problem.block.restitution(),
        problem.pulse.amplitude / (problem.block.slenderness() * problem.block.gravity()),
        problem.pulse.circular_frequency / problem.block.frequency_parameter(),
    )
}

/// Runs one history and checks that the answer and its numerics report are sane.
fn run_sane(problem: &Problem, solver: Solver) -> Response {
    let what = label(problem, &solver);
    let r = simulate(problem, &Options::history(solver))
        .unwrap_or_else(|e| panic!("{what}: simulation failed: {e}"));
    eprintln!(
        "{what}: rocked={} overturned={} mode={:?} impacts={} rest={:?} end={:.6} peak={:.4} steps={} events={} err={:.2e} wall={:.3}s warnings={:?}",
        r.rocked,
        r.overturned,
        r.mode,
        r.impact_count,
        r.rest_time,
        r.end_time,
        r.peak_theta_over_alpha,
        r.numerics.steps_accepted,
        r.numerics.events,
        r.numerics.error_estimate,
        r.numerics.wall_time,
        r.warnings,
    );
    numerics_are_sane(&r, solver, &what);
    times_are_inside(&r, &what);
    demand_is_sane(&r, &what);
    outcome_is_consistent(&r, problem, &what);
    r
}

/// The numerics report of `r` (solved by `solver`) fits its answer:
/// steps and events where it rocked, finite estimates, the tolerances
/// asked.
fn numerics_are_sane(r: &Response, solver: Solver, what: &str) {
    let n = &r.numerics;
    assert_eq!(n.method, solver.name(), "{what}");
    if r.rocked {
        assert!(n.steps_accepted > 0, "{what}: no step accepted");
        assert!(n.events >= 1, "{what}: rocked without an event");
        assert!(r.rocking_start.is_some(), "{what}: rocked without a start");
        assert!(r.rocking_starts >= 1, "{what}");
    } else {
        assert!(!r.overturned, "{what}: overturned without rocking");
        assert_eq!(r.impact_count, 0, "{what}");
        assert!(r.rocking_start.is_none(), "{what}");
        assert_eq!(r.peak_theta_over_alpha, 0.0, "{what}");
    }
    assert!(
        n.error_estimate.is_finite() && n.error_estimate >= 0.0,
        "{what}: error estimate {}",
        n.error_estimate
    );
    assert!(
        n.wall_time.is_finite() && n.wall_time >= 0.0,
        "{what}: wall time {}",
        n.wall_time
    );
    match solver {
        Solver::Exact => {
            assert_eq!(n.rtol, None, "{what}");
            assert_eq!(n.atol, None, "{what}");
        }
        Solver::RungeKutta { rtol, atol, .. } => {
            assert_eq!(n.rtol, Some(rtol), "{what}");
            assert_eq!(n.atol, Some(atol), "{what}");
            if r.rocked {
                assert!(n.rhs_evaluations > 0, "{what}");
            }
        }
    }
}

/// Every time `r` reports is finite and inside the simulated interval.
fn times_are_inside(r: &Response, what: &str) {
    let end = r.end_time;
    assert!(end.is_finite() && end >= 0.0, "{what}: end time {end}");
    assert!(
        r.decided_at.is_finite(),
        "{what}: decided_at {}",
        r.decided_at
    );
    assert!(r.decided_at <= end, "{what}: decided after the end");
    for (name, t) in [
        ("rocking_start", r.rocking_start),
        ("overturn_time", r.overturn_time),
        ("rest_time", r.rest_time),
    ] {
        if let Some(t) = t {
            assert!(
                t.is_finite() && (0.0..=end).contains(&t),
                "{what}: {name} = {t} outside [0, {end}]"
            );
        }
    }
    for (k, i) in r.impacts.iter().enumerate() {
        assert!(
            i.time.is_finite() && (0.0..=end).contains(&i.time),
            "{what}: impact {k} at {} outside [0, {end}]",
            i.time
        );
        assert!(
            i.velocity_before.is_finite() && i.velocity_after.is_finite(),
            "{what}: impact {k} velocities"
        );
    }
    assert!(r.impacts.len() as u64 <= r.impact_count, "{what}");
}

/// The friction demand of `r` is finite where bounded, unbounded only
/// after lift-off; its warnings' times are finite.
fn demand_is_sane(r: &Response, what: &str) {
    if let Some(f) = r.friction {
        match (f.peak, f.peak_time) {
            (Some(peak), Some(time)) => {
                assert!(peak.is_finite() && peak >= 0.0, "{what}: peak demand");
                assert!(time.is_finite(), "{what}: peak demand time");
                assert!(f.first_lift_off.is_none(), "{what}: bounded after lift-off");
            }
            (None, None) => assert!(
                f.first_lift_off.is_some(),
                "{what}: unbounded without lift-off"
            ),
            other => panic!("{what}: peak and its time disagree: {other:?}"),
        }
        if let Some(i) = f.initiation {
            assert!(i.is_finite(), "{what}: initiation demand");
        }
    }
    for w in &r.warnings {
        if let Warning::Sliding(t) | Warning::LiftOff(t) | Warning::DemandExcludesFall(t) = *w {
            assert!(t.is_finite(), "{what}: warning time {t}");
        }
    }
}

/// The peak rotation of `r` stays below overturning, and its outcome's
/// bookkeeping agrees: a mode and no rest when it overturned, neither a
/// mode nor an overturning time when not.
fn outcome_is_consistent(r: &Response, problem: &Problem, what: &str) {
    let cap = FRAC_PI_2 / problem.block.slenderness() * (1.0 + 1e-9);
    assert!(
        r.peak_theta_over_alpha.is_finite() && r.peak_theta_over_alpha <= cap,
        "{what}: peak theta/alpha {} above pi/(2 alpha) = {cap}",
        r.peak_theta_over_alpha
    );
    // Outcome bookkeeping.
    if r.overturned {
        assert!(r.mode.is_some(), "{what}: overturned without a mode");
        assert!(r.rest_time.is_none(), "{what}: overturned and at rest");
    } else {
        assert!(r.mode.is_none(), "{what}");
        assert!(r.overturn_time.is_none(), "{what}");
    }
}

fn problem(formulation: Formulation, block: Block, pulse: Pulse) -> Problem {
    Problem {
        block,
        pulse,
        formulation,
    }
}

fn sweep_frequency(omega_ratio: f64) {
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for (formulation, solver) in configurations() {
            let pr = problem(
                formulation,
                block(ALPHA, P, None),
                pulse(shape, 3.0 * ALPHA * G, omega_ratio * P),
            );
            let r = run_sane(&pr, solver);
            assert!(r.rocked, "3 alpha g exceeds both thresholds");
        }
    }
}

#[test]
fn very_long_pulse_omega_over_p_0_01_gives_finite_sane_results() {
    sweep_frequency(0.01);
}

#[test]
fn long_pulse_omega_over_p_0_1_gives_finite_sane_results() {
    sweep_frequency(0.1);
}

#[test]
fn short_pulse_omega_over_p_100_gives_finite_sane_results() {
    sweep_frequency(100.0);
}

#[test]
fn very_short_pulse_omega_over_p_1000_gives_finite_sane_results() {
    sweep_frequency(1000.0);
}

#[test]
fn very_slender_block_alpha_1e_minus_4_gives_finite_sane_results() {
    let alpha = 1e-4;
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for (formulation, solver) in configurations() {
            let pr = problem(
                formulation,
                block(alpha, P, None),
                pulse(shape, 3.0 * alpha * G, 5.0 * P),
            );
            let r = run_sane(&pr, solver);
            assert!(r.rocked);
        }
    }
}

#[test]
fn stocky_block_alpha_1_2_has_housner_eta_zero_and_gives_finite_sane_results() {
    let alpha = 1.2;
    let b = block(alpha, P, None);
    assert_eq!(
        b.restitution(),
        0.0,
        "Housner's eta vanishes for alpha = 1.2"
    );
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for (formulation, solver) in configurations() {
            let pr = problem(formulation, b, pulse(shape, 3.0 * alpha * G, 5.0 * P));
            let r = run_sane(&pr, solver);
            assert!(r.rocked);
            // With eta = 0 every impact stops the block.
            for i in &r.impacts {
                assert_eq!(i.velocity_after, 0.0);
            }
        }
    }
}

#[test]
fn perfectly_plastic_impacts_eta_0_stop_the_block_at_the_first_impact() {
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for (formulation, solver) in configurations() {
            let pr = problem(
                formulation,
                block(ALPHA, P, Some(0.0)),
                pulse(shape, 2.5 * ALPHA * G, 5.0 * P),
            );
            let r = run_sane(&pr, solver);
            assert!(r.rocked);
            for i in &r.impacts {
                assert_eq!(i.velocity_after, 0.0);
            }
            if !r.overturned {
                let rest = r
                    .rest_time
                    .expect("an eta = 0 block that survives comes to rest");
                assert!(rest.is_finite());
            }
        }
    }
}

#[test]
fn elastic_impacts_eta_1_never_rest_and_truncate_free_rocking_quickly() {
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for (formulation, solver) in configurations() {
            let pr = problem(
                formulation,
                block(ALPHA, P, Some(1.0)),
                pulse(shape, 2.5 * ALPHA * G, 5.0 * P),
            );
            let r = run_sane(&pr, solver);
            let what = label(&pr, &solver);
            assert!(r.rocked, "{what}");
            assert_eq!(r.rest_time, None, "{what}: an elastic block never rests");
            let truncated = r
                .warnings
                .iter()
                .any(|w| matches!(w, Warning::FreeRockingTruncated(_)));
            assert!(
                r.overturned || truncated,
                "{what}: neither overturned nor reported truncated free rocking: {:?}",
                r.warnings
            );
            if truncated {
                assert!(r.impact_count >= 1000, "{what}");
            }
            for i in &r.impacts {
                assert_eq!(i.velocity_after, i.velocity_before, "{what}");
            }
            assert!(
                r.numerics.wall_time < 10.0,
                "{what}: took {} s",
                r.numerics.wall_time
            );
        }
    }
}

fn threshold(formulation: Formulation, b: &Block) -> f64 {
    match formulation {
        Formulation::Linear => b.gravity() * b.slenderness(),
        Formulation::Nonlinear => b.gravity() * b.slenderness().tan(),
    }
}

#[test]
fn amplitude_just_above_the_threshold_rocks_without_overturning() {
    let b = block(ALPHA, P, None);
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for omega_ratio in [0.5, 5.0] {
            for (formulation, solver) in configurations() {
                let thr = threshold(formulation, &b);
                assert_eq!(thr, formulation.rocking_threshold(&b));
                let pr = problem(
                    formulation,
                    b,
                    pulse(shape, (1.0 + 1e-12) * thr, omega_ratio * P),
                );
                let r = run_sane(&pr, solver);
                let what = label(&pr, &solver);
                assert!(r.rocked, "{what}: must rock just above the threshold");
                assert!(!r.overturned, "{what}: must not overturn");
                assert!(r.peak_theta_over_alpha < 1e-3, "{what}");
            }
        }
    }
}

#[test]
fn amplitude_exactly_at_the_threshold_does_not_rock() {
    let b = block(ALPHA, P, None);
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for (formulation, solver) in configurations() {
            let thr = threshold(formulation, &b);
            for a_p in [thr, -thr] {
                let pr = problem(formulation, b, pulse(shape, a_p, 5.0 * P));
                let r = run_sane(&pr, solver);
                assert!(
                    !r.rocked,
                    "{}: rocked at the threshold",
                    label(&pr, &solver)
                );
            }
        }
    }
}

#[test]
fn huge_amplitude_1e4_alpha_g_overturns_at_a_finite_time() {
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for omega_ratio in [0.5, 5.0] {
            for (formulation, solver) in configurations() {
                let pr = problem(
                    formulation,
                    block(ALPHA, P, None),
                    pulse(shape, 1e4 * ALPHA * G, omega_ratio * P),
                );
                let r = run_sane(&pr, solver);
                let what = label(&pr, &solver);
                assert!(r.overturned, "{what}");
                let t = r.overturn_time.expect("overturn time");
                assert!(t.is_finite() && t > 0.0, "{what}: {t}");
            }
        }
    }
}

#[test]
fn small_block_p_50_gives_finite_sane_results() {
    for shape in [PulseShape::OneSine, PulseShape::OneCosine] {
        for omega_ratio in [0.5, 5.0] {
            for (formulation, solver) in configurations() {
                let pr = problem(
                    formulation,
                    block(ALPHA, 50.0, None),
                    pulse(shape, 3.0 * ALPHA * G, omega_ratio * 50.0),
                );
                let r = run_sane(&pr, solver);
                assert!(r.rocked);
            }
        }
    }
}

#[test]
fn long_free_rocking_records_hundreds_of_ordered_impacts_scaled_by_eta_and_rests() {
    let eta = 0.95;
    for (formulation, solver) in configurations() {
        let pr = problem(
            formulation,
            block(ALPHA, P, Some(eta)),
            pulse(PulseShape::OneSine, 2.5 * ALPHA * G, 5.0 * P),
        );
        let r = run_sane(&pr, solver);
        let what = label(&pr, &solver);
        assert!(!r.overturned, "{what}: must survive");
        assert!(r.impact_count >= 100, "{what}: {} impacts", r.impact_count);
        // Every impact is listed, but for the chattering tail summed in closed form.
        assert_eq!(
            r.impacts.len() as u64 + r.summed_impacts,
            r.impact_count,
            "{what}"
        );
        assert!(r.impacts.len() >= 100, "{what}: {} listed", r.impacts.len());
        for w in r.impacts.windows(2) {
            assert!(
                w[1].time > w[0].time,
                "{what}: impacts not strictly increasing: {} then {}",
                w[0].time,
                w[1].time
            );
        }
        for (k, i) in r.impacts.iter().enumerate() {
            let expected = eta * i.velocity_before.abs();
            assert!(
                (i.velocity_after.abs() - expected).abs() <= 1e-12 * expected,
                "{what}: impact {k}: |after| = {} but eta |before| = {expected}",
                i.velocity_after.abs()
            );
        }
        let rest = r.rest_time.expect("the block comes to rest");
        assert!(rest.is_finite(), "{what}");
        assert!(
            !r.warnings
                .iter()
                .any(|w| matches!(w, Warning::FreeRockingTruncated(_))),
            "{what}: free rocking truncated before rest"
        );
    }
}

/// A pulse that barely exceeds the rocking threshold: each lift-off is a flight
/// of ~1e-24 rad/s that lands exactly at the end of its exceedance window. The
/// block must wait for the next window there, not lift again in an empty one.
#[test]
fn a_pulse_grazing_the_threshold_ends_in_a_few_impacts() {
    let b = Block::new(0.3544, 4.734, Some(0.5425), None, None).expect("valid block");
    let a_p = 1.0440824777601374 * b.slenderness() * b.gravity();
    let p = pulse(PulseShape::Cn(3), a_p, 4.6687 * b.frequency_parameter());
    let problem = Problem {
        block: b,
        pulse: p,
        formulation: Formulation::Nonlinear,
    };
    for (formulation, solver) in configurations() {
        if formulation != Formulation::Nonlinear {
            continue;
        }
        let r = simulate(&problem, &Options::outcome(solver)).expect("finishes");
        assert!(r.rocked && !r.overturned);
        // A few lift-offs per window of the three-cycle pulse, not millions.
        assert!(r.impact_count <= 100, "{} impacts", r.impact_count);
    }
}
