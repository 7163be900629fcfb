//! The tracker's peaks against brute force. Peak |θ| and peak friction demand
//! |f_x/f_z| of a history (records: a piece per sample interval, sampled at
//! its ends and refined only where a maximum can be inside; pulses: sampled
//! for the forcing, golden-section refined; free rocking: as records) must be
//! the maxima of the same history's series, sampled every millisecond and at
//! every sample of the record and at every impact, then zoomed in five times
//! (±1 ms down to ±10 ps, 201 points each) around every sampled maximum near
//! the largest: the reference is then within rounding of the true maximum.
//! The tolerance is `REL_TOL` relative: far below any physical meaning, far
//! above rounding.
//! First sliding and lift-off are checked the same way against the series
//! (the demand and f_z recomputed from the series' states).

use crate::ground_motion::sampled;
use crate::synthetic::synthetic;
use topple::dynamics::reactions::reactions_per_mass;
use topple::dynamics::{
    Block, Forcing, Formulation, Method, Options, Problem, Pulse, PulseShape, Record, Response,
    Solver, simulate,
};

const G: f64 = 9.81;

/// Tracked peaks must match the dense reference to this, relative.
const REL_TOL: f64 = 1e-12;

/// Spacing of the first, uniform reference grid, s.
const GRID: f64 = 1e-3;

fn dop853() -> Solver {
    Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-12,
        atol: 1e-14,
    }
}

fn options(solver: Solver, series_at: Option<Vec<f64>>) -> Options {
    let mut o = Options::history(solver);
    o.max_free_impacts = 20;
    o.series_at = series_at;
    o
}

/// The history of `problem`, with the series at `times` (sorted) if given.
fn run<G: Forcing>(problem: &Problem<G>, solver: Solver, times: Option<Vec<f64>>) -> Response {
    simulate(problem, &options(solver, times)).expect("simulates")
}

