//! Engine benchmarks: one simulation of the reference case (locomotive block,
//! one-sine pulse, ω_p/p = 5, a_p = 4 αg), each pulse family, and a long
//! random-like record.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use topple::dynamics::{
    Block, Forcing, Formulation, Method, Options, Problem, Pulse, PulsePair, PulseShape, Record,
    RecordPair, Solver, simulate,
};

#[path = "../tests/common/synthetic.rs"]
mod synthetic;
use synthetic::synthetic;

fn problem(formulation: Formulation) -> Problem {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    let pulse = Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * 9.81, 5.0 * 2.14).expect("valid");
    Problem {
        block,
        pulse,
        formulation,
    }
}

fn rk(method: Method, rtol: f64) -> Solver {
    Solver::RungeKutta {
        method,
        rtol,
        atol: rtol / 100.0,
    }
}

fn engine(c: &mut Criterion) {
    let nonlinear = problem(Formulation::Nonlinear);
    let linear = problem(Formulation::Linear);
    let mut g = c.benchmark_group("history");
    for (name, p, solver) in [
        (
            "nonlinear_dop853_rtol1e-8",
            nonlinear,
            rk(Method::Dop853, 1e-8),
        ),
        (
            "nonlinear_dopri5_rtol1e-8",
            nonlinear,
            rk(Method::Dopri5, 1e-8),
        ),
        (
            "nonlinear_dop853_rtol1e-10",
            nonlinear,
            rk(Method::Dop853, 1e-10),
        ),
        ("linear_exact", linear, Solver::Exact),
        ("linear_dop853_rtol1e-8", linear, rk(Method::Dop853, 1e-8)),
    ] {
        // Through the pulse, outcome decided exactly at its end.
        let outcome = Options::outcome(solver);
        g.bench_function(format!("{name}/outcome"), |b| {
            b.iter(|| simulate(black_box(&p), black_box(&outcome)))
        });
        // The full result of a time-history job: reactions, peaks, impacts,
        // free motion until overturning.
        let full = Options::history(solver);
        g.bench_function(format!("{name}/full"), |b| {
            b.iter(|| simulate(black_box(&p), black_box(&full)))
        });
    }
    g.finish();
}

/// Each pulse family at the same ω_p/p = 5 and a_p = 4 αg (locomotive block,
/// nonlinear dop853 at rtol 1e-10; the sinusoidal ones also linear exact):
/// the per-simulation cost of a spectrum's point ("outcome"). And the
/// one-off cost of building a Mavroeidis–Papageorgiou pulse (its extrema
/// located), which a spectrum pays once per frequency.
fn pulses(c: &mut Criterion) {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    let mp = |gamma, nu| PulseShape::mavroeidis_papageorgiou(gamma, nu).expect("valid");
    let mut g = c.benchmark_group("pulse");
    for (name, shape) in [
        ("mavroeidis_papageorgiou_2", mp(2.0, 0.0)),
        ("mavroeidis_papageorgiou_20", mp(20.0, 1.0)),
    ] {
        g.bench_function(format!("{name}/build"), |b| {
            b.iter(|| Pulse::new(black_box(shape), 4.0 * 0.25 * 9.81, 5.0 * 2.14))
        });
    }
    for (name, shape) in [
        ("one_sine", PulseShape::OneSine),
        ("half_sine", PulseShape::HalfSine),
        ("rectangular", PulseShape::Rectangular),
        ("ricker", PulseShape::Ricker { symmetric: true }),
        (
            "ricker_antisymmetric",
            PulseShape::Ricker { symmetric: false },
        ),
        ("mavroeidis_papageorgiou_2_0", mp(2.0, 0.0)),
        (
            "mavroeidis_papageorgiou_3_half_pi",
            mp(3.0, std::f64::consts::FRAC_PI_2),
        ),
    ] {
        let pulse = Pulse::new(shape, 4.0 * 0.25 * 9.81, 5.0 * 2.14).expect("valid");
        for (formulation, solver, tag) in [
            (
                Formulation::Nonlinear,
                rk(Method::Dop853, 1e-10),
                "nonlinear_dop853",
            ),
            (Formulation::Linear, Solver::Exact, "linear_exact"),
        ] {
            if solver == Solver::Exact && !shape.is_sinusoidal() {
                continue;
            }
            let p = Problem {
                block,
                pulse,
                formulation,
            };
            let outcome = Options::outcome(solver);
            g.bench_function(format!("{name}/{tag}"), |b| {
                b.iter(|| simulate(black_box(&p), black_box(&outcome)))
            });
        }
    }
    g.finish();
}

