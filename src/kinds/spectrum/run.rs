//! How a spectrum job is computed.

use super::result::{
    FrequencyDoc, ModeChangeDoc, PrincipalDoc, PulseScalesDoc, SlidePointDoc, SpectrumNumerics,
    SpectrumResult, TransitionDoc,
};
use super::spec::SpectrumJob;
use crate::dynamics::SimError;
use crate::jobs::names::tag;
use crate::spectrum::overturning::Derived;
use crate::spectrum::scan::ScanStats;
use crate::spectrum::{Control, SpectrumRequest, overturning_spectrum};
pub(super) fn intervals(d: &Derived) -> Vec<[f64; 2]> {
    d.safe_intervals.iter().map(|&(a, b)| [a, b]).collect()
}

impl SpectrumJob {
    /// ü_v/ü_g, when the job has a vertical motion.
    pub fn vertical_ratio(&self) -> Option<f64> {
        self.vertical.as_ref().and_then(|v| v.ratio())
    }

    /// The residual-slide lines, one per frequency, when asked for (on a
    /// Coulomb floor), and what they cost.
    #[allow(clippy::type_complexity)]
    fn residual_slides(
        &self,
        req: &SpectrumRequest,
        control: &Control,
    ) -> Result<Option<(Vec<Vec<SlidePointDoc>>, ScanStats)>, crate::spectrum::scan::ScanError>
    {
        use crate::dynamics::{Options, Problem, PulsePair};
        use crate::spectrum::scan::ScanError;
        use crate::spectrum::slide::{Fate, SlidePoint, residual_slide};
        let (Some(steps), Some(friction)) = (self.residual_slide_steps, req.friction) else {
            return Ok(None);
        };
        let levels: Vec<f64> = (1..=steps)
            .map(|k| req.a_max * f64::from(k) / f64::from(steps))
            .collect();
        let bad = || ScanError::Simulation(SimError::Tolerance);
        let pulses = crate::spectrum::overturning::line_pulses(req)?;
        fn on<G>(req: &SpectrumRequest, pulse: G) -> Problem<G> {
            Problem {
                block: req.block,
                pulse,
                formulation: req.formulation,
            }
        }
        let options = Options::outcome(req.solver);
        let own = self.vertical.as_ref().and_then(|v| v.scaled_pulse());
        let (lines, stats) = match (own, req.vertical_ratio) {
            (Some(v), _) => {
                let pairs = pulses
                    .into_iter()
                    .map(|p| v.pair(p).map(|q| on(req, q)))
                    .collect::<Result<Vec<_>, ScanError>>()?;
                residual_slide(&pairs, &options, friction, &levels, control)?
            }
            (None, Some(r)) => {
                let pairs = pulses
                    .into_iter()
                    .map(|p| {
                        PulsePair::proportional(p, r)
                            .map(|q| on(req, q))
                            .ok_or_else(bad)
                    })
                    .collect::<Result<Vec<_>, ScanError>>()?;
                residual_slide(&pairs, &options, friction, &levels, control)?
            }
            (None, None) => {
                let problems: Vec<_> = pulses.into_iter().map(|q| on(req, q)).collect();
                residual_slide(&problems, &options, friction, &levels, control)?
            }
        };
        let doc = |p: &SlidePoint| SlidePointDoc {
            a_alpha_g: p.level,
            residual_slide_m: p.residual,
            peak_slide_m: p.peak,
            outcome: match p.fate {
                Fate::Stands => "stands",
                Fate::Overturns => "overturns",
            }
            .to_string(),
        };
        Ok(Some((
            lines.iter().map(|l| l.iter().map(doc).collect()).collect(),
            stats,
        )))
    }

    /// The same job on a floor the block cannot slide on: what the same
    /// spec without `contact` validates to. `Some` when the spectrum beside
    /// this one is asked for.
    pub fn pure_rocking(&self) -> Option<SpectrumJob> {
        (self.no_sliding_beside && self.contact.is_some()).then(|| SpectrumJob {
            contact: None,
            residual_slide_steps: None,
            no_sliding_beside: false,
            ..self.clone()
        })
    }

