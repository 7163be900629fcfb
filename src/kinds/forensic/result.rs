//! A forensic job's result document.

use super::spec::{AmplitudeRange, ForensicJob, Observation};
use crate::dynamics::Formulation;
use crate::jobs::names::{EngineDoc, Excitation, tag};
use crate::kinds::record_spectrum::RecordDoc;
use crate::kinds::record_spectrum::ScaleRangeNorm;
use crate::kinds::spectrum::{PulseFamily, ScanCost};
use serde::{Deserialize, Serialize};
/// One observation's consistent amplitudes at one frequency.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ObservationSet {
    /// The observation.
    pub name: String,
    /// Amplitudes certainly consistent with it, g: every one verified
    /// inside ([`crate::spectrum::verify`]).
    pub consistent_g: Vec<[f64; 2]>,
    /// Where its outcome alternates finer than the scan resolves, g, with
    /// the fraction of probed amplitudes at which its block did what was
    /// seen.
    #[serde(default)]
    pub mixed_g: Vec<super::mixed::MixedDoc>,
    /// On a Coulomb floor: from this amplitude (g, the lowest found within
    /// the tolerance) its block leaves the floor; nothing above is claimed
    /// consistent with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_g: Option<f64>,
}

/// One pulse frequency of the answer.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicFrequency {
    /// f_p, Hz.
    pub frequency_hz: f64,
    /// ω_p, rad/s.
    pub omega_p: f64,
    /// Amplitudes certainly consistent with every observation, g.
    pub consistent_g: Vec<[f64; 2]>,
    /// Where every observation is consistent or mixed and one at least
    /// mixed, g (the fraction: the product of theirs).
    #[serde(default)]
    pub mixed_g: Vec<super::mixed::MixedDoc>,
    /// Each observation's consistent amplitudes, g.
    pub per_observation: Vec<ObservationSet>,
}

/// The range of pulses consistent with everything seen.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct Bounds {
    /// Lowest consistent amplitude at any frequency, g.
    #[schema(required = true)]
    pub min_g: Option<f64>,
    /// Highest consistent amplitude at any frequency, g.
    #[schema(required = true)]
    pub max_g: Option<f64>,
    /// Lowest and highest frequency with a consistent amplitude, Hz (null
    /// for a record query).
    #[schema(required = true)]
    pub frequency_hz: Option<[f64; 2]>,
    /// Lowest consistent scale factor (record queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_scale: Option<f64>,
    /// Highest consistent scale factor (record queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_scale: Option<f64>,
}

/// One observation's consistent scales of a record query.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordObservationSet {
    /// The observation.
    pub name: String,
    /// Whether it overturned.
    pub overturned: bool,
    /// Scale factors certainly consistent with it: every interval verified
    /// inside ([`crate::spectrum::verify`]).
    pub consistent_scale: Vec<[f64; 2]>,
    /// The same, as the scaled record's PGA, g.
    pub consistent_pga_g: Vec<[f64; 2]>,
    /// Where its outcome alternates finer than the scan resolves (scale
    /// factors), with the fraction of probed scales at which its block did
    /// what was seen.
    #[serde(default)]
    pub mixed_scale: Vec<super::mixed::MixedDoc>,
    /// The same, as the scaled record's PGA, g.
    #[serde(default)]
    pub mixed_pga_g: Vec<super::mixed::MixedDoc>,
    /// Scale factors at which its block certainly overturns (within the
    /// range examined, outside the mixed zones).
    pub overturning_scale: Vec<[f64; 2]>,
    /// Scale factor at which its block starts to rock (PGA = g tan α, or g α linear).
    pub threshold_scale: f64,
    /// On a Coulomb floor: from this scale factor (the lowest found within
    /// the tolerance) its block leaves the floor; nothing above is claimed
    /// consistent with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_scale: Option<f64>,
}

/// Cost and accuracy.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicNumerics {
    /// Solver, cost and worst error estimate (all observations).
    #[serde(flatten)]
    pub cost: ScanCost,
    /// Every interval end is bracketed within this, g.
    pub tolerance_g: f64,
    /// Scan step, g.
    pub scan_step_g: f64,
    /// Wall time, s (of a query computed in several tasks: their total
    /// compute time).
    pub wall_time_s: f64,
    /// Tasks the query was computed in (absent: one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tasks: Option<usize>,
}

/// The result document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ForensicResult {
    /// "forensic".
    pub kind: tag::Forensic,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// "pulse": the unknowns are the pulse's frequency and amplitude
    /// (`pulse`, `frequencies`); "ground_motion": the unknown is the record's
    /// scale (`record`, `scale`, `consistent_scale`, `per_observation`).
    #[schema(value_type = crate::jobs::schema::ForensicExcitation)]
    pub excitation: Excitation,
    /// Pulse family (pulse queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulse: Option<PulseFamily>,
    /// The record's PGA, PGV, PGD and sampling, unscaled (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub record: Option<RecordDoc>,
    /// Amplitudes examined, g (a record query: the scaled PGA).
    pub a_p_g: AmplitudeRange,
    /// Scale factors examined (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<ScaleRangeNorm>,
    /// The observations.
    pub observations: Vec<Observation>,
    /// One entry per frequency (empty for a record query).
    pub frequencies: Vec<ForensicFrequency>,
    /// Scale factors consistent with every observation (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub consistent_scale: Option<Vec<[f64; 2]>>,
    /// The same, as the scaled record's PGA, g (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub consistent_pga_g: Option<Vec<[f64; 2]>>,
    /// Where every observation is consistent or mixed, and one at least
    /// mixed: scale factors, with the product of their fractions (record
    /// queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mixed_scale: Option<Vec<super::mixed::MixedDoc>>,
    /// The same, as the scaled record's PGA, g (record queries).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mixed_pga_g: Option<Vec<super::mixed::MixedDoc>>,
    /// Each observation's consistent scales (record queries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_observation: Option<Vec<RecordObservationSet>>,
    /// Overall bounds.
    pub bounds: Bounds,
    /// Under a vertical motion: from this amplitude (g; a pulse's peak, or
    /// the scaled record's PGA) the ground falls away faster than gravity
    /// (g + ü_v ≤ 0) and the block leaves it. The query is answered up to
    /// just below it (`a_p_g`/`pga_g` end there) and claims nothing above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_g: Option<f64>,
    /// Numerics.
    pub numerics: ForensicNumerics,
    /// The normalised spec.
    pub spec: ForensicJob,
    /// Notes on the inputs (`implausible_size`: a block smaller than 1 cm or
    /// larger than 100 m; `implausible_slide`: a seen slide past 1 m); absent
    /// when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(ForensicResult);
