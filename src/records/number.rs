//! Numbers read from a file's text, converted to m/s² without a rounding of
//! their own.
//!
//! A value in cm/s² is divided by 100 in its text, by lowering its decimal
//! exponent by 2, before it becomes an `f64`: the standard library's parse
//! rounds correctly, so `1.23` cm/s² and `0.0123` m/s² become the same bits,
//! and a motion uploaded in either unit gets the same
//! [`record_id`](super::record_id). Multiplying by 0.01 afterwards would round
//! twice. A value in g is multiplied by [`G_M_S2`](super::G_M_S2) after the
//! parse, exactly as a job spec's `"unit": "g"` is.

use super::unit::Unit;

/// The parts of a decimal number's text: `[+-] mantissa [(e|E|d|D) [+-] digits]`.
struct Decimal<'a> {
    /// Sign and mantissa, e.g. `-.1234`.
    mantissa: &'a str,
    /// The written exponent (0 when none), saturated far beyond f64's range.
    exponent: i64,
    /// Whether the text can go to `f64::from_str` as it is (no `D`
    /// exponent).
    plain: bool,
}

/// Splits `text` into a [`Decimal`], or `None` when it is not a decimal
/// number (`inf`, `NaN`, hexadecimal, an empty mantissa, stray characters).
fn decimal(text: &str) -> Option<Decimal<'_>> {
    let bytes = text.as_bytes();
    let mut i = 0;
    if matches!(bytes.first(), Some(b'+' | b'-')) {
        i = 1;
    }
    let mut digits = 0;
    while i < bytes.len() && bytes[i].is_ascii_digit() {
        i += 1;
        digits += 1;
    }
    if i < bytes.len() && bytes[i] == b'.' {
        i += 1;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
            digits += 1;
        }
    }
    if digits == 0 {
        return None;
    }
    let mantissa = &text[..i];
    if i == bytes.len() {
        return Some(Decimal {
            mantissa,
            exponent: 0,
            plain: true,
        });
    }
    let plain = matches!(bytes[i], b'e' | b'E');
    if !(plain || matches!(bytes[i], b'd' | b'D')) {
        return None;
    }
    let exponent_text = &text[i + 1..];
    let unsigned = exponent_text
        .strip_prefix(['+', '-'])
        .unwrap_or(exponent_text);
    if unsigned.is_empty() || !unsigned.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    // Past ±10⁶ every f64 is 0 or ∞ anyway; saturate instead of overflowing.
    let magnitude: i64 = unsigned.parse().unwrap_or(i64::MAX).min(1_000_000);
    let exponent = if exponent_text.starts_with('-') {
        -magnitude
    } else {
        magnitude
    };
    Some(Decimal {
        mantissa,
        exponent,
        plain,
    })
}

/// Whether `text` is a decimal number (see [`parse`]).
pub fn is_number(text: &str) -> bool {
    decimal(text).is_some()
}

/// The value of the decimal number `text` times 10^`shift`, rounded once.
/// `None` when `text` is not a decimal number; the result may be infinite
/// when the written exponent is out of range (the caller refuses it).
/// Fortran's `D` exponent is read as `E`. `buffer` is scratch space reused
/// between calls.
pub fn parse_shifted(text: &str, shift: i64, buffer: &mut String) -> Option<f64> {
    let d = decimal(text)?;
    if shift == 0 && d.plain {
        return text.parse().ok();
    }
    use std::fmt::Write;
    buffer.clear();
    buffer.push_str(d.mantissa);
    let _ = write!(buffer, "e{}", d.exponent + shift);
    buffer.parse().ok()
}

/// The value of the decimal number `text`, rounded once.
pub fn parse(text: &str) -> Option<f64> {
    parse_shifted(text, 0, &mut String::new())
}

/// The acceleration written as `text` in `unit`, in m/s² (see the module
/// doc for why cm/s² is converted in the text).
pub fn acceleration(text: &str, unit: Unit, buffer: &mut String) -> Option<f64> {
    match unit {
        Unit::MetresPerSecondSquared => parse_shifted(text, 0, buffer),
        Unit::CentimetresPerSecondSquared => parse_shifted(text, -2, buffer),
        Unit::G => parse_shifted(text, 0, buffer).map(|g| g * super::G_M_S2),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centimetres_and_metres_of_one_decimal_have_the_same_bits() {
        let mut b = String::new();
        for (cm, m) in [
            ("1.23", "0.0123"),
            ("-.1234E+02", "-0.1234"),
            ("981", "9.81"),
            ("0.7", "0.007"),
            ("3.3D-01", "0.0033"),
            ("12345.678901234567", "123.45678901234567"),
        ] {
            let a = acceleration(cm, Unit::CentimetresPerSecondSquared, &mut b).expect("number");
            let c = acceleration(m, Unit::MetresPerSecondSquared, &mut b).expect("number");
            assert_eq!(a.to_bits(), c.to_bits(), "{cm} cm/s2 vs {m} m/s2");
        }
        // Multiplying after the parse would not be exact: 0.7 × 0.01 ≠ 0.007.
        assert_ne!(0.7f64 * 0.01, 0.007);
    }

    #[test]
    fn a_value_in_g_is_the_parsed_value_times_9_81() {
        let mut b = String::new();
        let a = acceleration("0.35", Unit::G, &mut b).expect("number");
        assert_eq!(a.to_bits(), (0.35f64 * 9.81).to_bits());
    }

    #[test]
    fn fortran_d_exponents_read_as_e() {
        assert_eq!(parse("1.5D-03"), Some(1.5e-3));
        assert_eq!(parse("-.25d+01"), Some(-2.5));
        assert_eq!(parse("+2."), Some(2.0));
        assert_eq!(parse(".5"), Some(0.5));
    }

    #[test]
    fn words_and_special_values_are_not_numbers() {
        for text in [
            "", "-", ".", "e5", "inf", "NaN", "infinity", "0x10", "1e", "1e+", "1.2.3", "1,5",
            "1_0", "--1", "12a",
        ] {
            assert_eq!(parse(text), None, "{text:?}");
            assert!(!is_number(text), "{text:?}");
        }
    }

    #[test]
    fn an_exponent_out_of_range_gives_infinity_or_zero_not_a_panic() {
        assert_eq!(parse("1e400"), Some(f64::INFINITY));
        assert_eq!(parse("1e-99999999999999999999999"), Some(0.0));
        let mut b = String::new();
        assert_eq!(
            parse_shifted("1e99999999999999999999999", -2, &mut b),
            Some(f64::INFINITY)
        );
    }
}
