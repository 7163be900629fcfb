//! Numbers as a CSV table writes them: to 15 significant digits, in JSON's
//! style.

use serde::{Serialize, Serializer};

/// The significant digits a CSV number keeps: 15, the most any decimal
/// keeps through a double and back. Beyond them a double's digits are the
/// rounding of the arithmetic that made it (a grid from 0.1 to 1 in 10 steps
/// holds 0.30000000000000004 and 0.7999999999999999, a size 0.5 comes back
/// from its p as 0.5000000000000001); to 15 digits those are the decimals the
/// user wrote, and computed values keep a relative precision of 5e-15. The
/// JSON document holds every double exactly.
pub const SIGNIFICANT_DIGITS: usize = 15;

/// `x` as a CSV number: `x` rounded to [`SIGNIFICANT_DIGITS`], written as the
/// shortest decimal that reads back as that double, in JSON's style (`1.0`,
/// `1e-7`, `-0.0`); empty when `x` is not finite (JSON has no such number).
///
/// The rounding starts from the shortest decimal of `x` (as JSON writes it):
/// when it has at most 15 digits it is the answer, as no other decimal of 15
/// digits lies within half an ulp of `x`; with 17, or 16 not ending in 5, no
/// tie of the 15-digit rounding lies between it and `x` (the shortest decimal
/// would be that tie), so its digits round as `x` does. Only a 16th digit 5
/// asks for `x`'s exact digits.
pub fn number(x: f64) -> String {
    let Some(shortest) = json_number(x) else {
        return String::new();
    };
    let Some(Digits {
        negative,
        mut digits,
        mut power,
    }) = Digits::of(&shortest)
    else {
        return shortest;
    };
    if digits.len() <= SIGNIFICANT_DIGITS {
        return shortest;
    }
    let decimal = if digits.len() == SIGNIFICANT_DIGITS + 1 && digits.ends_with(b"5") {
        format!("{x:.prec$e}", prec = SIGNIFICANT_DIGITS - 1)
    } else {
        let up = digits[SIGNIFICANT_DIGITS] >= b'5';
        digits.truncate(SIGNIFICANT_DIGITS);
        if up {
            while digits.last() == Some(&b'9') {
                digits.pop();
            }
            match digits.last_mut() {
                Some(last) => *last += 1,
                None => {
                    digits.push(b'1');
                    power += 1;
                }
            }
        }
        let sign = if negative { "-" } else { "" };
        format!("{sign}0.{}e{}", String::from_utf8_lossy(&digits), power + 1)
    };
    decimal
        .parse::<f64>()
        .ok()
        // Next to f64::MAX the rounding can leave the doubles: keep x.
        .filter(|r| r.is_finite())
        .and_then(json_number)
        .unwrap_or(shortest)
}

/// A number cell: `x` as [`number`] writes it (empty when not finite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Number(pub f64);

impl Serialize for Number {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&number(self.0))
    }
}

/// `x` as JSON writes it (the shortest decimal that reads back as `x`).
fn json_number(x: f64) -> Option<String> {
    serde_json::Number::from_f64(x).map(|n| n.to_string())
}

/// The significant digits of a decimal.
struct Digits {
    /// Whether it is below zero.
    negative: bool,
    /// Its digits (ASCII) from the first not 0 to the last not 0; none for 0.
    digits: Vec<u8>,
    /// The power of ten of the first digit.
    power: i32,
}

impl Digits {
    /// The digits of decimal `text` as JSON writes a number (`-0.0123`,
    /// `1.25e-7`, `1.2e+19`, `100.0`); `None` when it is not one.
    fn of(text: &str) -> Option<Digits> {
        let (negative, unsigned) = match text.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, text),
        };
        let (mantissa, exponent) = match unsigned.split_once(['e', 'E']) {
            Some((mantissa, exponent)) => (mantissa, exponent.parse::<i32>().ok()?),
            None => (unsigned, 0),
        };
        let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        let mut power = exponent.checked_add(i32::try_from(whole.len()).ok()?)? - 1;
        let mut digits = Vec::with_capacity(whole.len() + fraction.len());
        for d in whole.bytes().chain(fraction.bytes()) {
            if !d.is_ascii_digit() {
                return None;
            }
            if digits.is_empty() && d == b'0' {
                power -= 1;
            } else {
                digits.push(d);
            }
        }
        while digits.last() == Some(&b'0') {
            digits.pop();
        }
        Some(Digits {
            negative,
            digits,
            power,
        })
    }
}

