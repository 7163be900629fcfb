//! Flight: a block off the floor, and its landing.
//!
//! Where the floor would have to pull (the normal force of rock or
//! slide-rock falls to 0, or g + ü_v ≤ 0 under a block lying flat) the
//! block leaves it. In the ground's frame its centre then moves under
//! gravity and the ground's acceleration alone and it spins freely:
//!
//! ```text
//! ẍ_c = −ü_g,   ÿ_c = −(g + ü_v),   θ̈ = 0
//! ```
//!
//! all in closed form from the ground's velocity and displacement
//! ([`Flight::pose`]). With θ positive about the corner at +b (as in
//! [`super::slide_rock`]), the corner s = ±1 is at
//! (x_c + s R sin(α − sθ), y_c − R cos(α − sθ)); the lower one is
//! s = sgn θ, and the block lands when its height, the *clearance*
//! y_c − R cos(α − |θ|), returns to 0 ([`Flight::end`]: sampled, then
//! bisected to adjacent floating-point times). It overturns in the air
//! where |θ| reaches π/2.
//!
//! **Landing** ([`land`]): the corner strikes the floor with no rebound
//! (Newton's restitution 0 at the corner). The impulse (P_t, P_n) that
//! stops it — its velocity after is 0 — is taken when |P_t| ≤ μ_s P_n: the
//! angular momentum about the corner is conserved, Housner's balance
//! (from rocking at θ = 0 it gives his η exactly). Otherwise the corner
//! slides through the impact with P_t = ±μ_k P_n, the sign the holding
//! impulse had (Shenton & Jones 1991), and only its normal velocity is
//! stopped. Either way no energy is gained (tested). A block landing flat
//! (it took off flat: θ = θ̇ = 0 throughout) stops its fall with both
//! corners, unless the friction impulse tips it onto its leading corner,
//! which the single-corner law then answers.

use super::Block;
use super::sliding::Kinematics;

/// Position and velocity of a block in the air, relative to the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Horizontal position of the centre, m (0 where it stood at t = 0).
    pub x: f64,
    /// Height of the centre above the floor, m.
    pub y: f64,
    /// ẋ_c, m/s.
    pub vx: f64,
    /// ẏ_c, m/s.
    pub vy: f64,
    /// θ, rad.
    pub theta: f64,
    /// θ̇, rad/s.
    pub omega: f64,
}

impl Pose {
    /// A block at `theta`, `theta_dot` on the corner `side` whose slip (the
    /// corner at `slip + side b`) moves at `slip_velocity`.
    pub fn on_corner(
        block: &Block,
        side: f64,
        theta: f64,
        theta_dot: f64,
        slip: f64,
        slip_velocity: f64,
    ) -> Pose {
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        let (s, c) = (side * alpha - theta).sin_cos();
        Pose {
            x: slip + side * r * alpha.sin() - r * s,
            y: r * c,
            vx: slip_velocity + r * c * theta_dot,
            vy: r * s * theta_dot,
            theta,
            omega: theta_dot,
        }
    }

    /// A block lying flat at slip `slip`, moving at `velocity`.
    pub fn flat(block: &Block, slip: f64, velocity: f64) -> Pose {
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        Pose {
            x: slip,
            y: r * alpha.cos(),
            vx: velocity,
            vy: 0.0,
            theta: 0.0,
            omega: 0.0,
        }
    }

    /// The lower corner's height above the floor, m.
    pub fn clearance(&self, block: &Block) -> f64 {
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        self.y - r * (alpha - self.theta.abs()).cos()
    }

    /// The slip of the lower corner s = sgn θ: its position less s b (the
    /// centre's position while θ = 0), m.
    pub fn slip(&self, block: &Block) -> f64 {
        self.corner_slip(block, if self.theta >= 0.0 { 1.0 } else { -1.0 })
    }

    /// The slip of the corner `side`: its position less `side` b, m.
    pub fn corner_slip(&self, block: &Block, side: f64) -> f64 {
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        self.x + side * r * ((alpha - side * self.theta).sin() - alpha.sin())
    }

