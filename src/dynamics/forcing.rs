//! The ground motion that forces the block: a cycloidal pulse (paper eqs. 22
//! and 53) or a sampled acceleration record.
//!
//! The driver ([`simulate`](super::simulate::simulate)) is generic over
//! [`Forcing`], so that each kind of ground motion gets its own monomorphised
//! right-hand side: the pulse keeps its closed-form cosine, the record
//! interpolates linearly between samples.
//!
//! A record `ü_g(t_k) = a_k`, `t_k = k·dt` (k = 0..N−1), is linear on every
//! `[t_k, t_{k+1}]` and zero outside `[0, (N−1)·dt]`. Its derivative jumps at the
//! sample times, so the Runge–Kutta steps stop there ([`Forcing::breakpoint_after`]),
//! and the threshold crossings |ü_g| = g tan α (or g α) are solved on each
//! linear piece in closed form. So is the linear equation of motion
//! ([`Forcing::linear_segment`]): its exact solution runs piece by piece.
//!
//! A ground motion with a vertical component is a pair of these
//! ([`super::vertical`]); without one, the trait's vertical methods are the
//! horizontal ones and cost nothing.

use std::sync::{Arc, OnceLock};

use super::block::Block;
use super::equations::{Formulation, RockingRhs, Threshold};
use super::exact::LinearSegment;
use super::excitation::{Exceedance, Pulse, Wave};
use super::integrator::{Rhs, State};

/// A ground motion acting on `0 ≤ t ≤ duration()`.
pub trait Forcing: Clone + std::fmt::Debug {
    /// The right-hand side of eq. 49 / 50 under this ground motion.
    type Rhs<'a>: Rhs
    where
        Self: 'a;

    /// Right-hand side on `side`, forced by this motion when `forced`.
    fn rhs<'a>(
        &'a self,
        formulation: Formulation,
        block: &Block,
        side: f64,
        forced: bool,
    ) -> Self::Rhs<'a>;

    /// The closed-form linear solution (eqs. 23–33) of `rhs` from `(t0, y0)`,
    /// and the time up to which it holds: ∞ for a pulse's cosine, the next
    /// sample for a record (whose slope changes there). `None` when the ground
    /// term has no closed form (a wavelet).
    fn linear_segment(rhs: &Self::Rhs<'_>, t0: f64, y0: State) -> Option<(LinearSegment, f64)>;

    /// Ground acceleration ü_g(t), m/s² (zero outside the motion).
    fn acceleration(&self, t: f64) -> f64;

    /// End of the forcing, s.
    fn duration(&self) -> f64;

    /// The first stretch at or after `from` where |ü_g| > `threshold`.
    fn next_exceedance(&self, from: f64, threshold: f64) -> Option<Exceedance>;

    /// Whether |ü_g| exceeds `threshold` somewhere in `[from, until]`.
    fn exceeds_before(&self, from: f64, until: f64, threshold: f64) -> bool {
        self.next_exceedance(from, threshold)
            .is_some_and(|e| e.start <= until)
    }

    /// The first time after `t` at which ü_g is not smooth (∞ if none): the
    /// Runge–Kutta steps end there.
    #[inline]
    fn breakpoint_after(&self, _t: f64) -> f64 {
        f64::INFINITY
    }

    /// A circular frequency resolving the forcing's variation, rad/s (used to
    /// sample tracked quantities densely enough).
    fn resolving_frequency(&self) -> f64;

    /// The slope d ü_g/dt (m/s³) when ü_g is linear in time over all of
    /// `[ta, tb]`, `None` otherwise (or when it is not known to be).
    ///
    /// On such a piece the forcing has no time scale of its own: the tracked
    /// quantities vary only as fast as the block moves, and the tracker
    /// samples them for the block alone (a record's piece inside one sample
    /// interval). A pulse answers `None`: its pieces are sampled for its
    /// [`resolving_frequency`](Forcing::resolving_frequency).
    #[inline]
    fn linear_over(&self, _ta: f64, _tb: f64) -> Option<f64> {
        None
    }

    /// The vertical acceleration's slope over `[ta, tb]`, m/s³, where
    /// [`linear_over`](Forcing::linear_over) finds the motion linear there
    /// (zero without a vertical component).
    #[inline]
    fn vertical_jerk_over(&self, _ta: f64, _tb: f64) -> f64 {
        0.0
    }

    /// max |ü_g| over `[ta, tb]` and where it is reached.
    fn peak_between(&self, ta: f64, tb: f64) -> (f64, f64);

    /// Whether the motion has a vertical component. Without one (a pulse, a
    /// record) the methods below are the horizontal ones, to the bit.
    const VERTICAL: bool = false;

    /// Vertical ground acceleration ü_v(t), m/s², positive up (zero outside
    /// the motion).
    #[inline]
    fn vertical_acceleration(&self, _t: f64) -> f64 {
        0.0
    }

    /// The first stretch at or after `from` where the ground rocks a block
    /// at rest: |ü_g| > (g + ü_v)·k ([`Threshold`]); its side is the one the
    /// ground pushes the block to.
    #[inline]
    fn next_rocking(&self, from: f64, threshold: &Threshold) -> Option<Exceedance> {
        self.next_exceedance(from, threshold.level)
    }

    /// Whether the ground rocks a block at rest somewhere in `[from, until]`.
    #[inline]
    fn rocks_before(&self, from: f64, until: f64, threshold: &Threshold) -> bool {
        self.exceeds_before(from, until, threshold.level)
    }

    /// The first time at or after `from` at which g + ü_v ≤ 0 (`gravity` =
    /// g): the ground falls away at least as fast as the block would, and
    /// nothing holds the block on it.
    #[inline]
    fn next_weightless(&self, _from: f64, _gravity: f64) -> Option<f64> {
        None
    }

    /// The friction demand of the block at rest on the base (f_x = m ü_g,
    /// f_z = m(g + ü_v)): max |ü_g|/(g + ü_v) over `[ta, tb]` and where.
    #[inline]
    fn rest_demand_peak(&self, ta: f64, tb: f64, gravity: f64) -> (f64, f64) {
        let best = self.peak_between(ta, tb);
        (best.0 / gravity, best.1)
    }
}

