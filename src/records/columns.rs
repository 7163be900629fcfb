//! Records in columns: CSV, semicolon- or tab-separated, or aligned with
//! blanks, as spreadsheets and processing scripts write them.
//!
//! ```text
//! # Imperial Valley 1979, El Centro #6, 230     <- comments (#, %, //)
//! time_s,acc_g                                  <- optional row of names
//! 0.000,0.0012                                  <- data
//! 0.005,-0.0031
//! ```
//!
//! The delimiter is told from the first data row (`;`, then tab, then `,`,
//! else runs of blanks). One column is acceleration (with the `dt` option);
//! with two the first is time; with more, `acc_column` must say which.
//! A time column gives dt, and must step uniformly. The unit comes from a
//! column's name (`acc_g`, `acc (cm/s2)`), an optional row of units under the
//! names, or the `unit` option.

use std::borrow::Cow;

use super::MAX_RECORD_SAMPLES;
use super::format::is_comment;
use super::number;
use super::text::{clip, numbered_lines, quote};
use super::unit::{ACCEPTED_UNITS, Unit, bracketed};
use super::{DT_TOLERANCE, MAX_NAME_CHARS, Parsed, ReadError, ReadOptions};

/// Which column of a file: by position or by the name in its header row.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Column {
    /// 1-based position.
    Index(usize),
    /// Name in the header row (compared without case and outer blanks).
    Name(String),
}

impl Column {
    /// A positive whole number is a position, anything else a name.
    pub fn parse(text: &str) -> Column {
        let text = text.trim();
        match text.parse::<usize>() {
            Ok(i) if i > 0 => Column::Index(i),
            _ => Column::Name(text.to_string()),
        }
    }
}

impl std::fmt::Display for Column {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Column::Index(i) => write!(f, "{i}"),
            Column::Name(n) => write!(f, "{n:?}"),
        }
    }
}

/// How the fields of a row are separated.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Delimiter {
    /// One character, fields trimmed, `"…"` quoting allowed.
    Char(char),
    /// Runs of spaces and tabs.
    Blanks,
}

impl Delimiter {
    /// The delimiter of `row`: `;` first (its files may write decimal
    /// commas), then tab, then `,`, else blanks.
    fn of(row: &str) -> Delimiter {
        [';', '\t', ',']
            .into_iter()
            .find(|&c| row.contains(c))
            .map_or(Delimiter::Blanks, Delimiter::Char)
    }

    fn describe(self) -> &'static str {
        match self {
            Delimiter::Char(';') => "semicolons",
            Delimiter::Char('\t') => "tabs",
            Delimiter::Char(_) => "commas",
            Delimiter::Blanks => "blanks",
        }
    }

    /// The fields of `row`. A delimiter closing the row adds no field.
    fn split(self, row: &str) -> Vec<Cow<'_, str>> {
        match self {
            Delimiter::Blanks => row.split_whitespace().map(Cow::Borrowed).collect(),
            Delimiter::Char(d) => {
                // Blanks around the row are not fields (a tab-separated row
                // indented with a tab).
                let row = row.trim();
                let mut fields = if row.contains('"') {
                    quoted_fields(row, d)
                } else {
                    row.split(d).map(|f| Cow::Borrowed(f.trim())).collect()
                };
                if fields.len() > 1 && fields.last().is_some_and(|f| f.is_empty()) {
                    fields.pop();
                }
                fields
            }
        }
    }
}

/// The fields of `row` separated by `d`, with RFC 4180 quoting (`"a, b"`,
/// `""` for a quote inside). Laxer than RFC 4180, as files written by hand
/// need: a quote opens or closes a quoted stretch wherever it stands, so
/// `1.0, "2.0"` (a blank before the quote) reads as two numbers, where a
/// strict reader such as the `csv` crate's keeps `"2.0"` whole.
fn quoted_fields(row: &str, d: char) -> Vec<Cow<'_, str>> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut in_quotes = false;
    let mut chars = row.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if in_quotes && chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            '"' => in_quotes = !in_quotes,
            c if c == d && !in_quotes => {
                fields.push(Cow::Owned(field.trim().to_string()));
                field.clear();
            }
            c => field.push(c),
        }
    }
    fields.push(Cow::Owned(field.trim().to_string()));
    fields
}

