//! A time history job's spec as users write it, the validated job, and the
//! validation from one to the other.

use crate::dynamics::Formulation;
use crate::jobs::contact::{ContactNorm, ContactSpec, validate_contact};
use crate::jobs::names::tag;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, GroundMotionNorm, GroundMotionSpec, PulseNorm, PulseSpec, SolverNorm,
    SolverSpec, SpecError, parse_formulation, validate_pulse,
};
use crate::jobs::vertical::{
    VerticalPulseNorm, VerticalPulseSpec, validate_record_with_vertical, validate_vertical_pulse,
};
use serde::{Deserialize, Serialize};
/// Largest series accepted.
pub const MAX_SERIES_POINTS: usize = 1_000_000;

/// What to compute and keep beyond the outcome.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputsSpec {
    /// Number of uniformly spaced samples of (t, θ, θ̇, ü_g, f_x/f_z, and ü_v under a vertical ground motion); none by default (at most 1e6).
    #[schema(maximum = 1_000_000)]
    pub series: Option<usize>,
    /// Follow the base reactions (peak friction demand, warnings); default true.
    pub reactions: Option<bool>,
    /// List the impacts (default true; the count is always given).
    pub impacts: Option<bool>,
    /// Follow free rocking after the pulse for at most this many impacts (default 1000).
    pub max_free_impacts: Option<u64>,
    /// Stop the simulation at this time, s (free rocking only).
    #[schema(exclusive_minimum = 0.0)]
    pub duration: Option<f64>,
}

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct TimeHistorySpec {
    /// "time_history".
    #[schema(value_type = crate::jobs::names::tag::TimeHistory)]
    pub kind: String,
    /// The block.
    #[schema(required = true, value_type = BlockSpec)]
    pub block: Option<BlockSpec>,
    /// The pulse (give this or `ground_motion`).
    pub pulse: Option<PulseSpec>,
    /// With `pulse`: the vertical ground acceleration (positive up),
    /// `{"ratio": r}` (ü_v = r·ü_g) or a pulse of its own (with `delay_s`).
    /// A record takes its own in `ground_motion.vertical`.
    pub vertical: Option<VerticalPulseSpec>,
    /// A sampled ground-acceleration record (give this or `pulse`).
    pub ground_motion: Option<GroundMotionSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// Solver (default: exact for the linear formulation of a sinusoidal pulse
    /// or a record, dop853 otherwise).
    pub solver: Option<SolverSpec>,
    /// Extra outputs.
    pub outputs: Option<OutputsSpec>,
    /// The contact with the floor: `{"model": "no_sliding"}` (pure rocking,
    /// the default) or `{"model": "coulomb", "mu": μ, "mu_kinetic": μ_k}`
    /// (the block sticks, slides, rocks, slide-rocks).
    pub contact: Option<ContactSpec>,
}

/// Outputs, normalised.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct OutputsNorm {
    /// Series samples (0: none).
    pub series: usize,
    /// Follow reactions.
    pub reactions: bool,
    /// List impacts.
    pub impacts: bool,
    /// Free-rocking impact limit.
    pub max_free_impacts: u64,
    /// End time, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
}

/// A validated time-history job; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct TimeHistoryJob {
    /// "time_history".
    pub kind: tag::TimeHistory,
    /// Block.
    pub block: BlockNorm,
    /// Pulse (when the ground motion is a pulse).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulse: Option<PulseNorm>,
    /// The vertical motion beside the pulse (when there is one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::vertical::VerticalPulseDoc>)]
    pub vertical: Option<VerticalPulseNorm>,
    /// Record (when the ground motion is a record).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_motion: Option<GroundMotionNorm>,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// Solver.
    pub solver: SolverNorm,
    /// Outputs.
    pub outputs: OutputsNorm,
    /// Coulomb friction (absent: pure rocking).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactNorm>,
}

impl crate::jobs::kind::Validate for TimeHistorySpec {
    type Job = TimeHistoryJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<TimeHistoryJob, SpecError> {
        let block = crate::jobs::spec::the_block(self.block.as_ref())?;
        let (pulse, ground_motion) = match (&self.pulse, &self.ground_motion) {
            (Some(p), None) => (Some(validate_pulse(p, &block, "/pulse")?.0), None),
            (None, Some(g)) => (
                None,
                Some(validate_record_with_vertical(g, &block, "/ground_motion")?),
            ),
            (None, None) => {
                return Err(SpecError::at(
                    "/pulse",
                    "missing field: give pulse or ground_motion",
                ));
            }
            (Some(_), Some(_)) => {
                return Err(SpecError::at(
                    "/ground_motion",
                    "give either pulse or ground_motion, not both",
                ));
            }
        };
        let vertical = match (&self.vertical, &pulse) {
            (Some(v), Some(_)) => validate_vertical_pulse(v, &block, "/vertical")?,
            (Some(_), None) => {
                return Err(SpecError::at(
                    "/vertical",
                    "goes with a pulse: a record takes its vertical acceleration in ground_motion.vertical",
                ));
            }
            (None, _) => None,
        };
        let with_vertical =
            vertical.is_some() || ground_motion.as_ref().is_some_and(|g| g.vertical.is_some());
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        // The closed form covers the sinusoidal pulses and every record
        // (linear between samples); a wavelet has none, nor any motion with
        // a vertical component.
        let closed_form = pulse.as_ref().is_none_or(|p| p.shape.is_sinusoidal());
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            closed_form,
            with_vertical,
            "/solver",
        )?;
        let contact = validate_contact(self.contact.as_ref(), formulation, "/contact")?;
        let out = self.outputs.clone().unwrap_or_default();
        let series = out.series.unwrap_or(0);
        if contact.is_some() && out.duration.is_some() {
            return Err(SpecError::at(
                "/outputs/duration",
                "under the coulomb contact model the history is followed to rest, overturning or lift-off",
            ));
        }
        if series > MAX_SERIES_POINTS {
            return Err(SpecError::at(
                "/outputs/series",
                format!("at most {MAX_SERIES_POINTS} points"),
            ));
        }
        if let Some(d) = out.duration
            && !(d.is_finite() && d > 0.0)
        {
            return Err(SpecError::at(
                "/outputs/duration",
                "must be positive and finite (s)",
            ));
        }
        Ok(TimeHistoryJob {
            kind: tag::TimeHistory,
            block,
            pulse,
            vertical,
            ground_motion,
            formulation,
            solver,
            outputs: OutputsNorm {
                series,
                reactions: out.reactions.unwrap_or(true),
                impacts: out.impacts.unwrap_or(true),
                max_free_impacts: out.max_free_impacts.unwrap_or(1_000),
                duration: out.duration,
            },
            contact,
        })
    }
}
