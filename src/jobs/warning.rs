//! A note on a result: what every kind's `warnings` holds.

use serde::{Deserialize, Serialize};

/// A note on a result.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct WarningDoc {
    /// "sliding" | "lift_off" | "demand_excludes_fall" | "free_rocking_truncated" |
    /// "impact_list_truncated" | "near_separatrix" | "implausible_size".
    #[schema(value_type = crate::jobs::schema::WarningKind)]
    pub kind: String,
    /// When it happens, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    /// Explanation.
    pub message: String,
}
