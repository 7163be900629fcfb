//! The measured computation rate of this instance, per job kind, for the
//! estimates a submission answers with and the poll interval it suggests.
//!
//! A job's size carries the CPU seconds its simulations take on the
//! reference machine ([`crate::jobs::cost`]); its expected wall time here is
//! that, spread over the compute threads it can use, times this instance's
//! rate for its kind: a moving average of what finished tasks measured
//! against what their size predicted (1 before anything was measured; the
//! first measurement of a kind replaces it).

use std::collections::HashMap;
use std::sync::Mutex;

use crate::jobs::kind::Size;

/// Tasks predicted shorter than this say more about overheads than about
/// the rate, s.
const MIN_PREDICTED_S: f64 = 0.005;

/// Weight of the newest measurement in the moving average.
const WEIGHT: f64 = 0.3;

/// Rates never leave this range: one wild measurement (a task stalled by a
/// paused process) must not make every estimate absurd.
const RATE_RANGE: (f64, f64) = (0.05, 50.0);

/// This instance's rate per kind.
#[derive(Debug)]
pub struct Throughput {
    threads: usize,
    rates: Mutex<HashMap<String, f64>>,
}

impl Throughput {
    /// Rates of an instance of `threads` compute threads.
    pub fn new(threads: usize) -> Self {
        Throughput {
            threads: threads.max(1),
            rates: Mutex::new(HashMap::new()),
        }
    }

    /// Records a task of `kind` whose size was `size` and that took
    /// `seconds` of wall time.
    pub fn record(&self, kind: &str, size: &Size, seconds: f64) {
        let predicted = size.wall_s(self.threads, 1.0);
        if predicted < MIN_PREDICTED_S || !(seconds.is_finite() && seconds > 0.0) {
            return;
        }
        let measured = (seconds / predicted).clamp(RATE_RANGE.0, RATE_RANGE.1);
        if let Ok(mut rates) = self.rates.lock() {
            // The first measurement of a kind replaces the model's guess.
            rates
                .entry(kind.to_string())
                .and_modify(|rate| *rate += WEIGHT * (measured - *rate))
                .or_insert(measured);
        }
    }

    /// The rate of `kind`: measured wall seconds per predicted second.
    pub fn rate(&self, kind: &str) -> f64 {
        self.rates
            .lock()
            .ok()
            .and_then(|r| r.get(kind).copied())
            .unwrap_or(1.0)
    }

    /// Expected wall seconds of a job of `kind` and `size`.
    pub fn seconds(&self, kind: &str, size: &Size) -> f64 {
        size.wall_s(self.threads, self.rate(kind))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn size(cpu_s: f64) -> Size {
        Size {
            cpu_s,
            lanes: 100.0,
            work: 1000.0,
            ..Size::one(0.0)
        }
    }

    #[test]
    fn each_kind_moves_toward_what_its_tasks_measure_and_tiny_tasks_are_ignored() {
        let t = Throughput::new(2);
        // Predicted 0.5 s on two threads.
        assert!((t.seconds("spectrum", &size(1.0)) - 0.5).abs() < 1e-12);
        t.record("spectrum", &size(0.001), 100.0);
        assert_eq!(t.rate("spectrum"), 1.0);
        t.record("spectrum", &size(1.0), 0.25);
        assert!((t.rate("spectrum") - 0.5).abs() < 1e-12);
        for _ in 0..60 {
            t.record("spectrum", &size(1.0), 1.5);
        }
        assert!((t.rate("spectrum") - 3.0).abs() < 1e-6);
        assert!((t.seconds("spectrum", &size(1.0)) - 1.5).abs() < 1e-5);
        // Another kind keeps its own rate.
        assert_eq!(t.rate("fragility"), 1.0);
        // One simulation runs on one thread.
        assert!((t.seconds("time_history", &Size::one(0.2)) - 0.2).abs() < 1e-12);
        // A stalled task moves the rate, within bounds.
        t.record("fragility", &size(1.0), 1e6);
        assert!(t.rate("fragility") <= RATE_RANGE.1);
    }
}
