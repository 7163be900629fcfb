//! The `fragility` job: the probability that a block topples at each of
//! several intensity levels (stripes), by Monte Carlo over uncertain geometry
//! and pulse frequency (or over a suite of records), each simulation decided
//! exactly (events located, overturning from the separatrix); then the
//! lognormal fragility fitted to the stripes by maximum likelihood (Baker
//! 2015), with a bootstrap band.
//!
//! Reproducible whatever the split: stripe k's samples come in chunks of
//! [`CHUNK`], chunk c drawing from its own ChaCha8 stream seeded by (seed, k,
//! c); sample j of a chunk always takes the same four uniforms (α or b, p or
//! h, η, frequency) — a fifth when the vertical ratio is a distribution — so
//! a result depends on the spec only, and a campaign under a fixed vertical
//! ratio simulates the very blocks and pulses of the one without.
//!
//! Under a vertical ground motion (ü_v = r ü_g, or a suite's records with
//! their own vertical component) a sample whose ground falls away faster
//! than g lifts off: pure rocking has no verdict on it, so it is counted
//! apart (`lift_off`) and each stripe's probability is taken over the
//! samples decided.

pub mod figure;
pub mod table;

mod result;
mod run;
mod spec;
pub use result::*;
pub use run::*;
pub use spec::*;

use crate::jobs::JobError;
use crate::spectrum::Control;

/// The `fragility` kind: the probability of overturning against an
/// intensity measure, by Monte Carlo; split into parts of whole units.
pub struct Fragility;

impl crate::kinds::kind::Kind for Fragility {
    const NAME: &'static str = crate::jobs::names::tag::Fragility::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Fragility";
    type Spec = FragilitySpec;
    type Job = FragilityJob;
    type Result = FragilityResult;
    type Part = FragilityPart;
    type Range = [usize; 2];

    fn run(
        job: &FragilityJob,
        part: Option<[usize; 2]>,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, JobError> {
        use crate::kinds::kind::Output;
        Ok(match part {
            // A task's counts, assembled by the service.
            Some(units) => Output::Part(job.run_part(units, control)?),
            None => Output::Whole(job.run(control)?),
        })
    }
    fn table(
        result: &FragilityResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &FragilityResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    fn size(job: &FragilityJob, part: Option<[usize; 2]>) -> crate::jobs::kind::Size {
        let work = job.simulations(part) as f64;
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: work as usize,
            work,
            record_work: work * job.longest_record() as f64,
            cpu_s: work * job.simulation_s(),
            lanes: work,
        }
    }

    fn grid_field(_job: &FragilityJob) -> &'static str {
        "/samples"
    }

    fn warnings(job: &FragilityJob) -> Vec<crate::jobs::warning::WarningDoc> {
        job.ground_motions
            .iter()
            .flatten()
            .enumerate()
            .flat_map(|(i, m)| {
                crate::jobs::plausible::record_warnings(&m.motion, &format!("/ground_motions/{i}"))
            })
            .collect()
    }

    /// Parts of whole units; a task's payload names its units only (the
    /// suite is stored once, with the job).
    fn split(
        job: &FragilityJob,
        _size: &crate::jobs::kind::Size,
    ) -> Vec<crate::kinds::kind::Task<Self>> {
        use crate::kinds::kind::Task;
        let units = job.units();
        let per = crate::jobs::split::per_task(units, CHUNK as f64 * job.simulation_s());
        if per >= units {
            return vec![Task::whole(job.clone())];
        }
        (0..units)
            .step_by(per)
            .map(|from| Task {
                job: job.clone(),
                part: Some([from, (from + per).min(units)]),
            })
            .collect()
    }

    fn fits(whole: &FragilityJob, &[from, to]: &[usize; 2]) -> Result<(), JobError> {
        if from < to && to <= whole.units() {
            return Ok(());
        }
        Err(JobError::Task(format!(
            "a task's part {:?} does not fit its {} job",
            [from, to],
            Self::NAME
        )))
    }

    /// The parts' counts summed per stripe, and the fit made on the sums.
    fn assemble(
        job: &FragilityJob,
        parts: Vec<FragilityPart>,
    ) -> Result<FragilityResult, JobError> {
        job.assemble(&parts)
    }
}
