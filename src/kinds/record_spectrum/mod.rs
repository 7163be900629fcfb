//! The `record_spectrum` job: which blocks of which size a recorded motion
//! topples, at which scale (the rocking spectrum of Makris & Konstantinidis
//! 2003). One line per block size p (or R = 3g/(4p²)), each the overturning
//! set over the record's scale factor.
//!
//! Internally a scale factor s is the level s·PGA/(αg) of a pulse spectrum's
//! amplitude axis, so the defaults (scan step 0.02 αg, tolerance 1e-4 αg) are
//! the pulse spectra's, expressed in scale units: step 0.02·s_α and tolerance
//! 1e-4·s_α, with s_α = αg/PGA the scale at which the record's PGA reaches αg.

pub mod figure;
pub mod table;

mod result;
mod run;
mod spec;
pub use result::*;
pub use spec::*;

use crate::jobs::error::JobError;
use crate::spectrum::Control;

pub mod part;

/// The `record_spectrum` kind: the rocking spectrum of a recorded motion.
pub struct RecordSpectrum;

impl crate::kinds::kind::Kind for RecordSpectrum {
    const NAME: &'static str = crate::jobs::names::tag::RecordSpectrum::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Record spectrum";
    type Spec = RecordSpectrumSpec;
    type Job = RecordSpectrumJob;
    type Result = RecordSpectrumResult;
    type Part = crate::jobs::scan_parts::PartDoc;
    type Range = crate::jobs::scan_parts::Part;

    fn run(
        job: &RecordSpectrumJob,
        part: Option<crate::jobs::scan_parts::Part>,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        use crate::kinds::kind::Output;
        Ok(match part {
            // A task's transitions, assembled by the service.
            Some(p) => Output::Part(part::run(job, p, control)?),
            None => Output::Whole(job.run(control)?),
        })
    }

    fn table(
        result: &RecordSpectrumResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &RecordSpectrumResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    /// Scan points of every size, each bisected down to the tolerance
    /// ([`crate::jobs::cost::record_line_simulations`]), at the cost of a
    /// simulation of the record.
    fn size(
        job: &RecordSpectrumJob,
        part: Option<crate::jobs::scan_parts::Part>,
    ) -> crate::jobs::kind::Size {
        let scan = job.points_per_size();
        let grid = job.grid();
        let (n, points) = match part {
            Some(p) => (
                (p.lines[1] - p.lines[0]) as f64,
                (p.levels[1] - p.levels[0] + 1) as f64,
            ),
            None => (job.p.len() as f64, scan),
        };
        let work =
            n * crate::jobs::cost::record_line_simulations(points, grid.step, grid.tolerance);
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: (n * points).min(usize::MAX as f64) as usize,
            work,
            record_work: work * job.ground_motion.acc.len() as f64,
            cpu_s: work
                * crate::jobs::cost::record_simulation_s(&job.ground_motion.acc)
                * crate::jobs::cost::contact_factor(job.contact.as_ref()),
            lanes: n * (points / 48.0).ceil(),
        }
    }

    /// The scan's simulations and CPU time measured on a sample of its
    /// brackets ([`part::sample`], on two threads): the model's
    /// [`crate::jobs::cost::RECORD_BISECTIONS_PER_POINT`] holds under an
    /// ordered record, but a chaotic one bisects five times as much, and a
    /// block that overturns early costs a fraction of the record. A few
    /// costly brackets hold much of a scan's bisection, which a small sample
    /// tends to miss: the simulations are the sample's or the model's,
    /// whichever is more.
    fn sampled_size(
        job: &RecordSpectrumJob,
        size: &crate::jobs::kind::Size,
    ) -> Option<crate::jobs::kind::Size> {
        use crate::jobs::cost;
        const THREADS: usize = 2;
        let budget = cost::sample_budget_s(size.cpu_s) / THREADS as f64;
        let sample = part::sample(job, THREADS, cost::sample_deadline(budget), |s| {
            s.brackets >= cost::SAMPLE_BRACKETS[0] && s.cpu_s >= budget
        })
        .ok()?;
        let work = sample
            .simulations(job.p.len(), job.grid().points())?
            .max(size.work);
        Some(crate::jobs::kind::Size {
            work,
            record_work: work * job.ground_motion.acc.len() as f64,
            cpu_s: work * sample.simulation_cpu_s(),
            ..*size
        })
    }

    fn grid_field(_job: &RecordSpectrumJob) -> &'static str {
        "/p"
    }

    fn warnings(job: &RecordSpectrumJob) -> Vec<crate::jobs::warning::WarningDoc> {
        use crate::jobs::plausible::{coarse_dt_warning, record_warnings};
        let mut found = record_warnings(&job.ground_motion, "/ground_motion");
        if let Some(p) = job.p.iter().copied().reduce(f64::max) {
            found.extend(coarse_dt_warning(job.ground_motion.dt, p, "/ground_motion"));
        }
        found
    }

    /// Tasks of about [`crate::jobs::cost::TASK_CPU_S`]: sizes grouped, or a
    /// size split along the scale axis ([`part`]); each task names its part
    /// of the job, whose record is stored once.
    fn split(
        job: &RecordSpectrumJob,
        size: &crate::jobs::kind::Size,
    ) -> Vec<crate::kinds::kind::Task<Self>> {
        crate::kinds::kind::Task::parts(job, part::cut(job, size))
    }

    fn fits(
        whole: &RecordSpectrumJob,
        p: &crate::jobs::scan_parts::Part,
    ) -> Result<(), crate::jobs::JobError> {
        part::fits(whole, p)
    }

    /// The parts' transitions gathered per size, and everything derived
    /// from them as one task would.
    fn assemble(
        job: &RecordSpectrumJob,
        parts: Vec<crate::jobs::scan_parts::PartDoc>,
    ) -> Result<RecordSpectrumResult, JobError> {
        job.result_of(&parts)
    }
}
