//! A survival job's spec as users write it,
//! the validated job, and the validation from one to the other.

use crate::jobs::distribution::{DistributionNorm, DistributionSpec};
use crate::jobs::names::{Im, tag};
use crate::jobs::spec::SpecError;
use crate::probability::hazard::HazardCurve;
use serde::{Deserialize, Serialize};
use serde_json::Value;
/// Most points of a hazard curve.
pub const MAX_HAZARD_POINTS: usize = 1_000;
/// Most rocks in one job.
pub const MAX_ROCKS: usize = 100;
/// Most ages of one rock.
pub const MAX_AGES: usize = 1_000;
/// Oldest age, years (the age of the Earth, rounded up).
pub const MAX_AGE_YEARS: f64 = 5e9;
/// Survival probability at which the rate scale is reported.
pub const TARGET: f64 = 0.05;

/// A hazard curve as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct HazardSpec {
    /// The intensity measure: "pga_g" (g) or "pgv_m_s" (m/s).
    #[schema(required = true, value_type = ImName)]
    pub im: Option<String>,
    /// `[intensity, annual exceedance rate]` pairs, intensities rising and
    /// rates falling (2 to 1,000), interpolated log-log; beyond the first and
    /// last points the end segments' power laws continue.
    #[schema(required = true, value_type = Vec<[f64; 2]>, min_items = 2, max_items = 1000)]
    pub points: Option<Vec<[f64; 2]>>,
}

/// The intensity measures of hazard curves and fragilities.
#[derive(utoipa::ToSchema)]
#[schema(rename_all = "snake_case")]
#[allow(dead_code)]
pub enum ImName {
    /// Peak ground acceleration, g.
    PgaG,
    /// Peak ground velocity, m/s.
    PgvMS,
}

/// A lognormal fragility as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FragilityInput {
    /// Median intensity at which the rock topples, g (with `im` = "pga_g").
    #[schema(exclusive_minimum = 0.0)]
    pub median_g: Option<f64>,
    /// Median intensity in the hazard's unit (g or m/s).
    #[schema(exclusive_minimum = 0.0)]
    pub median: Option<f64>,
    /// Dispersion β (0 to 3; 0: a sharp threshold).
    #[schema(minimum = 0.0, maximum = 3.0)]
    pub beta: Option<f64>,
    /// Instead of median and beta: the id of a finished `fragility` job of
    /// the same tenant, whose lognormal fit the service reads (and writes
    /// into the normalised spec as median and beta).
    #[schema(format = "uuid")]
    pub job: Option<String>,
}

/// One rock as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RockSpec {
    /// What it is.
    pub name: Option<String>,
    /// Its fragility.
    #[schema(required = true, value_type = FragilityInput)]
    pub fragility: Option<FragilityInput>,
    /// Its age, years: a number or a distribution.
    #[schema(required = true, value_type = AgeInput)]
    pub age_years: Option<Value>,
}

/// An age in years: one number, a list, or a distribution.
#[derive(Deserialize, utoipa::ToSchema)]
#[serde(untagged)]
#[allow(dead_code)]
pub enum AgeInput {
    /// One age.
    Years(f64),
    /// Several ages.
    List(Vec<f64>),
    /// An uncertain age.
    Distribution(DistributionSpec),
}

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SurvivalSpec {
    /// "survival".
    #[schema(value_type = crate::jobs::names::tag::Survival)]
    pub kind: String,
    /// The hazard curve.
    #[schema(required = true, value_type = HazardSpec)]
    pub hazard: Option<HazardSpec>,
    /// The rock's fragility (one rock; or give `rocks`).
    pub fragility: Option<FragilityInput>,
    /// The rock's age, years: a number, a list, or a distribution.
    #[schema(value_type = Option<AgeInput>)]
    pub age_years: Option<Value>,
    /// Several rocks, each with its fragility and age (a number or a
    /// distribution); their joint survival is the product.
    #[schema(max_items = 100)]
    pub rocks: Option<Vec<RockSpec>>,
}

