//! A record spectrum job's result document.

use super::spec::RecordSpectrumJob;
use crate::jobs::names::{EngineDoc, tag};
use crate::kinds::spectrum::ScanCost;
use crate::kinds::time_history::GroundPeaksDoc;
use serde::{Deserialize, Serialize};
/// A survive ↔ overturn transition over the scale factor.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScaleTransitionDoc {
    /// Scale factor (bracket midpoint).
    pub scale: f64,
    /// The scaled record's PGA there, g.
    pub pga_g: f64,
    /// "up": overturning begins as the scale grows; "down": a safe interval begins.
    #[schema(value_type = crate::jobs::schema::TransitionDirection)]
    pub direction: String,
    /// Mode on the overturning side.
    pub mode: u8,
    /// Impacts on the overturning side.
    pub impacts: u64,
    /// [lo, hi] scale factors, width ≤ tolerance.
    pub bracket: [f64; 2],
}

/// A change of overturning mode over the scale factor.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScaleModeChangeDoc {
    /// Scale factor.
    pub scale: f64,
    /// Mode below.
    pub from_mode: u8,
    /// Mode above.
    pub to_mode: u8,
    /// Bracket, scale factors.
    pub bracket: [f64; 2],
}

/// The principal view of one block size.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScalePrincipalDoc {
    /// Transitions without narrow bands.
    pub transitions: Vec<ScaleTransitionDoc>,
    /// Lowest overturning scale factor.
    #[schema(required = true)]
    pub min_overturn_scale: Option<f64>,
    /// Its mode.
    #[schema(required = true)]
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum, [lo, hi] scale factors.
    pub safe_intervals: Vec<[f64; 2]>,
    /// Every scale above this overturns (up to the highest examined).
    #[schema(required = true)]
    pub overturns_above_scale: Option<f64>,
}

/// One block size of a record spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SizeDoc {
    /// Frequency parameter p, rad/s.
    pub p: f64,
    /// Size R = 3g/(4p²), m.
    #[serde(rename = "R_m")]
    pub r_m: f64,
    /// Scale factor at which the block starts to rock (PGA = g tan α, or g α linear).
    pub threshold_scale: f64,
    /// Every transition (fine structure).
    pub transitions: Vec<ScaleTransitionDoc>,
    /// Mode changes inside overturning regions.
    pub mode_changes: Vec<ScaleModeChangeDoc>,
    /// Lowest overturning scale factor.
    #[schema(required = true)]
    pub min_overturn_scale: Option<f64>,
    /// The scaled record's PGA there, g.
    #[schema(required = true)]
    pub min_overturn_pga_g: Option<f64>,
    /// Its mode.
    #[schema(required = true)]
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum, [lo, hi] scale factors.
    pub safe_intervals: Vec<[f64; 2]>,
    /// Every scale above this overturns (up to the highest examined).
    #[schema(required = true)]
    pub overturns_above_scale: Option<f64>,
    /// Without bands narrower than the principal relative width.
    pub principal: ScalePrincipalDoc,
    /// On a Coulomb floor: the lowest scale found (within the tolerance) at
    /// which the normal force reaches 0 and the block leaves the floor; this
    /// size claims nothing above it (absent when it never does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_scale: Option<f64>,
    /// Where the outcome alternates finer than the scan resolves (scale
    /// factors), with the fraction of probed scales at which the block
    /// overturns: no transition, band or safe interval is certain inside.
    #[serde(default)]
    #[schema(required = true)]
    pub mixed: Vec<crate::jobs::mixed::MixedDoc>,
    /// Where `min_overturn_scale` lies: "band" (a certain overturning band)
    /// or "mixed" (a mixed zone, `min_overturn_zone`); null when the block
    /// never overturns.
    #[serde(default)]
    #[schema(required = true)]
    pub min_overturn_in: Option<String>,
    /// The mixed zone holding `min_overturn_scale`, with its fraction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_overturn_zone: Option<crate::jobs::mixed::MixedDoc>,
    /// The lowest scale from which overturning is certain (verified, outside
    /// every mixed zone) over a band at least `principal_relative_width` of
    /// its scale wide.
    #[serde(default)]
    #[schema(required = true)]
    pub min_certain_overturn_scale: Option<f64>,
    /// The scaled record's PGA there, g.
    #[serde(default)]
    #[schema(required = true)]
    pub min_certain_overturn_pga_g: Option<f64>,
}

/// The record as given: its peaks and sampling.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordDoc {
    /// PGA, PGV, PGD of the unscaled record (from rest, no baseline correction).
    #[serde(flatten)]
    pub peaks: GroundPeaksDoc,
    /// Sampling interval, s.
    pub dt_s: f64,
    /// Samples.
    pub samples: usize,
    /// Duration (N − 1)·dt, s.
    pub duration_s: f64,
}

/// Cost and accuracy of a record spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordSpectrumNumerics {
    /// Solver, cost and worst error estimate.
    #[serde(flatten)]
    pub cost: ScanCost,
    /// Bracket width of transitions, scale units.
    pub tolerance: f64,
    /// Scan step, scale units.
    pub scan_step: f64,
    /// Wall time, s (of a job computed in several tasks: their total
    /// compute time).
    pub wall_time_s: f64,
    /// Tasks the job was computed in (absent: one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tasks: Option<usize>,
}

/// The result document of a record spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordSpectrumResult {
    /// "record_spectrum".
    pub kind: tag::RecordSpectrum,
    /// The record's PGA, PGV, PGD and sampling.
    pub record: RecordDoc,
    /// One entry per block size, in the order of `spec.p`.
    pub spectrum: Vec<SizeDoc>,
    /// Under a vertical motion: from this scale factor the ground falls away
    /// faster than gravity (g + ü_v ≤ 0) and the block leaves it; every size
    /// is scanned up to just below it and claims nothing above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_scale: Option<f64>,
    /// Cost and accuracy.
    pub numerics: RecordSpectrumNumerics,
    /// The normalised spec.
    pub spec: RecordSpectrumJob,
    /// Notes on the inputs; absent when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(RecordSpectrumResult);
