//! Times a 40-frequency one-sine overturning spectrum of the paper's
//! locomotive (α = 0.25, p = 2.14 rad/s; ω_p/p = 1 to 10.75, up to 20 αg,
//! scan step 0.02 αg, tolerance 1e-4 αg, dop853 at rtol 1e-10) on a Coulomb
//! floor with μ = 0.3 beside the same spectrum under pure rocking, in one
//! run, on every core; prints the wall times, simulations and the lowest
//! overturning amplitude of some frequencies.
//!
//!     cargo run --release --example contact_spectrum [mu]

use topple::dynamics::sliding::Friction;
use topple::dynamics::{Block, Formulation, Method, PulseShape, Solver};
use topple::spectrum::{Control, Spectrum, SpectrumRequest, overturning_spectrum};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mu: f64 = match std::env::args().nth(1) {
        Some(s) => s.parse()?,
        None => 0.3,
    };
    let block = Block::new(0.25, 2.14, None, None, None)?;
    let coulomb = SpectrumRequest {
        block,
        shape: PulseShape::OneSine,
        formulation: Formulation::Nonlinear,
        solver: Solver::RungeKutta {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
        },
        omega_ratios: (0..40).map(|i| 1.0 + 0.25 * f64::from(i)).collect(),
        a_max: 20.0,
        tolerance: 1e-4,
        scan_step: 0.02,
        principal_relative_width: 0.01,
        vertical_ratio: None,
        friction: Some(Friction {
            static_coefficient: mu,
            kinetic_coefficient: mu,
        }),
    };
    let pure = SpectrumRequest {
        friction: None,
        ..coulomb.clone()
    };
    let control = Control::new();
    let a = overturning_spectrum(&pure, &control)?;
    let b = overturning_spectrum(&coulomb, &control)?;
    // The threads the scans ran on (RAYON_NUM_THREADS sets them).
    let cores = rayon::current_num_threads();
    println!("40 frequencies, {cores} threads");
    let row = |name: &str, s: &Spectrum| {
        println!(
            "{name:>14}: {:6.2} s wall, {:7} simulations, {:6.1} µs each (wall × threads / simulations), {:6.1} steps and {:5.1} events each",
            s.wall_time,
            s.stats.simulations,
            1e6 * s.wall_time * cores as f64 / s.stats.simulations as f64,
            s.stats.steps as f64 / s.stats.simulations as f64,
            s.stats.events as f64 / s.stats.simulations as f64
        );
    };
    row("pure rocking", &a);
    row(&format!("coulomb μ={mu}"), &b);
    println!("ratio of wall times: {:.1}×", b.wall_time / a.wall_time);
    println!(
        "ω_p/p | lowest overturning, αg: pure rocking | coulomb | principal safe intervals on coulomb"
    );
    for (x, y) in a.lines.iter().zip(&b.lines).step_by(4) {
        let f = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.3}"));
        let safe: Vec<String> = y
            .principal
            .safe_intervals
            .iter()
            .map(|(lo, hi)| format!("{lo:.2}–{hi:.2}"))
            .collect();
        println!(
            "{:5.2} | {} | {} | {}",
            x.omega_ratio,
            f(x.derived.min_overturn),
            f(y.derived.min_overturn),
            safe.join(", ")
        );
    }
    Ok(())
}
