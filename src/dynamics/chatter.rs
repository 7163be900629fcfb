//! Chattering: impacts piling up in finite time (the Zeno case) summed in
//! closed form.
//!
//! Right after an impact at θ = 0 with a small velocity v, the block flies on
//! the side s = sgn v under an almost constant pull back to θ = 0, A_s (the
//! angular acceleration at θ = 0, eq. 12 or 50), returns after 2|v|/A_s with
//! velocity −v, and the impact multiplies it by η (eqs. 13–15). The flights
//! alternate sides, so the block settles after
//!
//! ```text
//! T_Z = 2|v| (1/A_s + η/A_{−s}) / (1 − η²)
//! ```
//!
//! having made k = ⌈ln(v_rest/|v|)/ln η⌉ more impacts before its velocity falls
//! below the rest threshold — exactly the count an impact-by-impact simulation
//! reaches. The sum is used only where it is accurate: both sides pull back
//! (|ü_g| below the rocking threshold) until the block has settled, the
//! excursions v²/(2A) are below 1e-6 α, and the velocity is below 1e-4 p α.
//! Under a vertical ground acceleration the pulls are those of gravity
//! g + ü_v, and the ground must keep the block on it (g + ü_v > 0) meanwhile.

use super::block::Block;
use super::equations::Formulation;
use super::forcing::Forcing;

/// Velocity (relative to p α) below which chattering may be summed.
pub const CHATTER_VELOCITY: f64 = 1e-4;
/// Largest flight excursion (relative to α) for which chattering may be summed.
pub const CHATTER_EXCURSION: f64 = 1e-6;

/// The summed end of a chattering sequence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settling {
    /// Time the block comes to rest.
    pub rest_time: f64,
    /// Impacts until then (those a step-by-step simulation would count).
    pub impacts: u64,
}

/// Pull-back accelerations at θ = 0 on sides +1 and −1 (positive when the
/// block is pulled back to θ = 0), with the ground at `u` = ü_g/g.
fn pull_back(formulation: Formulation, block: &Block, u: f64) -> (f64, f64) {
    let p2 = block.frequency_parameter().powi(2);
    let acc =
        |side: f64| -side * formulation.angular_acceleration(p2, block.slenderness(), side, 0.0, u);
    (acc(1.0), acc(-1.0))
}

/// [`pull_back`] under a vertical ground acceleration too: `weight` = 1 + ü_v/g.
fn pull_back_weighted(formulation: Formulation, block: &Block, u: f64, weight: f64) -> (f64, f64) {
    let p2 = block.frequency_parameter().powi(2);
    let acc = |side: f64| {
        -side
            * formulation.angular_acceleration_weighted(
                p2,
                block.slenderness(),
                side,
                0.0,
                u,
                weight,
            )
    };
    (acc(1.0), acc(-1.0))
}

/// The settling of a block that has just left θ = 0 at time `t` with velocity
/// `v` (after the impact), if chattering can be summed there. `v_rest` is the
/// rest threshold; `forced` whether the ground motion still acts.
#[allow(clippy::too_many_arguments)]
pub fn settle<G: Forcing>(
    formulation: Formulation,
    block: &Block,
    pulse: &G,
    forced: bool,
    t: f64,
    v: f64,
    v_rest: f64,
) -> Option<Settling> {
    let eta = block.restitution();
    let speed = v.abs();
    let scale = block.frequency_parameter() * block.slenderness();
    if !(eta > 0.0 && eta < 1.0) || speed <= v_rest || speed > CHATTER_VELOCITY * scale {
        return None;
    }
    let u = if forced {
        pulse.acceleration(t) / block.gravity()
    } else {
        0.0
    };
    let (plus, minus) = if G::VERTICAL {
        let weight = if forced {
            1.0 + pulse.vertical_acceleration(t) / block.gravity()
        } else {
            1.0
        };
        pull_back_weighted(formulation, block, u, weight)
    } else {
        pull_back(formulation, block, u)
    };
    if !(plus > 0.0 && minus > 0.0) {
        return None;
    }
    if speed * speed / (2.0 * plus.min(minus)) > CHATTER_EXCURSION * block.slenderness() {
        return None;
    }
    let (own, other) = if v > 0.0 {
        (plus, minus)
    } else {
        (minus, plus)
    };
    let duration = 2.0 * speed * (1.0 / own + eta / other) / (1.0 - eta * eta);
    let rest_time = t + duration;
    if forced {
        // The ground must keep pulling back until the block has settled.
        let threshold = formulation.threshold(block);
        if pulse.rocks_before(t, t + 2.0 * duration, &threshold) {
            return None;
        }
        if pulse
            .next_weightless(t, block.gravity())
            .is_some_and(|tw| tw <= t + 2.0 * duration)
        {
            return None;
        }
        if rest_time >= pulse.duration() {
            return None;
        }
    }
    let impacts = ((v_rest / speed).ln() / eta.ln()).ceil().max(1.0) as u64;
    Some(Settling { rest_time, impacts })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::excitation::{Pulse, PulseShape};

    #[test]
    fn free_chattering_settles_after_the_geometric_sum_of_flights() {
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        let pulse = Pulse::new(PulseShape::OneSine, 1.0, 1.0).expect("valid");
        let v = 1e-6;
        let s = settle(Formulation::Linear, &block, &pulse, false, 0.0, v, 1e-15).expect("sums");
        // Linear free flight: 2v/(p² α) per flight, geometric with ratio η.
        let flight = 2.0 * v / (2.14f64.powi(2) * 0.25);
        assert!((s.rest_time - flight / (1.0 - 0.9)).abs() < 1e-12 * flight);
        assert_eq!(s.impacts, ((1e-15f64 / v).ln() / 0.9f64.ln()).ceil() as u64);
    }

    #[test]
    fn no_sum_while_the_ground_pushes_the_block_over() {
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        // ü_g = 2 g α at t = 0 (one-cosine): the ground lifts the block.
        let pulse = Pulse::new(PulseShape::OneCosine, 2.0 * 0.25 * 9.81, 1.0).expect("valid");
        assert!(settle(Formulation::Linear, &block, &pulse, true, 0.0, 1e-7, 1e-15).is_none());
    }
}
