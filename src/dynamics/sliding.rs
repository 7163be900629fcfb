//! Pure sliding of a rigid block on a rigid floor with Coulomb friction
//! (Shenton 1996; the paper's eqs. 2–3 and 7–9 with the friction force at its
//! limit): the motion of a block that cannot rock, μ_s < tan α — sliding
//! starts before rocking could, and a sliding block's horizontal force, μ_k
//! times its weight, never reaches the tan α times its weight rocking needs.
//!
//! While the block sticks it moves with the ground. It slips once
//! |ü_g| > μ_s (g + ü_v), away from the direction the ground pushes. While it
//! slides (θ = 0, both corners on the floor) its displacement relative to
//! the ground, x, obeys
//!
//!   ẍ = −ü_g − s μ_k (g + ü_v),   s = sgn ẋ,
//!
//! whose right-hand side depends on time only: ẋ and x are the ground's
//! velocity and displacement in closed form ([`Kinematics`]). The block
//! stops where ẋ returns to 0 — located exactly: s ẋ grows only inside the
//! windows where −s ü_g > μ_k (g + ü_v) (the rocking threshold's machinery,
//! [`Forcing::next_rocking`], with μ_k for tan α), so between them it is
//! monotone and its zero is bracketed — and there sticks again when
//! |ü_g| ≤ μ_s (g + ü_v), or slides back. A ground falling away faster
//! than gravity (g + ü_v ≤ 0) ends the history as lift-off.

use super::Pulse;
use super::equations::Threshold;
use super::forcing::{Forcing, Record};
use super::vertical::{PulsePair, RecordPair};

/// Coulomb friction between block and floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    /// μ_s: the static coefficient, at which a sticking block slips.
    pub static_coefficient: f64,
    /// μ_k ≤ μ_s: the kinetic coefficient, while it slides.
    pub kinetic_coefficient: f64,
}

/// Why friction coefficients are not usable.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum FrictionError {
    /// μ_s must be finite and positive.
    #[error("the static friction coefficient must be finite and > 0 (got {0})")]
    Static(f64),
    /// 0 < μ_k ≤ μ_s.
    #[error("the kinetic friction coefficient must satisfy 0 < mu_kinetic <= mu (got {0})")]
    Kinetic(f64),
}

impl Friction {
    /// μ_s and μ_k (μ_s when `None`), checked.
    pub fn new(mu: f64, mu_kinetic: Option<f64>) -> Result<Self, FrictionError> {
        if !(mu.is_finite() && mu > 0.0) {
            return Err(FrictionError::Static(mu));
        }
        let k = mu_kinetic.unwrap_or(mu);
        if !(k.is_finite() && k > 0.0 && k <= mu) {
            return Err(FrictionError::Kinetic(k));
        }
        Ok(Friction {
            static_coefficient: mu,
            kinetic_coefficient: k,
        })
    }
}

/// The ground's velocity and displacement from rest at t = 0, in closed
/// form: (horizontal, vertical), each (m/s, m).
pub trait Kinematics: Forcing {
    /// ((v_g, u_g), (v_v, u_v)) at `t`.
    fn kinematics(&self, t: f64) -> ((f64, f64), (f64, f64));
}

impl Kinematics for Pulse {
    #[inline]
    fn kinematics(&self, t: f64) -> ((f64, f64), (f64, f64)) {
        (self.ground_motion(t), (0.0, 0.0))
    }
}

impl Kinematics for PulsePair {
    #[inline]
    fn kinematics(&self, t: f64) -> ((f64, f64), (f64, f64)) {
        (
            self.horizontal.ground_motion(t),
            self.vertical.ground_motion(t - self.delay),
        )
    }
}

impl Kinematics for Record {
    #[inline]
    fn kinematics(&self, t: f64) -> ((f64, f64), (f64, f64)) {
        (Record::kinematics(self, t), (0.0, 0.0))
    }
}

