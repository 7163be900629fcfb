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
    // No vertical motion: weight 1 and g + 0 are the plain equations to the bit.
    reactions_per_mass_vertical(formulation, block, side, theta, theta_dot, ground, 0.0)
}

/// [`reactions_per_mass`] under a vertical ground acceleration `vertical`
/// (ü_v, m/s², positive up): f_z = m(g + ü_v + z̈), and θ̈ from the equation
/// with gravity g + ü_v ([`Formulation::angular_acceleration_weighted`]).
pub fn reactions_per_mass_vertical(
    formulation: Formulation,
    block: &Block,
    side: f64,
    theta: f64,
    theta_dot: f64,
    ground: f64,
    vertical: f64,
) -> (f64, f64) {
    let phi = (block.slenderness() * side - theta).sin_cos();
    match formulation {
        Formulation::Nonlinear => nonlinear_reactions_at(block, phi, theta_dot, ground, vertical),
        Formulation::Linear => {
            let g = block.gravity();
            let acc = formulation.angular_acceleration_weighted(
                block.frequency_parameter().powi(2),
                block.slenderness(),
                side,
                theta,
                ground / g,
                1.0 + vertical / g,
            );
            reactions_with(block, phi, theta_dot, ground, vertical, acc)
        }
    }
}

/// [`reactions_per_mass_vertical`] of the nonlinear formulation (eq. 12
/// with g + ü_v, then eqs. 16–19) from `(sin ϕ, cos ϕ)`, ϕ = α s − θ,
/// already known: one sine and cosine serve θ̈ and the centre's
/// kinematics, the arithmetic that of [`reactions_per_mass_vertical`] to
/// the bit.
#[inline]
pub fn nonlinear_reactions_at(
    block: &Block,
    (sp, cp): (f64, f64),
    theta_dot: f64,
    ground: f64,
    vertical: f64,
) -> (f64, f64) {
    let g = block.gravity();
    let p2 = block.frequency_parameter().powi(2);
    let weight = 1.0 + vertical / g;
    // Formulation::angular_acceleration_weighted, nonlinear.
    let acc = -p2 * (weight * sp + ground / g * cp);
    reactions_with(block, (sp, cp), theta_dot, ground, vertical, acc)
}

/// Eqs. 16–19 at θ̈ = `acc`.
#[inline]
fn reactions_with(
    block: &Block,
    (sp, cp): (f64, f64),
    theta_dot: f64,
    ground: f64,
    vertical: f64,
    acc: f64,
) -> (f64, f64) {
    let r = block.half_diagonal();
    let w2 = theta_dot * theta_dot;
    (
        ground + r * (acc * cp + w2 * sp),
        block.gravity() + vertical + r * (acc * sp - w2 * cp),
    )
}

/// The base reactions per unit mass at a rocking state and their rates of
/// change along the motion, the rates written as affine functions of the
/// ground's jerk (d ü_g/dt, m/s³): a record's jerk jumps at every sample while
/// the state does not, so one evaluation serves both sides of a sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReactionRates {
    /// f_x/m, m/s².
    pub fx: f64,
    /// f_z/m, m/s².
    pub fz: f64,
    /// d(f_x/m)/dt = `fx_rate[0] + fx_rate[1] · jerk`.
    pub fx_rate: [f64; 2],
    /// d(f_z/m)/dt = `fz_rate[0] + fz_rate[1] · jerk`.
    pub fz_rate: [f64; 2],
    /// f_x/f_z (meaningful while f_z > 0).
    pub ratio: f64,
    /// d(f_x/f_z)/dt = `ratio_rate[0] + ratio_rate[1] · jerk` (while f_z > 0).
    pub ratio_rate: [f64; 2],
    /// The parts of d(f_x/m)/dt, d(f_z/m)/dt and d(f_x/f_z)/dt per unit
    /// vertical jerk (d ü_v/dt, m/s³): zero without a vertical motion.
    pub vertical_rate: [f64; 3],
}

