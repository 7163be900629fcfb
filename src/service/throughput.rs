//! The measured computation rate of this instance, for the estimates a
//! submission answers with and the poll interval it suggests.

use std::sync::atomic::{AtomicU64, Ordering};

/// Wall seconds per simulation before anything was measured: a nonlinear
/// dop853 simulation with its events takes about 10 µs on one core of the
/// reference machine; a job's simulations share the pool.
const DEFAULT_SECONDS_PER_SIMULATION: f64 = 2e-5;

/// Tasks with fewer simulations say more about overheads than about the rate.
const MIN_SIMULATIONS: u64 = 32;

/// Weight of the newest measurement in the moving average.
const WEIGHT: f64 = 0.3;

/// Wall seconds per simulation on this instance, an exponential moving
/// average over finished tasks.
#[derive(Debug)]
pub struct Throughput {
    seconds_per_simulation: AtomicU64,
}

impl Default for Throughput {
    fn default() -> Self {
        Throughput {
            seconds_per_simulation: AtomicU64::new(DEFAULT_SECONDS_PER_SIMULATION.to_bits()),
        }
    }
}

impl Throughput {
    /// Records a task of `simulations` that took `seconds` of wall time.
    pub fn record(&self, simulations: u64, seconds: f64) {
        if simulations < MIN_SIMULATIONS || !(seconds.is_finite() && seconds > 0.0) {
            return;
        }
        let measured = seconds / simulations as f64;
        let _ = self.seconds_per_simulation.fetch_update(
            Ordering::Relaxed,
            Ordering::Relaxed,
            |bits| {
                let old = f64::from_bits(bits);
                Some((old + WEIGHT * (measured - old)).to_bits())
            },
        );
    }

    /// Wall seconds per simulation.
    pub fn seconds_per_simulation(&self) -> f64 {
        f64::from_bits(self.seconds_per_simulation.load(Ordering::Relaxed))
    }

    /// Expected wall seconds of `simulations`.
    pub fn seconds(&self, simulations: f64) -> f64 {
        simulations * self.seconds_per_simulation()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_moves_toward_what_tasks_measure_and_ignores_tiny_ones() {
        let t = Throughput::default();
        t.record(4, 100.0);
        assert_eq!(t.seconds_per_simulation(), DEFAULT_SECONDS_PER_SIMULATION);
        for _ in 0..60 {
            t.record(1000, 0.005);
        }
        assert!((t.seconds_per_simulation() - 5e-6).abs() < 1e-9);
        assert!((t.seconds(2e5) - 1.0).abs() < 1e-3);
    }
}
