//! Adaptive explicit Runge–Kutta pairs with error control and dense output,
//! specialised to the two-component rocking state `[θ, θ̇]`.
//!
//! The simulation driver ([`crate::dynamics::simulate()`]) advances one accepted
//! step at a time and inspects each step's [`DenseStep`] for events, so no event
//! is ever judged only from the values at step ends.
//!
//! ## Reference
//! Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*,
//! §II.4–II.6 (step-size control, dense output; codes DOPRI5 and DOP853).

mod dop853;
mod dopri5;
mod stepper;

pub use stepper::{StepError, Stepper, StepperStats, single_step};

/// A two-component state `[θ, θ̇]`.
pub type State = [f64; 2];

/// The right-hand side `y' = f(t, y)` of a smooth piece of the motion.
pub trait Rhs {
    /// Evaluates `f(t, y)`.
    fn eval(&self, t: f64, y: State) -> State;
}

impl<F: Fn(f64, State) -> State> Rhs for F {
    fn eval(&self, t: f64, y: State) -> State {
        self(t, y)
    }
}

/// The explicit Runge–Kutta pairs on offer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Dormand–Prince 5(4), 7 stages (FSAL), quartic dense output.
    Dopri5,
    /// Dormand–Prince 8(5,3), 12 stages (FSAL) + 3 for the degree-7 dense output.
    Dop853,
}

impl Method {
    /// The name used in job specs and reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
        }
    }
}

/// Highest polynomial degree of any dense output (DOP853: 7).
pub const MAX_DEGREE: usize = 7;

/// One accepted step with its continuous extension.
///
/// The dense output is stored as monomial coefficients in the normalised step
/// variable `σ = (t − t0)/h ∈ [0, 1]`, one polynomial per state component, so that
/// event functions can be examined as polynomials (see [`crate::dynamics::events`]).
#[derive(Clone, Copy, Debug)]
pub struct DenseStep {
    /// Start of the step.
    pub t0: f64,
    /// Step length (positive).
    pub h: f64,
    /// State at the start of the step.
    pub y0: State,
    /// State at the end of the step.
    pub y1: State,
    /// `coeffs[c][k]` multiplies `σ^k` in component `c`; degree ≤ [`MAX_DEGREE`].
    pub coeffs: [[f64; MAX_DEGREE + 1]; 2],
    /// Number of coefficients in use (degree + 1).
    pub len: usize,
}

impl DenseStep {
    /// State at normalised position `σ ∈ [0, 1]`.
    pub fn at_sigma(&self, sigma: f64) -> State {
        let mut out = [0.0; 2];
        for (c, poly) in self.coeffs.iter().enumerate() {
            let mut acc = 0.0;
            for k in (0..self.len).rev() {
                acc = acc * sigma + poly[k];
            }
            out[c] = acc;
        }
        out
    }

    /// State at time `t` inside the step.
    pub fn at(&self, t: f64) -> State {
        self.at_sigma(((t - self.t0) / self.h).clamp(0.0, 1.0))
    }

    /// End time of the step.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }
}

/// Result of one attempted step of a pair.
#[derive(Clone, Copy, Debug)]
pub struct TrialStep {
    /// Proposed new state.
    pub y1: State,
    /// `f(t0 + h, y1)` (first stage of the next step, FSAL).
    pub f1: State,
    /// Scaled error norm (accept when ≤ 1).
    pub err: f64,
    /// Unscaled local error estimate of θ (radians), for the numerics report.
    pub err_theta: f64,
    /// Right-hand-side evaluations spent.
    pub nfev: u32,
}

/// Per-component error scale `atol + rtol · max(|y0|, |y1|)`.
#[inline]
pub(crate) fn scale(atol: f64, rtol: f64, y0: State, y1: State) -> State {
    [
        atol + rtol * y0[0].abs().max(y1[0].abs()),
        atol + rtol * y0[1].abs().max(y1[1].abs()),
    ]
}
