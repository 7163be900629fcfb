//! The Coulomb floor over the whole space of valid histories: every one is
//! answered, finite, within a bounded work, consistent with itself, with
//! pure rocking where friction never binds, and with its mirror image.
//!
//! Drawn: α from 0.005 to 1.3 (log-uniform), p from 0.5 to 10 rad/s, η
//! including 0, 1 and Housner's; μ from 0.02 to 100, near tan α and near
//! (1 − η)/((1 + η) tan α) (where Housner's impact starts to slide), μ_k ≤ μ;
//! every pulse family, or a record window (a seeded, smoothed random
//! accelerogram); no vertical motion, one in proportion, or a pulse of its
//! own. `cargo test` runs [`CASES`] of them from a fixed seed;
//! `bench/contact_soak.sh` runs many more from fresh ones
//! (`TOPPLE_FUZZ_CASES`, `TOPPLE_FUZZ_SEED`).

use std::sync::Arc;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use topple::dynamics::coulomb::Cut;
use topple::dynamics::floor::{AnsweredBy, CoulombHistory, run_coulomb};
use topple::dynamics::response::{MAX_IMPACTS, MAX_STEPS, Warning};
use topple::dynamics::sliding::{Friction, Kinematics};
use topple::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulsePair, PulseShape, Record, RecordPair,
    Response, Solver, simulate,
};

/// Cases per `cargo test` run.
const CASES: u32 = 600;

/// A case (its history, the mirror one and pure rocking's) taking longer
/// than this is reported.
const SLOW_S: f64 = 0.5;

/// The ground motion of a case.
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)] // a test's case, built once
enum Ground {
    Pulse(Pulse),
    Pair(PulsePair),
    Record(Record),
    RecordPair(RecordPair),
}

#[derive(Clone, Debug)]
struct Case {
    block: Block,
    friction: Friction,
    ground: Ground,
    max_free_impacts: u64,
}

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (0.0..1.0f64).prop_map(move |u| (lo.ln() + u * (hi.ln() - lo.ln())).exp())
}

fn shape() -> impl Strategy<Value = PulseShape> {
    prop_oneof![
        Just(PulseShape::OneSine),
        Just(PulseShape::OneCosine),
        (2u32..5).prop_map(PulseShape::Cn),
        Just(PulseShape::HalfSine),
        Just(PulseShape::Rectangular),
        any::<bool>().prop_map(|symmetric| PulseShape::Ricker { symmetric }),
    ]
}

/// A smoothed random accelerogram of `seconds` at 100 samples/s, its peak
/// `peak` m/s², tapered at both ends.
fn accelerogram(seed: u64, seconds: f64, peak: f64) -> Record {
    let n = (seconds * 100.0) as usize;
    let mut x = seed | 1;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (mut a, mut v) = (0.0f64, 0.0f64);
    let mut samples: Vec<f64> = (0..n)
        .map(|k| {
            // A lightly damped oscillator (about 2 Hz) driven by noise.
            let (w, z, dt) = (12.0, 0.3, 0.01);
            v += (next() * 400.0 - 2.0 * z * w * v - w * w * a) * dt;
            a += v * dt;
            let taper = ((k as f64 / n as f64) * std::f64::consts::PI).sin();
            a * taper
        })
        .collect();
    let max = samples.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    if max > 0.0 {
        for s in &mut samples {
            *s *= peak / max;
        }
    }
    Record::new(Arc::from(samples), 0.01).expect("valid record")
}