/// Sorted, deduplicated times.
fn sorted(mut times: Vec<f64>) -> Vec<f64> {
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// (t, |θ|, demand) at a series sample; the demand (|f_x/f_z| as the series
/// gives it, at rest |ü_g|/g) is None where it is not followed.
type Sample = (f64, f64, Option<f64>);

/// The samples of the history of `problem` at `times`.
fn samples<G: Forcing>(problem: &Problem<G>, solver: Solver, times: Vec<f64>) -> Vec<Sample> {
    let r = run(problem, solver, Some(times));
    let until = r
        .friction
        .and_then(|f| f.followed_until)
        .unwrap_or(f64::INFINITY);
    let s = r.series.expect("series");
    let ratio = s.reaction_ratio.expect("reactions followed");
    s.t.iter()
        .zip(&s.theta)
        .zip(&ratio)
        .map(|((&t, th), q)| (t, th.abs(), q.filter(|_| t <= until).map(f64::abs)))
        .collect()
}

/// The largest value of the quantity `pick` selects, by brute force: on the
/// uniform grid (plus `extra` times), then zoomed in five times around each
/// sampled local maximum within 1e-4 (relative) of the largest.
fn reference<G: Forcing>(
    problem: &Problem<G>,
    solver: Solver,
    end: f64,
    extra: &[f64],
    pick: fn(&Sample) -> Option<f64>,
) -> (f64, f64) {
    let n = (end / GRID).ceil() as usize;
    let mut grid: Vec<f64> = (0..=n).map(|k| (k as f64 * GRID).min(end)).collect();
    grid.extend(extra.iter().filter(|&&t| t <= end));
    let coarse = samples(problem, solver, sorted(grid));
    let values: Vec<(f64, f64)> = coarse
        .iter()
        .filter_map(|s| pick(s).map(|v| (s.0, v)))
        .collect();
    let top = values.iter().fold(0.0f64, |m, &(_, v)| m.max(v));
    let mut candidates: Vec<(f64, f64)> = (0..values.len())
        .filter(|&i| {
            let v = values[i].1;
            v >= top * (1.0 - 1e-4)
                && (i == 0 || values[i - 1].1 <= v)
                && (i + 1 == values.len() || values[i + 1].1 <= v)
        })
        .map(|i| values[i])
        .collect();
    candidates.sort_by(|a, b| b.1.total_cmp(&a.1));
    candidates.truncate(8);
    let mut best = (f64::NAN, f64::NEG_INFINITY);
    for (mut tc, mut vc) in candidates {
        for half in [GRID, 1e-5, 1e-7, 1e-9, 1e-11] {
            let zoom: Vec<f64> = (0..=200)
                .map(|k| (tc + half * (k as f64 / 100.0 - 1.0)).clamp(0.0, end))
                .chain([tc])
                .collect();
            for s in samples(problem, solver, sorted(zoom)) {
                if let Some(v) = pick(&s)
                    && v > vc
                {
                    (tc, vc) = (s.0, v);
                }
            }
        }
        if vc > best.1 {
            best = (tc, vc);
        }
    }
    best
}

/// Checks the tracked peak |θ| and peak demand of `problem` against the
/// brute-force reference; returns the peak demand.
fn check_peaks<G: Forcing>(problem: &Problem<G>, solver: Solver, what: &str, extra: &[f64]) -> f64 {
    let r = run(problem, solver, None);
    assert!(
        r.rocked && !r.overturned,
        "{what}: pick a case that rocks and stands"
    );
    let end = r.end_time;
    let alpha = problem.block.slenderness();
    let peak_theta = r.peak_theta_over_alpha * alpha;
    // The demand jumps at impacts (θ̇ ← η θ̇) and where rocking starts: the
    // reference samples those instants too.
    let mut extra = extra.to_vec();
    extra.extend(r.impacts.iter().map(|i| i.time));
    extra.extend(r.rocking_start);
    let extra = &extra;
    let (_, ref_theta) = reference(problem, solver, end, extra, |s| Some(s.1));
    let f = r.friction.expect("reactions followed");
    let peak_demand = f.peak.expect("no lift-off");
    let peak_time = f.peak_time.expect("peak time");
    let (ref_time, ref_demand) = reference(problem, solver, end, extra, |s| s.2);
    let (e_theta, e_demand) = (
        (peak_theta - ref_theta).abs() / ref_theta,
        (peak_demand - ref_demand).abs() / ref_demand,
    );
    eprintln!(
        "{what}: {} impacts; peak |θ| {peak_theta:.15e} (reference {ref_theta:.15e}, {e_theta:.1e}), \
         peak demand {peak_demand:.15e} at {peak_time} s (reference {ref_demand:.15e} at {ref_time} s, {e_demand:.1e})",
        r.impact_count
    );
    assert!(e_theta <= REL_TOL, "{what}: peak |θ| off by {e_theta:e}");
    assert!(
        e_demand <= REL_TOL,
        "{what}: peak demand off by {e_demand:e}"
    );
    assert!(
        (peak_time - ref_time).abs() <= 1e-6,
        "{what}: peak demand at {peak_time} s, reference {ref_time} s"
    );
    peak_demand
}

/// The record's sample times (kinks of the demand, where it often peaks).
fn sample_times(record: &Record) -> Vec<f64> {
    (0..record.samples().len())
        .map(|k| k as f64 * record.dt())
        .collect()
}

/// The benchmark's block (α = 0.15, p = 1.5 rad/s, η = 0.9) under 20 s of
/// the benchmark's kind of record at 3 αg.
fn record_problem(formulation: Formulation, friction: Option<f64>) -> Problem<Record> {
    let block = Block::new(0.15, 1.5, Some(0.9), friction, None).expect("valid block");
    let acc = synthetic(7, 2000, 0.01, 3.0 * 0.15 * G, 1.0, 8.0);
    Problem {
        block,
        pulse: Record::new(acc.into(), 0.01).expect("valid record"),
        formulation,
    }
}

#[test]
fn record_peaks_match_brute_force_for_the_exact_solver_and_dop853() {
    // The random-like record's demand peaks on a sample, a kink (the jump of
    // the ground's slope outweighs the block's terms); a slow one-sine
    // (ω_p/p = 1/2, 1.05 αg) sampled at T/2000 has so little curvature that
    // its demand peaks inside a sample interval.
    let locomotive = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid block");
    let slow = Pulse::new(PulseShape::OneSine, 1.05 * 0.25 * G, 0.5 * 2.14).expect("valid");
    for (formulation, solver) in [
        (Formulation::Linear, Solver::Exact),
        (Formulation::Linear, dop853()),
        (Formulation::Nonlinear, dop853()),
    ] {
        let problem = record_problem(formulation, None);
        let what = format!("record, {formulation:?}, {}", solver.name());
        check_peaks(&problem, solver, &what, &sample_times(&problem.pulse));
        let problem = Problem {
            block: locomotive,
            pulse: sampled(&slow, 2000),
            formulation,
        };
        let what = format!("slow sampled one-sine, {formulation:?}, {}", solver.name());
        check_peaks(&problem, solver, &what, &sample_times(&problem.pulse));
    }
}

#[test]
fn pulse_peaks_match_brute_force() {
    // The locomotive block under a one-sine pulse (ω_p/p = 5, 2 αg): it rocks
    // through the pulse and then freely until the impacts run out; and a
    // one-cosine (ω_p/p = 4, 3 αg) whose demand peaks as rocking starts.
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid block");
    for (shape, ratio, level) in [
        (PulseShape::OneSine, 5.0, 2.0),
        (PulseShape::OneCosine, 4.0, 3.0),
    ] {
        let pulse = Pulse::new(shape, level * 0.25 * G, ratio * 2.14).expect("valid pulse");
        for (formulation, solver) in [
            (Formulation::Linear, Solver::Exact),
            (Formulation::Nonlinear, dop853()),
        ] {
            let problem = Problem {
                block,
                pulse,
                formulation,
            };
            let what = format!(
                "{shape:?} {ratio} {level} αg, {formulation:?}, {}",
                solver.name()
            );
            check_peaks(&problem, solver, &what, &[0.0, pulse.duration]);
        }
    }
}

#[test]
fn first_sliding_on_a_record_is_the_first_crossing_of_mu() {
    for solver in [Solver::Exact, dop853()] {
        let free = record_problem(Formulation::Linear, None);
        let peak = run(&free, solver, None)
            .friction
            .and_then(|f| f.peak)
            .expect("bounded");
        // At rest the demand stays below α: a μ above it is crossed rocking.
        let alpha = free.block.slenderness();
        assert!(peak > 1.05 * alpha, "{peak}");
        let mu = alpha + 0.5 * (peak - alpha);
        let problem = record_problem(Formulation::Linear, Some(mu));
        let r = run(&problem, solver, None);
        let ts = r.friction.and_then(|f| f.first_sliding).expect("slides");
        // No grid sample before it exceeds μ ...
        let n = (ts / GRID).floor() as usize;
        let grid: Vec<f64> = (0..=n)
            .map(|k| k as f64 * GRID)
            .filter(|&t| t < ts)
            .collect();
        for (t, _, d) in samples(&problem, solver, grid) {
            assert!(
                d.is_some_and(|d| d <= mu),
                "{}: {d:?} > μ = {mu} at {t} < {ts}",
                solver.name()
            );
        }
        // ... and it is where the demand crosses μ, to a nanosecond.
        let near: Vec<f64> = (0..=200).map(|k| ts + 1e-9 * (k as f64 - 100.0)).collect();
        for (t, _, d) in samples(&problem, solver, near) {
            let d = d.expect("followed");
            if t < ts - 2e-9 {
                assert!(d <= mu, "{}: {d} > μ = {mu} at {t} < {ts}", solver.name());
            } else if t > ts + 2e-9 && t < ts + 1e-7 {
                assert!(d > mu, "{}: {d} ≤ μ = {mu} at {t} > {ts}", solver.name());
            }
        }
    }
}

#[test]
fn lift_off_under_a_sampled_one_cosine_is_where_f_z_first_vanishes() {
    // The one-cosine of `paper.rs` (ω_p/p = 1 at 6 αg, locomotive block,
    // nonlinear), sampled at dt = T/4000: the pulse lifts the block off at
    // 0.4105116 s (SciPy); the record, tracked piece by piece, at the same
    // time to O(dt²), and exactly where f_z of its own history vanishes.
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid block");
    let pulse = Pulse::new(PulseShape::OneCosine, 6.0 * 0.25 * G, 2.14).expect("valid pulse");
    let n = 4000;
    let dt = pulse.duration / n as f64;
    let acc: Vec<f64> = (0..=n)
        .map(|k| pulse.amplitude * (pulse.circular_frequency * k as f64 * dt).cos())
        .collect();
    let problem = Problem {
        block,
        pulse: Record::new(acc.into(), dt).expect("valid record"),
        formulation: Formulation::Nonlinear,
    };
    let solver = Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-10,
        atol: 1e-12,
    };
    let r = run(&problem, solver, None);
    let f = r.friction.expect("reactions followed");
    assert_eq!(f.peak, None);
    let tl = f.first_lift_off.expect("lifts off");
    assert!((tl - 0.410_511_6).abs() < 1e-5, "lift-off at {tl}");
    // f_z from the series' own states: positive on a dense grid before tl,
    // not after it.
    let fz = |times: Vec<f64>| -> Vec<(f64, f64)> {
        let mut o = options(solver, Some(times));
        o.reactions = false;
        let s = simulate(&problem, &o)
            .expect("simulates")
            .series
            .expect("series");
        (0..s.t.len())
            .map(|i| {
                let (th, w) = (s.theta[i], s.theta_dot[i]);
                let side = if th != 0.0 { th.signum() } else { -w.signum() };
                let (_, fz) = reactions_per_mass(
                    Formulation::Nonlinear,
                    &block,
                    side,
                    th,
                    w,
                    s.ground_acceleration[i],
                );
                (s.t[i], fz)
            })
            .collect()
    };
    let before: Vec<f64> = (1..=4000)
        .map(|k| tl * k as f64 / 4000.0)
        .filter(|&t| t < tl - 1e-9)
        .collect();
    for (t, fz) in fz(before) {
        assert!(fz > 0.0, "f_z = {fz} at {t} < {tl}");
    }
    for (t, fz) in fz((1..=100).map(|k| tl + 1e-9 * k as f64).collect()) {
        assert!(fz <= 0.0, "f_z = {fz} at {t} > {tl}");
    }
}
