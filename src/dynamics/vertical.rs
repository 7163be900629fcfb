//! Ground motion with a vertical component ü_v (positive up) beside the
//! horizontal ü_g: a pair of pulses, or a pair of records on the same samples.
//!
//! In the block's frame the vertical acceleration adds to gravity: eq. 12
//! becomes
//!
//! ```text
//! θ̈ = −p² { (1 + ü_v/g) sin(α sgn θ − θ) + (ü_g/g) cos(α sgn θ − θ) }
//! ```
//!
//! (the linear eq. 50 likewise, with 1 + ü_v/g on the restoring term); rocking
//! starts once |ü_g| exceeds (g + ü_v) tan α ((g + ü_v) α linear), towards the
//! side the ground pushes the block to; the reactions (eqs. 2–3, 16–19) carry
//! g + ü_v; impacts keep Housner's η (eqs. 13–15). Where g + ü_v ≤ 0 nothing
//! holds the block on the ground ([`Forcing::next_weightless`]).
//!
//! The threshold is crossed where s ü_g − k ü_v = k g (s = ±1 the sign of
//! ü_g, k = tan α or α). On a pair of records both sides are linear between
//! samples, and the crossing is solved there in closed form. On a pair of
//! pulses they are located by bisection on the pieces between the turning
//! points of either pulse, where each is monotone: there the ends bound s ü_g
//! − k ü_v from above, pieces that cannot reach the level are passed over,
//! and the first crossing is found to the last bit.

use std::f64::consts::PI;
use std::sync::Arc;

use super::block::Block;
use super::equations::{Formulation, RockingRhs, Threshold};
use super::exact::LinearSegment;
use super::excitation::{Exceedance, Pulse, Wave};
use super::forcing::{Forcing, Record, RecordError, RecordRhs};
use super::integrator::{Rhs, State};

/// A right-hand side's ground term ü/g at t (zero when free).
pub trait GroundTerm {
    /// ü/g at `t` (no support check).
    fn over_g(&self, t: f64) -> f64;
}

impl GroundTerm for RockingRhs {
    #[inline]
    fn over_g(&self, t: f64) -> f64 {
        self.ground(t)
    }
}

impl GroundTerm for RecordRhs<'_> {
    #[inline]
    fn over_g(&self, t: f64) -> f64 {
        self.ground(t)
    }
}

/// The right-hand side of the rocking equation under ü_g and ü_v.
#[derive(Clone, Copy, Debug)]
pub struct VerticalRhs<R> {
    formulation: Formulation,
    p2: f64,
    alpha: f64,
    side: f64,
    horizontal: R,
    vertical: R,
    /// Where each component acts, s (zero outside).
    h_support: (f64, f64),
    v_support: (f64, f64),
    /// The vertical component's own time starts this late, s.
    delay: f64,
    /// ü_v/ü_g of a proportional pair: the vertical term is the horizontal
    /// one's times this, not evaluated again.
    ratio: Option<f64>,
}

impl<R: GroundTerm> VerticalRhs<R> {
    /// (ü_g/g, 1 + ü_v/g) at t.
    #[inline]
    pub fn ground(&self, t: f64) -> (f64, f64) {
        let u = if t >= self.h_support.0 && t <= self.h_support.1 {
            self.horizontal.over_g(t)
        } else {
            0.0
        };
        if let Some(r) = self.ratio {
            return (u, 1.0 + r * u);
        }
        let v = if t >= self.v_support.0 && t <= self.v_support.1 {
            self.vertical.over_g(t - self.delay)
        } else {
            0.0
        };
        (u, 1.0 + v)
    }
}

impl<R: GroundTerm> Rhs for VerticalRhs<R> {
    #[inline]
    fn eval(&self, t: f64, y: State) -> State {
        let (u, weight) = self.ground(t);
        [
            y[1],
            self.formulation
                .angular_acceleration_weighted(self.p2, self.alpha, self.side, y[0], u, weight),
        ]
    }
}

/// The infimum of {t ∈ [lo, hi] : f(t) > level}, given f(lo) ≤ level and
/// `upper(a, b)` ≥ f on every [a, b] inside; `None` if f stays at or below
/// the level (a window narrower than the spacing of floating-point times is
/// passed over). Left halves first: the first crossing, not any.
fn first_above<F: Fn(f64) -> f64, U: Fn(f64, f64) -> f64>(
    f: &F,
    upper: &U,
    lo: f64,
    hi: f64,
    level: f64,
) -> Option<f64> {
    if upper(lo, hi) <= level {
        return None;
    }
    let mid = 0.5 * (lo + hi);
    if !(mid > lo && mid < hi) {
        return (f(hi) > level).then_some(hi);
    }
    if let Some(t) = first_above(f, upper, lo, mid, level) {
        return Some(t);
    }
    if f(mid) > level {
        return Some(mid);
    }
    first_above(f, upper, mid, hi, level)
}

/// Steps of [`first_above_curved`] before it hands over to bisection.
const CURVED_STEPS: usize = 200;