/// Whether every field of `row`, split by its own delimiter, is a number.
fn is_data(row: &str) -> bool {
    let fields = Delimiter::of(row).split(row);
    !fields.is_empty() && fields.iter().all(|f| number::is_number(f))
}

/// Whether `field` names a unit (of time or acceleration), for a row of
/// units under the names.
fn is_unit(field: &str) -> bool {
    let inner = bracketed(field).unwrap_or(field);
    inner.is_empty() || Unit::parse(inner).is_some() || time_scale_of(inner).is_some()
}

/// Seconds per unit of a time unit's spelling: `s`, `sec`, `seconds` → 1,
/// `ms`, `msec` → 0.001.
fn time_scale_of(unit: &str) -> Option<f64> {
    match unit.trim().to_ascii_lowercase().as_str() {
        "s" | "sec" | "secs" | "second" | "seconds" => Some(1.0),
        "ms" | "msec" | "millisecond" | "milliseconds" => Some(1e-3),
        _ => None,
    }
}

/// Seconds per unit of a time column named `name` (`time (ms)`, `t_ms`);
/// seconds when the name does not say.
fn time_scale(name: &str) -> f64 {
    bracketed(name)
        .and_then(time_scale_of)
        .or_else(|| name.rsplit(['_', ' ']).next().and_then(time_scale_of))
        .unwrap_or(1.0)
}

/// Whether a header name says time: its first word is `t` or `time`.
fn is_time_name(name: &str) -> bool {
    let first = name
        .split(|c: char| !c.is_ascii_alphanumeric())
        .find(|w| !w.is_empty())
        .unwrap_or("");
    ["t", "time", "times"]
        .iter()
        .any(|w| first.eq_ignore_ascii_case(w))
}

/// The header rows before the data: column names, then optionally their
/// units.
struct Header {
    names: Option<(usize, String)>,
    units: Option<(usize, String)>,
}

/// The columns of the file, as far as needed to choose them.
struct Layout {
    count: usize,
    names: Option<Vec<String>>,
    units: Option<Vec<String>>,
}

impl Layout {
    /// "1 "time", 2 "acc_g"", or "1 to 3" without names.
    fn describe(&self) -> String {
        match &self.names {
            Some(names) => names
                .iter()
                .enumerate()
                .map(|(i, n)| format!("{} {n:?}", i + 1))
                .collect::<Vec<_>>()
                .join(", "),
            None => format!("1 to {} (the file names none)", self.count),
        }
    }

    /// The 0-based position of `column`; `field` is the option's name.
    fn resolve(&self, column: &Column, field: &'static str) -> Result<usize, ReadError> {
        let found = match column {
            Column::Index(i) => (1..=self.count).contains(i).then(|| i - 1),
            Column::Name(n) => self.names.as_ref().and_then(|names| {
                names
                    .iter()
                    .position(|x| x.trim().eq_ignore_ascii_case(n.trim()))
            }),
        };
        found.ok_or_else(|| {
            ReadError::new(
                field,
                format!(
                    "the file has no column {column}: its columns are {}",
                    self.describe()
                ),
            )
        })
    }

    fn name(&self, i: usize) -> Option<&str> {
        self.names.as_ref().map(|n| n[i].as_str())
    }

    /// "column 2 ("acc_g")".
    fn label(&self, i: usize) -> String {
        match self.name(i) {
            Some(n) => format!("column {} ({n:?})", i + 1),
            None => format!("column {}", i + 1),
        }
    }
}

/// What comes before the data: the name the first comment gives, the rows
/// of column names and units, and the first data row (its line number and
/// text).
struct Preamble<'a> {
    name: Option<String>,
    header: Header,
    first: (usize, &'a str),
}

