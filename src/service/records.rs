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
        let Some(row) = row else {
            return Err(unknown(&at, &id).into());
        };
        let mut motion = stored_motion(store, tenant, &id, &at).await?;
        // A suite's member is named: as the spec names it, or as the record
        // was uploaded.
        if at.starts_with("/ground_motions/") {
            motion["name"] = given("name").cloned().unwrap_or(Value::String(row.name));
        }
        if let Some(vertical) = given("vertical").cloned() {
            motion["vertical"] = vertical;
        }
        let replacement = motion;
        if let Some(slot) = spec.pointer_mut(&at) {
            *slot = replacement;
        }
        if !named.contains(&id) {
            named.push(id);
        }
    }
    for at in record_slots(&spec) {
        if let Some(id) =
            resolve_vertical(store, tenant, &mut spec, &format!("{at}/vertical")).await?
            && !named.contains(&id)
        {
            named.push(id);
        }
    }
    Ok((spec, named))
}

/// The stored record named as a record's vertical acceleration at `at`
/// (`"ground_motion": {…, "vertical": {"record": id}}`, or a suite member's)
/// read into the spec as its samples on their own dt (another dt than the
/// horizontal record's is refused when the spec is validated, at
/// `…/vertical/dt`); returns the id named. A `file` is refused, as beside a
/// horizontal record.
async fn resolve_vertical(
    store: &dyn JobStore,
    tenant: &str,
    spec: &mut Value,
    at: &str,
) -> Result<Option<String>, ResolveError> {
    let Some(slot) = spec.pointer(at).and_then(Value::as_object) else {
        return Ok(None);
    };
    let given = |k: &str| slot.get(k).filter(|v| !v.is_null());
    if given("file").is_some() {
        return Err(SpecError::at(
            format!("{at}/file"),
            "a file is read by `topple run` only: upload it (POST /v1/records) and name it with {\"record\": id}",
        )
        .into());
    }
    let Some(id) = given("record") else {
        return Ok(None);
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
    if let Some(other) = slot
        .iter()
        .find(|(k, v)| !v.is_null() && k.as_str() != "record")
        .map(|(k, _)| k)
    {
        return Err(SpecError::at(
            format!("{at}/{other}"),
            "a stored record brings its own samples, dt and unit: name it with {\"record\": id} alone",
        )
        .into());
    }
    if store.get_record(tenant, &id).await?.is_none() {
        return Err(unknown(at, &id).into());
    }
    let motion = stored_motion(store, tenant, &id, at).await?;
    if let Some(slot) = spec.pointer_mut(at) {
        *slot = motion;
    }
    Ok(Some(id))
}

/// No record `id` of the tenant, named at `at`.
fn unknown(at: &str, id: &str) -> SpecError {
    SpecError::at(
        format!("{at}/record"),
        format!("no record {id}: upload it first (POST /v1/records); GET /v1/records lists yours"),
    )
}

/// The samples of the tenant's stored record `id` (named at `at`) as a
/// spec holds them: `{"dt", "acc", "unit": "m/s2"}`, with
/// `allow_large_pga` when its PGA is above the plausible (the stored record
/// passed that check when it was uploaded).
async fn stored_motion(
    store: &dyn JobStore,
    tenant: &str,
    id: &str,
    at: &str,
) -> Result<Value, ResolveError> {
    let Some((dt, acc)) = store.record_samples(tenant, id).await? else {
        return Err(unknown(at, id).into());
    };
    let pga_g = acc.iter().fold(0.0f64, |m, a| m.max(a.abs())) / crate::records::G_M_S2;
    let id = id.to_string();
    tokio::task::spawn_blocking(move || {
        let mut motion = json!({"dt": dt, "acc": acc, "unit": "m/s2"});
        if pga_g > crate::records::PGA_IMPLAUSIBLE_G {
            motion["allow_large_pga"] = Value::Bool(true);
        }
        motion
    })
    .await
    .map_err(|e| StoreError::Corrupt(format!("reading record {id} stopped: {e}")).into())
}

/// Whether `s` is a record id: 32 lowercase hexadecimal digits.
pub fn is_record_id(s: &str) -> bool {
    s.len() == 32 && s.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}
