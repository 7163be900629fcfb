//! Rocking spectra of a recorded motion (Makris & Konstantinidis 2003): for
//! each block size p (same α, η), the overturning set over the record's scale
//! factor, with the scan and bisection guarantees of the pulse spectra
//! ([`scan`](super::scan)). Levels are the scaled record's PGA in α g, so a
//! record's spectrum and a pulse's are scanned on the same grid.

use std::time::Instant;

use crate::dynamics::block::BlockError;
use crate::dynamics::{Block, Formulation, Problem, Record, SimError, Solver};

use super::scan::Scalable;

use super::control::Control;
use super::overturning::{LineScan, ScanGrid, scan_lines};
use super::scan::{Model, ScanError, ScanStats};
use crate::dynamics::sliding::Friction;

/// What to compute.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordSpectrumRequest<G = Record> {
    /// The record, as given (the scan scales it): a [`Record`], or a
    /// [`RecordPair`](crate::dynamics::RecordPair) with its vertical.
    pub record: G,
    /// The block; its frequency parameter is replaced by each of `ps`.
    pub block: Block,
    /// Block frequency parameters p, rad/s.
    pub ps: Vec<f64>,
    /// Equation of motion.
    pub formulation: Formulation,
    /// Solver.
    pub solver: Solver,
    /// Coulomb friction at the floor; `None`: pure rocking.
    pub friction: Option<Friction>,
    /// Levels examined: the scaled record's PGA in α g.
    pub grid: ScanGrid,
}

/// A record's spectrum: one line per p, in request order.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordSpectrum {
    /// The overturning set of each p, in levels (PGA in α g).
    pub lines: Vec<LineScan>,
    /// Cost.
    pub stats: ScanStats,
    /// Wall time, s.
    pub wall_time: f64,
}

/// Computes the spectrum, in parallel over block sizes and chunks of levels.
pub fn record_spectrum<G: Scalable + Sync + Clone>(
    req: &RecordSpectrumRequest<G>,
    control: &Control,
) -> Result<RecordSpectrum, ScanError> {
    let started = Instant::now();
    let problems: Vec<Problem<G>> = req
        .ps
        .iter()
        .map(|&p| {
            Ok(Problem {
                block: req.block.with_frequency_parameter(p)?,
                pulse: req.record.clone(),
                formulation: req.formulation,
            })
        })
        .collect::<Result<_, BlockError>>()
        .map_err(SimError::from)?;
    let (lines, stats) = scan_lines(
        &problems,
        Model {
            solver: req.solver,
            friction: req.friction,
            slide_band: None,
        },
        &req.grid,
        control,
    )?;
    Ok(RecordSpectrum {
        lines,
        stats,
        wall_time: started.elapsed().as_secs_f64(),
    })
}