/// A fragility, normalised: median in the hazard's unit.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FragilityNorm {
    /// Median intensity (g or m/s).
    pub median: f64,
    /// Dispersion β.
    pub beta: f64,
}

/// An age, normalised.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[serde(untagged)]
pub enum AgeNorm {
    /// Known ages, years.
    Known(Vec<f64>),
    /// An uncertain age.
    Uncertain(DistributionNorm),
}

/// A rock, normalised.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RockNorm {
    /// Its name.
    pub name: String,
    /// Its fragility.
    pub fragility: FragilityNorm,
    /// Its age.
    pub age_years: AgeNorm,
}

/// A hazard curve, normalised.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct HazardNorm {
    /// "pga_g" | "pgv_m_s".
    #[schema(value_type = ImName)]
    pub im: Im,
    /// The points.
    pub points: Vec<[f64; 2]>,
}

/// A validated survival job; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SurvivalJob {
    /// "survival".
    pub kind: tag::Survival,
    /// The hazard curve.
    pub hazard: HazardNorm,
    /// The rocks (one when the spec gave `fragility` and `age_years`).
    pub rocks: Vec<RockNorm>,
}

pub(super) fn validate_fragility(
    f: Option<&FragilityInput>,
    im: Im,
    at: &str,
) -> Result<FragilityNorm, SpecError> {
    let f = f.ok_or_else(|| {
        SpecError::at(
            at,
            "missing field: {\"median_g\" (or \"median\"), \"beta\"}",
        )
    })?;
    if f.job.is_some() {
        return Err(SpecError::at(
            format!("{at}/job"),
            "a fragility job is read by the service when the spec is submitted; here give median_g (or median) and beta",
        ));
    }
    let median = match (f.median_g, f.median) {
        (Some(_), Some(_)) => {
            return Err(SpecError::at(
                format!("{at}/median"),
                "give median_g or median, not both",
            ));
        }
        (Some(_), None) if im != Im::PgaG => {
            return Err(SpecError::at(
                format!("{at}/median_g"),
                format!("the hazard's intensity is {im}: give the median in its unit as median"),
            ));
        }
        (Some(m), None) => (m, "median_g"),
        (None, Some(m)) => (m, "median"),
        (None, None) => {
            return Err(SpecError::at(
                format!("{at}/median_g"),
                "missing field: the median intensity at which the rock topples",
            ));
        }
    };
    if !(median.0.is_finite() && median.0 > 0.0) {
        return Err(SpecError::at(
            format!("{at}/{}", median.1),
            "must be a finite number > 0",
        ));
    }
    let beta = f
        .beta
        .ok_or_else(|| SpecError::at(format!("{at}/beta"), "missing field: the dispersion β"))?;
    if !(beta.is_finite() && (0.0..=3.0).contains(&beta)) {
        return Err(SpecError::at(format!("{at}/beta"), "must lie in [0, 3]"));
    }
    Ok(FragilityNorm {
        median: median.0,
        beta,
    })
}

pub(super) fn validate_age(
    v: Option<&Value>,
    at: &str,
    list_allowed: bool,
) -> Result<AgeNorm, SpecError> {
    let one = |x: &Value, at: &str| -> Result<f64, SpecError> {
        match x.as_f64() {
            Some(t) if t.is_finite() && t > 0.0 && t <= MAX_AGE_YEARS => Ok(t),
            _ => Err(SpecError::at(
                at,
                format!("an age must be a number of years in (0, {MAX_AGE_YEARS:e}]"),
            )),
        }
    };
    match v {
        None | Some(Value::Null) => Err(SpecError::at(
            at,
            "missing field: the age in years (a number, a list, or a distribution)",
        )),
        Some(Value::Number(_)) => Ok(AgeNorm::Known(vec![one(v.unwrap_or(&Value::Null), at)?])),
        Some(Value::Array(list)) => {
            if !list_allowed {
                return Err(SpecError::at(
                    at,
                    "with several rocks each has one age (a number or a distribution): their joint survival is for that set of ages",
                ));
            }
            if list.is_empty() || list.len() > MAX_AGES {
                return Err(SpecError::at(at, format!("give 1 to {MAX_AGES} ages")));
            }
            let ages = list
                .iter()
                .enumerate()
                .map(|(i, x)| one(x, &format!("{at}/{i}")))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(AgeNorm::Known(ages))
        }
        Some(obj @ Value::Object(_)) => {
            let d: DistributionSpec = crate::jobs::spec::from_value(obj, at)?;
            Ok(AgeNorm::Uncertain(d.validate(
                at,
                (0.0, f64::INFINITY),
                true,
                "an age (years)",
            )?))
        }
        Some(_) => Err(SpecError::at(
            at,
            "must be a number of years, a list of them, or a distribution {\"dist\", …}",
        )),
    }
}