    /// The rate of [`Pose::slip`]: the lower corner's horizontal velocity,
    /// m/s.
    pub fn slip_velocity(&self, block: &Block) -> f64 {
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        let s = if self.theta >= 0.0 { 1.0 } else { -1.0 };
        self.vx - r * (alpha - s * self.theta).cos() * self.omega
    }

    /// Kinetic energy per unit mass relative to the ground, J/kg.
    pub fn energy(&self, block: &Block) -> f64 {
        let r = block.half_diagonal();
        0.5 * (self.vx * self.vx + self.vy * self.vy + r * r / 3.0 * self.omega * self.omega)
    }
}

/// A flight from its take-off.
pub struct Flight<'a, G> {
    forcing: &'a G,
    block: Block,
    t0: f64,
    start: Pose,
    /// The ground's kinematics at t0.
    at0: ((f64, f64), (f64, f64)),
}

/// How a flight ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlightEnd {
    /// A corner (or the base) reached the floor at this time.
    Landing(f64),
    /// |θ| reached π/2 in the air at this time.
    Overturn(f64),
}

impl<'a, G: Kinematics> Flight<'a, G> {
    /// A flight from `start` at `t0`.
    pub fn new(forcing: &'a G, block: &Block, t0: f64, start: Pose) -> Self {
        Flight {
            forcing,
            block: *block,
            t0,
            start,
            at0: forcing.kinematics(t0),
        }
    }

    /// The largest |slip| over [t0, `t1`]: at the ends, where θ passes 0
    /// (the lower corner changes), and where the lower corner's horizontal
    /// velocity changes sign on a grid of 64 intervals (bisected to
    /// adjacent floating-point times).
    pub fn peak_slip(&self, t1: f64) -> f64 {
        let block = self.block;
        let slip = |t: f64| self.pose(t).slip(&block);
        let rate = |t: f64| self.pose(t).slip_velocity(&block);
        let mut points: Vec<f64> = (0..=64)
            .map(|k| self.t0 + (t1 - self.t0) * f64::from(k) / 64.0)
            .collect();
        let p = self.start;
        if p.omega != 0.0 {
            let level = self.t0 - p.theta / p.omega;
            if level > self.t0 && level < t1 {
                points.push(level);
                points.sort_by(f64::total_cmp);
            }
        }
        let mut peak = slip(self.t0).abs().max(slip(t1).abs());
        for w in points.windows(2) {
            let (mut a, mut b) = (w[0], w[1]);
            peak = peak.max(slip(b).abs());
            let (ra, rb) = (rate(a), rate(b));
            if ra * rb >= 0.0 {
                continue;
            }
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if m <= a || m >= b {
                    break;
                }
                if rate(m) * ra > 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            peak = peak.max(slip(a).abs()).max(slip(b).abs());
        }
        peak
    }

    /// The pose at `t` (closed form).
    pub fn pose(&self, t: f64) -> Pose {
        let tau = t - self.t0;
        let ((vg, ug), (vv, uv)) = self.forcing.kinematics(t);
        let ((vg0, ug0), (vv0, uv0)) = self.at0;
        let g = self.block.gravity();
        let p = self.start;
        Pose {
            x: p.x + p.vx * tau - (ug - ug0 - vg0 * tau),
            y: p.y + p.vy * tau - 0.5 * g * tau * tau - (uv - uv0 - vv0 * tau),
            vx: p.vx - (vg - vg0),
            vy: p.vy - g * tau - (vv - vv0),
            theta: p.theta + p.omega * tau,
            omega: p.omega,
        }
    }

    fn clearance(&self, t: f64) -> f64 {
        self.pose(t).clearance(&self.block)
    }

    /// The time |θ| reaches π/2, if it turns at all.
    fn overturn_time(&self) -> Option<f64> {
        let p = self.start;
        (p.omega != 0.0).then(|| {
            let target = p.omega.signum() * std::f64::consts::FRAC_PI_2;
            self.t0 + (target - p.theta) / p.omega
        })
    }

