//! A forensic query on a recorded motion: which scale factors of the record
//! are consistent with every observation. Each observation's block is scanned
//! over the scaled PGA, in g, from where it starts to rock to the highest PGA
//! examined, with the guarantees of the pulse queries (scan plus bisection of
//! every transition, each interval end bracketed within `tolerance_g`); the
//! sets of all observations are intersected.

use rayon::prelude::*;

use super::{
    AmplitudeRange, Bounds, ForensicJob, ForensicNumerics, ForensicResult, Intervals,
    RecordObservationSet, complement, intersect, overturning_set,
};
use crate::dynamics::{Problem, SimError, peaks};
use crate::jobs::names::{Excitation, tag};
use crate::jobs::record_spectrum::RecordDoc;
use crate::jobs::spec::GroundMotionNorm;
use crate::jobs::spectrum::ScanCost;
use crate::jobs::time_history::GroundPeaksDoc;
use crate::spectrum::Control;
use crate::spectrum::overturning::{ScanGrid, scan_lines, threshold_alpha_g};
use crate::spectrum::scan::{ScanError, ScanStats};

/// One observation's overturning set (PGA in g) and where it starts to rock (g).
struct Scanned {
    overturning_g: Intervals,
    threshold_g: f64,
    stats: ScanStats,
}

/// Runs `job`, whose excitation is the record `gm`.
pub fn run(
    job: &ForensicJob,
    gm: &GroundMotionNorm,
    control: &Control,
) -> Result<ForensicResult, ScanError> {
    let started = std::time::Instant::now();
    let record = gm
        .record()
        .map_err(|_| ScanError::Simulation(crate::dynamics::SimError::Tolerance))?;
    let formulation = job.formulation;
    let solver = job.solver.solver();
    let AmplitudeRange { from, to } = job.range_g();
    let g = job.observations.first().map_or(9.81, |o| o.block.g);
    let peak_g = crate::jobs::record_spectrum::pga(&gm.acc) / g;
    // Observations in parallel; each line's levels are the scaled PGA in its α g.
    let scanned = job
        .observations
        .par_iter()
        .map(|o| {
            let block = o.block.block().map_err(SimError::from)?;
            let alpha = block.slenderness();
            let threshold = threshold_alpha_g(formulation, &block);
            let mut stats = ScanStats::default();
            let overturning_g = if to / alpha <= threshold {
                // Never rocks in the range: nothing overturns.
                Vec::new()
            } else {
                // From the threshold, whatever `from` is: the state at the
                // range's start is then known, not assumed.
                let grid = ScanGrid {
                    from: threshold,
                    to: to / alpha,
                    step: job.scan_step_g / alpha,
                    tolerance: job.tolerance_g / alpha,
                    principal_relative_width: 0.0,
                };
                let problem = Problem {
                    block,
                    pulse: record.clone(),
                    formulation,
                };
                let (lines, s) = scan_lines(&[problem], solver, &grid, control)?;
                stats = s;
                lines
                    .first()
                    .map(|l| overturning_set(&l.transitions, alpha, from, to))
                    .unwrap_or_default()
            };
            Ok(Scanned {
                overturning_g,
                threshold_g: threshold * alpha,
                stats,
            })
        })
        .collect::<Result<Vec<Scanned>, ScanError>>()?;
    let to_scale = |set: &[[f64; 2]]| -> Intervals {
        set.iter().map(|&[a, b]| [a / peak_g, b / peak_g]).collect()
    };
    let mut stats = ScanStats::default();
    let mut all: Intervals = vec![[from, to]];
    let per_observation: Vec<RecordObservationSet> = job
        .observations
        .iter()
        .zip(&scanned)
        .map(|(o, s)| {
            stats.absorb(&s.stats);
            let consistent = if o.overturned {
                s.overturning_g.clone()
            } else {
                complement(&s.overturning_g, from, to)
            };
            all = intersect(&all, &consistent);
            RecordObservationSet {
                name: o.name.clone(),
                overturned: o.overturned,
                consistent_scale: to_scale(&consistent),
                consistent_pga_g: consistent,
                overturning_scale: to_scale(&s.overturning_g),
                threshold_scale: s.threshold_g / peak_g,
            }
        })
        .collect();
    let bounds = Bounds {
        min_g: all.first().map(|i| i[0]),
        max_g: all.last().map(|i| i[1]),
        frequency_hz: None,
        min_scale: all.first().map(|i| i[0] / peak_g),
        max_scale: all.last().map(|i| i[1] / peak_g),
    };
    let n = gm.acc.len();
    Ok(ForensicResult {
        warnings: Vec::new(),
        kind: tag::Forensic,
        formulation: job.formulation,
        excitation: Excitation::GroundMotion,
        pulse: None,
        record: Some(RecordDoc {
            peaks: GroundPeaksDoc::new(&peaks::of_record(&record), g),
            dt_s: gm.dt,
            samples: n,
            duration_s: (n - 1) as f64 * gm.dt,
        }),
        a_p_g: job.range_g(),
        scale: job.scale(),
        observations: job.observations.clone(),
        frequencies: Vec::new(),
        consistent_scale: Some(to_scale(&all)),
        consistent_pga_g: Some(all),
        per_observation: Some(per_observation),
        bounds,
        numerics: ForensicNumerics {
            cost: ScanCost::new(&job.solver, &stats),
            tolerance_g: job.tolerance_g,
            scan_step_g: job.scan_step_g,
            wall_time_s: started.elapsed().as_secs_f64(),
        },
        spec: job.clone(),
        engine: None,
    })
}
