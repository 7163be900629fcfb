//! A block rotating about a corner that slides on a Coulomb floor (Shenton
//! 1996; Zhang & Makris's eqs. 2–3 and 16–19 with the friction force at its
//! limit), and the impact of a corner on the floor with friction (Shenton &
//! Jones 1991).
//!
//! With θ the rotation (positive about the corner at +b), s = sgn θ its
//! pivot, ϕ = s α − θ, S = sin ϕ, C = cos ϕ, g_z = g + ü_v, the pivot sliding
//! in direction σ = sgn ẋ_p (relative to the ground) and κ = σ μ_k: the floor
//! pushes the block by f_z = N up and f_x = −κ N along the ground, so
//!
//! ```text
//! m ẍ_c = −κ N − m ü_g,       x_c = x_p − R S
//! m ÿ_c = N − m g_z,          y_c = R C
//! I_c θ̈ = −R N (S − κ C),     I_c = m R²/3
//! ```
//!
//! whence, the corner staying on the floor,
//!
//! ```text
//! θ̈ = −(S − κ C)(g_z − R C θ̇²) / (R (1/3 + S (S − κ C)))
//! N/m = g_z + R (S θ̈ − C θ̇²)
//! ```
//!
//! (κ = 0: the frictionless rocking block; a pivot that holds instead gives
//! eq. 12). The horizontal ground acceleration enters θ̈ only through σ: ẋ_c
//! integrates in closed form, ẋ_c(t) − ẋ_c(t₀) = −Δv_g − κ (Δẏ_c + g Δt +
//! Δv_v), and the pivot's slip follows from θ and θ̇ ([`SlideRockLeg`]). Where
//! 1/3 + S (S − κ C) ≤ 0 (very large μ on a squat block: Painlevé's
//! paradox) no sliding motion is consistent and the pivot holds.

use super::Block;
use super::forcing::Forcing;
use super::integrator::{Rhs, State};
use super::sliding::Kinematics;

/// The angular acceleration of a block rotating about a sliding corner
/// (module docs), or `None` where the motion is inconsistent (Painlevé).
#[inline]
pub fn angular_acceleration(
    alpha: f64,
    r: f64,
    side: f64,
    kappa: f64,
    g_z: f64,
    theta: f64,
    theta_dot: f64,
) -> Option<f64> {
    angular_acceleration_at(phase(alpha, side, theta), r, kappa, g_z, theta_dot)
}

/// (S, C) = (sin ϕ, cos ϕ), ϕ = s α − θ: the one sine and cosine every
/// quantity of a slide-rocking state at θ is written with (module docs).
#[inline]
pub fn phase(alpha: f64, side: f64, theta: f64) -> (f64, f64) {
    (side * alpha - theta).sin_cos()
}

/// [`angular_acceleration`] from (S, C) = [`phase`].
#[inline]
pub fn angular_acceleration_at(
    (s, c): (f64, f64),
    r: f64,
    kappa: f64,
    g_z: f64,
    theta_dot: f64,
) -> Option<f64> {
    let lever = s - kappa * c;
    let inertia = 1.0 / 3.0 + s * lever;
    (inertia > 0.0).then(|| -lever * (g_z - r * c * theta_dot * theta_dot) / (r * inertia))
}

/// The reduced inertia 1/3 + S (S − κ C) of slide-rocking on `side` at θ:
/// θ̈ divides by it, and where it reaches 0 no sliding motion is
/// consistent (Painlevé).
#[inline]
pub fn inertia(alpha: f64, side: f64, kappa: f64, theta: f64) -> f64 {
    inertia_at(phase(alpha, side, theta), kappa)
}

/// [`inertia`] from (S, C) = [`phase`].
#[inline]
pub fn inertia_at((s, c): (f64, f64), kappa: f64) -> f64 {
    1.0 / 3.0 + s * (s - kappa * c)
}

/// Reduced inertia ([`inertia`]) at which a slide-rock jams: its pivot
/// stops at once, the sliding motion about to become inconsistent.
pub const JAM_INERTIA: f64 = 1e-3;

/// N/m, m/s², at a slide-rocking state with angular acceleration `acc`.
#[inline]
pub fn normal_per_mass(
    alpha: f64,
    r: f64,
    side: f64,
    g_z: f64,
    theta: f64,
    y: State,
    acc: f64,
) -> f64 {
    normal_per_mass_at(phase(alpha, side, theta), r, g_z, y, acc)
}

