//! A record file's text as numbered lines, whatever its line endings, and the
//! short quotes of them that error messages carry.

/// Longest quote of a line in an error message, in characters.
pub const QUOTE_CHARS: usize = 40;

/// `text` without a leading UTF-8 byte-order mark.
pub fn without_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The lines of `text` with their 1-based numbers, ends stripped of `\r`:
/// `\n` and `\r\n` end lines, and so does a lone `\r` in a file that has no
/// `\n` at all (old Macintosh files).
pub fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let separator = if !text.contains('\n') && text.contains('\r') {
        '\r'
    } else {
        '\n'
    };
    text.split(separator)
        .map(|line| line.strip_suffix('\r').unwrap_or(line))
        .enumerate()
        .map(|(i, line)| (i + 1, line))
}

/// `line` trimmed and cut to [`QUOTE_CHARS`] characters (with `…` when cut),
/// in quotes, for an error message.
pub fn quote(line: &str) -> String {
    let line = line.trim();
    let mut chars = line.chars();
    let head: String = chars.by_ref().take(QUOTE_CHARS).collect();
    if chars.next().is_some() {
        format!("{head:?}…")
    } else {
        format!("{head:?}")
    }
}

/// `name` trimmed, cut to `max` characters.
pub fn clip(name: &str, max: usize) -> String {
    name.trim()
        .chars()
        .take(max)
        .collect::<String>()
        .trim()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crlf_lf_and_lone_cr_files_give_the_same_lines() {
        let expected = vec![(1, "a"), (2, "b"), (3, "")];
        for text in ["a\nb\n", "a\r\nb\r\n", "a\rb\r"] {
            assert_eq!(
                numbered_lines(text).collect::<Vec<_>>(),
                expected,
                "{text:?}"
            );
        }
    }

    #[test]
    fn a_bom_is_stripped_once() {
        assert_eq!(without_bom("\u{feff}x"), "x");
        assert_eq!(without_bom("x"), "x");
    }

    #[test]
    fn quotes_stop_at_forty_characters() {
        let long = "x".repeat(100);
        let q = quote(&long);
        assert_eq!(q, format!("\"{}\"…", "x".repeat(40)));
        assert_eq!(quote("  1, 2  "), "\"1, 2\"");
    }
}
