//! Equations of motion while rocking: nonlinear (eqs. 12 / 49) and linearised for
//! slender blocks (eqs. 23–24 / 50), and the free-vibration barrier that decides
//! overturning once no forcing remains.

use super::block::Block;
use super::excitation::{Pulse, Wave};
use super::integrator::{Rhs, State};

/// Which equation of motion is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Formulation {
    /// Slender-block linearisation, eqs. 23–24 / 50.
    Linear,
    /// Full nonlinear equation, eq. 12 / 49.
    Nonlinear,
}

impl Formulation {
    /// The name used in job specs and reports.
    pub fn name(self) -> &'static str {
        match self {
            Formulation::Linear => "linear",
            Formulation::Nonlinear => "nonlinear",
        }
    }

    /// Ground acceleration (m/s²) that |ü_g| must exceed for rocking to start:
    /// g·tan α (nonlinear, § "Condition for Initiation") or g·α (linear).
    pub fn rocking_threshold(self, block: &Block) -> f64 {
        self.rocking_threshold_of(block.slenderness(), block.gravity())
    }

    /// [`Formulation::rocking_threshold`] of any block of slenderness α under
    /// gravity g, whatever its size.
    #[inline]
    pub fn rocking_threshold_of(self, slenderness: f64, gravity: f64) -> f64 {
        match self {
            Formulation::Linear => gravity * slenderness,
            Formulation::Nonlinear => gravity * slenderness.tan(),
        }
    }

    /// The rocking threshold of `block` under this formulation, for ground
    /// motions with or without a vertical component.
    pub fn threshold(self, block: &Block) -> Threshold {
        Threshold {
            level: self.rocking_threshold(block),
            factor: self.rocking_threshold_of(block.slenderness(), 1.0),
            gravity: block.gravity(),
        }
    }

    /// Angular acceleration θ̈ while pivoting on the corner of side `side` (±1, the
    /// sign of θ), with the ground acceleration `ug_over_g` = ü_g/g.
    ///
    /// Nonlinear, eq. 12: θ̈ = −p² { sin(α s − θ) + (ü_g/g) cos(α s − θ) }.
    /// Linear, eq. 50:    θ̈ = p² { θ − α s − ü_g/g }.
    #[inline]
    pub fn angular_acceleration(
        self,
        p2: f64,
        alpha: f64,
        side: f64,
        theta: f64,
        ug_over_g: f64,
    ) -> f64 {
        match self {
            Formulation::Linear => p2 * (theta - alpha * side - ug_over_g),
            Formulation::Nonlinear => {
                let (s, c) = (alpha * side - theta).sin_cos();
                -p2 * (s + ug_over_g * c)
            }
        }
    }

    /// [`Formulation::angular_acceleration`] under a vertical ground
    /// acceleration ü_v (positive up): `weight` = 1 + ü_v/g scales the
    /// restoring term, gravity being g + ü_v in the block's frame.
    ///
    /// Nonlinear (eq. 12 with g + ü_v):
    /// θ̈ = −p² { (1 + ü_v/g) sin(α s − θ) + (ü_g/g) cos(α s − θ) }.
    /// Linear (eq. 50 likewise): θ̈ = p² { (1 + ü_v/g)(θ − α s) − ü_g/g }.
    /// With `weight` = 1 it is [`Formulation::angular_acceleration`] to the bit.
    #[inline]
    pub fn angular_acceleration_weighted(
        self,
        p2: f64,
        alpha: f64,
        side: f64,
        theta: f64,
        ug_over_g: f64,
        weight: f64,
    ) -> f64 {
        match self {
            Formulation::Linear => p2 * (weight * (theta - alpha * side) - ug_over_g),
            Formulation::Nonlinear => {
                let (s, c) = (alpha * side - theta).sin_cos();
                -p2 * (weight * s + ug_over_g * c)
            }
        }
    }

    /// Free-vibration energy above the barrier at |θ| = α, in units where the
    /// block can pass the barrier exactly when this is positive.
    ///
    /// Nonlinear: E − 1 with E = θ̇²/(2p²) + cos(α − |θ|) (eq. 12 with ü_g = 0).
    /// Linear: ½(θ̇²/p² − (|θ| − α)²), the sign of the growing exponential's
    /// coefficient when moving towards the barrier (eq. 33).
    pub fn barrier_excess(self, block: &Block, theta: f64, theta_dot: f64) -> f64 {
        let p = block.frequency_parameter();
        let d = block.slenderness() - theta.abs();
        let kinetic = 0.5 * (theta_dot / p).powi(2);
        match self {
            Formulation::Linear => kinetic - 0.5 * d * d,
            Formulation::Nonlinear => kinetic - 2.0 * (0.5 * d).sin().powi(2),
        }
    }
}

/// When the ground rocks a block at rest: |ü_g| > (g + ü_v)·k with k = tan α
/// (nonlinear, § "Condition for Initiation of Rocking Motion") or α
/// (linear); without vertical motion the level g·k.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Threshold {
    /// g·k, m/s²: the level |ü_g| must exceed without vertical motion
    /// ([`Formulation::rocking_threshold`], to the bit).
    pub level: f64,
    /// k: tan α or α.
    pub factor: f64,
    /// g, m/s².
    pub gravity: f64,
}

impl Threshold {
    /// The level |ü_g| must exceed under the vertical acceleration ü_v, m/s².
    #[inline]
    pub fn under(&self, vertical: f64) -> f64 {
        (self.gravity + vertical) * self.factor
    }
}

