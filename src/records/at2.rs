//! PEER NGA strong-motion files (`.AT2`): four header lines, then the
//! accelerations, several to a line.
//!
//! ```text
//! PEER NGA STRONG MOTION DATABASE RECORD
//! Imperial Valley-06, 10/15/1979, El Centro Array #6, 230
//! ACCELERATION TIME SERIES IN UNITS OF G
//! NPTS=  3930, DT=   .0050 SEC
//!   .1234E-02  .2345E-02 -.3456E-02 ...
//! ```
//!
//! Line 3 states the unit (`IN UNITS OF G`, `CM/S/S`, `CM/SEC/SEC`,
//! `CM/S^2`; `TIME HISTORY` in the older files, `TIME SERIES` in
//! NGA-West2). Line 4 states the count and the step in one of the spellings
//! the public readers handle (OpenSees' `ReadRecord.tcl`, its Python port,
//! the NGA readers in pystrata and others): keywords first
//! (`NPTS=  3930, DT= .00500 SEC`, commas, `=` and `SEC` optional, in either
//! order) or numbers first (`  3930    .00500    NPTS, DT`, the older PEER
//! database), or the two numbers alone. Values are free format or fixed
//! width; in fixed width a minus sign may touch the number before it
//! (`-.1234E-02-.5678E-03`), and Fortran writes `D` exponents.

use super::MAX_RECORD_SAMPLES;
use super::format::words;
use super::number;
use super::text::{clip, numbered_lines, quote};
use super::unit::{ACCEPTED_UNITS, Unit, bracketed};
use super::{MAX_NAME_CHARS, Parsed, ReadError, ReadOptions, RecordWarning};

/// Reads an AT2 file.
pub(super) fn read(text: &str, opts: &ReadOptions) -> Result<Parsed, ReadError> {
    let mut lines = numbered_lines(text);
    let mut header = Vec::with_capacity(4);
    for (_, line) in lines.by_ref().take(4) {
        header.push(line);
    }
    let [title, event, units, counts] = header[..] else {
        return Err(ReadError::body(
            None,
            format!(
                "an AT2 file has four header lines (title; event and station; units; NPTS and \
                 DT) before its values, and this one has {} lines",
                header.len()
            ),
        ));
    };
    let unit = unit(units, opts)?;
    let (npts, dt) = counts_and_step(counts, opts)?;
    let acc = values(lines, unit, npts)?;
    let warnings = npts
        .filter(|&npts| npts != acc.len())
        .map(|npts| npts_mismatch(npts, acc.len()))
        .into_iter()
        .collect();
    // Line 2 names the event, station and component; line 1 is a title.
    let name = [event, title]
        .into_iter()
        .map(|l| clip(l, MAX_NAME_CHARS))
        .find(|l| !l.is_empty());
    Ok(Parsed {
        name,
        unit,
        dt,
        acc,
        warnings,
        flat: true,
    })
}

/// The accelerations of the value `lines` (after the header) in `unit`, in
/// m/s², up to an END line (`npts`: the count line 4 states).
fn values<'a>(
    lines: impl Iterator<Item = (usize, &'a str)>,
    unit: Unit,
    npts: Option<usize>,
) -> Result<Vec<f64>, ReadError> {
    let mut acc = Vec::with_capacity(npts.unwrap_or(0).min(MAX_RECORD_SAMPLES));
    let mut buffer = String::new();
    let mut ended_at = None;
    for (n, line) in lines {
        if let Some(end) = ended_at {
            if !line.trim().is_empty() {
                return Err(ReadError::body(
                    Some(n),
                    format!("values follow the END on line {end}: {}", quote(line)),
                ));
            }
            continue;
        }
        if line.trim().eq_ignore_ascii_case("end") {
            ended_at = Some(n);
            continue;
        }
        let mut take = |piece: &str| {
            let a = number::acceleration(piece, unit, &mut buffer).ok_or_else(|| {
                ReadError::body(
                    Some(n),
                    format!("{} is not a number, in {}", quote(piece), quote(line)),
                )
            })?;
            if !a.is_finite() {
                return Err(ReadError::body(
                    Some(n),
                    format!("{} is too large to be an acceleration", quote(piece)),
                ));
            }
            if acc.len() == MAX_RECORD_SAMPLES {
                return Err(super::too_many().at_line(n));
            }
            acc.push(a);
            Ok(())
        };
        for token in line.split_whitespace() {
            match touching(token) {
                Touching::One => take(token)?,
                Touching::Many(pieces) => pieces.into_iter().try_for_each(&mut take)?,
                Touching::Unclear => {
                    return Err(ReadError::body(
                        Some(n),
                        format!(
                            "{} cannot be split into numbers (numbers that touch need decimal \
                             points), in {}",
                            quote(token),
                            quote(line)
                        ),
                    ));
                }
            }
        }
    }
    Ok(acc)
}

