//! What a job costs before it runs: the CPU seconds of its simulations on the
//! reference machine (one core of a 2-core x86-64 server), from what one
//! simulation costs — its pulse shape, formulation and method, or the part
//! of its record that keeps a block rocking — and, for a scan, how many
//! simulations its bisection takes. Estimates, poll intervals and task sizes
//! are taken from it; each instance then corrects its seconds per kind with
//! the rate it measures ([`crate::service::throughput`]).
//!
//! The constants were measured with `bench/estimates.py` and by timing
//! spectra of every pulse shape (7 frequencies, scan to 10 αg): the table
//! holds each within a factor of 1.5.

use crate::dynamics::{Formulation, PulseShape};

use super::names::SolverMethod;

/// CPU seconds a task of a split job aims at: a fraction of a second of the
/// reference machine (whose model seconds run about twice the measured
/// ones), so that a small job submitted behind it starts well within a
/// second. A task also costs a claim, heartbeats and a write (a few
/// milliseconds on PostgreSQL): a few per cent.
pub const TASK_CPU_S: f64 = 0.3;

/// CPU seconds of one simulation of a pulse of `shape` (a spectrum's
/// average: blocks that overturn early stop early), µs × 1e-6.
pub fn pulse_simulation_s(
    shape: &PulseShape,
    formulation: Formulation,
    method: SolverMethod,
) -> f64 {
    let linear = formulation == Formulation::Linear;
    let exact = method == SolverMethod::Exact;
    // Cycles of the pulse: its cost grows with them.
    let us = match *shape {
        PulseShape::OneSine if exact => 14.0,
        PulseShape::OneSine if linear => 24.0,
        PulseShape::OneSine => 60.0,
        PulseShape::OneCosine if exact => 40.0,
        PulseShape::OneCosine if linear => 25.0,
        PulseShape::OneCosine => 60.0,
        PulseShape::Cn(n) if linear => 22.0 * f64::from(n.max(1)),
        PulseShape::Cn(n) => 40.0 * f64::from(n.max(1)),
        PulseShape::HalfSine if linear => 4.5,
        PulseShape::HalfSine => 34.0,
        PulseShape::Rectangular if linear => 1.0,
        PulseShape::Rectangular => 11.0,
        PulseShape::Ricker { .. } if linear => 56.0,
        PulseShape::Ricker { .. } => 90.0,
        PulseShape::MavroeidisPapageorgiou { gamma, .. } if linear => 24.0 * gamma.get().max(0.5),
        PulseShape::MavroeidisPapageorgiou { gamma, .. } => 35.0 * gamma.get().max(0.5),
    };
    us * 1e-6
}

/// CPU seconds of one simulation of a record `acc` (any unit): a block
/// rocks, and costs, while the record shakes, about a step a sample;
/// before and after, its samples are only read. The shaking part is from
/// the first to the last sample above a tenth of the peak.
pub fn record_simulation_s(acc: &[f64]) -> f64 {
    record_steps_simulation_s(acc.len(), shaking_samples(acc) as f64)
}

/// CPU seconds a simulation of a record costs whatever its length.
const SIMULATION_S: f64 = 2e-5;

/// CPU seconds a simulation spends on each sample of its record (read,
/// integrated or not).
const PER_SAMPLE_S: f64 = 5e-8;

/// CPU seconds of one simulation of a record of `samples` samples, `steps`
/// of which are integrated.
fn record_steps_simulation_s(samples: usize, steps: f64) -> f64 {
    SIMULATION_S + PER_SAMPLE_S * samples as f64 + PER_SHAKING_SAMPLE_S * steps
}

/// CPU seconds of one shaking sample of a record: the block rocks through
/// it, an integration step or more.
const PER_SHAKING_SAMPLE_S: f64 = 1.8e-6;

/// Jobs whose model CPU time is at least this, s, are sized on a sample of
/// their work where their kind measures one ([`crate::kinds::Kind::sampled_size`]):
/// below it a misjudged estimate costs seconds, and a sample would cost a
/// large share of the job.
pub const SAMPLE_FROM_S: f64 = 10.0;

/// CPU seconds a sample of a job of `cpu_s` model seconds may spend: 2 %
/// of the job, at most two seconds over two threads (the submission waits
/// for it about a second).
pub fn sample_budget_s(cpu_s: f64) -> f64 {
    (0.02 * cpu_s).min(2.0)
}