/// Reads comments, blank lines and up to two header rows from `lines`, to
/// the first data row.
fn preamble<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Result<Preamble<'a>, ReadError> {
    let mut comment_name = None;
    let mut header = Header {
        names: None,
        units: None,
    };
    let first = loop {
        let Some((n, line)) = lines.next() else {
            return Err(ReadError::body(None, "the file holds no rows of numbers"));
        };
        if is_comment(line) {
            if comment_name.is_none() {
                let text = line.trim_start().trim_start_matches(['#', '%', '/']);
                let text = clip(text, MAX_NAME_CHARS);
                comment_name = (!text.is_empty()).then_some(text);
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        if is_data(line) {
            break (n, line);
        }
        match (&header.names, &header.units) {
            (None, _) => header.names = Some((n, line.to_string())),
            (Some(_), None) if Delimiter::of(line).split(line).iter().all(|f| is_unit(f)) => {
                header.units = Some((n, line.to_string()));
            }
            _ => {
                return Err(ReadError::body(
                    Some(n),
                    format!(
                        "{} is neither data{} nor the row of column names (or their units) \
                         before the data: start comment lines with #",
                        quote(line),
                        decimal_comma_hint(line)
                    ),
                ));
            }
        }
    };
    Ok(Preamble {
        name: comment_name,
        header,
        first,
    })
}

/// How the data rows read: their delimiter and number of fields (those of
/// the first data row, on line `first_line`), and the column and unit of
/// the accelerations.
struct Rows {
    delimiter: Delimiter,
    count: usize,
    first_line: usize,
    acc: usize,
    unit: Unit,
}

/// The accelerations of the data `rows` in m/s² (the times going to
/// `times`): one series, each row of `format`'s fields, all numbers.
fn read_rows<'a>(
    rows: impl Iterator<Item = (usize, &'a str)>,
    format: &Rows,
    times: &mut TimeColumn,
) -> Result<Vec<f64>, ReadError> {
    let Rows {
        delimiter,
        count,
        first_line,
        acc: acc_index,
        unit,
    } = *format;
    let mut acc = Vec::new();
    let mut buffer = String::new();
    let mut blank: Option<usize> = None;
    for (n, line) in rows {
        if is_comment(line) {
            continue;
        }
        if line.trim().is_empty() {
            blank = blank.or(Some(n));
            continue;
        }
        if let Some(b) = blank {
            return Err(ReadError::body(
                Some(b),
                "a blank line inside the data: the file seems to hold more than one series; \
                 upload one, or remove the blank line",
            ));
        }
        let fields = delimiter.split(line);
        if fields.len() != count {
            return Err(ReadError::body(
                Some(n),
                format!(
                    "{} has {} fields where the first data row (line {}) has {count}, separated \
                     by {}",
                    quote(line),
                    fields.len(),
                    first_line,
                    delimiter.describe()
                ),
            ));
        }
        if let Some(bad) = fields.iter().position(|f| !number::is_number(f)) {
            return Err(not_a_number(n, line, &fields[bad], delimiter));
        }
        if acc.len() == MAX_RECORD_SAMPLES {
            return Err(super::too_many().at_line(n));
        }
        let a = number::acceleration(&fields[acc_index], unit, &mut buffer)
            .filter(|a| a.is_finite())
            .ok_or_else(|| {
                ReadError::body(
                    Some(n),
                    format!("{:?} is too large to be an acceleration", fields[acc_index]),
                )
            })?;
        acc.push(a);
        times.push(n, &fields)?;
    }
    Ok(acc)
}

/// The time step: the time column's (agreeing with `opts.dt` if given
/// too), or without one `opts.dt`.
fn time_step(times: &TimeColumn, layout: &Layout, opts: &ReadOptions) -> Result<f64, ReadError> {
    Ok(match times.step(layout)? {
        Some(found) => {
            super::agree_dt(opts.dt, found, "the time column")?;
            found
        }
        None => opts.dt.ok_or_else(|| {
            let message = if layout.count == 1 {
                "a file of one column holds accelerations only: give dt, the time step in \
                 seconds"
                    .to_string()
            } else {
                format!(
                    "no column of this file is taken as time (its columns are {}): give dt, the \
                     time step in seconds, or time_column",
                    layout.describe()
                )
            };
            ReadError::new("dt", message)
        })?,
    })
}

/// Reads a column file.
pub(super) fn read(text: &str, opts: &ReadOptions) -> Result<Parsed, ReadError> {
    let mut lines = numbered_lines(text);
    let Preamble {
        name,
        header,
        first,
    } = preamble(&mut lines)?;
    let delimiter = Delimiter::of(first.1);
    let count = delimiter.split(first.1).len();
    let layout = Layout {
        count,
        names: header_row(&header.names, delimiter, count)?,
        units: header_row(&header.units, delimiter, count)?,
    };
    let (time, acc_index) = choose_columns(&layout, opts)?;
    let unit = unit(&layout, acc_index, opts)?;
    let format = Rows {
        delimiter,
        count,
        first_line: first.0,
        acc: acc_index,
        unit,
    };
    let mut times = TimeColumn::new(time.map(|i| (i, time_scale(layout.name(i).unwrap_or("")))));
    let acc = read_rows(std::iter::once(first).chain(lines), &format, &mut times)?;
    let dt = time_step(&times, &layout, opts)?;
    Ok(Parsed {
        name,
        unit,
        dt,
        acc,
        warnings: Vec::new(),
        flat: time.is_none(),
    })
}

/// The error for a field that is not a number, with a hint for decimal
/// commas.
fn not_a_number(n: usize, line: &str, field: &str, delimiter: Delimiter) -> ReadError {
    let hint = if field.contains(',') && number::is_number(&field.replace(',', ".")) {
        DECIMAL_COMMA_HINT
    } else {
        ""
    };
    ReadError::body(
        Some(n),
        format!(
            "{} is not a number{hint}, in {} (fields separated by {})",
            quote(field),
            quote(line),
            delimiter.describe()
        ),
    )
}

/// Said when a row would be numbers with decimal points for its commas.
const DECIMAL_COMMA_HINT: &str = " (decimal commas are not read: write 0.5, not 0,5)";

/// [`DECIMAL_COMMA_HINT`] when `row` is data written with decimal commas.
fn decimal_comma_hint(row: &str) -> &'static str {
    if row.contains(';') && row.contains(',') && is_data(&row.replace(',', ".")) {
        DECIMAL_COMMA_HINT
    } else {
        ""
    }
}

