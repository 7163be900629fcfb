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
    /// Mean right-hand-side evaluations per simulation (closed-form
    /// evaluations for `exact`): the work, independent of the machine.
    pub evaluations_per_run: f64,
    /// Mean wall time per simulation, s, once measured ([`time_rows`]).
    pub time_per_run: Option<f64>,
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
    let Ok(block) = Block::new(0.25, 2.14, Some(0.9), None, None) else {
        return Vec::new();
    };
    CASES
        .iter()
        .filter_map(|&(shape, ratio, level)| {
            let pulse = Pulse::new(
                shape,
                level * block.slenderness() * block.gravity(),
                ratio * block.frequency_parameter(),
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
    let opts = run_options(solver);
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

/// What a timed run computes: the history through the pulse and the exact
/// decision at its end, without reactions or free impacts.
fn run_options(solver: Solver) -> Options {
    Options {
        reactions: false,
        peak: false,
        max_free_impacts: 0,
        ..Options::history(solver)
    }
}

/// Mean right-hand-side evaluations per simulation of `solver` on `problems`.
fn evaluations_per_run(problems: &[Problem], solver: Solver) -> Result<f64, SimError> {
    let opts = run_options(solver);
    let mut total = 0u64;
    for p in problems {
        total += simulate(p, &opts)?.numerics.rhs_evaluations;
    }
    Ok(total as f64 / problems.len().max(1) as f64)
}

/// The solvers of the study, in the order of its rows.
fn solvers() -> Vec<Solver> {
    let mut out = vec![Solver::Exact];
    for method in [Method::Dopri5, Method::Dop853] {
        for &rtol in &LADDER {
            out.push(Solver::RungeKutta {
                method,
                rtol,
                atol: rtol / 100.0,
            });
        }
    }
    out
}

/// Runs the study: errors and work, the same on every run (no timing).
pub fn study() -> Result<Vec<PrecisionRow>, SimError> {
    let problems = problems();
    let mut rows = Vec::new();
    for solver in solvers() {
        let (mut err, mut terr) = (0.0f64, 0.0f64);
        if solver != Solver::Exact {
            for p in &problems {
                let (e, t) = compare_with_exact(p, solver)?;
                err = err.max(e);
                terr = terr.max(t);
            }
        }
        let (method, rtol) = match solver {
            Solver::Exact => ("exact", None),
            Solver::RungeKutta { method, rtol, .. } => (method.name(), Some(rtol)),
        };
        rows.push(PrecisionRow {
            method,
            rtol,
            max_error: err,
            max_impact_time_error: terr,
            evaluations_per_run: evaluations_per_run(&problems, solver)?,
            time_per_run: None,
        });
    }
    Ok(rows)
}

/// Measures each row's wall time per simulation (best of five batches).
pub fn time_rows(rows: &mut [PrecisionRow]) -> Result<(), SimError> {
    let problems = problems();
    for (row, solver) in rows.iter_mut().zip(solvers()) {
        row.time_per_run = Some(time_per_run(&problems, solver)?);
    }
    Ok(())
}

/// Where README.md holds the table [`markdown`] writes.
pub const README_BEGIN: &str = "<!-- topple precision --readme: begin -->";
/// The end of the README's table.
pub const README_END: &str = "<!-- topple precision --readme: end -->";

/// The README's table: the rows at rtol 1e-6, 1e-8, 1e-10 and 1e-12, errors
/// to two significant digits, work in right-hand-side evaluations.
pub fn markdown(rows: &[PrecisionRow]) -> String {
    let mut out = String::from(
        "| method | rtol | max abs error θ (rad) | max impact-time error (s) | evaluations/run |\n|---|---|---|---|---|\n",
    );
    for r in rows {
        let shown = match r.rtol {
            None => true,
            Some(t) => [1e-6, 1e-8, 1e-10, 1e-12].contains(&t),
        };
        if !shown {
            continue;
        }
        let (rtol, err, terr) = match r.rtol {
            None => ("–".to_string(), "(reference)".to_string(), "–".to_string()),
            Some(t) => (
                format!("{t:.0e}"),
                format!("{:.1e}", r.max_error),
                format!("{:.1e}", r.max_impact_time_error),
            ),
        };
        let work = if r.evaluations_per_run > 0.0 {
            format!("{:.0}", r.evaluations_per_run)
        } else {
            "–".to_string()
        };
        out.push_str(&format!(
            "| {} | {rtol} | {err} | {terr} | {work} |\n",
            r.method
        ));
    }
    out
}

/// `readme` with the text between [`README_BEGIN`] and [`README_END`]
/// replaced by `table`; `None` when the markers are missing.
pub fn with_table(readme: &str, table: &str) -> Option<String> {
    let begin = readme.find(README_BEGIN)? + README_BEGIN.len();
    let end = begin + readme[begin..].find(README_END)?;
    Some(format!("{}\n{table}{}", &readme[..begin], &readme[end..]))
}

/// The `topple precision` command: prints the table with times measured on
/// this machine, writes the diagram `draw` makes of it to `svg_path`, and
/// with `readme` rewrites that file's table.
pub fn report(
    svg_path: &str,
    readme: Option<&str>,
    draw: impl Fn(&[PrecisionRow]) -> Result<String, String>,
) -> Result<(), String> {
    use std::io::Write;
    let mut rows = study().map_err(|e| e.to_string())?;
    std::fs::write(svg_path, draw(&rows)?).map_err(|e| format!("{svg_path}: {e}"))?;
    if let Some(path) = readme {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
        let new = with_table(&text, &markdown(&rows))
            .ok_or_else(|| format!("{path}: no table between {README_BEGIN} and {README_END}"))?;
        std::fs::write(path, new).map_err(|e| format!("{path}: {e}"))?;
    }
    time_rows(&mut rows).map_err(|e| e.to_string())?;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "work-precision, linear formulation, {} cases (locomotive block, one-sine / one-cosine / C1 pulses)",
        CASES.len()
    );
    let _ = writeln!(
        out,
        "{:<8} {:>8} {:>14} {:>16} {:>12} {:>14}",
        "method", "rtol", "max |dtheta|", "max |dt_impact|", "evals/run", "time/run (us)"
    );
    for r in &rows {
        let _ = writeln!(
            out,
            "{:<8} {:>8} {:>14.3e} {:>16.3e} {:>12.0} {:>14.2}",
            r.method,
            r.rtol
                .map(|t| format!("{t:.0e}"))
                .unwrap_or_else(|| "-".into()),
            r.max_error,
            r.max_impact_time_error,
            r.evaluations_per_run,
            r.time_per_run.unwrap_or(f64::NAN) * 1e6
        );
    }
    let _ = writeln!(out, "diagram written to {svg_path}");
    if let Some(path) = readme {
        let _ = writeln!(out, "table written to {path}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> std::path::PathBuf {
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
    }

    /// The book's table (Solvers and precision) and its diagram are what the
    /// study computes now (regenerate both with `topple precision --svg
    /// docs/book/src/figures/precision.svg --readme docs/book/src/solvers.md`).
    #[test]
    fn readme_table_and_diagram_are_the_studys() {
        let rows = study().expect("study runs");
        let chapter = "docs/book/src/solvers.md";
        let diagram = "docs/book/src/figures/precision.svg";
        let text = std::fs::read_to_string(root().join(chapter)).expect(chapter);
        let regenerate =
            format!("regenerate with `topple precision --svg {diagram} --readme {chapter}`");
        let expected = with_table(&text, &markdown(&rows)).expect("the chapter has the markers");
        assert!(
            expected == text,
            "{chapter}'s precision table drifted: {regenerate}"
        );
        let svg = std::fs::read_to_string(root().join(diagram)).expect("svg");
        let drawn = crate::plot::precision_diagram(&rows).expect("draws");
        assert!(drawn == svg, "{diagram} drifted: {regenerate}");
    }

    /// The table's numbers: tighter tolerances give smaller errors for more
    /// work, and dop853 needs fewer evaluations than dopri5 at 1e-10.
    #[test]
    fn errors_fall_and_work_grows_down_the_ladder() {
        let rows = study().expect("study runs");
        assert_eq!(rows.len(), 1 + 2 * LADDER.len());
        for method in ["dopri5", "dop853"] {
            let r: Vec<&PrecisionRow> = rows.iter().filter(|r| r.method == method).collect();
            assert!(r[0].max_error > 1e3 * r[r.len() - 1].max_error, "{method}");
            for w in r.windows(2) {
                assert!(
                    w[1].evaluations_per_run > w[0].evaluations_per_run,
                    "{method}"
                );
            }
            assert!(
                r.iter()
                    .all(|x| x.max_error.is_finite() && x.max_error < 1e-2)
            );
        }
        let at = |m: &str| {
            rows.iter()
                .find(|r| r.method == m && r.rtol == Some(1e-10))
                .map(|r| r.evaluations_per_run)
                .expect("row")
        };
        assert!(at("dop853") < at("dopri5"));
    }

    #[test]
    fn with_table_replaces_only_between_the_markers() {
        let text = format!("a\n{README_BEGIN}\nold\n{README_END}\nb\n");
        assert_eq!(
            with_table(&text, "new\n").as_deref(),
            Some(format!("a\n{README_BEGIN}\nnew\n{README_END}\nb\n").as_str())
        );
        assert_eq!(with_table("no markers", "x"), None);
    }
}
