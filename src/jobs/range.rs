//! A list of values given as `{"from", "to", "steps"}`, a list, or one number.

use serde::{Deserialize, Serialize};

use super::spec::SpecError;

/// Values as users write them.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(untagged)]
pub enum RangeSpec {
    /// `steps` evenly spaced values from `from` to `to` inclusive.
    Even {
        /// First value.
        #[schema(exclusive_minimum = 0.0)]
        from: f64,
        /// Last value (at least `from`).
        #[schema(exclusive_minimum = 0.0)]
        to: f64,
        /// Number of values (≥ 1).
        #[schema(minimum = 1)]
        steps: usize,
    },
    /// Explicit values.
    #[schema(value_type = Vec<crate::jobs::schema::PositiveNumber>)]
    List(Vec<f64>),
    /// One value.
    #[schema(value_type = crate::jobs::schema::PositiveNumber)]
    One(f64),
}

impl RangeSpec {
    /// Expands to values, each checked to lie in `[lo, hi]`, at most `max` of them.
    pub fn values(
        &self,
        pointer: &str,
        lo: f64,
        hi: f64,
        max: usize,
    ) -> Result<Vec<f64>, SpecError> {
        let values = match self {
            RangeSpec::Even { from, to, steps } => {
                if *steps == 0 || *steps > max {
                    return Err(SpecError::at(
                        format!("{pointer}/steps"),
                        format!("must satisfy 1 <= steps <= {max}"),
                    ));
                }
                if !(from.is_finite() && to.is_finite()) || to < from {
                    return Err(SpecError::at(
                        pointer,
                        "from and to must be finite with from <= to",
                    ));
                }
                if *steps == 1 {
                    vec![*from]
                } else {
                    (0..*steps)
                        .map(|k| from + (to - from) * k as f64 / (*steps - 1) as f64)
                        .collect()
                }
            }
            RangeSpec::List(v) => {
                if v.is_empty() || v.len() > max {
                    return Err(SpecError::at(
                        pointer,
                        format!("give between 1 and {max} values"),
                    ));
                }
                v.clone()
            }
            RangeSpec::One(x) => vec![*x],
        };
        for (i, &v) in values.iter().enumerate() {
            if !(v.is_finite() && v >= lo && v <= hi) {
                let at = match self {
                    RangeSpec::List(_) => format!("{pointer}/{i}"),
                    _ => pointer.to_string(),
                };
                return Err(SpecError::at(
                    at,
                    format!("values must lie in [{lo}, {hi}] (got {v})"),
                ));
            }
        }
        Ok(values)
    }
}
