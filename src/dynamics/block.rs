//! The free-standing rectangular block (paper Fig. 3).

use std::f64::consts::FRAC_PI_2;

/// Standard gravity, m/s².
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Why a block cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BlockError {
    /// Slenderness must lie in (0, π/2).
    #[error("slenderness must satisfy 0 < alpha < pi/2 (got {0})")]
    Slenderness(f64),
    /// Frequency parameter must be positive and finite.
    #[error("frequency parameter p must be positive and finite (got {0})")]
    FrequencyParameter(f64),
    /// Restitution must lie in [0, 1].
    #[error("coefficient of restitution must satisfy 0 <= eta <= 1 (got {0})")]
    Restitution(f64),
    /// Friction must be positive and finite.
    #[error("friction coefficient must be positive and finite (got {0})")]
    Friction(f64),
    /// Gravity must be positive and finite.
    #[error("gravity must be positive and finite (got {0})")]
    Gravity(f64),
    /// Geometry must be positive and finite.
    #[error("half-width and half-height must be positive and finite (got b = {0}, h = {1})")]
    Geometry(f64, f64),
}

/// A rigid block rocking on a rigid base, described by the paper's parameters.
/// Built valid only ([`Block::new`], [`Block::from_geometry`],
/// [`Block::with_frequency_parameter`]); read through its accessors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// Slenderness α = atan(b/h), radians; 0 < α < π/2.
    slenderness: f64,
    /// Frequency parameter p = √(3g/(4R)), rad/s (eq. 5).
    frequency_parameter: f64,
    /// Coefficient of restitution η: θ̇ after impact = η · θ̇ before (eqs. 13–15).
    restitution: f64,
    /// Static friction coefficient μ at the base, if known (eqs. 6–9).
    friction: Option<f64>,
    /// Gravitational acceleration g, m/s².
    gravity: f64,
}

/// Housner's maximum coefficient of restitution, η = 1 − 1.5 sin²α (eq. 15,
/// r = η²), floored at 0 for stocky blocks (α ≥ asin √(2/3)).
pub fn housner_restitution(slenderness: f64) -> f64 {
    (1.0 - 1.5 * slenderness.sin().powi(2)).max(0.0)
}

impl Block {
    /// Builds a block from α, p and optionally η (default: [`housner_restitution`]),
    /// μ and g (default [`STANDARD_GRAVITY`]).
    pub fn new(
        slenderness: f64,
        frequency_parameter: f64,
        restitution: Option<f64>,
        friction: Option<f64>,
        gravity: Option<f64>,
    ) -> Result<Self, BlockError> {
        if !(slenderness > 0.0 && slenderness < FRAC_PI_2) {
            return Err(BlockError::Slenderness(slenderness));
        }
        if !(frequency_parameter > 0.0 && frequency_parameter.is_finite()) {
            return Err(BlockError::FrequencyParameter(frequency_parameter));
        }
        let restitution = restitution.unwrap_or_else(|| housner_restitution(slenderness));
        if !(0.0..=1.0).contains(&restitution) {
            return Err(BlockError::Restitution(restitution));
        }
        if let Some(mu) = friction
            && !(mu > 0.0 && mu.is_finite())
        {
            return Err(BlockError::Friction(mu));
        }
        let gravity = gravity.unwrap_or(STANDARD_GRAVITY);
        if !(gravity > 0.0 && gravity.is_finite()) {
            return Err(BlockError::Gravity(gravity));
        }
        Ok(Block {
            slenderness,
            frequency_parameter,
            restitution,
            friction,
            gravity,
        })
    }

    /// Builds a block from its half-width `b` and half-height `h` in metres:
    /// α = atan(b/h), R = √(b² + h²), p = √(3g/(4R)).
    pub fn from_geometry(
        half_width: f64,
        half_height: f64,
        restitution: Option<f64>,
        friction: Option<f64>,
        gravity: Option<f64>,
    ) -> Result<Self, BlockError> {
        if !(half_width > 0.0
            && half_width.is_finite()
            && half_height > 0.0
            && half_height.is_finite())
        {
            return Err(BlockError::Geometry(half_width, half_height));
        }
        let g = gravity.unwrap_or(STANDARD_GRAVITY);
        if !(g > 0.0 && g.is_finite()) {
            return Err(BlockError::Gravity(g));
        }
        let radius = half_width.hypot(half_height);
        let p = (3.0 * g / (4.0 * radius)).sqrt();
        Block::new(
            half_width.atan2(half_height),
            p,
            restitution,
            friction,
            Some(g),
        )
    }

