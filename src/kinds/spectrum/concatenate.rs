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
    for part in parts {
        lines.extend(part.spectrum);
        no_sliding.extend(part.no_sliding);
        let c = &part.numerics.cost;
        let counts = [
            c.simulations,
            c.steps_accepted,
            c.steps_rejected,
            c.rhs_evaluations,
            c.events,
            c.verification_simulations,
            c.undecided_simulations,
        ];
        for (sum, n) in sums.iter_mut().zip(counts) {
            *sum += n;
        }
        error = error.max(c.error_estimate);
        wall += part.numerics.wall_time_s;
        numerics.get_or_insert(part.numerics);
    }
    let mut numerics = numerics.unwrap_or_else(|| SpectrumNumerics {
        cost: ScanCost::new(&job.solver, &Default::default()),
        tolerance: job.tolerance,
        scan_step_alpha_g: job.scan_step_alpha_g,
        wall_time_s: 0.0,
        tasks: None,
    });
    let c = &mut numerics.cost;
    [
        c.simulations,
        c.steps_accepted,
        c.steps_rejected,
        c.rhs_evaluations,
        c.events,
        c.verification_simulations,
        c.undecided_simulations,
    ] = sums;
    c.error_estimate = error;
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