/// The infimum of {t ∈ [lo, hi] : f(t) > level} as [`first_above`], given
/// f(lo) ≤ level and |f″| ≤ `curvature` on [lo, hi]; `f_slope` gives f and
/// f′. From x with f(x) ≤ level the parabola f(x) + f′(x)τ + ½Mτ² bounds f
/// from above, so f stays at or below the level until its first root τ:
/// stepping by τ never passes a crossing, and at a simple one it is Newton's
/// step from below (quadratic). `Err(x)` when the steps stall short of the
/// end (f touching the level), f being at or below it on [lo, x]: the
/// caller goes on from x by bisection.
fn first_above_curved<F: Fn(f64) -> (f64, f64)>(
    f_slope: &F,
    curvature: f64,
    lo: f64,
    hi: f64,
    level: f64,
) -> Result<Option<f64>, f64> {
    let at_end = || (f_slope(hi).0 > level).then_some(hi);
    let mut x = lo;
    let mut stalls = 0;
    for _ in 0..CURVED_STEPS {
        let (value, slope) = f_slope(x);
        let gap = level - value;
        if gap < 0.0 {
            return Ok(Some(x));
        }
        // The smallest τ > 0 with −gap + f′τ + ½Mτ² = 0 (none: infinite).
        let root = (slope * slope + 2.0 * curvature * gap).sqrt();
        let tau = if slope > 0.0 {
            2.0 * gap / (slope + root)
        } else if curvature > 0.0 {
            (root - slope) / curvature
        } else {
            f64::INFINITY
        };
        let next = x + tau;
        // (A NaN step ends the search as one past the piece does.)
        if next.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
            return Ok(at_end());
        }
        if next > x {
            x = next;
            continue;
        }
        // A step below half an ulp: the crossing is at the next time, or f
        // only touches the level here.
        let up = x.next_up();
        if up >= hi {
            return Ok(at_end());
        }
        if f_slope(up).0 > level {
            return Ok(Some(up));
        }
        x = up;
        stalls += 1;
        if stalls > 4 {
            break;
        }
    }
    Err(x)
}

/// A horizontal pulse and a vertical one whose own time starts `delay`
/// seconds later (ü_v(t) = vertical(t − delay)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulsePair {
    /// ü_g.
    pub horizontal: Pulse,
    /// ü_v, from `delay` on.
    pub vertical: Pulse,
    /// Start of the vertical pulse, s (≥ 0).
    pub delay: f64,
    /// End of the later of the two, s.
    end: f64,
    /// ü_v/ü_g when the vertical pulse is the horizontal one scaled (in
    /// phase, no delay): the rocking windows and the demand at rest then
    /// follow from the horizontal pulse alone, in closed form.
    ratio: Option<f64>,
}

/// The times where a pulse starting at `shift` turns (its extrema inside, its
/// ends), pushed onto `out`: between two of them ü is continuous and monotone.
fn turning_points(p: &Pulse, shift: f64, out: &mut Vec<f64>) {
    out.push(shift);
    out.push(shift + p.duration);
    match p.wave {
        Wave::Cosine if p.carrier > 0.0 => {
            // cos(ω t + φ) turns where ω t + φ = mπ.
            let mut m = (p.phase / PI).floor() + 1.0;
            loop {
                let t = (m * PI - p.phase) / p.carrier;
                if t >= p.duration {
                    break;
                }
                if t > 0.0 {
                    out.push(shift + t);
                }
                m += 1.0;
            }
        }
        Wave::Cosine => {}
        _ => out.extend(p.extrema.as_slice().iter().map(|t| t + shift)),
    }
}

impl PulsePair {
    /// ü_g = `horizontal`, ü_v = `vertical` from `delay` s on. A vertical
    /// pulse of the horizontal's very shape, frequency and time is the
    /// horizontal one times the ratio of their amplitudes: the pair is then
    /// proportional ([`PulsePair::proportional`]), its vertical term read off
    /// the horizontal one rather than evaluated again.
    pub fn new(horizontal: Pulse, vertical: Pulse, delay: f64) -> Self {
        let pair = PulsePair::unmarked(horizontal, vertical, delay);
        let same_shape = pair.delay == 0.0
            && horizontal.amplitude != 0.0
            && vertical.with_amplitude(horizontal.amplitude) == horizontal;
        let ratio = vertical.amplitude / horizontal.amplitude;
        PulsePair {
            ratio: (same_shape && ratio != 0.0 && ratio.is_finite()).then_some(ratio),
            ..pair
        }
    }

    /// The pair as given, its vertical pulse evaluated on its own whatever
    /// its shape.
    fn unmarked(horizontal: Pulse, vertical: Pulse, delay: f64) -> Self {
        let delay = delay.max(0.0);
        PulsePair {
            horizontal,
            vertical,
            delay,
            end: horizontal.duration.max(delay + vertical.duration),
            ratio: None,
        }
    }

    /// Both pulses' amplitudes times `factor` (a proportional pair stays one).
    pub fn scaled(&self, factor: f64) -> Self {
        PulsePair {
            horizontal: self
                .horizontal
                .with_amplitude(self.horizontal.amplitude * factor),
            vertical: self
                .vertical
                .with_amplitude(self.vertical.amplitude * factor),
            ..*self
        }
    }

    /// ü_v = `ratio`·ü_g, in phase; `None` for a ratio of 0 (no vertical
    /// motion) or one that is not finite.
    pub fn proportional(horizontal: Pulse, ratio: f64) -> Option<Self> {
        (ratio != 0.0 && ratio.is_finite()).then(|| PulsePair {
            ratio: Some(ratio),
            ..PulsePair::unmarked(
                horizontal,
                horizontal.with_amplitude(ratio * horizontal.amplitude),
                0.0,
            )
        })
    }

    /// ü_g on a piece whose inside holds `mid` (continued to the piece's ends).
    #[inline]
    fn h_on(&self, t: f64, mid: f64) -> f64 {
        if (0.0..=self.horizontal.duration).contains(&mid) {
            self.horizontal.amplitude * self.horizontal.unit(t)
        } else {
            0.0
        }
    }