/// The significant digits of decimal `text` (`1.25e-7`: 3; `100.0`: 1).
#[cfg(test)]
pub fn significant_digits(text: &str) -> usize {
    Digits::of(text).map_or(usize::MAX, |d| d.digits.len())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::range::RangeSpec;

    /// `x` as serde_json writes it.
    fn json_text(x: &f64) -> String {
        serde_json::to_string(x).expect("json")
    }

    /// A small deterministic generator (xorshift64*) for the property tests.
    struct Draws(u64);

    impl Draws {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }

        /// An integer in `lo..=hi`.
        fn between(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % (hi - lo + 1) as u64) as i64
        }
    }

    #[test]
    fn numbers_of_at_most_15_digits_are_written_as_json_writes_them() {
        for x in [
            1.0,
            -0.0,
            1e-7,
            0.1,
            1.5e-4,
            1e300,
            5e-324,
            0.123456789012345,
            123456789012345.0,
            -9.99999999999999e-100,
        ] {
            assert_eq!(number(x), json_text(&x), "{x:e}");
        }
        assert_eq!(number(1.0), "1.0");
        assert_eq!(number(1e-7), "1e-7");
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(number(x), "", "{x}");
        }
    }

    #[test]
    fn binary_noise_is_written_as_the_decimal_it_stands_for() {
        // A grid from 0.1 to 1 in 10 steps, as the spec expands it.
        let grid = RangeSpec::Even {
            from: 0.1,
            to: 1.0,
            steps: 10,
        }
        .values("/x", 0.0, 10.0, 100)
        .expect("a grid");
        let written: Vec<String> = grid.iter().map(|&x| number(x)).collect();
        assert_eq!(
            written,
            [
                "0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1.0"
            ]
        );
        // The grid holds noise: this test would pass without it otherwise.
        assert!(grid.iter().map(json_text).any(|t| t.len() > 5), "{grid:?}");
        for (x, text) in [
            (0.30000000000000004, "0.3"),
            (0.3999999999999999, "0.4"),
            (0.5000000000000001, "0.5"),
            (1.9999999999999998, "2.0"),
            (-0.7999999999999999, "-0.8"),
            (1.0000000000000002e-7, "1e-7"),
            // Computed values keep 15 digits.
            (std::f64::consts::PI, "3.14159265358979"),
            (0.123_456_789_012_345_68, "0.123456789012346"),
            (12345678901234567890.0, "1.23456789012346e+19"),
            (2.0f64.sqrt(), "1.4142135623731"),
            (2.0f64.sqrt() * 1e-200, "1.41421356237309e-200"),
            // Rounding f64::MAX to 15 digits leaves the doubles: it is kept.
            (f64::MAX, "1.7976931348623157e+308"),
        ] {
            assert_eq!(number(x), text, "{x:e}");
        }
    }

    #[test]
    fn any_decimal_of_15_digits_reads_back_as_written_within_an_ulp() {
        let mut draws = Draws(0x9E37_79B9_7F4A_7C15);
        for _ in 0..20_000 {
            let digits = draws.between(1, 15) as i32;
            let mantissa =
                draws.between(10i64.pow(digits as u32 - 1), 10i64.pow(digits as u32) - 1);
            let exponent = draws.between(-300, 290);
            let decimal = format!("{mantissa}e{exponent}");
            let nearest: f64 = decimal.parse().expect("a number");
            let expected = json_text(&nearest);
            for x in [nearest.next_down(), nearest, nearest.next_up()] {
                assert_eq!(number(x), expected, "{decimal} as {x:e}");
            }
        }
    }

    /// `x` rounded to 15 significant digits from its exact binary value,
    /// written as JSON writes the double nearest that.
    fn rounded_exactly(x: f64) -> String {
        let decimal: f64 = format!("{x:.14e}").parse().expect("a number");
        json_text(&decimal)
    }

    #[test]
    fn a_written_number_is_its_double_rounded_to_15_digits_and_is_written_again_alike() {
        let mut draws = Draws(0xD1B5_4A32_D192_ED03);
        let mut ties = 0;
        for k in 0..40_000 {
            // Any double; every other one of few digits, plus noise.
            let x = if k % 2 == 0 {
                f64::from_bits(draws.next())
            } else {
                let digits = draws.between(1, 16) as u32;
                let mantissa = draws.between(1, 10i64.pow(digits) - 1);
                let x: f64 = format!("{mantissa}e{}", draws.between(-20, 20))
                    .parse()
                    .expect("a number");
                let ulps = draws.between(0, 4) as u64;
                f64::from_bits(x.to_bits().wrapping_add(ulps).wrapping_sub(2))
            };
            if !x.is_finite() || x.abs() > 1e308 || x.abs() < 1e-300 {
                continue;
            }
            let text = number(x);
            assert_eq!(text, rounded_exactly(x), "{x:e}");
            let shortest = Digits::of(&json_text(&x)).expect("digits");
            ties += usize::from(shortest.digits.len() == 16 && shortest.digits.ends_with(b"5"));
            assert!(significant_digits(&text) <= 15, "{x:e}: {text}");
            let back: f64 = text.parse().expect("a number");
            // Half a unit of the 15th digit, and half an ulp.
            assert!((back - x).abs() <= 5.2e-15 * x.abs(), "{x:e}: {text}");
            assert_eq!(number(back), text, "{x:e}");
        }
        // The case whose digits are read exactly was met.
        assert!(ties > 10, "{ties}");
    }
}
