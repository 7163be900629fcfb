//! The kinds of accelerogram file a record is read from, and how a file's
//! kind is told from its content.

/// The kind of file a record is read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// PEER NGA strong-motion format: four header lines, then the values.
    At2,
    /// Delimited or whitespace-separated columns, with optional header.
    Csv,
    /// A job spec's `ground_motion` object, with a `name`.
    Json,
}

impl Format {
    /// The format named `text` (case-insensitive, a leading `.` allowed):
    /// `at2`; `csv`, `txt`, `tsv` or `dat` for columns; `json`.
    pub fn parse(text: &str) -> Option<Format> {
        let key = text.trim().trim_start_matches('.').to_ascii_lowercase();
        match key.as_str() {
            "at2" => Some(Format::At2),
            "csv" | "txt" | "tsv" | "dat" => Some(Format::Csv),
            "json" => Some(Format::Json),
            _ => None,
        }
    }

    /// `at2`, `csv` or `json`.
    pub fn as_str(self) -> &'static str {
        match self {
            Format::At2 => "at2",
            Format::Csv => "csv",
            Format::Json => "json",
        }
    }

    /// The format of `text` (BOM already stripped) told from its content:
    /// JSON starts with `{`; an AT2 file's fourth line holds the words `NPTS`
    /// or `DT`, or its third says `UNITS OF`; anything else is columns. A
    /// comment line (`#`, `%`, `//`) is never an AT2 header line, so a
    /// column file whose fourth line is `# dt = 0.01` stays columns.
    pub fn detect(text: &str) -> Format {
        if text.trim_start().starts_with('{') {
            return Format::Json;
        }
        let mut lines = super::text::numbered_lines(text).map(|(_, l)| l);
        let (third, fourth) = (lines.nth(2), lines.next());
        let header = |line: Option<&str>, says: &dyn Fn(&str) -> bool| {
            line.is_some_and(|l| !is_comment(l) && says(l))
        };
        let fourth_names_npts_or_dt = header(fourth, &|l| {
            words(l).any(|w| w.eq_ignore_ascii_case("npts") || w.eq_ignore_ascii_case("dt"))
        });
        let third_says_units = header(third, &|l| l.to_ascii_uppercase().contains("UNITS OF"));
        if fourth_names_npts_or_dt || third_says_units {
            Format::At2
        } else {
            Format::Csv
        }
    }
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Whether `line` is a comment in a column file: it starts (after blanks)
/// with `#`, `%` or `//`.
pub fn is_comment(line: &str) -> bool {
    let l = line.trim_start();
    l.starts_with('#') || l.starts_with('%') || l.starts_with("//")
}

/// The runs of ASCII letters in `line`: `NPTS=  4015, DT= .0100SEC` holds
/// `NPTS`, `DT`, `SEC` (a word glued to a number still counts; `WIDTH` does
/// not hold `DT`).
pub fn words(line: &str) -> impl Iterator<Item = &str> {
    line.split(|c: char| !c.is_ascii_alphabetic())
        .filter(|w| !w.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_names_parse_case_insensitively() {
        assert_eq!(Format::parse("AT2"), Some(Format::At2));
        assert_eq!(Format::parse("txt"), Some(Format::Csv));
        assert_eq!(Format::parse("CSV"), Some(Format::Csv));
        assert_eq!(Format::parse(".json"), Some(Format::Json));
        assert_eq!(Format::parse("xlsx"), None);
        for f in [Format::At2, Format::Csv, Format::Json] {
            assert_eq!(Format::parse(f.as_str()), Some(f));
        }
    }

    #[test]
    fn content_tells_the_format() {
        assert_eq!(Format::detect("  {\"dt\": 0.01}"), Format::Json);
        let at2 = "PEER\nX\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 3, DT= .01 SEC\n1 2 3\n";
        assert_eq!(Format::detect(at2), Format::At2);
        let old = "PEER\nX\nY\n  3   .0100   NPTS, DT\n1 2 3\n";
        assert_eq!(Format::detect(old), Format::At2);
        let units_only = "PEER\nX\nACCELERATION IN UNITS OF G\n3 .01\n1 2 3\n";
        assert_eq!(Format::detect(units_only), Format::At2);
        assert_eq!(Format::detect("0,1\n0.01,2\n0.02,3\n0.03,4\n"), Format::Csv);
        let commented = "# a\n# b\n# units of g\n# dt = 0.01\n1\n2\n";
        assert_eq!(Format::detect(commented), Format::Csv);
        let width = "t,a\n0,1\n0.01,2\nwidth,x\n";
        assert_eq!(Format::detect(width), Format::Csv);
    }
}