impl ReactionRates {
    /// The reactions `fx`, `fz` with their rates, and the ratio's.
    #[inline]
    fn new(fx: f64, fz: f64, fx_rate: [f64; 2], fz_rate: [f64; 2]) -> Self {
        // The quotient rule, its two coefficients over one division.
        let inv_fz2 = 1.0 / (fz * fz);
        ReactionRates {
            fx,
            fz,
            fx_rate,
            fz_rate,
            ratio: fx / fz,
            ratio_rate: [
                (fx_rate[0] * fz - fx * fz_rate[0]) * inv_fz2,
                (fx_rate[1] * fz - fx * fz_rate[1]) * inv_fz2,
            ],
            vertical_rate: [0.0; 3],
        }
    }

    /// [`ReactionRates::new`] with the rates' parts per unit vertical jerk,
    /// `fx_v` and `fz_v`.
    #[inline]
    fn with_vertical(mut self, fx_v: f64, fz_v: f64) -> Self {
        let inv_fz2 = 1.0 / (self.fz * self.fz);
        self.vertical_rate = [fx_v, fz_v, (fx_v * self.fz - self.fx * fz_v) * inv_fz2];
        self
    }

    /// (f_x/f_z, its time derivative) under the ground jerk `jerk`, m/s³
    /// (meaningful while f_z > 0).
    #[inline]
    pub fn ratio(&self, jerk: f64) -> (f64, f64) {
        (self.ratio, self.ratio_rate[0] + self.ratio_rate[1] * jerk)
    }
}

/// [`reactions_per_mass`] with the rates of change of both reactions, for
/// one block and formulation (the constants worked out once).
///
/// Differentiating eqs. 16–19 along the motion, with ϕ̇ = −θ̇ and
/// θ⃛ = dθ̈/dt from the formulation (linear: p²(θ̇ − u̇); nonlinear:
/// p²(θ̇ cos ϕ − u̇ cos ϕ − u θ̇ sin ϕ), u = ü_g/g):
///
/// ```text
/// ḟ_x/m = d ü_g/dt + R (θ⃛ cos ϕ + 3 θ̈ θ̇ sin ϕ − θ̇³ cos ϕ),
/// ḟ_z/m =            R (θ⃛ sin ϕ − 3 θ̈ θ̇ cos ϕ − θ̇³ sin ϕ).
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ReactionModel {
    formulation: Formulation,
    alpha: f64,
    g: f64,
    p2: f64,
    /// R, the half-diagonal.
    r: f64,
    /// −p²/g: the part of θ⃛ per unit jerk (times cos ϕ when nonlinear).
    jerk_gain: f64,
}

impl ReactionModel {
    /// The model of `block` under `formulation`.
    pub fn new(formulation: Formulation, block: &Block) -> Self {
        let p2 = block.frequency_parameter().powi(2);
        ReactionModel {
            formulation,
            alpha: block.slenderness(),
            g: block.gravity(),
            p2,
            r: block.half_diagonal(),
            jerk_gain: -p2 / block.gravity(),
        }
    }

    /// The reactions and their rates at a rocking state on `side`, the ground
    /// acceleration being `ground` (m/s²). The values are those of
    /// [`reactions_per_mass`], to the last bit.
    #[inline]
    pub fn rates(&self, side: f64, theta: f64, theta_dot: f64, ground: f64) -> ReactionRates {
        let (g, p2, r) = (self.g, self.p2, self.r);
        let u = ground / g;
        let (sp, cp) = (self.alpha * side - theta).sin_cos();
        let w = theta_dot;
        let w2 = w * w;
        // θ̈, and θ⃛ = jerk_0 + jerk_1 · (d ü_g/dt).
        let (acc, jerk_0, jerk_1) = match self.formulation {
            Formulation::Linear => (p2 * (theta - self.alpha * side - u), p2 * w, self.jerk_gain),
            Formulation::Nonlinear => (
                -p2 * (sp + u * cp),
                p2 * w * (cp - u * sp),
                self.jerk_gain * cp,
            ),
        };
        let rest_x = 3.0 * acc * w * sp - w2 * w * cp;
        let rest_z = -3.0 * acc * w * cp - w2 * w * sp;
        ReactionRates::new(
            ground + r * (acc * cp + w2 * sp),
            g + r * (acc * sp - w2 * cp),
            [r * (jerk_0 * cp + rest_x), 1.0 + r * jerk_1 * cp],
            [r * (jerk_0 * sp + rest_z), r * jerk_1 * sp],
        )
    }

