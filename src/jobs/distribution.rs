//! Distributions as specs write them: `{"dist": "normal", "mean", "sd",
//! "min"?, "max"?}`, `{"dist": "lognormal", "median", "beta"}`,
//! `{"dist": "uniform", "min", "max"}`; validated against the range the
//! quantity may take, naming the field.

use serde::{Deserialize, Serialize};

use super::spec::SpecError;
use crate::probability::distribution::Distribution;

/// A distribution as users write it.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct DistributionSpec {
    /// "normal" | "lognormal" | "uniform".
    #[schema(required = true, value_type = DistributionName)]
    pub dist: Option<String>,
    /// Mean (normal).
    pub mean: Option<f64>,
    /// Standard deviation (normal, > 0).
    #[schema(exclusive_minimum = 0.0)]
    pub sd: Option<f64>,
    /// Median (lognormal, > 0).
    #[schema(exclusive_minimum = 0.0)]
    pub median: Option<f64>,
    /// Dispersion β, the standard deviation of the logarithm (lognormal, > 0).
    #[schema(exclusive_minimum = 0.0)]
    pub beta: Option<f64>,
    /// Lower end (uniform), or truncation (normal, optional).
    pub min: Option<f64>,
    /// Upper end (uniform), or truncation (normal, optional).
    pub max: Option<f64>,
}

/// The distributions offered.
#[derive(utoipa::ToSchema)]
#[schema(rename_all = "snake_case")]
#[allow(dead_code)]
pub enum DistributionName {
    /// Normal, optionally truncated to [min, max].
    Normal,
    /// Lognormal (median, beta).
    Lognormal,
    /// Uniform on [min, max].
    Uniform,
}

/// A distribution, normalised (as stored in canonical specs).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[serde(tag = "dist", rename_all = "snake_case")]
pub enum DistributionNorm {
    /// Normal truncated to [min, max] (null: unbounded on that side).
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
        /// Lower truncation.
        min: Option<f64>,
        /// Upper truncation.
        max: Option<f64>,
    },
    /// Lognormal.
    Lognormal {
        /// Median.
        median: f64,
        /// Dispersion β.
        beta: f64,
    },
    /// Uniform.
    Uniform {
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
}

impl DistributionNorm {
    /// The domain distribution.
    pub fn distribution(&self) -> Distribution {
        match *self {
            DistributionNorm::Normal { mean, sd, min, max } => Distribution::Normal {
                mean,
                sd,
                min: min.unwrap_or(f64::NEG_INFINITY),
                max: max.unwrap_or(f64::INFINITY),
            },
            DistributionNorm::Lognormal { median, beta } => {
                Distribution::LogNormal { median, beta }
            }
            DistributionNorm::Uniform { min, max } => Distribution::Uniform { min, max },
        }
    }
}

fn finite(v: Option<f64>, at: &str, name: &str) -> Result<Option<f64>, SpecError> {
    match v {
        Some(x) if !x.is_finite() => Err(SpecError::at(
            format!("{at}/{name}"),
            "must be a finite number",
        )),
        other => Ok(other),
    }
}

fn required(v: Option<f64>, at: &str, name: &str, dist: &str) -> Result<f64, SpecError> {
    finite(v, at, name)?.ok_or_else(|| {
        SpecError::at(
            format!("{at}/{name}"),
            format!("missing field: a {dist} distribution needs {name}"),
        )
    })
}

/// Where a distribution is validated, and the range its every value must lie
/// in.
struct Within<'a> {
    /// Its JSON pointer.
    at: &'a str,
    /// Its family, as given.
    dist: &'a str,
    /// The lower end of the range.
    lo: f64,
    /// The upper end of the range.
    hi: f64,
    /// Whether `lo` itself is excluded.
    open_lo: bool,
    /// The quantity, in messages.
    what: &'a str,
    /// The range, as written in messages.
    range: String,
}