    /// ü_v on a piece whose inside holds `mid` (continued to the piece's ends).
    #[inline]
    fn v_on(&self, t: f64, mid: f64) -> f64 {
        let (tv, mv) = (t - self.delay, mid - self.delay);
        if (0.0..=self.vertical.duration).contains(&mv) {
            self.vertical.amplitude * self.vertical.unit(tv)
        } else {
            0.0
        }
    }

    /// (ü_g, dü_g/dt) on a piece whose inside holds `mid`.
    #[inline]
    fn h_slope_on(&self, t: f64, mid: f64) -> (f64, f64) {
        let p = &self.horizontal;
        if (0.0..=p.duration).contains(&mid) {
            let (u, du) = p.unit_and_slope(t);
            (p.amplitude * u, p.amplitude * du)
        } else {
            (0.0, 0.0)
        }
    }

    /// (ü_v, dü_v/dt) on a piece whose inside holds `mid`.
    #[inline]
    fn v_slope_on(&self, t: f64, mid: f64) -> (f64, f64) {
        let p = &self.vertical;
        if (0.0..=p.duration).contains(&(mid - self.delay)) {
            let (u, du) = p.unit_and_slope(t - self.delay);
            (p.amplitude * u, p.amplitude * du)
        } else {
            (0.0, 0.0)
        }
    }

    /// A bound on |s ü_g″ − k ü_v″| on a piece whose inside holds `mid`;
    /// `None` where a pulse acting there has none in closed form.
    fn curvature_on(&self, mid: f64, k: f64) -> Option<f64> {
        let bound = |p: &Pulse, own: f64| {
            if (0.0..=p.duration).contains(&own) {
                p.unit_curvature_bound().map(|m| p.amplitude.abs() * m)
            } else {
                Some(0.0)
            }
        };
        Some(bound(&self.horizontal, mid)? + k.abs() * bound(&self.vertical, mid - self.delay)?)
    }

    /// [`Forcing::next_rocking`] of a proportional pair, ü_v = r ü_g: where
    /// ü_g > 0 the block rocks once ü_g (1 − k r) > k g, where ü_g < 0 once
    /// |ü_g| (1 + k r) > k g: windows of |ü_g| over a level of each sign,
    /// found by the horizontal pulse's own closed form
    /// ([`Pulse::next_exceedance`]) at the lower level, and within a window
    /// of the sign whose level is higher, at that one.
    fn proportional_rocking(&self, from: f64, k: f64, level: f64, r: f64) -> Option<Exceedance> {
        // The level of each sign of ü_g (infinite where it cannot rock).
        let of = |d: f64| if d > 0.0 { level / d } else { f64::INFINITY };
        let (up, down) = (of(1.0 - k * r), of(1.0 + k * r));
        let (low, high) = (up.min(down), up.max(down));
        // Side −1 is ü_g > 0.
        let low_side = if up <= down { -1.0 } else { 1.0 };
        let h = &self.horizontal;
        let mut from = from;
        // At most one pass per half-wave of the pulse.
        for _ in 0..100_000 {
            let w = h.next_exceedance(from, low)?;
            if w.side == low_side || low == high {
                return Some(w);
            }
            // A lobe of the other sign: rocking only where it passes its own,
            // higher, level.
            if let Some(v) = h.next_exceedance(w.start, high)
                && v.start < w.end
            {
                return Some(v);
            }
            if w.end <= from {
                return None;
            }
            from = w.end;
        }
        None
    }

    /// The pieces' ends after `from` (sorted, the motion's end last).
    fn cuts_after(&self, from: f64) -> Vec<f64> {
        let mut cuts = Vec::with_capacity(16);
        turning_points(&self.horizontal, 0.0, &mut cuts);
        turning_points(&self.vertical, self.delay, &mut cuts);
        cuts.retain(|&t| t > from && t <= self.end);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        cuts
    }

    /// The first crossing on [a, b] (with f(a) ≤ level on both sides) of
    /// s ü_g − k ü_v above `level`, side s = ±1 first, or where that falls
    /// back to or below it (`back`). Where both pulses have a curvature
    /// bound it is stepped to from below ([`first_above_curved`]);
    /// otherwise, or from where that stalls, bisected.
    fn crossing_on(&self, a: f64, b: f64, s: f64, k: f64, level: f64, back: bool) -> Option<f64> {
        let mid = 0.5 * (a + b);
        let sign = if back { -1.0 } else { 1.0 };
        let Some(curvature) = self.curvature_on(mid, k) else {
            return self.bisected_crossing(a, b, mid, s, k, level, back);
        };
        let f_slope = |t: f64| {
            let ((h, dh), (v, dv)) = (self.h_slope_on(t, mid), self.v_slope_on(t, mid));
            (sign * (s * h - k * v), sign * (s * dh - k * dv))
        };
        match first_above_curved(&f_slope, curvature, a, b, sign * level) {
            Ok(t) => t,
            Err(x) => self.bisected_crossing(x, b, mid, s, k, level, back),
        }
    }

