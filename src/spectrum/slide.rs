//! The residual-slide spectrum: on a Coulomb floor, where the block ends up
//! (and how far it slipped on the way) at each amplitude of each frequency
//! of a pulse spectrum, on a uniform grid of amplitudes.

use rayon::prelude::*;

use crate::dynamics::floor::run_coulomb;
use crate::dynamics::sliding::Friction;
use crate::dynamics::{Options, Problem};

use super::control::Control;
use super::scan::{Scalable, ScanError, ScanStats};

/// What became of the block at one amplitude.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fate {
    /// At rest (or still moving at the end of what was followed).
    Stands,
    /// Overturned.
    Overturns,
}

/// One amplitude of a residual-slide line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlidePoint {
    /// Amplitude, in the scan's levels (α g).
    pub level: f64,
    /// The base's slip on the floor at the end (rest, overturning or
    /// lift-off), m, + towards +x.
    pub residual: f64,
    /// max |slip|, m.
    pub peak: f64,
    /// What became of it.
    pub fate: Fate,
}

/// The residual slide of every problem's block (its ground motion scaled to
/// each of `levels`) on a floor with `friction`, in parallel over lines and
/// levels; one line per problem, in order.
pub fn residual_slide<G: Scalable + Sync>(
    problems: &[Problem<G>],
    options: &Options,
    friction: Friction,
    levels: &[f64],
    control: &Control,
) -> Result<(Vec<Vec<SlidePoint>>, ScanStats), ScanError> {
    control.add_total((problems.len() * levels.len()) as u64);
    let points: Vec<Result<(SlidePoint, ScanStats), ScanError>> = problems
        .par_iter()
        .flat_map_iter(|problem| levels.iter().map(move |&level| (problem, level)))
        .map(|(problem, level)| {
            control.check()?;
            let block = problem.block;
            let scaled = Problem {
                block,
                pulse: problem.pulse.at_level(level, &block),
                formulation: problem.formulation,
            };
            let h = run_coulomb(&scaled, options, friction)
                .map_err(|source| ScanError::At { level, source })?;
            control.add_done(1);
            let c = &h.contact;
            let fate = if c.overturned {
                Fate::Overturns
            } else {
                Fate::Stands
            };
            let n = &h.response.numerics;
            let stats = ScanStats {
                simulations: 1,
                steps: n.steps_accepted,
                rejected: n.steps_rejected,
                rhs_evaluations: n.rhs_evaluations,
                events: n.events,
                max_error_estimate: n.error_estimate,
                probes: 0,
                undecided: u64::from(matches!(
                    c.cut,
                    Some(crate::dynamics::coulomb::Cut::Limit(_))
                )),
            };
            Ok((
                SlidePoint {
                    level,
                    residual: c.residual_slide,
                    peak: c.peak_slide,
                    fate,
                },
                stats,
            ))
        })
        .collect();
    let mut stats = ScanStats::default();
    let mut lines = Vec::with_capacity(problems.len());
    let mut points = points.into_iter();
    for _ in problems {
        let mut line = Vec::with_capacity(levels.len());
        for _ in levels {
            let (p, s) = points
                .next()
                .ok_or(ScanError::Simulation(crate::dynamics::SimError::Tolerance))??;
            stats.absorb(&s);
            line.push(p);
        }
        lines.push(line);
    }
    Ok((lines, stats))
}
