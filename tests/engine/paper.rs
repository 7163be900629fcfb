//! Acceptance values read off Makris & Zhang (2001): Figs. 7–10 and eq. 51.

use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, Solver, simulate,
};

const G: f64 = 9.81;

fn locomotive() -> Block {
    Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid block")
}

fn outcome(problem: &Problem, solver: Solver) -> (bool, u64) {
    let r = simulate(problem, &Options::outcome(solver)).expect("simulates");
    (r.overturned, r.impact_count)
}

/// Amplitudes (in αg) where the outcome (overturned, mode) flips in [lo, hi]:
/// a scan at `step` followed by bisection to 1e-6 αg.
fn flips(
    block: Block,
    shape: PulseShape,
    ratio: f64,
    formulation: Formulation,
    solver: Solver,
    (lo, hi, step): (f64, f64, f64),
) -> Vec<(f64, bool, Option<u8>, u64)> {
    let unit = block.slenderness() * G;
    let at = |level: f64| {
        let pulse = Pulse::new(shape, level * unit, ratio * block.frequency_parameter())
            .expect("valid pulse");
        let r = simulate(
            &Problem {
                block,
                pulse,
                formulation,
            },
            &Options::outcome(solver),
        )
        .expect("simulates");
        (r.overturned, r.mode.map(|m| m.number()), r.impact_count)
    };
    let mut out = Vec::new();
    let mut a = lo;
    let mut prev = at(a);
    while a < hi {
        let b = a + step;
        let cur = at(b);
        if (cur.0, cur.1) != (prev.0, prev.1) {
            let (mut l, mut h) = (a, b);
            while h - l > 1e-6 {
                let m = 0.5 * (l + h);
                let o = at(m);
                if (o.0, o.1) == (prev.0, prev.1) {
                    l = m;
                } else {
                    h = m;
                }
            }
            let o = at(h);
            out.push((0.5 * (l + h), o.0, o.1, o.2));
        }
        prev = cur;
        a = b;
    }
    out
}

fn assert_within(value: f64, expected: f64, rel: f64, what: &str) {
    assert!(
        ((value - expected) / expected).abs() <= rel,
        "{what}: {value} not within {}% of {expected}",
        rel * 100.0
    );
}

#[test]
fn figs_7_and_8_outcome_flips_at_3_01_then_6_32_then_7_17_alpha_g() {
    let solvers = [
        Solver::Exact,
        Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        },
        Solver::RungeKutta {
            method: Method::Dopri5,
            rtol: 1e-10,
            atol: 1e-12,
        },
    ];
    for solver in solvers {
        let f = flips(
            locomotive(),
            PulseShape::OneSine,
            5.0,
            Formulation::Linear,
            solver,
            (2.5, 8.0, 0.05),
        );
        assert_eq!(f.len(), 3, "{}: flips {f:?}", solver.name());
        // survives → mode 1 with exactly one impact
        assert_within(f[0].0, 3.01, 0.005, "first flip");
        assert_eq!((f[0].1, f[0].2, f[0].3), (true, Some(1), 1));
        // mode 1 → survives
        assert_within(f[1].0, 6.32, 0.005, "second flip");
        assert!(!f[1].1);
        // survives → mode 2, no impact
        assert_within(f[2].0, 7.17, 0.005, "third flip");
        assert_eq!((f[2].1, f[2].2, f[2].3), (true, Some(2), 0));
    }
}

#[test]
fn locomotive_nonlinear_one_sine_at_15_7_rad_s_overturns_at_2_25_g_not_at_2_20_g() {
    let block = locomotive();
    for method in [Method::Dop853, Method::Dopri5] {
        let solver = Solver::RungeKutta {
            method,
            rtol: 1e-10,
            atol: 1e-12,
        };
        let run = |a_g: f64| {
            let pulse = Pulse::new(PulseShape::OneSine, a_g * G, 15.7).expect("valid");
            simulate(
                &Problem {
                    block,
                    pulse,
                    formulation: Formulation::Nonlinear,
                },
                &Options::history(solver),
            )
            .expect("simulates")
        };
        let strong = run(2.25);
        assert!(strong.overturned);
        assert_eq!(strong.mode.map(|m| m.number()), Some(1));
        let weak = run(2.20);
        assert!(!weak.overturned, "{:?}", weak.mode);
    }
}