fn case() -> impl Strategy<Value = Case> {
    let eta = prop_oneof![
        Just(None),
        Just(Some(0.0)),
        Just(Some(1.0)),
        (0.0..1.0f64).prop_map(Some),
    ];
    (
        log_uniform(0.005, 1.3),
        log_uniform(0.5, 10.0),
        eta,
        (0u8..4, log_uniform(0.02, 100.0), 0.9..1.1f64, 0.5..1.0f64),
        (
            shape(),
            log_uniform(0.1, 20.0),
            log_uniform(0.6, 10.0),
            any::<bool>(),
        ),
        (
            0u8..5,
            (0.05..1.0f64, any::<bool>()).prop_map(|(s, down)| if down { -s } else { s }),
            log_uniform(0.3, 10.0),
            any::<u64>(),
            2.0..40.0f64,
        ),
        prop_oneof![Just(1_000u64), 0u64..12],
    )
        .prop_map(
            |(alpha, p, eta, (mu_kind, mu_free, near, kinetic), pulse, vertical, max_free)| {
                let block = Block::new(alpha, p, eta, None, None).expect("valid block");
                let tan = alpha.tan();
                let e = block.restitution();
                let mu = match mu_kind {
                    0 => mu_free,
                    1 => tan * near,
                    2 => ((1.0 - e) / ((1.0 + e) * tan)).clamp(0.02, 100.0) * near,
                    _ => 10.0 + mu_free,
                };
                let friction = Friction::new(mu, Some(mu * kinetic)).expect("valid friction");
                let (shape, ratio, level, negative) = pulse;
                let g = block.gravity();
                let a = level * tan * g * if negative { -1.0 } else { 1.0 };
                let horizontal = Pulse::new(shape, a, ratio * p).expect("valid pulse");
                let (kind, share, v_ratio, seed, seconds) = vertical;
                let ground = match kind {
                    0 => Ground::Pulse(horizontal),
                    1 => Ground::Pair(PulsePair::new(
                        horizontal,
                        horizontal.with_amplitude(share * a),
                        0.0,
                    )),
                    2 => Ground::Pair(PulsePair::new(
                        horizontal,
                        Pulse::new(PulseShape::OneSine, share * 1.5 * g, v_ratio * p)
                            .expect("valid pulse"),
                        0.0,
                    )),
                    3 => Ground::Record(accelerogram(seed, seconds, a.abs())),
                    _ => {
                        let h = accelerogram(seed, seconds, a.abs());
                        let v = accelerogram(seed.rotate_left(17), seconds, share.abs() * g);
                        Ground::RecordPair(RecordPair::new(h, v).expect("valid pair"))
                    }
                };
                Case {
                    block,
                    friction,
                    ground,
                    max_free_impacts: max_free,
                }
            },
        )
}

fn solver() -> Solver {
    Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-10,
        atol: 1e-12,
    }
}

fn options(max_free_impacts: u64) -> Options {
    Options {
        max_free_impacts,
        ..Options::history(solver())
    }
}

fn coulomb<G: Kinematics + Clone>(
    c: &Case,
    ground: G,
) -> Result<(CoulombHistory, Response), TestCaseError> {
    let problem = Problem {
        block: c.block,
        pulse: ground,
        formulation: Formulation::Nonlinear,
    };
    let h = run_coulomb(&problem, &options(c.max_free_impacts), c.friction)
        .map_err(|e| TestCaseError::fail(format!("no answer: {e}")))?;
    let pure = simulate(&problem, &options(c.max_free_impacts))
        .map_err(|e| TestCaseError::fail(format!("pure rocking: no answer: {e}")))?;
    Ok((h, pure))
}

