//! How a block at rest on a floor with Coulomb friction starts to move
//! (Shenton 1996; the paper's eqs. 2–8): the contact modes, and the one the
//! block enters when the ground first moves it.
//!
//! With g_z = g + ü_v the gravity in the block's frame, a block at rest
//! slips once |ü_g| > μ_s g_z and would start rocking once
//! |ü_g| > tan α · g_z. Rocking from rest needs, at that instant, the
//! friction of eq. 7 (g → g_z):
//!
//!   f_x/f_z = (a − ¾ g_z cos α sin α (a/(g_z tan α) − 1))
//!             / (g_z + ¾ g_z sin²α (a/(g_z tan α) − 1)),   a = |ü_g|,
//!
//! which is tan α when the acceleration builds up gradually (eq. 8) and grows
//! with a jump at the onset (eq. 51 for the one-cosine pulse). Hence:
//! - μ_s < tan α: the slip threshold comes first, and a sliding block's
//!   horizontal force μ_k f_z < tan α f_z cannot tip it: **slide**;
//! - μ_s ≥ tan α: the rocking threshold comes first; where eq. 7 ≤ μ_s the
//!   pivot holds: **rock**; otherwise the pivot slips, and the block
//!   rotates about its sliding corner when μ_k > tan α (**slide-rock**),
//!   slides flat otherwise (**slide**);
//! - g_z ≤ 0: nothing holds the block on the floor: **flight**.

use super::Block;
use super::equations::Threshold;
use super::forcing::Forcing;
use super::sliding::Friction;

/// A block's contact with the floor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mode {
    /// At rest on the floor, moving with it.
    Stick,
    /// Flat on the floor (θ = 0), both corners sliding.
    Slide,
    /// Rotating about a corner that holds.
    Rock,
    /// Rotating about a corner that slides.
    SlideRock,
    /// No contact.
    Flight,
}

impl Mode {
    /// The name results give it.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Stick => "stick",
            Mode::Slide => "slide",
            Mode::Rock => "rock",
            Mode::SlideRock => "slide_rock",
            Mode::Flight => "flight",
        }
    }
}

/// Eq. 7 with gravity `g_z` (m/s²): the friction a block at rest needs to
/// start rocking without sliding when the ground acceleration there is
/// `ground` (m/s², |ground| ≥ tan α g_z).
pub fn rocking_onset_demand(slenderness: f64, g_z: f64, ground: f64) -> f64 {
    super::reactions::initiation_demand_under(slenderness, g_z, ground)
}

/// The mode a block at rest enters at the instant the ground first moves
/// it, the ground then at `ground` (m/s², signed) and `vertical` (m/s²,
/// positive up): at or past the lower of its two thresholds.
pub fn entered_mode(block: &Block, friction: Friction, ground: f64, vertical: f64) -> Mode {
    let g_z = block.gravity() + vertical;
    if g_z <= 0.0 {
        return Mode::Flight;
    }
    let tan = block.slenderness().tan();
    if friction.static_coefficient < tan {
        return Mode::Slide;
    }
    if rocking_onset_demand(block.slenderness(), g_z, ground) <= friction.static_coefficient {
        Mode::Rock
    } else if friction.kinetic_coefficient > tan {
        Mode::SlideRock
    } else {
        Mode::Slide
    }
}

