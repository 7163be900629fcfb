//! Accelerogram files read into records: PEER NGA `.AT2`, delimited or
//! whitespace columns, and JSON in a job spec's `ground_motion` shape.
//!
//! Pure: text in, samples in m/s² out, no I/O. The HTTP upload and the CLI's
//! `topple record FILE` both come here, so a file reads the same either way.
//! Nothing is guessed silently: a unit, a step or a column that the file
//! does not state and the options do not give is refused with the field the
//! user must change; what is read but unlikely to be meant (a PGA of many g,
//! an uncorrected baseline, a header count that disagrees) comes back as a
//! warning with the record.
//!
//! Two uploads of the same motion get the same [`record_id`] whichever
//! format and unit they came in: cm/s² are converted exactly in the text
//! (`number.rs`), g by the same product as a job spec's `"unit": "g"`.

mod at2;
mod columns;
mod embed;
mod format;
mod guards;
mod json;
mod meta;
mod number;
mod options;
mod text;
mod unit;

pub use columns::Column;
pub use embed::embed_files;
pub use format::Format;
pub use guards::{
    PGA_IMPLAUSIBLE_G, PGA_LARGE_G, PgaCheck, baseline_drift, check_pga, looks_interleaved,
    looks_like_time,
};
pub use meta::{RecordMeta, RecordWarningDoc};
pub use options::OptionTexts;
pub use unit::{ACCEPTED_UNITS, Unit};

/// Most samples in a record.
pub const MAX_RECORD_SAMPLES: usize = 1_000_000;
/// Range of a record's sampling interval, s.
pub const RECORD_DT_RANGE: (f64, f64) = (1e-5, 1.0);

/// How a record in g is converted to m/s²: the default block's g, so that
/// a record uploaded in g and the same samples in a job spec in g give the
/// same m/s² samples.
pub const G_M_S2: f64 = crate::dynamics::block::STANDARD_GRAVITY;

/// Relative tolerance within which two time steps agree (an option and the
/// file, or two rows of a time column).
pub const DT_TOLERANCE: f64 = 1e-6;

/// Longest name taken from a file's content, in characters.
pub const MAX_NAME_CHARS: usize = 200;

/// What the caller knows about a file besides its text. Every field is
/// optional: what the file states is used, and what both state must agree.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// The file's format; detected from the content when `None`.
    pub format: Option<Format>,
    /// The unit of the accelerations; needed when the file does not say.
    pub unit: Option<Unit>,
    /// The time step, s; needed for a file with no time column or header.
    pub dt: Option<f64>,
    /// Which column holds time (columns only).
    pub time_column: Option<Column>,
    /// Which column holds acceleration (columns only; needed with more
    /// than two).
    pub acc_column: Option<Column>,
    /// The record's name, instead of the one in the file.
    pub name: Option<String>,
    /// Keep a record whose PGA exceeds [`PGA_IMPLAUSIBLE_G`] (with a
    /// warning) instead of refusing it as a unit read wrongly.
    pub allow_large_pga: bool,
}

/// A record read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordFile {
    /// The name: the option, else the file's (AT2 event line, first comment
    /// line, JSON `name`), else `record`.
    pub name: String,
    /// The format read.
    pub format: Format,
    /// The unit the values were written in (as given or stated).
    pub unit: Unit,
    /// Time step, s.
    pub dt: f64,
    /// Accelerations, m/s².
    pub acc: Vec<f64>,
    /// What was read but may not be meant, and what to do about it.
    pub warnings: Vec<RecordWarning>,
}

impl RecordFile {
    /// The record's content address ([`record_id`]).
    pub fn id(&self) -> String {
        record_id(self.dt, &self.acc)
    }
}

/// Something read that may not be what the user meant.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordWarning {
    /// A stable name for the kind: `npts_mismatch`, `large_pga`,
    /// `baseline_drift`.
    pub kind: &'static str,
    /// What was found and what the user might do.
    pub message: String,
}