impl Within<'_> {
    /// None of `names` (a field and whether it is given) is given: the first
    /// given is an error, a field this family has not.
    fn not_for(&self, names: &[(&str, bool)]) -> Result<(), SpecError> {
        let (at, dist) = (self.at, self.dist);
        match names.iter().find(|(_, given)| *given) {
            Some((name, _)) => Err(SpecError::at(
                format!("{at}/{name}"),
                format!("a {dist} distribution has no {name}"),
            )),
            None => Ok(()),
        }
    }

    /// Whether `x` lies in the range.
    fn inside(&self, x: f64) -> bool {
        (if self.open_lo {
            x > self.lo
        } else {
            x >= self.lo
        }) && x <= self.hi
    }
}

impl DistributionSpec {
    /// Validates the distribution at `at`, whose every value must lie in
    /// `[lo, hi]` (`what` names the quantity in messages; `open_lo`: the
    /// lower end itself is excluded).
    pub fn validate(
        &self,
        at: &str,
        (lo, hi): (f64, f64),
        open_lo: bool,
        what: &str,
    ) -> Result<DistributionNorm, SpecError> {
        let dist = self.dist.as_deref().ok_or_else(|| {
            SpecError::at(
                format!("{at}/dist"),
                "missing field: normal | lognormal | uniform",
            )
        })?;
        let range = if open_lo {
            format!("({lo}, {hi}]")
        } else {
            format!("[{lo}, {hi}]")
        };
        let within = Within {
            at,
            dist,
            lo,
            hi,
            open_lo,
            what,
            range,
        };
        let norm = match dist {
            "normal" => self.normal(&within)?,
            "lognormal" => self.lognormal(&within)?,
            "uniform" => self.uniform(&within)?,
            other => {
                return Err(SpecError::at(
                    format!("{at}/dist"),
                    format!(
                        "unknown distribution {other:?}: expected normal | lognormal | uniform"
                    ),
                ));
            }
        };
        Ok(norm)
    }

    /// A normal distribution: mean, sd > 0, and a truncation [min, max]
    /// inside the range that keeps some of the law.
    fn normal(&self, within: &Within) -> Result<DistributionNorm, SpecError> {
        let Within {
            at,
            dist,
            lo,
            hi,
            open_lo,
            what,
            ref range,
        } = *within;
        within.not_for(&[
            ("median", self.median.is_some()),
            ("beta", self.beta.is_some()),
        ])?;
        let mean = required(self.mean, at, "mean", dist)?;
        let sd = required(self.sd, at, "sd", dist)?;
        if sd <= 0.0 {
            return Err(SpecError::at(format!("{at}/sd"), "must be > 0"));
        }
        let min = finite(self.min, at, "min")?;
        let max = finite(self.max, at, "max")?;
        // Every sample must be valid: the truncation must keep the
        // law inside the quantity's range.
        let (a, b) = (
            min.unwrap_or(f64::NEG_INFINITY),
            max.unwrap_or(f64::INFINITY),
        );
        let lower_ok = if open_lo { a > lo } else { a >= lo };
        if !lower_ok {
            return Err(SpecError::at(
                format!("{at}/min"),
                format!(
                    "{what} must lie in {range}: a normal distribution needs min (truncation) inside it (got {})",
                    min.map_or("none".to_string(), |m| m.to_string())
                ),
            ));
        }
        if b > hi {
            return Err(SpecError::at(
                format!("{at}/max"),
                format!(
                    "{what} must lie in {range}: a normal distribution needs max (truncation) inside it (got {})",
                    max.map_or("none".to_string(), |m| m.to_string())
                ),
            ));
        }
        if b <= a {
            return Err(SpecError::at(format!("{at}/max"), "must exceed min"));
        }
        let mass = crate::probability::normal::between((a - mean) / sd, (b - mean) / sd);
        if mass < 1e-9 {
            return Err(SpecError::at(
                at,
                format!(
                    "the truncation [{a}, {b}] keeps only {mass:.1e} of the law: move mean or widen it"
                ),
            ));
        }
        Ok(DistributionNorm::Normal { mean, sd, min, max })
    }