impl Kinematics for RecordPair {
    #[inline]
    fn kinematics(&self, t: f64) -> ((f64, f64), (f64, f64)) {
        (self.horizontal.kinematics(t), self.vertical.kinematics(t))
    }
}

/// One slide: from a standstill relative to the ground to the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slide {
    /// Start, s.
    pub from: f64,
    /// End (ẋ = 0 again), s.
    pub to: f64,
    /// s = sgn ẋ: +1 when the block moves forward relative to the ground.
    pub direction: f64,
    /// x at the start, m.
    pub x_from: f64,
    /// x at the end, m.
    pub x_to: f64,
}

/// The sliding history of a block.
#[derive(Clone, Debug, PartialEq)]
pub struct Sliding {
    /// The slides in time order (a reversal starts one where the last ends).
    pub slides: Vec<Slide>,
    /// Displacement relative to the ground at the end (where it lifts off,
    /// if it does: a slide cut short there is not in `slides`), m.
    pub residual: f64,
    /// max |x|, m (x is monotone within a slide: reached at a slide's end).
    pub peak: f64,
    /// Total time sliding, s.
    pub time_sliding: f64,
    /// When the ground first fell away faster than gravity (g + ü_v ≤ 0),
    /// if it did: the history ends there, the block leaves the floor.
    pub lift_off: Option<f64>,
}

/// The state of a slide of direction `s` started at `t0` from (x0, v0):
/// (x, ẋ) at `t`, from the ground's kinematics in closed form.
pub(crate) struct Leg<'a, G> {
    forcing: &'a G,
    g: f64,
    mu_k: f64,
    s: f64,
    t0: f64,
    x0: f64,
    v0: f64,
    /// The ground's kinematics at t0.
    at0: ((f64, f64), (f64, f64)),
}

impl<'a, G: Kinematics> Leg<'a, G> {
    /// A slide of direction `s` from (`x0`, `v0`) at `t0`.
    pub(crate) fn new(
        forcing: &'a G,
        g: f64,
        mu_k: f64,
        s: f64,
        t0: f64,
        x0: f64,
        v0: f64,
    ) -> Self {
        Leg {
            forcing,
            g,
            mu_k,
            s,
            t0,
            x0,
            v0,
            at0: forcing.kinematics(t0),
        }
    }

    /// ẋ at `t`.
    pub(crate) fn velocity(&self, t: f64) -> f64 {
        let ((vg, _), (vv, _)) = self.forcing.kinematics(t);
        let ((vg0, _), (vv0, _)) = self.at0;
        self.v0 - (vg - vg0) - self.s * self.mu_k * (self.g * (t - self.t0) + (vv - vv0))
    }

    /// x at `t`.
    pub(crate) fn displacement(&self, t: f64) -> f64 {
        let tau = t - self.t0;
        let ((_, ug), (_, uv)) = self.forcing.kinematics(t);
        let ((vg0, ug0), (vv0, uv0)) = self.at0;
        self.x0 + self.v0 * tau
            - (ug - ug0 - vg0 * tau)
            - self.s * self.mu_k * (0.5 * self.g * tau * tau + (uv - uv0 - vv0 * tau))
    }

    /// The zero of s ẋ on [a, b], where s ẋ(a) > 0 ≥ s ẋ(b) and s ẋ does
    /// not increase: bisection to adjacent floating-point times.
    fn stop_between(&self, mut a: f64, mut b: f64) -> f64 {
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if self.s * self.velocity(m) > 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        b
    }
}