    /// [`crossing_on`](Self::crossing_on) by bisection ([`first_above`]) on
    /// [a, b] inside the piece holding `mid`, where each component is
    /// monotone: its ends bound it.
    #[allow(clippy::too_many_arguments)]
    fn bisected_crossing(
        &self,
        a: f64,
        b: f64,
        mid: f64,
        s: f64,
        k: f64,
        level: f64,
        back: bool,
    ) -> Option<f64> {
        let sign = if back { -1.0 } else { 1.0 };
        let f = |t: f64| sign * (s * self.h_on(t, mid) - k * self.v_on(t, mid));
        let upper = |x: f64, y: f64| {
            let (h0, h1) = (s * self.h_on(x, mid), s * self.h_on(y, mid));
            let (v0, v1) = (k * self.v_on(x, mid), k * self.v_on(y, mid));
            if back {
                v0.max(v1) - h0.min(h1)
            } else {
                h0.max(h1) - v0.min(v1)
            }
        };
        first_above(&f, &upper, a, b, sign * level)
    }
}

impl Forcing for PulsePair {
    type Rhs<'a> = VerticalRhs<RockingRhs>;

    const VERTICAL: bool = true;

    fn rhs(
        &self,
        formulation: Formulation,
        block: &Block,
        side: f64,
        forced: bool,
    ) -> VerticalRhs<RockingRhs> {
        VerticalRhs {
            formulation,
            p2: block.frequency_parameter().powi(2),
            alpha: block.slenderness(),
            side,
            horizontal: RockingRhs::new(formulation, block, &self.horizontal, side, forced),
            vertical: RockingRhs::new(formulation, block, &self.vertical, side, forced),
            h_support: (0.0, self.horizontal.duration),
            v_support: (self.delay, self.delay + self.vertical.duration),
            delay: self.delay,
            ratio: self.ratio,
        }
    }

    fn linear_segment(
        _rhs: &VerticalRhs<RockingRhs>,
        _t0: f64,
        _y0: State,
    ) -> Option<(LinearSegment, f64)> {
        None
    }

    #[inline]
    fn acceleration(&self, t: f64) -> f64 {
        self.horizontal.acceleration(t)
    }

    #[inline]
    fn vertical_acceleration(&self, t: f64) -> f64 {
        self.vertical.acceleration(t - self.delay)
    }

    fn duration(&self) -> f64 {
        self.end
    }

    fn next_exceedance(&self, from: f64, threshold: f64) -> Option<Exceedance> {
        self.horizontal.next_exceedance(from, threshold)
    }

    fn next_rocking(&self, from: f64, threshold: &Threshold) -> Option<Exceedance> {
        let (k, level) = (threshold.factor, threshold.level);
        let from = from.max(0.0);
        if from >= self.end {
            return None;
        }
        if let Some(r) = self.ratio {
            return self.proportional_rocking(from, k, level, r);
        }
        let cuts = self.cuts_after(from);
        // The start and the sign s of ü_g there.
        let mut found = None;
        let mut a = from;
        for (i, &b) in cuts.iter().enumerate() {
            let mid = 0.5 * (a + b);
            let f = |t: f64, s: f64| s * self.h_on(t, mid) - k * self.v_on(t, mid);
            let first = [1.0, -1.0]
                .into_iter()
                .filter_map(|s| {
                    if f(a, s) > level {
                        Some((a, s))
                    } else {
                        self.crossing_on(a, b, s, k, level, false).map(|t| (t, s))
                    }
                })
                .min_by(|x, y| x.0.total_cmp(&y.0));
            if let Some(start) = first {
                found = Some((start, i));
                break;
            }
            a = b;
        }
        let ((start, s), i) = found?;
        // The window closes where s ü_g − k ü_v falls back to k g.
        let mut a = start;
        let mut end = self.end;
        for &b in &cuts[i..] {
            if let Some(t) = self.crossing_on(a, b, s, k, level, true) {
                end = t;
                break;
            }
            a = b;
        }
        Some(Exceedance {
            start,
            end: end.max(start),
            side: -s,
        })
    }

    fn rocks_before(&self, from: f64, until: f64, threshold: &Threshold) -> bool {
        self.next_rocking(from, threshold)
            .is_some_and(|e| e.start <= until)
    }

    fn next_weightless(&self, from: f64, gravity: f64) -> Option<f64> {
        // ü_v < −g: a window of |ü_v| > g where ü_v is negative.
        let mut own = (from - self.delay).max(0.0);
        for _ in 0..64 {
            let e = self.vertical.next_exceedance(own, gravity)?;
            if e.side > 0.0 {
                return Some(e.start + self.delay);
            }
            if e.end <= own {
                return None;
            }
            own = e.end;
        }
        None
    }

    #[inline]
    fn breakpoint_after(&self, t: f64) -> f64 {
        // The ends of either pulse: inside, both are smooth.
        [
            self.horizontal.duration,
            self.delay,
            self.delay + self.vertical.duration,
        ]
        .into_iter()
        .filter(|&b| b > t)
        .fold(f64::INFINITY, f64::min)
    }

    fn resolving_frequency(&self) -> f64 {
        self.horizontal
            .resolving_frequency()
            .max(self.vertical.resolving_frequency())
    }

    fn peak_between(&self, ta: f64, tb: f64) -> (f64, f64) {
        self.horizontal.peak_between(ta, tb)
    }