impl Forcing for Pulse {
    type Rhs<'a> = RockingRhs;

    #[inline]
    fn rhs(&self, formulation: Formulation, block: &Block, side: f64, forced: bool) -> RockingRhs {
        RockingRhs::new(formulation, block, self, side, forced)
    }

    #[inline]
    fn linear_segment(rhs: &RockingRhs, t0: f64, y0: State) -> Option<(LinearSegment, f64)> {
        (rhs.wave == Wave::Cosine).then(|| (LinearSegment::new(rhs, t0, y0), f64::INFINITY))
    }

    #[inline]
    fn acceleration(&self, t: f64) -> f64 {
        Pulse::acceleration(self, t)
    }

    #[inline]
    fn duration(&self) -> f64 {
        self.duration
    }

    #[inline]
    fn next_exceedance(&self, from: f64, threshold: f64) -> Option<Exceedance> {
        Pulse::next_exceedance(self, from, threshold)
    }

    #[inline]
    fn resolving_frequency(&self) -> f64 {
        match self.wave {
            // Its highest harmonic: ω_p (1 + 1/γ).
            Wave::MavroeidisPapageorgiou { shape, .. } => {
                self.circular_frequency * (1.0 + 1.0 / shape.gamma)
            }
            _ => self.circular_frequency,
        }
    }

    fn peak_between(&self, ta: f64, tb: f64) -> (f64, f64) {
        // The largest of the ends and the first crest of the cosine inside.
        let mut best = (Pulse::acceleration(self, ta).abs(), ta);
        let b = (Pulse::acceleration(self, tb).abs(), tb);
        if b.0 > best.0 {
            best = b;
        }
        if self.carrier == 0.0 {
            return best; // constant: any point is a peak
        }
        if self.wave != Wave::Cosine {
            for &t in self.extrema.as_slice() {
                if t > ta && t < tb {
                    let v = Pulse::acceleration(self, t).abs();
                    if v > best.0 {
                        best = (v, t);
                    }
                }
            }
            return best;
        }
        let (chi_a, chi_b) = (self.phase_at(ta), self.phase_at(tb.min(self.duration)));
        let k = (chi_a / std::f64::consts::PI).ceil();
        let chi = k * std::f64::consts::PI;
        if chi <= chi_b {
            let t = (chi - self.phase) / self.carrier;
            best = (self.amplitude.abs(), t);
        }
        best
    }
}

