//! Base reactions and the friction needed for pure rocking (eqs. 2–9, 16–20, 51).

use super::block::Block;
use super::equations::Formulation;

/// Horizontal and vertical base reactions per unit mass, `(f_x/m, f_z/m)`, m/s².
///
/// Eqs. 16–19: `f_x = m(ü_g + ẍ)`, `f_z = m(g + z̈)` with the centre-of-mass
/// kinematics `ẍ = R(θ̈ cos ϕ + θ̇² sin ϕ)`, `z̈ = R(θ̈ sin ϕ − θ̇² cos ϕ)`,
/// `ϕ = α s − θ`, and θ̈ from the formulation in use. For the nonlinear
/// formulation the ratio is exactly eq. 20.
pub fn reactions_per_mass(
    formulation: Formulation,
    block: &Block,
    side: f64,
    theta: f64,
    theta_dot: f64,
    ground: f64,
) -> (f64, f64) {
    let g = block.gravity;
    let p2 = block.frequency_parameter.powi(2);
    let r = block.half_diagonal();
    let acc = formulation.angular_acceleration(p2, block.slenderness, side, theta, ground / g);
    let (sp, cp) = (block.slenderness * side - theta).sin_cos();
    let w2 = theta_dot * theta_dot;
    (
        ground + r * (acc * cp + w2 * sp),
        g + r * (acc * sp - w2 * cp),
    )
}

/// Eq. 20 as printed: f_x/f_z of a rocking block (nonlinear formulation).
pub fn eq20_ratio(block: &Block, side: f64, theta: f64, theta_dot: f64, ground: f64) -> f64 {
    let u = ground / block.gravity;
    let phi = block.slenderness * side - theta;
    let w2 = (theta_dot / block.frequency_parameter).powi(2);
    let num = u * (5.0 - 3.0 * (2.0 * phi).cos()) - 3.0 * (2.0 * phi).sin() + 6.0 * w2 * phi.sin();
    let den = 5.0 - 3.0 * u * (2.0 * phi).sin() + 3.0 * (2.0 * phi).cos() - 6.0 * w2 * phi.cos();
    num / den
}

/// Friction demand at the instant rocking starts, eq. 7 (eq. 51 for the
/// one-cosine pulse, where λ a_p = a_p): the ground acceleration there is
/// `ground` (= λ a_p, signed).
pub fn initiation_demand(block: &Block, ground: f64) -> f64 {
    let a = block.slenderness;
    let g = block.gravity;
    let lam = ground.abs();
    let excess = lam / (g * a.tan()) - 1.0;
    let num = lam - 0.75 * g * a.cos() * a.sin() * excess;
    let den = g + 0.75 * g * a.sin().powi(2) * excess;
    num / den
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block() -> Block {
        Block::new(0.25, 2.14, Some(0.9), Some(0.7), None).expect("valid")
    }

    #[test]
    fn demand_at_one_sine_initiation_is_tan_alpha() {
        let b = block();
        let ground = b.gravity * b.slenderness.tan();
        let (fx, fz) = reactions_per_mass(Formulation::Nonlinear, &b, -1.0, 0.0, 0.0, ground);
        assert!((fx / fz - b.slenderness.tan()).abs() < 1e-15);
        assert!((initiation_demand(&b, ground) - b.slenderness.tan()).abs() < 1e-15);
    }

    #[test]
    fn nonlinear_reactions_are_eq_20() {
        let b = block();
        for &(side, th, w, ug) in &[
            (-1.0, -0.1, -0.3, 5.0),
            (1.0, 0.2, 0.4, -3.0),
            (1.0, 0.05, -0.9, 2.0),
        ] {
            let (fx, fz) = reactions_per_mass(Formulation::Nonlinear, &b, side, th, w, ug);
            let r20 = eq20_ratio(&b, side, th, w, ug);
            assert!((fx / fz - r20).abs() < 1e-13, "{} vs {r20}", fx / fz);
        }
    }

    #[test]
    fn initiation_demand_is_eq_20_at_rest_for_any_level() {
        let b = block();
        for level in [1.0, 2.0, 6.0] {
            let ground = level * b.gravity * b.slenderness;
            let r20 = eq20_ratio(&b, -1.0, 0.0, 0.0, ground);
            assert!((initiation_demand(&b, ground) - r20).abs() < 1e-14);
        }
    }

    #[test]
    fn one_cosine_demand_at_six_alpha_g_is_about_two_alpha() {
        // Paper Fig. 9 (bottom) and eq. 51: a_p = 6 α g needs μ ≈ 2 α to start rocking.
        let b = Block::new(0.25, 2.14, None, None, None).expect("valid");
        let d = initiation_demand(&b, 6.0 * 0.25 * b.gravity);
        assert!((d / 0.25 - 2.0).abs() < 0.1, "{}", d / 0.25);
    }
}
