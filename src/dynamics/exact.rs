//! Closed-form solution of the linear formulation (eqs. 25–31), generalised to
//! every segment between rocking start, impacts, the kinks of the forcing and
//! its end.
//!
//! On a segment that starts at `t0` on side `s` with `(θ0, θ̇0)`, eq. 50 reads
//! `θ̈ = p² (θ − α s − ü_g/g)`, `τ = t − t0`. The ground term is either a
//! pulse's cosine, `ü_g/g = U cos(χ0 + ω τ)` with `U = a_p/g`, whose particular
//! solution has the amplitude `C = U / (1 + ω²/p²)` (eq. 25), or a piece of a
//! sampled record, `ü_g/g = u0 + u1 τ`, whose particular solution is
//! `α s + u0 + u1 τ` itself (its second derivative vanishes). Writing the
//! solution relative to its own start, with `λ = θ0 − α s − u0`,
//!
//! ```text
//! θ(τ) = θ0 + λ·2 sinh²(pτ/2) + (θ̇0/p)·sinh(pτ) + C·F(τ) − (u1/p)·pτ·shc(pτ),
//! F(τ) = −2 cos χ0 (sin²(ωτ/2) + sinh²(pτ/2)) + ωτ sin χ0 (shc(pτ) + snc(ωτ)),
//! ```
//!
//! with `shc(x) = sinh x / x − 1` and `snc(y) = 1 − sin y / y`, keeps every term
//! free of cancellation near τ = 0, so excursions as small as 1e-30 rad (a pulse
//! that exceeds the rocking threshold by 1e-12) are resolved. Segments are cut at
//! `pτ ≤ 20` and re-anchored, so nothing overflows however long the case; a
//! record's segments also end at every sample, where its slope changes.

use super::equations::RockingRhs;
use super::events::brent;
use super::integrator::State;
use std::f64::consts::FRAC_PI_2;
use std::ops::ControlFlow;

/// Longest segment, in units of 1/p, before re-anchoring.
pub const MAX_SEGMENT_PT: f64 = 20.0;

/// (sinh x, cosh x − 1), both free of cancellation: for |x| < 0.1 (a record's
/// short pieces) their Taylor series to x¹⁰, otherwise from one exponential,
/// with m = eˣ − 1 and r = m/(1 + m) = 1 − e⁻ˣ: sinh x = (m + r)/2 and
/// cosh x − 1 = m r/2 (= 2 sinh²(x/2)).
#[inline]
fn sinh_cosh_m1(x: f64) -> (f64, f64) {
    if x.abs() < 0.1 {
        // Truncation below 1e-18 relative.
        let x2 = x * x;
        let sh = x
            * (1.0 + x2 * (1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (1.0 / 5040.0 + x2 / 362_880.0))));
        let ch_m1 = x2
            * (0.5
                + x2 * (1.0 / 24.0
                    + x2 * (1.0 / 720.0 + x2 * (1.0 / 40_320.0 + x2 / 3_628_800.0))));
        return (sh, ch_m1);
    }
    let m = x.exp_m1();
    let r = m / (1.0 + m);
    (0.5 * (m + r), 0.5 * (m * r))
}