/// Why a record cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RecordError {
    /// At least two samples are needed.
    #[error("a record needs at least 2 samples (got {0})")]
    TooShort(usize),
    /// The sampling interval must be positive and finite.
    #[error("the sampling interval must be positive and finite (got {0})")]
    Interval(f64),
    /// Every sample must be finite.
    #[error("sample {0} is not finite")]
    Sample(usize),
}

/// (velocity, displacement) of the ground at each sample of a record.
type SampleKinematics = Box<[(f64, f64)]>;

/// A sampled ground-acceleration record, linear between samples.
#[derive(Clone, Debug)]
pub struct Record {
    /// Samples a_k = ü_g(k·dt), m/s².
    samples: Arc<[f64]>,
    /// Sampling interval, s.
    dt: f64,
    /// (N − 1)·dt, s.
    end: f64,
    /// Ground velocity and displacement at each sample (from rest at
    /// t = 0), made when first asked for ([`Record::kinematics`]).
    at_samples: Arc<OnceLock<SampleKinematics>>,
}

impl PartialEq for Record {
    fn eq(&self, other: &Self) -> bool {
        self.samples == other.samples && self.dt == other.dt && self.end == other.end
    }
}

impl Record {
    /// A record of `samples` (m/s²) taken every `dt` seconds.
    pub fn new(samples: Arc<[f64]>, dt: f64) -> Result<Self, RecordError> {
        if samples.len() < 2 {
            return Err(RecordError::TooShort(samples.len()));
        }
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(RecordError::Interval(dt));
        }
        if let Some(k) = samples.iter().position(|a| !a.is_finite()) {
            return Err(RecordError::Sample(k));
        }
        let end = (samples.len() - 1) as f64 * dt;
        Ok(Record {
            samples,
            dt,
            end,
            at_samples: Arc::default(),
        })
    }

    /// The ground's velocity and displacement at `t` (m/s, m) from rest at
    /// t = 0: the exact integrals of the acceleration, linear between
    /// samples (velocity quadratic, displacement cubic on each piece;
    /// constant velocity after the record's end).
    pub fn kinematics(&self, t: f64) -> (f64, f64) {
        if t <= 0.0 {
            return (0.0, 0.0);
        }
        let dt = self.dt;
        let table = self.at_samples.get_or_init(|| {
            let mut out = Vec::with_capacity(self.samples.len());
            let (mut v, mut u) = (0.0f64, 0.0f64);
            out.push((v, u));
            for w in self.samples.windows(2) {
                let (a0, a1) = (w[0], w[1]);
                u += v * dt + dt * dt * (a0 / 3.0 + a1 / 6.0);
                v += 0.5 * dt * (a0 + a1);
                out.push((v, u));
            }
            out.into_boxed_slice()
        });
        if t >= self.end {
            let (v, u) = table[table.len() - 1];
            return (v, u + v * (t - self.end));
        }
        let k = self.piece(t);
        let (v0, u0) = table[k];
        let (a0, a1) = (self.samples[k], self.samples[k + 1]);
        let tau = t - self.time(k);
        let slope = (a1 - a0) / dt;
        (
            v0 + a0 * tau + 0.5 * slope * tau * tau,
            u0 + v0 * tau + 0.5 * a0 * tau * tau + slope * tau * tau * tau / 6.0,
        )
    }

    /// The samples, m/s².
    pub fn samples(&self) -> &[f64] {
        &self.samples
    }

    /// The sampling interval, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The record with every sample multiplied by `factor`.
    pub fn scaled(&self, factor: f64) -> Record {
        Record {
            samples: self.samples.iter().map(|a| a * factor).collect(),
            dt: self.dt,
            end: self.end,
            at_samples: Arc::default(),
        }
    }

    /// Time of sample k.
    #[inline]
    fn time(&self, k: usize) -> f64 {
        k as f64 * self.dt
    }

    /// The piece `[t_k, t_{k+1}]` holding t (clamped to the record).
    #[inline]
    fn piece(&self, t: f64) -> usize {
        let k = (t / self.dt).floor();
        if k <= 0.0 {
            0
        } else {
            (k as usize).min(self.samples.len() - 2)
        }
    }

    /// ü_g(t) on `[0, end]` by linear interpolation (t is clamped there).
    #[inline]
    fn interpolate(&self, t: f64) -> f64 {
        interpolate(&self.samples, self.dt, self.end, t)
    }

    /// The time in piece k where the line through (t_k, a_k), (t_{k+1}, a_{k+1})
    /// takes the value `level`.
    #[inline]
    fn crossing(&self, k: usize, level: f64) -> f64 {
        let (a0, a1) = (self.samples[k], self.samples[k + 1]);
        let s = ((level - a0) / (a1 - a0)).clamp(0.0, 1.0);
        self.time(k) + s * self.dt
    }

    /// The first time at or after `from` (and not after `until`) where
    /// |ü_g| > `threshold`, with the sign of ü_g there and the piece holding it.
    fn first_start(&self, from: f64, until: f64, threshold: f64) -> Option<(f64, f64, usize)> {
        let k0 = self.piece(from);
        let a_from = self.interpolate(from);
        if a_from.abs() > threshold {
            return Some((from, a_from.signum(), k0));
        }
        // On each piece the line leaves [−c, c] at most once, towards its end value.
        for k in k0..self.samples.len() - 1 {
            if self.time(k) > until {
                return None;
            }
            let a1 = self.samples[k + 1];
            if a1.abs() > threshold {
                let sign = a1.signum();
                let start = self.crossing(k, sign * threshold).max(from);
                return (start <= until).then_some((start, sign, k));
            }
        }
        None
    }
}