    /// A lognormal distribution: its median in the range, beta in (0, 3],
    /// for a quantity ranging from 0 to ∞ only.
    fn lognormal(&self, within: &Within) -> Result<DistributionNorm, SpecError> {
        let Within {
            at,
            dist,
            lo,
            hi,
            what,
            ref range,
            ..
        } = *within;
        within.not_for(&[
            ("mean", self.mean.is_some()),
            ("sd", self.sd.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
        ])?;
        let median = required(self.median, at, "median", dist)?;
        let beta = required(self.beta, at, "beta", dist)?;
        if !(median > 0.0 && within.inside(median)) {
            return Err(SpecError::at(
                format!("{at}/median"),
                format!("{what} must lie in {range} (got {median})"),
            ));
        }
        if !(beta > 0.0 && beta <= 3.0) {
            return Err(SpecError::at(format!("{at}/beta"), "must lie in (0, 3]"));
        }
        if lo > 0.0 || hi.is_finite() {
            return Err(SpecError::at(
                format!("{at}/dist"),
                format!(
                    "{what} must lie in {range}: a lognormal reaches from 0 to ∞; use a truncated normal or a uniform"
                ),
            ));
        }
        Ok(DistributionNorm::Lognormal { median, beta })
    }

    /// A uniform distribution: min and max in the range, max above min.
    fn uniform(&self, within: &Within) -> Result<DistributionNorm, SpecError> {
        let Within {
            at,
            dist,
            hi,
            what,
            ref range,
            ..
        } = *within;
        within.not_for(&[
            ("mean", self.mean.is_some()),
            ("sd", self.sd.is_some()),
            ("median", self.median.is_some()),
            ("beta", self.beta.is_some()),
        ])?;
        let min = required(self.min, at, "min", dist)?;
        let max = required(self.max, at, "max", dist)?;
        if !within.inside(min) {
            return Err(SpecError::at(
                format!("{at}/min"),
                format!("{what} must lie in {range} (got {min})"),
            ));
        }
        if !(max > min && max <= hi) {
            return Err(SpecError::at(
                format!("{at}/max"),
                format!("must exceed min and lie in {range} (got {max})"),
            ));
        }
        Ok(DistributionNorm::Uniform { min, max })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(v: serde_json::Value) -> DistributionSpec {
        serde_json::from_value(v).expect("shape")
    }

    #[test]
    fn every_sample_valid_or_the_field_named() {
        let positive = (0.0, f64::INFINITY);
        let ok = spec(serde_json::json!({"dist": "lognormal", "median": 1e4, "beta": 0.3}));
        assert!(ok.validate("/age_years", positive, true, "an age").is_ok());
        for (v, pointer) in [
            (
                serde_json::json!({"dist": "normal", "mean": 1e4, "sd": 2e3}),
                "/age_years/min",
            ),
            (
                serde_json::json!({"dist": "normal", "mean": 1e4, "sd": 0.0}),
                "/age_years/sd",
            ),
            (
                serde_json::json!({"dist": "uniform", "min": -1.0, "max": 2.0}),
                "/age_years/min",
            ),
            (
                serde_json::json!({"dist": "uniform", "min": 3.0, "max": 2.0}),
                "/age_years/max",
            ),
            (
                serde_json::json!({"dist": "lognormal", "median": 1.0}),
                "/age_years/beta",
            ),
            (
                serde_json::json!({"dist": "lognormal", "median": 1.0, "beta": 0.2, "sd": 1.0}),
                "/age_years/sd",
            ),
            (serde_json::json!({"dist": "gamma"}), "/age_years/dist"),
            (serde_json::json!({"mean": 1.0}), "/age_years/dist"),
        ] {
            let e = spec(v.clone())
                .validate("/age_years", positive, true, "an age")
                .expect_err("refused");
            assert_eq!(e.pointer, pointer, "{v}: {}", e.message);
        }
        // Truncated at 0 (excluded): min 0 is not enough for an open range.
        let e = spec(serde_json::json!({"dist": "normal", "mean": 0.2, "sd": 0.05, "min": 0.0}))
            .validate(
                "/block/alpha",
                (0.0, std::f64::consts::FRAC_PI_2),
                true,
                "α",
            )
            .expect_err("refused");
        assert_eq!(e.pointer, "/block/alpha/min");
        let ok = spec(
            serde_json::json!({"dist": "normal", "mean": 0.2, "sd": 0.05, "min": 0.01, "max": 1.5}),
        );
        assert!(
            ok.validate(
                "/block/alpha",
                (0.0, std::f64::consts::FRAC_PI_2),
                true,
                "α"
            )
            .is_ok()
        );
    }
}