/// sinh(x)/x − 1 given `sh` = sinh x, accurate for small x.
#[inline]
fn shc(x: f64, sh: f64) -> f64 {
    if x.abs() < 0.1 {
        let x2 = x * x;
        x2 * (1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (1.0 / 5040.0 + x2 / 362_880.0)))
    } else {
        sh / x - 1.0
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
    /// θ̇0/p and u1/p, the coefficients of sinh pτ and of the ramp's term.
    v0_over_p: f64,
    u1_over_p: f64,
    /// λ = θ0 − α s − u0: the distance from the particular solution at the
    /// start, the coefficient of the growing and decaying exponentials.
    lean: f64,
    /// Particular-solution amplitude C = U/(1 + ω²/p²) (eq. 25).
    c: f64,
    omega: f64,
    cos_chi0: f64,
    sin_chi0: f64,
    /// Bound on |ü_g/g| over the segment, used by the safe stepping.
    u_abs: f64,
    /// Bound on |d(ü_g/g)/dt| over the segment (the third-order step bound).
    rate_abs: f64,
    /// U = a_p/g (signed), for the ground term of g̈.
    u_amp: f64,
    /// u0: a record piece's ü_g/g at the start (zero for a pulse).
    u0: f64,
    /// u1: a record piece's slope of ü_g/g, 1/s (zero for a pulse).
    u1: f64,
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
            v0_over_p: y0[1] / p,
            u1_over_p: 0.0,
            lean: y0[0] - rhs.alpha * rhs.side,
            c: u / (1.0 + (w / p).powi(2)),
            omega: w,
            cos_chi0,
            sin_chi0,
            u_abs: u.abs(),
            rate_abs: u.abs() * w,
            u_amp: u,
            u0: 0.0,
            u1: 0.0,
        }
    }

    /// The segment starting at `(t0, y0)` under a ground term linear in time,
    /// `ü_g/g = u0 + u1 (t − t0)`, held until `t1` (a piece of a record; with
    /// u0 = u1 = 0, free vibration); `p` is the frequency parameter.
    #[allow(clippy::too_many_arguments)]
    pub fn linear_ground(
        p: f64,
        alpha: f64,
        side: f64,
        t0: f64,
        y0: State,
        u0: f64,
        u1: f64,
        t1: f64,
    ) -> Self {
        let u_end = if t1.is_finite() {
            u0 + u1 * (t1 - t0)
        } else {
            u0
        };
        LinearSegment {
            t0,
            y0,
            side,
            p,
            alpha,
            v0_over_p: y0[1] / p,
            u1_over_p: u1 / p,
            lean: y0[0] - alpha * side - u0,
            c: 0.0,
            omega: 0.0,
            cos_chi0: 1.0,
            sin_chi0: 0.0,
            u_abs: u0.abs().max(u_end.abs()),
            rate_abs: u1.abs(),
            u_amp: 0.0,
            u0,
            u1,
        }
    }

    /// A bound on the rounding error of the state at `τ`: the unit roundoff of
    /// the start's terms, grown by the exponentials as cosh(pτ).
    pub fn rounding_error(&self, tau: f64) -> f64 {
        let x = self.p * tau;
        // (cosh x − 1)/x² grows with |x|: below 1 it is at most cosh 1 − 1.
        let growth = if x.abs() <= 1.0 {
            1.0 + 0.543_081 * x * x
        } else {
            x.cosh()
        };
        f64::EPSILON
            * growth
            * (self.alpha
                + self.u_abs
                + self.y0[0].abs()
                + self.v0_over_p.abs()
                + self.u1_over_p.abs())
    }

    /// State at `τ = t − t0 ≥ 0`.
    #[inline]
    pub fn at_tau(&self, tau: f64) -> State {
        let (p, w) = (self.p, self.omega);
        let x = p * tau;
        // sh_half2 = 2 sinh²(x/2) = cosh x − 1.
        let (sh, sh_half2) = sinh_cosh_m1(x);
        let lean = self.lean;
        let mut theta = self.y0[0] + lean * sh_half2 + self.v0_over_p * sh;
        let mut theta_dot = lean * p * sh + self.y0[1] * (1.0 + sh_half2);
        if self.u1 != 0.0 {
            // The ramp u1 τ: −(u1/p)(sinh x − x) and −u1 (cosh x − 1).
            theta -= self.u1_over_p * (x * shc(x, sh));
            theta_dot -= self.u1 * sh_half2;
        }
        if self.c != 0.0 {
            let y = w * tau;
            let sy = y.sin();
            let s_half = (0.5 * y).sin();
            let s_half2 = 2.0 * s_half * s_half;
            let f =
                -self.cos_chi0 * (s_half2 + sh_half2) + y * self.sin_chi0 * (shc(x, sh) + snc(y));
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
        let line = self.u0 + self.u1 * tau;
        if self.u_amp == 0.0 {
            return line;
        }
        let (sy, cy) = (self.omega * tau).sin_cos();
        self.u_amp * (self.cos_chi0 * cy - self.sin_chi0 * sy) + line
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
    /// The segment reached `t` without event (pulse end, a record's sample,
    /// horizon or re-anchor), in the state given.
    Reached(f64, State),
}

/// The safe stepping of [`first_event`] over one segment: the segment, where
/// it stops, and the bounds on g̈ that size the steps.
struct Stepping<'a> {
    seg: &'a LinearSegment,
    /// The side, ±1.
    s: f64,
    t_stop: f64,
    /// The stop, in time since the segment's start (at most p τ = 20).
    tau_stop: f64,
    /// Bounds on −g̈ and on g̈ over the segment.
    k_low: f64,
    k_up: f64,
    k_abs: f64,
    p2: f64,
}

