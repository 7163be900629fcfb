//! The Mavroeidis–Papageorgiou (2003) near-fault pulse, in dimensionless time.
//!
//! With f_p the pulse frequency, the ground velocity is
//! v(τ) = (V/2)[1 + cos(2π f_p τ/γ)] cos(2π f_p τ + ν) for |τ| ≤ γ/(2f_p) and
//! zero outside: a harmonic of frequency f_p and phase ν under a cosine bell
//! γ/f_p long (γ > 1 carrier cycles). Time here runs from the start of the
//! support, x = f_p t = f_p τ + γ/2 ∈ [0, γ], and V = 1; with θ = πx/γ (the
//! half-angle of the bell, 0 to π) and ψ = 2πx + ν − πγ (the carrier phase,
//! ψ = 2π f_p τ + ν):
//!
//! - velocity    v(x) = sin²θ cos ψ,
//! - acceleration v′(x) = 2π sin θ (cos θ cos ψ/γ − sin θ sin ψ),
//! - jerk        v″(x) = 2π² [(cos 2θ/γ² − 2 sin²θ) cos ψ − (2/γ) sin 2θ sin ψ],
//! - displacement ∫₀ˣ v = Σ c_k (sin(ω_k x + ψ₀) − sin ψ₀)/ω_k, from
//!   v = ½ cos ψ − ¼ cos(ψ + 2θ) − ¼ cos(ψ − 2θ): (c_k, ω_k) = (½, 2π),
//!   (−¼, 2π(1 + 1/γ)), (−¼, 2π(1 − 1/γ)), ψ₀ = ν − πγ.
//!
//! In time t = x/f_p these are scaled by V, V f_p, V f_p², V/f_p. Written
//! from the start of the support (θ = πx/γ, not π/2 − πx/γ), the bell and
//! so the acceleration keep full relative precision near t = 0, where a
//! strong pulse first exceeds the rocking threshold.
//!
//! # Where the extrema are
//! Each derivative is Re(e^{iψ} w(θ)) = |w| cos(ψ + arg w) with a complex
//! w that runs once along an ellipse:
//! - acceleration: w ∝ cos θ/γ + i sin θ, an ellipse about the origin for
//!   θ ∈ (0, π) (and sin θ = 0 at the ends, where v′ = 0), arg w rising
//!   from 0 to π;
//! - jerk: w ∝ (1 + 1/γ²) cos 2θ − 1 + (2i/γ) sin 2θ, an ellipse centred at
//!   −1 with real semi-axis 1 + 1/γ² > 1, so it winds once around the
//!   origin, never through it: arg w rises from 0 to 2π.
//!
//! A convex curve around the origin is seen from it at a strictly rising
//! angle, so the phase Φ = ψ + arg w rises strictly (ψ rises at 2π), and the
//! zeros of the derivative are exactly the points Φ = π/2 + kπ: each one
//! simple, one per crossing, found by a root search on a monotone function
//! that cannot miss one. So ü_g has at most ⌈2(γ + 1)⌉ extrema inside the
//! support (42 for γ = 20) and the velocity ⌈2γ + 1⌉; the displacement's
//! extrema are the zeros of cos ψ, in closed form.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::events::brent;

/// Largest γ accepted: 20 carrier cycles under the bell. The records Mavroeidis
/// & Papageorgiou (2003) fitted have γ of about 1.5 to 3; the bound keeps the
/// fixed-size list of extrema ([`MAX_EXTREMA`]) small.
pub const GAMMA_MAX: f64 = 20.0;

/// Most extrema of ü_g inside the support, ⌈2(γ + 1)⌉ at γ = [`GAMMA_MAX`].
pub const MAX_EXTREMA: usize = 2 * (GAMMA_MAX as usize) + 2;

/// The pulse's shape: γ, ν and the carrier phase at the start of the support.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MavroeidisPapageorgiou {
    /// γ, carrier cycles under the bell (1 < γ ≤ [`GAMMA_MAX`]).
    pub gamma: f64,
    /// ν, phase of the carrier at the bell's centre, rad.
    pub nu: f64,
    /// π/γ: θ per unit x.
    envelope_rate: f64,
    /// ψ₀ = ν − πγ: the carrier phase at x = 0.
    psi0: f64,
}

