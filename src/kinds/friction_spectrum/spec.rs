//! A friction spectrum job's spec as users write it,
//! the validated job, and the validation from one to the other.

use crate::dynamics::Formulation;
use crate::jobs::names::tag;
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, OMEGA_RATIO_RANGE, PulseSpec, SolverNorm, SolverSpec, SpecError,
    in_one_unit, parse_formulation,
};
use crate::kinds::spectrum::{PulseFamily, validate_family};
use serde::{Deserialize, Serialize};
/// Most amplitudes in one friction spectrum.
pub const MAX_AMPLITUDES: usize = 100_000;

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = FrictionSpectrumSpec)]
pub struct FrictionSpec {
    /// "friction_spectrum".
    #[schema(value_type = crate::jobs::names::tag::FrictionSpectrum)]
    pub kind: String,
    /// The block.
    #[schema(required = true, value_type = BlockSpec)]
    pub block: Option<BlockSpec>,
    /// The pulse family (`type`, `n`).
    #[schema(required = true, value_type = crate::jobs::schema::PulseFamilyInput)]
    pub pulse: Option<PulseSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// ω_p/p (one value, 1e-3 to 1e4; or give `omega_p` or `frequency_hz`).
    #[schema(minimum = 1e-3, maximum = 1e4)]
    pub omega_ratio: Option<f64>,
    /// ω_p, rad/s.
    #[schema(exclusive_minimum = 0.0)]
    pub omega_p: Option<f64>,
    /// f_p = ω_p/2π, Hz.
    #[schema(exclusive_minimum = 0.0)]
    pub frequency_hz: Option<f64>,
    /// Amplitudes a_p/(αg) (or give `a_p` or `a_p_g`).
    pub a_alpha_g: Option<RangeSpec>,
    /// Amplitudes, m/s².
    pub a_p: Option<RangeSpec>,
    /// Amplitudes, g.
    pub a_p_g: Option<RangeSpec>,
    /// Solver.
    pub solver: Option<SolverSpec>,
    /// The vertical ground acceleration (positive up), scaled with each
    /// pulse: `{"ratio": r}` (ü_v = r·ü_g), or a pulse of its own (`type`,
    /// `amplitude_ratio` a_v/a_p, `frequency_ratio` ω_v/ω_p or an absolute
    /// `omega_p`/`frequency_hz`, optional `delay_s`).
    pub vertical: Option<crate::jobs::vertical::VerticalPulseSpec>,
}

/// A validated friction-spectrum job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[schema(as = FrictionSpectrumJob)]
pub struct FrictionJob {
    /// "friction_spectrum".
    pub kind: tag::FrictionSpectrum,
    /// Block.
    pub block: BlockNorm,
    /// Pulse family.
    pub pulse: PulseFamily,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// Amplitudes, αg.
    pub a_alpha_g: Vec<f64>,
    /// Solver.
    pub solver: SolverNorm,
    /// The vertical motion (positive up), when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::vertical::VerticalPulseDoc>)]
    pub vertical: Option<crate::jobs::vertical::VerticalPulseNorm>,
}

impl crate::jobs::kind::Validate for FrictionSpec {
    type Job = FrictionJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<FrictionJob, SpecError> {
        let block = crate::jobs::spec::the_block(self.block.as_ref())?;
        let pulse = validate_family(self.pulse.as_ref(), "/pulse")?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let vertical =
            crate::jobs::vertical::validate_scaled_vertical(self.vertical.as_ref(), "/vertical")?;
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            pulse.shape().is_sinusoidal(),
            vertical.is_some(),
            "/solver",
        )?;
        // The frequency and the amplitudes in any unit, normalised to ω_p/p and αg.
        let p = block.p;
        let unit_g = block.alpha * block.g;
        let (value, name, to_ratio) = in_one_unit(
            &[
                (self.omega_ratio, "omega_ratio", 1.0),
                (self.omega_p, "omega_p", 1.0 / p),
                (self.frequency_hz, "frequency_hz", std::f64::consts::TAU / p),
            ],
            "frequency",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/omega_ratio",
                "missing field: one frequency as omega_ratio (ω_p/p), omega_p (rad/s) or frequency_hz",
            )
        })?;
        let omega_ratio = value * to_ratio;
        if !(omega_ratio.is_finite()
            && (OMEGA_RATIO_RANGE.0..=OMEGA_RATIO_RANGE.1).contains(&omega_ratio))
        {
            return Err(SpecError::at(
                format!("/{name}"),
                format!(
                    "must give ω_p/p in [{}, {}] for this block (p = {p} rad/s; got ω_p/p = {omega_ratio})",
                    OMEGA_RATIO_RANGE.0, OMEGA_RATIO_RANGE.1
                ),
            ));
        }
        let (range, name, to_alpha_g) = in_one_unit(
            &[
                (self.a_alpha_g.as_ref(), "a_alpha_g", 1.0),
                (self.a_p.as_ref(), "a_p", 1.0 / unit_g),
                (self.a_p_g.as_ref(), "a_p_g", block.g / unit_g),
            ],
            "amplitude axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/a_alpha_g",
                "missing field: the amplitudes as a_alpha_g (αg), a_p (m/s²) or a_p_g: {\"from\", \"to\", \"steps\"} or a list",
            )
        })?;
        let pointer = format!("/{name}");
        let a_alpha_g: Vec<f64> = range
            .values(&pointer, 0.0, f64::MAX, MAX_AMPLITUDES)?
            .into_iter()
            .map(|a| a * to_alpha_g)
            .collect();
        if let Some(bad) = a_alpha_g.iter().find(|a| !(1e-6..=1e6).contains(*a)) {
            return Err(SpecError::at(
                pointer,
                format!("every amplitude must give a_p/(αg) in [1e-6, 1e6]; one gives {bad}"),
            ));
        }
        Ok(FrictionJob {
            kind: tag::FrictionSpectrum,
            block,
            pulse,
            formulation,
            omega_ratio,
            a_alpha_g,
            solver,
            vertical,
        })
    }
}
