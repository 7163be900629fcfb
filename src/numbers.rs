//! Numbers as people read them, in labels and messages.

/// A number for a label: at most `digits` significant digits, no trailing
/// zeros; beyond 10^9 or below 10^-6 in scientific notation (`1.27e307`), never
/// a row of hundreds of digits.
pub fn fmt_num(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-6..=9).contains(&mag) {
        let s = format!("{v:.prec$e}", prec = digits.saturating_sub(1));
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = if mantissa.contains('.') {
            mantissa.trim_end_matches('0').trim_end_matches('.')
        } else {
            mantissa
        };
        return format!("{mantissa}e{exponent}");
    }
    let decimals = (digits as i32 - 1 - mag).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits_and_scientific_notation() {
        assert_eq!(fmt_num(0.25, 3), "0.25");
        assert_eq!(fmt_num(1341.6408, 6), "1341.64");
        assert_eq!(fmt_num(1.2663572206001402e307, 3), "1.27e307");
        assert_eq!(fmt_num(-2.5e-9, 4), "-2.5e-9");
        assert_eq!(fmt_num(f64::INFINITY, 4), "inf");
    }
}
