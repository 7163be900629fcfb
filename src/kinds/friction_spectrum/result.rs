//! A friction spectrum job's result document.

use super::spec::FrictionJob;
use crate::jobs::names::{EngineDoc, tag};
use crate::kinds::spectrum::SpectrumNumerics;
use serde::{Deserialize, Serialize};
/// One amplitude of a friction spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FrictionPointDoc {
    /// a_p/(αg).
    pub a_alpha_g: f64,
    /// a_p, g.
    #[serde(default)]
    #[schema(required = true)]
    pub a_p_g: f64,
    /// max |f_x/f_z| over the rocking history: the minimum μ for pure rocking;
    /// null when the block lifts off (`lift_off`): the demand is unbounded.
    #[schema(required = true)]
    pub peak_friction_demand: Option<f64>,
    /// The same over tan α (the axis of Fig. 9); null with it.
    #[schema(required = true)]
    pub peak_over_tan_alpha: Option<f64>,
    /// f_x/f_z when rocking starts (eq. 7; eq. 51 for one-cosine).
    #[schema(required = true)]
    pub initiation_friction_demand: Option<f64>,
    /// Whether the block overturned.
    pub overturned: bool,
    /// Overturning mode.
    #[schema(required = true)]
    pub mode: Option<u8>,
    /// Whether f_z reached 0: the block would lift off, no μ sustains pure
    /// rocking.
    #[serde(default)]
    #[schema(required = true)]
    pub lift_off: bool,
    /// First time f_z ≤ 0, s.
    #[schema(required = true)]
    pub lift_off_time: Option<f64>,
    /// The demand was followed up to this time (the pulse end) only: the block
    /// was then bound to overturn, and its fall is not counted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_demand_followed_until: Option<f64>,
}

/// The result document of a friction-spectrum job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[schema(as = FrictionSpectrumResult)]
pub struct FrictionResult {
    /// "friction_spectrum".
    pub kind: tag::FrictionSpectrum,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// ω_p, rad/s.
    pub omega_p: f64,
    /// f_p, Hz.
    pub frequency_hz: f64,
    /// One entry per amplitude.
    pub points: Vec<FrictionPointDoc>,
    /// Cost and accuracy.
    pub numerics: SpectrumNumerics,
    /// The normalised spec.
    pub spec: FrictionJob,
    /// Notes on the inputs (`implausible_size`: a block smaller than 1 cm or
    /// larger than 100 m); absent when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(FrictionResult);
