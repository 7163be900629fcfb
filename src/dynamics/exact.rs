//! Closed-form solution of the linear formulation (eqs. 25–31), generalised to
//! every segment between rocking start, impacts and pulse end.
//!
//! On a segment that starts at `t0` on side `s` with `(θ0, θ̇0)`, eq. 50 reads
//! `θ̈ = p² (θ − α s − U cos(χ0 + ω τ))`, `τ = t − t0`, `U = a_p/g`, and
//! `C = U / (1 + ω²/p²)` is the amplitude of the particular solution (eq. 25).
//! Writing the solution relative to its own start,
//!
//! ```text
//! θ(τ) = θ0 + (θ0 − α s)·2 sinh²(pτ/2) + (θ̇0/p)·sinh(pτ) + C·F(τ),
//! F(τ) = −2 cos χ0 (sin²(ωτ/2) + sinh²(pτ/2)) + ωτ sin χ0 (shc(pτ) + snc(ωτ)),
//! ```
//!
//! with `shc(x) = sinh x / x − 1` and `snc(y) = 1 − sin y / y`, keeps every term
//! free of cancellation near τ = 0, so excursions as small as 1e-30 rad (a pulse
//! that exceeds the rocking threshold by 1e-12) are resolved. Segments are cut at
//! `pτ ≤ 20` and re-anchored, so nothing overflows however long the case.

use super::equations::RockingRhs;
use super::events::brent;
use super::integrator::State;
use std::f64::consts::FRAC_PI_2;

/// Longest segment, in units of 1/p, before re-anchoring.
pub const MAX_SEGMENT_PT: f64 = 20.0;

/// sinh(x)/x − 1, accurate for small x.
#[inline]
fn shc(x: f64) -> f64 {
    if x.abs() < 0.1 {
        let x2 = x * x;
        x2 * (1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (1.0 / 5040.0 + x2 / 362_880.0)))
    } else {
        x.sinh() / x - 1.0
    }
}

/// 1 − sin(y)/y, accurate for small y.
#[inline]
fn snc(y: f64) -> f64 {
    if y.abs() < 0.1 {
        let y2 = y * y;
        y2 * (1.0 / 6.0 - y2 * (1.0 / 120.0 - y2 * (1.0 / 5040.0 - y2 / 362_880.0)))
    } else {
        1.0 - y.sin() / y
    }
}

/// One smooth piece of the linear motion, in closed form.
#[derive(Clone, Copy, Debug)]
pub struct LinearSegment {
    /// Start time.
    pub t0: f64,
    /// State at the start.
    pub y0: State,
    /// Side ±1.
    pub side: f64,
    p: f64,
    alpha: f64,
    /// Particular-solution amplitude C = U/(1 + ω²/p²) (eq. 25).
    c: f64,
    omega: f64,
    cos_chi0: f64,
    sin_chi0: f64,
    /// Bound on |U| used by the safe stepping.
    u_abs: f64,
    /// U = a_p/g (signed), for the ground term of g̈.
    u_amp: f64,
}

impl LinearSegment {
    /// The segment of `rhs` (linear formulation) starting at `(t0, y0)`.
    pub fn new(rhs: &RockingRhs, t0: f64, y0: State) -> Self {
        let p = rhs.p2.sqrt();
        let u = rhs.amplitude_over_g;
        let w = rhs.omega;
        let (sin_chi0, cos_chi0) = (w * t0 + rhs.phase).sin_cos();
        LinearSegment {
            t0,
            y0,
            side: rhs.side,
            p,
            alpha: rhs.alpha,
            c: u / (1.0 + (w / p).powi(2)),
            omega: w,
            cos_chi0,
            sin_chi0,
            u_abs: u.abs(),
            u_amp: u,
        }
    }

    /// State at `τ = t − t0 ≥ 0`.
    #[inline]
    pub fn at_tau(&self, tau: f64) -> State {
        let (p, w) = (self.p, self.omega);
        let x = p * tau;
        let sh = x.sinh();
        let ch = x.cosh();
        let sh_half = (0.5 * x).sinh();
        let sh_half2 = 2.0 * sh_half * sh_half;
        let lean = self.y0[0] - self.alpha * self.side;
        let mut theta = self.y0[0] + lean * sh_half2 + (self.y0[1] / p) * sh;
        let mut theta_dot = lean * p * sh + self.y0[1] * ch;
        if self.c != 0.0 {
            let y = w * tau;
            let sy = y.sin();
            let s_half = (0.5 * y).sin();
            let s_half2 = 2.0 * s_half * s_half;
            let f = -self.cos_chi0 * (s_half2 + sh_half2) + y * self.sin_chi0 * (shc(x) + snc(y));
            let fd = -self.cos_chi0 * (w * sy + p * sh) + w * self.sin_chi0 * (sh_half2 + s_half2);
            theta += self.c * f;
            theta_dot += self.c * fd;
        }
        [theta, theta_dot]
    }