fn check(c: &Case, h: &CoulombHistory, pure: &Response) -> Result<(), TestCaseError> {
    let (r, k) = (&h.response, &h.contact);
    let finite = [
        r.end_time,
        r.peak_theta_over_alpha,
        k.peak_slide,
        k.residual_slide,
        k.time_sliding,
        k.time_in_flight,
        r.numerics.error_estimate,
    ];
    prop_assert!(finite.iter().all(|x| x.is_finite()), "{finite:?}");
    prop_assert!(
        k.impacts
            .iter()
            .all(|i| i.t.is_finite() && i.theta_dot.0.is_finite() && i.theta_dot.1.is_finite())
    );
    prop_assert!(
        k.residual_slide.abs() <= k.peak_slide * (1.0 + 1e-12) + 1e-15,
        "residual {} peak {}",
        k.residual_slide,
        k.peak_slide
    );
    if let Some(t) = r.overturn_time {
        prop_assert!(r.overturned);
        prop_assert!(
            t <= r.end_time,
            "overturned at {t}, ended at {}",
            r.end_time
        );
        prop_assert!(
            r.peak_theta_over_alpha >= 1.0,
            "{}",
            r.peak_theta_over_alpha
        );
    }
    if r.overturned && r.overturn_time.is_none() {
        // Decided in closed form where the history was cut short.
        prop_assert!(
            k.cut.is_some()
                || r.warnings
                    .iter()
                    .any(|w| matches!(w, Warning::FreeRockingTruncated(_)))
        );
    }
    prop_assert!(
        k.impacts.windows(2).all(|w| w[0].t <= w[1].t),
        "impacts out of order"
    );
    // Bounded work.
    prop_assert!(r.numerics.steps_accepted <= MAX_STEPS + 100_000);
    prop_assert!(k.impact_count - k.summed_impacts <= MAX_IMPACTS + 1_000);
    // Free motion followed as far as asked.
    if let Some(Cut::FreeImpacts(n)) = k.cut {
        prop_assert_eq!(n, c.max_free_impacts);
    }
    // Where friction never binds, the floor is pure rocking's.
    let mu = c.friction.static_coefficient;
    let bound = pure.friction.is_some_and(|f| {
        f.peak.is_some_and(|p| p < mu)
            && f.initiation.is_none_or(|i| i < mu)
            && f.first_lift_off.is_none()
            && f.followed_until.is_none()
    }) && pure.lift_off.is_none()
        && pure.rocking_starts <= 1;
    if mu >= 10.0 && bound {
        prop_assert_eq!(h.answered_by, AnsweredBy::PureRocking);
        prop_assert_eq!(r.overturned, pure.overturned);
        prop_assert_eq!(r.impact_count, pure.impact_count);
        prop_assert_eq!(&r.warnings, &pure.warnings);
    }
    Ok(())
}

/// The mirror image of a history: the same outcome, impacts and slides,
/// to the other side.
fn mirrored(a: &CoulombHistory, b: &CoulombHistory) -> Result<(), TestCaseError> {
    let (x, y) = (&a.contact, &b.contact);
    prop_assert_eq!(x.overturned, y.overturned);
    prop_assert_eq!(x.overturn_side, y.overturn_side.map(|s| -s));
    prop_assert_eq!(x.impact_count, y.impact_count);
    prop_assert_eq!(x.cut.is_some(), y.cut.is_some());
    let scale = x.peak_slide.max(1e-9);
    prop_assert!(
        (x.residual_slide + y.residual_slide).abs() <= 1e-6 * scale,
        "{} vs {}",
        x.residual_slide,
        y.residual_slide
    );
    prop_assert!((x.end_time - y.end_time).abs() <= 1e-9 * x.end_time.max(1.0));
    Ok(())
}

fn run_case(c: &Case) -> Result<(), TestCaseError> {
    match &c.ground {
        Ground::Pulse(p) => {
            let (h, pure) = coulomb(c, *p)?;
            check(c, &h, &pure)?;
            let (m, _) = coulomb(c, p.with_amplitude(-p.amplitude))?;
            mirrored(&h, &m)
        }
        Ground::Pair(pair) => {
            let (h, pure) = coulomb(c, *pair)?;
            check(c, &h, &pure)?;
            let flipped = PulsePair::new(
                pair.horizontal.with_amplitude(-pair.horizontal.amplitude),
                pair.vertical,
                pair.delay,
            );
            let (m, _) = coulomb(c, flipped)?;
            mirrored(&h, &m)
        }
        Ground::Record(rec) => {
            let (h, pure) = coulomb(c, rec.clone())?;
            check(c, &h, &pure)?;
            let (m, _) = coulomb(c, rec.scaled(-1.0))?;
            mirrored(&h, &m)
        }
        Ground::RecordPair(pair) => {
            let (h, pure) = coulomb(c, pair.clone())?;
            check(c, &h, &pure)
        }
    }
}