    fn rest_demand_peak(&self, ta: f64, tb: f64, gravity: f64) -> (f64, f64) {
        if let Some(r) = self.ratio {
            // |ü_g|/(g + r ü_g) grows with |ü_g| on either sign of ü_g: its
            // maximum is at an end or where ü_g turns.
            let demand = |t: f64| {
                let u = self.horizontal.acceleration(t);
                let fz = gravity + r * u;
                if fz > 0.0 {
                    u.abs() / fz
                } else {
                    f64::INFINITY
                }
            };
            let mut cuts = Vec::with_capacity(16);
            turning_points(&self.horizontal, 0.0, &mut cuts);
            return cuts
                .into_iter()
                .filter(|&t| t > ta && t < tb)
                .chain([ta, tb])
                .map(|t| (demand(t), t))
                .fold(
                    (f64::NEG_INFINITY, ta),
                    |b, c| if c.0 > b.0 { c } else { b },
                );
        }
        let demand = |t: f64, mid: f64| {
            let fz = gravity + self.v_on(t, mid);
            if fz > 0.0 {
                self.h_on(t, mid).abs() / fz
            } else {
                f64::INFINITY
            }
        };
        let mut best = (f64::NEG_INFINITY, ta);
        let mut a = ta;
        let mut cuts: Vec<f64> = self
            .cuts_after(ta)
            .into_iter()
            .filter(|&c| c < tb)
            .collect();
        cuts.push(tb);
        for &b in &cuts {
            if b < a {
                continue;
            }
            let mid = 0.5 * (a + b);
            let n = 32;
            let at = |j: usize| a + (b - a) * j as f64 / n as f64;
            let mut k_best = 0;
            let mut v_best = f64::NEG_INFINITY;
            for j in 0..=n {
                let v = demand(at(j), mid);
                if v > v_best {
                    (k_best, v_best) = (j, v);
                }
            }
            let (lo, hi) = (at(k_best.saturating_sub(1)), at((k_best + 1).min(n)));
            let (t, v) = super::tracking::golden_max_in(lo, hi, 60, |t| demand(t, mid));
            let cand = if v > v_best {
                (v, t)
            } else {
                (v_best, at(k_best))
            };
            if cand.0 > best.0 {
                best = cand;
            }
            a = b;
        }
        if best.0 == f64::NEG_INFINITY {
            (0.0, ta)
        } else {
            best
        }
    }
}

/// A horizontal record and a vertical one on the same samples (the shorter
/// given padded with zeros), linear between samples.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordPair {
    /// ü_g.
    pub horizontal: Record,
    /// ü_v.
    pub vertical: Record,
}

/// Why a pair of records cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PairError {
    /// Both records must share the sampling interval.
    #[error(
        "the vertical record's dt ({vertical} s) differs from the horizontal one's ({horizontal} s)"
    )]
    Interval {
        /// The horizontal dt, s.
        horizontal: f64,
        /// The vertical dt, s.
        vertical: f64,
    },
    /// A record is not valid.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// Neither vertical samples nor a non-zero ratio.
    #[error("a vertical record needs samples or a non-zero ratio")]
    Empty,
}

/// `samples` followed by zeros up to `n`.
fn padded(samples: &[f64], n: usize) -> Arc<[f64]> {
    let mut out = samples.to_vec();
    out.resize(n.max(samples.len()), 0.0);
    out.into()
}

impl RecordPair {
    /// ü_g = `horizontal`, ü_v = `vertical`, taken every `dt` seconds; the
    /// shorter is padded with zeros.
    pub fn new(horizontal: Record, vertical: Record) -> Result<Self, PairError> {
        if horizontal.dt() != vertical.dt() {
            return Err(PairError::Interval {
                horizontal: horizontal.dt(),
                vertical: vertical.dt(),
            });
        }
        let n = horizontal.samples().len().max(vertical.samples().len());
        let dt = horizontal.dt();
        Ok(RecordPair {
            horizontal: Record::new(padded(horizontal.samples(), n), dt)?,
            vertical: Record::new(padded(vertical.samples(), n), dt)?,
        })
    }

    /// ü_v = `ratio`·ü_g; `None` for a ratio of 0 or one that is not finite.
    pub fn proportional(horizontal: Record, ratio: f64) -> Option<Self> {
        (ratio != 0.0 && ratio.is_finite()).then(|| RecordPair {
            vertical: horizontal.scaled(ratio),
            horizontal,
        })
    }

    #[inline]
    fn dt(&self) -> f64 {
        self.horizontal.dt()
    }

    #[inline]
    fn end(&self) -> f64 {
        self.horizontal.duration()
    }

    /// The piece `[t_j, t_{j+1}]` holding t (clamped to the record).
    #[inline]
    fn piece(&self, t: f64) -> usize {
        let j = (t / self.dt()).floor();
        let last = self.horizontal.samples().len() - 2;
        if j <= 0.0 { 0 } else { (j as usize).min(last) }
    }

    /// The first time at or after `from` (in the record) where the line
    /// through the values `value(j)` of the samples exceeds `level`, the
    /// value at `from` being `at_from`; with the piece holding it.
    fn first_over<V: Fn(usize) -> f64>(
        &self,
        from: f64,
        at_from: f64,
        value: V,
        level: f64,
    ) -> Option<(f64, usize)> {
        if at_from > level {
            return Some((from, self.piece(from)));
        }
        let dt = self.dt();
        let n = self.horizontal.samples().len();
        let (mut ta, mut fa) = (from, at_from);
        for j in self.piece(from)..n - 1 {
            let tb = (j + 1) as f64 * dt;
            let fb = value(j + 1);
            if fb > level {
                let s = ((level - fa) / (fb - fa)).clamp(0.0, 1.0);
                return Some(((ta + s * (tb - ta)).max(from), j));
            }
            (ta, fa) = (tb, fb);
        }
        None
    }
}

impl Forcing for RecordPair {
    type Rhs<'a> = VerticalRhs<RecordRhs<'a>>;

    const VERTICAL: bool = true;