    /// [`ReactionModel::rates`] under a vertical ground acceleration
    /// `vertical` (ü_v, m/s², positive up), whose jerk d ü_v/dt enters the
    /// rates through [`ReactionRates::vertical_rate`]. The values are those
    /// of [`reactions_per_mass_vertical`], to the last bit.
    ///
    /// With w = 1 + ü_v/g, θ̈ is eq. 12 (eq. 50) with w on the restoring
    /// term, and its rate gains the part of ẇ = (d ü_v/dt)/g:
    ///
    /// ```text
    /// linear:    θ⃛ = p² (w θ̇ − u̇ + ẇ (θ − α s)),
    /// nonlinear: θ⃛ = p² (θ̇ (w cos ϕ − u sin ϕ) − u̇ cos ϕ − ẇ sin ϕ),
    /// ḟ_z/m = d ü_v/dt + R (θ⃛ sin ϕ − 3 θ̈ θ̇ cos ϕ − θ̇³ sin ϕ).
    /// ```
    #[inline]
    pub fn rates_vertical(
        &self,
        side: f64,
        theta: f64,
        theta_dot: f64,
        ground: f64,
        vertical: f64,
    ) -> ReactionRates {
        let (g, p2, r) = (self.g, self.p2, self.r);
        let u = ground / g;
        let weight = 1.0 + vertical / g;
        let (sp, cp) = (self.alpha * side - theta).sin_cos();
        let w = theta_dot;
        let w2 = w * w;
        // θ̈, and θ⃛ = jerk_0 + jerk_1 · (d ü_g/dt) + jerk_v · (d ü_v/dt).
        let (acc, jerk_0, jerk_1, jerk_v) = match self.formulation {
            Formulation::Linear => (
                p2 * (weight * (theta - self.alpha * side) - u),
                p2 * weight * w,
                self.jerk_gain,
                -self.jerk_gain * (theta - self.alpha * side),
            ),
            Formulation::Nonlinear => (
                -p2 * (weight * sp + u * cp),
                p2 * w * (weight * cp - u * sp),
                self.jerk_gain * cp,
                self.jerk_gain * sp,
            ),
        };
        let rest_x = 3.0 * acc * w * sp - w2 * w * cp;
        let rest_z = -3.0 * acc * w * cp - w2 * w * sp;
        ReactionRates::new(
            ground + r * (acc * cp + w2 * sp),
            g + vertical + r * (acc * sp - w2 * cp),
            [r * (jerk_0 * cp + rest_x), 1.0 + r * jerk_1 * cp],
            [r * (jerk_0 * sp + rest_z), r * jerk_1 * sp],
        )
        .with_vertical(r * jerk_v * cp, 1.0 + r * jerk_v * sp)
    }
}

/// Eq. 20 as printed: f_x/f_z of a rocking block (nonlinear formulation).
pub fn eq20_ratio(block: &Block, side: f64, theta: f64, theta_dot: f64, ground: f64) -> f64 {
    let u = ground / block.gravity();
    let phi = block.slenderness() * side - theta;
    let w2 = (theta_dot / block.frequency_parameter()).powi(2);
    let num = u * (5.0 - 3.0 * (2.0 * phi).cos()) - 3.0 * (2.0 * phi).sin() + 6.0 * w2 * phi.sin();
    let den = 5.0 - 3.0 * u * (2.0 * phi).sin() + 3.0 * (2.0 * phi).cos() - 6.0 * w2 * phi.cos();
    num / den
}

/// Friction demand at the instant rocking starts, eq. 7 (eq. 51 for the
/// one-cosine pulse, where λ a_p = a_p): the ground acceleration there is
/// `ground` (= λ a_p, signed).
pub fn initiation_demand(block: &Block, ground: f64) -> f64 {
    initiation_demand_under(block.slenderness(), block.gravity(), ground)
}