impl Stepping<'_> {
    /// g = sθ at τ.
    fn g(&self, tau: f64) -> f64 {
        self.s * self.seg.at_tau(tau)[0]
    }

    /// The room before overturning, π/2 − sθ, at τ.
    fn top(&self, tau: f64) -> f64 {
        FRAC_PI_2 - self.s * self.seg.at_tau(tau)[0]
    }

    /// The shortest step worth taking at τ.
    fn resolution(&self, tau: f64) -> f64 {
        8.0 * f64::EPSILON * (self.seg.t0 + tau).abs().max(1.0 / self.seg.p)
    }

    /// The end without event, with its state (`y` when it is already known
    /// at τ).
    fn reached(&self, tau: f64, y: Option<State>) -> SegmentEnd {
        let seg = self.seg;
        let t = if seg.t0 + tau >= self.t_stop {
            self.t_stop
        } else {
            seg.t0 + tau
        };
        let tau_end = t - seg.t0;
        match y {
            Some(y) if tau_end == tau => SegmentEnd::Reached(t, y),
            _ => SegmentEnd::Reached(t, seg.at_tau(tau_end)),
        }
    }

    /// The event bracketed in `[a, b]`, solved.
    fn bracket(&self, a: f64, b: f64) -> SegmentEnd {
        bracket(self.seg, a, b, &|tau| self.g(tau), &|tau| self.top(tau))
    }

    /// No event can occur between `from` and the stop: check the stop itself.
    fn to_stop(&self, from: f64) -> SegmentEnd {
        let y_stop = self.seg.at_tau(self.tau_stop);
        let gs = self.s * y_stop[0];
        if gs > 0.0 && FRAC_PI_2 - gs > 0.0 {
            self.reached(self.tau_stop, Some(y_stop))
        } else {
            self.bracket(from, self.tau_stop)
        }
    }

    /// Lift-off from rest until `no_return_before`: g is convex and
    /// increasing until the ground stops exceeding the threshold, so only
    /// overturning can happen there. Where the search goes on (τ), or how
    /// the segment ends.
    fn lift_off(&self, no_return_before: f64) -> ControlFlow<SegmentEnd, f64> {
        let seg = self.seg;
        let lift = (no_return_before - seg.t0).min(self.tau_stop);
        if lift > 0.0 {
            let top = |tau: f64| self.top(tau);
            if top(lift) <= 0.0 {
                let r = brent(top, 0.0, lift, top(0.0), top(lift), 0.0);
                return ControlFlow::Break(SegmentEnd::Overturn(seg.t0 + r));
            }
            if lift >= self.tau_stop {
                return ControlFlow::Break(self.reached(lift, None));
            }
            return ControlFlow::Continue(lift);
        }
        ControlFlow::Continue(0.0)
    }

    /// One safe step from τ: where the next one starts, or how the segment
    /// ends (`stop_state` keeps the state at the stop once evaluated).
    fn step(&self, tau: f64, stop_state: &mut Option<State>) -> ControlFlow<SegmentEnd, f64> {
        let seg = self.seg;
        // At the start the state is known: no need to evaluate the closed form.
        let y = if tau == 0.0 { seg.y0 } else { seg.at_tau(tau) };
        let (gk, gdk) = (self.s * y[0], self.s * y[1]);
        // Neither quadratic bound reaches its event before the stop: they are
        // concave and non-negative at δ = 0, so their values at the stop tell
        // (a record's short pieces mostly end here, with no root to solve).
        let rest = self.tau_stop - tau;
        let room = FRAC_PI_2 - gk;
        let inside = (gk > 0.0 || (gk == 0.0 && tau == 0.0)) && room > 0.0;
        if inside
            && gk + rest * (gdk - 0.5 * self.k_low * rest) > 0.0
            && room - rest * (gdk + 0.5 * self.k_up * rest) > 0.0
        {
            return ControlFlow::Break(self.to_stop(tau));
        }
        if inside
            && rest * seg.p <= 1.0
            && let Some(end) = self.short_stretch(tau, (gk, gdk), stop_state)
        {
            return ControlFlow::Break(end);
        }
        let d_low = self.lower_reach(tau, gk, gdk);
        let d_up = self.upper_reach(gdk, room);
        let res = self.resolution(tau);
        let step = d_low.min(d_up);
        if tau + step >= self.tau_stop {
            return ControlFlow::Break(self.to_stop(tau));
        }
        if step <= res {
            // Converged onto an event from the safe side.
            return ControlFlow::Break(if d_low <= d_up {
                SegmentEnd::Impact(seg.t0 + tau + d_low)
            } else {
                SegmentEnd::Overturn(seg.t0 + tau + d_up)
            });
        }
        // Try to bracket with a Newton-like overshoot when close to an event.
        let near = 4.0 * step;
        if step < 1e-3 / seg.p && tau + near < self.tau_stop {
            let gn = self.g(tau + near);
            if gn <= 0.0 || FRAC_PI_2 - gn <= 0.0 {
                return ControlFlow::Break(self.bracket(tau + step, tau + near));
            }
        }
        ControlFlow::Continue(tau + step)
    }

    /// On a short stretch (from τ, at `(gk, gdk)` inside) the state at the
    /// stop settles most cases. The same bounds taken backwards from it: a
    /// root needs a first crossing beyond the forward bound's reach and a
    /// last one before the backward bound's, so reaches that add up to the
    /// stretch exclude it.
    fn short_stretch(
        &self,
        tau: f64,
        (gk, gdk): (f64, f64),
        stop_state: &mut Option<State>,
    ) -> Option<SegmentEnd> {
        let seg = self.seg;
        let rest = self.tau_stop - tau;
        let room = FRAC_PI_2 - gk;
        let ys = *stop_state.get_or_insert_with(|| seg.at_tau(self.tau_stop));
        let (gs, gds) = (self.s * ys[0], self.s * ys[1]);
        let room_s = FRAC_PI_2 - gs;
        if gs > 0.0
            && room_s > 0.0
            && reach(gk, gdk, self.k_low) + reach(gs, -gds, self.k_low) > rest
            && reach(room, -gdk, self.k_up) + reach(room_s, gds, self.k_up) > rest
        {
            return Some(self.reached(self.tau_stop, Some(ys)));
        }
        // Falling to an impact before the stop: while g ≤ gk, g̈ ≤ κ =
        // p²(gk − α + |u|), so ġ ≤ ġk + κ⁺ δ stays negative over the
        // stretch when κ⁺ δ < −ġk. Then g falls all the way, and its one
        // root is the impact.
        let kappa = (self.p2 * (gk - seg.alpha + seg.u_abs)).max(0.0);
        if gs <= 0.0 && gdk < 0.0 && kappa * rest < -gdk {
            let g = |tau: f64| self.g(tau);
            return Some(SegmentEnd::Impact(
                seg.t0 + brent(g, tau, self.tau_stop, gk, gs, 0.0),
            ));
        }
        None
    }

    /// Time from τ (at `gk`, `gdk`) before the lower bound gk + gdk δ −
    /// k_low δ²/2 can reach zero.
    fn lower_reach(&self, tau: f64, gk: f64, gdk: f64) -> f64 {
        if gk <= 0.0 && tau > 0.0 {
            return 0.0;
        }
        let seg = self.seg;
        let (s, p2, k_low) = (self.s, self.p2, self.k_low);
        let quadratic = (gdk + (gdk * gdk + 2.0 * k_low * gk.max(0.0)).sqrt()) / k_low;
        // A third-order bound is far tighter when g̈ is small (tiny motions
        // near the rocking threshold): g ≥ gk + ġ δ + g̈ δ²/2 − L δ³/6 with
        // L ≥ |g⃛| = p²|ġ − s u̇|, |ġ| ≤ |ġk| + k_abs δ on the step.
        let acc = p2 * (gk - seg.alpha - s * seg.ground(tau));
        let l0 = p2 * (gdk.abs() + seg.rate_abs);
        // (Not needed when the quadratic bound already covers the segment.)
        // Steps shorter than 0.05/max(p, ω) call for it.
        let short = 0.05 / seg.p.max(seg.omega);
        let cubic = if l0 > 0.0 && quadratic < short && tau + quadratic < self.tau_stop {
            let first = first_root_cubic(gk.max(0.0), gdk, 0.5 * acc, -l0 / 6.0);
            let l1 = p2 * (gdk.abs() + self.k_abs * first + seg.rate_abs);
            first_root_cubic(gk.max(0.0), gdk, 0.5 * acc, -l1 / 6.0)
        } else {
            0.0
        };
        quadratic.max(cubic)
    }

    /// Time before the upper bound reaches overturning, from `room` to it
    /// at `gdk`.
    fn upper_reach(&self, gdk: f64, room: f64) -> f64 {
        let k_up = self.k_up;
        if k_up > 0.0 {
            (-gdk + (gdk * gdk + 2.0 * k_up * room.max(0.0)).sqrt()) / k_up
        } else if gdk > 0.0 {
            room / gdk
        } else {
            f64::INFINITY
        }
    }
}

