//! The numerics report attached to every result.

use serde::{Deserialize, Serialize};

use crate::dynamics::response::Numerics;

/// Method, tolerances, cost and error of a computation.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct NumericsDoc {
    /// "exact" | "dopri5" | "dop853".
    #[schema(value_type = crate::jobs::schema::MethodName)]
    pub method: String,
    /// Relative tolerance.
    #[schema(required = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance.
    #[schema(required = true)]
    pub atol: Option<f64>,
    /// Accepted steps (closed-form segments for exact).
    pub steps_accepted: u64,
    /// Rejected steps.
    pub steps_rejected: u64,
    /// Right-hand-side evaluations (0 for exact).
    pub rhs_evaluations: u64,
    /// Events located (rocking starts, impacts, pulse ends, overturning).
    pub events: u64,
    /// Estimated error in θ, rad.
    pub error_estimate: f64,
    /// Wall time, s.
    pub wall_time_s: f64,
}

impl From<&Numerics> for NumericsDoc {
    fn from(n: &Numerics) -> Self {
        NumericsDoc {
            method: n.method.to_string(),
            rtol: n.rtol,
            atol: n.atol,
            steps_accepted: n.steps_accepted,
            steps_rejected: n.steps_rejected,
            rhs_evaluations: n.rhs_evaluations,
            events: n.events,
            error_estimate: n.error_estimate,
            wall_time_s: n.wall_time,
        }
    }
}
