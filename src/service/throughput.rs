//! The measured computation rate of this instance, per job kind, for the
//! estimates a submission answers with and the poll interval it suggests.
//!
//! A job's size carries the CPU seconds its simulations take on the
//! reference machine ([`crate::jobs::cost`]); its expected wall time here is
//! that, spread over the compute threads it can use, times this instance's
//! rate for its kind: the wall seconds its finished tasks took over the
//! seconds their sizes predicted, summed over about the last
//! [`MEMORY_S`] predicted seconds (so a long task counts for more than a
//! short one, whose cost the model knows less well), starting from the
//! model's own guess (a rate of 1) worth [`PRIOR_S`].

use std::collections::HashMap;
use std::sync::Mutex;

use crate::jobs::kind::Size;

/// Predicted seconds of work the rate remembers.
const MEMORY_S: f64 = 60.0;

/// Predicted seconds the model's guess counts for before anything is measured.
const PRIOR_S: f64 = 1.0;

/// Tasks predicted shorter than this say more about overheads than about
/// the rate, s.
const MIN_PREDICTED_S: f64 = 0.005;

/// Rates never leave this range: one wild measurement (a task stalled by a
/// paused process) must not make every estimate absurd.
const RATE_RANGE: (f64, f64) = (0.05, 50.0);

/// Measured and predicted seconds of one kind, both decayed alike.
#[derive(Clone, Copy, Debug)]
struct Sums {
    measured: f64,
    predicted: f64,
}

impl Default for Sums {
    fn default() -> Self {
        Sums {
            measured: PRIOR_S,
            predicted: PRIOR_S,
        }
    }
}

/// This instance's rate per kind.
#[derive(Debug)]
pub struct Throughput {
    threads: usize,
    sums: Mutex<HashMap<String, Sums>>,
}

impl Throughput {
    /// Rates of an instance of `threads` compute threads.
    pub fn new(threads: usize) -> Self {
        Throughput {
            threads: threads.max(1),
            sums: Mutex::new(HashMap::new()),
        }
    }

    /// Records a task of `kind` whose size was `size` and that took
    /// `seconds` of wall time while `busy` tasks (itself included, on
    /// average) computed on this instance: it had the threads to itself, or
    /// its share of them — a task of many lanes beside another runs on about
    /// half the threads, as a job's tasks do beside each other.
    pub fn record(&self, kind: &str, size: &Size, seconds: f64, busy: f64) {
        let share = (self.threads as f64 / busy.max(1.0)).max(1.0);
        let predicted = size.cpu_s / size.lanes.clamp(1.0, share);
        if predicted < MIN_PREDICTED_S || !(seconds.is_finite() && seconds > 0.0) {
            return;
        }
        let seconds = seconds.clamp(predicted * RATE_RANGE.0, predicted * RATE_RANGE.1);
        if let Ok(mut sums) = self.sums.lock() {
            let s = sums.entry(kind.to_string()).or_default();
            let keep = (-predicted / MEMORY_S).exp();
            s.measured = keep * s.measured + seconds;
            s.predicted = keep * s.predicted + predicted;
        }
    }

    /// The rate of `kind`: measured wall seconds per predicted second.
    pub fn rate(&self, kind: &str) -> f64 {
        let s = self
            .sums
            .lock()
            .ok()
            .and_then(|r| r.get(kind).copied())
            .unwrap_or_default();
        (s.measured / s.predicted).clamp(RATE_RANGE.0, RATE_RANGE.1)
    }

    /// Expected wall seconds of a job whose `size` was measured on a sample
    /// of it on this instance: the rate corrects a model, not a measurement.
    pub fn seconds_measured(&self, size: &Size) -> f64 {
        size.wall_s(self.threads, 1.0)
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
    fn each_kind_moves_toward_what_its_work_measures_and_tiny_tasks_are_ignored() {
        let t = Throughput::new(2);
        // Predicted 0.5 s on two threads.
        assert!((t.seconds("spectrum", &size(1.0)) - 0.5).abs() < 1e-12);
        t.record("spectrum", &size(0.001), 100.0, 1.0);
        assert_eq!(t.rate("spectrum"), 1.0);
        // One short task that ran fast moves the rate a little, weighted by
        // its predicted seconds against the prior's.
        t.record("spectrum", &size(0.2), 0.01, 1.0);
        let r = t.rate("spectrum");
        assert!(r < 1.0 && r > 0.8, "{r}");
        // A long run of tasks 3 times slower than predicted: the rate is 3.
        for _ in 0..400 {
            t.record("spectrum", &size(1.0), 1.5, 1.0);
        }
        assert!(
            (t.rate("spectrum") - 3.0).abs() < 1e-2,
            "{}",
            t.rate("spectrum")
        );
        assert!((t.seconds("spectrum", &size(1.0)) - 1.5).abs() < 1e-2);
        // Tasks of uneven cost: the rate is their total over their
        // predicted total, not the average of their ratios.
        let u = Throughput::new(2);
        for _ in 0..100 {
            u.record("record_spectrum", &size(0.02), 0.2, 1.0);
            u.record("record_spectrum", &size(1.0), 0.05, 1.0);
        }
        let r = u.rate("record_spectrum");
        assert!((r - 0.25 / 0.51).abs() < 0.05, "{r}");
        // Another kind keeps its own rate.
        assert_eq!(t.rate("fragility"), 1.0);
        // One simulation runs on one thread.
        assert!((t.seconds("time_history", &Size::one(0.2)) - 0.2).abs() < 1e-12);
        // A stalled task moves the rate, within bounds.
        t.record("fragility", &size(1.0), 1e6, 1.0);
        assert!(t.rate("fragility") <= RATE_RANGE.1);
    }

    #[test]
    fn a_task_beside_others_is_predicted_on_its_share_of_the_threads() {
        // Two workers, two tasks of many lanes at once: each on one thread.
        let t = Throughput::new(2);
        for _ in 0..400 {
            t.record("spectrum", &size(1.0), 1.0, 2.0);
        }
        assert!(
            (t.rate("spectrum") - 1.0).abs() < 1e-2,
            "{}",
            t.rate("spectrum")
        );
        // The same task alone on both threads, as fast as predicted.
        let u = Throughput::new(2);
        for _ in 0..400 {
            u.record("spectrum", &size(1.0), 0.5, 1.0);
        }
        assert!(
            (u.rate("spectrum") - 1.0).abs() < 1e-2,
            "{}",
            u.rate("spectrum")
        );
        // A task of one lane runs on one thread however many compute.
        let v = Throughput::new(2);
        for _ in 0..400 {
            v.record("record_spectrum", &Size::one(1.0), 1.0, 1.0);
        }
        assert!((v.rate("record_spectrum") - 1.0).abs() < 1e-2);
    }
}