    /// The same block with frequency parameter `p` (another size, the same
    /// slenderness, restitution, friction and gravity).
    pub fn with_frequency_parameter(&self, p: f64) -> Result<Self, BlockError> {
        Block::new(
            self.slenderness,
            p,
            Some(self.restitution),
            self.friction,
            Some(self.gravity),
        )
    }

    /// Slenderness α = atan(b/h), radians; 0 < α < π/2.
    #[inline]
    pub fn slenderness(&self) -> f64 {
        self.slenderness
    }

    /// Frequency parameter p = √(3g/(4R)), rad/s (eq. 5).
    #[inline]
    pub fn frequency_parameter(&self) -> f64 {
        self.frequency_parameter
    }

    /// Coefficient of restitution η: θ̇ after impact = η · θ̇ before (eqs. 13–15).
    #[inline]
    pub fn restitution(&self) -> f64 {
        self.restitution
    }

    /// Static friction coefficient μ at the base, if known (eqs. 6–9).
    #[inline]
    pub fn friction(&self) -> Option<f64> {
        self.friction
    }

    /// Gravitational acceleration g, m/s².
    #[inline]
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// Half-diagonal R = 3g/(4p²), m.
    pub fn half_diagonal(&self) -> f64 {
        3.0 * self.gravity / (4.0 * self.frequency_parameter.powi(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn housner_restitution_vanishes_at_the_perfectly_plastic_slenderness() {
        let alpha = (2.0f64 / 3.0).sqrt().asin();
        assert!(housner_restitution(alpha).abs() < 1e-15);
        assert_eq!(housner_restitution(1.2), 0.0);
        // Equipment of Fig. 10: α = 0.349 gives η ≈ 0.825.
        assert!((housner_restitution(0.349) - 0.825).abs() < 2e-3);
    }

    #[test]
    fn geometry_gives_paper_parameters() {
        let b = Block::from_geometry(0.5, 2.0, None, None, None).expect("valid");
        assert!((b.slenderness - 0.25f64.atan()).abs() < 1e-15);
        let r = (0.25f64 + 4.0).sqrt();
        assert!((b.frequency_parameter - (3.0 * 9.81 / (4.0 * r)).sqrt()).abs() < 1e-12);
        assert!((b.half_diagonal() - r).abs() < 1e-12);
    }

    #[test]
    fn invalid_parameters_are_refused() {
        assert!(Block::new(FRAC_PI_2, 2.0, None, None, None).is_err());
        assert!(Block::new(0.0, 2.0, None, None, None).is_err());
        assert!(Block::new(f64::NAN, 2.0, None, None, None).is_err());
        assert!(Block::new(0.2, -1.0, None, None, None).is_err());
        assert!(Block::new(0.2, 2.0, Some(1.1), None, None).is_err());
        assert!(Block::new(0.2, 2.0, None, Some(-0.1), None).is_err());
        assert!(Block::from_geometry(0.0, 1.0, None, None, None).is_err());
    }

    #[test]
    fn another_size_keeps_the_rest_and_is_checked() {
        let b = Block::new(0.25, 2.14, Some(0.9), Some(0.7), Some(9.8)).expect("valid");
        let c = b.with_frequency_parameter(5.0).expect("valid");
        assert_eq!(
            (c.slenderness(), c.restitution(), c.friction(), c.gravity()),
            (0.25, 0.9, Some(0.7), 9.8)
        );
        assert_eq!(c.frequency_parameter(), 5.0);
        assert_eq!(
            b.with_frequency_parameter(f64::INFINITY),
            Err(BlockError::FrequencyParameter(f64::INFINITY))
        );
        assert!(b.with_frequency_parameter(0.0).is_err());
    }
}
