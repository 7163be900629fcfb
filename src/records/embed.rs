//! Records named by file in a spec run offline (`topple run`):
//! `"ground_motion": {"file": "path", "unit"?, "dt"?, …}` read as
//! `topple record` reads it and replaced by its samples, so the spec is the
//! same computation as one holding them. The reading of files is the
//! caller's (this module does no I/O).

use serde_json::{Value, json};

use super::ReadError;
use super::{OptionTexts, RecordWarning, read};

/// The options a `file` object may carry beside it, as `topple record`'s flags.
const FILE_OPTIONS: [&str; 9] = [
    "file",
    "format",
    "unit",
    "dt",
    "time_column",
    "acc_column",
    "name",
    "allow_large_pga",
    "record_name",
];

/// Where a time history's record holds its vertical acceleration.
const VERTICAL: &str = "/ground_motion/vertical";

/// Reads every `{"file": …}` of `spec`'s `ground_motion` (and of its
/// `vertical` acceleration) and `ground_motions` with `read_file` and puts
/// its samples (m/s²) in its place; returns the records' warnings, each
/// prefixed with where it was. An error's `field` is the JSON pointer into
/// `spec` of what is at fault.
pub fn embed_files(
    spec: &mut Value,
    read_file: impl Fn(&str) -> Result<String, String>,
) -> Result<Vec<(String, RecordWarning)>, ReadError> {
    let mut slots = Vec::new();
    if spec.get("ground_motion").is_some_and(Value::is_object) {
        slots.push("/ground_motion".to_string());
        // Read after the horizontal record (whose `vertical` it keeps).
        slots.push(VERTICAL.to_string());
    }
    if let Some(list) = spec.get("ground_motions").and_then(Value::as_array) {
        slots.extend((0..list.len()).map(|i| format!("/ground_motions/{i}")));
    }
    let mut warnings = Vec::new();
    for at in slots {
        let Some(slot) = spec.pointer(&at).and_then(Value::as_object) else {
            continue;
        };
        let Some(path) = slot.get("file") else {
            continue;
        };
        let path = path
            .as_str()
            .ok_or_else(|| ReadError::new(format!("{at}/file"), "must be a path (a string)"))?;
        // Beside a time history's record file: its vertical acceleration
        // (kept as given); beside a vertical one: no name.
        let allowed = |k: &str| match at.as_str() {
            "/ground_motion" => FILE_OPTIONS.contains(&k) || k == "vertical",
            VERTICAL => FILE_OPTIONS.contains(&k) && !matches!(k, "name" | "record_name"),
            _ => FILE_OPTIONS.contains(&k),
        };
        if let Some(other) = slot.keys().find(|k| !allowed(k)) {
            let options: Vec<&str> = FILE_OPTIONS[1..8]
                .iter()
                .copied()
                .filter(|k| allowed(k))
                .collect();
            return Err(ReadError::new(
                format!("{at}/{other}"),
                format!(
                    "a file brings its own samples: beside `file` give only {}",
                    options.join(", ")
                ),
            ));
        }
        let text_of = |k: &str| -> Result<Option<&str>, ReadError> {
            match slot.get(k) {
                None | Some(Value::Null) => Ok(None),
                Some(Value::String(s)) => Ok(Some(s.as_str())),
                Some(_) => Err(ReadError::new(format!("{at}/{k}"), "must be a string")),
            }
        };
        let dt = match slot.get("dt") {
            None | Some(Value::Null) => None,
            Some(v) => Some(
                v.as_f64()
                    .ok_or_else(|| ReadError::new(format!("{at}/dt"), "must be a number (s)"))?,
            ),
        };
        let column = |k: &str| -> Result<Option<String>, ReadError> {
            match slot.get(k) {
                None | Some(Value::Null) => Ok(None),
                Some(Value::String(s)) => Ok(Some(s.clone())),
                Some(Value::Number(n)) => Ok(Some(n.to_string())),
                Some(_) => Err(ReadError::new(
                    format!("{at}/{k}"),
                    "a column number from 1 or a header name",
                )),
            }
        };
        let (time_column, acc_column) = (column("time_column")?, column("acc_column")?);
        let allow_large_pga = slot
            .get("allow_large_pga")
            .and_then(Value::as_bool)
            .unwrap_or(false);
        let opts = OptionTexts {
            format: text_of("format")?,
            unit: text_of("unit")?,
            dt,
            time_column: time_column.as_deref(),
            acc_column: acc_column.as_deref(),
            name: None,
            allow_large_pga,
        }
        .read()
        .map_err(|e| ReadError::new(format!("{at}/{}", e.field), e.message))?;
        let text = read_file(path).map_err(|e| {
            ReadError::new(format!("{at}/file"), format!("cannot read {path:?}: {e}"))
        })?;
        let file = read(&text, &opts).map_err(|e| {
            let field = if e.field == "body" {
                "file".to_string()
            } else {
                e.field.trim_start_matches('/').to_string()
            };
            let line = e.line.map(|l| format!("line {l}: ")).unwrap_or_default();
            ReadError::new(
                format!("{at}/{field}"),
                format!("{path}: {line}{}", e.message),
            )
        })?;
        let mut motion = json!({"dt": file.dt, "acc": file.acc, "unit": "m/s2"});
        if allow_large_pga {
            motion["allow_large_pga"] = Value::Bool(true);
        }
        if let Some(vertical) = slot.get("vertical").filter(|_| at == "/ground_motion") {
            motion["vertical"] = vertical.clone();
        }
        if at.starts_with("/ground_motions/") {
            motion["name"] = slot
                .get("name")
                .cloned()
                .unwrap_or_else(|| Value::String(file.name.clone()));
        }
        warnings.extend(file.warnings.into_iter().map(|w| (at.clone(), w)));
        if let Some(s) = spec.pointer_mut(&at) {
            *s = motion;
        }
    }
    Ok(warnings)
}