/// The warning that line 4's count, `npts`, is not the `found` values'.
fn npts_mismatch(npts: usize, found: usize) -> RecordWarning {
    let advice = if npts > found {
        "the file may have been cut short: download it again"
    } else {
        "check that the file holds a single record"
    };
    RecordWarning {
        kind: "npts_mismatch",
        message: format!(
            "line 4 says NPTS = {npts}, but the file holds {found} values, which are used as \
             read; {advice}"
        ),
    }
}

/// The unit stated on line 3, checked against the option.
fn unit(line: &str, opts: &ReadOptions) -> Result<Unit, ReadError> {
    let first_word = line.split_whitespace().next().unwrap_or("");
    for quantity in ["VELOCITY", "DISPLACEMENT"] {
        if first_word.eq_ignore_ascii_case(quantity) {
            return Err(ReadError::body(
                Some(3),
                format!(
                    "this is a {} time series ({}): upload the acceleration file (.AT2) of the \
                     record",
                    quantity.to_ascii_lowercase(),
                    quote(line)
                ),
            ));
        }
    }
    match (stated_unit(line), opts.unit) {
        (Some(stated), option) => {
            super::agree_unit(option, stated, "line 3 of the file").map_err(|e| e.at_line(3))?;
            Ok(stated)
        }
        (None, Some(option)) => Ok(option),
        (None, None) => Err(ReadError::new(
            "unit",
            format!(
                "line 3 ({}) states no unit that can be read: give unit ({ACCEPTED_UNITS})",
                quote(line)
            ),
        )
        .at_line(3)),
    }
}

/// The unit after `UNITS OF` (or in brackets) on `line`.
fn stated_unit(line: &str) -> Option<Unit> {
    // ASCII upper-casing keeps byte offsets, so `at` indexes `line` too.
    let upper = line.to_ascii_uppercase();
    let after = ["UNITS OF", "UNITS:", "UNIT:"]
        .iter()
        .find_map(|key| upper.find(key).map(|at| &line[at + key.len()..]));
    match after {
        Some(rest) => {
            let rest = rest.trim().trim_end_matches(['.', ',', ';']);
            Unit::parse(rest).or_else(|| {
                let first = rest.split_whitespace().next()?;
                Unit::parse(first.trim_end_matches(['.', ',', ';']))
            })
        }
        None => bracketed(line).and_then(Unit::parse),
    }
}

/// One item of line 4: a number's text or a word.
#[derive(Debug, PartialEq)]
enum Item<'a> {
    Number(&'a str),
    Word(&'a str),
}

/// Line 4 as numbers and words; `=`, `,`, `:` and blanks only separate.
fn items(line: &str) -> Vec<Item<'_>> {
    let bytes = line.as_bytes();
    let mut items = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c.is_ascii_alphabetic() {
            let start = i;
            while i < bytes.len() && bytes[i].is_ascii_alphabetic() {
                i += 1;
            }
            items.push(Item::Word(&line[start..i]));
        } else if let Some(end) = number_end(bytes, i) {
            items.push(Item::Number(&line[i..end]));
            i = end;
        } else {
            i += 1;
        }
    }
    items
}