/// When and how a block at rest from `from` on first moves under `forcing`
/// (nonlinear thresholds: tan α for rocking, μ_s for slipping): the first
/// instant either threshold is exceeded, and [`entered_mode`] there;
/// `None` if neither ever is.
pub fn onset<G: Forcing>(
    forcing: &G,
    block: &Block,
    friction: Friction,
    from: f64,
) -> Option<(f64, Mode)> {
    let g = block.gravity();
    let k = block.slenderness().tan().min(friction.static_coefficient);
    let lower = Threshold {
        level: k * g,
        factor: k,
        gravity: g,
    };
    let t = match (
        forcing.next_rocking(from, &lower).map(|w| w.start),
        forcing.next_weightless(from, g),
    ) {
        (Some(t), Some(l)) if l <= t => return Some((l, Mode::Flight)),
        (None, Some(l)) => return Some((l, Mode::Flight)),
        (Some(t), _) => t,
        (None, None) => return None,
    };
    Some((
        t,
        entered_mode(
            block,
            friction,
            forcing.acceleration(t),
            forcing.vertical_acceleration(t),
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{Pulse, PulseShape};

    /// Eq. 51 as printed (λ = 1, g = 9.81).
    fn eq51(alpha: f64, a_p: f64) -> f64 {
        let (g, t, s, c) = (9.81, alpha.tan(), alpha.sin(), alpha.cos());
        let x = a_p / (g * t) - 1.0;
        t * (a_p / (g * s) - 0.75 * c * x) / (t / s + 0.75 * t * s * x)
    }

    #[test]
    fn a_one_cosine_pulse_enters_the_regions_of_eq_51() {
        // The one-cosine pulse starts at its peak, a_p: below both
        // thresholds the block stays; μ < tan α it slides; above, it rocks
        // where eq. 51 ≤ μ and otherwise slide-rocks (μ_k = μ > tan α).
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        let tan = 0.25f64.tan();
        let mut seen = std::collections::HashSet::new();
        for i in 1..=40 {
            let mu = 0.025 * f64::from(i);
            for j in 1..=60 {
                let a_g = 0.05 * f64::from(j);
                let pulse = Pulse::new(PulseShape::OneCosine, a_g * 9.81, 8.0).expect("valid");
                let f = Friction::new(mu, None).expect("valid");
                let got = onset(&pulse, &block, f, 0.0).map(|(t, m)| {
                    assert_eq!(t, 0.0, "a one-cosine moves the block at once");
                    m
                });
                let expected = if a_g <= mu.min(tan) {
                    None
                } else if mu < tan {
                    Some(Mode::Slide)
                } else if eq51(0.25, a_g * 9.81) <= mu {
                    Some(Mode::Rock)
                } else {
                    Some(Mode::SlideRock)
                };
                // Exactly on a threshold the pulse's own rounding decides.
                if (a_g - mu).abs() > 1e-9 && (a_g - tan).abs() > 1e-9 {
                    assert_eq!(got, expected, "μ = {mu}, a_p = {a_g} g");
                }
                seen.insert(got);
            }
        }
        for m in [
            None,
            Some(Mode::Slide),
            Some(Mode::Rock),
            Some(Mode::SlideRock),
        ] {
            assert!(seen.contains(&m), "{m:?} never entered");
        }
    }

    #[test]
    fn a_one_sine_pulse_rocks_above_tan_alpha_and_slides_below() {
        // Built up gradually, the acceleration meets the lower threshold
        // exactly: eq. 8, tan α ≤ μ to rock; no slide-rock at the onset.
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        let tan = 0.25f64.tan();
        for mu in [0.05, 0.15, 0.2, 0.25, 0.26, 0.4, 0.8] {
            for a_g in [0.1, 0.3, 0.6, 1.5, 3.0] {
                let pulse = Pulse::new(PulseShape::OneSine, a_g * 9.81, 6.0).expect("valid");
                let got = onset(&pulse, &block, Friction::new(mu, None).expect("valid"), 0.0);
                let k = mu.min(tan);
                match got {
                    None => assert!(a_g <= k, "μ = {mu}, a_p = {a_g} g"),
                    Some((t, m)) => {
                        assert!(a_g > k);
                        assert!((9.81 * a_g * (6.0 * t).sin() - k * 9.81).abs() < 1e-9);
                        assert_eq!(m, if mu < tan { Mode::Slide } else { Mode::Rock });
                    }
                }
            }
        }
    }

    #[test]
    fn the_locomotive_on_mu_0_2_slides_and_a_kinetic_coefficient_below_tan_alpha_cannot_tip_it() {
        // The case: α = 0.25 (tan α = 0.255), μ = 0.2: it slides
        // from |ü_g| = μ g. A one-cosine jump past eq. 7's demand on μ_s = 0.5
        // slide-rocks with μ_k = 0.4, slides flat with μ_k = 0.2.
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        let pulse = Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * 9.81, 3.0 * 2.14).expect("valid");
        let (t, m) = onset(
            &pulse,
            &block,
            Friction::new(0.2, None).expect("valid"),
            0.0,
        )
        .expect("moves");
        assert_eq!(m, Mode::Slide);
        assert!((t - 0.2f64.asin() / (3.0 * 2.14)).abs() < 1e-12);
        let jump = Pulse::new(PulseShape::OneCosine, 3.0 * 9.81, 6.0).expect("valid");
        assert!(rocking_onset_demand(0.25, 9.81, 3.0 * 9.81) > 0.5);
        let f = |k| Friction::new(0.5, Some(k)).expect("valid");
        assert_eq!(
            onset(&jump, &block, f(0.4), 0.0),
            Some((0.0, Mode::SlideRock))
        );
        assert_eq!(onset(&jump, &block, f(0.2), 0.0), Some((0.0, Mode::Slide)));
        // Eq. 7 at the rocking threshold is eq. 8, tan α, whatever the
        // gravity; it depends on a/g_z only (the same block, heavier).
        for g_z in [3.0, 9.81, 15.0] {
            let tan = 0.25f64.tan();
            assert!((rocking_onset_demand(0.25, g_z, tan * g_z) - tan).abs() < 1e-15);
            for a in [2.6, 4.0, 9.0, 20.0] {
                let d = rocking_onset_demand(0.25, g_z, a * g_z / 9.81);
                assert!((d - rocking_onset_demand(0.25, 9.81, a)).abs() < 1e-14);
            }
        }
    }
}
