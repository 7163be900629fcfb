//! How a friction spectrum job is computed.

use super::result::{FrictionPointDoc, FrictionResult};
use super::spec::FrictionJob;
use crate::dynamics::SimError;
use crate::jobs::names::tag;
use crate::kinds::spectrum::SpectrumNumerics;
use crate::spectrum::Control;
use crate::spectrum::friction::{FrictionRequest, friction_spectrum};
use crate::spectrum::scan::ScanError;
impl FrictionJob {
    /// Runs the job under `control`.
    pub fn run(&self, control: &Control) -> Result<FrictionResult, ScanError> {
        let block = self.block.block().map_err(SimError::from)?;
        let req = FrictionRequest {
            block,
            shape: self.pulse.shape(),
            formulation: self.formulation,
            solver: self.solver.solver(),
            omega_ratio: self.omega_ratio,
            levels: self.a_alpha_g.clone(),
            vertical: crate::jobs::vertical::ScaledVertical::of(self.vertical.as_ref(), None)
                .and_then(|v| v.of_pulses()),
        };
        let s = friction_spectrum(&req, control)?;
        let tan = block.slenderness().tan();
        Ok(FrictionResult {
            warnings: Vec::new(),
            kind: tag::FrictionSpectrum,
            omega_ratio: self.omega_ratio,
            omega_p: self.omega_ratio * self.block.p,
            frequency_hz: self.omega_ratio * self.block.p / std::f64::consts::TAU,
            points: s
                .points
                .iter()
                .map(|p| FrictionPointDoc {
                    a_alpha_g: p.level,
                    a_p_g: p.level * block.slenderness(),
                    peak_friction_demand: p.peak_demand,
                    peak_over_tan_alpha: p.peak_demand.map(|d| d / tan),
                    initiation_friction_demand: p.initiation_demand,
                    overturned: p.overturned,
                    mode: p.mode,
                    lift_off: p.lift_off.is_some(),
                    lift_off_time: p.lift_off,
                    friction_demand_followed_until: p.followed_until,
                })
                .collect(),
            numerics: SpectrumNumerics::new(&self.solver, &s.stats, 0.0, 0.0, s.wall_time),
            spec: self.clone(),
            engine: None,
        })
    }
}