/// ν reduced to (−π, π]: values already there are kept exactly, so that a
/// normalised spec validates to itself.
pub fn reduce_phase(nu: f64) -> f64 {
    if nu > -PI && nu <= PI {
        return nu;
    }
    let r = (nu + PI).rem_euclid(TAU) - PI;
    if r <= -PI { r + TAU } else { r }
}

impl MavroeidisPapageorgiou {
    /// The shape of `gamma` and `nu`; `None` unless 1 < γ ≤ [`GAMMA_MAX`] and ν
    /// is finite (ν is taken modulo 2π, to (−π, π]).
    pub fn new(gamma: f64, nu: f64) -> Option<Self> {
        if !(gamma > 1.0 && gamma <= GAMMA_MAX && nu.is_finite()) {
            return None;
        }
        let nu = reduce_phase(nu);
        Some(MavroeidisPapageorgiou {
            gamma,
            nu,
            envelope_rate: PI / gamma,
            psi0: nu - PI * gamma,
        })
    }

    /// Length of the support in x = f_p t: γ.
    pub fn span(&self) -> f64 {
        self.gamma
    }

    /// (sin θ, cos θ, sin ψ, cos ψ) at x.
    #[inline]
    fn angles(&self, x: f64) -> (f64, f64, f64, f64) {
        let (st, ct) = (self.envelope_rate * x).sin_cos();
        let (sp, cp) = (TAU * x + self.psi0).sin_cos();
        (st, ct, sp, cp)
    }

    /// Velocity v(x) = sin²θ cos ψ (V = 1).
    #[inline]
    pub fn velocity(&self, x: f64) -> f64 {
        let (st, _, _, cp) = self.angles(x);
        st * st * cp
    }

    /// Acceleration dv/dx = 2π sin θ (cos θ cos ψ/γ − sin θ sin ψ).
    #[inline]
    pub fn acceleration(&self, x: f64) -> f64 {
        let (st, ct, sp, cp) = self.angles(x);
        TAU * st * (ct * cp / self.gamma - st * sp)
    }

    /// Jerk d²v/dx² = 2π² [(cos 2θ/γ² − 2 sin²θ) cos ψ − (2/γ) sin 2θ sin ψ].
    pub fn jerk(&self, x: f64) -> f64 {
        let (st, ct, sp, cp) = self.angles(x);
        let g = self.gamma;
        let cos2 = ct * ct - st * st;
        let sin2 = 2.0 * st * ct;
        2.0 * PI * PI * ((cos2 / (g * g) - 2.0 * st * st) * cp - 2.0 / g * sin2 * sp)
    }

    /// Displacement ∫₀ˣ v (V = 1), from the three harmonics of v.
    pub fn displacement(&self, x: f64) -> f64 {
        let g = self.gamma;
        [
            (0.5, TAU),
            (-0.25, TAU * (1.0 + 1.0 / g)),
            (-0.25, TAU * (1.0 - 1.0 / g)),
        ]
        .iter()
        .map(|&(c, w)| c * ((w * x + self.psi0).sin() - self.psi0.sin()) / w)
        .sum()
    }

    /// arg of the jerk's w(θ), unwrapped to [0, 2π] over the support.
    fn jerk_angle(&self, x: f64) -> f64 {
        let theta = self.envelope_rate * x;
        let (s2, c2) = (2.0 * theta).sin_cos();
        let g = self.gamma;
        let a = (2.0 / g * s2).atan2((1.0 + 1.0 / (g * g)) * c2 - 1.0);
        // Past θ = π/2 the ellipse is below the real axis: arg in (π, 2π].
        if a < 0.0 || (theta > FRAC_PI_2 && a == 0.0) {
            a + TAU
        } else {
            a
        }
    }

    /// arg of the acceleration's w(θ) = cos θ/γ + i sin θ, in [0, π].
    fn acceleration_angle(&self, x: f64) -> f64 {
        let (st, ct) = (self.envelope_rate * x).sin_cos();
        st.max(0.0).atan2(ct / self.gamma)
    }