/// Why a file cannot be read as a record.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadError {
    /// What the user must change: `body` (the file's content), `format`,
    /// `unit`, `dt`, `time_column`, `acc_column`, or, in a JSON file, a JSON
    /// pointer into it (`/acc/3`).
    pub field: String,
    /// The 1-based line of the file at fault, when one is.
    pub line: Option<usize>,
    /// What is wrong, and what would be right.
    pub message: String,
    /// The file holds more samples than this (the reader stopped there).
    pub more_samples_than: Option<usize>,
}

impl ReadError {
    /// An error about option or pointer `field`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> ReadError {
        ReadError {
            field: field.into(),
            line: None,
            message: message.into(),
            more_samples_than: None,
        }
    }

    /// An error about the file's content, at `line` when one is at fault.
    pub fn body(line: Option<usize>, message: impl Into<String>) -> ReadError {
        ReadError {
            field: "body".into(),
            line,
            message: message.into(),
            more_samples_than: None,
        }
    }

    /// This error, at `line`.
    pub fn at_line(mut self, line: usize) -> ReadError {
        self.line = Some(line);
        self
    }
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(line) => write!(f, "{} (line {line}): {}", self.field, self.message),
            None => write!(f, "{}: {}", self.field, self.message),
        }
    }
}

impl std::error::Error for ReadError {}

/// What a format's reader hands back, before the checks shared by all.
struct Parsed {
    /// The name found in the file, if any.
    name: Option<String>,
    unit: Unit,
    dt: f64,
    /// m/s².
    acc: Vec<f64>,
    warnings: Vec<RecordWarning>,
    /// Whether the values came as one series (one column, an AT2 file, a
    /// JSON array), where time values could pass for accelerations.
    flat: bool,
}

/// Reads the record in `text`, a whole file (a UTF-8 BOM and CRLF endings
/// are fine).
pub fn read(text: &str, opts: &ReadOptions) -> Result<RecordFile, ReadError> {
    let text = text::without_bom(text);
    if let Some(dt) = opts.dt {
        check_dt(dt).map_err(|m| ReadError::new("dt", m))?;
    }
    let format = opts.format.unwrap_or_else(|| Format::detect(text));
    let parsed = match format {
        Format::At2 => at2::read(text, opts)?,
        Format::Csv => columns::read(text, opts)?,
        Format::Json => json::read(text, opts)?,
    };
    finish(parsed, format, opts)
}

/// The checks every format shares: sample count, then the guards against a
/// silent misread.
fn finish(parsed: Parsed, format: Format, opts: &ReadOptions) -> Result<RecordFile, ReadError> {
    let Parsed {
        name,
        unit,
        dt,
        acc,
        mut warnings,
        flat,
    } = parsed;
    check_count(acc.len())?;
    if flat {
        check_flat(&acc)?;
    }
    let pga = acc.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    match check_pga(pga / G_M_S2, unit) {
        PgaCheck::Fine => {}
        PgaCheck::Large(w) => warnings.push(w),
        PgaCheck::Implausible(message) if opts.allow_large_pga => warnings.push(RecordWarning {
            kind: "large_pga",
            message: format!("{message} (kept: allow_large_pga is set)"),
        }),
        PgaCheck::Implausible(message) => {
            return Err(ReadError::new(
                "unit",
                format!(
                    "{message}; if the PGA is right, set allow_large_pga to keep the record \
                     as read"
                ),
            ));
        }
    }
    warnings.extend(baseline_drift(dt, &acc));
    let name = opts
        .name
        .clone()
        .filter(|n| !n.trim().is_empty())
        .or(name.filter(|n| !n.is_empty()))
        .unwrap_or_else(|| "record".into());
    Ok(RecordFile {
        name,
        format,
        unit,
        dt,
        acc,
        warnings,
    })
}

