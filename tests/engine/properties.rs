//! Physical properties every solution must have.

use topple::dynamics::response::Response;
use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, Solver, simulate,
};

const G: f64 = 9.81;

fn solvers(formulation: Formulation) -> Vec<Solver> {
    let mut v = vec![
        Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-11,
            atol: 1e-13,
        },
        Solver::RungeKutta {
            method: Method::Dopri5,
            rtol: 1e-11,
            atol: 1e-13,
        },
    ];
    if formulation == Formulation::Linear {
        v.push(Solver::Exact);
    }
    v
}

/// No ground motion at all: free rocking from an initial state.
fn still_ground() -> Pulse {
    Pulse {
        shape: PulseShape::OneSine,
        amplitude: 0.0,
        circular_frequency: 1.0,
        carrier: 1.0,
        phase: 0.0,
        wave: topple::dynamics::excitation::Wave::Cosine,
        duration: 0.0,
        extrema: topple::dynamics::excitation::Extrema::NONE,
    }
}

fn free_rocking(
    block: Block,
    formulation: Formulation,
    solver: Solver,
    theta0: f64,
    samples: usize,
    end: f64,
) -> Response {
    let mut opts = Options::history(solver);
    opts.initial_state = Some([theta0, 0.0]);
    opts.series_at = Some(
        (0..samples)
            .map(|k| end * k as f64 / samples as f64)
            .collect(),
    );
    opts.reactions = false;
    simulate(
        &Problem {
            block,
            pulse: still_ground(),
            formulation,
        },
        &opts,
    )
    .expect("simulates")
}

#[test]
fn free_rocking_reaches_zero_after_housners_quarter_period() {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    for theta0 in [0.02f64, 0.15, 0.24] {
        let expected = (1.0f64 / (1.0 - theta0 / 0.25)).acosh() / 2.14;
        for solver in solvers(Formulation::Linear) {
            let r = free_rocking(block, Formulation::Linear, solver, theta0, 2, 1.0);
            let first = r.impacts.first().expect("impact").time;
            assert!(
                (first - expected).abs() < 1e-9,
                "{}: θ0 = {theta0}: {first} vs {expected}",
                solver.name()
            );
        }
    }
}

#[test]
fn energy_never_increases_in_free_rocking_and_each_impact_multiplies_velocity_by_eta() {
    for formulation in [Formulation::Linear, Formulation::Nonlinear] {
        let block = Block::new(0.3, 2.0, Some(0.85), None, None).expect("valid");
        for solver in solvers(formulation) {
            let r = free_rocking(block, formulation, solver, 0.27, 4000, 12.0);
            assert!(!r.overturned);
            assert!(r.impact_count >= 10, "{}", r.impact_count);
            for i in &r.impacts {
                assert!(
                    (i.velocity_after - 0.85 * i.velocity_before).abs()
                        <= 1e-15 * i.velocity_before.abs()
                );
            }
            let s = r.series.expect("series");
            let mut last = f64::INFINITY;
            for k in 0..s.t.len() {
                let e = formulation.barrier_excess(&block, s.theta[k], s.theta_dot[k]);
                assert!(
                    e <= last + 1e-10,
                    "{}: energy rose at t = {}: {last} → {e}",
                    solver.name(),
                    s.t[k]
                );
                last = e;
            }
            // and it did fall: the impacts dissipate.
            let first = formulation.barrier_excess(&block, s.theta[0], s.theta_dot[0]);
            assert!(last < first - 1e-3);
            assert!(r.rest_time.is_some(), "comes to rest");
        }
    }
}

#[test]
fn a_negative_pulse_mirrors_the_rotation() {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    for formulation in [Formulation::Linear, Formulation::Nonlinear] {
        for solver in solvers(formulation) {
            for shape in [
                PulseShape::OneSine,
                PulseShape::OneCosine,
                PulseShape::Cn(2),
            ] {
                let run = |sign: f64| {
                    let pulse =
                        Pulse::new(shape, sign * 3.5 * 0.25 * G, 3.0 * 2.14).expect("valid");
                    let mut opts = Options::history(solver);
                    opts.series_points = Some(300);
                    simulate(
                        &Problem {
                            block,
                            pulse,
                            formulation,
                        },
                        &opts,
                    )
                    .expect("simulates")
                };
                let (up, down) = (run(1.0), run(-1.0));
                assert_eq!(up.overturned, down.overturned);
                assert_eq!(up.impact_count, down.impact_count);
                let (a, b) = (up.series.expect("series"), down.series.expect("series"));
                assert_eq!(a.theta.len(), b.theta.len());
                for k in 0..a.theta.len() {
                    assert!(
                        (a.theta[k] + b.theta[k]).abs() <= 1e-12,
                        "{k}: {} vs {}",
                        a.theta[k],
                        b.theta[k]
                    );
                }
                assert!(a.theta.iter().any(|&x| x != 0.0));
            }
        }
    }
}

#[test]
fn a_pulse_below_the_threshold_does_not_rock_the_block() {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    let nl = Pulse::new(PulseShape::OneSine, 0.999 * G * 0.25f64.tan(), 5.0).expect("valid");
    let r = simulate(
        &Problem {
            block,
            pulse: nl,
            formulation: Formulation::Nonlinear,
        },
        &Options::history(solvers(Formulation::Nonlinear)[0]),
    )
    .expect("simulates");
    assert!(!r.rocked && !r.overturned && r.impact_count == 0);
    // The friction demand of a block moving with the ground is |ü_g|/g.
    let peak = r.friction.and_then(|f| f.peak).expect("bounded demand");
    assert!((peak - 0.999 * 0.25f64.tan()).abs() < 1e-12, "{peak}");
}

#[test]
fn rocking_starts_at_the_paper_phase_psi() {
    // One-sine: sin(ω t) = g tan α / a_p (nonlinear), g α / a_p (linear).
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    for (formulation, threshold) in [
        (Formulation::Nonlinear, 0.25f64.tan()),
        (Formulation::Linear, 0.25),
    ] {
        let pulse = Pulse::new(PulseShape::OneSine, 2.0 * G, 10.0).expect("valid");
        let r = simulate(
            &Problem {
                block,
                pulse,
                formulation,
            },
            &Options::outcome(solvers(formulation)[0]),
        )
        .expect("simulates");
        let psi = (threshold / 2.0f64).asin();
        assert!((r.rocking_start.expect("rocks") - psi / 10.0).abs() < 1e-15);
    }
}

#[test]
fn following_no_free_impacts_ends_at_the_pulse_with_the_exact_decision() {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    let pulse = Pulse::new(PulseShape::OneSine, 2.5 * 0.25 * G, 5.0 * 2.14).expect("valid");
    let problem = Problem {
        block,
        pulse,
        formulation: Formulation::Linear,
    };
    let mut opts = Options::history(Solver::Exact);
    opts.max_free_impacts = 0;
    let r = simulate(&problem, &opts).expect("simulates");
    assert_eq!(r.end_time, pulse.duration);
    let full = simulate(&problem, &Options::history(Solver::Exact)).expect("simulates");
    assert_eq!(r.overturned, full.overturned);
    assert!(full.impact_count > r.impact_count);
}