    /// State at time `t`.
    #[inline]
    pub fn at(&self, t: f64) -> State {
        self.at_tau(t - self.t0)
    }

    /// ü_g/g at `τ`.
    #[inline]
    fn ground(&self, tau: f64) -> f64 {
        if self.u_amp == 0.0 {
            return 0.0;
        }
        let (sy, cy) = (self.omega * tau).sin_cos();
        self.u_amp * (self.cos_chi0 * cy - self.sin_chi0 * sy)
    }

    /// Curvature bounds of g = sθ valid while 0 ≤ g ≤ π/2: −k_low ≤ g̈ ≤ k_up.
    fn curvature_bounds(&self) -> (f64, f64) {
        let p2 = self.p * self.p;
        (
            p2 * (self.alpha + self.u_abs),
            p2 * ((FRAC_PI_2 - self.alpha).max(0.0) + self.u_abs),
        )
    }
}

/// What ended a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SegmentEnd {
    /// θ returned to zero at `t` (an impact).
    Impact(f64),
    /// |θ| reached π/2 at `t`.
    Overturn(f64),
    /// The segment reached `t` without event (pulse end, horizon or re-anchor).
    Reached(f64),
}

/// The first event of `seg` in `(t0, t_stop]`, found by safe stepping: from each
/// point the quadratic bounds on g = sθ exclude a root for a computable time, so
/// no root is ever stepped over; the last stretch is bracketed and solved with
/// Brent's method on the closed form. `no_return_before` disarms the impact event
/// until that time (the block is still being lifted off from rest).
pub fn first_event(seg: &LinearSegment, t_stop: f64, no_return_before: f64) -> SegmentEnd {
    let s = seg.side;
    let (k_low, k_up) = seg.curvature_bounds();
    let tau_stop = (t_stop - seg.t0).min(MAX_SEGMENT_PT / seg.p);
    let reached = |tau: f64| {
        if seg.t0 + tau >= t_stop {
            SegmentEnd::Reached(t_stop)
        } else {
            SegmentEnd::Reached(seg.t0 + tau)
        }
    };
    if tau_stop <= 0.0 {
        return SegmentEnd::Reached(seg.t0.max(t_stop));
    }
    let g = |tau: f64| s * seg.at_tau(tau)[0];
    let top = |tau: f64| FRAC_PI_2 - s * seg.at_tau(tau)[0];
    let resolution = |tau: f64| 8.0 * f64::EPSILON * (seg.t0 + tau).abs().max(1.0 / seg.p);
    let p2 = seg.p * seg.p;
    let uw = seg.u_abs * seg.omega;
    let k_abs = k_low.max(k_up);
    // Steps shorter than this call for the third-order bound.
    let short = 0.05 / seg.p.max(seg.omega);

    let mut tau = 0.0;
    // Lift-off from rest: g is convex and increasing until the ground stops
    // exceeding the threshold, so only overturning can happen there.
    let lift = (no_return_before - seg.t0).min(tau_stop);
    if lift > 0.0 {
        if top(lift) <= 0.0 {
            let r = brent(top, 0.0, lift, top(0.0), top(lift), 0.0);
            return SegmentEnd::Overturn(seg.t0 + r);
        }
        tau = lift;
        if tau >= tau_stop {
            return reached(tau);
        }
    }
    for _ in 0..100_000 {
        let y = seg.at_tau(tau);
        let (gk, gdk) = (s * y[0], s * y[1]);
        // Time before the lower bound gk + gdk δ − k_low δ²/2 can reach zero.
        let d_low = if gk <= 0.0 && tau > 0.0 {
            0.0
        } else {
            let quadratic = (gdk + (gdk * gdk + 2.0 * k_low * gk.max(0.0)).sqrt()) / k_low;
            // A third-order bound is far tighter when g̈ is small (tiny motions
            // near the rocking threshold): g ≥ gk + ġ δ + g̈ δ²/2 − L δ³/6 with
            // L ≥ |g⃛| = p²|ġ − s u̇|, |ġ| ≤ |ġk| + k_abs δ on the step.
            let acc = p2 * (gk - seg.alpha - s * seg.ground(tau));
            let l0 = p2 * (gdk.abs() + uw);
            let cubic = if l0 > 0.0 && quadratic < short {
                let first = first_root_cubic(gk.max(0.0), gdk, 0.5 * acc, -l0 / 6.0);
                let l1 = p2 * (gdk.abs() + k_abs * first + uw);
                first_root_cubic(gk.max(0.0), gdk, 0.5 * acc, -l1 / 6.0)
            } else {
                0.0
            };
            quadratic.max(cubic)
        };
        let room = FRAC_PI_2 - gk;
        let d_up = if k_up > 0.0 {
            (-gdk + (gdk * gdk + 2.0 * k_up * room.max(0.0)).sqrt()) / k_up
        } else if gdk > 0.0 {
            room / gdk
        } else {
            f64::INFINITY
        };
        let res = resolution(tau);
        let step = d_low.min(d_up);
        if tau + step >= tau_stop {
            // No event can occur before the stop: check the stop point itself.
            let (gs, ts) = (g(tau_stop), top(tau_stop));
            if gs > 0.0 && ts > 0.0 {
                return reached(tau_stop);
            }
            return bracket(seg, tau, tau_stop, &g, &top);
        }
        if step <= res {
            // Converged onto an event from the safe side.
            return if d_low <= d_up {
                SegmentEnd::Impact(seg.t0 + tau + d_low)
            } else {
                SegmentEnd::Overturn(seg.t0 + tau + d_up)
            };
        }
        // Try to bracket with a Newton-like overshoot when close to an event.
        let near = 4.0 * step;
        if step < 1e-3 / seg.p && tau + near < tau_stop {
            let (gn, tn) = (g(tau + near), top(tau + near));
            if gn <= 0.0 || tn <= 0.0 {
                return bracket(seg, tau + step, tau + near, &g, &top);
            }
        }
        tau += step;
    }
    // Pathologically slow approach to a tangency: re-anchor here and go on.
    reached(tau)
}