/// The slides of a block that cannot rock under `forcing`, with gravity
/// `gravity` (m/s²) and `friction`, from rest at t = 0 until the block
/// sticks for good after the motion ends (or lifts off).
pub fn slide<G: Kinematics>(forcing: &G, gravity: f64, friction: Friction) -> Sliding {
    let (mu_s, mu_k) = (friction.static_coefficient, friction.kinetic_coefficient);
    let slip = Threshold {
        level: mu_s * gravity,
        factor: mu_s,
        gravity,
    };
    let drive = Threshold {
        level: mu_k * gravity,
        factor: mu_k,
        gravity,
    };
    let weightless = forcing.next_weightless(0.0, gravity);
    let mut out = Sliding {
        slides: Vec::new(),
        residual: 0.0,
        peak: 0.0,
        time_sliding: 0.0,
        lift_off: None,
    };
    let (mut t, mut x) = (0.0f64, 0.0f64);
    // The next slip from a standstill at t.
    let mut next = forcing.next_rocking(t, &slip);
    while let Some(w) = next {
        if let Some(l) = weightless.filter(|&l| l <= w.start) {
            out.lift_off = Some(l);
            break;
        }
        let leg = Leg {
            forcing,
            g: gravity,
            mu_k,
            s: w.side,
            t0: w.start,
            x0: x,
            v0: 0.0,
            at0: forcing.kinematics(w.start),
        };
        let end = stop(&leg, &drive);
        if let Some(l) = weightless.filter(|&l| l < end) {
            out.lift_off = Some(l);
            x = leg.displacement(l);
            out.time_sliding += l - w.start;
            out.peak = out.peak.max(x.abs());
            break;
        }
        let x_end = leg.displacement(end);
        out.slides.push(Slide {
            from: w.start,
            to: end,
            direction: w.side,
            x_from: x,
            x_to: x_end,
        });
        out.time_sliding += end - w.start;
        out.peak = out.peak.max(x_end.abs());
        (t, x) = (end, x_end);
        // Stuck again unless the ground already pulls it the other way
        // beyond μ_s (a slip window open at the stop).
        next = forcing.next_rocking(t, &slip);
    }
    out.residual = x;
    out
}

/// Where the slide `leg` stops: the first zero of s ẋ after its start. s ẋ
/// grows only inside the windows of side s where −s ü_g > μ_k (g + ü_v)
/// (`drive`); each stretch between them is searched in turn, and after the
/// motion's end ẍ = −s μ_k g is constant: the stop is in closed form. A
/// slide still running where the ground first falls away (g + ü_v ≤ 0)
/// ends there.
pub(crate) fn stop<G: Kinematics>(leg: &Leg<'_, G>, drive: &Threshold) -> f64 {
    let end = leg.forcing.duration();
    let mut a = leg.t0;
    let lift = leg.forcing.next_weightless(a, leg.g);
    loop {
        // The next window driving the slide on, from a (skipping the other
        // side's, where s ẋ falls all the more).
        let mut from = a;
        let mut window = None;
        while let Some(w) = leg.forcing.next_rocking(from, drive) {
            if w.side == leg.s {
                window = Some(w);
                break;
            }
            if w.end <= from {
                break;
            }
            from = w.end;
        }
        // Where the ground falls away (g + ü_v ≤ 0) the slide ends, the
        // block leaving the floor (the caller's concern): the friction
        // there would not oppose the slip, so no stop is looked for past it.
        let next = window.map_or(f64::INFINITY, |w| w.start.max(a));
        if let Some(l) = lift.filter(|&l| l <= next.min(a.max(end))) {
            if leg.s * leg.velocity(l) <= 0.0 {
                return leg.stop_between(a, l);
            }
            return l;
        }
        match window {
            Some(w) if w.start <= a => {
                // Inside a driving window: s ẋ grows to its end.
                if w.end <= a {
                    // A window of no width: step past it.
                    a = next_after(a);
                } else {
                    a = w.end;
                }
            }
            Some(w) => {
                // s ẋ does not increase on [a, w.start].
                if leg.s * leg.velocity(w.start) <= 0.0 {
                    return leg.stop_between(a, w.start);
                }
                a = w.end.max(w.start);
            }
            None => {
                // No driving window left: s ẋ falls to the end of the motion
                // and then at the rate μ_k g.
                let te = a.max(end);
                let v_end = leg.s * leg.velocity(te);
                if v_end <= 0.0 {
                    return leg.stop_between(a, te);
                }
                return te + v_end / (leg.mu_k * leg.g);
            }
        }
    }
}