/// The linear formulation under a 20,000-sample record (200 s at dt = 0.01 s,
/// 1–8 Hz, peak 3 αg) that keeps a slender block (α = 0.15, p = 1.5 rad/s,
/// η = 0.9) rocking from its first seconds to its end, with some 540
/// impacts: the exact solution piece by piece against dop853 at rtol 1e-12,
/// whose steps also stop at every sample.
fn record(c: &mut Criterion) {
    let block = Block::new(0.15, 1.5, Some(0.9), None, None).expect("valid");
    let acc = synthetic(7, 20_000, 0.01, 3.0 * 0.15 * 9.81, 1.0, 8.0);
    let problem = Problem {
        block,
        pulse: Record::new(acc.into(), 0.01).expect("valid"),
        formulation: Formulation::Linear,
    };
    let mut g = c.benchmark_group("record");
    g.sample_size(20);
    for (name, solver) in [
        ("exact", Solver::Exact),
        (
            "dop853_rtol1e-12",
            Solver::RungeKutta {
                method: Method::Dop853,
                rtol: 1e-12,
                atol: 1e-14,
            },
        ),
    ] {
        let outcome = Options::outcome(solver);
        g.bench_function(format!("{name}/outcome"), |b| {
            b.iter(|| simulate(black_box(&problem), black_box(&outcome)))
        });
        let full = Options::history(solver);
        g.bench_function(format!("{name}/full"), |b| {
            b.iter(|| simulate(black_box(&problem), black_box(&full)))
        });
    }
    g.finish();
}

/// `block` under `motion`, nonlinear.
fn nonlinear<G: Forcing>(block: Block, motion: G) -> Problem<G> {
    Problem {
        block,
        pulse: motion,
        formulation: Formulation::Nonlinear,
    }
}