/// The first positive root of c0 + c1 σ + c2 σ² + c3 σ³ with c0 ≥ 0 and c3 < 0
/// (so a root exists): the cubic is split into monotone pieces at the roots of
/// its derivative, and the first piece that ends at or below zero is solved by
/// Brent's method.
fn first_root_cubic(c0: f64, c1: f64, c2: f64, c3: f64) -> f64 {
    let h = |x: f64| c0 + x * (c1 + x * (c2 + x * c3));
    if c0 <= 0.0 {
        return 0.0;
    }
    // h'(σ) = c1 + 2 c2 σ + 3 c3 σ²: critical points.
    let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, c1);
    let disc = qb * qb - 4.0 * qa * qc;
    let mut cuts = [f64::NAN; 2];
    if disc >= 0.0 {
        let sq = disc.sqrt();
        let q = -0.5 * (qb + sq.copysign(qb));
        let r1 = q / qa;
        let r2 = if q != 0.0 { qc / q } else { r1 };
        cuts = [r1.min(r2), r1.max(r2)];
    }
    let mut lo = 0.0;
    for &c in cuts.iter().filter(|c| c.is_finite() && **c > 0.0) {
        if h(c) <= 0.0 {
            return brent(h, lo, c, h(lo), h(c), 0.0);
        }
        lo = c;
    }
    // Last piece: h decreases to −∞; find where it is ≤ 0.
    let mut hi = if lo > 0.0 {
        2.0 * lo
    } else {
        (c0 / -c3).cbrt()
    };
    let mut guard = 0;
    while h(hi) > 0.0 && guard < 2000 {
        hi *= 2.0;
        guard += 1;
    }
    brent(h, lo, hi, h(lo), h(hi), 0.0)
}