/// Eq. 7 with gravity `g` (m/s²; g + ü_v under a vertical motion) for a
/// block of slenderness `a`: the friction it needs to start rocking
/// without sliding when the ground acceleration there is `ground` (m/s²,
/// |ground| ≥ tan α g).
pub fn initiation_demand_under(a: f64, g: f64, ground: f64) -> f64 {
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
    fn reaction_rates_are_the_derivatives_along_the_motion() {
        // Central differences along the local Taylor expansion of the motion
        // (θ⃛ from the rates' own θ̈ and the formulation), the ground linear.
        let b = block();
        for formulation in [Formulation::Linear, Formulation::Nonlinear] {
            for &(side, th, w, ug, jerk) in &[
                (-1.0, -0.1, -0.3, 5.0, 40.0),
                (1.0, 0.2, 0.4, -3.0, -250.0),
                (1.0, 0.05, -0.9, 2.0, 0.0),
            ] {
                let r = ReactionModel::new(formulation, &b).rates(side, th, w, ug);
                let (fx, fz) = reactions_per_mass(formulation, &b, side, th, w, ug);
                assert_eq!((r.fx, r.fz), (fx, fz));
                let p2 = b.frequency_parameter().powi(2);
                let g = b.gravity();
                let acc = |th: f64, ug: f64| {
                    formulation.angular_acceleration(p2, b.slenderness(), side, th, ug / g)
                };
                // θ⃛ by differentiating θ̈(θ(t), ü_g(t)) numerically.
                let e = 1e-6;
                let a0 = acc(th, ug);
                let a3 =
                    (acc(th + w * e, ug + jerk * e) - acc(th - w * e, ug - jerk * e)) / (2.0 * e);
                let at = |t: f64| {
                    let th_t = th + w * t + a0 * t * t / 2.0 + a3 * t * t * t / 6.0;
                    let w_t = w + a0 * t + a3 * t * t / 2.0;
                    reactions_per_mass(formulation, &b, side, th_t, w_t, ug + jerk * t)
                };
                let h = 1e-5;
                let (xp, zp) = at(h);
                let (xm, zm) = at(-h);
                let dfx = r.fx_rate[0] + r.fx_rate[1] * jerk;
                let dfz = r.fz_rate[0] + r.fz_rate[1] * jerk;
                let scale = 1.0 + jerk.abs();
                assert!(
                    ((xp - xm) / (2.0 * h) - dfx).abs() < 1e-6 * scale,
                    "{formulation:?}"
                );
                assert!(
                    ((zp - zm) / (2.0 * h) - dfz).abs() < 1e-6 * scale,
                    "{formulation:?}"
                );
                let (q, dq) = r.ratio(jerk);
                assert_eq!(q, fx / fz);
                let fd = (xp / zp - xm / zm) / (2.0 * h);
                assert!((fd - dq).abs() < 1e-6 * scale, "{formulation:?} {fd} {dq}");
            }
        }
    }

    #[test]
    fn vertical_reaction_rates_are_the_derivatives_along_the_motion() {
        // As above, both ground components linear in time: ü_g + j t, ü_v + k t.
        let b = block();
        let p2 = b.frequency_parameter().powi(2);
        let g = b.gravity();
        for formulation in [Formulation::Linear, Formulation::Nonlinear] {
            let model = ReactionModel::new(formulation, &b);
            for &(side, th, w, ug, uv, jerk, vjerk) in &[
                (-1.0, -0.1, -0.3, 5.0, 2.0, 40.0, -30.0),
                (1.0, 0.2, 0.4, -3.0, -4.0, -250.0, 120.0),
                (1.0, 0.05, -0.9, 2.0, 0.0, 0.0, 60.0),
            ] {
                let r = model.rates_vertical(side, th, w, ug, uv);
                let (fx, fz) = reactions_per_mass_vertical(formulation, &b, side, th, w, ug, uv);
                assert_eq!((r.fx, r.fz), (fx, fz));
                let acc = |th: f64, ug: f64, uv: f64| {
                    formulation.angular_acceleration_weighted(
                        p2,
                        b.slenderness(),
                        side,
                        th,
                        ug / g,
                        1.0 + uv / g,
                    )
                };
                let e = 1e-6;
                let a0 = acc(th, ug, uv);
                let a3 = (acc(th + w * e, ug + jerk * e, uv + vjerk * e)
                    - acc(th - w * e, ug - jerk * e, uv - vjerk * e))
                    / (2.0 * e);
                let at = |t: f64| {
                    let th_t = th + w * t + a0 * t * t / 2.0 + a3 * t * t * t / 6.0;
                    let w_t = w + a0 * t + a3 * t * t / 2.0;
                    reactions_per_mass_vertical(
                        formulation,
                        &b,
                        side,
                        th_t,
                        w_t,
                        ug + jerk * t,
                        uv + vjerk * t,
                    )
                };
                let h = 1e-5;
                let (xp, zp) = at(h);
                let (xm, zm) = at(-h);
                let [vx, vz, vq] = r.vertical_rate;
                let dfx = r.fx_rate[0] + r.fx_rate[1] * jerk + vx * vjerk;
                let dfz = r.fz_rate[0] + r.fz_rate[1] * jerk + vz * vjerk;
                let scale = 1.0 + jerk.abs() + vjerk.abs();
                let fd_x = (xp - xm) / (2.0 * h);
                let fd_z = (zp - zm) / (2.0 * h);
                assert!(
                    (fd_x - dfx).abs() < 1e-6 * scale,
                    "{formulation:?} {fd_x} {dfx}"
                );
                assert!(
                    (fd_z - dfz).abs() < 1e-6 * scale,
                    "{formulation:?} {fd_z} {dfz}"
                );
                let (q, dq) = r.ratio(jerk);
                assert_eq!(q, fx / fz);
                let fd = (xp / zp - xm / zm) / (2.0 * h);
                let dq = dq + vq * vjerk;
                assert!((fd - dq).abs() < 1e-6 * scale, "{formulation:?} {fd} {dq}");
            }
            // Without a vertical motion, the rates of the plain model.
            let plain = model.rates(1.0, 0.1, 0.2, 3.0);
            let mut v = model.rates_vertical(1.0, 0.1, 0.2, 3.0, 0.0);
            v.vertical_rate = [0.0; 3];
            assert_eq!(v, plain);
        }
    }

    #[test]
    fn vertical_reactions_are_those_of_a_block_under_another_gravity() {
        // A constant ü_v is gravity g + ü_v: the same α, p² scaled by (g + ü_v)/g.
        let b = block();
        let (g, av) = (b.gravity(), 2.5);
        let heavier = Block::new(
            b.slenderness(),
            b.frequency_parameter() * ((g + av) / g).sqrt(),
            Some(b.restitution()),
            b.friction(),
            Some(g + av),
        )
        .expect("valid");
        for formulation in [Formulation::Linear, Formulation::Nonlinear] {
            for &(side, th, w, ug) in &[(-1.0, -0.1, -0.3, 5.0), (1.0, 0.2, 0.4, -3.0)] {
                let (fx, fz) = reactions_per_mass_vertical(formulation, &b, side, th, w, ug, av);
                let (hx, hz) = reactions_per_mass(formulation, &heavier, side, th, w, ug);
                assert!((fx - hx).abs() < 1e-12 && (fz - hz).abs() < 1e-12);
                let plain = reactions_per_mass(formulation, &b, side, th, w, ug);
                let none = reactions_per_mass_vertical(formulation, &b, side, th, w, ug, 0.0);
                assert_eq!(plain, none);
            }
        }
    }

    #[test]
    fn demand_at_one_sine_initiation_is_tan_alpha() {
        let b = block();
        let ground = b.gravity() * b.slenderness().tan();
        let (fx, fz) = reactions_per_mass(Formulation::Nonlinear, &b, -1.0, 0.0, 0.0, ground);
        assert!((fx / fz - b.slenderness().tan()).abs() < 1e-15);
        assert!((initiation_demand(&b, ground) - b.slenderness().tan()).abs() < 1e-15);
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
            let ground = level * b.gravity() * b.slenderness();
            let r20 = eq20_ratio(&b, -1.0, 0.0, 0.0, ground);
            assert!((initiation_demand(&b, ground) - r20).abs() < 1e-14);
        }
    }

    #[test]
    fn one_cosine_demand_at_six_alpha_g_is_about_two_alpha() {
        // Paper Fig. 9 (bottom) and eq. 51: a_p = 6 α g needs μ ≈ 2 α to start rocking.
        let b = Block::new(0.25, 2.14, None, None, None).expect("valid");
        let d = initiation_demand(&b, 6.0 * 0.25 * b.gravity());
        assert!((d / 0.25 - 2.0).abs() < 0.1, "{}", d / 0.25);
    }
}