    /// The landing or overturning that ends the flight, looked for until
    /// `limit` (`None`: still in the air there). The clearance is sampled
    /// every `dt` (and at the forcing's breakpoints); its first return to
    /// 0 after it has been positive is bisected to adjacent floating-point
    /// times. A flight too short to show a positive clearance at any of 60
    /// halvings of the first interval lands where it took off.
    pub fn end(&self, dt: f64, limit: f64) -> Option<FlightEnd> {
        let over = self.overturn_time().filter(|&t| t > self.t0);
        let mut a = self.t0;
        let mut lifted = false;
        loop {
            if a >= limit {
                return None;
            }
            let mut b = (a + dt).min(self.forcing.breakpoint_after(a)).min(limit);
            if let Some(o) = over
                && o <= b
            {
                b = o;
            }
            let hb = self.clearance(b);
            if hb > 0.0 {
                if over == Some(b) {
                    return Some(FlightEnd::Overturn(b));
                }
                a = b;
                lifted = true;
                continue;
            }
            if !lifted {
                // Look for the positive clearance nearer the take-off.
                let mut hi = b;
                let mut found = None;
                for _ in 0..60 {
                    let m = self.t0 + 0.5 * (hi - self.t0);
                    if m <= self.t0 {
                        break;
                    }
                    if self.clearance(m) > 0.0 {
                        found = Some(m);
                        break;
                    }
                    hi = m;
                }
                match found {
                    Some(m) => {
                        a = m;
                        b = hi;
                    }
                    None => return Some(FlightEnd::Landing(self.t0)),
                }
            }
            // Bisect (a, b]: clearance(a) > 0 ≥ clearance(b).
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if m <= a || m >= b {
                    break;
                }
                if self.clearance(m) > 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            return Some(FlightEnd::Landing(b));
        }
    }
}

/// What a landing leaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Landed {
    /// On the corner `side`, rotating at `theta_dot`, the corner slipping at
    /// `slip_velocity` (0: it holds).
    Corner {
        /// The corner that landed (±1).
        side: f64,
        /// θ̇ after, rad/s.
        theta_dot: f64,
        /// The corner's slip velocity after, m/s.
        slip_velocity: f64,
        /// Whether the corner held during the impact.
        sticking: bool,
    },
    /// Flat on the floor, sliding at `velocity` (0: it sticks).
    Flat {
        /// ẋ after, m/s.
        velocity: f64,
    },
}

/// A landing and its energy per unit mass before and after (J/kg,
/// relative to the ground).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Landing {
    /// What it leaves.
    pub landed: Landed,
    /// Energy before and after.
    pub energy: (f64, f64),
}

/// The impulse per unit mass (P_t, P_n) stopping the corner `side` of a
/// block in `pose`, and the velocities (ẋ_c, ẏ_c, θ̇) after it (module
/// docs), or `None` where the corner is not moving into the floor.
fn corner_impact(block: &Block, mu_s: f64, mu_k: f64, side: f64, pose: &Pose) -> Option<Impulse> {
    let (alpha, r) = (block.slenderness(), block.half_diagonal());
    let (d, c) = (alpha - side * pose.theta).sin_cos();
    // The corner's velocity: along the floor and into it.
    let vt = pose.vx - r * c * pose.omega;
    let vn = pose.vy - side * r * d * pose.omega;
    if vn >= 0.0 {
        return None;
    }
    // With M⁻¹ = diag(1, 1, 3/R²) per unit mass, the corner's velocity
    // changes by A P, A = [[1 + 3c², 3scd], [3scd, 1 + 3d²]], det A = 4.
    let scd = side * c * d;
    let after = |pt: f64, pn: f64| {
        let w = pose.omega - 3.0 / r * (c * pt + side * d * pn);
        let (vx, vy) = (pose.vx + pt, pose.vy + pn);
        Impulse {
            vx,
            vy,
            omega: w,
            slip_velocity: vx - r * c * w,
            sticking: false,
        }
    };
    let pt = -((1.0 + 3.0 * d * d) * vt - 3.0 * scd * vn) / 4.0;
    let pn = -(-3.0 * scd * vt + (1.0 + 3.0 * c * c) * vn) / 4.0;
    if pn > 0.0 && pt.abs() <= mu_s * pn {
        return Some(Impulse {
            slip_velocity: 0.0,
            sticking: true,
            ..after(pt, pn)
        });
    }
    let kappa = if pt >= 0.0 { mu_k } else { -mu_k };
    let denominator = 1.0 + 3.0 * d * d + 3.0 * scd * kappa;
    if denominator <= 0.0 {
        // No sliding impact is consistent (Painlevé): the corner holds.
        return Some(Impulse {
            slip_velocity: 0.0,
            sticking: true,
            ..after(pt, pn.max(0.0))
        });
    }
    let pn = -vn / denominator;
    Some(after(kappa * pn, pn))
}

