//! Overturning and friction spectra against the paper (Figs. 6, 9, 10, 11), the
//! closed forms, and each other.

use std::time::{Duration, Instant};

use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, Solver, simulate,
};
use topple::spectrum::friction::{FrictionRequest, friction_spectrum};
use topple::spectrum::overturning::FrequencyLine;
use topple::spectrum::scan::Direction;
use topple::spectrum::{Control, SpectrumRequest, overturning_spectrum};

const G: f64 = 9.81;

fn locomotive() -> Block {
    Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid")
}

fn equipment() -> Block {
    Block::new(0.349, 2.0, Some(0.825), None, None).expect("valid")
}

fn dop853() -> Solver {
    Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-10,
        atol: 1e-12,
    }
}

fn solver_for(formulation: Formulation) -> Solver {
    match formulation {
        Formulation::Linear => Solver::Exact,
        Formulation::Nonlinear => dop853(),
    }
}

fn spectrum_with(
    block: Block,
    shape: PulseShape,
    formulation: Formulation,
    solver: Solver,
    ratios: &[f64],
) -> Vec<FrequencyLine> {
    let req = SpectrumRequest {
        block,
        shape,
        formulation,
        solver,
        omega_ratios: ratios.to_vec(),
        a_max: 20.0,
        tolerance: 1e-4,
        scan_step: 0.02,
        principal_relative_width: 0.01,
        vertical_ratio: None,
        friction: None,
    };
    overturning_spectrum(&req, &Control::new())
        .expect("computes")
        .lines
}

fn spectrum(
    block: Block,
    shape: PulseShape,
    formulation: Formulation,
    ratios: &[f64],
) -> Vec<FrequencyLine> {
    spectrum_with(block, shape, formulation, solver_for(formulation), ratios)
}

fn minimum(line: &FrequencyLine) -> f64 {
    line.principal.min_overturn.expect("overturns below a_max")
}

fn within(value: f64, expected: f64, rel: f64) -> bool {
    ((value - expected) / expected).abs() <= rel
}

#[test]
fn linear_one_sine_at_omega_ratio_5_flips_up_at_3_01_down_at_6_32_up_at_7_17() {
    let line = &spectrum(
        locomotive(),
        PulseShape::OneSine,
        Formulation::Linear,
        &[5.0],
    )[0];
    let t = &line.transitions;
    assert_eq!(t.len(), 3, "{t:?}");
    let expect = [
        (3.01, Direction::Up, 1),
        (6.32, Direction::Down, 1),
        (7.17, Direction::Up, 2),
    ];
    for (got, (a, dir, mode)) in t.iter().zip(expect) {
        assert!(within(got.at, a, 0.005), "{} vs {a}", got.at);
        assert_eq!(got.direction, dir);
        assert!(got.bracket.1 - got.bracket.0 <= 1e-4);
        if dir == Direction::Up {
            assert_eq!(got.mode, mode);
        }
    }
    assert_eq!(line.derived.min_overturn_mode, Some(1));
    assert_eq!(line.derived.safe_intervals.len(), 1);
    assert!(within(
        line.derived.overturns_above.expect("all overturn"),
        7.17,
        0.005
    ));
    // The corrected eq. 47 gives the mode-2 edge to within the tolerance.
    let closed = line.mode2_closed_form.expect("closed form");
    assert!((closed - t[2].at).abs() <= 1e-4, "{closed} vs {}", t[2].at);
}

fn has_mode_one_band(ratio: f64) -> bool {
    let line = &spectrum(
        locomotive(),
        PulseShape::OneSine,
        Formulation::Linear,
        &[ratio],
    )[0];
    line.transitions
        .iter()
        .any(|t| t.direction == Direction::Up && t.mode == 1)
}

