//! A forensic query on a recorded motion: which scale factors of the record
//! are consistent with every observation. Each observation's block is scanned
//! over the scaled PGA, in g, from where it starts to rock to the highest PGA
//! examined ([`super::scan`]), with the guarantees of the pulse queries (scan
//! plus bisection of every transition, each interval end bracketed within
//! `tolerance_g`); the sets of all observations are intersected.

use super::mixed::{self, MixedDoc};
use super::scan::ObservationScan;
use super::{
    AmplitudeRange, Bounds, ForensicJob, ForensicNumerics, ForensicResult, Intervals, LineSet,
    RecordObservationSet, intersect,
};
use crate::dynamics::{SimError, peaks};
use crate::jobs::names::{Excitation, tag};
use crate::jobs::spec::GroundMotionNorm;
use crate::kinds::record_spectrum::RecordDoc;
use crate::kinds::spectrum::ScanCost;
use crate::kinds::time_history::GroundPeaksDoc;
use crate::spectrum::scan::{ScanError, ScanStats};

/// The result of `job`, whose excitation is the record `gm`, from each
/// observation's overturning set (`sets[observation][0]`, scaled PGA in g).
pub fn result(
    job: &ForensicJob,
    gm: &GroundMotionNorm,
    scans: &[ObservationScan],
    sets: &[Vec<LineSet>],
    stats: &ScanStats,
) -> Result<ForensicResult, ScanError> {
    let record = gm
        .record()
        .map_err(|_| ScanError::Simulation(SimError::Tolerance))?;
    let AmplitudeRange { from, to } = job.range_g();
    let g = job.observations.first().map_or(9.81, |o| o.block.g);
    let peak_g = crate::kinds::record_spectrum::pga(&gm.acc) / g;
    let to_scale = |set: &[[f64; 2]]| -> Intervals {
        set.iter().map(|&[a, b]| [a / peak_g, b / peak_g]).collect()
    };
    let mut all: Intervals = vec![[from, to]];
    let mut consistent_each: Vec<Intervals> = Vec::new();
    let mut zones_each: Vec<Vec<MixedDoc>> = Vec::new();
    let per_observation: Vec<RecordObservationSet> = job
        .observations
        .iter()
        .zip(scans)
        .zip(sets)
        .map(|((o, s), lines)| {
            let line = lines.first().cloned().unwrap_or(LineSet {
                decided_to: to,
                ..LineSet::default()
            });
            let consistent = line.consistent(o.overturned, from);
            let overturning_g = line.certain_overturning();
            let zones = mixed::observation_zones(&line, o, from);
            all = intersect(&all, &consistent);
            consistent_each.push(consistent.clone());
            zones_each.push(zones.clone());
            RecordObservationSet {
                name: o.name.clone(),
                overturned: o.overturned,
                consistent_scale: to_scale(&consistent),
                consistent_pga_g: consistent,
                mixed_scale: zones.iter().map(|z| z.rescaled(peak_g)).collect(),
                mixed_pga_g: zones,
                overturning_scale: to_scale(&overturning_g),
                threshold_scale: s.threshold * s.alpha / peak_g,
                lift_off_above_scale: line.lift_off_g.map(|a| a / peak_g),
            }
        })
        .collect();
    let combined = mixed::combined(&consistent_each, &zones_each);
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
        mixed_scale: Some(combined.iter().map(|z| z.rescaled(peak_g)).collect()),
        mixed_pga_g: Some(combined),
        per_observation: Some(per_observation),
        bounds,
        lift_off_above_g: job.lift_off_g().map(|(_, hi)| hi),
        numerics: ForensicNumerics {
            cost: ScanCost::new(&job.solver, stats),
            tolerance_g: job.tolerance_g,
            scan_step_g: job.scan_step_g,
            wall_time_s: 0.0,
            tasks: None,
        },
        spec: job.clone(),
        engine: None,
    })
}