/// The cases and seed: [`CASES`] from a fixed seed, or as the environment
/// says (`TOPPLE_FUZZ_CASES`, `TOPPLE_FUZZ_SEED`).
fn config() -> Config {
    let env = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<u64>().ok());
    Config {
        cases: env("TOPPLE_FUZZ_CASES").map_or(CASES, |n| n as u32),
        rng_seed: RngSeed::Fixed(env("TOPPLE_FUZZ_SEED").unwrap_or(0x70_9913)),
        failure_persistence: None,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// Every valid Coulomb history answers, within bounded work, with
    /// finite, self-consistent numbers, pure rocking's answer where
    /// friction never binds, and its mirror image's under −ü_g.
    #[test]
    fn every_coulomb_history_is_answered_and_consistent(c in case()) {
        let started = std::time::Instant::now();
        run_case(&c)?;
        // Reported, not asserted (a loaded machine is slower): the soak
        // script gathers these.
        let took = started.elapsed();
        if took.as_secs_f64() > SLOW_S {
            eprintln!("slow case: {:.3} s: {c:?}", took.as_secs_f64());
        }
    }
}

/// The histories that once hung or failed on a Coulomb floor, each
/// answered as physics says.
mod once_failed {
    use super::*;
    use topple::dynamics::coulomb::simulate_contact;

    fn one_sine(block: &Block, ratio: f64, a_g: f64) -> Pulse {
        Pulse::new(
            PulseShape::OneSine,
            a_g * block.gravity(),
            ratio * block.frequency_parameter(),
        )
        .expect("valid pulse")
    }

    fn contact(
        block: &Block,
        pulse: &Pulse,
        mu: f64,
    ) -> topple::dynamics::coulomb::ContactResponse {
        let f = Friction::new(mu, None).expect("valid friction");
        simulate_contact(block, pulse, f, Method::Dop853, 1e-10, 1e-12).expect("answers")
    }

    #[test]
    fn a_squat_block_on_mu_10_flies_and_overturns_as_on_mu_3() {
        // α = 0.68: the friction limit is passed where no slip is
        // consistent (Painlevé); the pivot holds to the lift-off.
        let b = Block::new(0.68, 5.0, None, None, None).expect("valid block");
        let pulse = one_sine(&b, 0.25, 5.0);
        let (high, three) = (contact(&b, &pulse, 10.0), contact(&b, &pulse, 3.0));
        assert!(high.overturned && three.overturned);
        let lift = high.first_flight.expect("flies");
        let (a, b) = (
            three.first_flight.expect("flies"),
            three.overturn_time.expect("over"),
        );
        assert!((lift - a).abs() < 1e-9, "{lift} vs {a}");
        let over = high.overturn_time.expect("overturns");
        assert!((over - b).abs() < 1e-9, "{over} vs {b}");
        assert!((lift - 0.4142).abs() < 1e-3, "{lift}");
    }

    #[test]
    fn eta_0_on_mu_5_holds_at_its_impacts_and_rests_as_pure_rocking() {
        let b = Block::new(0.1, 2.0, Some(0.0), None, None).expect("valid block");
        let pulse = one_sine(&b, 0.5, 0.101);
        let c = contact(&b, &pulse, 5.0);
        let problem = Problem {
            block: b,
            pulse,
            formulation: Formulation::Nonlinear,
        };
        let pure = simulate(&problem, &options(1_000)).expect("answers");
        assert_eq!(c.impact_count, pure.impact_count);
        assert_eq!(c.impact_count, 2);
        let (x, y) = (c.rest_time.expect("rests"), pure.rest_time.expect("rests"));
        assert!((x - y).abs() < 1e-9, "{x} vs {y}");
        assert!(c.impacts.iter().all(|i| i.sticking && i.theta_dot.1 == 0.0));
    }