/// When a sample of `per_thread` CPU seconds a thread is stopped, wall
/// time (its job then keeps the model's estimate): its minimum of brackets
/// may cost more than its budget, but never minutes, whatever the record.
pub fn sample_deadline(per_thread: f64) -> std::time::Duration {
    std::time::Duration::from_secs_f64(1.0 + 2.0 * per_thread.max(0.0))
}

/// Brackets a sample of a record's scan runs per thread: at least the
/// first (however much they cost); in all at most the second (within its
/// budget: under an ordered record a bracket costs a few milliseconds,
/// under a chaotic one a hundred simulations).
pub const SAMPLE_BRACKETS: [u64; 2] = [4, 512];

/// Samples from the first to the last one above a tenth of the peak.
pub fn shaking_samples(acc: &[f64]) -> usize {
    let peak = acc.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let loud = |a: &&f64| a.abs() >= 0.1 * peak && peak > 0.0;
    match (
        acc.iter().position(|a| loud(&a)),
        acc.iter().rposition(|a| loud(&a)),
    ) {
        (Some(first), Some(last)) => last - first + 1,
        _ => 0,
    }
}

/// Transitions assumed per line of a pulse spectrum: a bracket of one scan
/// step narrowed to the tolerance takes log2(step/tolerance) bisection steps;
/// a line has a handful of transitions (Figs. 6, 10, 11 show at most four).
pub const TRANSITIONS_PER_PULSE_LINE: f64 = 6.0;

/// Bisection steps per scan point of a record's line: under a record the
/// impact count changes between most neighbouring levels, and each change is
/// bisected down to the tolerance (measured: 19 to 24 simulations per scan
/// point at 7.6 bisection steps a bracket).
pub const RECORD_BISECTIONS_PER_POINT: f64 = 2.4;

/// Bisection steps from a scan `step` down to `tolerance`.
pub fn bisection_steps(step: f64, tolerance: f64) -> f64 {
    (step / tolerance).log2().ceil().max(1.0)
}

/// Simulations of one line of a pulse spectrum of `points` scan points.
pub fn pulse_line_simulations(points: f64, step: f64, tolerance: f64) -> f64 {
    points + TRANSITIONS_PER_PULSE_LINE * bisection_steps(step, tolerance)
}

/// Simulations of one line of a record's scan of `points` scan points.
pub fn record_line_simulations(points: f64, step: f64, tolerance: f64) -> f64 {
    points * (1.0 + RECORD_BISECTIONS_PER_POINT * bisection_steps(step, tolerance))
}

/// How much more a scan's simulation costs on a Coulomb floor (`contact`)
/// than under pure rocking: each level runs pure rocking until the friction
/// it needs first exceeds μ, then the modes until the outcome is decided (a
/// 40-frequency one-sine spectrum of the locomotive on μ = 0.3 measured
/// 48 µs a simulation against pure rocking's 18 µs on one thread, 2.6–2.7×,
/// `examples/contact_spectrum.rs`).
pub fn contact_factor(contact: Option<&super::contact::ContactNorm>) -> f64 {
    if contact.is_some() { 2.8 } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shaking_record_costs_more_than_a_quiet_tail() {
        let mut acc = vec![0.0; 4000];
        for (k, a) in acc.iter_mut().enumerate().skip(100).take(300) {
            *a = (k as f64 * 0.1).sin();
        }
        let pulse_like = record_simulation_s(&acc);
        let shaking: Vec<f64> = (0..4000).map(|k| (k as f64 * 0.1).sin()).collect();
        assert!(shaking_samples(&acc) <= 300 && shaking_samples(&acc) > 250);
        assert!(shaking_samples(&shaking) > 3990);
        assert!(record_simulation_s(&shaking) > 5.0 * pulse_like);
        assert_eq!(shaking_samples(&[0.0; 10]), 0);
    }

    #[test]
    fn a_pulse_of_more_cycles_costs_more() {
        let nl = Formulation::Nonlinear;
        let rk = SolverMethod::RungeKutta(crate::dynamics::Method::Dop853);
        assert!(
            pulse_simulation_s(&PulseShape::Cn(4), nl, rk)
                > pulse_simulation_s(&PulseShape::Cn(2), nl, rk)
        );
        assert!(
            pulse_simulation_s(
                &PulseShape::OneSine,
                Formulation::Linear,
                SolverMethod::Exact
            ) < pulse_simulation_s(&PulseShape::OneSine, nl, rk)
        );
    }
}