/// A corner sliding on the floor that must stop at once (a slide-rock
/// jamming where no sliding motion stays consistent, Painlevé): the
/// impulse that stops the corner (its normal velocity, if into the floor,
/// too), and θ̇ after it — `None` where the floor would have to pull
/// (P_n < 0: the block leaves it instead).
pub fn jam(block: &Block, side: f64, pose: &Pose) -> Option<f64> {
    let (alpha, r) = (block.slenderness(), block.half_diagonal());
    let (d, c) = (alpha - side * pose.theta).sin_cos();
    let vt = pose.vx - r * c * pose.omega;
    let vn = (pose.vy - side * r * d * pose.omega).min(0.0);
    let scd = side * c * d;
    let pt = -((1.0 + 3.0 * d * d) * vt - 3.0 * scd * vn) / 4.0;
    let pn = -(-3.0 * scd * vt + (1.0 + 3.0 * c * c) * vn) / 4.0;
    (pn >= 0.0).then(|| pose.omega - 3.0 / r * (c * pt + side * d * pn))
}

struct Impulse {
    vx: f64,
    vy: f64,
    omega: f64,
    slip_velocity: f64,
    sticking: bool,
}

/// The landing of a block in `pose` (its clearance 0) on a floor with
/// friction (μ_s, μ_k) (module docs).
pub fn land(block: &Block, mu_s: f64, mu_k: f64, pose: &Pose) -> Landing {
    let before = pose.energy(block);
    let energy_of = |vx: f64, vy: f64, omega: f64| Pose {
        vx,
        vy,
        omega,
        ..*pose
    };
    let corner = |side: f64| {
        corner_impact(block, mu_s, mu_k, side, pose).map(|i| Landing {
            landed: Landed::Corner {
                side,
                theta_dot: i.omega,
                slip_velocity: i.slip_velocity,
                sticking: i.sticking,
            },
            energy: (before, energy_of(i.vx, i.vy, i.omega).energy(block)),
        })
    };
    if pose.theta != 0.0 {
        let side = pose.theta.signum();
        return corner(side).unwrap_or_else(|| {
            // Touching without moving into the floor (a flight of no
            // length): no impulse, the corner on the floor as it moves.
            let (alpha, r) = (block.slenderness(), block.half_diagonal());
            let slip_velocity = pose.vx - r * (alpha - side * pose.theta).cos() * pose.omega;
            Landing {
                landed: Landed::Corner {
                    side,
                    theta_dot: pose.omega,
                    slip_velocity,
                    sticking: slip_velocity == 0.0,
                },
                energy: (before, before),
            }
        });
    } else if pose.omega != 0.0 {
        // Level, turning: the corner moving down faster lands.
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        let side = if -r * alpha.sin() * pose.omega <= r * alpha.sin() * pose.omega {
            1.0
        } else {
            -1.0
        };
        if let Some(l) = corner(side) {
            return l;
        }
    } else if pose.vx != 0.0 {
        // Flat, moving along: the friction impulse may tip it onto its
        // leading corner.
        let side = pose.vx.signum();
        if let Some(l) = corner(side)
            && let Landed::Corner { theta_dot, .. } = l.landed
            && theta_dot * side > 0.0
        {
            return l;
        }
    }
    land_flat(block, mu_s, mu_k, pose)
}