    #[test]
    fn impacts_that_slide_chatter_to_rest_summed_in_closed_form() {
        // μ = 0.103 is below the (1 − η)/((1 + η) tan α) = 1.11 a holding
        // impact needs: every impact slides, and the chattering ends.
        let b = Block::new(0.1, 2.0, Some(0.8), None, None).expect("valid block");
        let c = contact(&b, &one_sine(&b, 8.0, 0.7), 0.103);
        assert!(!c.overturned && c.cut.is_none());
        assert!(c.impacts.iter().any(|i| !i.sticking));
        assert!(c.summed_impacts > 0, "{}", c.summed_impacts);
        let rest = c.rest_time.expect("rests");
        // The last impact followed one by one comes before the summed rest.
        let last = c.impacts.last().expect("impacts").t;
        assert!(last < rest && rest - last < 1.0, "{last} {rest}");
    }

    #[test]
    fn the_free_impacts_asked_for_are_followed_on_a_coulomb_floor_as_under_pure_rocking() {
        // η = 1 never rests: cut after 10 free impacts.
        let b = Block::new(0.035, 1.0, Some(1.0), None, None).expect("valid block");
        let problem = Problem {
            block: b,
            pulse: one_sine(&b, 9.0, 0.2),
            formulation: Formulation::Nonlinear,
        };
        let f = Friction::new(0.04, None).expect("valid friction");
        let h = run_coulomb(&problem, &options(10), f).expect("answers");
        assert_eq!(h.contact.cut, Some(Cut::FreeImpacts(10)));
        assert!(
            h.response
                .warnings
                .contains(&Warning::FreeRockingTruncated(10))
        );
        // μ = 10 never binds: the answer and its cut are pure rocking's.
        let b = Block::new(0.25, 2.14, None, None, None).expect("valid block");
        let problem = Problem {
            block: b,
            pulse: Pulse::new(PulseShape::OneSine, 1.3 * 0.25 * b.gravity(), 3.0 * 2.14)
                .expect("valid pulse"),
            formulation: Formulation::Nonlinear,
        };
        let f = Friction::new(10.0, None).expect("valid friction");
        let h = run_coulomb(&problem, &options(3), f).expect("answers");
        let pure = simulate(&problem, &options(3)).expect("answers");
        assert_eq!(h.response.impact_count, pure.impact_count);
        assert_eq!(h.response.impact_count, 4);
        assert_eq!(h.response.warnings, pure.warnings);
        assert!(pure.warnings.contains(&Warning::FreeRockingTruncated(3)));
    }

    #[test]
    fn no_free_rocking_asked_for_ends_at_the_pulse_with_its_verdict_and_says_so() {
        let b = Block::new(0.056, 4.2, None, None, None).expect("valid block");
        let problem = Problem {
            block: b,
            pulse: one_sine(&b, 7.0, 0.5),
            formulation: Formulation::Nonlinear,
        };
        let cut = simulate(&problem, &options(0)).expect("answers");
        let whole = simulate(&problem, &options(1_000)).expect("answers");
        assert!(whole.overturned && whole.overturn_time.is_some());
        assert_eq!(cut.overturned, whole.overturned);
        assert_eq!(cut.overturn_time, None);
        assert_eq!(cut.end_time, problem.pulse.duration);
        assert!(cut.warnings.contains(&Warning::FreeRockingTruncated(0)));
    }

    #[test]
    fn a_slide_rock_nearing_painleves_limit_jams_and_the_history_ends() {
        // α = 1.087 on μ = 2 (μ_k = 1.96) under a one-sine of 6.4 g: the
        // slide-rock's reduced inertia reaches 0 at 2.64 s (the step size
        // once underflowed there).
        let b = Block::new(1.0871269159971297, 0.5, Some(0.0), None, None).expect("valid block");
        let pulse = Pulse::new(PulseShape::OneSine, 62.73490248637098, 0.498084132335692)
            .expect("valid pulse");
        let f = Friction::new(1.998214455568104, Some(1.963076023338019)).expect("valid");
        let c = simulate_contact(&b, &pulse, f, Method::Dop853, 1e-10, 1e-12).expect("answers");
        let slide_rock_end = c
            .modes
            .iter()
            .find(|m| m.mode == topple::dynamics::contact::Mode::SlideRock)
            .map(|m| m.to)
            .expect("slide-rocks");
        assert!((slide_rock_end - 2.64).abs() < 0.01, "{slide_rock_end}");
        assert!(c.overturned);
    }
}
