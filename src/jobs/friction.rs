//! The `friction_spectrum` job: the friction pure rocking needs (paper Fig. 9).

use serde::{Deserialize, Serialize};

use super::range::RangeSpec;
use super::spec::{
    BlockNorm, BlockSpec, OMEGA_RATIO_RANGE, PulseSpec, SolverNorm, SolverSpec, SpecError,
    parse_formulation, validate_block, validate_solver,
};
use super::spectrum::{PulseFamily, SpectrumNumerics, validate_family};
use crate::dynamics::Formulation;
use crate::spectrum::Control;
use crate::spectrum::friction::{FrictionRequest, friction_spectrum};
use crate::spectrum::scan::ScanError;

/// Most amplitudes in one friction spectrum.
pub const MAX_AMPLITUDES: usize = 100_000;

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FrictionSpec {
    /// "friction_spectrum".
    #[schema(pattern = "^friction_spectrum$")]
    pub kind: String,
    /// The block.
    #[schema(required = true, value_type = BlockSpec)]
    pub block: Option<BlockSpec>,
    /// The pulse family.
    pub pulse: Option<PulseSpec>,
    /// "linear" | "nonlinear" (default).
    pub formulation: Option<String>,
    /// ω_p/p (one value).
    pub omega_ratio: Option<f64>,
    /// Amplitudes a_p/(αg).
    pub a_alpha_g: Option<RangeSpec>,
    /// Solver.
    pub solver: Option<SolverSpec>,
}

/// A validated friction-spectrum job.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FrictionJob {
    /// "friction_spectrum".
    pub kind: &'static str,
    /// Block.
    pub block: BlockNorm,
    /// Pulse family.
    pub pulse: PulseFamily,
    /// "linear" | "nonlinear".
    pub formulation: &'static str,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// Amplitudes, αg.
    pub a_alpha_g: Vec<f64>,
    /// Solver.
    pub solver: SolverNorm,
}

impl FrictionSpec {
    /// Validates into a runnable job.
    pub fn validate(&self) -> Result<FrictionJob, SpecError> {
        let block_spec = self
            .block
            .as_ref()
            .ok_or_else(|| SpecError::at("/block", "missing field"))?;
        let block = validate_block(block_spec, "/block")?;
        let pulse = validate_family(self.pulse.as_ref(), "/pulse")?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let solver = validate_solver(self.solver.as_ref(), formulation, "/solver")?;
        let omega_ratio = self
            .omega_ratio
            .ok_or_else(|| SpecError::at("/omega_ratio", "missing field (one value of ω_p/p)"))?;
        if !(omega_ratio.is_finite()
            && (OMEGA_RATIO_RANGE.0..=OMEGA_RATIO_RANGE.1).contains(&omega_ratio))
        {
            return Err(SpecError::at(
                "/omega_ratio",
                format!(
                    "must lie in [{}, {}] (got {omega_ratio})",
                    OMEGA_RATIO_RANGE.0, OMEGA_RATIO_RANGE.1
                ),
            ));
        }
        let a_alpha_g = self
            .a_alpha_g
            .as_ref()
            .ok_or_else(|| {
                SpecError::at(
                    "/a_alpha_g",
                    "missing field: {\"from\", \"to\", \"steps\"} or a list",
                )
            })?
            .values("/a_alpha_g", 1e-6, 1e6, MAX_AMPLITUDES)?;
        Ok(FrictionJob {
            kind: "friction_spectrum",
            block,
            pulse,
            formulation: formulation.name(),
            omega_ratio,
            a_alpha_g,
            solver,
        })
    }
}

/// One amplitude of a friction spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FrictionPointDoc {
    /// a_p/(αg).
    pub a_alpha_g: f64,
    /// max |f_x/f_z| over the rocking history: the minimum μ for pure rocking.
    pub peak_friction_demand: f64,
    /// The same over tan α (the axis of Fig. 9).
    pub peak_over_tan_alpha: f64,
    /// f_x/f_z when rocking starts (eq. 7; eq. 51 for one-cosine).
    pub initiation_friction_demand: Option<f64>,
    /// Whether the block overturned.
    pub overturned: bool,
    /// Overturning mode.
    pub mode: Option<u8>,
    /// First time f_z ≤ 0, s.
    pub lift_off_time: Option<f64>,
}

/// The result document of a friction-spectrum job.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FrictionResult {
    /// "friction_spectrum".
    pub kind: &'static str,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// One entry per amplitude.
    pub points: Vec<FrictionPointDoc>,
    /// Cost and accuracy.
    pub numerics: SpectrumNumerics,
    /// The normalised spec.
    pub spec: FrictionJob,
}

impl FrictionJob {
    /// Runs the job under `control`.
    pub fn run(&self, control: &Control) -> Result<FrictionResult, ScanError> {
        let block = self.block.block();
        let req = FrictionRequest {
            block,
            shape: self.pulse.shape(),
            formulation: if self.formulation == "linear" {
                Formulation::Linear
            } else {
                Formulation::Nonlinear
            },
            solver: self.solver.solver(),
            omega_ratio: self.omega_ratio,
            levels: self.a_alpha_g.clone(),
        };
        let s = friction_spectrum(&req, control)?;
        let tan = block.slenderness.tan();
        Ok(FrictionResult {
            kind: "friction_spectrum",
            omega_ratio: self.omega_ratio,
            points: s
                .points
                .iter()
                .map(|p| FrictionPointDoc {
                    a_alpha_g: p.level,
                    peak_friction_demand: p.peak_demand,
                    peak_over_tan_alpha: p.peak_demand / tan,
                    initiation_friction_demand: p.initiation_demand,
                    overturned: p.overturned,
                    mode: p.mode,
                    lift_off_time: p.lift_off,
                })
                .collect(),
            numerics: SpectrumNumerics::new(&self.solver, &s.stats, 0.0, 0.0, s.wall_time),
            spec: self.clone(),
        })
    }
}
