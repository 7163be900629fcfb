//! A spectrum split into tasks along its frequencies, put back together.

use super::{ScanCost, SpectrumJob, SpectrumNumerics, SpectrumResult};

/// The result of a spectrum `job` from its tasks' results (each a
/// spectrum of some of its frequencies): the lines (`spectrum`, and
/// `no_sliding` when the tasks carry it) concatenated in task order, the
/// counts summed (`wall_time_s` is then the tasks' total compute time;
/// `error_estimate` their largest), the rest of the numerics the first
/// task's, and `tasks` their number.
pub fn concatenate(job: &SpectrumJob, parts: Vec<SpectrumResult>) -> SpectrumResult {
    let tasks = parts.len();
    let mut lines = Vec::new();
    let mut no_sliding = Vec::new();
    let mut numerics: Option<SpectrumNumerics> = None;
    let (mut error, mut wall) = (0.0f64, 0.0f64);
    let mut sums = [0u64; 7];
    for mut part in parts {
        for (sum, n) in sums.iter_mut().zip(counts(&mut part.numerics.cost)) {
            *sum += *n;
        }
        error = error.max(part.numerics.cost.error_estimate);
        wall += part.numerics.wall_time_s;
        lines.extend(part.spectrum);
        no_sliding.extend(part.no_sliding);
        numerics.get_or_insert(part.numerics);
    }
    let mut numerics = numerics.unwrap_or_else(|| SpectrumNumerics {
        cost: ScanCost::new(&job.solver, &Default::default()),
        tolerance: job.tolerance,
        scan_step_alpha_g: job.scan_step_alpha_g,
        wall_time_s: 0.0,
        tasks: None,
    });
    for (n, sum) in counts(&mut numerics.cost).into_iter().zip(sums) {
        *n = sum;
    }
    numerics.cost.error_estimate = error;
    numerics.wall_time_s = wall;
    numerics.tasks = Some(tasks);
    SpectrumResult {
        kind: Default::default(),
        spectrum: lines,
        no_sliding,
        numerics,
        spec: job.clone(),
        warnings: Vec::new(),
        engine: None,
    }
}

/// The counts of a scan's cost that add up over its tasks.
fn counts(c: &mut ScanCost) -> [&mut u64; 7] {
    [
        &mut c.simulations,
        &mut c.steps_accepted,
        &mut c.steps_rejected,
        &mut c.rhs_evaluations,
        &mut c.events,
        &mut c.verification_simulations,
        &mut c.undecided_simulations,
    ]
}
