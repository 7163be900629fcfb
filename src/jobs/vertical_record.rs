//! The vertical acceleration inside a record, as given and normalised
//! (`"ground_motion": {…, "vertical": {"ratio": r}, samples, a stored
//! record by id or a file}`); validated by [`super::vertical`].

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::names::tag;

/// The vertical acceleration of a record (positive up): `{"ratio": r}`, or
/// samples taken with the horizontal record's `dt` (the shorter of the two
/// is padded with zeros), given as `acc` and `unit`, as a stored record's id
/// (`record`; the service reads it) or as a file (`file`; `topple run`
/// reads it).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct VerticalRecordSpec {
    /// ü_v/ü_g (−100 to 100; 0 is no vertical motion). Alone.
    #[schema(minimum = -100.0, maximum = 100.0)]
    pub ratio: Option<f64>,
    /// Sampling interval, s: the horizontal record's (default; another is refused).
    #[schema(minimum = 1e-5, maximum = 1.0)]
    pub dt: Option<f64>,
    /// Accelerations at t_k = k·dt, positive up.
    #[schema(min_items = 2, max_items = 1_000_000)]
    pub acc: Option<Vec<f64>>,
    /// Unit of `acc`: "g" | "m/s2" | "cm/s2" (also "gal").
    #[schema(value_type = Option<crate::jobs::schema::UnitInput>)]
    pub unit: Option<String>,
    /// The samples' PGA above 5 g in their unit is intended.
    pub allow_large_pga: Option<bool>,
    /// A stored record (`POST /v1/records`), by id, instead of the samples:
    /// the same computation as the spec holding its samples (its dt must be
    /// the horizontal record's).
    #[schema(pattern = "^[0-9a-f]{32}$")]
    pub record: Option<String>,
    /// A record file read by `topple run` (offline only; the service refuses
    /// it): `{"file": "path", "format"?, "unit"?, "dt"?, "time_column"?,
    /// "acc_column"?}` as for `topple record`.
    pub file: Option<String>,
}

/// The vertical acceleration of a record, normalised: a ratio, or samples
/// in m/s² on the horizontal record's dt.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct VerticalRecordNorm {
    /// ü_v/ü_g.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// Sampling interval, s (the horizontal record's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Accelerations, m/s².
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "serialize_samples",
        deserialize_with = "deserialize_samples"
    )]
    #[schema(value_type = Option<Vec<f64>>)]
    pub acc: Option<Arc<[f64]>>,
    /// "m/s2" with samples.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::schema::MetresPerSecondSquared>)]
    pub unit: Option<tag::MetresPerSecondSquared>,
}

fn serialize_samples<S: serde::Serializer>(
    v: &Option<Arc<[f64]>>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match v {
        Some(v) => s.collect_seq(v.iter()),
        None => s.serialize_none(),
    }
}

fn deserialize_samples<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<Arc<[f64]>>, D::Error> {
    Option::<Vec<f64>>::deserialize(d).map(|v| v.map(Arc::from))
}