/// Linear interpolation of `samples` taken every `dt`, on `[0, end]`.
#[inline]
pub(super) fn interpolate(samples: &[f64], dt: f64, end: f64, t: f64) -> f64 {
    let t = t.clamp(0.0, end);
    let x = t / dt;
    let k = (x.floor() as usize).min(samples.len() - 2);
    let s = x - k as f64;
    let a0 = samples[k];
    a0 + (samples[k + 1] - a0) * s
}

/// The right-hand side of eq. 49 / 50 under a record.
#[derive(Clone, Copy, Debug)]
pub struct RecordRhs<'a> {
    formulation: Formulation,
    /// p, for the closed form; p² for the equation of motion.
    p: f64,
    p2: f64,
    alpha: f64,
    side: f64,
    /// 1/g when forced, zero for free vibration.
    inv_g: f64,
    samples: &'a [f64],
    dt: f64,
    end: f64,
}

impl RecordRhs<'_> {
    /// ü_g/g at time t.
    #[inline]
    pub fn ground(&self, t: f64) -> f64 {
        if self.inv_g == 0.0 {
            0.0
        } else {
            self.inv_g * interpolate(self.samples, self.dt, self.end, t)
        }
    }

    /// The line ü_g/g follows from `t` on: `(u0, u1, t1)` with ü_g/g =
    /// u0 + u1 (t' − t) for t ≤ t' ≤ t1, t1 the first sample time after t.
    /// Free vibration, and the record past its end, give `(0, 0, ∞)`.
    #[inline]
    pub fn piece_from(&self, t: f64) -> (f64, f64, f64) {
        if self.inv_g == 0.0 || t >= self.end {
            return (0.0, 0.0, f64::INFINITY);
        }
        let last = self.samples.len() - 2;
        let x = t.max(0.0) / self.dt;
        // (x ≥ 0: truncation is the floor.)
        let mut k = (x as usize).min(last);
        // A start on a sample time belongs to the piece that begins there.
        if k < last && (k + 1) as f64 * self.dt <= t {
            k += 1;
        }
        // On the last piece this is the record's end (the same product).
        let t1 = (k + 1) as f64 * self.dt;
        let (a0, a1) = (self.samples[k], self.samples[k + 1]);
        let value = a0 + (a1 - a0) * (x - k as f64);
        (self.inv_g * value, self.inv_g * ((a1 - a0) / self.dt), t1)
    }
}

