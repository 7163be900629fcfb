//! A time window of a time-history figure: the span `start,end` (seconds)
//! the figure draws instead of the whole history.

use std::fmt;

/// The largest |t| a window may name, s (about four months).
pub const MAX_SECONDS: f64 = 1e7;
/// The shortest span a window may draw, s.
pub const MIN_SPAN: f64 = 1e-6;

/// A span of time to draw, start < end, both finite (seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    start: f64,
    end: f64,
}

impl Window {
    /// The window from `start` to `end` seconds.
    pub fn new(start: f64, end: f64) -> Result<Window, String> {
        if !start.is_finite() || !end.is_finite() {
            return Err(format!(
                "window {start},{end}: both ends must be finite numbers of seconds"
            ));
        }
        if start >= end {
            return Err(format!(
                "window {start},{end}: the start must come before the end"
            ));
        }
        // An axis over an infinite or vanishing span cannot be ticked.
        if start.abs() > MAX_SECONDS || end.abs() > MAX_SECONDS {
            return Err(format!(
                "window {start:e},{end:e}: both ends must lie within ±{MAX_SECONDS:e} s"
            ));
        }
        if end - start < MIN_SPAN {
            return Err(format!(
                "window {start},{end}: the span must be at least {MIN_SPAN:e} s"
            ));
        }
        // -0 and 0 are one window (and one entity tag).
        Ok(Window {
            start: start + 0.0,
            end: end + 0.0,
        })
    }

    /// A window written `start,end` in seconds, e.g. `0,1.2`.
    pub fn parse(text: &str) -> Result<Window, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        let [start, end] = parts.as_slice() else {
            return Err(format!(
                "window {text:?}: expected two numbers of seconds, start,end (e.g. 0,1.2)"
            ));
        };
        let number = |s: &str| {
            s.parse::<f64>()
                .map_err(|_| format!("window {text:?}: {s:?} is not a number of seconds"))
        };
        Window::new(number(start)?, number(end)?)
    }

    /// Its start, s.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// Its end, s.
    pub fn end(&self) -> f64 {
        self.end
    }
}

impl Window {
    /// `start_end`, each number in its shortest exact form (`0e0_1.2e0`):
    /// one text per window, short whatever the numbers, and free of the
    /// commas that separate entity tags in `If-None-Match`.
    pub fn tag(&self) -> String {
        format!("{:e}_{:e}", self.start, self.end)
    }
}

/// `start,end` in seconds, as a query writes it.
impl fmt::Display for Window {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.start, self.end)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_finite_numbers_in_order_make_a_window() {
        let w = Window::parse("0, 1.2").expect("window");
        assert_eq!((w.start(), w.end()), (0.0, 1.2));
        assert_eq!(w.to_string(), "0,1.2");
        assert_eq!(w.tag(), "0e0_1.2e0");
        assert_eq!(Window::parse("-0,1.2000").expect("window").tag(), w.tag());
        assert_eq!(
            Window::new(-1e7, 1e-300).expect("window").tag(),
            "-1e7_1e-300"
        );
    }

    #[test]
    fn anything_else_is_refused_with_the_reason() {
        for (bad, why) in [
            ("1.2,0", "before the end"),
            ("1,1", "before the end"),
            ("0", "two numbers"),
            ("0,1,2", "two numbers"),
            ("0,x", "\"x\" is not a number"),
            ("0,inf", "finite"),
            ("NaN,1", "finite"),
            ("", "two numbers"),
            // Finite, but an axis could not be ticked over them.
            ("-1e308,1e308", "within"),
            ("0,2e7", "within"),
            ("1,1.0000000001", "at least"),
        ] {
            let e = Window::parse(bad).expect_err(bad);
            assert!(e.contains(why), "{bad}: {e}");
        }
    }
}
