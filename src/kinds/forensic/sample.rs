//! A forensic query under a record sized on a sample of its scans
//! ([`crate::spectrum::pilot`]): as a record spectrum's, the bisection of an
//! observation's line follows the record's chaos, which its model
//! ([`crate::jobs::cost::record_line_simulations`]) cannot foresee.

use super::ForensicJob;
use crate::dynamics::Problem;
use crate::jobs::cost;
use crate::jobs::kind::Size;
use crate::spectrum::overturning::ScanGrid;
use crate::spectrum::pilot::{self, Sample};
use crate::spectrum::scan::{Model, Scalable};

/// Threads a sample runs on.
const THREADS: usize = 2;

/// The sample of one line: at most `budget` CPU seconds over its threads,
/// stopped at `deadline`.
fn sample_line<G: Scalable + Sync>(
    problem: Problem<G>,
    model: Model,
    grid: &ScanGrid,
    budget: f64,
    deadline: std::time::Duration,
) -> Option<Sample> {
    let count = [cost::SAMPLE_BRACKETS[1] as usize, THREADS];
    let per_thread = budget / THREADS as f64;
    pilot::sample(&[problem], model, grid, count, deadline, |s| {
        s.brackets >= cost::SAMPLE_BRACKETS[0] && s.cpu_s >= per_thread
    })
    .ok()
}

impl ForensicJob {
    /// The query's size (`size`: its model's) with the line of each
    /// observation under its record measured on a sample of its brackets,
    /// each observation given its share of the budget
    /// ([`cost::sample_budget_s`]) by its model's work; its simulations the
    /// sample's, or the model's where that is more. `None` under a pulse
    /// (the model holds: a handful of transitions a line).
    pub fn sampled_size(&self, size: &Size) -> Option<Size> {
        let gm = self.ground_motion.as_ref()?;
        let record = gm.record().ok()?;
        let pair = match self.scaled_vertical() {
            Some(v) => Some(v.record_pair(record.clone()).ok()?),
            None => None,
        };
        let budget = cost::sample_budget_s(size.cpu_s);
        // One deadline for the whole query, as for a record spectrum.
        let started = std::time::Instant::now();
        let deadline = cost::sample_deadline(budget / THREADS as f64);
        let (mut work, mut cpu_s) = (0.0, 0.0);
        for (o, scan) in self.observation_scans().ok()?.iter().enumerate() {
            let Some(grid) = scan.grid else { continue };
            let points = grid.points();
            let model_work = self.line_simulations(points as f64, &grid);
            let share = budget * model_work / size.work.max(1.0);
            let model = Model {
                solver: self.solver.solver(),
                friction: self.contact.as_ref().map(|c| c.friction()),
                slide_band: self.observations.get(o).and_then(|o| o.slid_m),
            };
            let (block, formulation) = (scan.block, self.formulation);
            let left = deadline.checked_sub(started.elapsed())?;
            let sample = match &pair {
                None => sample_line(
                    Problem {
                        block,
                        pulse: record.clone(),
                        formulation,
                    },
                    model,
                    &grid,
                    share,
                    left,
                ),
                Some(p) => sample_line(
                    Problem {
                        block,
                        pulse: p.clone(),
                        formulation,
                    },
                    model,
                    &grid,
                    share,
                    left,
                ),
            }?;
            let line = sample.simulations(1, points)?.max(model_work);
            work += line;
            cpu_s += line * sample.simulation_cpu_s();
        }
        Some(Size {
            work,
            record_work: work * gm.acc.len() as f64,
            cpu_s,
            ..*size
        })
    }
}