impl Rhs for RecordRhs<'_> {
    #[inline]
    fn eval(&self, t: f64, y: State) -> State {
        [
            y[1],
            self.formulation.angular_acceleration(
                self.p2,
                self.alpha,
                self.side,
                y[0],
                self.ground(t),
            ),
        ]
    }
}

impl Forcing for Record {
    type Rhs<'a> = RecordRhs<'a>;

    fn rhs<'a>(
        &'a self,
        formulation: Formulation,
        block: &Block,
        side: f64,
        forced: bool,
    ) -> RecordRhs<'a> {
        RecordRhs {
            formulation,
            p: block.frequency_parameter(),
            p2: block.frequency_parameter().powi(2),
            alpha: block.slenderness(),
            side,
            inv_g: if forced { 1.0 / block.gravity() } else { 0.0 },
            samples: &self.samples,
            dt: self.dt,
            end: self.end,
        }
    }

    #[inline]
    fn linear_segment(rhs: &RecordRhs<'_>, t0: f64, y0: State) -> Option<(LinearSegment, f64)> {
        let (u0, u1, t1) = rhs.piece_from(t0);
        let seg = LinearSegment::linear_ground(rhs.p, rhs.alpha, rhs.side, t0, y0, u0, u1, t1);
        Some((seg, t1))
    }

    #[inline]
    fn acceleration(&self, t: f64) -> f64 {
        if (0.0..=self.end).contains(&t) {
            self.interpolate(t)
        } else {
            0.0
        }
    }

    fn duration(&self) -> f64 {
        self.end
    }

    fn next_exceedance(&self, from: f64, threshold: f64) -> Option<Exceedance> {
        if threshold.is_nan() || threshold < 0.0 {
            return None;
        }
        let mut from = from.max(0.0);
        loop {
            if from >= self.end {
                return None;
            }
            let (start, sign, k0) = self.first_start(from, self.end, threshold)?;
            if start >= self.end {
                return None;
            }
            // The window closes on the first piece whose end is back within
            // the threshold (the line is monotone on each piece).
            let level = sign * threshold;
            let mut end = self.end;
            let mut last = self.samples.len() - 2;
            for k in k0..self.samples.len() - 1 {
                if sign * self.samples[k + 1] <= threshold {
                    end = self.crossing(k, level);
                    last = k;
                    break;
                }
            }
            if end > start {
                return Some(Exceedance {
                    start,
                    end,
                    side: -sign,
                });
            }
            // A window narrower than the time resolution: look past it.
            from = self.time(last + 1);
        }
    }

    fn exceeds_before(&self, from: f64, until: f64, threshold: f64) -> bool {
        from < self.end && self.first_start(from.max(0.0), until, threshold).is_some()
    }

    #[inline]
    fn breakpoint_after(&self, t: f64) -> f64 {
        let k = (t / self.dt).floor() + 1.0;
        let mut b = k * self.dt;
        if b <= t + 1e-9 * self.dt {
            b = (k + 1.0) * self.dt;
        }
        b
    }

    fn resolving_frequency(&self) -> f64 {
        std::f64::consts::PI / self.dt
    }

    /// The slope of the sample interval holding `[ta, tb]` (a start on a
    /// sample time belongs to the interval that begins there, as for
    /// [`RecordRhs::piece_from`]); zero past the record's end.
    #[inline]
    fn linear_over(&self, ta: f64, tb: f64) -> Option<f64> {
        if ta >= self.end {
            return Some(0.0);
        }
        if !(ta >= 0.0 && tb >= ta) {
            return None;
        }
        let last = self.samples.len() - 2;
        // (ta ≥ 0: truncation is the floor.)
        let mut k = ((ta / self.dt) as usize).min(last);
        if k < last && self.time(k + 1) <= ta {
            k += 1;
        }
        (tb <= self.time(k + 1)).then(|| (self.samples[k + 1] - self.samples[k]) / self.dt)
    }

    fn peak_between(&self, ta: f64, tb: f64) -> (f64, f64) {
        let mut best = (self.acceleration(ta).abs(), ta);
        let b = (self.acceleration(tb).abs(), tb);
        if b.0 > best.0 {
            best = b;
        }
        let (lo, hi) = (ta.max(0.0), tb.min(self.end));
        if lo < hi {
            let first = (lo / self.dt).ceil() as usize;
            let last = ((hi / self.dt).floor() as usize).min(self.samples.len() - 1);
            for k in first..=last {
                let a = self.samples[k].abs();
                if a > best.0 {
                    best = (a, self.time(k));
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(samples: &[f64], dt: f64) -> Record {
        Record::new(samples.into(), dt).expect("valid")
    }

    #[test]
    fn interpolates_linearly_and_vanishes_outside() {
        let r = record(&[0.0, 2.0, -2.0], 0.5);
        assert_eq!(r.duration(), 1.0);
        assert!((r.acceleration(0.25) - 1.0).abs() < 1e-15);
        assert!((r.acceleration(0.75) - 0.0).abs() < 1e-15);
        assert_eq!(r.acceleration(1.0), -2.0);
        assert_eq!(r.acceleration(1.0 + 1e-9), 0.0);
        assert_eq!(r.acceleration(-1e-9), 0.0);
    }

    #[test]
    fn exceedance_is_solved_on_the_linear_piece() {
        let r = record(&[0.0, 2.0, 2.0, -3.0, 0.0], 0.1);
        let e = r.next_exceedance(0.0, 1.0).expect("exceeds");
        assert!((e.start - 0.05).abs() < 1e-15, "{e:?}");
        // 2 → −3 on [0.2, 0.3] falls to 1 at 0.2 + 0.1/5.
        assert!((e.end - 0.22).abs() < 1e-15, "{e:?}");
        assert_eq!(e.side, -1.0);
        let e2 = r.next_exceedance(e.end, 1.0).expect("second window");
        // 2 → −3 on [0.2, 0.3] reaches −1 at 0.2 + 0.1·3/5.
        assert!((e2.start - 0.26).abs() < 1e-15, "{e2:?}");
        assert_eq!(e2.side, 1.0);
        // −3 → 0 on [0.3, 0.4] rises to −1 at 0.3 + 0.1·2/3.
        assert!((e2.end - (0.3 + 0.2 / 3.0)).abs() < 1e-15, "{e2:?}");
        assert!(r.next_exceedance(e2.end, 1.0).is_none());
        assert!(r.next_exceedance(0.0, 3.0).is_none());
        assert!(r.exceeds_before(0.0, 0.06, 1.0));
        assert!(!r.exceeds_before(0.0, 0.04, 1.0));
    }

    #[test]
    fn a_records_kinematics_are_the_exact_integrals_of_its_lines() {
        // A ramp a(t) = 2 t + 1 sampled every 0.1 s is its own interpolant:
        // v = t² + t, u = t³/3 + t²/2 to rounding; past the end v is constant.
        let r = record(
            &(0..11)
                .map(|k| 2.0 * (k as f64 * 0.1) + 1.0)
                .collect::<Vec<_>>(),
            0.1,
        );
        for t in [0.0, 0.05, 0.1, 0.37, 0.999, 1.0] {
            let (v, u) = r.kinematics(t);
            assert!((v - (t * t + t)).abs() < 1e-14, "{t}: {v}");
            assert!(
                (u - (t * t * t / 3.0 + t * t / 2.0)).abs() < 1e-14,
                "{t}: {u}"
            );
        }
        let (v, u) = r.kinematics(1.5);
        assert!((v - 2.0).abs() < 1e-14 && (u - (1.0 / 3.0 + 0.5 + 2.0 * 0.5)).abs() < 1e-13);
        // A one-sine pulse sampled finely: its closed-form motion to O(dt²).
        let pulse = Pulse::new(crate::dynamics::PulseShape::OneSine, 3.0, 6.0).expect("valid");
        let dt = 1e-3;
        let n = (pulse.duration / dt) as usize + 1;
        let r = record(
            &(0..n)
                .map(|k| pulse.acceleration(k as f64 * dt))
                .collect::<Vec<_>>(),
            dt,
        );
        for t in [0.1, 0.5, 0.9] {
            let ((v, u), (v0, u0)) = (r.kinematics(t), pulse.ground_motion(t));
            assert!(
                (v - v0).abs() < 1e-5 && (u - u0).abs() < 1e-5,
                "{t}: {v} {v0} {u} {u0}"
            );
        }
    }

    #[test]
    fn breakpoints_are_the_next_sample_times() {
        let r = record(&[0.0; 11], 0.1);
        assert_eq!(r.breakpoint_after(0.0), 0.1);
        assert_eq!(r.breakpoint_after(0.05), 0.1);
        let b = r.breakpoint_after(0.1);
        assert!((b - 0.2).abs() < 1e-15);
        assert!(r.breakpoint_after(3.0 * 0.1) > 0.3 + 1e-12);
    }

    #[test]
    fn a_piece_starts_at_its_sample_and_follows_the_interpolant() {
        let block = Block::new(0.25, 2.0, None, None, None).expect("valid");
        let r = record(&[0.0, 2.0, -2.0, 1.0], 0.1);
        let rhs = r.rhs(Formulation::Linear, &block, 1.0, true);
        let g = block.gravity();
        // Inside the second piece: the line through (0.1, 2) and (0.2, −2).
        let (u0, u1, t1) = rhs.piece_from(0.125);
        assert!((u0 - rhs.ground(0.125)).abs() < 1e-15, "{u0}");
        assert!((u1 + 40.0 / g).abs() < 1e-12, "{u1}");
        assert_eq!(t1, 2.0 * 0.1);
        // On a sample time the piece that begins there.
        for k in 1..3 {
            let t = k as f64 * 0.1;
            let (u0, _, t1) = rhs.piece_from(t);
            assert!((u0 - r.samples()[k] / g).abs() < 1e-15);
            assert_eq!(t1, (k + 1) as f64 * 0.1);
        }
        // The last piece ends with the record; past it, and when free, no ground.
        assert_eq!(rhs.piece_from(0.25).2, r.duration());
        assert_eq!(rhs.piece_from(r.duration()), (0.0, 0.0, f64::INFINITY));
        let free = r.rhs(Formulation::Linear, &block, 1.0, false);
        assert_eq!(free.piece_from(0.125), (0.0, 0.0, f64::INFINITY));
    }

    #[test]
    fn linear_over_one_sample_interval_only() {
        let r = record(&[0.0, 2.0, -2.0, 1.0], 0.1);
        assert_eq!(r.linear_over(0.0, 0.1), Some(20.0));
        assert_eq!(r.linear_over(0.02, 0.07), Some(20.0));
        // A start on a sample time belongs to the interval beginning there.
        let s = r.linear_over(0.1, 0.2).expect("one interval");
        assert!((s + 40.0).abs() < 1e-12, "{s}");
        assert_eq!(r.linear_over(0.05, 0.15), None);
        let s = r.linear_over(0.25, r.duration()).expect("last interval");
        assert!((s - 30.0).abs() < 1e-12, "{s}");
        // Past the end the ground is at rest.
        assert_eq!(r.linear_over(r.duration(), 5.0), Some(0.0));
        assert_eq!(r.linear_over(0.25, 5.0), None);
        // A pulse is never treated as linear.
        let pulse = Pulse::new(crate::dynamics::PulseShape::OneSine, 1.0, 2.0).expect("valid");
        assert_eq!(pulse.linear_over(0.0, 1e-9), None);
    }

    #[test]
    fn peak_between_sees_the_samples_inside() {
        let r = record(&[0.0, 1.0, -4.0, 1.0], 1.0);
        assert_eq!(r.peak_between(0.5, 2.5), (4.0, 2.0));
        assert_eq!(r.peak_between(0.0, 0.5), (0.5, 0.5));
    }

    #[test]
    fn bad_records_are_refused() {
        assert_eq!(
            Record::new(vec![1.0].into(), 0.1),
            Err(RecordError::TooShort(1))
        );
        assert_eq!(
            Record::new(vec![1.0, f64::NAN].into(), 0.1),
            Err(RecordError::Sample(1))
        );
        assert!(Record::new(vec![1.0, 2.0].into(), 0.0).is_err());
    }
}