/// The end of the number starting at `start` in `bytes`, if one does:
/// `[+-] digits [. digits] [(E|D) [+-] digits]`, an exponent only when
/// digits follow its letter (so `.0050SEC` ends before `SEC`).
fn number_end(bytes: &[u8], start: usize) -> Option<usize> {
    let digits = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = start;
    if matches!(bytes.get(i), Some(b'+' | b'-')) {
        i += 1;
    }
    let integer_end = digits(i);
    let mut end = integer_end;
    let mut any = integer_end > i;
    if bytes.get(end) == Some(&b'.') {
        let fraction_end = digits(end + 1);
        any |= fraction_end > end + 1;
        end = fraction_end;
    }
    if !any {
        return None;
    }
    if matches!(bytes.get(end), Some(b'e' | b'E' | b'd' | b'D')) {
        let mut j = end + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let exponent_end = digits(j);
        if exponent_end > j {
            end = exponent_end;
        }
    }
    Some(end)
}

/// NPTS and DT from line 4, checked against the option `dt`.
fn counts_and_step(line: &str, opts: &ReadOptions) -> Result<(Option<usize>, f64), ReadError> {
    let items = items(line);
    let is = |item: &Item, key: &str| matches!(item, Item::Word(w) if w.eq_ignore_ascii_case(key));
    let mut npts_text = None;
    let mut dt_text = None;
    // Keywords first: NPTS= 3930, DT= .005 SEC (either order).
    for pair in items.windows(2) {
        if let Item::Number(value) = pair[1] {
            if is(&pair[0], "NPTS") {
                npts_text = Some(value);
            } else if is(&pair[0], "DT") {
                dt_text = Some(value);
            }
        }
    }
    // Numbers first: 3930 .00500 NPTS, DT (the keywords name the numbers
    // in order), or the two numbers alone.
    if npts_text.is_none() && dt_text.is_none() {
        let numbers: Vec<&str> = items
            .iter()
            .map_while(|item| match item {
                Item::Number(n) => Some(*n),
                Item::Word(_) => None,
            })
            .collect();
        let keys: Vec<&str> = words(line)
            .filter(|w| w.eq_ignore_ascii_case("NPTS") || w.eq_ignore_ascii_case("DT"))
            .collect();
        if keys.is_empty() && numbers.len() == 2 {
            npts_text = Some(numbers[0]);
            dt_text = Some(numbers[1]);
        } else {
            for (value, key) in numbers.iter().zip(&keys) {
                if key.eq_ignore_ascii_case("NPTS") {
                    npts_text = Some(value);
                } else {
                    dt_text = Some(value);
                }
            }
        }
    }

    let npts = match npts_text {
        None => None,
        // A whole number, possibly written with a point (`3930.`).
        Some(text) => Some(whole(text).ok_or_else(|| {
            ReadError::body(
                Some(4),
                format!(
                    "NPTS on line 4 ({}) is {text:?}, not a whole number of points",
                    quote(line)
                ),
            )
        })?),
    };
    let dt = match (dt_text, opts.dt) {
        (Some(text), option) => {
            let dt = number::parse(text).ok_or_else(|| {
                ReadError::body(
                    Some(4),
                    format!("DT on line 4 ({}) is not a number", quote(line)),
                )
            })?;
            super::check_dt(dt).map_err(|m| {
                ReadError::body(Some(4), format!("{m} (DT on line 4: {})", quote(line)))
            })?;
            super::agree_dt(option, dt, "line 4 of the file").map_err(|e| e.at_line(4))?;
            dt
        }
        (None, Some(option)) => option,
        (None, None) => {
            return Err(ReadError::new(
                "dt",
                format!(
                    "line 4 ({}) states no DT (expected e.g. \"NPTS=  3930, DT= .0050 SEC\" or \
                     \"3930  .0050  NPTS, DT\"): give dt, in seconds",
                    quote(line)
                ),
            )
            .at_line(4));
        }
    };
    Ok((npts, dt))
}