    /// The x in (0, γ) where `phase` (strictly rising from `phase(0)` by
    /// `rise` over the support) crosses π/2 + kπ, in increasing order, into
    /// `out`; how many (at most `out.len()`: further ones are dropped, which
    /// the bound on γ rules out).
    fn crossings(&self, phase: impl Fn(f64) -> f64, rise: f64, out: &mut [f64]) -> usize {
        let start = phase(0.0);
        let end = start + rise;
        let mut k = ((start - FRAC_PI_2) / PI).floor() + 1.0;
        let (mut lo, mut count) = (0.0, 0);
        while count < out.len() {
            let target = FRAC_PI_2 + k * PI;
            if target >= end {
                break;
            }
            k += 1.0;
            if target <= start {
                continue;
            }
            let f = |x: f64| phase(x) - target;
            let (fa, fb) = (f(lo), f(self.gamma));
            if !(fa < 0.0 && fb > 0.0) {
                // Rounding at an end of the support: no interior crossing.
                continue;
            }
            let x = brent(f, lo, self.gamma, fa, fb, 0.0);
            if x > 0.0 && x < self.gamma {
                out[count] = x;
                count += 1;
                lo = x;
            }
        }
        count
    }

    /// The extrema of the acceleration inside (0, γ): the zeros of the jerk,
    /// each located on its phase crossing and polished on the jerk itself.
    pub fn acceleration_extrema(&self) -> ([f64; MAX_EXTREMA], usize) {
        let mut out = [0.0; MAX_EXTREMA];
        let n = self.crossings(
            |x| TAU * x + self.psi0 + self.jerk_angle(x),
            TAU * (self.gamma + 1.0),
            &mut out,
        );
        for x in &mut out[..n] {
            *x = self.polish(|y| self.jerk(y), *x);
        }
        (out, n)
    }

    /// The extrema of the velocity inside (0, γ): the zeros of the acceleration.
    fn velocity_extrema(&self) -> ([f64; MAX_EXTREMA], usize) {
        let mut out = [0.0; MAX_EXTREMA];
        let n = self.crossings(
            |x| TAU * x + self.psi0 + self.acceleration_angle(x),
            TAU * self.gamma + PI,
            &mut out,
        );
        for x in &mut out[..n] {
            *x = self.polish(|y| self.acceleration(y), *x);
        }
        (out, n)
    }

    /// A zero of `f` found from its phase crossing `x`, refined on `f` itself
    /// when a sign change brackets it within a few ulps of phase.
    fn polish(&self, f: impl Fn(f64) -> f64, x: f64) -> f64 {
        let h = 1e-12 * self.gamma;
        let (a, b) = ((x - h).max(0.0), (x + h).min(self.gamma));
        let (fa, fb) = (f(a), f(b));
        if fa * fb < 0.0 {
            brent(f, a, b, fa, fb, 0.0)
        } else {
            x
        }
    }

    /// max |dv/dx| over the support, given its `extrema` inside
    /// ([`Self::acceleration_extrema`]; the ends are zero).
    pub fn peak_acceleration(&self, extrema: &[f64]) -> f64 {
        extrema
            .iter()
            .fold(0.0, |m: f64, &x| m.max(self.acceleration(x).abs()))
    }

    /// max |v| over the support (V = 1).
    pub fn peak_velocity(&self) -> f64 {
        let (ext, n) = self.velocity_extrema();
        ext[..n]
            .iter()
            .fold(0.0, |m: f64, &x| m.max(self.velocity(x).abs()))
    }

