//! A fragility job's result document.

use super::spec::FragilityJob;
use crate::jobs::names::{EngineDoc, Im, tag};
use serde::{Deserialize, Serialize};
/// One stripe's counts.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct StripeResult {
    /// Intensity (g or m/s).
    pub im: f64,
    /// Simulations.
    pub n: u64,
    /// How many toppled.
    pub overturned: u64,
    /// overturned / the samples decided (n − lift_off); null when none was.
    #[serde(deserialize_with = "nan_for_null_one")]
    #[schema(value_type = Option<f64>, required = true)]
    pub p: f64,
    /// 95 % Wilson score interval of p (nulls when no sample was decided).
    #[serde(deserialize_with = "nan_for_null")]
    #[schema(value_type = [Option<f64>; 2])]
    pub interval_95: [f64; 2],
    /// Topplings after at least one impact (mode 1).
    pub mode_1: u64,
    /// Topplings without impact (mode 2).
    pub mode_2: u64,
    /// Under a vertical ground motion: samples whose ground fell away faster
    /// than g (lift-off), with no verdict on overturning and left out of p
    /// and the fit. Absent without a vertical motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off: Option<u64>,
    /// Samples whose history reached a bound on its work (impacts, steps,
    /// free motion) before its outcome was decided: undecided, left out of
    /// p and the fit like `lift_off`. Absent when none was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub undecided: Option<u64>,
}

impl StripeResult {
    /// The samples with a verdict.
    pub fn decided(&self) -> u64 {
        self.n - self.lift_off.unwrap_or(0) - self.undecided.unwrap_or(0)
    }
}

/// A number that was NaN, serialised as null.
pub(super) fn nan_for_null_one<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A point of the fitted curve and its bootstrap band.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct CurvePoint {
    /// Intensity.
    pub im: f64,
    /// Φ(ln(im/θ)/β).
    pub p: f64,
    /// 2.5 % of the bootstrap curves there.
    pub lo: f64,
    /// 97.5 % of the bootstrap curves there.
    pub hi: f64,
}

/// The lognormal fragility fitted to the stripes.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct LognormalFit {
    /// Median θ (g or m/s).
    pub median: f64,
    /// Dispersion β.
    pub beta: f64,
    /// 95 % bootstrap interval of θ.
    // NaN ends (no replicate fitted) are written as null.
    #[serde(deserialize_with = "nan_for_null")]
    pub median_interval_95: [f64; 2],
    /// 95 % bootstrap interval of β.
    #[serde(deserialize_with = "nan_for_null")]
    pub beta_interval_95: [f64; 2],
    /// ln L at the fit.
    pub log_likelihood: f64,
    /// The fitted curve with its 95 % bootstrap band.
    pub curve: Vec<CurvePoint>,
}

/// An interval whose ends were NaN, serialised as null.
pub(super) fn nan_for_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let [a, b] = <[Option<f64>; 2]>::deserialize(d)?;
    Ok([a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN)])
}

/// Cost.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FragilityNumerics {
    /// Solver method.
    pub method: String,
    /// Simulations run.
    pub simulations: u64,
    /// Simulations per second (all cores).
    pub simulations_per_second: f64,
    /// Wall time, s.
    pub wall_time_s: f64,
    /// Bootstrap replicates of the fit.
    pub bootstrap: usize,
    /// Tasks the job was computed as (several: `wall_time_s` is their wall
    /// times summed, wherever they ran, plus the assembly's).
    pub tasks: usize,
}

/// The result document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FragilityResult {
    /// "fragility".
    pub kind: tag::Fragility,
    /// The intensity measure.
    #[schema(value_type = crate::kinds::survival::ImName)]
    pub im: Im,
    /// One entry per stripe, in the order of `spec.stripes`: the empirical
    /// fragility, the primary answer.
    pub stripes: Vec<StripeResult>,
    /// "wilson": the score interval at 95 %.
    pub interval_method: String,
    /// Whether the empirical probabilities never fall as the intensity rises
    /// (safe regions make a fall real).
    pub monotone: bool,
    /// Intensities whose probability is below the previous stripe's.
    pub falls_at: Vec<f64>,
    /// The maximum-likelihood lognormal fragility (null when the counts do
    /// not bound it: every stripe all standing or all toppled, or a step
    /// without spread).
    #[schema(required = true)]
    pub lognormal: Option<LognormalFit>,
    /// Cost.
    pub numerics: FragilityNumerics,
    /// The normalised spec.
    pub spec: FragilityJob,
    /// Notes on the suite's records (`large_pga`, `baseline_drift`), added
    /// as the document leaves [`crate::kinds::Job::run`]; absent when there
    /// are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schema(ignore)]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(FragilityResult);