/// Bisects the boundary of a predicate that holds below it and fails above.
fn boundary(mut lo: f64, mut hi: f64, holds: impl Fn(f64) -> bool) -> f64 {
    assert!(holds(lo) && !holds(hi));
    while hi - lo > 1e-3 {
        let mid = 0.5 * (lo + hi);
        if holds(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn linear_mode_one_band_ends_near_omega_ratio_6_59() {
    let edge = boundary(6.0, 7.2, has_mode_one_band);
    println!("mode-1 band ends at ω_p/p = {edge:.4}");
    assert!(
        within(edge, 6.59, 0.01),
        "mode-1 band ends at ω_p/p = {edge}"
    );
}

#[test]
fn linear_mode_one_impact_precedes_the_pulse_end_up_to_omega_ratio_4_8() {
    // At the minimum overturning amplitude (mode 1), does the impact come
    // before the pulse ends (the paper's case 1)?
    let impact_first = |ratio: f64| {
        let block = locomotive();
        let line = &spectrum(block, PulseShape::OneSine, Formulation::Linear, &[ratio])[0];
        let up = line
            .transitions
            .iter()
            .find(|t| t.direction == Direction::Up)
            .expect("overturns");
        assert_eq!(up.mode, 1);
        let pulse =
            Pulse::new(PulseShape::OneSine, up.bracket.1 * 0.25 * G, ratio * 2.14).expect("valid");
        let r = simulate(
            &Problem {
                block,
                pulse,
                formulation: Formulation::Linear,
            },
            &Options::history(Solver::Exact),
        )
        .expect("simulates");
        r.impacts.first().expect("mode 1 impact").time < pulse.duration
    };
    let edge = boundary(4.0, 5.6, impact_first);
    println!("impact before the pulse end up to ω_p/p = {edge:.4}");
    assert!(
        within(edge, 4.8, 0.01),
        "impact before the pulse end up to ω_p/p = {edge}"
    );
}

#[test]
fn locomotive_at_15_7_rad_s_linear_needs_3_24_g_mode_2_nonlinear_2_22_g_mode_1() {
    let ratio = 15.7 / 2.14;
    let lin = &spectrum(
        locomotive(),
        PulseShape::OneSine,
        Formulation::Linear,
        &[ratio],
    )[0];
    let nl = &spectrum(
        locomotive(),
        PulseShape::OneSine,
        Formulation::Nonlinear,
        &[ratio],
    )[0];
    println!(
        "linear {:.4} g, nonlinear {:.4} g",
        minimum(lin) * 0.25,
        minimum(nl) * 0.25
    );
    assert!(
        within(minimum(lin) * 0.25, 3.24, 0.01),
        "linear {} g",
        minimum(lin) * 0.25
    );
    assert_eq!(lin.principal.min_overturn_mode, Some(2));
    assert!(
        within(minimum(nl) * 0.25, 2.22, 0.01),
        "nonlinear {} g",
        minimum(nl) * 0.25
    );
    assert_eq!(nl.principal.min_overturn_mode, Some(1));
}

fn relative_difference(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.min(b)
}

/// Relative difference between the linear and nonlinear minima at each of `ratios`.
fn formulation_gaps(block: Block, ratios: &[f64]) -> Vec<(f64, f64)> {
    let lin = spectrum(block, PulseShape::OneSine, Formulation::Linear, ratios);
    let nl = spectrum(block, PulseShape::OneSine, Formulation::Nonlinear, ratios);
    lin.iter()
        .zip(&nl)
        .map(|(l, n)| (l.omega_ratio, relative_difference(minimum(l), minimum(n))))
        .collect()
}

/// The formulations agree within `agree` up to `low_end`, and somewhere in
/// `[lo, hi]` differ by more than 15 % (paper Fig. 10).
fn assert_agree_then_part(block: Block, low_end: f64, agree: f64, (lo, hi): (f64, f64)) {
    let low: Vec<f64> = (1..)
        .map(|k| 0.25 * k as f64)
        .take_while(|r| *r <= low_end)
        .collect();
    for (ratio, d) in formulation_gaps(block, &low) {
        assert!(d <= agree, "ω_p/p = {ratio}: formulations differ by {d}");
    }
    let steps = ((hi - lo) / 0.1).round() as usize;
    let bay: Vec<f64> = (0..=steps).map(|k| lo + 0.1 * k as f64).collect();
    let largest = formulation_gaps(block, &bay)
        .into_iter()
        .map(|g| g.1)
        .fold(0.0, f64::max);
    assert!(largest > 0.15, "largest difference in {lo}–{hi}: {largest}");
}

#[test]
fn locomotive_formulations_agree_to_6_and_part_in_the_bay() {
    assert_agree_then_part(locomotive(), 6.0, 0.05, (6.5, 7.5));
}

#[test]
fn equipment_formulations_part_in_4_7_to_5_8_and_agree_to_4_5() {
    assert_agree_then_part(equipment(), 4.5, 0.06, (4.7, 5.8));
}

#[test]
fn eq_21_approximates_the_minimum_for_slow_pulses() {
    let ratios: Vec<f64> = (1..=12).map(|k| 0.25 * k as f64).collect();
    for formulation in [Formulation::Linear, Formulation::Nonlinear] {
        for (shape, rel) in [(PulseShape::OneSine, 0.10), (PulseShape::OneCosine, 0.25)] {
            for line in spectrum(locomotive(), shape, formulation, &ratios) {
                let m = minimum(&line);
                let eq21 = line.eq21.expect("eq. 21 holds for cycloidal pulses");
                assert!(
                    within(m, eq21, rel),
                    "{shape:?} {formulation:?} ω_p/p = {}: {m} vs eq. 21 {eq21}",
                    line.omega_ratio,
                );
            }
        }
    }
}

#[test]
fn exact_and_numerical_linear_spectra_agree_to_the_tolerance() {
    let ratios = [0.5, 1.5, 3.0, 5.0, 6.5, 8.0];
    for shape in [
        PulseShape::OneSine,
        PulseShape::OneCosine,
        PulseShape::Cn(1),
    ] {
        let exact = spectrum_with(
            locomotive(),
            shape,
            Formulation::Linear,
            Solver::Exact,
            &ratios,
        );
        let rk = spectrum_with(locomotive(), shape, Formulation::Linear, dop853(), &ratios);
        for (e, n) in exact.iter().zip(&rk) {
            assert_eq!(
                e.transitions.len(),
                n.transitions.len(),
                "{shape:?} ω_p/p = {}",
                e.omega_ratio
            );
            for (a, b) in e.transitions.iter().zip(&n.transitions) {
                assert_eq!((a.direction, a.mode), (b.direction, b.mode));
                assert!(
                    (a.at - b.at).abs() <= 1e-4,
                    "{shape:?}: {} vs {}",
                    a.at,
                    b.at
                );
            }
        }
    }
}

#[test]
fn nonlinear_comb_near_the_threshold_at_omega_ratio_0_25_has_bands_whose_impacts_step_by_two() {
    let req = SpectrumRequest {
        block: locomotive(),
        shape: PulseShape::OneSine,
        formulation: Formulation::Nonlinear,
        solver: dop853(),
        omega_ratios: vec![0.25],
        a_max: 1.2,
        tolerance: 1e-5,
        scan_step: 0.02,
        principal_relative_width: 0.01,
        vertical_ratio: None,
        friction: None,
    };
    let line = &overturning_spectrum(&req, &Control::new())
        .expect("computes")
        .lines[0];
    let bands: Vec<_> = line
        .transitions
        .windows(2)
        .filter(|w| w[0].direction == Direction::Up && w[1].direction == Direction::Down)
        .map(|w| (w[0].at, w[1].at - w[0].at, w[0].impacts))
        .collect();
    assert!(bands.len() >= 5, "{bands:?}");
    assert!(bands[0].0 > 1.045 && bands[0].0 < 1.047, "{bands:?}");
    for b in &bands {
        assert!(b.1 < 1e-3, "band at {} is {} wide", b.0, b.1);
    }
    for w in bands.windows(2) {
        assert_eq!(w[0].2, w[1].2 + 2, "impacts step by two: {bands:?}");
    }
    // The principal view starts where overturning becomes a wide region.
    let principal = line.principal.min_overturn.expect("overturns");
    assert!(principal > bands[bands.len() - 1].0);
}

#[test]
fn friction_demand_grows_with_the_amplitude_and_starts_at_tan_alpha() {
    let block = locomotive();
    let req = FrictionRequest {
        block,
        shape: PulseShape::OneSine,
        formulation: Formulation::Nonlinear,
        solver: dop853(),
        omega_ratio: 15.7 / 2.14,
        levels: vec![2.0, 4.0, 6.0, 8.9],
        vertical: None,
    };
    let s = friction_spectrum(&req, &Control::new()).expect("computes");
    let tan = 0.25f64.tan();
    for p in &s.points {
        assert!((p.initiation_demand.expect("rocks") - tan).abs() < 1e-12);
    }
    let peaks: Vec<f64> = s
        .points
        .iter()
        .map(|p| p.peak_demand.expect("no lift-off"))
        .collect();
    for w in peaks.windows(2) {
        assert!(w[1] > w[0], "{:?}", s.points);
    }
    let last = peaks[peaks.len() - 1];
    assert!((last / tan - 2.5).abs() <= 0.25, "{}", last / tan);
}

#[test]
fn a_large_spectrum_stops_soon_after_cancellation() {
    let req = SpectrumRequest {
        block: locomotive(),
        shape: PulseShape::OneSine,
        formulation: Formulation::Nonlinear,
        solver: dop853(),
        omega_ratios: (0..200).map(|k| 0.25 + 9.75 * k as f64 / 199.0).collect(),
        a_max: 20.0,
        tolerance: 1e-4,
        scan_step: 0.02,
        principal_relative_width: 0.01,
        vertical_ratio: None,
        friction: None,
    };
    let control = Control::new();
    let (stopped_at, outcome) = std::thread::scope(|s| {
        // A pool of its own: the other tests' work on the global pool would
        // hold the join, which is not the cancellation being measured.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("a pool");
        let (req, control) = (&req, &control);
        let worker = s.spawn(move || {
            let r = pool.install(|| overturning_spectrum(req, control));
            (Instant::now(), r)
        });
        std::thread::sleep(Duration::from_millis(50));
        let asked = Instant::now();
        assert!(control.progress() < 1.0);
        control.cancel();
        let (stopped, r) = worker.join().expect("worker");
        (stopped.duration_since(asked), r)
    });
    assert!(outcome.is_err(), "canceled");
    // 100 ms is the promise; the margin absorbs a loaded test machine.
    assert!(
        stopped_at < Duration::from_millis(500),
        "stopped after {stopped_at:?}"
    );
}
