//! Records in JSON: a job spec's `ground_motion` object with a name,
//! `{"name": "…", "dt": 0.01, "unit": "g", "acc": [0.001, -0.002, …]}`.
//!
//! The accelerations are read from their number tokens' text, not from an
//! `f64` that serde parsed, so that cm/s² convert exactly (see
//! [`number`](super::number)) as they do in the other formats.

use serde::de::{self, Deserialize, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::value::RawValue;

use super::MAX_RECORD_SAMPLES;
use super::number;
use super::text::clip;
use super::unit::{ACCEPTED_UNITS, Unit};
use super::{MAX_NAME_CHARS, Parsed, ReadError, ReadOptions};

/// The members a record object may have.
const FIELDS: [&str; 4] = ["name", "dt", "unit", "acc"];

/// The members of the top-level object, in order, values unparsed.
struct Members<'a>(Vec<(String, &'a RawValue)>);

impl<'de> Deserialize<'de> for Members<'de> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct MembersVisitor;
        impl<'de> Visitor<'de> for MembersVisitor {
            type Value = Members<'de>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(r#"an object {"name", "dt", "unit", "acc"}"#)
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Members<'de>, A::Error> {
                let mut members = Vec::new();
                while let Some(member) = map.next_entry::<String, &'de RawValue>()? {
                    members.push(member);
                }
                Ok(Members(members))
            }
        }
        deserializer.deserialize_map(MembersVisitor)
    }
}

/// The `acc` array's elements, unparsed, stopping past the largest record.
struct Elements<'a> {
    items: Vec<&'a RawValue>,
    too_many: bool,
}

impl<'de> Visitor<'de> for &mut Elements<'de> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("an array of numbers")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while let Some(item) = seq.next_element::<&'de RawValue>()? {
            if self.items.len() == MAX_RECORD_SAMPLES {
                self.too_many = true;
                return Err(de::Error::custom("too many samples"));
            }
            self.items.push(item);
        }
        Ok(())
    }
}

impl<'de> DeserializeSeed<'de> for &mut Elements<'de> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_seq(self)
    }
}

/// A member's JSON kind, for messages.
fn kind(value: &RawValue) -> &'static str {
    match value.get().as_bytes().first() {
        Some(b'"') => "a string",
        Some(b'{') => "an object",
        Some(b'[') => "an array",
        Some(b't' | b'f') => "a boolean",
        Some(b'n') => "null",
        _ => "a number",
    }
}

/// Whether `value` is a JSON number (serde_json has checked its grammar).
fn is_number(value: &RawValue) -> bool {
    matches!(value.get().as_bytes().first(), Some(b'-' | b'0'..=b'9'))
}

/// The record's four fields among `members` (name, dt, unit, acc; null
/// taken as absent), each given at most once and no other.
fn fields<'a>(members: &[(String, &'a RawValue)]) -> Result<[Option<&'a RawValue>; 4], ReadError> {
    let mut found: [Option<&RawValue>; 4] = [None; 4];
    for (key, value) in members {
        let pointer = format!("/{}", key.replace('~', "~0").replace('/', "~1"));
        let Some(slot) = FIELDS.iter().position(|f| f == key) else {
            return Err(ReadError::new(
                pointer,
                format!("unknown field {key:?}: a record has only name, dt, unit and acc"),
            ));
        };
        if found[slot].is_some() {
            return Err(ReadError::new(pointer, "given twice"));
        }
        // null is absent, as in a job spec.
        if value.get() != "null" {
            found[slot] = Some(value);
        }
    }
    Ok(found)
}

/// The record's name: the string `name`, clipped.
fn name_of(name: Option<&RawValue>) -> Result<Option<String>, ReadError> {
    Ok(match name {
        None => None,
        Some(v) => match serde_json::from_str::<String>(v.get()) {
            Ok(s) => Some(clip(&s, MAX_NAME_CHARS)),
            Err(_) => {
                return Err(ReadError::new(
                    "/name",
                    format!("must be a string, not {}", kind(v)),
                ));
            }
        },
    })
}