/// The fields of a header row, as many as the data's columns.
fn header_row(
    row: &Option<(usize, String)>,
    delimiter: Delimiter,
    count: usize,
) -> Result<Option<Vec<String>>, ReadError> {
    let Some((n, line)) = row else {
        return Ok(None);
    };
    let mut fields: Vec<String> = delimiter
        .split(line)
        .into_iter()
        .map(|f| f.trim_matches('"').trim().to_string())
        .collect();
    if fields.len() != count && delimiter == Delimiter::Blanks {
        // Names with blanks in them, aligned: "Time (s)    Acc (g)".
        fields = line
            .split('\t')
            .flat_map(|f| f.split("  "))
            .map(str::trim)
            .filter(|f| !f.is_empty())
            .map(str::to_string)
            .collect();
    }
    if fields.len() != count {
        return Err(ReadError::body(
            Some(*n),
            format!(
                "the header row {} has {} fields, but the data has {count} columns: make them \
                 agree, or start the row with #",
                quote(line),
                fields.len()
            ),
        ));
    }
    Ok(Some(fields))
}

/// The time column (if any) and the acceleration column, 0-based.
fn choose_columns(
    layout: &Layout,
    opts: &ReadOptions,
) -> Result<(Option<usize>, usize), ReadError> {
    let count = layout.count;
    let time_option = opts
        .time_column
        .as_ref()
        .map(|c| layout.resolve(c, "time_column"))
        .transpose()?;
    let acc = match (&opts.acc_column, count, time_option) {
        (Some(c), _, _) => layout.resolve(c, "acc_column")?,
        (None, 1, _) => 0,
        (None, 2, Some(t)) => 1 - t,
        (None, 2, None) => 1,
        (None, _, _) => {
            return Err(ReadError::new(
                "acc_column",
                format!(
                    "the file has {count} columns: say which holds the acceleration with \
                     acc_column (a position or a name); its columns are {}",
                    layout.describe()
                ),
            ));
        }
    };
    let time = match time_option {
        Some(t) if t == acc => {
            return Err(ReadError::new(
                "time_column",
                format!("time_column and acc_column both name {}", layout.label(acc)),
            ));
        }
        Some(t) => Some(t),
        None if count == 1 => None,
        // Two columns are time and acceleration, unless the header names the
        // other one as something else and dt is given (two components).
        None if count == 2 => {
            let other = 1 - acc;
            let named_otherwise = layout.name(other).is_some_and(|n| !is_time_name(n));
            (!(named_otherwise && opts.dt.is_some())).then_some(other)
        }
        None => {
            let named: Vec<usize> = (0..count)
                .filter(|&i| i != acc && layout.name(i).is_some_and(is_time_name))
                .collect();
            match named[..] {
                [t] => Some(t),
                _ => None,
            }
        }
    };
    Ok((time, acc))
}