/// The first event of `seg` in `(t0, t_stop]`, found by safe stepping: from each
/// point the quadratic bounds on g = sθ exclude a root for a computable time, so
/// no root is ever stepped over; the last stretch is bracketed and solved with
/// Brent's method on the closed form. `no_return_before` disarms the impact event
/// until that time (the block is still being lifted off from rest).
pub fn first_event(seg: &LinearSegment, t_stop: f64, no_return_before: f64) -> SegmentEnd {
    let (k_low, k_up) = seg.curvature_bounds();
    let stepping = Stepping {
        seg,
        s: seg.side,
        t_stop,
        tau_stop: (t_stop - seg.t0).min(MAX_SEGMENT_PT / seg.p),
        k_low,
        k_up,
        k_abs: k_low.max(k_up),
        p2: seg.p * seg.p,
    };
    if stepping.tau_stop <= 0.0 {
        let t = seg.t0.max(t_stop);
        return SegmentEnd::Reached(t, seg.at(t));
    }
    let mut tau = match stepping.lift_off(no_return_before) {
        ControlFlow::Break(end) => return end,
        ControlFlow::Continue(tau) => tau,
    };
    // The state at the stop, once evaluated.
    let mut stop_state: Option<State> = None;
    for _ in 0..100_000 {
        match stepping.step(tau, &mut stop_state) {
            ControlFlow::Break(end) => return end,
            ControlFlow::Continue(next) => tau = next,
        }
    }
    // Pathologically slow approach to a tangency: re-anchor here and go on.
    stepping.reached(tau, None)
}

