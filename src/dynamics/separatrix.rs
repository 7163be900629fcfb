//! Exact overturning decision once no forcing remains.
//!
//! In free vibration the energy is conserved between impacts and each impact
//! multiplies θ̇ by η (eqs. 13–15), so whether the block passes the barrier at
//! |θ| = α — and how many impacts it makes first — follows from the state alone:
//! the sign of the growing exponential's coefficient for the linear formulation
//! (eq. 33) and the energy against the barrier for the nonlinear one. No
//! integration over "long enough" times is involved.

use super::block::Block;
use super::equations::Formulation;
use std::f64::consts::FRAC_PI_2;

/// What free vibration will do from a given state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FreeOutcome {
    /// The block overturns after this many further impacts (0 or 1).
    Overturns {
        /// Impacts still to come before overturning.
        impacts: u32,
    },
    /// The block stays up (and comes to rest unless η = 1).
    Survives,
}

/// Barrier height in the units of [`Formulation::barrier_excess`]: the excess
/// of a block at θ = 0 at rest.
fn barrier_height(formulation: Formulation, block: &Block) -> f64 {
    let a = block.slenderness();
    match formulation {
        Formulation::Linear => 0.5 * a * a,
        Formulation::Nonlinear => 2.0 * (0.5 * a).sin().powi(2),
    }
}

/// Decides overturning in free vibration from `(θ, θ̇)` on `side` (±1, the sign
/// of θ; needed when θ = 0 just after an impact).
pub fn decide(
    formulation: Formulation,
    block: &Block,
    theta: f64,
    theta_dot: f64,
    side: f64,
) -> FreeOutcome {
    let gamma = side * theta;
    let gamma_dot = side * theta_dot;
    if gamma >= FRAC_PI_2 {
        return FreeOutcome::Overturns { impacts: 0 };
    }
    let excess = formulation.barrier_excess(block, theta, theta_dot);
    let outward = gamma_dot > 0.0;
    let beyond = gamma > block.slenderness();
    let reaches_zero = if beyond {
        // Past the barrier: only a sufficiently energetic inward motion comes back.
        !outward && excess > 0.0
    } else {
        // Inside the well: it returns unless it climbs over the barrier outward.
        !(outward && excess > 0.0)
    };
    if !reaches_zero {
        return FreeOutcome::Overturns { impacts: 0 };
    }
    if gamma == 0.0 && gamma_dot == 0.0 {
        return FreeOutcome::Survives;
    }
    // Energy at θ = 0 is excess + B; the impact scales the kinetic part by η².
    let b = barrier_height(formulation, block);
    let eta2 = block.restitution() * block.restitution();
    let after = eta2 * (excess + b) - b;
    if after > 0.0 {
        FreeOutcome::Overturns { impacts: 1 }
    } else {
        FreeOutcome::Survives
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block() -> Block {
        Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid")
    }

    #[test]
    fn linear_decision_is_the_sign_of_the_growing_exponential() {
        let b = block();
        let p = 2.14;
        // Eq. 33: θ̇ + p(θ − α) > 0 overturns for θ > 0.
        for &(theta, vel) in &[
            (0.1, 0.33),
            (0.1, 0.31),
            (0.3, -0.05),
            (0.3, -0.2),
            (0.05, -0.4),
        ] {
            let growing = vel + p * (theta - 0.25);
            let decided = decide(Formulation::Linear, &b, theta, vel, 1.0);
            if growing > 0.0 {
                assert_eq!(
                    decided,
                    FreeOutcome::Overturns { impacts: 0 },
                    "{theta} {vel}"
                );
            } else {
                assert_ne!(
                    decided,
                    FreeOutcome::Overturns { impacts: 0 },
                    "{theta} {vel}"
                );
            }
        }
    }

    #[test]
    fn after_an_impact_the_restitution_decides() {
        let b = block();
        let p = 2.14;
        // Leaving θ = 0 towards the other side: overturns after one impact iff
        // η |θ̇| > p α (linear, eq. 41).
        let v = -0.25 * p / 0.9 * 1.0001;
        assert_eq!(
            decide(Formulation::Linear, &b, -0.0, v, 1.0),
            FreeOutcome::Overturns { impacts: 1 }
        );
        let v = -0.25 * p / 0.9 * 0.9999;
        assert_eq!(
            decide(Formulation::Linear, &b, -0.0, v, 1.0),
            FreeOutcome::Survives
        );
    }

    #[test]
    fn at_rest_survives() {
        let b = block();
        for f in [Formulation::Linear, Formulation::Nonlinear] {
            assert_eq!(decide(f, &b, 0.0, 0.0, 1.0), FreeOutcome::Survives);
        }
    }
}
