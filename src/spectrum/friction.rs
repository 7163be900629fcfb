//! Friction-demand spectra (paper Fig. 9): the friction coefficient that pure
//! rocking needs, as a function of the pulse amplitude.

use std::time::Instant;

use rayon::prelude::*;

use crate::dynamics::{
    Block, Formulation, Options, Problem, Pulse, PulseShape, Response, SimError, Solver, simulate,
};

use super::control::Control;
use super::overturning::PulseVertical;
use super::scan::{ScanError, ScanStats};

/// What to compute.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionRequest {
    /// The block.
    pub block: Block,
    /// Pulse family.
    pub shape: PulseShape,
    /// Equation of motion.
    pub formulation: Formulation,
    /// Solver.
    pub solver: Solver,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// Amplitudes a_p/(αg).
    pub levels: Vec<f64>,
    /// A vertical ground acceleration (positive up) scaled with each pulse.
    pub vertical: Option<PulseVertical>,
}

/// The demand at one amplitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionPoint {
    /// a_p/(αg).
    pub level: f64,
    /// max |f_x/f_z| over the rocking history (not counting the fall of a block
    /// already bound to overturn); `None` when the block lifts off (f_z → 0⁺):
    /// the demand is unbounded.
    pub peak_demand: Option<f64>,
    /// f_x/f_z when rocking starts (eq. 7; eq. 51 for one-cosine), if it rocks.
    pub initiation_demand: Option<f64>,
    /// Whether the block overturned.
    pub overturned: bool,
    /// Mode.
    pub mode: Option<u8>,
    /// First time f_z ≤ 0, if any: while rocking, or (under a vertical
    /// motion) where the ground falls away faster than gravity.
    pub lift_off: Option<f64>,
    /// The demand was followed up to this time only (the block was then bound
    /// to overturn: its fall is not counted).
    pub followed_until: Option<f64>,
}

/// A friction-demand spectrum.
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionSpectrum {
    /// One point per amplitude, in request order.
    pub points: Vec<FrictionPoint>,
    /// Cost.
    pub stats: ScanStats,
    /// Wall time, s.
    pub wall_time: f64,
}

/// Computes the friction-demand spectrum, in parallel over amplitudes.
pub fn friction_spectrum(
    req: &FrictionRequest,
    control: &Control,
) -> Result<FrictionSpectrum, ScanError> {
    let started = Instant::now();
    control.add_total(req.levels.len() as u64);
    let unit = req.block.slenderness() * req.block.gravity();
    let results: Vec<Result<(FrictionPoint, ScanStats), ScanError>> = req
        .levels
        .par_iter()
        .map(|&level| {
            control.check()?;
            let pulse = Pulse::new(
                req.shape,
                level * unit,
                req.omega_ratio * req.block.frequency_parameter(),
            )
            .map_err(|_| ScanError::Simulation(SimError::Tolerance))?;
            let mut opts = Options::history(req.solver);
            opts.record_impacts = false;
            let r: Response = match req.vertical {
                None => simulate(
                    &Problem {
                        block: req.block,
                        pulse,
                        formulation: req.formulation,
                    },
                    &opts,
                )?,
                Some(vertical) => simulate(
                    &Problem {
                        block: req.block,
                        pulse: vertical.pair(pulse)?,
                        formulation: req.formulation,
                    },
                    &opts,
                )?,
            };
            control.add_done(1);
            // A block that never rocks needs at most its at-rest demand, which
            // the tracker always reports; the fallback is never taken.
            let f = r
                .friction
                .unwrap_or(crate::dynamics::response::FrictionDemand {
                    peak: Some(0.0),
                    peak_time: Some(0.0),
                    initiation: None,
                    first_sliding: None,
                    first_lift_off: None,
                    followed_until: None,
                });
            let stats = ScanStats {
                simulations: 1,
                steps: r.numerics.steps_accepted,
                rejected: r.numerics.steps_rejected,
                rhs_evaluations: r.numerics.rhs_evaluations,
                events: r.numerics.events,
                max_error_estimate: r.numerics.error_estimate,
                probes: 0,
                undecided: u64::from(r.reached_limit()),
            };
            // The ground falling away faster than gravity lifts the block
            // off as surely as f_z → 0⁺ while rocking: no demand is finite.
            let lift_off = match (f.first_lift_off, r.lift_off) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            Ok((
                FrictionPoint {
                    level,
                    peak_demand: f.peak.filter(|_| r.lift_off.is_none()),
                    initiation_demand: f.initiation,
                    overturned: r.overturned,
                    mode: r.mode.map(|m| m.number()),
                    lift_off,
                    followed_until: f.followed_until.filter(|_| r.overturned),
                },
                stats,
            ))
        })
        .collect();
    let mut points = Vec::with_capacity(results.len());
    let mut stats = ScanStats::default();
    for r in results {
        let (p, s) = r?;
        points.push(p);
        stats.absorb(&s);
    }
    Ok(FrictionSpectrum {
        points,
        stats,
        wall_time: started.elapsed().as_secs_f64(),
    })
}