/// The next floating-point time after `t` (t ≥ 0).
fn next_after(t: f64) -> f64 {
    if t == 0.0 {
        f64::MIN_POSITIVE
    } else {
        f64::from_bits(t.to_bits() + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::PulseShape;

    const G: f64 = 9.81;

    #[test]
    fn a_rectangular_pulse_slides_the_block_as_the_closed_form() {
        // a_p = 0.5 g for T = π/ω s on μ = 0.2: relative acceleration
        // −(a_p − μ g) during the pulse, then μ g deceleration to a stop.
        for (a_g, mu, omega) in [(0.5, 0.2, 6.0), (1.2, 0.35, 2.0), (0.31, 0.3, 20.0)] {
            let pulse = Pulse::new(PulseShape::Rectangular, a_g * G, omega).expect("valid");
            let t_p = pulse.duration;
            let f = Friction::new(mu, None).expect("valid");
            let s = slide(&pulse, G, f);
            let d = (a_g - mu) * G;
            let (v_end, x_end) = (-d * t_p, -0.5 * d * t_p * t_p);
            let t_stop = t_p + d * t_p / (mu * G);
            let x_final = x_end - v_end * v_end / (2.0 * mu * G);
            assert_eq!(s.slides.len(), 1, "{s:?}");
            let one = s.slides[0];
            assert_eq!(one.from, 0.0);
            assert_eq!(one.direction, -1.0);
            assert!(
                (one.to - t_stop).abs() <= 1e-10 * t_stop,
                "{} vs {t_stop}",
                one.to
            );
            assert!(
                (s.residual - x_final).abs() <= 1e-10 * x_final.abs(),
                "{} vs {x_final}",
                s.residual
            );
            assert_eq!(s.peak, s.residual.abs());
            assert!((s.time_sliding - t_stop).abs() <= 1e-10 * t_stop);
            assert_eq!(s.lift_off, None);
            // At the pulse's end, the displacement of the closed form.
            let leg = Leg {
                forcing: &pulse,
                g: G,
                mu_k: mu,
                s: -1.0,
                t0: 0.0,
                x0: 0.0,
                v0: 0.0,
                at0: pulse.kinematics(0.0),
            };
            assert!((leg.displacement(t_p) - x_end).abs() <= 1e-12 * x_end.abs());
            assert!((leg.velocity(t_p) - v_end).abs() <= 1e-12 * v_end.abs());
        }
    }

    #[test]
    fn each_slide_balances_kinetic_energy_and_the_work_of_friction() {
        // In the ground's absolute frame the block's velocity is v_g + ẋ; a
        // slide starts and ends with ẋ = 0, and the only horizontal force on
        // the block is friction, −s μ_k m g: ½(v_g(t1)² − v_g(t0)²) =
        // −s μ_k g (Δu_g + Δx). Of that work, μ_k g |Δx| is dissipated.
        let mut slides = 0;
        for (shape, a_g, omega, mu, mu_k) in [
            (PulseShape::OneSine, 0.6, 6.0, 0.2, 0.2),
            (PulseShape::OneSine, 1.5, 3.0, 0.3, 0.25),
            (PulseShape::OneCosine, 0.8, 8.0, 0.25, 0.15),
            (PulseShape::Ricker { symmetric: true }, 1.0, 5.0, 0.3, 0.3),
            (PulseShape::Cn(3), 0.9, 10.0, 0.2, 0.1),
        ] {
            let pulse = Pulse::new(shape, a_g * G, omega).expect("valid");
            let s = slide(&pulse, G, Friction::new(mu, Some(mu_k)).expect("valid"));
            assert!(!s.slides.is_empty(), "{shape:?} slides");
            for w in &s.slides {
                let ((v0, u0), _) = pulse.kinematics(w.from);
                let ((v1, u1), _) = pulse.kinematics(w.to);
                let kinetic = 0.5 * (v1 * v1 - v0 * v0);
                let work = -w.direction * mu_k * G * (u1 - u0 + w.x_to - w.x_from);
                let scale = kinetic.abs().max(work.abs()).max(1e-12);
                assert!(
                    (kinetic - work).abs() <= 1e-9 * scale,
                    "{shape:?} {w:?}: {kinetic} vs {work}"
                );
                // x moves the slide's way: friction dissipates μ_k g |Δx|.
                assert!(w.direction * (w.x_to - w.x_from) >= 0.0, "{w:?}");
                slides += 1;
            }
            // A reversal starts where the last slide ends; otherwise the
            // block sticks in between.
            for pair in s.slides.windows(2) {
                assert!(pair[1].from >= pair[0].to);
                assert_eq!(pair[1].x_from, pair[0].x_to);
            }
            assert_eq!(s.residual, s.slides.last().expect("one").x_to);
        }
        assert!(slides >= 8, "{slides} slides");
    }

    #[test]
    fn a_vertical_pulse_presses_or_lightens_the_block() {
        // ü_v = r ü_g in phase: slipping where |ü_g| > μ (g + r ü_g). A
        // ratio of 0 is the block without one; a ground falling faster than
        // g lifts the block off.
        let h = Pulse::new(PulseShape::OneSine, 0.6 * G, 6.0).expect("valid");
        let f = Friction::new(0.2, None).expect("valid");
        let alone = slide(&h, G, f);
        let lighter = slide(&PulsePair::proportional(h, -0.5).expect("ratio"), G, f);
        let heavier = slide(&PulsePair::proportional(h, 0.5).expect("ratio"), G, f);
        // Forward ground acceleration first: the block slides backward, the
        // farther the lighter the ground's forward push makes it; the pulse's
        // second half turns it round at once (its stop is a reversal).
        assert!(lighter.peak > alone.peak && alone.peak > heavier.peak);
        for s in [&alone, &lighter, &heavier] {
            assert_eq!(s.slides.len(), 2, "{s:?}");
            assert_eq!((s.slides[0].direction, s.slides[1].direction), (-1.0, 1.0));
            assert_eq!(s.slides[1].from, s.slides[0].to);
            assert_eq!(s.peak, -s.slides[0].x_to);
        }
        // The first slip where 0.6 g sin(ω t) = 0.2 (g − 0.5·0.6 g sin(ω t)).
        let start = |s: &Sliding| s.slides[0].from;
        let expected = (0.2f64 / (0.6 * (1.0 + 0.2 * 0.5))).asin() / 6.0;
        assert!(
            (start(&lighter) - expected).abs() < 1e-12,
            "{}",
            start(&lighter)
        );
        let falling = PulsePair::proportional(h, -2.0).expect("ratio");
        let lifted = slide(&falling, G, f);
        let l = lifted.lift_off.expect("lifts off");
        assert!((l - (1.0f64 / 1.2).asin() / 6.0).abs() < 1e-9, "{l}");
    }

    #[test]
    fn below_the_static_coefficient_the_block_sticks() {
        let pulse = Pulse::new(PulseShape::OneSine, 0.19 * G, 5.0).expect("valid");
        let s = slide(&pulse, G, Friction::new(0.2, None).expect("valid"));
        assert!(s.slides.is_empty());
        assert_eq!((s.residual, s.peak, s.time_sliding), (0.0, 0.0, 0.0));
    }

    #[test]
    fn friction_coefficients_are_checked() {
        assert!(Friction::new(0.0, None).is_err());
        assert!(Friction::new(f64::NAN, None).is_err());
        assert!(Friction::new(0.3, Some(0.4)).is_err());
        assert!(Friction::new(0.3, Some(0.0)).is_err());
        assert_eq!(
            Friction::new(0.3, Some(0.2))
                .expect("valid")
                .kinetic_coefficient,
            0.2
        );
    }
}
