//! A survival job's result document.

use super::spec::{FragilityNorm, ImName, SurvivalJob};
use crate::jobs::names::{EngineDoc, Im, tag};
use crate::jobs::warning::WarningDoc;
use serde::{Deserialize, Serialize};
/// One age of a rock.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct AgeResult {
    /// Age, years.
    pub age_years: f64,
    /// P(still standing) = exp(−λ_t T).
    pub survival_probability: f64,
    /// The factor on every hazard rate that brings P_s to 5 % (null: never topples).
    #[schema(required = true)]
    pub rate_scale_at_5_percent: Option<f64>,
}

/// An uncertain age of a rock.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct AgeDistributionResult {
    /// Median age, years.
    pub median_age_years: f64,
    /// E[exp(−λ_t T)] over the age.
    pub survival_probability: f64,
    /// The factor on every hazard rate that brings it to 5 % (null: never topples).
    #[schema(required = true)]
    pub rate_scale_at_5_percent: Option<f64>,
}

/// One rock's figures.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RockResult {
    /// Its name.
    pub name: String,
    /// Its fragility.
    pub fragility: FragilityNorm,
    /// λ_t: topplings per year.
    pub annual_toppling_rate: f64,
    /// 1/λ_t, years (null when it cannot topple).
    #[schema(required = true)]
    pub mean_years_between_topplings: Option<f64>,
    /// The share of λ_t from intensities beyond the tabulated curve (its end
    /// segments continued).
    pub extrapolated_share: f64,
    /// One entry per known age.
    pub ages: Vec<AgeResult>,
    /// The uncertain age's figures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub age_distribution: Option<AgeDistributionResult>,
}

/// Several rocks all standing.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct JointResult {
    /// Π P_s of the rocks.
    pub survival_probability: f64,
    /// The factor on every hazard rate that brings it to 5 %.
    #[schema(required = true)]
    pub rate_scale_at_5_percent: Option<f64>,
}

/// Cost.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SurvivalNumerics {
    /// How λ_t was computed.
    pub method: String,
    /// Wall time, s.
    pub wall_time_s: f64,
}

/// The result document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SurvivalResult {
    /// "survival".
    pub kind: tag::Survival,
    /// The intensity measure.
    #[schema(value_type = ImName)]
    pub im: Im,
    /// λ_t of the (single) rock, 1/yr; absent with several rocks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub annual_toppling_rate: Option<f64>,
    /// The (single) rock's ages; absent with several rocks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ages: Option<Vec<AgeResult>>,
    /// The (single) rock's uncertain age.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub age_distribution: Option<AgeDistributionResult>,
    /// Every rock's figures.
    pub rocks: Vec<RockResult>,
    /// All rocks standing (several rocks).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint: Option<JointResult>,
    /// Cost.
    pub numerics: SurvivalNumerics,
    /// The normalised spec.
    pub spec: SurvivalJob,
    /// Notes about the inputs (none yet for a survival).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(SurvivalResult);