/// The landing of a block in `pose` on both corners at once: its fall and
/// its rotation stopped, its slide slowed by the friction impulse.
pub fn land_flat(block: &Block, mu_s: f64, mu_k: f64, pose: &Pose) -> Landing {
    let before = pose.energy(block);
    let pn = (-pose.vy).max(0.0);
    let velocity = if pose.vx.abs() <= mu_s * pn {
        0.0
    } else {
        pose.vx - pose.vx.signum() * mu_k * pn
    };
    let after = Pose {
        vx: velocity,
        vy: 0.0,
        omega: 0.0,
        ..*pose
    };
    Landing {
        landed: Landed::Flat { velocity },
        energy: (before, after.energy(block)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::slide_rock;
    use crate::dynamics::{Pulse, PulseShape};

    fn block(alpha: f64) -> Block {
        Block::new(alpha, 2.0, None, None, None).expect("valid")
    }

    #[test]
    fn a_pose_on_a_corner_is_on_the_floor_with_its_pivot_at_the_slip() {
        for alpha in [0.1, 0.25, 0.6] {
            let b = block(alpha);
            let half_width = b.half_diagonal() * alpha.sin();
            for side in [1.0, -1.0] {
                for theta in [0.0, 0.3 * alpha, 2.0 * alpha] {
                    let p = Pose::on_corner(&b, side, side * theta, 0.7, 0.4, -0.2);
                    assert!(p.clearance(&b).abs() < 1e-15, "{alpha} {side} {theta}");
                    // The corner's position less s b.
                    assert!((p.slip(&b) - 0.4).abs() < 1e-15);
                    let pivot = p.x + side * b.half_diagonal() * (alpha - side * p.theta).sin();
                    assert!((pivot - (0.4 + side * half_width)).abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn landing_from_rocking_at_theta_0_is_the_rocking_impact() {
        // The same impact law: a block rocking on `side` strikes with the
        // other corner at θ = 0. Holding, Housner's η; sliding, Shenton &
        // Jones; the two computations agree to rounding.
        for alpha in [0.1, 0.25, 0.45] {
            let b = block(alpha);
            for mu in [0.05, 0.2, 0.5, 2.0] {
                for side in [1.0, -1.0] {
                    for w in [0.01, 0.5, 3.0] {
                        for slip in [-2.0, -0.3, 0.0, 0.3, 2.0] {
                            let theta_dot = -side * w;
                            let rocking =
                                slide_rock::impact(&b, mu, 0.8 * mu, side, theta_dot, slip);
                            let pose = Pose::on_corner(&b, side, 0.0, theta_dot, 0.0, slip);
                            let landing =
                                corner_impact(&b, mu, 0.8 * mu, -side, &pose).expect("strikes");
                            let scale = w.max(slip.abs()).max(1.0);
                            assert_eq!(
                                landing.sticking, rocking.sticking,
                                "{alpha} {mu} {side} {w} {slip}"
                            );
                            assert!((landing.omega - rocking.theta_dot).abs() < 1e-13 * scale);
                            assert!(
                                (landing.slip_velocity - rocking.slip_velocity).abs()
                                    < 1e-13 * scale,
                                "{} vs {}",
                                landing.slip_velocity,
                                rocking.slip_velocity
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn no_landing_gains_energy_and_a_holding_corner_stops() {
        let mut sliding = 0;
        for alpha in [0.1, 0.25, 0.6] {
            let b = block(alpha);
            let r = b.half_diagonal();
            for mu in [0.05, 0.3, 1.0] {
                for theta in [-1.2, -0.2, -0.01, 0.0, 0.01, 0.2, 1.2] {
                    for omega in [-3.0, -0.4, 0.0, 0.4, 3.0] {
                        for (vx, vy) in [(0.0, -0.5), (0.8, -0.1), (-1.5, -1.0), (0.3, -3.0)] {
                            let mut pose = Pose {
                                x: 0.0,
                                y: 0.0,
                                vx,
                                vy,
                                theta: theta * alpha,
                                omega,
                            };
                            pose.y = r * (alpha - pose.theta.abs()).cos();
                            let l = land(&b, mu, 0.8 * mu, &pose);
                            let (e0, e1) = l.energy;
                            assert!(
                                e1 <= e0 * (1.0 + 1e-12),
                                "{alpha} {mu} {pose:?}: {e0} → {e1}"
                            );
                            match l.landed {
                                Landed::Corner {
                                    side,
                                    theta_dot,
                                    slip_velocity,
                                    sticking,
                                } => {
                                    if sticking {
                                        assert_eq!(slip_velocity, 0.0);
                                    } else {
                                        sliding += 1;
                                    }
                                    // The corner no longer moves into the floor.
                                    let (d, _) = (alpha - side * pose.theta).sin_cos();
                                    let after = Pose::on_corner(
                                        &b,
                                        side,
                                        pose.theta,
                                        theta_dot,
                                        0.0,
                                        slip_velocity,
                                    );
                                    let vn = after.vy - side * r * d * theta_dot;
                                    assert!(vn.abs() < 1e-12, "{vn}");
                                }
                                Landed::Flat { velocity } => {
                                    assert!(velocity.abs() <= vx.abs());
                                    assert!(velocity * vx >= 0.0);
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(sliding > 0);
    }

    #[test]
    fn a_tilted_block_touching_without_falling_keeps_its_motion_on_its_corner() {
        // A flight of no length: the lower corner at the floor, not moving
        // into it. No impulse, and the block stays tilted on that corner.
        let b = block(0.25);
        for side in [1.0, -1.0] {
            let mut pose = Pose::on_corner(&b, side, side * 0.1, side * 0.5, 0.0, 0.3);
            pose.vy += 0.01;
            let l = land(&b, 0.5, 0.5, &pose);
            let Landed::Corner {
                side: s,
                theta_dot,
                slip_velocity,
                sticking,
            } = l.landed
            else {
                panic!("stays on its corner: {l:?}")
            };
            assert_eq!((s, theta_dot, sticking), (side, side * 0.5, false));
            assert!((slip_velocity - 0.3).abs() < 1e-12);
            assert_eq!(l.energy.0, l.energy.1);
        }
    }

    #[test]
    fn a_flat_flight_under_a_vertical_fall_lands_where_its_parabola_says() {
        // Under a rectangular vertical acceleration −a (a > g) for t_d the
        // block rises with (a − g), then falls with g: it lands at
        // t_d + τ₁ + √(τ₁² + 2 h₁/g), τ₁ = v₁/g, (v₁, h₁) its rise at t_d.
        // (The horizontal pulse, 10⁻⁹ m/s², moves it by 10⁻¹¹ m.)
        use crate::dynamics::PulsePair;
        let b = block(0.25);
        let g = b.gravity();
        let w = std::f64::consts::PI / 0.2;
        let a = 1.5 * g;
        let pair = PulsePair::new(
            Pulse::new(PulseShape::Rectangular, 1e-9, w).expect("valid"),
            Pulse::new(PulseShape::Rectangular, -a, w).expect("valid"),
            0.0,
        );
        let t_d = 0.2;
        let f = Flight::new(&pair, &b, 0.0, Pose::flat(&b, 0.0, 0.0));
        let Some(FlightEnd::Landing(t)) = f.end(1e-3, 10.0) else {
            panic!("lands")
        };
        let rise = a - g;
        let (v1, h1) = (rise * t_d, 0.5 * rise * t_d * t_d);
        let tau = v1 / g;
        let expected = t_d + tau + (tau * tau + 2.0 * h1 / g).sqrt();
        assert!((t - expected).abs() < 1e-12, "{t} vs {expected}");
        // It lands moving down as fast as the parabola says, and sticks.
        let pose = f.pose(t);
        let vy = v1 - g * (t - t_d);
        assert!((pose.vy - vy).abs() < 1e-12, "{} vs {vy}", pose.vy);
        assert!(pose.x.abs() < 1e-9 && pose.theta == 0.0);
        let l = land(&b, 0.5, 0.5, &pose);
        assert_eq!(l.landed, Landed::Flat { velocity: 0.0 });
        assert!(l.energy.1 < 1e-18);
    }
}