/// The whole number written `text` (`3930`, `3930.`, `3.93E+03`).
fn whole(text: &str) -> Option<usize> {
    text.parse::<usize>().ok().or_else(|| {
        let x = number::parse(text)?;
        (x >= 0.0 && x.fract() == 0.0 && x <= MAX_RECORD_SAMPLES as f64 * 1e3).then_some(x as usize)
    })
}

/// How one whitespace-free token of values splits into numbers.
#[derive(Debug, PartialEq)]
enum Touching<'a> {
    /// It is one number (or not a number at all).
    One,
    /// Numbers whose signs touch the number before them.
    Many(Vec<&'a str>),
    /// A sign inside it, but pieces without a decimal point (`12-3`).
    Unclear,
}

/// The numbers in one whitespace-free `token`: fixed-width files let a sign
/// touch the number before it (`-.1234E-02-.5678E-03`), so a `+` or `-`
/// that neither starts the token nor follows an exponent letter starts a
/// new number. Each number of a token so split must have a decimal point:
/// `12-3` is refused rather than read as 12 and −3.
fn touching(token: &str) -> Touching<'_> {
    let bytes = token.as_bytes();
    let splits_at = |i: usize| {
        i > 0
            && matches!(bytes[i], b'+' | b'-')
            && !matches!(bytes[i - 1], b'e' | b'E' | b'd' | b'D')
    };
    if !(1..bytes.len()).any(splits_at) {
        return Touching::One;
    }
    let mut pieces = Vec::new();
    let mut start = 0;
    for i in (1..bytes.len()).filter(|&i| splits_at(i)) {
        pieces.push(&token[start..i]);
        start = i;
    }
    pieces.push(&token[start..]);
    if pieces.iter().all(|p| p.contains('.')) {
        Touching::Many(pieces)
    } else {
        Touching::Unclear
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Format, ReadOptions, read};
    use super::*;

    /// A small AT2 file with header line 3 `units` and line 4 `counts`.
    fn at2(units: &str, counts: &str, values: &str) -> String {
        format!(
            "PEER NGA STRONG MOTION DATABASE RECORD\n\
             Imperial Valley-06, 10/15/1979, El Centro Array #6, 230\n\
             {units}\n{counts}\n{values}"
        )
    }

    const VALUES: &str = "  .1000E-01  .3000E-01 -.2000E-01  .5000E-01 -.4000E-01\n  .2000E-01\n";

    fn expected_g() -> Vec<f64> {
        [0.01, 0.03, -0.02, 0.05, -0.04, 0.02]
            .iter()
            .map(|g| g * 9.81)
            .collect()
    }

    #[test]
    fn every_line_4_spelling_gives_npts_and_dt() {
        for counts in [
            "NPTS=     6, DT=   .0100 SEC",
            "NPTS=  6, DT= .0100",
            "NPTS= 6 DT= .01",
            "NPTS=6,DT=.0100SEC",
            "npts = 6, dt = 0.01 sec",
            "DT= .0100 SEC, NPTS= 6",
            "     6    .0100    NPTS, DT",
            "6 0.01000 NPTS, DT",
            "   .0100     6    DT, NPTS",
            "6 .01",
            "NPTS=     6, DT=   1.0D-02 SEC",
            "NPTS=    6., DT=   .0100 SEC",
        ] {
            let text = at2("ACCELERATION TIME SERIES IN UNITS OF G", counts, VALUES);
            let r =
                read(&text, &ReadOptions::default()).unwrap_or_else(|e| panic!("{counts}: {e}"));
            assert_eq!(r.format, Format::At2, "{counts}");
            assert_eq!(r.dt, 0.01, "{counts}");
            assert_eq!(r.acc, expected_g(), "{counts}");
            assert!(r.warnings.is_empty(), "{counts}: {:?}", r.warnings);
        }
    }

    #[test]
    fn nga_west2_header_reads_unit_dt_and_name() {
        let text = at2(
            "ACCELERATION TIME SERIES IN UNITS OF G",
            "NPTS=     6, DT=   .0100 SEC",
            VALUES,
        );
        let r = read(&text, &ReadOptions::default()).expect("reads");
        assert_eq!(r.unit, Unit::G);
        assert_eq!(
            r.name,
            "Imperial Valley-06, 10/15/1979, El Centro Array #6, 230"
        );
    }

    #[test]
    fn older_time_history_header_with_trailing_npts_dt_reads() {
        let text = "PACIFIC ENGINEERING AND ANALYSIS STRONG-MOTION DATA\r\n \
                    IMPERIAL VALLEY 10/15/79 2319, EL CENTRO ARRAY 6, 230\r\n  \
                    ACCELERATION TIME HISTORY IN UNITS OF G\r\n  \
                    6 0.01000 NPTS, DT\r\n .01 .03 -.02 .05 -.04\r\n .02\r\n";
        let r = read(text, &ReadOptions::default()).expect("reads");
        assert_eq!(r.dt, 0.01);
        assert_eq!(r.acc, expected_g());
        assert_eq!(
            r.name,
            "IMPERIAL VALLEY 10/15/79 2319, EL CENTRO ARRAY 6, 230"
        );
    }

    #[test]
    fn centimetre_units_on_line_3_read_exactly() {
        for units in [
            "ACCELERATION TIME SERIES IN UNITS OF CM/S/S",
            "ACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC",
            "ACCELERATION TIME SERIES IN UNITS OF CM/S^2",
            "ACCELERATION (CM/S2)",
        ] {
            let text = at2(units, "NPTS= 3, DT= .005", "12.5 -30.25 0.7\n");
            let r = read(&text, &ReadOptions::default()).unwrap_or_else(|e| panic!("{units}: {e}"));
            assert_eq!(r.unit, Unit::CentimetresPerSecondSquared, "{units}");
            assert_eq!(r.acc, vec![0.125, -0.3025, 0.007], "{units}");
        }
    }

    #[test]
    fn fixed_width_values_with_touching_minus_signs_split() {
        let text = at2(
            "ACCELERATION TIME SERIES IN UNITS OF G",
            "NPTS=  5, DT= .01",
            " .1000E-01-.2000E-01-.3000E-01\n-.4000E-01 .5000D-01\n",
        );
        let r = read(&text, &ReadOptions::default()).expect("reads");
        let expected: Vec<f64> = [0.01, -0.02, -0.03, -0.04, 0.05]
            .iter()
            .map(|g| g * 9.81)
            .collect();
        assert_eq!(r.acc, expected);
    }

    #[test]
    fn touching_numbers_without_decimal_points_are_refused() {
        assert_eq!(touching("12-3"), Touching::Unclear);
        assert_eq!(touching("-.1E-02"), Touching::One);
        assert_eq!(
            touching("1.5E-02+2.5E+01"),
            Touching::Many(vec!["1.5E-02", "+2.5E+01"])
        );
        let text = at2("IN UNITS OF G", "NPTS= 2, DT= .01", "0.1 12-3\n");
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(5)));
    }

    #[test]
    fn npts_disagreeing_with_the_values_warns_with_both_numbers() {
        let text = at2("IN UNITS OF G", "NPTS=     8, DT=   .0100 SEC", VALUES);
        let r = read(&text, &ReadOptions::default()).expect("reads");
        assert_eq!(r.acc.len(), 6);
        let w: Vec<_> = r
            .warnings
            .iter()
            .filter(|w| w.kind == "npts_mismatch")
            .collect();
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("NPTS = 8"), "{}", w[0].message);
        assert!(w[0].message.contains("6 values"), "{}", w[0].message);
    }

    #[test]
    fn an_unknown_unit_line_is_refused_naming_unit_and_line_3() {
        let text = at2(
            "ACCELERATION TIME SERIES IN UNITS OF FT/S2",
            "NPTS= 6, DT= .01",
            VALUES,
        );
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("unit", Some(3)));
        assert!(e.message.contains("cm/s2"), "{}", e.message);
        // The option decides when the file cannot.
        let opts = ReadOptions {
            unit: Some(Unit::G),
            ..ReadOptions::default()
        };
        assert_eq!(read(&text, &opts).expect("reads").acc, expected_g());
    }

    #[test]
    fn options_disagreeing_with_the_header_are_refused() {
        let text = at2("IN UNITS OF G", "NPTS= 6, DT= .01", VALUES);
        let unit = ReadOptions {
            unit: Some(Unit::CentimetresPerSecondSquared),
            ..ReadOptions::default()
        };
        assert_eq!(read(&text, &unit).expect_err("refused").field, "unit");
        let dt = ReadOptions {
            dt: Some(0.02),
            ..ReadOptions::default()
        };
        assert_eq!(read(&text, &dt).expect_err("refused").field, "dt");
        let same = ReadOptions {
            dt: Some(0.01),
            unit: Some(Unit::G),
            ..ReadOptions::default()
        };
        assert!(read(&text, &same).is_ok());
    }

    #[test]
    fn a_velocity_file_is_refused_with_a_hint() {
        let text = at2(
            "VELOCITY TIME SERIES IN UNITS OF CM/S",
            "NPTS= 6, DT= .01",
            VALUES,
        );
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(3)));
        assert!(e.message.contains(".AT2"), "{}", e.message);
    }

    #[test]
    fn a_missing_dt_is_asked_for_and_a_wild_one_refused() {
        let text = at2("IN UNITS OF G", "NPTS= 6", VALUES);
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("dt", Some(4)));
        let text = at2("IN UNITS OF G", "NPTS= 6, DT= 5.0 SEC", VALUES);
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(4)));
    }

    #[test]
    fn a_word_among_the_values_is_refused_naming_its_line() {
        let text = at2(
            "IN UNITS OF G",
            "NPTS= 6, DT= .01",
            ".01 .02\n.03 oops .04\n",
        );
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!((e.field.as_str(), e.line), ("body", Some(6)));
        assert!(e.message.contains("oops"), "{}", e.message);
    }

    #[test]
    fn a_closing_end_line_is_allowed_but_not_values_after_it() {
        let text = at2(
            "IN UNITS OF G",
            "NPTS= 6, DT= .01",
            &format!("{VALUES}END\n\n"),
        );
        assert_eq!(
            read(&text, &ReadOptions::default()).expect("reads").acc,
            expected_g()
        );
        let text = at2(
            "IN UNITS OF G",
            "NPTS= 6, DT= .01",
            &format!("{VALUES}END\n.07\n"),
        );
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!(e.line, Some(8));
    }

    #[test]
    fn a_200000_sample_file_parses() {
        let n = 200_000;
        let mut values = String::with_capacity(16 * n);
        for k in 0..n {
            let g = 0.3 * (0.01 * k as f64).sin() * (-(k as f64) / 80_000.0).exp();
            values.push_str(&format!("{g:11.4E}"));
            if k % 5 == 4 {
                values.push('\n');
            }
        }
        let text = at2(
            "ACCELERATION TIME SERIES IN UNITS OF G",
            &format!("NPTS={n:7}, DT=   .0050 SEC"),
            &values,
        );
        let r = read(&text, &ReadOptions::default()).expect("reads");
        assert_eq!(r.acc.len(), n);
        let k = 12_345;
        let g = 0.3 * (0.01 * k as f64).sin() * (-(k as f64) / 80_000.0).exp();
        let written: f64 = format!("{g:.4E}").parse().expect("number");
        assert_eq!(r.acc[k], written * 9.81);
        assert!(r.warnings.iter().all(|w| w.kind != "npts_mismatch"));
    }

    #[test]
    fn more_than_the_largest_record_is_refused() {
        let n = MAX_RECORD_SAMPLES + 1;
        let values = ".001 -.001\n".repeat(n.div_ceil(2));
        let text = at2("IN UNITS OF G", "NPTS= 1, DT= .01", &values);
        let e = read(&text, &ReadOptions::default()).expect_err("refused");
        assert_eq!(e.field, "body");
        assert!(
            e.message.contains(&MAX_RECORD_SAMPLES.to_string()),
            "{}",
            e.message
        );
    }
}
