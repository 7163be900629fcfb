//! Quantities followed along a history: peak rotation, friction demand, series.
//!
//! The propagators hand every piece of motion to a [`Tracker`] as a function of
//! time (a closed-form segment or a step's dense output); the tracker samples
//! it densely enough for the forcing and the block's own time scale and refines
//! the maxima by golden-section search. Nothing here runs unless asked for.

use super::block::Block;
use super::equations::Formulation;
use super::forcing::Forcing;
use super::integrator::State;
use super::reactions::reactions_per_mass;
use super::response::Series;

/// What to follow.
#[derive(Clone, Debug, Default)]
pub struct TrackRequest {
    /// Follow max |θ|.
    pub peak: bool,
    /// Follow f_x/f_z.
    pub reactions: bool,
    /// Uniform sample times for the series (sorted).
    pub series_times: Vec<f64>,
}

/// Accumulates the tracked quantities.
#[derive(Debug)]
pub struct Tracker<'a, G: Forcing> {
    formulation: Formulation,
    block: &'a Block,
    pulse: &'a G,
    req: TrackRequest,
    next_sample: usize,
    /// Series collected so far.
    pub series: Series,
    /// max |θ|.
    pub peak_theta: f64,
    /// max |f_x/f_z| (f_z > 0) and its time.
    pub peak_demand: (f64, f64),
    /// First time |f_x/f_z| > μ.
    pub first_sliding: Option<f64>,
    /// First time f_z ≤ 0.
    pub first_lift_off: Option<f64>,
    /// When the demand stopped being followed (the block was bound to overturn).
    pub reactions_stopped_at: Option<f64>,
    /// Whether the demand is still followed (off once the block is doomed).
    reactions_on: bool,
}

impl<'a, G: Forcing> Tracker<'a, G> {
    /// A tracker for `req`.
    pub fn new(
        formulation: Formulation,
        block: &'a Block,
        pulse: &'a G,
        req: TrackRequest,
    ) -> Self {
        let n = req.series_times.len();
        let series = Series {
            t: Vec::with_capacity(n),
            theta: Vec::with_capacity(n),
            theta_dot: Vec::with_capacity(n),
            ground_acceleration: Vec::with_capacity(n),
            reaction_ratio: req.reactions.then(|| Vec::with_capacity(n)),
        };
        Tracker {
            formulation,
            block,
            pulse,
            req,
            next_sample: 0,
            series,
            peak_theta: 0.0,
            peak_demand: (0.0, 0.0),
            first_sliding: None,
            first_lift_off: None,
            reactions_stopped_at: None,
            reactions_on: true,
        }
    }

    /// Stops following the friction demand at `t` (the block is already bound
    /// to overturn: its fall is not rocking).
    pub fn stop_reactions(&mut self, t: f64) {
        if self.reactions_on && self.req.reactions {
            self.reactions_stopped_at = Some(t);
        }
        self.reactions_on = false;
    }

    /// Whether anything is followed at all.
    pub fn active(&self) -> bool {
        self.req.peak || self.req.reactions || !self.req.series_times.is_empty()
    }

    fn ground(&self, t: f64, forced: bool) -> f64 {
        if forced {
            self.pulse.acceleration(t)
        } else {
            0.0
        }
    }

    /// (|f_x/f_z| or ∞ when f_z ≤ 0, f_z) at a rocking state.
    fn demand(&self, side: f64, t: f64, y: State, forced: bool) -> (f64, f64, f64) {
        let (fx, fz) = reactions_per_mass(
            self.formulation,
            self.block,
            side,
            y[0],
            y[1],
            self.ground(t, forced),
        );
        let d = if fz > 0.0 {
            (fx / fz).abs()
        } else {
            f64::INFINITY
        };
        (d, fx / fz, fz)
    }

    /// A piece of rocking motion on `side` over `[ta, tb]`.
    pub fn rocking<E: Fn(f64) -> State>(
        &mut self,
        ta: f64,
        tb: f64,
        side: f64,
        forced: bool,
        eval: E,
    ) {
        if !self.active() || tb < ta {
            return;
        }
        // Series samples falling in this piece.
        while let Some(&ts) = self.req.series_times.get(self.next_sample) {
            if ts > tb {
                break;
            }
            if ts >= ta {
                let y = eval(ts);
                self.push_sample(ts, y, Some(side), forced);
            }
            self.next_sample += 1;
        }
        if !(self.req.peak || self.req.reactions) {
            return;
        }
        let span = tb - ta;
        let w = if forced {
            self.pulse.resolving_frequency()
        } else {
            0.0
        };
        let p = self.block.frequency_parameter;
        let n = (8.0 + span * (4.0 * w / std::f64::consts::PI + 2.0 * p)).min(400.0) as usize;
        let mut best_theta = (f64::NEG_INFINITY, 0usize);
        let mut best_demand = (f64::NEG_INFINITY, 0usize);
        let mut prev: Option<(f64, f64, f64)> = None;
        // Pure rocking (and so the demand) is meaningful only while f_z > 0.
        let follow = self.req.reactions && self.reactions_on && self.first_lift_off.is_none();
        let mut demand_until = tb;
        let mut following = follow;
        for k in 0..=n {
            let t = ta + span * (k as f64) / (n as f64);
            let y = eval(t);
            if y[0].abs() > best_theta.0 {
                best_theta = (y[0].abs(), k);
            }
            if !following {
                continue;
            }
            let (d, _, fz) = self.demand(side, t, y, forced);
            if fz <= 0.0 {
                let tl = match prev {
                    Some((tp, _, _)) => {
                        self.refine_crossing(tp, t, side, forced, &eval, |_, fz| -fz)
                    }
                    None => t,
                };
                self.first_lift_off = Some(tl);
                demand_until = tl;
                following = false;
                continue;
            }
            if d > best_demand.0 {
                best_demand = (d, k);
            }
            if let Some(mu) = self.block.friction
                && self.first_sliding.is_none()
                && d > mu
            {
                self.first_sliding = Some(match prev {
                    Some((tp, dp, _)) if dp <= mu => {
                        self.refine_crossing(tp, t, side, forced, &eval, |d, _| d - mu)
                    }
                    _ => t,
                });
            }
            prev = Some((t, d, fz));
        }
        let at = |k: usize| ta + span * (k as f64) / (n as f64);
        let bracket = |k: usize| (at(k.saturating_sub(1)), at((k + 1).min(n)));
        let (lo, hi) = bracket(best_theta.1);
        let (_, v) = golden_max(lo, hi, |t| eval(t)[0].abs());
        self.peak_theta = self.peak_theta.max(v.max(best_theta.0));
        if follow && best_demand.0.is_finite() {
            let (lo, hi) = bracket(best_demand.1);
            let hi = hi.min(demand_until);
            let (t, v) = golden_max(lo, hi.max(lo), |t| {
                let (d, _, fz) = self.demand(side, t, eval(t), forced);
                if fz > 0.0 { d } else { 0.0 }
            });
            let (t, v) = if v >= best_demand.0 {
                (t, v)
            } else {
                (at(best_demand.1), best_demand.0)
            };
            if v > self.peak_demand.0 {
                self.peak_demand = (v, t);
            }
        }
    }