#[test]
fn locomotive_nonlinear_minimum_is_about_2_22_g_and_linear_is_much_higher() {
    let block = locomotive();
    let ratio = 15.7 / 2.14;
    let solver = Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-10,
        atol: 1e-12,
    };
    // a_p/(αg) = 2.22/0.25 = 8.88 for the nonlinear formulation.
    let f = flips(
        block,
        PulseShape::OneSine,
        ratio,
        Formulation::Nonlinear,
        solver,
        (8.0, 10.0, 0.02),
    );
    let first = f.first().expect("overturns");
    assert!(first.1 && first.2 == Some(1), "{f:?}");
    assert_within(first.0 * 0.25, 2.22, 0.01, "nonlinear minimum (g)");
    // The linear formulation needs 3.24 g, in mode 2.
    let f = flips(
        block,
        PulseShape::OneSine,
        ratio,
        Formulation::Linear,
        Solver::Exact,
        (8.0, 14.0, 0.02),
    );
    let first = f.first().expect("overturns");
    assert!(first.1 && first.2 == Some(2), "{f:?}");
    assert_within(first.0 * 0.25, 3.24, 0.01, "linear minimum (g)");
}

#[test]
fn friction_demand_peaks_near_2_5_tan_alpha_for_the_locomotive_at_8_9_alpha_g() {
    let block = locomotive();
    let pulse = Pulse::new(PulseShape::OneSine, 8.9 * 0.25 * G, 15.7).expect("valid");
    let r = simulate(
        &Problem {
            block,
            pulse,
            formulation: Formulation::Nonlinear,
        },
        &Options::history(Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        }),
    )
    .expect("simulates");
    let f = r.friction.expect("reactions followed");
    let tan = 0.25f64.tan();
    assert!((f.initiation.expect("rocked") - tan).abs() < 1e-12);
    let peak = f.peak.expect("no lift-off");
    assert!(
        ((peak / tan) - 2.5).abs() <= 0.25,
        "peak {} tan α",
        peak / tan
    );
}

#[test]
fn one_cosine_initiation_demand_at_6_alpha_g_is_about_twice_alpha() {
    let block = Block::new(0.25, 2.14, None, None, None).expect("valid");
    let pulse = Pulse::new(PulseShape::OneCosine, 6.0 * 0.25 * G, 5.0 * 2.14).expect("valid");
    let r = simulate(
        &Problem {
            block,
            pulse,
            formulation: Formulation::Nonlinear,
        },
        &Options::history(Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        }),
    )
    .expect("simulates");
    let init = r.friction.and_then(|f| f.initiation).expect("rocked");
    assert!((init / 0.25 - 2.0).abs() < 0.1, "{}", init / 0.25);
    assert_eq!(r.rocking_start, Some(0.0));
}

#[test]
fn outcome_helper_agrees_with_full_history() {
    let block = locomotive();
    let pulse = Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * G, 5.0 * 2.14).expect("valid");
    let problem = Problem {
        block,
        pulse,
        formulation: Formulation::Linear,
    };
    let full = simulate(&problem, &Options::history(Solver::Exact)).expect("simulates");
    assert_eq!(
        outcome(&problem, Solver::Exact),
        (full.overturned, full.impact_count)
    );
}

// ---------------------------------------------------------------------------
// Friction demand (eqs. 7, 20, 51; Fig. 9)
// ---------------------------------------------------------------------------

/// Eq. 51 as printed: the friction a block needs to enter rocking under a
/// one-cosine pulse of amplitude `a_p` (λ = 1).
fn eq51(alpha: f64, a_p: f64) -> f64 {
    let excess = a_p / (G * alpha.tan()) - 1.0;
    alpha.tan() * (a_p / (G * alpha.sin()) - 0.75 * alpha.cos() * excess)
        / (alpha.tan() / alpha.sin() + 0.75 * alpha.tan() * alpha.sin() * excess)
}

fn friction_history(shape: PulseShape, ratio: f64, level: f64) -> topple::dynamics::Response {
    let block = locomotive();
    let pulse = Pulse::new(shape, level * 0.25 * G, ratio * 2.14).expect("valid");
    let mut options = Options::history(Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-10,
        atol: 1e-12,
    });
    options.series_points = Some(2001);
    simulate(
        &Problem {
            block,
            pulse,
            formulation: Formulation::Nonlinear,
        },
        &options,
    )
    .expect("simulates")
}