/// The right-hand side of eq. 49 / 50 on one side, under a pulse or free.
#[derive(Clone, Copy, Debug)]
pub struct RockingRhs {
    /// Equation used.
    pub formulation: Formulation,
    /// p².
    pub p2: f64,
    /// α.
    pub alpha: f64,
    /// Side ±1: the sign of θ during this piece of motion.
    pub side: f64,
    /// a_p/g, zero for free vibration.
    pub amplitude_over_g: f64,
    /// ω_p.
    pub omega: f64,
    /// φ.
    pub phase: f64,
    /// The waveform: the cosine of ω and φ, or a wavelet.
    pub wave: Wave,
}

impl RockingRhs {
    /// Right-hand side on `side`, forced by `pulse` when `forced`.
    pub fn new(
        formulation: Formulation,
        block: &Block,
        pulse: &Pulse,
        side: f64,
        forced: bool,
    ) -> Self {
        RockingRhs {
            formulation,
            p2: block.frequency_parameter().powi(2),
            alpha: block.slenderness(),
            side,
            amplitude_over_g: if forced {
                pulse.amplitude / block.gravity()
            } else {
                0.0
            },
            omega: pulse.carrier,
            phase: pulse.phase,
            wave: pulse.wave,
        }
    }

    /// A wavelet's unit waveform at t (kept out of line: the cosine is the hot path).
    #[inline(never)]
    fn wave_at(&self, t: f64) -> f64 {
        match self.wave {
            Wave::Cosine => (self.omega * t + self.phase).cos(),
            wave => wave.value(t),
        }
    }

    /// ü_g/g at time t on this piece.
    #[inline]
    pub fn ground(&self, t: f64) -> f64 {
        if self.amplitude_over_g == 0.0 {
            0.0
        } else if let Wave::Cosine = self.wave {
            self.amplitude_over_g * (self.omega * t + self.phase).cos()
        } else {
            self.amplitude_over_g * self.wave_at(t)
        }
    }
}

impl Rhs for RockingRhs {
    #[inline]
    fn eval(&self, t: f64, y: State) -> State {
        [
            y[1],
            self.formulation.angular_acceleration(
                self.p2,
                self.alpha,
                self.side,
                y[0],
                self.ground(t),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nonlinear_reduces_to_linear_for_small_angles() {
        let (p2, alpha) = (4.0, 1e-3);
        for &(side, theta, u) in &[(1.0, 2e-4, -5e-4), (-1.0, -7e-4, 2e-3)] {
            let nl = Formulation::Nonlinear.angular_acceleration(p2, alpha, side, theta, u);
            let li = Formulation::Linear.angular_acceleration(p2, alpha, side, theta, u);
            assert!((nl - li).abs() < 1e-8 * p2, "{nl} vs {li}");
        }
    }

    #[test]
    fn rocking_starts_exactly_at_the_threshold() {
        let block = Block::new(0.3, 2.0, None, None, None).expect("valid");
        for f in [Formulation::Linear, Formulation::Nonlinear] {
            let u = f.rocking_threshold(&block) / block.gravity();
            // Positive ground acceleration pushes towards θ < 0 (side −1).
            let acc = f.angular_acceleration(4.0, 0.3, -1.0, 0.0, u);
            assert!(acc.abs() < 1e-14, "{f:?}: {acc}");
            assert!(f.angular_acceleration(4.0, 0.3, -1.0, 0.0, u * 1.01) < 0.0);
        }
    }

    #[test]
    fn a_weight_of_one_is_the_plain_equation_and_a_weight_is_another_gravity() {
        let (p2, alpha) = (4.0, 0.3);
        for f in [Formulation::Linear, Formulation::Nonlinear] {
            for &(side, theta, u) in &[(1.0, 0.2, -0.4), (-1.0, -0.05, 0.7)] {
                let plain = f.angular_acceleration(p2, alpha, side, theta, u);
                let one = f.angular_acceleration_weighted(p2, alpha, side, theta, u, 1.0);
                assert_eq!(plain.to_bits(), one.to_bits(), "{f:?}");
                // g + ü_v = w g: p² → w p², ü_g/g → ü_g/(w g).
                let w = 1.6;
                let weighted = f.angular_acceleration_weighted(p2, alpha, side, theta, u, w);
                let heavier = f.angular_acceleration(w * p2, alpha, side, theta, u / w);
                assert!((weighted - heavier).abs() < 1e-14, "{f:?}");
            }
        }
    }

    #[test]
    fn the_threshold_carries_the_vertical_acceleration() {
        let block = Block::new(0.3, 2.0, None, None, None).expect("valid");
        for f in [Formulation::Linear, Formulation::Nonlinear] {
            let th = f.threshold(&block);
            assert_eq!(th.level, f.rocking_threshold(&block));
            assert_eq!(th.under(0.0), th.level);
            let u = th.under(-3.0) / block.gravity();
            let w = 1.0 - 3.0 / block.gravity();
            let acc = f.angular_acceleration_weighted(4.0, 0.3, -1.0, 0.0, u, w);
            assert!(acc.abs() < 1e-14, "{f:?}: {acc}");
        }
    }

    #[test]
    fn barrier_excess_vanishes_on_the_separatrix() {
        let block = Block::new(0.25, 2.14, None, None, None).expect("valid");
        // Linear: θ̇ = p(α − θ) reaches θ = α with zero velocity (eq. 33).
        let e = Formulation::Linear.barrier_excess(&block, 0.1, 2.14 * 0.15);
        assert!(e.abs() < 1e-15);
        // Nonlinear: from θ = 0 the separatrix speed is p √(2(1 − cos α)).
        let v = 2.14 * (2.0 * (1.0 - 0.25f64.cos())).sqrt();
        assert!(Formulation::Nonlinear.barrier_excess(&block, 0.0, v).abs() < 1e-15);
    }
}
