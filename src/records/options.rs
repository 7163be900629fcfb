//! The options of a read as users write them — query parameters of an
//! upload, flags of `topple record`, fields beside a spec's `file` — checked
//! once, each refusal naming the option.

use super::{Column, Format, ReadError, ReadOptions, Unit};

/// The options, as text.
#[derive(Clone, Debug, Default)]
pub struct OptionTexts<'a> {
    /// `at2` | `csv` | `json` (also `txt`, `tsv`, `dat`).
    pub format: Option<&'a str>,
    /// `g` | `m/s2` | `cm/s2` and their spellings.
    pub unit: Option<&'a str>,
    /// Sampling interval, s.
    pub dt: Option<f64>,
    /// A 1-based column number or a header name.
    pub time_column: Option<&'a str>,
    /// A 1-based column number or a header name.
    pub acc_column: Option<&'a str>,
    /// The record's name.
    pub name: Option<&'a str>,
    /// A PGA above 5 g is intended.
    pub allow_large_pga: bool,
}

/// Longest option text taken, characters (a name, a column name).
const MAX_OPTION_CHARS: usize = super::MAX_NAME_CHARS;

/// At most 40 characters of `text`, for a message.
fn quoted(text: &str) -> String {
    format!("{:?}", text.chars().take(40).collect::<String>())
}

impl OptionTexts<'_> {
    /// The options read, or the first one that cannot be (named as its
    /// option: `format`, `unit`, `dt`, `time_column`, `acc_column`, `name`).
    pub fn read(&self) -> Result<ReadOptions, ReadError> {
        let format = self
            .format
            .map(|f| {
                Format::parse(f).ok_or_else(|| {
                    ReadError::new(
                        "format",
                        format!("format {}: expected at2, csv (or txt) or json", quoted(f)),
                    )
                })
            })
            .transpose()?;
        let unit = self
            .unit
            .map(|u| {
                Unit::parse(u).ok_or_else(|| {
                    ReadError::new(
                        "unit",
                        format!("unit {}: expected {}", quoted(u), super::ACCEPTED_UNITS),
                    )
                })
            })
            .transpose()?;
        if let Some(dt) = self.dt
            && !(dt.is_finite()
                && (super::RECORD_DT_RANGE.0..=super::RECORD_DT_RANGE.1).contains(&dt))
        {
            return Err(ReadError::new(
                "dt",
                format!(
                    "dt must satisfy {:e} <= dt <= {} (s)",
                    super::RECORD_DT_RANGE.0,
                    super::RECORD_DT_RANGE.1
                ),
            ));
        }
        let column = |field: &'static str, text: Option<&str>| match text {
            None => Ok(None),
            Some(c) if c.trim().is_empty() || c.chars().count() > MAX_OPTION_CHARS => {
                Err(ReadError::new(
                    field,
                    format!("{field} must be a column number from 1 or a header name"),
                ))
            }
            Some(c) => Ok(Some(Column::parse(c))),
        };
        if self
            .name
            .is_some_and(|n| n.chars().count() > MAX_OPTION_CHARS)
        {
            return Err(ReadError::new(
                "name",
                format!("name must be at most {MAX_OPTION_CHARS} characters"),
            ));
        }
        Ok(ReadOptions {
            format,
            unit,
            dt: self.dt,
            time_column: column("time_column", self.time_column)?,
            acc_column: column("acc_column", self.acc_column)?,
            name: self
                .name
                .filter(|n| !n.trim().is_empty())
                .map(str::to_string),
            allow_large_pga: self.allow_large_pga,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_option_that_cannot_be_read_is_named() {
        let field = |o: OptionTexts| o.read().expect_err("refused").field;
        assert_eq!(
            field(OptionTexts {
                format: Some("xls"),
                ..Default::default()
            }),
            "format"
        );
        assert_eq!(
            field(OptionTexts {
                unit: Some("ft/s2"),
                ..Default::default()
            }),
            "unit"
        );
        assert_eq!(
            field(OptionTexts {
                dt: Some(0.0),
                ..Default::default()
            }),
            "dt"
        );
        assert_eq!(
            field(OptionTexts {
                acc_column: Some(" "),
                ..Default::default()
            }),
            "acc_column"
        );
        let long = "x".repeat(MAX_OPTION_CHARS + 1);
        assert_eq!(
            field(OptionTexts {
                name: Some(&long),
                ..Default::default()
            }),
            "name"
        );
        let read = OptionTexts {
            format: Some("CSV"),
            unit: Some("gal"),
            dt: Some(0.01),
            acc_column: Some("2"),
            name: Some("  "),
            ..Default::default()
        }
        .read()
        .expect("reads");
        assert_eq!(read.format, Some(Format::Csv));
        assert_eq!(read.unit, Some(Unit::CentimetresPerSecondSquared));
        assert_eq!(read.acc_column, Some(Column::Index(2)));
        assert_eq!(read.name, None);
    }
}