    fn rhs<'a>(
        &'a self,
        formulation: Formulation,
        block: &Block,
        side: f64,
        forced: bool,
    ) -> VerticalRhs<RecordRhs<'a>> {
        let end = self.end();
        VerticalRhs {
            formulation,
            p2: block.frequency_parameter().powi(2),
            alpha: block.slenderness(),
            side,
            horizontal: self.horizontal.rhs(formulation, block, side, forced),
            vertical: self.vertical.rhs(formulation, block, side, forced),
            h_support: (0.0, end),
            v_support: (0.0, end),
            delay: 0.0,
            ratio: None,
        }
    }

    fn linear_segment(
        _rhs: &VerticalRhs<RecordRhs<'_>>,
        _t0: f64,
        _y0: State,
    ) -> Option<(LinearSegment, f64)> {
        None
    }

    #[inline]
    fn acceleration(&self, t: f64) -> f64 {
        self.horizontal.acceleration(t)
    }

    #[inline]
    fn vertical_acceleration(&self, t: f64) -> f64 {
        self.vertical.acceleration(t)
    }

    fn duration(&self) -> f64 {
        self.end()
    }

    fn next_exceedance(&self, from: f64, threshold: f64) -> Option<Exceedance> {
        self.horizontal.next_exceedance(from, threshold)
    }

    fn next_rocking(&self, from: f64, threshold: &Threshold) -> Option<Exceedance> {
        let (k, level) = (threshold.factor, threshold.level);
        let (a, b) = (self.horizontal.samples(), self.vertical.samples());
        let mut from = from.max(0.0);
        loop {
            if from >= self.end() {
                return None;
            }
            let (h0, v0) = (self.acceleration(from), self.vertical_acceleration(from));
            let start = [1.0, -1.0]
                .into_iter()
                .filter_map(|s| {
                    self.first_over(from, s * h0 - k * v0, |j| s * a[j] - k * b[j], level)
                        .map(|(t, j)| (t, j, s))
                })
                .min_by(|x, y| x.0.total_cmp(&y.0));
            let (start, _, s) = start?;
            if start >= self.end() {
                return None;
            }
            // The window closes where s ü_g − k ü_v falls back to k g.
            // At the start the line is at the level (or above, at `from`).
            let at_start =
                (k * self.vertical_acceleration(start) - s * self.acceleration(start)).min(-level);
            let end = self
                .first_over(start, at_start, |j| -(s * a[j] - k * b[j]), -level)
                .map_or(self.end(), |(t, _)| t);
            if end > start {
                return Some(Exceedance {
                    start,
                    end,
                    side: -s,
                });
            }
            // A window narrower than the time resolution: look past it.
            from = self.breakpoint_after(start);
        }
    }

    fn rocks_before(&self, from: f64, until: f64, threshold: &Threshold) -> bool {
        self.next_rocking(from, threshold)
            .is_some_and(|e| e.start <= until)
    }

    fn next_weightless(&self, from: f64, gravity: f64) -> Option<f64> {
        let from = from.max(0.0);
        if from > self.end() {
            return None;
        }
        let b = self.vertical.samples();
        // −ü_v ≥ g, the crossing of the line from above.
        let at_from = -self.vertical_acceleration(from);
        if at_from >= gravity {
            return Some(from);
        }
        self.first_over(from, at_from, |j| -b[j], gravity)
            .map(|(t, _)| t)
            .or_else(|| {
                // A last sample exactly at −g.
                (-b[b.len() - 1] >= gravity).then(|| self.end())
            })
    }

    #[inline]
    fn breakpoint_after(&self, t: f64) -> f64 {
        self.horizontal.breakpoint_after(t)
    }

    fn resolving_frequency(&self) -> f64 {
        self.horizontal.resolving_frequency()
    }

    /// Both components are linear over one sample interval.
    #[inline]
    fn linear_over(&self, ta: f64, tb: f64) -> Option<f64> {
        self.horizontal.linear_over(ta, tb)
    }

    #[inline]
    fn vertical_jerk_over(&self, ta: f64, tb: f64) -> f64 {
        self.vertical.linear_over(ta, tb).unwrap_or(0.0)
    }

    fn peak_between(&self, ta: f64, tb: f64) -> (f64, f64) {
        self.horizontal.peak_between(ta, tb)
    }

    /// On each piece |ü_g|/(g + ü_v) is a ratio of lines (where g + ü_v >
    /// 0): monotone but for a minimum where ü_g = 0, so its maximum is at a
    /// sample or an end.
    fn rest_demand_peak(&self, ta: f64, tb: f64, gravity: f64) -> (f64, f64) {
        let demand = |t: f64| {
            let fz = gravity + self.vertical_acceleration(t);
            if fz > 0.0 {
                self.acceleration(t).abs() / fz
            } else {
                f64::INFINITY
            }
        };
        let mut best = (demand(ta), ta);
        let b = (demand(tb), tb);
        if b.0 > best.0 {
            best = b;
        }
        let (lo, hi) = (ta.max(0.0), tb.min(self.end()));
        if lo < hi {
            let dt = self.dt();
            let first = (lo / dt).ceil() as usize;
            let last = ((hi / dt).floor() as usize).min(self.horizontal.samples().len() - 1);
            for j in first..=last {
                let t = j as f64 * dt;
                let d = demand(t);
                if d > best.0 {
                    best = (d, t);
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::PulseShape;

    fn block() -> Block {
        Block::new(0.25, 2.14, Some(0.9), None, None).expect("valid")
    }

    #[test]
    fn a_proportional_pair_finds_the_windows_and_demand_of_the_general_search() {
        // The closed form of ü_v = r ü_g against the bisection on monotone
        // pieces that any pair takes (the same pulses, not marked proportional).
        let b = block();
        let g = b.gravity();
        for shape in [
            PulseShape::OneSine,
            PulseShape::OneCosine,
            PulseShape::Cn(3),
            PulseShape::Ricker { symmetric: true },
        ] {
            for formulation in [Formulation::Linear, Formulation::Nonlinear] {
                let threshold = formulation.threshold(&b);
                for (level, r) in [(1.5, 0.5), (1.5, -0.5), (3.0, 1.2), (1.2, -2.0), (0.9, 0.8)] {
                    let h = Pulse::new(shape, level * threshold.level, 6.0).expect("valid");
                    let fast = PulsePair::proportional(h, r).expect("non-zero");
                    let slow = PulsePair::unmarked(h, h.with_amplitude(r * h.amplitude), 0.0);
                    let marked = PulsePair::new(h, h.with_amplitude(r * h.amplitude), 0.0).ratio;
                    assert!(
                        marked.is_some_and(|m| (m - r).abs() <= 1e-15 * r.abs()),
                        "a vertical pulse of the horizontal's shape is proportional: {marked:?}"
                    );
                    let mut from = 0.0;
                    let mut windows = 0;
                    loop {
                        let (x, y) = (
                            fast.next_rocking(from, &threshold),
                            slow.next_rocking(from, &threshold),
                        );
                        let what =
                            format!("{shape:?} {formulation:?} level {level} r {r} from {from}");
                        match (x, y) {
                            (None, None) => break,
                            (Some(x), Some(y)) => {
                                assert!((x.start - y.start).abs() < 1e-12, "{what}: {x:?} {y:?}");
                                assert!((x.end - y.end).abs() < 1e-12, "{what}: {x:?} {y:?}");
                                assert_eq!(x.side, y.side, "{what}");
                                windows += 1;
                                from = x.end.max(x.start) + 1e-9;
                            }
                            _ => panic!("{what}: {x:?} {y:?}"),
                        }
                    }
                    let (d0, t0) = fast.rest_demand_peak(0.0, fast.duration(), g);
                    let (d1, _) = slow.rest_demand_peak(0.0, slow.duration(), g);
                    assert!(
                        (d0 - d1).abs() <= 1e-9 * d1.abs().max(1.0) || d0 == d1,
                        "{shape:?} {formulation:?} {level} {r}: {d0} at {t0} vs {d1}"
                    );
                    assert!(windows > 0 || level < 1.0, "{shape:?} {level} {r}");
                }
            }
        }
    }

    #[test]
    fn a_pulse_pair_starts_rocking_where_the_threshold_carries_the_vertical() {
        // ü_g = a sin(ω t), ü_v = r ü_g: the start solves a sin ψ = k g/(1 − k r).
        let b = block();
        for f in [Formulation::Linear, Formulation::Nonlinear] {
            let th = f.threshold(&b);
            let k = th.factor;
            let a = 4.0 * th.level;
            let h = Pulse::new(PulseShape::OneSine, a, 5.0).expect("valid");
            for r in [-1.0, -0.5, 0.5, 1.0] {
                let pair = PulsePair::proportional(h, r).expect("non-zero");
                let e = pair.next_rocking(0.0, &th).expect("rocks");
                let expect = (k * b.gravity() / (1.0 - k * r) / a).asin() / 5.0;
                assert!(
                    (e.start - expect).abs() < 1e-13,
                    "{f:?} r={r}: {e:?} vs {expect}"
                );
                assert_eq!(e.side, -1.0);
                // It closes symmetrically about the crest at π/(2ω).
                let crest = std::f64::consts::FRAC_PI_2 / 5.0;
                assert!((e.end - (2.0 * crest - expect)).abs() < 1e-12, "{e:?}");
                // The negative half: −a sin ψ·(1 + k r) = k g.
                let e2 = pair.next_rocking(e.end, &th).expect("second window");
                let expect2 = PI / 5.0 + (k * b.gravity() / (1.0 + k * r) / a).asin() / 5.0;
                assert!((e2.start - expect2).abs() < 1e-12, "{e2:?} vs {expect2}");
                assert_eq!(e2.side, 1.0);
            }
        }
    }

    #[test]
    fn a_record_pair_starts_rocking_on_the_line_in_closed_form() {
        // ü_g from 0 to 2 k g, ü_v from 0 to −g/2 over [0, 1]: the start solves
        // 2 k g t = k (g − g t/2), t = 1/2.5.
        let b = block();
        let th = Formulation::Nonlinear.threshold(&b);
        let (k, g) = (th.factor, b.gravity());
        let h = Record::new(vec![0.0, 2.0 * k * g, 0.0].into(), 1.0).expect("valid");
        let v = Record::new(vec![0.0, -0.5 * g].into(), 1.0).expect("valid");
        let pair = RecordPair::new(h, v).expect("same dt");
        assert_eq!(pair.vertical.samples(), &[0.0, -0.5 * g, 0.0]);
        let e = pair.next_rocking(0.0, &th).expect("rocks");
        assert!((e.start - 0.4).abs() < 1e-15, "{e:?}");
        assert_eq!(e.side, -1.0);
        // Back down on [1, 2]: 2 k g (2 − t) = k (g − g (2 − t)/2), t = 2 − 1/2.5.
        assert!((e.end - 1.6).abs() < 1e-15, "{e:?}");
        assert!(pair.next_weightless(0.0, g).is_none());
        let deep = Record::new(vec![0.0, -2.0 * g].into(), 1.0).expect("valid");
        let pair = RecordPair::new(pair.horizontal.clone(), deep).expect("same dt");
        assert!((pair.next_weightless(0.0, g).expect("falls away") - 0.5).abs() < 1e-15);
        let other = Record::new(vec![0.0, 1.0].into(), 0.5).expect("valid");
        assert!(RecordPair::new(pair.horizontal.clone(), other).is_err());
    }

    #[test]
    fn a_delayed_vertical_pulse_falls_away_where_it_passes_minus_g() {
        let g = 9.81;
        let h = Pulse::new(PulseShape::OneSine, 3.0, 2.0).expect("valid");
        // −2g cos(3 t') from t' = t − 0.4: below −g for 3 t' < π/3.
        let v = Pulse::new(PulseShape::OneCosine, -2.0 * g, 3.0).expect("valid");
        let pair = PulsePair::new(h, v, 0.4);
        assert_eq!(pair.next_weightless(0.0, g), Some(0.4));
        let later = pair.next_weightless(0.5, g).expect("again");
        assert_eq!(later, 0.5);
        let second = pair
            .next_weightless(0.4 + PI / 9.0 + 1e-9, g)
            .expect("the last crest");
        assert!((second - (0.4 + (2.0 * PI - PI / 3.0) / 3.0)).abs() < 1e-12);
        assert_eq!(pair.duration(), PI);
        assert_eq!(pair.vertical_acceleration(0.3), 0.0);
        assert_eq!(pair.vertical_acceleration(0.4), -2.0 * g);
    }

    #[test]
    fn stepping_to_a_crossing_finds_what_bisection_finds() {
        // On every piece of pairs of pulses of their own (several families,
        // frequencies, delays, levels), each crossing of s ü_g − k ü_v, up
        // and back, stepped to from below against the bisection's, and the
        // last bit of time there.
        let b = block();
        let g = b.gravity();
        let shapes = [
            PulseShape::OneSine,
            PulseShape::OneCosine,
            PulseShape::Cn(2),
            PulseShape::HalfSine,
            PulseShape::Rectangular,
            PulseShape::Ricker { symmetric: true },
            PulseShape::Ricker { symmetric: false },
        ];
        let mut found = 0;
        for formulation in [Formulation::Linear, Formulation::Nonlinear] {
            let th = formulation.threshold(&b);
            let (k, level) = (th.factor, th.level);
            for (i, &hs) in shapes.iter().enumerate() {
                for (j, &vs) in shapes.iter().enumerate() {
                    let (ah, av) = (
                        (1.5 + 0.7 * i as f64) * level,
                        (0.3 + 0.25 * j as f64) * g * if (i + j) % 2 == 0 { 1.0 } else { -1.0 },
                    );
                    let h = Pulse::new(hs, ah, 4.0 + i as f64).expect("valid");
                    let v = Pulse::new(vs, av, 3.0 + 2.5 * j as f64).expect("valid");
                    for delay in [0.0, 0.13, 0.7] {
                        let pair = PulsePair::new(h, v, delay);
                        let mut a = 0.0;
                        for c in pair.cuts_after(0.0) {
                            let mid = 0.5 * (a + c);
                            for s in [1.0, -1.0] {
                                let f = s * pair.h_on(a, mid) - k * pair.v_on(a, mid);
                                let back = f > level;
                                let x = pair.crossing_on(a, c, s, k, level, back);
                                let y = pair.bisected_crossing(a, c, mid, s, k, level, back);
                                let what = format!(
                                    "{formulation:?} {hs:?} {vs:?} delay {delay} [{a}, {c}] s {s} back {back}"
                                );
                                match (x, y) {
                                    (None, None) => {}
                                    (Some(x), Some(y)) => {
                                        assert!((x - y).abs() < 1e-12, "{what}: {x} vs {y}");
                                        found += 1;
                                    }
                                    _ => panic!("{what}: {x:?} vs {y:?}"),
                                }
                            }
                            a = c;
                        }
                    }
                }
            }
        }
        assert!(found > 500, "{found} crossings");
    }

    #[test]
    fn stepping_from_below_never_passes_the_first_of_close_crossings() {
        // f = sin(t) − ε t² on [0, π]: 0.5 is crossed on the way up and
        // down; |f″| ≤ 1 + 2ε. The first, to the last bit.
        let eps = 0.01;
        let f = |t: f64| (t.sin() - eps * t * t, t.cos() - 2.0 * eps * t);
        let first = first_above_curved(&f, 1.0 + 2.0 * eps, 0.0, PI, 0.5)
            .expect("no stall")
            .expect("crosses");
        assert!(f(first).0 > 0.5 && f(first.next_down()).0 <= 0.5, "{first}");
        assert!(first < 1.0, "{first}");
        // A crest below the level: none.
        assert_eq!(
            first_above_curved(&f, 1.0 + 2.0 * eps, 0.0, PI, 0.99),
            Ok(None)
        );
    }

    #[test]
    fn the_first_crossing_is_found_among_several() {
        // f = sin(t) on [0, 10] above 0.5: first at π/6, not 2π + π/6; the
        // bound from |f′| ≤ 1.
        let f = |t: f64| t.sin();
        let upper = |a: f64, b: f64| 0.5 * (f(a) + f(b)) + 0.5 * (b - a);
        let t = first_above(&f, &upper, 0.0, 10.0, 0.5).expect("crosses");
        assert!((t - PI / 6.0).abs() < 1e-15, "{t}");
        assert!(first_above(&f, &upper, 0.0, 10.0, 1.5).is_none());
    }
}
