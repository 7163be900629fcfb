//! Stored records named by job specs: `"ground_motion": {"record": "<id>"}`
//! (and each of a fragility suite's `ground_motions`) is replaced by the
//! record's samples, so that a spec naming a record is the same computation
//! — the same canonical spec and cache key — as the spec embedding them.

use serde_json::{Value, json};

use crate::jobs::SpecError;
use crate::store::{JobStore, StoreError};

/// Why a spec's records could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ResolveError {
    /// The spec names a record wrongly (no such record of the tenant, a
    /// record beside samples, a file).
    #[error(transparent)]
    Invalid(#[from] SpecError),
    /// The store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// Where a spec may hold records: its `ground_motion`, and each of
/// `ground_motions`.
fn record_slots(spec: &Value) -> Vec<String> {
    let mut at = Vec::new();
    if spec.get("ground_motion").is_some_and(Value::is_object) {
        at.push("/ground_motion".to_string());
    }
    if let Some(list) = spec.get("ground_motions").and_then(Value::as_array) {
        at.extend(
            (0..list.len())
                .filter(|i| list[*i].is_object())
                .map(|i| format!("/ground_motions/{i}")),
        );
    }
    at
}

/// Fields a record named by id may have beside `record`: a suite's member
/// its `name`, a time history's record its `vertical` acceleration (kept as
/// given).
const BESIDE_RECORD: [&str; 3] = ["record", "name", "vertical"];

/// The tenant's records named in `spec` read into it; returns the spec and
/// the ids named (in order, without repeats). A `file` is refused: only
/// `topple run` reads files.
pub async fn resolve(
    store: &dyn JobStore,
    tenant: &str,
    mut spec: Value,
) -> Result<(Value, Vec<String>), ResolveError> {
    let mut named = Vec::new();
    for at in record_slots(&spec) {
        let Some(slot) = spec.pointer(&at) else {
            continue;
        };
        // A field set to null is absent (as serde reads it).
        let given = |k: &str| slot.get(k).filter(|v| !v.is_null());
        if given("file").is_some() {
            return Err(SpecError::at(
                format!("{at}/file"),
                "a file is read by `topple run` only: upload it (POST /v1/records) and name it with {\"record\": id}",
            )
            .into());
        }
        let Some(id) = given("record") else {
            continue;
        };
        let id = id
            .as_str()
            .filter(|s| is_record_id(s))
            .ok_or_else(|| {
                SpecError::at(
                    format!("{at}/record"),
                    "must be a record id: 32 hexadecimal digits, as POST /v1/records answers",
                )
            })?
            .to_string();
        if let Some(other) = slot.as_object().and_then(|o| {
            o.iter()
                .find(|(k, v)| !v.is_null() && !BESIDE_RECORD.contains(&k.as_str()))
                .map(|(k, _)| k)
        }) {
            return Err(SpecError::at(
                format!("{at}/{other}"),
                "a stored record brings its own samples, dt and unit: name it with {\"record\": id} alone",
            )
            .into());
        }
        if given("name").is_some() && at == "/ground_motion" {
            return Err(SpecError::at(
                format!("{at}/name"),
                "unknown field `name`: a stored record keeps the name it was uploaded with",
            )
            .into());
        }
        let row = store.get_record(tenant, &id).await?;
        let samples = store.record_samples(tenant, &id).await?;
        let (Some(row), Some((dt, acc))) = (row, samples) else {
            return Err(SpecError::at(
                format!("{at}/record"),
                format!("no record {id}: upload it first (POST /v1/records); GET /v1/records lists yours"),
            )
            .into());
        };
        // A suite's member is named: as the spec names it, or as the record
        // was uploaded.
        let name = at
            .starts_with("/ground_motions/")
            .then(|| given("name").cloned().unwrap_or(Value::String(row.name)));
        let vertical = given("vertical").cloned();
        let pga_g = acc.iter().fold(0.0f64, |m, a| m.max(a.abs())) / crate::records::G_M_S2;
        let replacement = tokio::task::spawn_blocking(move || {
            let mut motion = json!({"dt": dt, "acc": acc, "unit": "m/s2"});
            // The stored record passed the PGA check when it was uploaded.
            if pga_g > crate::records::PGA_IMPLAUSIBLE_G {
                motion["allow_large_pga"] = Value::Bool(true);
            }
            if let Some(name) = name {
                motion["name"] = name;
            }
            if let Some(vertical) = vertical {
                motion["vertical"] = vertical;
            }
            motion
        })
        .await
        .map_err(|e| StoreError::Corrupt(format!("reading record {id} stopped: {e}")))?;
        if let Some(slot) = spec.pointer_mut(&at) {
            *slot = replacement;
        }
        if !named.contains(&id) {
            named.push(id);
        }
    }
    Ok((spec, named))
}

/// Whether `s` is a record id: 32 lowercase hexadecimal digits.
pub fn is_record_id(s: &str) -> bool {
    s.len() == 32 && s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}