#[test]
fn one_cosine_peak_demand_is_eq_51_when_rocking_starts_at_once() {
    // Fig. 9 (bottom): at a_p = 6 αg, ω_p/p = 4, pure rocking needs μ ≈ 2α,
    // reached when rocking starts (t = 0), where the demand is eq. 51 — not the
    // at-rest |ü_g|/g = a_p/g = 1.5 of a block that never rests.
    let r = friction_history(PulseShape::OneCosine, 4.0, 6.0);
    let f = r.friction.expect("reactions followed");
    let peak = f.peak.expect("no lift-off");
    let expected = eq51(0.25, 6.0 * 0.25 * G);
    assert!((expected - 0.5096).abs() < 5e-5, "eq. 51 = {expected}");
    assert!(
        (peak / expected - 1.0).abs() < 5e-3,
        "peak {peak} vs eq. 51 {expected}"
    );
    assert!(
        (peak / 0.25 - 2.0).abs() < 0.05,
        "peak / α = {}",
        peak / 0.25
    );
    assert!((f.initiation.expect("rocks") - expected).abs() < 1e-12);
    // The demand is stationary at t = 0 (ü_g and θ̇ both start flat): the
    // maximum search settles within nanoseconds of it.
    assert!(f.peak_time.expect("time") < 1e-6, "{:?}", f.peak_time);
    assert!(f.first_lift_off.is_none() && !r.overturned);
    // The series sample at t = 0 is the rocking block's f_x/f_z (eq. 7), not
    // the at-rest ratio ü_g/g.
    let s = r.series.expect("series");
    assert_eq!(s.t[0], 0.0);
    let first = s.reaction_ratio.expect("ratio")[0].expect("f_z > 0");
    assert!(
        (first.abs() - expected).abs() < 1e-12,
        "first sample {first}"
    );
}

#[test]
fn one_cosine_demand_follows_eq_51_at_every_amplitude_where_it_peaks_at_the_start() {
    // Below the overturning amplitudes of ω_p/p = 4 the largest demand is the
    // one when rocking starts: eq. 51, growing with the amplitude.
    let mut last = 0.0;
    for level in [2.0, 3.0, 6.0] {
        let r = friction_history(PulseShape::OneCosine, 4.0, level);
        let peak = r.friction.and_then(|f| f.peak).expect("bounded");
        let expected = eq51(0.25, level * 0.25 * G);
        assert!(
            (peak / expected - 1.0).abs() < 5e-3,
            "{level} αg: {peak} vs {expected}"
        );
        assert!(peak > last);
        last = peak;
    }
}

#[test]
fn lift_off_makes_the_demand_unbounded() {
    // One-cosine ω_p/p = 1 at 6 αg: f_z → 0⁺ at t = 0.4105116 s (SciPy DOP853 on
    // eqs. 12 and 20, bench/friction_scipy.py), where f_x/f_z grows without bound.
    let r = friction_history(PulseShape::OneCosine, 1.0, 6.0);
    let f = r.friction.expect("reactions followed");
    assert_eq!(f.peak, None, "unbounded demand reported as {:?}", f.peak);
    assert_eq!(f.peak_time, None);
    let tl = f.first_lift_off.expect("lifts off");
    assert!((tl - 0.410_511_6).abs() < 1e-6, "lift-off at {tl}");
    assert!(
        r.warnings
            .iter()
            .any(|w| matches!(w, topple::dynamics::response::Warning::LiftOff(t) if *t == tl))
    );
    // The series of f_x/f_z ends at lift-off.
    let s = r.series.expect("series");
    let ratio = s.reaction_ratio.expect("ratio");
    for (t, q) in s.t.iter().zip(&ratio) {
        assert_eq!(q.is_some(), *t < tl, "t = {t}: {q:?}");
    }
}

#[test]
fn the_fall_of_a_block_bound_to_overturn_is_not_counted_and_the_result_says_so() {
    // One-cosine ω_p/p = 2 at 6 αg: |θ| passes α during the pulse and the block
    // overturns without impact after the pulse. The demand is followed up to the
    // pulse end, T = 2π/ω_p.
    let r = friction_history(PulseShape::OneCosine, 2.0, 6.0);
    assert!(r.overturned);
    let f = r.friction.expect("reactions followed");
    let end = 2.0 * std::f64::consts::PI / (2.0 * 2.14);
    let until = f.followed_until.expect("followed up to the pulse end");
    assert!((until - end).abs() < 1e-12, "{until} vs {end}");
    assert!(r.warnings.iter().any(
        |w| matches!(w, topple::dynamics::response::Warning::DemandExcludesFall(t) if *t == until)
    ));
    let peak = f.peak.expect("bounded");
    let t = f.peak_time.expect("peak time");
    assert!(
        t <= until && peak > eq51(0.25, 6.0 * 0.25 * G),
        "{peak} at {t}"
    );
    // SciPy DOP853 on eqs. 12 and 20 (bench/friction_scipy.py): 1.2612240 at T.
    assert!((peak - 1.261_224_0).abs() < 1e-6, "{peak}");
}
