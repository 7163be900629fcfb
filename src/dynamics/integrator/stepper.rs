//! Step-size control shared by the pairs: one accepted step per call, never past
//! a given end time, no heap allocation.

use super::{DenseStep, Method, Rhs, State, dop853, dopri5};

/// Counters for the numerics report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepperStats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Sum of the local error estimates of θ over accepted steps (radians).
    pub local_error_sum: f64,
}

impl StepperStats {
    /// Adds another run's counters.
    pub fn absorb(&mut self, other: &StepperStats) {
        self.accepted += other.accepted;
        self.rejected += other.rejected;
        self.rhs_evals += other.rhs_evals;
        self.local_error_sum += other.local_error_sum;
    }
}

/// Why the stepper could not go on.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum StepError {
    /// The step size fell below what the time resolution allows.
    #[error("step size underflow at t = {t}")]
    StepUnderflow {
        /// Time at which it happened.
        t: f64,
    },
    /// The right-hand side produced a non-finite value.
    #[error("non-finite state at t = {t}")]
    NonFinite {
        /// Time at which it happened.
        t: f64,
    },
}

/// An adaptive integrator positioned at `(t, y)`.
///
/// Created afresh at every event (impact, pulse end, rocking start) so that no
/// step straddles a discontinuity of the right-hand side.
#[derive(Clone, Debug)]
pub struct Stepper {
    method: Method,
    rtol: f64,
    atol: f64,
    /// Current time.
    pub t: f64,
    /// Current state.
    pub y: State,
    f: State,
    h: f64,
    /// Largest step allowed (keeps the dense output meaningful for sampling).
    h_max: f64,
    /// Counters since creation.
    pub stats: StepperStats,
    last_rejected: bool,
}

const SAFETY: f64 = 0.9;
const FAC_MIN: f64 = 0.2;

impl Stepper {
    /// Starts at `(t, y)`. `h_hint` is a step that worked nearby (0 for none).
    #[allow(clippy::too_many_arguments)]
    pub fn new<R: Rhs>(
        method: Method,
        rtol: f64,
        atol: f64,
        rhs: &R,
        t: f64,
        y: State,
        h_max: f64,
        h_hint: f64,
    ) -> Self {
        let f = rhs.eval(t, y);
        let mut s = Stepper {
            method,
            rtol,
            atol,
            t,
            y,
            f,
            h: 0.0,
            h_max,
            stats: StepperStats {
                rhs_evals: 1,
                ..Default::default()
            },
            last_rejected: false,
        };
        s.h = if h_hint > 0.0 {
            h_hint.min(h_max)
        } else {
            s.initial_step(rhs)
        };
        s
    }

    fn order(&self) -> f64 {
        match self.method {
            Method::Dopri5 => dopri5::ERROR_ORDER,
            Method::Dop853 => dop853::ERROR_ORDER,
        }
    }

