//! When free rocking on a Coulomb floor is pure rocking to its end.
//!
//! Once the ground has stopped, a block rocking on a holding pivot keeps or
//! loses energy (impacts), never gains it. Its states stay in the energy
//! well it is in: with E = θ̇²/2 + p² cos(α − |θ|) (energy per I_O, eqs. 1–2
//! with I_O = 4mR²/3, so m g R / I_O = p²), θ̇² ≤ 2(E − p² cos(α − |θ|)) at
//! every |θ| it can reach. Without ground motion the angular acceleration
//! depends on θ alone, so the base reactions (eqs. 16–20) are affine in θ̇²
//! at a given θ, and |f_x|/f_z, a ratio of affine functions, is largest at
//! θ̇² = 0 or at the well's bound. Where, over every reachable |θ|, f_z
//! stays above 0 and |f_x| within μ_s f_z at both ends, and Housner's impact
//! holds (the tangential impulse it needs, a fixed fraction of the normal
//! one, within μ_s), the pivot never slips and the block never leaves the
//! floor: the rest of the motion is pure rocking, decided in closed form by
//! [`super::separatrix::decide`].

use super::Block;
use super::reactions::nonlinear_reactions_at;
use super::slide_rock;

/// Points over 0 ≤ |θ| ≤ π/2 at which the reactions are evaluated.
const POINTS: usize = 256;

/// The margin, in g, by which f_z and μ_s f_z − |f_x| must clear 0 at every
/// point (it bounds what the reactions, smooth in θ, can do between two
/// points π/512 apart).
const MARGIN_G: f64 = 2e-3;

/// Whether a block rocking freely (no ground motion) at (θ, θ̇) on a floor
/// with static friction `mu_s` rocks purely from here on: its pivot holds,
/// it never leaves the floor, and every impact holds.
pub fn stays_pure(block: &Block, mu_s: f64, theta: f64, theta_dot: f64) -> bool {
    impacts_hold(block, mu_s) && within_limits(block, mu_s, theta, theta_dot)
}

/// Whether Housner's impact (the landing corner holding, θ̇ → η θ̇) needs a
/// tangential impulse within μ_s times the normal one. Both impulses are
/// proportional to θ̇ before it, so one impact stands for all.
pub fn impacts_hold(block: &Block, mu_s: f64) -> bool {
    slide_rock::impact(block, mu_s, mu_s, 1.0, -1.0, 0.0).sticking
}

/// Whether f_z > 0 and |f_x| ≤ μ_s f_z over the energy well of (θ, θ̇), both
/// with [`MARGIN_G`] to spare.
pub fn within_limits(block: &Block, mu_s: f64, theta: f64, theta_dot: f64) -> bool {
    use std::f64::consts::FRAC_PI_2;
    let alpha = block.slenderness();
    let p2 = block.frequency_parameter().powi(2);
    let g = block.gravity();
    let gamma0 = theta.abs().min(FRAC_PI_2);
    // θ̇² at |θ| = γ on the energy level of the state.
    let level = theta_dot * theta_dot + 2.0 * p2 * (alpha - gamma0).cos();
    let w2 = |gamma: f64| level - 2.0 * p2 * (alpha - gamma).cos();
    // Over the top (|θ| = α) the well is one; below it, the state's side.
    let over_top = w2(alpha) >= 0.0;
    let inside = gamma0 <= alpha;
    let margin = MARGIN_G * g;
    with_phases(alpha, |phases| {
        phases.iter().enumerate().all(|(k, &phi)| {
            let gamma = FRAC_PI_2 * k as f64 / POINTS as f64;
            // ϕ = α − γ on the side θ > 0: one sine and cosine serve the
            // well's bound and both reactions.
            let bound = level - 2.0 * p2 * phi.1;
            if bound < 0.0 || !(over_top || (gamma <= alpha) == inside) {
                return true;
            }
            [0.0, bound.sqrt()].iter().all(|&w| {
                let (fx, fz) = nonlinear_reactions_at(block, phi, w, 0.0, 0.0);
                fz >= margin && fx.abs() <= mu_s * fz - margin
            })
        })
    })
}