/// Resolves the first event in `[a, b]`, where it is known that none occurs
/// before `a` and at least one of g, top is ≤ 0 at `b`.
fn bracket<G: Fn(f64) -> f64, T: Fn(f64) -> f64>(
    seg: &LinearSegment,
    a: f64,
    b: f64,
    g: &G,
    top: &T,
) -> SegmentEnd {
    let (ga, gb) = (g(a), g(b));
    let (ta, tb) = (top(a), top(b));
    let impact = if gb <= 0.0 {
        Some(if ga <= 0.0 {
            a
        } else {
            brent(g, a, b, ga, gb, 0.0)
        })
    } else {
        None
    };
    let over = if tb <= 0.0 {
        Some(if ta <= 0.0 {
            a
        } else {
            brent(top, a, b, ta, tb, 0.0)
        })
    } else {
        None
    };
    match (impact, over) {
        (Some(i), Some(o)) if o < i => SegmentEnd::Overturn(seg.t0 + o),
        (Some(i), _) => SegmentEnd::Impact(seg.t0 + i),
        (None, Some(o)) => SegmentEnd::Overturn(seg.t0 + o),
        (None, None) => SegmentEnd::Reached(seg.t0 + b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::block::Block;
    use crate::dynamics::equations::Formulation;
    use crate::dynamics::excitation::{Pulse, PulseShape};
    use crate::dynamics::integrator::Rhs;

    fn rhs(side: f64, forced: bool) -> RockingRhs {
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        let pulse = Pulse::new(PulseShape::OneSine, 4.0 * 0.25 * 9.81, 5.0 * 2.14).expect("valid");
        RockingRhs::new(Formulation::Linear, &block, &pulse, side, forced)
    }

    #[test]
    fn closed_form_satisfies_the_equation_of_motion() {
        let r = rhs(-1.0, true);
        let seg = LinearSegment::new(&r, 0.13, [-0.02, -0.07]);
        for &tau in &[1e-6, 0.01, 0.3, 1.7] {
            let h = 1e-4;
            let y_m = seg.at_tau(tau - h);
            let y = seg.at_tau(tau);
            let y_p = seg.at_tau(tau + h);
            let acc_fd = (y_p[0] - 2.0 * y[0] + y_m[0]) / (h * h);
            let vel_fd = (y_p[0] - y_m[0]) / (2.0 * h);
            let acc = r.eval(0.13 + tau, y)[1];
            assert!(
                (acc_fd - acc).abs() < 1e-5 * (1.0 + acc.abs()),
                "{acc_fd} vs {acc}"
            );
            assert!((vel_fd - y[1]).abs() < 1e-7, "{vel_fd} vs {}", y[1]);
        }
        let y0 = seg.at_tau(0.0);
        assert_eq!(y0, [-0.02, -0.07]);
    }

    #[test]
    fn housner_quarter_period_of_free_rocking() {
        // Released from θ0 at rest: reaches θ = 0 after (1/p) acosh(1/(1 − θ0/α)).
        let r = rhs(1.0, false);
        let theta0 = 0.15;
        let seg = LinearSegment::new(&r, 0.0, [theta0, 0.0]);
        let expected = (1.0 / (1.0 - theta0 / 0.25)).acosh() / 2.14;
        match first_event(&seg, 100.0, 0.0) {
            SegmentEnd::Impact(t) => assert!((t - expected).abs() < 1e-14, "{t} vs {expected}"),
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn overturns_beyond_the_separatrix() {
        let r = rhs(1.0, false);
        let seg = LinearSegment::new(&r, 0.0, [0.0, 2.14 * 0.25 * 1.001]);
        assert!(matches!(
            first_event(&seg, 100.0, 0.0),
            SegmentEnd::Overturn(_)
        ));
        let seg = LinearSegment::new(&r, 0.0, [0.0, 2.14 * 0.25 * 0.999]);
        assert!(matches!(
            first_event(&seg, 100.0, 0.0),
            SegmentEnd::Impact(_)
        ));
    }

    #[test]
    fn cubic_first_root_is_the_smallest_positive_one() {
        // (1 − σ)(2 − σ)(3 − σ)·(−1)… scaled: roots 1, 2, 3 with c0 = 6 > 0.
        let r = first_root_cubic(6.0, -11.0, 6.0, -1.0);
        assert!((r - 1.0).abs() < 1e-14, "{r}");
        // A single root far out.
        let r = first_root_cubic(1e-26, 0.0, 0.0, -1.0);
        assert!((r - 1e-26f64.cbrt()).abs() < 1e-20, "{r}");
    }

    #[test]
    fn long_segments_are_cut_before_overflow() {
        let r = rhs(1.0, false);
        // Exactly at the unstable equilibrium θ = α: stays there in exact arithmetic.
        let seg = LinearSegment::new(&r, 0.0, [0.25, 0.0]);
        match first_event(&seg, 1e6, 0.0) {
            SegmentEnd::Reached(t) => assert!((t - MAX_SEGMENT_PT / 2.14).abs() < 1e-12),
            other => panic!("unexpected {other:?}"),
        }
    }
}