/// [`normal_per_mass`] from (S, C) = [`phase`] at θ = `y[0]`.
#[inline]
pub fn normal_per_mass_at((s, c): (f64, f64), r: f64, g_z: f64, y: State, acc: f64) -> f64 {
    g_z + r * (s * acc - c * y[1] * y[1])
}

/// The right-hand side of slide-rocking on `side` with κ = σ μ_k.
pub struct SlideRockRhs<'a, G> {
    /// The ground motion (its vertical component only enters).
    pub forcing: &'a G,
    /// Whether the ground motion still acts.
    pub forced: bool,
    /// α.
    pub alpha: f64,
    /// R, m.
    pub r: f64,
    /// g, m/s².
    pub g: f64,
    /// s.
    pub side: f64,
    /// κ = σ μ_k.
    pub kappa: f64,
}

impl<G: Forcing> SlideRockRhs<'_, G> {
    /// g + ü_v at t.
    #[inline]
    pub fn g_z(&self, t: f64) -> f64 {
        if self.forced && G::VERTICAL {
            self.g + self.forcing.vertical_acceleration(t)
        } else {
            self.g
        }
    }
}

impl<G: Forcing> Rhs for SlideRockRhs<'_, G> {
    #[inline]
    fn eval(&self, t: f64, y: State) -> State {
        let acc = angular_acceleration(
            self.alpha,
            self.r,
            self.side,
            self.kappa,
            self.g_z(t),
            y[0],
            y[1],
        )
        // Outside the consistent region the leg ends at once (its start is
        // checked); a finite value keeps the stepper's arithmetic finite.
        .unwrap_or(0.0);
        [y[1], acc]
    }
}

/// The horizontal velocity of the centre of mass relative to the ground at
/// a state: the pivot's slip velocity plus the rotation's share.
#[inline]
pub fn centre_velocity(alpha: f64, r: f64, side: f64, y: State, slip_velocity: f64) -> (f64, f64) {
    let (s, c) = (side * alpha - y[0]).sin_cos();
    (slip_velocity + r * c * y[1], r * s * y[1])
}

/// A slide-rock leg's closed forms: the pivot's slip velocity and
/// displacement at (t, θ, θ̇), from the state it started at.
pub struct SlideRockLeg<'a, G> {
    /// The ground motion.
    pub forcing: &'a G,
    /// α, R, g.
    pub alpha: f64,
    /// R, m.
    pub r: f64,
    /// g, m/s².
    pub g: f64,
    /// s.
    pub side: f64,
    /// κ = σ μ_k.
    pub kappa: f64,
    /// t₀, s.
    pub t0: f64,
    /// (ẋ_c, ẏ_c) at t₀, m/s.
    pub centre_velocity0: (f64, f64),
    /// (x_c, y_c) at t₀ relative to the pivot's start, m.
    pub centre0: (f64, f64),
    /// The ground's kinematics at t₀.
    pub ground0: ((f64, f64), (f64, f64)),
    /// The pivot's slip at t₀, m.
    pub slip0: f64,
}

impl<G: Kinematics> SlideRockLeg<'_, G> {
    /// A leg starting at `t0` in state `y0` with the pivot slipping at
    /// `slip_velocity` and displaced by `slip` (m).
    #[allow(clippy::too_many_arguments)]
    pub fn new<'a>(
        forcing: &'a G,
        block: &Block,
        side: f64,
        kappa: f64,
        t0: f64,
        y0: State,
        slip: f64,
        slip_velocity: f64,
    ) -> SlideRockLeg<'a, G> {
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        let (s, c) = (side * alpha - y0[0]).sin_cos();
        SlideRockLeg {
            forcing,
            alpha,
            r,
            g: block.gravity(),
            side,
            kappa,
            t0,
            centre_velocity0: centre_velocity(alpha, r, side, y0, slip_velocity),
            centre0: (-r * s, r * c),
            ground0: forcing.kinematics(t0),
            slip0: slip,
        }
    }

    /// (slip, slip velocity) of the pivot at `t` in state `y`.
    pub fn slip(&self, t: f64, y: State) -> (f64, f64) {
        self.slip_at(t, y, phase(self.alpha, self.side, y[0]))
    }

    /// [`SlideRockLeg::slip`] with (S, C) = [`phase`] at θ = `y[0]`.
    #[inline]
    pub fn slip_at(&self, t: f64, y: State, (s, c): (f64, f64)) -> (f64, f64) {
        let tau = t - self.t0;
        let ((vg, ug), (vv, uv)) = self.forcing.kinematics(t);
        let ((vg0, ug0), (vv0, uv0)) = self.ground0;
        let (xd0, yd0) = self.centre_velocity0;
        let (x0, y0c) = self.centre0;
        let yd = self.r * s * y[1];
        let yc = self.r * c;
        let xd = xd0 - (vg - vg0) - self.kappa * (yd - yd0 + self.g * tau + (vv - vv0));
        let xc = x0 + xd0 * tau
            - (ug - ug0 - vg0 * tau)
            - self.kappa
                * ((yc - y0c - yd0 * tau) + 0.5 * self.g * tau * tau + (uv - uv0 - vv0 * tau));
        // x_p = x_c + R S, the pivot at 0 at t₀.
        (self.slip0 + xc + self.r * s, xd - self.r * c * y[1])
    }
}