/// The unit of column `acc`: from its name or units row, or the option.
fn unit(layout: &Layout, acc: usize, opts: &ReadOptions) -> Result<Unit, ReadError> {
    let from_units_row = layout.units.as_ref().and_then(|u| {
        let field = u[acc].as_str();
        Unit::parse(bracketed(field).unwrap_or(field))
    });
    let from_name = layout.name(acc).and_then(Unit::in_column_name);
    let stated = match (from_units_row, from_name) {
        (Some(a), Some(b)) if a != b => {
            return Err(ReadError::body(
                None,
                format!(
                    "the header says two units for {}: {a} in the units row, {b} in its name",
                    layout.label(acc)
                ),
            ));
        }
        (a, b) => a.or(b),
    };
    match (stated, opts.unit) {
        (Some(s), option) => {
            super::agree_unit(option, s, &format!("the header of {}", layout.label(acc)))?;
            Ok(s)
        }
        (None, Some(option)) => Ok(option),
        (None, None) => Err(ReadError::new(
            "unit",
            format!(
                "the file does not say the unit of its accelerations ({}): give unit, one of \
                 {ACCEPTED_UNITS}, or name the column with its unit (acc_g, acc (cm/s2))",
                layout.label(acc)
            ),
        )),
    }
}

/// A time column read row by row, its spacing checked as it comes.
struct TimeColumn {
    /// The column (0-based) and its seconds per unit.
    column: Option<(usize, f64)>,
    first: f64,
    previous: f64,
    /// The spacing of the first two rows.
    spacing: f64,
    count: usize,
}

impl TimeColumn {
    fn new(column: Option<(usize, f64)>) -> TimeColumn {
        TimeColumn {
            column,
            first: 0.0,
            previous: 0.0,
            spacing: 0.0,
            count: 0,
        }
    }

    /// Takes the time of file line `n`'s `fields`: it must increase, by the
    /// spacing of the first two rows to 1e-6 of it.
    fn push(&mut self, n: usize, fields: &[Cow<'_, str>]) -> Result<(), ReadError> {
        let Some((column, _)) = self.column else {
            return Ok(());
        };
        let t = number::parse(&fields[column])
            .filter(|t| t.is_finite())
            .ok_or_else(|| {
                ReadError::body(
                    Some(n),
                    format!("the time {:?} is too large", fields[column]),
                )
            })?;
        if self.count > 0 {
            let step = t - self.previous;
            if step <= 0.0 {
                return Err(ReadError::body(
                    Some(n),
                    format!(
                        "the time does not increase: {} after {} (column {})",
                        fields[column],
                        self.previous,
                        column + 1
                    ),
                ));
            }
            if self.count == 1 {
                self.spacing = step;
            } else if (step - self.spacing).abs() > DT_TOLERANCE * self.spacing {
                return Err(ReadError::body(
                    Some(n),
                    format!(
                        "the time steps by {step} here but by {} between the first two rows: \
                         a record must be sampled uniformly (resample it, or upload the \
                         acceleration alone with dt)",
                        self.spacing
                    ),
                ));
            }
        } else {
            self.first = t;
        }
        self.previous = t;
        self.count += 1;
        Ok(())
    }

    /// The step, s: the mean spacing rounded to 10 significant digits (so
    /// 0.00, 0.01, 0.02, … gives exactly 0.01); `None` without a time
    /// column.
    fn step(&self, layout: &Layout) -> Result<Option<f64>, ReadError> {
        let Some((column, seconds)) = self.column else {
            return Ok(None);
        };
        if self.count < 2 {
            return Err(ReadError::body(
                None,
                format!(
                    "a record needs at least 2 samples; the file holds {}",
                    self.count
                ),
            ));
        }
        let mean = (self.previous - self.first) / (self.count - 1) as f64;
        let dt = significant(significant(mean) * seconds);
        super::check_dt(dt).map_err(|m| {
            ReadError::body(None, format!("{m}, from the time {}", layout.label(column)))
        })?;
        Ok(Some(dt))
    }
}

/// `x` rounded to 10 significant digits.
fn significant(x: f64) -> f64 {
    format!("{x:.9e}").parse().unwrap_or(x)
}

#[cfg(test)]
mod tests {
    use super::super::{Format, ReadOptions, read};
    use super::*;

    fn opts() -> ReadOptions {
        ReadOptions::default()
    }

    /// `[0.01, -0.02, 0.03, -0.01, 0.0]` in g, as m/s².
    fn five_g() -> Vec<f64> {
        [0.01, -0.02, 0.03, -0.01, 0.0]
            .iter()
            .map(|g| g * 9.81)
            .collect()
    }

