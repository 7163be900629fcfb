//! Closed-form cross-checks of the overturning spectrum.

use crate::dynamics::PulseShape;
use crate::dynamics::events::brent;
use std::f64::consts::{FRAC_PI_2, PI};

/// Eq. 21: a_p0/(αg) ≈ 1 + β ω_p/p, with β = 1/6 for one-sine and Type-Cn pulses
/// and 1/4 for one-cosine (Makris & Roussos), meant for ω_p/p ≤ 3; `None`
/// for the pulses it was not fitted to.
pub fn eq21_minimum(shape: PulseShape, omega_ratio: f64) -> Option<f64> {
    let beta = match shape {
        PulseShape::OneCosine => 0.25,
        PulseShape::OneSine | PulseShape::Cn(_) => 1.0 / 6.0,
        PulseShape::HalfSine
        | PulseShape::Rectangular
        | PulseShape::Ricker { .. }
        | PulseShape::MavroeidisPapageorgiou { .. } => return None,
    };
    Some(1.0 + beta * omega_ratio)
}

/// Housner's (1963) minimum overturning amplitude of a rectangular pulse of
/// duration t_d = π/ω_p, linear formulation: the block overturns iff
/// e^(p t_d) ≥ a_p/(a_p − αg), so a_p0/(αg) = 1/(1 − e^(−π/(ω_p/p))).
pub fn housner_rectangular_minimum(omega_ratio: f64) -> f64 {
    1.0 / -(-PI / omega_ratio).exp_m1()
}

/// The linear one-sine mode-2 boundary (overturning without impact), a_p/(αg).
///
/// From eqs. 44–46: with rocking starting at phase ψ (sin ψ = αg/a_p) and no
/// impact, the growing exponential of the free motion after the pulse vanishes
/// when `(ω_p/p) sin ψ − cos ψ = −exp[−(p/ω_p)(2π − ψ)]`. (Eq. 47 as printed has
/// the exponent's sign reversed and then has no root.) The left side grows with ψ
/// and the equation has exactly one root in (0, π/2); the boundary is
/// a_p/(αg) = 1/sin ψ.
pub fn linear_one_sine_mode2_boundary(omega_ratio: f64) -> Option<f64> {
    if !(omega_ratio > 0.0 && omega_ratio.is_finite()) {
        return None;
    }
    let r = omega_ratio;
    let f = |psi: f64| r * psi.sin() - psi.cos() + (-(2.0 * PI - psi) / r).exp();
    let (lo, hi) = (0.0, FRAC_PI_2);
    let (flo, fhi) = (f(lo), f(hi));
    if !(flo < 0.0 && fhi > 0.0) {
        return None;
    }
    let psi = brent(f, lo, hi, flo, fhi, 1e-15);
    Some(1.0 / psi.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_two_boundary_at_omega_ratio_5_is_just_below_7_17() {
        // Paper Figs. 7–8: survives at 7.17 αg, overturns without impact at 7.18.
        let a = linear_one_sine_mode2_boundary(5.0).expect("root");
        assert!(a > 7.15 && a < 7.18, "{a}");
    }

    #[test]
    fn mode_two_boundary_tends_to_one_for_slow_pulses() {
        // A very slow pulse overturns without impact just above the threshold.
        let a = linear_one_sine_mode2_boundary(0.05).expect("root");
        assert!(a > 1.0 && a < 1.1, "{a}");
    }

    #[test]
    fn eq21_coefficients() {
        assert_eq!(eq21_minimum(PulseShape::OneCosine, 2.0), Some(1.5));
        assert!((eq21_minimum(PulseShape::OneSine, 3.0).unwrap_or(0.0) - 1.5).abs() < 1e-15);
        assert!((eq21_minimum(PulseShape::Cn(2), 3.0).unwrap_or(0.0) - 1.5).abs() < 1e-15);
        assert_eq!(eq21_minimum(PulseShape::HalfSine, 1.0), None);
    }
}