/// How far `v + d δ − k δ²/2` (v ≥ 0, k ≥ 0) stays positive: its first
/// positive root, ∞ if none.
#[inline]
fn reach(v: f64, d: f64, k: f64) -> f64 {
    if k > 0.0 {
        (d + (d * d + 2.0 * k * v).sqrt()) / k
    } else if d < 0.0 {
        v / -d
    } else {
        f64::INFINITY
    }
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
    let (ta, tb) = (FRAC_PI_2 - ga, FRAC_PI_2 - gb);
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
        (None, None) => SegmentEnd::Reached(seg.t0 + b, seg.at_tau(b)),
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

    /// θ̈ by central differences of the closed form.
    fn second_difference(seg: &LinearSegment, tau: f64, h: f64) -> f64 {
        let (m, c, p) = (seg.at_tau(tau - h), seg.at_tau(tau), seg.at_tau(tau + h));
        (p[0] - 2.0 * c[0] + m[0]) / (h * h)
    }

    #[test]
    fn a_ramp_of_ground_acceleration_satisfies_the_equation_of_motion() {
        let (p, alpha) = (2.14, 0.25);
        for side in [1.0, -1.0] {
            let (u0, u1) = (-0.3, 0.8);
            let seg = LinearSegment::linear_ground(p, alpha, side, 1.5, [0.03, -0.2], u0, u1, 4.0);
            assert_eq!(seg.at_tau(0.0), [0.03, -0.2]);
            for &tau in &[1e-3, 0.05, 0.7, 2.4] {
                let y = seg.at_tau(tau);
                let acc = Formulation::Linear.angular_acceleration(
                    p * p,
                    alpha,
                    side,
                    y[0],
                    u0 + u1 * tau,
                );
                let acc_fd = second_difference(&seg, tau, 1e-4);
                assert!(
                    (acc_fd - acc).abs() < 1e-5 * (1.0 + acc.abs()),
                    "{acc_fd} vs {acc}"
                );
                let h = 1e-5;
                let vel_fd = (seg.at_tau(tau + h)[0] - seg.at_tau(tau - h)[0]) / (2.0 * h);
                assert!((vel_fd - y[1]).abs() < 1e-8, "{vel_fd} vs {}", y[1]);
            }
        }
    }

    #[test]
    fn a_constant_ground_is_the_rectangular_pulse() {
        // Housner's rectangular pulse is the cosine with ω = 0: the same motion.
        let block = Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid");
        let pulse = Pulse::new(PulseShape::Rectangular, -3.0 * 0.25 * 9.81, 2.0).expect("valid");
        let r = RockingRhs::new(Formulation::Linear, &block, &pulse, 1.0, true);
        let y0 = [0.04, 0.11];
        let cosine = LinearSegment::new(&r, 0.2, y0);
        let u0 = pulse.amplitude / block.gravity();
        let line = LinearSegment::linear_ground(2.14, r.alpha, 1.0, 0.2, y0, u0, 0.0, 1.0);
        for &tau in &[1e-9, 1e-3, 0.1, 0.5, 1.2] {
            let (a, b) = (cosine.at_tau(tau), line.at_tau(tau));
            assert!(
                (a[0] - b[0]).abs() <= 1e-15 * (1.0 + a[0].abs()),
                "{a:?} vs {b:?}"
            );
            assert!(
                (a[1] - b[1]).abs() <= 1e-15 * (1.0 + a[1].abs()),
                "{a:?} vs {b:?}"
            );
        }
    }

    #[test]
    fn a_ramp_just_past_the_threshold_lifts_the_block_by_its_cubic() {
        // From rest at the threshold (u0 = −α on side +1), the excess grows as
        // −u1 τ: θ = (|u1|/p)(sinh pτ − pτ) ≈ |u1| p² τ³/6, down to 1e-30 rad.
        let (p, alpha, u1) = (2.14, 0.25, -1e-9);
        let seg = LinearSegment::linear_ground(p, alpha, 1.0, 0.0, [0.0, 0.0], -alpha, u1, 1.0);
        for &tau in &[1e-6, 1e-4, 1e-2] {
            let x: f64 = p * tau;
            let series = -u1 / p * x * x * x / 6.0 * (1.0 + x * x / 20.0 + x.powi(4) / 840.0);
            let theta = seg.at_tau(tau)[0];
            assert!(theta > 0.0);
            assert!(
                (theta - series).abs() <= 1e-14 * series,
                "{theta:e} vs {series:e}"
            );
        }
        assert!(seg.at_tau(1e-6)[0] < 1e-25);
    }

    #[test]
    fn a_record_piece_ends_at_its_sample_without_event() {
        // A strong ramp on a short piece: the segment runs to the piece end.
        let (p, alpha) = (2.14, 0.25);
        let seg = LinearSegment::linear_ground(p, alpha, 1.0, 0.0, [0.1, 0.3], -0.1, 2.0, 0.01);
        assert!(matches!(
            first_event(&seg, 0.01, 0.0),
            SegmentEnd::Reached(0.01, _)
        ));
    }

    #[test]
    fn long_segments_are_cut_before_overflow() {
        let r = rhs(1.0, false);
        // Exactly at the unstable equilibrium θ = α: stays there in exact arithmetic.
        let seg = LinearSegment::new(&r, 0.0, [0.25, 0.0]);
        match first_event(&seg, 1e6, 0.0) {
            SegmentEnd::Reached(t, _) => assert!((t - MAX_SEGMENT_PT / 2.14).abs() < 1e-12),
            other => panic!("unexpected {other:?}"),
        }
    }
}