    #[test]
    fn csv_with_comments_and_names_reads_time_unit_and_name() {
        let text = "# Imperial Valley 1979, El Centro #6\n# processed\n\
                    time_s,acc_g\n0.00,0.01\n0.01,-0.02\n0.02,0.03\n0.03,-0.01\n0.04,0.0\n\n\n";
        let r = read(text, &opts()).expect("reads");
        assert_eq!(r.format, Format::Csv);
        assert_eq!(r.name, "Imperial Valley 1979, El Centro #6");
        assert_eq!(r.unit, Unit::G);
        assert_eq!(r.dt, 0.01);
        assert_eq!(r.acc, five_g());
    }

    #[test]
    fn csv_without_header_needs_the_unit_and_takes_time_from_column_1() {
        let text = "0.00,0.01\n0.01,-0.02\n0.02,0.03\n0.03,-0.01\n0.04,0.0\n";
        let e = read(text, &opts()).expect_err("no unit");
        assert_eq!(e.field, "unit");
        assert!(
            e.message.contains("cm/s2") && e.message.contains("m/s2"),
            "{}",
            e.message
        );
        let r = read(
            text,
            &ReadOptions {
                unit: Some(Unit::G),
                ..opts()
            },
        )
        .expect("reads");
        assert_eq!(
            (r.dt, r.acc.clone(), r.name.as_str()),
            (0.01, five_g(), "record")
        );
    }

    #[test]
    fn one_column_with_dt_reads_and_without_dt_asks_for_it() {
        let text = "acc (g)\n0.01\n-0.02\n0.03\n-0.01\n0.0\n";
        let e = read(text, &opts()).expect_err("no dt");
        assert_eq!(e.field, "dt");
        assert!(e.message.contains("one column"), "{}", e.message);
        let r = read(
            text,
            &ReadOptions {
                dt: Some(0.005),
                ..opts()
            },
        )
        .expect("reads");
        assert_eq!((r.dt, r.acc), (0.005, five_g()));
    }

    #[test]
    fn whitespace_semicolon_and_tab_columns_read_alike() {
        for text in [
            "  Time (s)     Acc (g)\n  0.00   0.01\n  0.01  -0.02\n  0.02   0.03\n  0.03  -0.01\n  0.04   0.0\n",
            "t\tacc_g\n0.00\t0.01\n0.01\t-0.02\n0.02\t0.03\n0.03\t-0.01\n0.04\t0.0\n",
            "t;acc [g]\n0.00;0.01\n0.01;-0.02\n0.02;0.03\n0.03;-0.01\n0.04;0.0\n",
            "\"t\",\"acc, g\"\n0.00,0.01\n0.01,-0.02\n0.02,0.03\n0.03,-0.01\n0.04,0.0\n",
            // Blanks before quotes, as files written by hand have them.
            "\"t\", \"acc, g\"\n0.00, \"0.01\"\n0.01,-0.02\n0.02,0.03\n0.03,-0.01\n0.04,0.0\n",
            "0.00 0.01\r\n0.01 -0.02\r\n0.02 0.03\r\n0.03 -0.01\r\n0.04 0.0\r\n",
        ] {
            let o = ReadOptions {
                unit: text.starts_with('0').then_some(Unit::G),
                ..opts()
            };
            let r = read(text, &o).unwrap_or_else(|e| panic!("{text:?}: {e}"));
            assert_eq!((r.dt, r.acc), (0.01, five_g()), "{text:?}");
        }
    }

    #[test]
    fn centimetre_columns_read_exactly() {
        let text = "t,acc (cm/s2)\n0,1.23\n0.02,-4.5\n0.04,0.7\n";
        let r = read(text, &opts()).expect("reads");
        assert_eq!(r.unit, Unit::CentimetresPerSecondSquared);
        assert_eq!(r.dt, 0.02);
        assert_eq!(r.acc, vec![0.0123, -0.045, 0.007]);
    }

    #[test]
    fn a_units_row_under_the_names_gives_the_unit() {
        let text = "Time,Acceleration\ns,gal\n0,1.23\n0.02,-4.5\n0.04,0.7\n";
        let r = read(text, &opts()).expect("reads");
        assert_eq!(r.unit, Unit::CentimetresPerSecondSquared);
        assert_eq!(r.acc, vec![0.0123, -0.045, 0.007]);
    }