    /// Runs the job under `control`: its lines, and with
    /// `no_sliding_beside` the lines of [`SpectrumJob::pure_rocking`] by the
    /// same path, their costs summed.
    pub fn run(
        &self,
        control: &Control,
    ) -> Result<SpectrumResult, crate::spectrum::scan::ScanError> {
        let (spectrum, mut stats, mut wall_time) = self.lines(control)?;
        let no_sliding = match self.pure_rocking() {
            Some(pure) => {
                let (lines, pure_stats, pure_wall) = pure.lines(control)?;
                stats.absorb(&pure_stats);
                wall_time += pure_wall;
                lines
            }
            None => Vec::new(),
        };
        Ok(SpectrumResult {
            warnings: Vec::new(),
            kind: tag::Spectrum,
            spectrum,
            no_sliding,
            numerics: SpectrumNumerics::new(
                &self.solver,
                &stats,
                self.tolerance,
                self.scan_step_alpha_g,
                wall_time,
            ),
            spec: self.clone(),
            engine: None,
        })
    }

    /// The lines of the job's spectrum (with their residual slides when
    /// asked for), what they cost and the scan's wall time, s.
    fn lines(
        &self,
        control: &Control,
    ) -> Result<(Vec<FrequencyDoc>, ScanStats, f64), crate::spectrum::scan::ScanError> {
        let formulation = self.formulation;
        let block = self.block.block().map_err(SimError::from)?;
        let req = SpectrumRequest {
            block,
            shape: self.pulse.shape(),
            formulation,
            solver: self.solver.solver(),
            omega_ratios: self.omega_ratio.clone(),
            a_max: self.a_max_alpha_g,
            tolerance: self.tolerance,
            scan_step: self.scan_step_alpha_g,
            principal_relative_width: self.principal_relative_width,
            vertical_ratio: self.vertical_ratio(),
            friction: self.contact.as_ref().map(|c| c.friction()),
        };
        let s = match self.vertical.as_ref().and_then(|v| v.scaled_pulse()) {
            Some(v) => crate::spectrum::overturning::overturning_spectrum_under(&req, &v, control)?,
            None => overturning_spectrum(&req, control)?,
        };
        let alpha = self.block.alpha;
        let mut stats = s.stats;
        let mut slides = match self.residual_slides(&req, control)? {
            Some((lines, slide_stats)) => {
                stats.absorb(&slide_stats);
                Some(lines.into_iter())
            }
            None => None,
        };
        let spectrum = s
            .lines
            .iter()
            .map(|l| FrequencyDoc {
                residual_slide: slides.as_mut().and_then(|lines| lines.next()),
                omega_ratio: l.omega_ratio,
                threshold_alpha_g: l.threshold,
                threshold_g: l.threshold * alpha,
                transitions: l
                    .transitions
                    .iter()
                    .map(|t| TransitionDoc::new(t, alpha))
                    .collect(),
                mode_changes: l.mode_changes.iter().map(ModeChangeDoc::from).collect(),
                min_overturn_alpha_g: l.derived.min_overturn,
                min_overturn_mode: l.derived.min_overturn_mode,
                safe_intervals: intervals(&l.derived),
                overturns_above_alpha_g: l.derived.overturns_above,
                principal: PrincipalDoc {
                    transitions: l
                        .principal_transitions
                        .iter()
                        .map(|t| TransitionDoc::new(t, alpha))
                        .collect(),
                    min_overturn_alpha_g: l.principal.min_overturn,
                    min_overturn_mode: l.principal.min_overturn_mode,
                    safe_intervals: intervals(&l.principal),
                    overturns_above_alpha_g: l.principal.overturns_above,
                },
                mixed: l
                    .mixed
                    .iter()
                    .map(|z| crate::jobs::mixed::MixedDoc::overturning(z, 1.0))
                    .collect(),
                min_overturn_in: crate::jobs::mixed::minimum_place(&l.derived, 1.0).0,
                min_overturn_zone: crate::jobs::mixed::minimum_place(&l.derived, 1.0).1,
                min_certain_overturn_alpha_g: l.derived.min_certain_overturn,
                eq21_alpha_g: l.eq21,
                closed_form_mode2_alpha_g: l.mode2_closed_form,
                lift_off_above_alpha_g: l.lift_off_above,
                omega_p: l.omega_ratio * self.block.p,
                frequency_hz: l.omega_ratio * self.block.p / std::f64::consts::TAU,
                min_overturn_g: l.derived.min_overturn.map(|a| a * self.block.alpha),
                min_overturn_m_s2: l
                    .derived
                    .min_overturn
                    .map(|a| a * self.block.alpha * self.block.g),
                ground: PulseScalesDoc::of(self.pulse.shape(), l.omega_ratio * self.block.p),
            })
            .collect();
        Ok((spectrum, stats, s.wall_time))
    }
}