    /// Hairer's starting-step heuristic (HINIT).
    fn initial_step<R: Rhs>(&mut self, rhs: &R) -> f64 {
        let sc = [
            self.atol + self.rtol * self.y[0].abs(),
            self.atol + self.rtol * self.y[1].abs(),
        ];
        let norm = |v: State| ((v[0] / sc[0]).powi(2) + (v[1] / sc[1]).powi(2)) / 2.0;
        let d0 = norm(self.y).sqrt();
        let d1 = norm(self.f).sqrt();
        let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        h0 = h0.min(self.h_max);
        let y1 = [self.y[0] + h0 * self.f[0], self.y[1] + h0 * self.f[1]];
        let f1 = rhs.eval(self.t + h0, y1);
        self.stats.rhs_evals += 1;
        let d2 = norm([f1[0] - self.f[0], f1[1] - self.f[1]]).sqrt() / h0;
        let dmax = d1.max(d2);
        let h1 = if dmax <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dmax).powf(1.0 / (self.order() + 1.0))
        };
        (100.0 * h0).min(h1).min(self.h_max)
    }

    /// The step size the controller would try next.
    pub fn next_step_size(&self) -> f64 {
        self.h
    }

    /// Takes one accepted step, ending exactly at `t_end` if it would reach it.
    pub fn step<R: Rhs>(&mut self, rhs: &R, t_end: f64) -> Result<DenseStep, StepError> {
        let exponent = 1.0 / (self.order() + 1.0);
        loop {
            let remaining = t_end - self.t;
            let mut h = self.h.min(self.h_max);
            let mut lands = false;
            if h >= remaining * (1.0 - 1e-12) {
                h = remaining;
                lands = true;
            }
            let h_min = 16.0 * f64::EPSILON * self.t.abs().max(1e-300);
            if h <= h_min && !lands {
                return Err(StepError::StepUnderflow { t: self.t });
            }
            let (trial, dense) = match self.method {
                Method::Dopri5 => {
                    let (tr, k) =
                        dopri5::trial(rhs, self.t, self.y, self.f, h, self.atol, self.rtol);
                    (tr, Dense::D5(k))
                }
                Method::Dop853 => {
                    let (tr, k) =
                        dop853::trial(rhs, self.t, self.y, self.f, h, self.atol, self.rtol);
                    (tr, Dense::D8(k))
                }
            };
            self.stats.rhs_evals += u64::from(trial.nfev);
            if !trial.err.is_finite() || !trial.y1[0].is_finite() || !trial.y1[1].is_finite() {
                self.stats.rejected += 1;
                self.h = h * FAC_MIN;
                self.last_rejected = true;
                if self.h <= h_min {
                    return Err(StepError::NonFinite { t: self.t });
                }
                continue;
            }
            if trial.err <= 1.0 {
                let fac_max = if self.last_rejected {
                    1.0
                } else {
                    match self.method {
                        Method::Dopri5 => 10.0,
                        Method::Dop853 => 6.0,
                    }
                };
                let fac = if trial.err == 0.0 {
                    fac_max
                } else {
                    (SAFETY * trial.err.powf(-exponent)).clamp(FAC_MIN, fac_max)
                };
                let t1 = if lands { t_end } else { self.t + h };
                let step = match dense {
                    Dense::D5(k) => dopri5::dense(self.t, h, self.y, trial.y1, &k),
                    Dense::D8(k) => {
                        let (step, extra) = dop853::dense(rhs, self.t, h, self.y, trial.y1, &k);
                        self.stats.rhs_evals += u64::from(extra);
                        step
                    }
                };
                self.stats.accepted += 1;
                self.stats.local_error_sum += trial.err_theta;
                self.t = t1;
                self.y = trial.y1;
                self.f = trial.f1;
                // Do not let a short landing step shrink the next one.
                self.h = if lands { self.h.max(h * fac) } else { h * fac };
                self.last_rejected = false;
                return Ok(step);
            }
            self.stats.rejected += 1;
            self.last_rejected = true;
            self.h = h * (SAFETY * trial.err.powf(-exponent)).clamp(FAC_MIN, 1.0);
        }
    }
}

/// One step of `method` from `(t, y)` of length `h`, without error control
/// (used to place an event found on the dense output). Returns the state and
/// the right-hand-side evaluations spent.
pub fn single_step<R: Rhs>(method: Method, rhs: &R, t: f64, y: State, h: f64) -> (State, u32) {
    let f0 = rhs.eval(t, y);
    let (trial, nfev) = match method {
        Method::Dopri5 => {
            let (tr, _) = dopri5::trial(rhs, t, y, f0, h, 1.0, 1.0);
            (tr, tr.nfev)
        }
        Method::Dop853 => {
            let (tr, _) = dop853::trial(rhs, t, y, f0, h, 1.0, 1.0);
            (tr, tr.nfev)
        }
    };
    (trial.y1, nfev + 1)
}

enum Dense {
    D5([State; 7]),
    D8(dop853::Stages),
}