/// Refuses a series that is time, or time and acceleration interleaved.
fn check_flat(acc: &[f64]) -> Result<(), ReadError> {
    if looks_interleaved(acc) {
        return Err(ReadError::body(
            None,
            "every other value rises by a constant step: these look like (time, acceleration) \
             pairs; upload them as two columns",
        ));
    }
    if looks_like_time(acc) {
        return Err(ReadError::body(
            None,
            format!(
                "all {} values rise by one constant step: this is a time column, not \
                 accelerations; upload the acceleration column (beside its time column, or \
                 alone with dt)",
                acc.len()
            ),
        ));
    }
    Ok(())
}

/// Refuses a step outside [`RECORD_DT_RANGE`], saying the range.
fn check_dt(dt: f64) -> Result<(), String> {
    let (lo, hi) = RECORD_DT_RANGE;
    if dt.is_finite() && (lo..=hi).contains(&dt) {
        Ok(())
    } else {
        Err(format!(
            "the time step {dt} s is outside {lo:e} s to {hi} s"
        ))
    }
}

/// Refuses fewer than 2 or more than [`MAX_RECORD_SAMPLES`] samples.
fn check_count(n: usize) -> Result<(), ReadError> {
    if n < 2 {
        return Err(ReadError::body(
            None,
            format!("a record needs at least 2 samples; the file holds {n}"),
        ));
    }
    if n > MAX_RECORD_SAMPLES {
        return Err(too_many());
    }
    Ok(())
}

/// The error for a file past [`MAX_RECORD_SAMPLES`] (raised as soon as the
/// count is passed, before the rest is read).
fn too_many() -> ReadError {
    ReadError {
        more_samples_than: Some(MAX_RECORD_SAMPLES),
        ..ReadError::body(
            None,
            format!(
                "the file holds more than {MAX_RECORD_SAMPLES} samples: shorten the record or \
                 resample it to a longer time step"
            ),
        )
    }
}

/// Checks the option `dt` against the file's `found` step, s (1e-6
/// relative); `source` says where the file states it.
fn agree_dt(option: Option<f64>, found: f64, source: &str) -> Result<(), ReadError> {
    match option {
        Some(dt) if (dt - found).abs() > DT_TOLERANCE * found.abs() => Err(ReadError::new(
            "dt",
            format!(
                "the dt option ({dt} s) disagrees with {source} ({found} s): leave dt out, or \
                 correct the file"
            ),
        )),
        _ => Ok(()),
    }
}

/// Checks the option `unit` against the file's `stated` unit.
fn agree_unit(option: Option<Unit>, stated: Unit, source: &str) -> Result<(), ReadError> {
    match option {
        Some(u) if u != stated => Err(ReadError::new(
            "unit",
            format!(
                "the unit option ({u}) disagrees with {source} ({stated}): leave unit out, or \
                 correct the file"
            ),
        )),
        _ => Ok(()),
    }
}

/// The peak ground acceleration of `acc` (its largest magnitude).
pub fn pga(acc: &[f64]) -> f64 {
    acc.iter().fold(0.0f64, |m, a| m.max(a.abs()))
}

/// The content address of a record: 32 lowercase hex digits of the blake3
/// hash of `dt`'s and every sample's f64 bits (little-endian), −0.0 counted
/// as 0.0. The same motion uploaded twice, in any format or unit that reads
/// to the same m/s² samples, gets the same id.
pub fn record_id(dt: f64, acc_m_s2: &[f64]) -> String {
    let bits = |x: f64| if x == 0.0 { 0u64 } else { x.to_bits() };
    let mut hasher = blake3::Hasher::new();
    hasher.update(&bits(dt).to_le_bytes());
    // Chunked, so that 200,000 samples hash in a few large updates.
    let mut buffer = Vec::with_capacity(8 * 4096);
    for chunk in acc_m_s2.chunks(4096) {
        buffer.clear();
        for &a in chunk {
            buffer.extend_from_slice(&bits(a).to_le_bytes());
        }
        hasher.update(&buffer);
    }
    let hash = hasher.finalize();
    hash.as_bytes()[..16]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

#[cfg(test)]
mod tests;