/// The time step: the file's `dt` (agreeing with the option if given
/// too), or the option's.
fn dt_of(dt: Option<&RawValue>, opts: &ReadOptions) -> Result<f64, ReadError> {
    Ok(match (dt, opts.dt) {
        (Some(v), option) => {
            let dt = is_number(v)
                .then(|| number::parse(v.get()))
                .flatten()
                .ok_or_else(|| {
                    ReadError::new("/dt", format!("must be a number (s), not {}", kind(v)))
                })?;
            super::check_dt(dt).map_err(|m| ReadError::new("/dt", m))?;
            super::agree_dt(option, dt, "the file's dt")?;
            dt
        }
        (None, Some(option)) => option,
        (None, None) => {
            return Err(ReadError::new(
                "/dt",
                "missing: the time step in seconds (or give the dt option)",
            ));
        }
    })
}

/// The unit of the accelerations: the file's `unit` (agreeing with the
/// option if given too), or the option's.
fn unit_of(unit: Option<&RawValue>, opts: &ReadOptions) -> Result<Unit, ReadError> {
    Ok(match (unit, opts.unit) {
        (Some(v), option) => {
            let text = serde_json::from_str::<String>(v.get()).map_err(|_| {
                ReadError::new("/unit", format!("must be a string, not {}", kind(v)))
            })?;
            let stated = Unit::parse(&text).ok_or_else(|| {
                ReadError::new(
                    "/unit",
                    format!("unknown unit {text:?}: expected one of {ACCEPTED_UNITS}"),
                )
            })?;
            super::agree_unit(option, stated, "the file's unit")?;
            stated
        }
        (None, Some(option)) => option,
        (None, None) => {
            return Err(ReadError::new(
                "/unit",
                format!(
                    "missing: the unit of acc, one of {ACCEPTED_UNITS} (or give the unit option)"
                ),
            ));
        }
    })
}

/// The accelerations of the array `acc` in `unit`, in m/s²: every element
/// a finite number.
fn acc_of(acc: Option<&RawValue>, unit: Unit) -> Result<Vec<f64>, ReadError> {
    let acc_raw = acc
        .ok_or_else(|| ReadError::new("/acc", "missing: the accelerations, an array of numbers"))?;
    let mut elements = Elements {
        items: Vec::new(),
        too_many: false,
    };
    let mut deserializer = serde_json::Deserializer::from_str(acc_raw.get());
    if let Err(e) = (&mut elements).deserialize(&mut deserializer) {
        return Err(if elements.too_many {
            super::too_many()
        } else {
            ReadError::new(
                "/acc",
                format!("must be an array of numbers, not {} ({e})", kind(acc_raw)),
            )
        });
    }
    let mut buffer = String::new();
    let mut samples = Vec::with_capacity(elements.items.len());
    for (k, v) in elements.items.iter().enumerate() {
        let a = is_number(v)
            .then(|| number::acceleration(v.get(), unit, &mut buffer))
            .flatten()
            .ok_or_else(|| {
                ReadError::new(
                    format!("/acc/{k}"),
                    format!("must be a number, not {}", kind(v)),
                )
            })?;
        if !a.is_finite() {
            return Err(ReadError::new(
                format!("/acc/{k}"),
                format!("{} is too large to be an acceleration", v.get()),
            ));
        }
        samples.push(a);
    }
    Ok(samples)
}

/// Reads a JSON record.
pub(super) fn read(text: &str, opts: &ReadOptions) -> Result<Parsed, ReadError> {
    let Members(members) = serde_json::from_str(text).map_err(|e| {
        ReadError::body(
            Some(e.line()).filter(|&l| l > 0),
            format!(
                "not a JSON record object ({e}): expected {{\"name\", \"dt\", \"unit\", \"acc\"}}"
            ),
        )
    })?;
    let [name, dt, unit, acc] = fields(&members)?;
    let name = name_of(name)?;
    let dt = dt_of(dt, opts)?;
    let unit = unit_of(unit, opts)?;
    Ok(Parsed {
        name,
        unit,
        dt,
        acc: acc_of(acc, unit)?,
        warnings: Vec::new(),
        flat: true,
    })
}

#[cfg(test)]
mod tests {
    use super::super::{Format, ReadOptions, read};
    use super::*;