    /// max |∫₀ˣ v| over the support (V = 1): at the end or where cos ψ = 0.
    pub fn peak_displacement(&self) -> f64 {
        let mut best = self.displacement(self.gamma).abs();
        let mut k = ((self.psi0 - FRAC_PI_2) / PI).ceil();
        loop {
            let x = (FRAC_PI_2 + k * PI - self.psi0) / TAU;
            if x >= self.gamma {
                break;
            }
            if x > 0.0 {
                best = best.max(self.displacement(x).abs());
            }
            k += 1.0;
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shapes() -> Vec<MavroeidisPapageorgiou> {
        let mut out = Vec::new();
        for gamma in [1.0001, 1.1, 1.5, 2.0, 2.5, 3.0, 7.3, 10.0, 19.99, 20.0] {
            for nu in [-PI, -2.0, -FRAC_PI_2, 0.0, 0.3, 1.0, FRAC_PI_2, 3.0, PI] {
                out.push(MavroeidisPapageorgiou::new(gamma, nu).expect("valid"));
            }
        }
        out
    }

    /// The phase crossings find every sign change of the jerk a dense grid
    /// sees, and of the acceleration, and nothing else.
    #[test]
    fn every_extremum_is_found_and_no_other() {
        for s in shapes() {
            let n = (s.gamma * 2000.0) as usize;
            // From just inside one end to just inside the other (v′ is 0 at the ends).
            let grid = |f: &dyn Fn(f64) -> f64| -> Vec<f64> {
                let at = |k: usize| {
                    let x = s.gamma * k as f64 / n as f64;
                    x.clamp(1e-9 * s.gamma, s.gamma * (1.0 - 1e-9))
                };
                let mut roots = Vec::new();
                let mut prev = f(at(0));
                for k in 1..=n {
                    let v = f(at(k));
                    if prev * v < 0.0 {
                        roots.push(at(k));
                    }
                    prev = v;
                }
                roots
            };
            // A zero at an end (ν − πγ = π/2 mod π) may round to either side.
            let inner = |x: &&f64| **x > 1e-9 * s.gamma && **x < s.gamma * (1.0 - 1e-9);
            let (ext, count) = s.acceleration_extrema();
            assert!(count <= (2.0 * (s.gamma + 1.0)).ceil() as usize);
            let ext: Vec<f64> = ext[..count].iter().filter(inner).copied().collect();
            let seen = grid(&|x| s.jerk(x));
            assert_eq!(ext.len(), seen.len(), "{s:?}");
            for (x, g) in ext.iter().zip(&seen) {
                assert!(
                    (x - g).abs() <= 2.0 * s.gamma / n as f64,
                    "{s:?}: {x} vs {g}"
                );
                assert!(s.jerk(*x).abs() < 1e-12 * 2.0 * PI * PI, "{s:?}: {x}");
            }
            let (vext, vcount) = s.velocity_extrema();
            let vext: Vec<f64> = vext[..vcount].iter().filter(inner).copied().collect();
            assert_eq!(vext.len(), grid(&|x| s.acceleration(x)).len(), "{s:?}");
            for x in &vext {
                assert!(s.acceleration(*x).abs() < 1e-12 * TAU, "{s:?}: {x}");
            }
        }
    }

    /// The derivatives and the integral agree with each other: central
    /// differences of v and v′, and a Simpson integration of v.
    #[test]
    fn derivatives_and_integral_are_consistent() {
        for s in shapes() {
            let h = 2e-6;
            for k in 1..50 {
                let x = s.gamma * k as f64 / 50.0;
                let dv = (s.velocity(x + h) - s.velocity(x - h)) / (2.0 * h);
                assert!((dv - s.acceleration(x)).abs() < 1e-8, "{s:?} at {x}");
                let da = (s.acceleration(x + h) - s.acceleration(x - h)) / (2.0 * h);
                assert!((da - s.jerk(x)).abs() < 1e-7, "{s:?} at {x}");
            }
            let n = 20_000;
            let dx = s.gamma / n as f64;
            let mut u = 0.0;
            for k in 0..n {
                let (a, b) = (k as f64 * dx, (k + 1) as f64 * dx);
                u += dx / 6.0 * (s.velocity(a) + 4.0 * s.velocity(0.5 * (a + b)) + s.velocity(b));
            }
            assert!((u - s.displacement(s.gamma)).abs() < 1e-12, "{s:?}");
        }
    }

    /// At the ends of the support the bell and its slope vanish: v = v′ = 0.
    #[test]
    fn velocity_and_acceleration_vanish_at_the_ends() {
        for s in shapes() {
            for x in [0.0, s.gamma] {
                assert!(s.velocity(x).abs() < 1e-15, "{s:?}");
                assert!(s.acceleration(x).abs() < 1e-14, "{s:?}");
            }
        }
    }

    #[test]
    fn phases_reduce_to_one_turn_and_gamma_is_bounded() {
        assert_eq!(reduce_phase(1.0), 1.0);
        assert_eq!(reduce_phase(PI), PI);
        assert!((reduce_phase(-PI) - PI).abs() < 1e-15);
        assert!((reduce_phase(1.0 + 4.0 * PI) - 1.0).abs() < 1e-14);
        assert!((reduce_phase(-1.0 - 2.0 * PI) + 1.0).abs() < 1e-14);
        assert!(MavroeidisPapageorgiou::new(1.0, 0.0).is_none());
        assert!(MavroeidisPapageorgiou::new(20.0 + 1e-9, 0.0).is_none());
        assert!(MavroeidisPapageorgiou::new(2.0, f64::NAN).is_none());
        assert!(MavroeidisPapageorgiou::new(f64::NAN, 0.0).is_none());
    }
}
