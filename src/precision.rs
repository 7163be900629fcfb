//! Work-precision study: the error of each Runge–Kutta pair against the closed
//! form (linear formulation) versus run time, across a tolerance ladder.

use std::time::Instant;

use crate::dynamics::{
    Block, Formulation, Method, Options, Problem, Pulse, PulseShape, SimError, Solver, simulate,
};

/// One row of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct PrecisionRow {
    /// "exact", "dopri5" or "dop853".
    pub method: &'static str,
    /// Relative tolerance (atol = rtol/100).
    pub rtol: Option<f64>,
    /// Largest |θ − θ_exact| over the cases, rad, at sample points and impact times.
    pub max_error: f64,
    /// Largest error in an impact time, s.
    pub max_impact_time_error: f64,
    /// Mean wall time per simulation, s.
    pub time_per_run: f64,
}

/// The fixed linear cases of the study: (shape, ω_p/p, a_p/(αg)) on the
/// locomotive block (α = 0.25, p = 2.14, η = 0.9).
pub const CASES: [(PulseShape, f64, f64); 6] = [
    (PulseShape::OneSine, 5.0, 4.0),
    (PulseShape::OneSine, 2.0, 1.8),
    (PulseShape::OneSine, 5.0, 6.5),
    (PulseShape::OneCosine, 3.0, 2.5),
    (PulseShape::OneCosine, 1.0, 1.3),
    (PulseShape::Cn(1), 4.0, 3.0),
];

/// The tolerance ladder.
pub const LADDER: [f64; 10] = [
    1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
];

fn problems() -> Vec<Problem> {
    let block = Block::new(0.25, 2.14, Some(0.9), None, None).unwrap_or(Block {
        slenderness: 0.25,
        frequency_parameter: 2.14,
        restitution: 0.9,
        friction: None,
        gravity: 9.81,
    });
    CASES
        .iter()
        .filter_map(|&(shape, ratio, level)| {
            let pulse = Pulse::new(
                shape,
                level * block.slenderness * block.gravity,
                ratio * block.frequency_parameter,
            )
            .ok()?;
            Some(Problem {
                block,
                pulse,
                formulation: Formulation::Linear,
            })
        })
        .collect()
}

/// Compares `solver` with the closed form on one problem over the pulse (and up
/// to overturning): (max |Δθ| at 400 sample times, max impact-time difference).
pub fn compare_with_exact(problem: &Problem, solver: Solver) -> Result<(f64, f64), SimError> {
    let mut opts = Options::history(Solver::Exact);
    opts.reactions = false;
    opts.max_free_impacts = 0;
    let reference = simulate(problem, &opts)?;
    let end = reference
        .overturn_time
        .unwrap_or(problem.pulse.duration)
        .min(problem.pulse.duration);
    let times: Vec<f64> = (0..400).map(|k| end * k as f64 / 400.0).collect();
    opts.series_at = Some(times.clone());
    let exact = simulate(problem, &opts)?;
    opts.solver = solver;
    let numeric = simulate(problem, &opts)?;
    let (Some(a), Some(b)) = (&exact.series, &numeric.series) else {
        return Ok((0.0, 0.0));
    };
    let n = a.theta.len().min(b.theta.len());
    let mut err: f64 = if a.theta.len() == b.theta.len() {
        0.0
    } else {
        f64::INFINITY
    };
    for k in 0..n {
        err = err.max((a.theta[k] - b.theta[k]).abs());
    }
    let mut terr: f64 = 0.0;
    let ia: Vec<_> = exact.impacts.iter().filter(|i| i.time <= end).collect();
    let ib: Vec<_> = numeric.impacts.iter().filter(|i| i.time <= end).collect();
    if ia.len() != ib.len() {
        terr = f64::INFINITY;
    } else {
        for (x, y) in ia.iter().zip(&ib) {
            terr = terr.max((x.time - y.time).abs());
        }
    }
    Ok((err, terr))
}

fn time_per_run(problems: &[Problem], solver: Solver) -> Result<f64, SimError> {
    let opts = Options {
        reactions: false,
        peak: false,
        max_free_impacts: 0,
        ..Options::history(solver)
    };
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        let reps = 50;
        for _ in 0..reps {
            for p in problems {
                std::hint::black_box(simulate(p, &opts)?);
            }
        }
        best = best.min(start.elapsed().as_secs_f64() / (reps * problems.len()) as f64);
    }
    Ok(best)
}

/// Runs the study.
pub fn study() -> Result<Vec<PrecisionRow>, SimError> {
    let problems = problems();
    let mut rows = Vec::new();
    rows.push(PrecisionRow {
        method: "exact",
        rtol: None,
        max_error: 0.0,
        max_impact_time_error: 0.0,
        time_per_run: time_per_run(&problems, Solver::Exact)?,
    });
    for method in [Method::Dopri5, Method::Dop853] {
        for &rtol in &LADDER {
            let solver = Solver::RungeKutta {
                method,
                rtol,
                atol: rtol / 100.0,
            };
            let (mut err, mut terr) = (0.0f64, 0.0f64);
            for p in &problems {
                let (e, t) = compare_with_exact(p, solver)?;
                err = err.max(e);
                terr = terr.max(t);
            }
            rows.push(PrecisionRow {
                method: method.name(),
                rtol: Some(rtol),
                max_error: err,
                max_impact_time_error: terr,
                time_per_run: time_per_run(&problems, solver)?,
            });
        }
    }
    Ok(rows)
}

/// Prints the table and writes the diagram (the `topple precision` command).
pub fn report(svg_path: &str) -> Result<(), String> {
    use std::io::Write;
    let rows = study().map_err(|e| e.to_string())?;
    crate::plot::precision_diagram(&rows, svg_path).map_err(|e| e.to_string())?;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "work-precision, linear formulation, {} cases (locomotive block, one-sine / one-cosine / C1 pulses)",
        CASES.len()
    );
    let _ = writeln!(
        out,
        "{:<8} {:>8} {:>14} {:>16} {:>14}",
        "method", "rtol", "max |dtheta|", "max |dt_impact|", "time/run (us)"
    );
    for r in &rows {
        let _ = writeln!(
            out,
            "{:<8} {:>8} {:>14.3e} {:>16.3e} {:>14.2}",
            r.method,
            r.rtol
                .map(|t| format!("{t:.0e}"))
                .unwrap_or_else(|| "-".into()),
            r.max_error,
            r.max_impact_time_error,
            r.time_per_run * 1e6
        );
    }
    let _ = writeln!(out, "diagram written to {svg_path}");
    Ok(())
}
