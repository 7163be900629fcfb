//! Spectrum benchmarks: the 40-frequency nonlinear one-sine spectrum of the
//! locomotive block, and how soon a large spectrum stops once canceled.

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use topple::dynamics::{Block, Formulation, Method, PulseShape, Solver};
use topple::spectrum::{Control, SpectrumRequest, overturning_spectrum};

fn request(frequencies: usize, formulation: Formulation, solver: Solver) -> SpectrumRequest {
    SpectrumRequest {
        block: Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid"),
        shape: PulseShape::OneSine,
        formulation,
        solver,
        omega_ratios: (0..frequencies)
            .map(|k| 0.25 + 9.75 * k as f64 / (frequencies - 1) as f64)
            .collect(),
        a_max: 20.0,
        tolerance: 1e-4,
        scan_step: 0.02,
        principal_relative_width: 0.01,
        vertical_ratio: None,
        friction: None,
    }
}

fn dop853() -> Solver {
    Solver::RungeKutta {
        method: Method::Dop853,
        rtol: 1e-10,
        atol: 1e-12,
    }
}

fn spectra(c: &mut Criterion) {
    let mut g = c.benchmark_group("spectrum");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(10));
    let nonlinear = request(40, Formulation::Nonlinear, dop853());
    g.bench_function("nonlinear_one_sine_40_frequencies_rtol1e-10", |b| {
        b.iter(|| overturning_spectrum(&nonlinear, &Control::new()).expect("computes"))
    });
    let linear = request(40, Formulation::Linear, Solver::Exact);
    g.bench_function("linear_exact_one_sine_40_frequencies", |b| {
        b.iter(|| overturning_spectrum(&linear, &Control::new()).expect("computes"))
    });
    // Time from cancel() to the spectrum returning, 200 frequencies, canceled
    // after 50 ms of work.
    let big = request(200, Formulation::Nonlinear, dop853());
    g.bench_function("cancel_latency_200_frequencies", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let control = Control::new();
                total += std::thread::scope(|s| {
                    let worker = s.spawn(|| {
                        let _ = overturning_spectrum(&big, &control);
                        Instant::now()
                    });
                    std::thread::sleep(Duration::from_millis(50));
                    let asked = Instant::now();
                    control.cancel();
                    worker.join().expect("worker").duration_since(asked)
                });
            }
            total
        })
    });
    g.finish();
}

criterion_group!(benches, spectra);
criterion_main!(benches);