    fn refine_crossing<E: Fn(f64) -> State, C: Fn(f64, f64) -> f64>(
        &self,
        mut lo: f64,
        mut hi: f64,
        side: f64,
        forced: bool,
        eval: &E,
        crit: C,
    ) -> f64 {
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            let (d, _, fz) = self.demand(side, mid, eval(mid), forced);
            if crit(d, fz) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }

    /// The block at rest on the base over `[ta, tb]` (moving with the ground),
    /// or over `[ta, tb)` when `rocking_follows`: rocking starts at `tb`, and
    /// that instant belongs to the rocking motion (its demand is eq. 7, taken
    /// by [`Tracker::rocking`]), not to the rest.
    pub fn resting(&mut self, ta: f64, tb: f64, rocking_follows: bool) {
        if !self.active() || tb < ta {
            return;
        }
        while let Some(&ts) = self.req.series_times.get(self.next_sample) {
            if ts > tb || (rocking_follows && ts >= tb) {
                break;
            }
            if ts >= ta {
                self.push_sample(ts, [0.0, 0.0], None, true);
            }
            self.next_sample += 1;
        }
        // A pulse that starts at or above the threshold starts rocking at once:
        // the block never rests, and |ü_g|/g there is no demand at all.
        let never_at_rest = rocking_follows && tb <= ta;
        if self.req.reactions && self.reactions_on && !never_at_rest {
            // At rest f_x = m ü_g and f_z = m g: the demand is |ü_g|/g. Over
            // [ta, tb) its supremum is the maximum over [ta, tb], the forcing
            // being continuous where a rest ends in rocking (at tb it reaches
            // the threshold, where eq. 7 gives the same value).
            let g = self.block.gravity;
            let best = self.pulse.peak_between(ta, tb);
            let d = best.0 / g;
            if d > self.peak_demand.0 {
                self.peak_demand = (d, best.1);
            }
            if let Some(mu) = self.block.friction
                && self.first_sliding.is_none()
                && d > mu
            {
                self.first_sliding = Some(best.1);
            }
        }
    }

    fn push_sample(&mut self, t: f64, y: State, side: Option<f64>, forced: bool) {
        let ground = self.ground(t, forced);
        self.series.t.push(t);
        self.series.theta.push(y[0]);
        self.series.theta_dot.push(y[1]);
        self.series.ground_acceleration.push(ground);
        if let Some(r) = self.series.reaction_ratio.as_mut() {
            let ratio = match side {
                Some(s) => {
                    let (fx, fz) =
                        reactions_per_mass(self.formulation, self.block, s, y[0], y[1], ground);
                    (fz > 0.0).then_some(fx / fz)
                }
                None => Some(ground / self.block.gravity),
            };
            r.push(ratio);
        }
    }

    /// The collected series; f_x/f_z is left out from the first lift-off on
    /// (pure rocking, and so the ratio, has no meaning after it).
    pub fn take_series(&mut self) -> Series {
        let mut series = std::mem::take(&mut self.series);
        if let (Some(tl), Some(ratio)) = (self.first_lift_off, series.reaction_ratio.as_mut()) {
            for (r, &t) in ratio.iter_mut().zip(&series.t) {
                if t >= tl {
                    *r = None;
                }
            }
        }
        series
    }

    /// Fills series samples at or after `t` with a constant state (after the
    /// motion ended: at rest, or the last state before overturning).
    pub fn finish(&mut self, end: f64) {
        while let Some(&ts) = self.req.series_times.get(self.next_sample) {
            if ts > end {
                break;
            }
            self.push_sample(ts, [0.0, 0.0], None, true);
            self.next_sample += 1;
        }
    }
}

/// Golden-section search for the maximum of `f` on `[lo, hi]`.
fn golden_max<F: Fn(f64) -> f64>(mut lo: f64, mut hi: f64, f: F) -> (f64, f64) {
    const R: f64 = 0.618_033_988_749_894_8;
    let mut x1 = hi - R * (hi - lo);
    let mut x2 = lo + R * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..40 {
        if f1 < f2 {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + R * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - R * (hi - lo);
            f1 = f(x1);
        }
        if hi - lo <= 1e-14 * hi.abs().max(1e-300) {
            break;
        }
    }
    if f1 > f2 { (x1, f1) } else { (x2, f2) }
}
