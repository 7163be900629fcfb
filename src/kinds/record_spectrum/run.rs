//! How a record spectrum job is computed.

use super::result::{
    RecordDoc, RecordSpectrumNumerics, RecordSpectrumResult, ScaleModeChangeDoc, ScalePrincipalDoc,
    ScaleTransitionDoc, SizeDoc,
};
use super::spec::{RecordSpectrumJob, size_of_p, threshold_of};
use crate::dynamics::block::BlockError;
use crate::dynamics::{Block, SimError, peaks};
use crate::jobs::error::JobError;
use crate::jobs::mixed::{MixedDoc, minimum_place};
use crate::jobs::names::tag;
use crate::jobs::vertical::ScaledVertical;
use crate::kinds::spectrum::ScanCost;
use crate::kinds::time_history::GroundPeaksDoc;
use crate::records::pga;
use crate::spectrum::Control;
use crate::spectrum::overturning::{Derived, LineScan, ScanGrid};
use crate::spectrum::record::{RecordSpectrumRequest, record_spectrum};
use crate::spectrum::scan::ScanStats;
use crate::spectrum::scan::{Direction, ModeChange, ScanError, Transition};
/// Levels (αg over the record's PGA) read as scale factors and as the scaled
/// record's PGA, g.
#[derive(Clone, Copy)]
pub(super) struct ToScale {
    /// The scale factor of a level of 1 (αg/PGA).
    unit: f64,
    /// The record's PGA, m/s².
    peak: f64,
    /// g, m/s².
    g: f64,
}

impl ToScale {
    /// The scale factor of `level`.
    fn scale(self, level: f64) -> f64 {
        level * self.unit
    }

    /// The PGA, g, of the record scaled to `level`.
    fn pga_g(self, level: f64) -> f64 {
        self.scale(level) * self.peak / self.g
    }

    /// A transition over the scale factor.
    fn transition(self, t: &Transition) -> ScaleTransitionDoc {
        ScaleTransitionDoc {
            scale: self.scale(t.at),
            pga_g: self.pga_g(t.at),
            direction: match t.direction {
                Direction::Up => "up",
                Direction::Down => "down",
                Direction::SlideIn => "slide_in",
                Direction::SlideOut => "slide_out",
            }
            .to_string(),
            mode: t.mode,
            impacts: t.impacts,
            bracket: [self.scale(t.bracket.0), self.scale(t.bracket.1)],
        }
    }

    /// A change of overturning mode over the scale factor.
    fn mode_change(self, m: &ModeChange) -> ScaleModeChangeDoc {
        ScaleModeChangeDoc {
            scale: self.scale(m.at),
            from_mode: m.from,
            to_mode: m.to,
            bracket: [self.scale(m.bracket.0), self.scale(m.bracket.1)],
        }
    }

    /// The safe intervals of `d` as scale factors.
    fn intervals(self, d: &Derived) -> Vec<[f64; 2]> {
        d.safe_intervals
            .iter()
            .map(|&(a, b)| [self.scale(a), self.scale(b)])
            .collect()
    }
}

impl RecordSpectrumJob {
    /// The block at frequency parameter `p` (an error for values no
    /// validated spec holds).
    pub fn block_at(&self, p: f64) -> Result<Block, BlockError> {
        Block::new(
            self.block.alpha,
            p,
            Some(self.block.eta),
            None,
            Some(self.block.g),
        )
    }

    /// The rocking threshold of every block size, αg (lowered where the
    /// vertical motion lightens the block).
    pub fn threshold_alpha_g(&self) -> f64 {
        threshold_of(
            self.formulation,
            self.block.alpha,
            self.block.g,
            &self.ground_motion,
            self.vertical.as_ref(),
        )
    }

    /// ü_v/ü_g, when the job has a vertical motion given as a ratio.
    pub fn vertical_ratio(&self) -> Option<f64> {
        self.vertical.as_ref().and_then(|v| v.ratio())
    }

    /// Coulomb friction at the floor, when the job has it.
    pub fn friction(&self) -> Option<crate::dynamics::sliding::Friction> {
        self.contact.as_ref().map(|c| c.friction())
    }