    #[test]
    fn time_in_milliseconds_gives_dt_in_seconds() {
        let text = "time (ms),acc_g\n0,0.01\n5,-0.02\n10,0.03\n";
        assert_eq!(read(text, &opts()).expect("reads").dt, 0.005);
    }

    #[test]
    fn dt_is_the_mean_spacing_to_ten_digits_wherever_time_starts() {
        // 0.1 + k·0.1 as written by a script: 0.30000000000000004 and so on.
        let mut text = String::from("t,acc_g\n");
        for k in 0..200 {
            let t = 12.3 + k as f64 * 0.1;
            text.push_str(&format!("{t},{}\n", if k % 2 == 0 { 0.01 } else { -0.01 }));
        }
        let r = read(&text, &opts()).expect("reads");
        assert_eq!(r.dt, 0.1);
        assert_eq!(r.acc.len(), 200);
    }

    #[test]
    fn non_uniform_time_is_refused_naming_the_first_bad_line_and_both_steps() {
        let text = "# rec\nt,acc_g\n0.00,0.01\n0.01,0.02\n0.02,0.03\n0.035,0.0\n0.045,0.01\n";
        let e = read(text, &opts()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(6)));
        assert!(e.message.contains("0.01 between"), "{}", e.message);
        assert!(e.message.contains("by 0.015"), "{}", e.message);
        let back = "t,acc_g\n0.00,0.01\n0.01,0.02\n0.01,0.03\n";
        let e = read(back, &opts()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(4)));
        assert!(e.message.contains("does not increase"), "{}", e.message);
    }

    #[test]
    fn a_dt_option_must_agree_with_the_time_column() {
        let text = "t,acc_g\n0.00,0.01\n0.01,-0.02\n0.02,0.03\n";
        let wrong = ReadOptions {
            dt: Some(0.02),
            ..opts()
        };
        assert_eq!(read(text, &wrong).expect_err("refused").field, "dt");
        let close = ReadOptions {
            dt: Some(0.010000001),
            ..opts()
        };
        assert_eq!(read(text, &close).expect("agrees").dt, 0.01);
    }

    #[test]
    fn three_columns_need_acc_column_and_list_the_names() {
        let text = "time,acc_x_g,acc_y_g\n0,0.01,0.02\n0.01,-0.02,0.01\n0.02,0.03,-0.01\n";
        let e = read(text, &opts()).expect_err("refused");
        assert_eq!(e.field, "acc_column");
        assert!(
            e.message.contains(r#"1 "time", 2 "acc_x_g", 3 "acc_y_g""#),
            "{}",
            e.message
        );
        let by_name = ReadOptions {
            acc_column: Some(Column::parse("ACC_Y_G")),
            ..opts()
        };
        let r = read(text, &by_name).expect("reads");
        assert_eq!(r.dt, 0.01);
        assert_eq!(r.acc, vec![0.02 * 9.81, 0.01 * 9.81, -0.01 * 9.81]);
        let by_index = ReadOptions {
            acc_column: Some(Column::parse("2")),
            ..opts()
        };
        assert_eq!(read(text, &by_index).expect("reads").acc[0], 0.01 * 9.81);
        let missing = ReadOptions {
            acc_column: Some(Column::parse("acc_z_g")),
            ..opts()
        };
        let e = read(text, &missing).expect_err("refused");
        assert_eq!(e.field, "acc_column");
        assert!(e.message.contains("acc_z_g"), "{}", e.message);
    }

    #[test]
    fn three_unnamed_columns_with_acc_column_need_dt_or_time_column() {
        let text = "0.01,0.02,0.00\n-0.02,0.01,0.01\n0.03,-0.01,0.02\n";
        let o = ReadOptions {
            acc_column: Some(Column::Index(1)),
            unit: Some(Unit::G),
            ..opts()
        };
        assert_eq!(read(text, &o).expect_err("no dt").field, "dt");
        let with_time = ReadOptions {
            time_column: Some(Column::Index(3)),
            ..o.clone()
        };
        let r = read(text, &with_time).expect("reads");
        assert_eq!((r.dt, r.acc[1]), (0.01, -0.02 * 9.81));
        let same = ReadOptions {
            time_column: Some(Column::Index(1)),
            ..o
        };
        assert_eq!(read(text, &same).expect_err("refused").field, "time_column");
    }

    #[test]
    fn swapped_columns_follow_the_options() {
        let text = "acc_g,t\n0.01,0\n-0.02,0.01\n0.03,0.02\n";
        let o = ReadOptions {
            acc_column: Some(Column::Index(1)),
            ..opts()
        };
        let r = read(text, &o).expect("reads");
        assert_eq!((r.dt, r.acc[2]), (0.01, 0.03 * 9.81));
        let o = ReadOptions {
            time_column: Some(Column::Name("t".into())),
            ..opts()
        };
        assert_eq!(read(text, &o).expect("reads").acc[2], 0.03 * 9.81);
    }

    #[test]
    fn two_named_components_with_dt_take_no_time_column() {
        let text = "acc_x_g,acc_y_g\n0.01,0.02\n-0.02,0.01\n0.03,-0.01\n";
        let o = ReadOptions {
            dt: Some(0.02),
            ..opts()
        };
        let r = read(text, &o).expect("reads");
        assert_eq!((r.dt, r.acc[1]), (0.02, 0.01 * 9.81));
        // Without dt the first column is taken as time, and does not increase.
        let e = read(text, &opts()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(3)));
    }

    #[test]
    fn a_tab_separated_row_may_start_with_a_tab() {
        let text = "\tt\tacc_g\n\t0\t0.01\n\t0.01\t-0.02\n\t0.02\t0.03\n";
        let r = read(text, &opts()).expect("reads");
        assert_eq!((r.dt, r.acc[2]), (0.01, 0.03 * 9.81));
    }

    #[test]
    fn a_ragged_row_or_a_word_is_refused_naming_its_line() {
        let ragged = "t,acc_g\n0,0.01\n0.01,0.02,0.5\n";
        let e = read(ragged, &opts()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(3)));
        assert!(e.message.contains("3 fields"), "{}", e.message);
        let word = format!("t,acc_g\n0,0.01\n0.01,n/a {}\n", "x".repeat(60));
        let e = read(&word, &opts()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(3)));
        assert!(e.message.contains('…'), "{}", e.message);
        assert!(!e.message.contains(&"x".repeat(41)), "{}", e.message);
    }

    #[test]
    fn decimal_commas_get_a_hint() {
        let text = "t;acc_g\n0;0,01\n0,01;0,02\n";
        let e = read(text, &opts()).expect_err("refused");
        assert_eq!(e.line, Some(2));
        assert!(e.message.contains("decimal commas"), "{}", e.message);
    }

    #[test]
    fn a_blank_line_inside_the_data_is_refused() {
        let text = "t,acc_g\n0,0.01\n0.01,0.02\n\n0.02,0.03\n";
        let e = read(text, &opts()).expect_err("refused");
        assert_eq!(e.line, Some(4));
    }

    #[test]
    fn a_one_column_time_series_is_refused_as_time() {
        let text = "0.00\n0.01\n0.02\n0.03\n0.04\n0.05\n";
        let o = ReadOptions {
            dt: Some(0.01),
            unit: Some(Unit::G),
            ..opts()
        };
        let e = read(text, &o).expect_err("refused");
        assert_eq!(e.field, "body");
        assert!(e.message.contains("time column"), "{}", e.message);
    }

    #[test]
    fn interleaved_time_and_acceleration_in_one_column_are_refused() {
        let text = "0.00\n0.012\n0.01\n-0.020\n0.02\n0.031\n0.03\n-0.004\n";
        let o = ReadOptions {
            dt: Some(0.01),
            unit: Some(Unit::G),
            ..opts()
        };
        let e = read(text, &o).expect_err("refused");
        assert_eq!(e.field, "body");
        assert!(
            e.message.contains("(time, acceleration) pairs"),
            "{}",
            e.message
        );
    }

    #[test]
    fn a_second_text_row_that_is_not_units_is_refused() {
        let text = "Station XYZ\nTime,Acc\n0,0.01\n0.01,0.02\n";
        let e = read(text, &opts()).expect_err("refused");
        assert_eq!(e.line, Some(2));
    }

    #[test]
    fn column_parses_positions_and_names() {
        assert_eq!(Column::parse(" 2 "), Column::Index(2));
        assert_eq!(Column::parse("0"), Column::Name("0".into()));
        assert_eq!(Column::parse("acc (g)"), Column::Name("acc (g)".into()));
    }
}