/// What a corner's impact on the floor leaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactOutcome {
    /// θ̇ after, rad/s (about the landing corner).
    pub theta_dot: f64,
    /// The landing corner's slip velocity after, m/s (0: it holds).
    pub slip_velocity: f64,
    /// Whether the landing corner held during the impact.
    pub sticking: bool,
    /// Kinetic energy per unit mass before and after (relative to the
    /// ground), J/kg.
    pub energy: (f64, f64),
}

/// The impact at θ = 0 of a block rotating on `side` with θ̇ = `theta_dot`
/// (towards 0) while its pivot slips at `slip_velocity`: the other corner
/// lands, with no rebound (Newton's restitution 0 at the corner), and
/// either holds — the angular momentum about it conserved, the rotational
/// part scaled by the block's η (Housner's unless given: θ̇⁺ = η θ̇⁻ +
/// (m h/I_O) ẋ_p⁻) — when the tangential impulse that needs is within μ_s
/// times the normal one, or slides with the tangential impulse at μ_k times
/// the normal one (Shenton & Jones 1991). Where no sliding impact is
/// consistent — the friction impulse's moment would drive the landing
/// corner into the floor (a non-positive normal impulse; with η → 0 and μ
/// below cot α) — the corner holds, as at a landing.
pub fn impact(
    block: &Block,
    mu_s: f64,
    mu_k: f64,
    side: f64,
    theta_dot: f64,
    slip_velocity: f64,
) -> ImpactOutcome {
    let alpha = block.slenderness();
    let r = block.half_diagonal();
    let (b, h) = (r * alpha.sin(), r * alpha.cos());
    let i_c = r * r / 3.0;
    let i_o = 4.0 * r * r / 3.0;
    let (xd, yd) = (slip_velocity + h * theta_dot, side * b * theta_dot);
    let energy = |xd: f64, yd: f64, w: f64| 0.5 * (xd * xd + yd * yd + i_c * w * w);
    let before = energy(xd, yd, theta_dot);
    // Holding: the landing corner (−s b, −h from the centre) stops.
    let w = block.restitution() * theta_dot + h * slip_velocity / i_o;
    let (pt, pn) = (h * w - xd, -side * b * w - yd);
    let holds = ImpactOutcome {
        theta_dot: w,
        slip_velocity: 0.0,
        sticking: true,
        energy: (before, energy(h * w, -side * b * w, w)),
    };
    if pt.abs() <= mu_s * pn {
        return holds;
    }
    // Sliding: P_t = κ P_n, κ = ±μ_k as the holding impulse pointed.
    let kappa = pt.signum() * mu_k;
    let denominator = 1.0 + (b * b - side * b * h * kappa) / i_c;
    let pn = -(yd + side * b * theta_dot) / denominator;
    if !(denominator > 0.0 && pn > 0.0) {
        // No sliding impact is consistent (the friction impulse would
        // drive the corner into the floor: Painlevé's paradox at an
        // impact, e.g. η → 0 with μ below cot α): the corner holds.
        return holds;
    }
    let w = theta_dot + (side * b - h * kappa) * pn / i_c;
    let (xa, ya) = (xd + kappa * pn, yd + pn);
    ImpactOutcome {
        theta_dot: w,
        slip_velocity: xa - h * w,
        sticking: false,
        energy: (before, energy(xa, ya, w)),
    }
}