/// (sin ϕ, cos ϕ) of ϕ = α − γ at the points γ_k = (π/2) k / [`POINTS`].
type Phases = [(f64, f64); POINTS + 1];

thread_local! {
    /// The phases of the last slenderness asked for on this thread, as
    /// (α's bits, phases): a scan asks [`within_limits`] of one block over
    /// and over, and the phases depend on α alone.
    static PHASES: std::cell::RefCell<Option<(u64, Box<Phases>)>> =
        const { std::cell::RefCell::new(None) };
}

/// Runs `f` on the phases of `alpha` (computed once per slenderness and
/// thread, the same values to the bit).
fn with_phases<R>(alpha: f64, f: impl FnOnce(&Phases) -> R) -> R {
    use std::f64::consts::FRAC_PI_2;
    let bits = alpha.to_bits();
    let phases = match PHASES.with(|cell| cell.take()) {
        Some((b, phases)) if b == bits => phases,
        _ => {
            let mut phases = Box::new([(0.0, 0.0); POINTS + 1]);
            for (k, phi) in phases.iter_mut().enumerate() {
                let gamma = FRAC_PI_2 * k as f64 / POINTS as f64;
                *phi = (alpha - gamma).sin_cos();
            }
            phases
        }
    };
    let r = f(&phases);
    PHASES.with(|cell| cell.replace(Some((bits, phases))));
    r
}

/// The energy above rest (θ̇²/2 + p²(cos(α − |θ|) − cos α), per I_O) of a
/// rocking state: what decides whether a state's well is smaller than one
/// found too large.
pub fn energy(block: &Block, theta: f64, theta_dot: f64) -> f64 {
    let alpha = block.slenderness();
    let p2 = block.frequency_parameter().powi(2);
    0.5 * theta_dot * theta_dot + p2 * ((alpha - theta.abs()).cos() - alpha.cos())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn locomotive() -> Block {
        Block::new(0.25, 2.14, None, None, None).expect("valid")
    }

    /// At rest on a corner (θ = θ̇ = 0⁺) rocking needs |f_x|/f_z =
    /// (3/4) sin α cos α / (1 − (3/4) sin² α) (eqs. 16–20 with ü_g = 0,
    /// R p² = 3g/4): 0.1884 for α = 0.25. The criterion holds just above it
    /// (for a small well) and fails below it.
    #[test]
    fn the_smallest_rocking_needs_the_closed_form_friction() {
        let b = locomotive();
        let (s, c) = 0.25f64.sin_cos();
        let need = 0.75 * s * c / (1.0 - 0.75 * s * s);
        assert!((need - 0.18845).abs() < 1e-4, "{need}");
        // A small well: θ̇ = 0.01 rad/s at θ = 0.
        assert!(within_limits(&b, need + 0.01, 0.0, 0.01));
        assert!(!within_limits(&b, need - 0.005, 0.0, 0.01));
    }

    /// Housner's impact needs P_t/P_n = (1 − η)/((1 + η) tan α) (the
    /// corner's impulses with the pivot holding): it holds above that μ and
    /// not below.
    #[test]
    fn impacts_hold_from_the_closed_form_ratio_on() {
        let b = locomotive();
        let eta = b.restitution();
        let need = (1.0 - eta) / ((1.0 + eta) * 0.25f64.tan());
        assert!(impacts_hold(&b, need * 1.001));
        assert!(!impacts_hold(&b, need * 0.999));
    }

    /// The well grows with the energy: a state that clears the limits at
    /// a small amplitude fails them once it can climb near the top, where
    /// the fall needs more friction (and, over the top, lifts off).
    #[test]
    fn a_larger_well_needs_more_friction() {
        let b = locomotive();
        let mu = 0.3;
        assert!(within_limits(&b, mu, 0.05, 0.0));
        // Enough energy to pass over the top and fall: f_z reaches 0.
        let over = (2.0 * 2.14f64.powi(2) * (1.0 - 0.25f64.cos())).sqrt() * 1.5;
        assert!(!within_limits(&b, 10.0, 0.0, over));
        assert!(energy(&b, 0.05, 0.0) < energy(&b, 0.0, over));
        assert!(energy(&b, 0.0, 0.0).abs() < 1e-15);
    }
}