impl crate::jobs::kind::Validate for SurvivalSpec {
    type Job = SurvivalJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<SurvivalJob, SpecError> {
        let hazard = self
            .hazard
            .as_ref()
            .ok_or_else(|| SpecError::at("/hazard", "missing field: {\"im\", \"points\"}"))?;
        let im = match hazard.im.as_deref() {
            Some("pga_g") => Im::PgaG,
            Some("pgv_m_s") => Im::PgvMS,
            Some(other) => {
                return Err(SpecError::at(
                    "/hazard/im",
                    format!("unknown intensity measure {other:?}: expected pga_g | pgv_m_s"),
                ));
            }
            None => {
                return Err(SpecError::at(
                    "/hazard/im",
                    "missing field: pga_g | pgv_m_s",
                ));
            }
        };
        let points = crate::jobs::spec::required(hazard.points.as_ref(), "/hazard/points")?;
        if points.len() > MAX_HAZARD_POINTS {
            return Err(SpecError::at(
                "/hazard/points",
                format!("at most {MAX_HAZARD_POINTS} points"),
            ));
        }
        HazardCurve::new(points).map_err(|e| {
            use crate::probability::hazard::HazardError;
            match e {
                HazardError::TooFew => SpecError::at("/hazard/points", e.to_string()),
                HazardError::NotPositive(i) | HazardError::NotMonotone(i) => {
                    SpecError::at(format!("/hazard/points/{i}"), e.to_string())
                }
            }
        })?;
        let rocks = match (&self.rocks, &self.fragility, &self.age_years) {
            (Some(_), Some(_), _) => {
                return Err(SpecError::at(
                    "/fragility",
                    "give one rock's fragility and age_years, or rocks, not both",
                ));
            }
            (Some(_), None, Some(_)) => {
                return Err(SpecError::at(
                    "/age_years",
                    "give one rock's fragility and age_years, or rocks, not both",
                ));
            }
            (Some(list), None, None) => {
                if list.is_empty() || list.len() > MAX_ROCKS {
                    return Err(SpecError::at(
                        "/rocks",
                        format!("give 1 to {MAX_ROCKS} rocks"),
                    ));
                }
                let several = list.len() > 1;
                list.iter()
                    .enumerate()
                    .map(|(i, r)| {
                        let at = format!("/rocks/{i}");
                        Ok(RockNorm {
                            name: r
                                .name
                                .clone()
                                .filter(|n| !n.trim().is_empty())
                                .unwrap_or_else(|| format!("rock {}", i + 1)),
                            fragility: validate_fragility(
                                r.fragility.as_ref(),
                                im,
                                &format!("{at}/fragility"),
                            )?,
                            age_years: validate_age(
                                r.age_years.as_ref(),
                                &format!("{at}/age_years"),
                                !several,
                            )?,
                        })
                    })
                    .collect::<Result<Vec<_>, SpecError>>()?
            }
            (None, f, age) => vec![RockNorm {
                name: "rock".to_string(),
                fragility: validate_fragility(f.as_ref(), im, "/fragility")?,
                age_years: validate_age(age.as_ref(), "/age_years", true)?,
            }],
        };
        Ok(SurvivalJob {
            kind: tag::Survival,
            hazard: HazardNorm {
                im,
                points: points.clone(),
            },
            rocks,
        })
    }
}