    #[test]
    fn a_ground_motion_object_with_a_name_reads() {
        let text =
            r#"{"name": "El Centro", "dt": 0.01, "unit": "g", "acc": [0.01, -0.02, 0.03, 0]}"#;
        let r = read(text, &ReadOptions::default()).expect("reads");
        assert_eq!(r.format, Format::Json);
        assert_eq!(
            (r.name.as_str(), r.dt, r.unit),
            ("El Centro", 0.01, Unit::G)
        );
        assert_eq!(r.acc, vec![0.01 * 9.81, -0.02 * 9.81, 0.03 * 9.81, 0.0]);
    }

    #[test]
    fn centimetres_in_json_convert_in_the_text() {
        let text = "{\"dt\": 0.02, \"unit\": \"cm/s2\", \"acc\": [1.23, -4.5e0, 0.7]}";
        let r = read(text, &ReadOptions::default()).expect("reads");
        assert_eq!(r.acc, vec![0.0123, -0.045, 0.007]);
        assert_eq!(r.name, "record");
    }

    #[test]
    fn unknown_fields_are_refused_naming_them() {
        let text = r#"{"dt": 0.01, "unit": "g", "acc": [0.1, 0.2], "units": "g"}"#;
        let e = read(text, &ReadOptions::default()).expect_err("refused");
        assert_eq!(e.field, "/units");
        assert!(e.message.contains("\"units\""), "{}", e.message);
        let slash = r#"{"a/b": 1, "dt": 0.01, "unit": "g", "acc": [0.1, 0.2]}"#;
        assert_eq!(
            read(slash, &ReadOptions::default())
                .expect_err("refused")
                .field,
            "/a~1b"
        );
        let twice = r#"{"dt": 0.01, "dt": 0.02, "unit": "g", "acc": [0.1, 0.2]}"#;
        assert_eq!(
            read(twice, &ReadOptions::default())
                .expect_err("refused")
                .field,
            "/dt"
        );
    }

    #[test]
    fn a_non_number_sample_is_refused_by_its_pointer() {
        let text = r#"{"dt": 0.01, "unit": "g", "acc": [0.1, 0.2, 0.3, "0.4"]}"#;
        let e = read(text, &ReadOptions::default()).expect_err("refused");
        assert_eq!(e.field, "/acc/3");
        assert!(e.message.contains("a string"), "{}", e.message);
        let huge = r#"{"dt": 0.01, "unit": "g", "acc": [0.1, 1e999]}"#;
        assert_eq!(
            read(huge, &ReadOptions::default())
                .expect_err("refused")
                .field,
            "/acc/1"
        );
        let not_array = r#"{"dt": 0.01, "unit": "g", "acc": {"x": 1}}"#;
        assert_eq!(
            read(not_array, &ReadOptions::default())
                .expect_err("refused")
                .field,
            "/acc"
        );
    }

    #[test]
    fn options_fill_in_and_must_agree() {
        let text = r#"{"acc": [0.1, -0.2, 0.1]}"#;
        let e = read(text, &ReadOptions::default()).expect_err("no dt");
        assert_eq!(e.field, "/dt");
        let opts = ReadOptions {
            dt: Some(0.01),
            unit: Some(Unit::MetresPerSecondSquared),
            ..ReadOptions::default()
        };
        assert_eq!(read(text, &opts).expect("reads").acc, vec![0.1, -0.2, 0.1]);
        let stated = r#"{"dt": 0.01, "unit": "g", "acc": [0.1, -0.2, 0.1]}"#;
        assert_eq!(read(stated, &opts).expect_err("refused").field, "unit");
        let opts = ReadOptions {
            dt: Some(0.02),
            ..ReadOptions::default()
        };
        assert_eq!(read(stated, &opts).expect_err("refused").field, "dt");
    }

    #[test]
    fn an_unknown_unit_is_refused_with_the_accepted_ones() {
        let text = r#"{"dt": 0.01, "unit": "ft/s2", "acc": [0.1, 0.2]}"#;
        let e = read(text, &ReadOptions::default()).expect_err("refused");
        assert_eq!(e.field, "/unit");
        assert!(e.message.contains("cm/s2"), "{}", e.message);
    }

    #[test]
    fn broken_json_names_its_line() {
        let text = "{\n\"dt\": 0.01,\n\"acc\": [0.1, 0.2,\n";
        let e = read(text, &ReadOptions::default()).expect_err("refused");
        assert_eq!(e.field, "body");
        assert!(e.line.is_some());
    }
}