/// The same simulations with and without a vertical ground motion, side by
/// side: the locomotive under the reference one-sine pulse alone, with
/// ü_v = 0.5 ü_g, with a one-sine vertical pulse of its own (twice the
/// frequency, 0.5 a_p, 0.1 s late), and with ü_v = 0.5 ü_g given as a pulse of
/// its own (`own_same`: the ratio's steps through the general path); a slender block (α = 0.15, p = 1.5) under
/// a 20-s synthetic record alone, with ü_v = 0.5 ü_g, and with a vertical
/// record of its own (another seed, peak 0.6 g). Nonlinear, dop853 at rtol
/// 1e-8; `outcome` what spectra run, `full` what a time history runs (peak,
/// friction demand, impacts).
fn vertical(c: &mut Criterion) {
    let mut g = c.benchmark_group("vertical");
    g.sample_size(20);
    let solver = rk(Method::Dop853, 1e-8);
    let (outcome, full) = (Options::outcome(solver), Options::history(solver));
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
    let horizontal = Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * 9.81, 5.0 * 2.14).expect("valid");
    let own = Pulse::new(PulseShape::OneSine, 0.5 * 4.0 * 0.25 * 9.81, 10.0 * 2.14).expect("valid");
    let alone = nonlinear(block, horizontal);
    let ratio = nonlinear(
        block,
        PulsePair::proportional(horizontal, 0.5).expect("non-zero"),
    );
    let pair = nonlinear(block, PulsePair::new(horizontal, own, 0.1));
    // The ratio's motion given as a pulse of its own (of the horizontal's
    // shape, frequency and time: run as the ratio).
    let same = nonlinear(
        block,
        PulsePair::new(
            horizontal,
            horizontal.with_amplitude(0.5 * horizontal.amplitude),
            0.0,
        ),
    );
    for (tag, options) in [("outcome", &outcome), ("full", &full)] {
        g.bench_function(format!("pulse/none/{tag}"), |b| {
            b.iter(|| simulate(black_box(&alone), black_box(options)))
        });
        g.bench_function(format!("pulse/ratio/{tag}"), |b| {
            b.iter(|| simulate(black_box(&ratio), black_box(options)))
        });
        g.bench_function(format!("pulse/own/{tag}"), |b| {
            b.iter(|| simulate(black_box(&pair), black_box(options)))
        });
        g.bench_function(format!("pulse/own_same/{tag}"), |b| {
            b.iter(|| simulate(black_box(&same), black_box(options)))
        });
    }
    let slender = Block::new(0.15, 1.5, Some(0.9), None, None).expect("valid");
    let h = Record::new(
        synthetic(7, 2_000, 0.01, 3.0 * 0.15 * 9.81, 1.0, 8.0).into(),
        0.01,
    )
    .expect("valid");
    let v = Record::new(
        synthetic(11, 2_000, 0.01, 0.6 * 9.81, 1.0, 15.0).into(),
        0.01,
    )
    .expect("valid");
    let alone = nonlinear(slender, h.clone());
    let ratio = nonlinear(
        slender,
        RecordPair::proportional(h.clone(), 0.5).expect("non-zero"),
    );
    let pair = nonlinear(slender, RecordPair::new(h, v).expect("same dt"));
    for (tag, options) in [("outcome", &outcome), ("full", &full)] {
        g.bench_function(format!("record/none/{tag}"), |b| {
            b.iter(|| simulate(black_box(&alone), black_box(options)))
        });
        g.bench_function(format!("record/ratio/{tag}"), |b| {
            b.iter(|| simulate(black_box(&ratio), black_box(options)))
        });
        g.bench_function(format!("record/own/{tag}"), |b| {
            b.iter(|| simulate(black_box(&pair), black_box(options)))
        });
    }
    g.finish();
}

/// On a Coulomb floor beside pure rocking, the same case: a μ never reached
/// (pure rocking answers, its friction demand followed), a block sliding
/// flat, one slide-rocking.
fn contact(c: &mut Criterion) {
    use topple::dynamics::sliding::Friction;
    use topple::jobs::contact::run_coulomb;
    let mut g = c.benchmark_group("contact");
    g.sample_size(20);
    let options = Options::history(rk(Method::Dop853, 1e-8));
    let block = Block::new(0.25, 2.14, None, None, None).expect("valid");
    let tan = 0.25f64.tan();
    let rests = nonlinear(
        block,
        Pulse::new(PulseShape::OneSine, 3.0 * tan * 9.81, 6.0 * 2.14).expect("valid"),
    );
    let strong = nonlinear(
        block,
        Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * 9.81, 3.0 * 2.14).expect("valid"),
    );
    let mu = |m: f64| Friction::new(m, None).expect("valid");
    g.bench_function("rests/no_sliding", |b| {
        b.iter(|| simulate(black_box(&rests), black_box(&options)))
    });
    g.bench_function("rests/coulomb_mu_10", |b| {
        b.iter(|| run_coulomb(black_box(&rests), black_box(&options), mu(10.0)))
    });
    g.bench_function("strong/no_sliding", |b| {
        b.iter(|| simulate(black_box(&strong), black_box(&options)))
    });
    g.bench_function("strong/coulomb_mu_0.2_slides", |b| {
        b.iter(|| run_coulomb(black_box(&strong), black_box(&options), mu(0.2)))
    });
    g.bench_function("strong/coulomb_mu_0.3_slide_rocks", |b| {
        b.iter(|| run_coulomb(black_box(&strong), black_box(&options), mu(0.3)))
    });
    g.finish();
}

criterion_group!(benches, engine, pulses, record, vertical, contact);
criterion_main!(benches);