    /// The vertical motion scaled with the record, when the job has one.
    pub fn scaled_vertical(&self) -> Option<ScaledVertical<'_>> {
        ScaledVertical::of(self.vertical.as_ref(), Some(&self.ground_motion))
    }

    /// Under a vertical motion: the level (scaled PGA in α g) from which the
    /// ground falls away faster than gravity (g + ü_v ≤ 0), bracketed; `None`
    /// when it does not up to `scale.to` (or without a vertical motion).
    pub fn lift_off_level(&self) -> Option<(f64, f64)> {
        // On a Coulomb floor the block's flights are followed.
        if self.contact.is_some() {
            return None;
        }
        let block = self.block_at(1.0).ok()?;
        self.scaled_vertical()?.record_lift_off(
            &self.record().ok()?,
            &block,
            self.scale.to / self.unit_scale(),
        )
    }

    /// s_α = αg/PGA: the scale factor of one level (scaled PGA of α g).
    pub fn unit_scale(&self) -> f64 {
        self.block.alpha * self.block.g / pga(&self.ground_motion.acc)
    }

    /// The scan grid in levels (scaled PGA in α g).
    pub fn grid(&self) -> ScanGrid {
        let unit = self.unit_scale();
        let threshold = self.threshold_alpha_g();
        ScanGrid {
            // From the threshold whatever `scale.from` is: a line that already
            // overturns at `from` would otherwise lose where overturning begins.
            from: threshold,
            // Under a vertical motion, up to just below the lift-off.
            to: self
                .lift_off_level()
                .map_or(self.scale.to / unit, |(lo, _)| lo.max(threshold)),
            step: self.scan_step / unit,
            tolerance: self.tolerance / unit,
            principal_relative_width: self.principal_relative_width,
        }
    }

    /// Scan points of one block size.
    pub fn points_per_size(&self) -> f64 {
        let grid = self.grid();
        ((grid.to - grid.from) / grid.step).ceil().max(0.0) + 1.0
    }

    /// The record as the engine takes it.
    pub fn record(&self) -> Result<crate::dynamics::Record, ScanError> {
        self.ground_motion
            .record()
            .map_err(|_| ScanError::Simulation(crate::dynamics::SimError::Tolerance))
    }

    /// The problems of the blocks of frequency parameters `ps` under the
    /// record (scaled per level by the scan).
    pub fn problems(
        &self,
        ps: &[f64],
    ) -> Result<Vec<crate::dynamics::Problem<crate::dynamics::Record>>, ScanError> {
        let record = self.record()?;
        ps.iter()
            .map(|&p| {
                Ok(crate::dynamics::Problem {
                    block: self.block_at(p).map_err(SimError::from)?,
                    pulse: record.clone(),
                    formulation: self.formulation,
                })
            })
            .collect()
    }

    /// The lines of the sizes `ps`: their problems under the record alone,
    /// or under it and its vertical motion.
    pub fn lines(&self, ps: &[f64]) -> Result<Lines, ScanError> {
        let problems = self.problems(ps)?;
        let Some(v) = self.scaled_vertical() else {
            return Ok(Lines::Plain(problems));
        };
        let pairs = problems
            .into_iter()
            .map(|q| {
                Ok(crate::dynamics::Problem {
                    block: q.block,
                    pulse: v.record_pair(q.pulse)?,
                    formulation: q.formulation,
                })
            })
            .collect::<Result<Vec<_>, ScanError>>()?;
        Ok(Lines::Paired(pairs))
    }

    /// Solver and floor of every simulation of the scan.
    pub fn model(&self) -> crate::spectrum::scan::Model {
        crate::spectrum::scan::Model {
            solver: self.solver.solver(),
            friction: self.friction(),
            slide_band: None,
        }
    }

    /// Runs the whole job under `control` (whatever its `part`).
    pub fn run(&self, control: &Control) -> Result<RecordSpectrumResult, ScanError> {
        let req = RecordSpectrumRequest {
            record: self.record()?,
            block: self.block_at(1.0).map_err(SimError::from)?,
            ps: self.p.clone(),
            formulation: self.formulation,
            solver: self.solver.solver(),
            friction: self.friction(),
            grid: self.grid(),
        };
        let s = match self.scaled_vertical() {
            None => record_spectrum(&req, control)?,
            Some(v) => {
                let pair = v.record_pair(req.record.clone())?;
                record_spectrum(
                    &RecordSpectrumRequest {
                        record: pair,
                        block: req.block,
                        ps: req.ps.clone(),
                        formulation: req.formulation,
                        solver: req.solver,
                        friction: req.friction,
                        grid: req.grid,
                    },
                    control,
                )?
            }
        };
        self.result(&s.lines, &s.stats, s.wall_time, None)
    }

    /// The whole job's result from its tasks' parts (in any order).
    pub fn result_of(
        &self,
        parts: &[crate::jobs::scan_parts::PartDoc],
    ) -> Result<RecordSpectrumResult, JobError> {
        let (found, stats, wall) = super::part::assemble(self, parts)?;
        let grid = self.grid();
        let lines: Vec<LineScan> = found.into_iter().map(|f| grid.line(f)).collect();
        self.result(&lines, &stats, wall, Some(parts.len()))
            .map_err(|e| JobError::Task(e.to_string()))
    }

    /// The result document of the lines found.
    fn result(
        &self,
        lines: &[LineScan],
        stats: &ScanStats,
        wall_time: f64,
        tasks: Option<usize>,
    ) -> Result<RecordSpectrumResult, ScanError> {
        let record = self.record()?;
        let unit = self.unit_scale();
        let g = self.block.g;
        let peak = pga(&self.ground_motion.acc);
        let threshold = self.threshold_alpha_g();
        let to = ToScale { unit, peak, g };
        let spectrum = self
            .p
            .iter()
            .zip(lines)
            .map(|(&p, l): (&f64, &LineScan)| self.size_doc(p, l, to, threshold))
            .collect();
        let n = self.ground_motion.acc.len();
        Ok(RecordSpectrumResult {
            kind: tag::RecordSpectrum,
            record: RecordDoc {
                peaks: GroundPeaksDoc::new(&peaks::of_record(&record), g),
                dt_s: self.ground_motion.dt,
                samples: n,
                duration_s: (n - 1) as f64 * self.ground_motion.dt,
            },
            spectrum,
            lift_off_above_scale: self.lift_off_level().map(|(_, hi)| to.scale(hi)),
            numerics: RecordSpectrumNumerics {
                cost: ScanCost::new(&self.solver, stats),
                tolerance: self.tolerance,
                scan_step: self.scan_step,
                wall_time_s: wall_time,
                tasks,
            },
            spec: self.clone(),
            warnings: Vec::new(),
            engine: None,
        })
    }

    /// The document of the block size `p` from its line `l` (levels read as
    /// scales by `to`; the rocking threshold `threshold`, αg).
    fn size_doc(&self, p: f64, l: &LineScan, to: ToScale, threshold: f64) -> SizeDoc {
        let g = self.block.g;
        SizeDoc {
            p,
            r_m: size_of_p(p, g),
            threshold_scale: to.scale(threshold),
            transitions: l.transitions.iter().map(|t| to.transition(t)).collect(),
            mode_changes: l.mode_changes.iter().map(|m| to.mode_change(m)).collect(),
            min_overturn_scale: l.derived.min_overturn.map(|a| to.scale(a)),
            min_overturn_pga_g: l.derived.min_overturn.map(|a| to.pga_g(a)),
            min_overturn_mode: l.derived.min_overturn_mode,
            safe_intervals: to.intervals(&l.derived),
            overturns_above_scale: l.derived.overturns_above.map(|a| to.scale(a)),
            principal: ScalePrincipalDoc {
                transitions: l
                    .principal_transitions
                    .iter()
                    .map(|t| to.transition(t))
                    .collect(),
                min_overturn_scale: l.principal.min_overturn.map(|a| to.scale(a)),
                min_overturn_mode: l.principal.min_overturn_mode,
                safe_intervals: to.intervals(&l.principal),
                overturns_above_scale: l.principal.overturns_above.map(|a| to.scale(a)),
            },
            lift_off_above_scale: self.lift_off_level().map(|(_, hi)| to.scale(hi)),
            mixed: l
                .mixed
                .iter()
                .map(|z| MixedDoc::overturning(z, to.unit))
                .collect(),
            min_overturn_in: minimum_place(&l.derived, to.unit).0,
            min_overturn_zone: minimum_place(&l.derived, to.unit).1,
            min_certain_overturn_scale: l.derived.min_certain_overturn.map(|a| to.scale(a)),
            min_certain_overturn_pga_g: l.derived.min_certain_overturn.map(|a| to.pga_g(a)),
        }
    }
}

/// The lines of a record spectrum's sizes ([`RecordSpectrumJob::lines`]).
pub enum Lines {
    /// Under the horizontal record.
    Plain(Vec<crate::dynamics::Problem<crate::dynamics::Record>>),
    /// Under the horizontal record and its vertical motion.
    Paired(Vec<crate::dynamics::Problem<crate::dynamics::RecordPair>>),
}
