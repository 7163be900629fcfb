//! Progress and cancellation shared between a running computation and its owner.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// A progress counter and a cancellation flag.
///
/// Workers check [`Control::canceled`] before every simulation (each takes
/// microseconds to milliseconds), so a cancellation takes effect within
/// milliseconds.
#[derive(Debug, Default)]
pub struct Control {
    canceled: AtomicBool,
    done: AtomicU64,
    total: AtomicU64,
}

/// The computation was canceled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("canceled")]
pub struct Canceled;

impl Control {
    /// A fresh control.
    pub fn new() -> Self {
        Control::default()
    }

    /// Asks the computation to stop.
    pub fn cancel(&self) {
        self.canceled.store(true, Ordering::Relaxed);
    }

    /// Whether a stop was asked for.
    pub fn canceled(&self) -> bool {
        self.canceled.load(Ordering::Relaxed)
    }

    /// `Err(Canceled)` once a stop was asked for.
    pub fn check(&self) -> Result<(), Canceled> {
        if self.canceled() {
            Err(Canceled)
        } else {
            Ok(())
        }
    }

    /// Adds to the amount of work expected.
    pub fn add_total(&self, n: u64) {
        self.total.fetch_add(n, Ordering::Relaxed);
    }

    /// Records finished work.
    pub fn add_done(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    /// Work finished so far (simulations).
    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }

    /// Fraction done, 0..=1.
    pub fn progress(&self) -> f64 {
        let total = self.total.load(Ordering::Relaxed);
        if total == 0 {
            return 0.0;
        }
        (self.done.load(Ordering::Relaxed) as f64 / total as f64).min(1.0)
    }
}
