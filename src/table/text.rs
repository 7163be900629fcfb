//! Text cells: quoted when they need to be (RFC 4180), and safe to open in
//! a spreadsheet.

use std::borrow::Cow;

use serde::{Serialize, Serializer};

/// A text cell ([`quote`]): names given by the user, and the words a result
/// writes (a transition's direction, say).
#[derive(Clone, Copy, Debug)]
pub struct Text<T>(pub T);

impl<T: AsRef<str>> Serialize for Text<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&quote(self.0.as_ref()))
    }
}

/// `s` as a CSV field (RFC 4180), safe to open in a spreadsheet: text
/// starting with `=`, `+`, `-`, `@`, a tab or a carriage return would be read
/// as a formula, so it gets a leading `'` and quotes (OWASP's rule for CSV
/// injection). Only text goes through here; numbers are written as they
/// are.
pub fn quote(s: &str) -> Cow<'_, str> {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        Cow::Owned(format!("\"'{}\"", s.replace('"', "\"\"")))
    } else if s.contains([',', '"', '\n', '\r']) {
        Cow::Owned(format!("\"{}\"", s.replace('"', "\"\"")))
    } else {
        Cow::Borrowed(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn user_text_cannot_be_a_spreadsheet_formula() {
        for (name, cell) in [
            (
                "=HYPERLINK(\"http://evil\",\"x\")",
                "\"'=HYPERLINK(\"\"http://evil\"\",\"\"x\"\")\"",
            ),
            ("+1+2", "\"'+1+2\""),
            ("-2+3", "\"'-2+3\""),
            ("@SUM(A1)", "\"'@SUM(A1)\""),
            ("\t=1", "\"'\t=1\""),
            ("\r=1", "\"'\r=1\""),
            ("a=1", "a=1"),
            ("loco, 1906", "\"loco, 1906\""),
            ("say \"hi\"", "\"say \"\"hi\"\"\""),
            ("two\nlines", "\"two\nlines\""),
            ("", ""),
        ] {
            assert_eq!(quote(name), cell, "{name:?}");
        }
    }
}
