//! Records named by file in a spec run offline (`topple run`):
//! `"ground_motion": {"file": "path", "unit"?, "dt"?, …}` read as
//! `topple record` reads it and replaced by its samples, so the spec is the
//! same computation as one holding them. The reading of files is the
//! caller's (this module does no I/O).

use serde_json::{Map, Value, json};

use super::ReadError;
use super::{OptionTexts, ReadOptions, RecordWarning, read};

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

/// Where `spec` may name record files: its `ground_motion` and its
/// vertical acceleration, each record of its `ground_motions` and its
/// vertical component; as JSON pointers, in the order they are read.
fn slots(spec: &Value) -> Vec<String> {
    let mut slots = Vec::new();
    if spec.get("ground_motion").is_some_and(Value::is_object) {
        slots.push("/ground_motion".to_string());
        // Read after the horizontal record (whose `vertical` it keeps).
        slots.push(VERTICAL.to_string());
    }
    if let Some(list) = spec.get("ground_motions").and_then(Value::as_array) {
        // Each suite record, then its own vertical component.
        slots.extend((0..list.len()).flat_map(|i| {
            [
                format!("/ground_motions/{i}"),
                format!("/ground_motions/{i}/vertical"),
            ]
        }));
    }
    slots
}

/// Reads every `{"file": …}` of `spec`'s `ground_motion` (and of its
/// `vertical` acceleration) and `ground_motions` with `read_file` and puts
/// its samples (m/s²) in its place; returns the records' warnings, each
/// prefixed with where it was. An error's `field` is the JSON pointer into
/// `spec` of what is at fault.
pub fn embed_files(
    spec: &mut Value,
    read_file: impl Fn(&str) -> Result<String, String>,
) -> Result<Vec<(String, RecordWarning)>, ReadError> {
    let mut warnings = Vec::new();
    for at in slots(spec) {
        let Some(slot) = spec.pointer(&at).and_then(Value::as_object) else {
            continue;
        };
        let Some(path) = slot.get("file") else {
            continue;
        };
        let path = path
            .as_str()
            .ok_or_else(|| ReadError::new(format!("{at}/file"), "must be a path (a string)"))?;
        let (motion, read) = embedded(slot, &at, path, &read_file)?;
        warnings.extend(read.into_iter().map(|w| (at.clone(), w)));
        if let Some(s) = spec.pointer_mut(&at) {
            *s = motion;
        }
    }
    Ok(warnings)
}

/// The ground motion the record file `path` named at `at` (by `slot`)
/// stands for, read by `read_file` as the options beside it say: its
/// samples in m/s², and the warnings of its reading.
fn embedded(
    slot: &Map<String, Value>,
    at: &str,
    path: &str,
    read_file: &impl Fn(&str) -> Result<String, String>,
) -> Result<(Value, Vec<RecordWarning>), ReadError> {
    // Beside a time history's record file: its vertical acceleration
    // (kept as given); beside a vertical one: no name.
    let is_vertical = at.ends_with("/vertical");
    check_options(slot, at, is_vertical)?;
    let allow_large_pga = slot
        .get("allow_large_pga")
        .and_then(Value::as_bool)
        .unwrap_or(false);
    let opts = read_options(slot, at, allow_large_pga)?;
    let text = read_file(path)
        .map_err(|e| ReadError::new(format!("{at}/file"), format!("cannot read {path:?}: {e}")))?;
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
    if let Some(vertical) = slot.get("vertical").filter(|_| !is_vertical) {
        motion["vertical"] = vertical.clone();
    }
    if at.starts_with("/ground_motions/") && !is_vertical {
        motion["name"] = slot
            .get("name")
            .cloned()
            .unwrap_or_else(|| Value::String(file.name.clone()));
    }
    Ok((motion, file.warnings))
}

/// Refuses anything beside a `file` at `at` but the options of its reading
/// (and, beside a horizontal record, its `vertical`; beside a vertical one,
/// no name).
fn check_options(slot: &Map<String, Value>, at: &str, is_vertical: bool) -> Result<(), ReadError> {
    let allowed = |k: &str| {
        if is_vertical {
            FILE_OPTIONS.contains(&k) && !matches!(k, "name" | "record_name")
        } else {
            FILE_OPTIONS.contains(&k) || k == "vertical"
        }
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
    Ok(())
}

/// The options of reading the file named at `at`, from those beside it.
fn read_options(
    slot: &Map<String, Value>,
    at: &str,
    allow_large_pga: bool,
) -> Result<ReadOptions, ReadError> {
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
    OptionTexts {
        format: text_of("format")?,
        unit: text_of("unit")?,
        dt,
        time_column: time_column.as_deref(),
        acc_column: acc_column.as_deref(),
        name: None,
        allow_large_pga,
    }
    .read()
    .map_err(|e| ReadError::new(format!("{at}/{}", e.field), e.message))
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    /// A two-column CSV (t, acceleration in g) of `n` samples at 0.01 s.
    fn csv(n: usize, scale: f64) -> String {
        let mut text = String::from("t,acc_g\n");
        for k in 0..n {
            let t = k as f64 * 0.01;
            text.push_str(&format!("{t:.4},{:.5}\n", scale * (7.0 * t).sin()));
        }
        text
    }

    #[test]
    fn a_suite_records_vertical_file_is_read_beside_it() {
        let mut spec = json!({"kind": "fragility", "ground_motions": [
            {"file": "h.csv", "name": "one", "vertical": {"file": "v.csv"}},
            {"file": "h.csv"}]});
        let read = |path: &str| -> Result<String, String> {
            match path {
                "h.csv" => Ok(csv(300, 0.3)),
                "v.csv" => Ok(csv(200, -0.2)),
                other => Err(format!("no {other}")),
            }
        };
        super::embed_files(&mut spec, read).expect("reads");
        let first = &spec["ground_motions"][0];
        assert_eq!(first["name"], "one");
        assert_eq!(first["acc"].as_array().map(Vec::len), Some(300));
        let vertical = &first["vertical"];
        assert_eq!(vertical["acc"].as_array().map(Vec::len), Some(200));
        assert_eq!(vertical["dt"], 0.01);
        // In m/s², from g; no name of its own.
        let a = vertical["acc"][1].as_f64().expect("a sample");
        assert!((a - (-0.2f64 * (0.07f64).sin() * 1e5).round() / 1e5 * 9.81).abs() < 1e-12);
        assert_eq!(vertical.get("name"), None);
        assert_eq!(spec["ground_motions"][1].get("vertical"), None);
        // A name beside a vertical file, or a file that cannot be read, is
        // named at its pointer.
        let mut named = json!({"ground_motions": [{"file": "h.csv",
            "vertical": {"file": "v.csv", "name": "v"}}]});
        let e = super::embed_files(&mut named, read).expect_err("refused");
        assert_eq!(e.field, "/ground_motions/0/vertical/name");
        let mut missing = json!({"ground_motions": [{"file": "h.csv",
            "vertical": {"file": "w.csv"}}]});
        let e = super::embed_files(&mut missing, read).expect_err("refused");
        assert_eq!(e.field, "/ground_motions/0/vertical/file");
    }
}
