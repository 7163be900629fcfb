//! The `survival` job: the probability that a rock of known (or uncertain)
//! age still stands under a hazard model. With a lognormal fragility (median
//! θ, dispersion β) and a tabulated hazard curve λ(x), the annual toppling
//! rate is λ_t = ∫ P(topple | x) |dλ(x)| in closed form
//! ([`HazardCurve::toppling_rate`]); topplings are a Poisson process, so a
//! rock of age T stands with P_s = exp(−λ_t T) ([`Age::survival`]).

pub mod figure;
pub mod table;

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::jobs::distribution::{DistributionNorm, DistributionSpec};
use crate::jobs::names::{EngineDoc, Im, tag};
use crate::jobs::spec::SpecError;
use crate::jobs::warning::WarningDoc;
use crate::probability::hazard::HazardCurve;
use crate::probability::survival::{Age, rate_scale};

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

fn validate_fragility(
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

fn validate_age(v: Option<&Value>, at: &str, list_allowed: bool) -> Result<AgeNorm, SpecError> {
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

impl SurvivalJob {
    /// Computes the rates and probabilities.
    pub fn run(&self) -> SurvivalResult {
        let started = std::time::Instant::now();
        // Validated: the curve is one.
        let curve = HazardCurve::new(&self.hazard.points);
        let mut joint_rocks = Vec::new();
        let rocks: Vec<RockResult> = self
            .rocks
            .iter()
            .map(|r| {
                let t = curve
                    .as_ref()
                    .map(|c| c.toppling_rate(r.fragility.median, r.fragility.beta))
                    .unwrap_or(crate::probability::hazard::TopplingRate {
                        rate: 0.0,
                        extrapolated_share: 0.0,
                    });
                let (ages, distribution) = match &r.age_years {
                    AgeNorm::Known(list) => {
                        let ages = list
                            .iter()
                            .map(|&years| {
                                let age = Age::Known(years);
                                AgeResult {
                                    age_years: years,
                                    survival_probability: age.survival(t.rate),
                                    rate_scale_at_5_percent: rate_scale(&[(t.rate, age)], TARGET),
                                }
                            })
                            .collect();
                        if let [years] = list[..] {
                            joint_rocks.push((t.rate, Age::Known(years)));
                        }
                        (ages, None)
                    }
                    AgeNorm::Uncertain(d) => {
                        let dist = d.distribution();
                        let age = Age::Uncertain(dist);
                        joint_rocks.push((t.rate, age));
                        (
                            Vec::new(),
                            Some(AgeDistributionResult {
                                median_age_years: dist.median(),
                                survival_probability: age.survival(t.rate),
                                rate_scale_at_5_percent: rate_scale(&[(t.rate, age)], TARGET),
                            }),
                        )
                    }
                };
                RockResult {
                    name: r.name.clone(),
                    fragility: r.fragility,
                    annual_toppling_rate: t.rate,
                    mean_years_between_topplings: Some(1.0 / t.rate).filter(|y| y.is_finite()),
                    extrapolated_share: t.extrapolated_share,
                    ages,
                    age_distribution: distribution,
                }
            })
            .collect();
        let single = (rocks.len() == 1).then(|| rocks[0].clone());
        let joint = (rocks.len() > 1).then(|| JointResult {
            survival_probability: joint_rocks.iter().map(|(l, a)| a.survival(*l)).product(),
            rate_scale_at_5_percent: rate_scale(&joint_rocks, TARGET),
        });
        SurvivalResult {
            kind: tag::Survival,
            im: self.hazard.im,
            annual_toppling_rate: single.as_ref().map(|r| r.annual_toppling_rate),
            ages: single
                .as_ref()
                .filter(|r| r.age_distribution.is_none())
                .map(|r| r.ages.clone()),
            age_distribution: single.and_then(|r| r.age_distribution),
            rocks,
            joint,
            numerics: SurvivalNumerics {
                method:
                    "closed form: λ_t = E[λ(X)], X lognormal, on the log-log interpolated curve"
                        .into(),
                wall_time_s: started.elapsed().as_secs_f64(),
            },
            spec: self.clone(),
            warnings: Vec::new(),
            engine: None,
        }
    }
}

/// The `survival` kind: the probability that rocks of known age still
/// stand under a hazard model (closed forms).
pub struct Survival;

impl crate::kinds::kind::Kind for Survival {
    const NAME: &'static str = crate::jobs::names::tag::Survival::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Survival";
    type Spec = SurvivalSpec;
    type Job = SurvivalJob;
    type Result = SurvivalResult;
    type Part = crate::jobs::kind::NoPart;

    fn run(
        job: &SurvivalJob,
        control: &crate::spectrum::Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        crate::kinds::kind::run_one::<Self>(control, || Ok(job.run()))
    }

    fn table(
        result: &SurvivalResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &SurvivalResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    /// Closed forms and a quadrature: under a millisecond.
    fn size(_job: &SurvivalJob) -> crate::jobs::kind::Size {
        crate::jobs::kind::Size::one(1e-4)
    }

    fn grid_field(_job: &SurvivalJob) -> &'static str {
        "/omega_ratio"
    }
}
