//! Quantities followed along a history: peak rotation, friction demand, series.
//!
//! The propagators hand every piece of motion to a [`Tracker`] as a function of
//! time (a closed-form segment or a step's dense output) with its end states.
//! Nothing here runs unless asked for.
//!
//! Where the ground acceleration is linear over the piece (a record's piece
//! inside one sample interval, free rocking), the forcing has no time scale of
//! its own: the piece is sampled for the block's time scale only (pτ ≤ 1/2
//! between samples, a single interval for a record's 0.01-s piece), and at
//! every sample |θ| and the demand |f_x/f_z| come with their exact time
//! derivatives (θ̇, and [`reaction_rates`]). A maximum inside an interval
//! between samples is looked for only where one can be (see
//! [`interior_max`]) and then located as a root of the derivative. Elsewhere
//! (a pulse) the piece is sampled densely enough for the forcing and the block
//! and the maxima refined by golden-section search around the best sample.
//! Under a vertical ground motion the reactions carry g + ü_v
//! ([`reactions_per_mass_vertical`]); a pair of records is linear in both
//! components over a sample interval, and its pieces are followed as a
//! record's, the demand's rate carrying the vertical jerk too.

use super::block::Block;
use super::equations::Formulation;
use super::forcing::Forcing;
use super::integrator::State;
use super::reactions::{
    ReactionModel, ReactionRates, reactions_per_mass, reactions_per_mass_vertical,
};
use super::response::Series;
use super::separatrix::{FreeOutcome, decide};

/// What to follow.
#[derive(Clone, Debug, Default)]
pub struct TrackRequest {
    /// Follow max |θ|.
    pub peak: bool,
    /// Follow f_x/f_z.
    pub reactions: bool,
    /// Uniform sample times for the series (sorted).
    pub series_times: Vec<f64>,
    /// Leave out of the friction demand the fall of a block that overturns
    /// while still forced (see [`Tracker::bound_to_overturn`]).
    pub fall_under_forcing: bool,
    /// Locate the peaks of |θ| and of the demand between the samples of a
    /// piece under a pulse (golden section); else the samples' largest
    /// stand. The first sliding and lift-off are found on the samples
    /// either way: an outcome that asks only those needs no peak.
    pub refine_peaks: bool,
}

/// The counts as they stood where the block, still forced, became bound to
/// overturn (the free motion from there overturns): restored, and the
/// demand's following stopped there, if it overturns before any state lets
/// it go (its fall is then not counted, as after a pulse's end).
#[derive(Clone, Copy, Debug)]
struct FallStart {
    /// Where the block became bound to overturn, s.
    t: f64,
    /// The peak demand and its time there.
    peak_demand: (f64, f64),
    /// The first sliding there.
    first_sliding: Option<f64>,
    /// The first lift-off there.
    first_lift_off: Option<f64>,
}

/// A piece of rocking scanned at `n` + 1 evenly spaced samples.
struct Piece {
    /// Its start, s.
    ta: f64,
    /// Its length, s.
    span: f64,
    n: usize,
    side: f64,
    forced: bool,
}

impl Piece {
    /// The time of sample `k`.
    fn at(&self, k: usize) -> f64 {
        self.ta + self.span * (k as f64) / (self.n as f64)
    }
}

/// What a scan of a piece of rocking found: the largest |θ| and demand
/// (value, sample), and until when the demand was followed.
struct Scan {
    theta: (f64, usize),
    demand: (f64, usize),
    demand_until: f64,
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
    /// Whether it stopped while the ground still moved (a fall under
    /// forcing), not at the end of the ground motion.
    pub stopped_while_forced: bool,
    /// Where the block, still forced, became bound to overturn, while it
    /// stays so.
    fall: Option<FallStart>,
    /// Whether the demand is still followed (off once the block is doomed).
    reactions_on: bool,
    /// The block's reactions, for the pieces under linear ground motion.
    model: ReactionModel,
    /// The demand at the end of the last such piece, (t, state, side,
    /// forced, demand; t NaN before any): the next one mostly starts there.
    last_end: (f64, State, f64, bool, Demand),
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
            vertical_acceleration: G::VERTICAL.then(|| Vec::with_capacity(n)),
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
            stopped_while_forced: false,
            fall: None,
            reactions_on: true,
            model: ReactionModel::new(formulation, block),
            last_end: (f64::NAN, [0.0; 2], 0.0, false, Demand::LIFTED),
        }
    }

    /// Stops following the friction demand at `t` (the block is already bound
    /// to overturn: its fall is not rocking).
    fn stop_reactions(&mut self, t: f64) {
        if self.reactions_on && self.req.reactions {
            self.reactions_stopped_at = Some(t);
        }
        self.reactions_on = false;
    }

    /// The block is bound to overturn: the friction demand is followed no
    /// further, its fall is not counted.
    ///
    /// `Some(t)`: the ground motion is over at `t` and the free motion from
    /// there overturns ([`decide`]); the demand stops at `t`. `None`: the
    /// block overturned while the ground still moved. With
    /// [`TrackRequest::fall_under_forcing`] the demand then stops where the
    /// free motion from every piece's start overturned, to the end (see
    /// [`Tracker::watch_fall`]), earlier than `t` where that stretch began
    /// before: the peak demand, first sliding and first lift-off are the
    /// ones that stood there. Without such a stretch an overturning under
    /// forcing changes nothing (a pulse's demand is followed while it acts).
    pub fn bound_to_overturn(&mut self, t: Option<f64>) {
        match (self.fall.take(), t) {
            (Some(f), _) => {
                if self.reactions_on && self.req.reactions {
                    self.peak_demand = f.peak_demand;
                    self.first_sliding = f.first_sliding;
                    self.first_lift_off = f.first_lift_off;
                    self.stopped_while_forced = true;
                }
                self.stop_reactions(f.t);
            }
            (None, Some(t)) => self.stop_reactions(t),
            (None, None) => {}
        }
    }

    /// Notes at the start `(t, y)` of a forced piece on `side` whether the
    /// block is bound to overturn: whether the free motion from there
    /// overturns ([`decide`], the verdict given at a pulse's end). The first
    /// piece of an unbroken run of such verdicts keeps the counts as they
    /// stand ([`FallStart`]); a piece whose verdict lets the block go
    /// discards them, the demand since counting in full. Only with
    /// [`TrackRequest::fall_under_forcing`] and while the demand is followed.
    fn watch_fall(&mut self, t: f64, y: State, side: f64, forced: bool) {
        if !(forced && self.req.fall_under_forcing && self.req.reactions && self.reactions_on) {
            return;
        }
        let bound = matches!(
            decide(self.formulation, self.block, y[0], y[1], side),
            FreeOutcome::Overturns { .. }
        );
        if !bound {
            self.fall = None;
        } else if self.fall.is_none() {
            self.fall = Some(FallStart {
                t,
                peak_demand: self.peak_demand,
                first_sliding: self.first_sliding,
                first_lift_off: self.first_lift_off,
            });
        }
    }

    /// Whether pure rocking has stopped being possible on the block's floor:
    /// the demand exceeded μ, or the block lifted off.
    pub fn past_pure_rocking(&self) -> bool {
        self.first_sliding.is_some() || self.first_lift_off.is_some()
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

    /// ü_v at t (zero when free).
    fn vertical(&self, t: f64, forced: bool) -> f64 {
        if forced {
            self.pulse.vertical_acceleration(t)
        } else {
            0.0
        }
    }

    /// (f_x/m, f_z/m) at a rocking state on `side`.
    #[inline]
    fn reactions(&self, side: f64, t: f64, y: State, forced: bool) -> (f64, f64) {
        let ground = self.ground(t, forced);
        if G::VERTICAL {
            reactions_per_mass_vertical(
                self.formulation,
                self.block,
                side,
                y[0],
                y[1],
                ground,
                self.vertical(t, forced),
            )
        } else {
            reactions_per_mass(self.formulation, self.block, side, y[0], y[1], ground)
        }
    }

    /// (|f_x/f_z| or ∞ when f_z ≤ 0, f_z) at a rocking state.
    fn demand(&self, side: f64, t: f64, y: State, forced: bool) -> (f64, f64, f64) {
        let (fx, fz) = self.reactions(side, t, y, forced);
        let d = if fz > 0.0 {
            (fx / fz).abs()
        } else {
            f64::INFINITY
        };
        (d, fx / fz, fz)
    }

    /// A piece of rocking motion on `side` from `start` = (ta, state at ta)
    /// to `end` = (tb, state at tb), `eval` giving the state in between.
    pub fn rocking<E: Fn(f64) -> State>(
        &mut self,
        start: (f64, State),
        end: (f64, State),
        side: f64,
        forced: bool,
        eval: E,
    ) {
        let (ta, tb) = (start.0, end.0);
        if !self.active() || tb < ta {
            return;
        }
        self.watch_fall(ta, start.1, side, forced);
        self.rocking_samples((ta, tb), side, forced, &eval);
        if !(self.req.peak || self.req.reactions) {
            return;
        }
        // Free rocking feels no ground at all.
        let linear = if forced {
            self.pulse
                .linear_over(ta, tb)
                .map(|h| [h, self.pulse.vertical_jerk_over(ta, tb)])
        } else {
            Some([0.0; 2])
        };
        if let Some(jerk) = linear {
            self.rocking_linear(start, end, side, forced, jerk, &eval);
            return;
        }
        let span = tb - ta;
        let w = if forced {
            self.pulse.resolving_frequency()
        } else {
            0.0
        };
        let p = self.block.frequency_parameter();
        let n = (8.0 + span * (4.0 * w / std::f64::consts::PI + 2.0 * p)).min(400.0) as usize;
        let piece = Piece {
            ta,
            span,
            n,
            side,
            forced,
        };
        self.rocking_scanned(&piece, tb, &eval);
    }

    /// The series samples falling in a piece of rocking on `side` over
    /// `(ta, tb)`.
    fn rocking_samples<E: Fn(f64) -> State>(
        &mut self,
        (ta, tb): (f64, f64),
        side: f64,
        forced: bool,
        eval: &E,
    ) {
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
    }

    /// The peaks of |θ| and of the friction demand over a `piece` of rocking
    /// (ending at `tb`) under a ground motion with no closed form: its
    /// samples scanned, the largest refined by golden section; where it
    /// slides or lifts off first.
    fn rocking_scanned<E: Fn(f64) -> State>(&mut self, piece: &Piece, tb: f64, eval: &E) {
        let (side, forced) = (piece.side, piece.forced);
        // Pure rocking (and so the demand) is meaningful only while f_z > 0.
        let follow = self.req.reactions && self.reactions_on && self.first_lift_off.is_none();
        let scan = self.scan(piece, tb, follow, eval);
        let (best_theta, best_demand) = (scan.theta, scan.demand);
        if !self.req.refine_peaks {
            self.peak_theta = self.peak_theta.max(best_theta.0);
            if follow && best_demand.0.is_finite() {
                self.demand_sample(piece.at(best_demand.1), best_demand.0);
            }
            return;
        }
        let at = |k: usize| piece.at(k);
        let bracket = |k: usize| (at(k.saturating_sub(1)), at((k + 1).min(piece.n)));
        let (lo, hi) = bracket(best_theta.1);
        let (_, v) = golden_max(lo, hi, |t| eval(t)[0].abs());
        self.peak_theta = self.peak_theta.max(v.max(best_theta.0));
        if follow && best_demand.0.is_finite() {
            let (lo, hi) = bracket(best_demand.1);
            let hi = hi.min(scan.demand_until);
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

    /// The samples of a `piece` of rocking (ending at `tb`): the largest |θ|
    /// and, while the demand is followed (`follow`), the largest demand;
    /// where it first lifts off or exceeds μ, refined.
    fn scan<E: Fn(f64) -> State>(
        &mut self,
        piece: &Piece,
        tb: f64,
        follow: bool,
        eval: &E,
    ) -> Scan {
        let (side, forced) = (piece.side, piece.forced);
        let mut best_theta = (f64::NEG_INFINITY, 0usize);
        let mut best_demand = (f64::NEG_INFINITY, 0usize);
        let mut prev: Option<(f64, f64, f64)> = None;
        let mut demand_until = tb;
        let mut following = follow;
        for k in 0..=piece.n {
            let t = piece.at(k);
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
                        self.refine_crossing(tp, t, side, forced, eval, |_, fz| -fz)
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
            if let Some(mu) = self.block.friction()
                && self.first_sliding.is_none()
                && d > mu
            {
                self.first_sliding = Some(match prev {
                    Some((tp, dp, _)) if dp <= mu => {
                        self.refine_crossing(tp, t, side, forced, eval, |d, _| d - mu)
                    }
                    _ => t,
                });
            }
            prev = Some((t, d, fz));
        }
        Scan {
            theta: best_theta,
            demand: best_demand,
            demand_until,
        }
    }

    /// The demand and its rate at `(t, y)` on `side`.
    #[inline]
    fn demand_at(&self, t: f64, y: State, side: f64, forced: bool) -> Demand {
        let ground = self.ground(t, forced);
        if G::VERTICAL {
            let vertical = self.vertical(t, forced);
            Demand::new(
                &self
                    .model
                    .rates_vertical(side, y[0], y[1], ground, vertical),
            )
        } else {
            Demand::new(&self.model.rates(side, y[0], y[1], ground))
        }
    }

    /// |θ| (as sθ) and the demand with their rates at `(t, y)`, the ground's
    /// jerks (horizontal, vertical) being `jerk`; the demand only when
    /// `demand` (NaN otherwise).
    #[inline(always)]
    fn probe(
        &self,
        t: f64,
        y: State,
        side: f64,
        forced: bool,
        jerk: [f64; 2],
        demand: bool,
    ) -> Probe {
        let d = demand.then(|| self.demand_at(t, y, side, forced));
        Probe::new(t, y, side, jerk, d.as_ref())
    }

    /// A piece over which the ground acceleration is linear (slopes `jerk`:
    /// horizontal, vertical).
    ///
    /// Samples: both ends (their states given) and, for a piece longer than
    /// 1/(2p), enough interior points for the block's time scale (pτ ≤ 1/2
    /// between samples). Peak |θ| and peak demand: the samples, and between
    /// consecutive samples the interior maximum where [`interior_max`] finds
    /// one. The first sliding and lift-off are the first crossings, refined
    /// between the last sample (or interior point) below and the first above.
    ///
    /// The demand at the end is evaluated on every piece, even one that
    /// looks unable to beat the running peak: a bound good enough to skip it
    /// would have to cover the jumps of its rate at every sample (the
    /// record's slope changes there), and under a record the demand moves by
    /// several hundredths per 0.01-s piece, so such a bound reaches the peak
    /// within a piece or two. The end's demand, reactions and all, is kept
    /// for the next piece, which starts there: one evaluation per piece.
    fn rocking_linear<E: Fn(f64) -> State>(
        &mut self,
        start: (f64, State),
        end: (f64, State),
        side: f64,
        forced: bool,
        jerk: [f64; 2],
        eval: &E,
    ) {
        let (ta, tb) = (start.0, end.0);
        let span = tb - ta;
        let p = self.block.frequency_parameter();
        let reach = 2.0 * p * span;
        let n = if reach <= 1.0 {
            1
        } else {
            reach.ceil().min(400.0) as usize
        };
        // Pure rocking (and so the demand) is meaningful only while f_z > 0.
        let mut following =
            self.req.reactions && self.reactions_on && self.first_lift_off.is_none();
        let mut prev = self.probe(ta, start.1, side, forced, jerk, false);
        self.peak_theta = self.peak_theta.max(start.1[0].abs());
        if following {
            // The start is mostly where the last piece ended: same state and
            // demand (already counted), only the jerk differs.
            let (t, y, s, f, d) = self.last_end;
            if t == ta && y == start.1 && s == side && f == forced {
                prev.demand = d.with_jerk(jerk);
            } else {
                prev.demand = self.demand_at(ta, start.1, side, forced).with_jerk(jerk);
                if prev.demand[0].is_finite() {
                    self.demand_sample(ta, prev.demand[0]);
                    if let Some(mu) = self.block.friction()
                        && self.first_sliding.is_none()
                        && prev.demand[0] > mu
                    {
                        self.first_sliding = Some(ta);
                    }
                } else {
                    self.first_lift_off = Some(ta);
                    following = false;
                }
            }
        }
        for k in 1..=n {
            let (t, y) = if k == n {
                end
            } else {
                let t = ta + span * (k as f64) / (n as f64);
                (t, eval(t))
            };
            let cur = if following && k == n {
                let d = self.demand_at(t, y, side, forced);
                self.last_end = (t, y, side, forced, d);
                Probe::new(t, y, side, jerk, Some(&d))
            } else {
                self.probe(t, y, side, forced, jerk, following)
            };
            self.peak_theta = self.peak_theta.max(y[0].abs());
            let lean = |t: f64| {
                let y = eval(t);
                [side * y[0], side * y[1]]
            };
            if let Some((_, v)) = interior_max((prev.t, prev.lean), (cur.t, cur.lean), lean) {
                self.peak_theta = self.peak_theta.max(v);
            }
            if following {
                following = self.demand_between(&prev, &cur, side, forced, jerk, eval);
            }
            prev = cur;
        }
    }

    /// The demand between consecutive samples `a` (followed, f_z > 0) and `b`
    /// of a piece under linear ground motion; whether it is still followed
    /// after `b` (not once the block lifts off).
    fn demand_between<E: Fn(f64) -> State>(
        &mut self,
        a: &Probe,
        b: &Probe,
        side: f64,
        forced: bool,
        jerk: [f64; 2],
        eval: &E,
    ) -> bool {
        let demand = |t: f64| self.probe(t, eval(t), side, forced, jerk, true).demand;
        // A lift-off inside shows as an interior maximum of the demand (it
        // grows without bound as f_z → 0⁺); the search stops on it.
        let interior = if b.demand[0].is_finite() {
            interior_max((a.t, a.demand), (b.t, b.demand), demand)
        } else {
            None
        };
        let lift = match interior {
            Some((t, v)) if !v.is_finite() => Some(t),
            _ if !b.demand[0].is_finite() => Some(b.t),
            _ => None,
        };
        // The first time the demand exceeds μ, from below at `a`.
        let mu = self
            .block
            .friction()
            .filter(|&mu| self.first_sliding.is_none() && a.demand[0] <= mu);
        if let Some(t_above) = lift {
            let tl = self.refine_crossing(a.t, t_above, side, forced, eval, |_, fz| -fz);
            if let Some(mu) = mu {
                self.first_sliding =
                    Some(self.refine_crossing(a.t, tl, side, forced, eval, |d, _| d - mu));
            }
            self.first_lift_off = Some(tl);
            return false;
        }
        if let Some((t, v)) = interior {
            self.demand_sample(t, v);
            if let Some(mu) = mu
                && v > mu
            {
                self.first_sliding =
                    Some(self.refine_crossing(a.t, t, side, forced, eval, |d, _| d - mu));
            }
        }
        if let Some(mu) = mu
            && self.first_sliding.is_none()
            && b.demand[0] > mu
        {
            self.first_sliding =
                Some(self.refine_crossing(a.t, b.t, side, forced, eval, |d, _| d - mu));
        }
        self.demand_sample(b.t, b.demand[0]);
        true
    }

    /// A demand reached at `t`: the peak so far if above it.
    #[inline]
    fn demand_sample(&mut self, t: f64, d: f64) {
        if d > self.peak_demand.0 {
            self.peak_demand = (d, t);
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
            let g = self.block.gravity();
            let best = self.pulse.rest_demand_peak(ta, tb, g);
            let d = best.0;
            if d > self.peak_demand.0 {
                self.peak_demand = (d, best.1);
            }
            if let Some(mu) = self.block.friction()
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
        if G::VERTICAL {
            let vertical = self.vertical(t, forced);
            if let Some(v) = self.series.vertical_acceleration.as_mut() {
                v.push(vertical);
            }
        }
        if self.series.reaction_ratio.is_some() {
            let ratio = match side {
                Some(s) => {
                    let (fx, fz) = self.reactions(s, t, y, forced);
                    (fz > 0.0).then_some(fx / fz)
                }
                None if G::VERTICAL => {
                    let fz = self.block.gravity() + self.vertical(t, forced);
                    (fz > 0.0).then_some(ground / fz)
                }
                None => Some(ground / self.block.gravity()),
            };
            if let Some(r) = self.series.reaction_ratio.as_mut() {
                r.push(ratio);
            }
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

/// A sample on a piece under linear ground motion: values and time
/// derivatives of the followed quantities.
#[derive(Clone, Copy, Debug)]
struct Probe {
    t: f64,
    /// [sθ, sθ̇]: |θ| on side s and its rate.
    lean: [f64; 2],
    /// [|f_x/f_z|, its rate]; [∞, 0] once f_z ≤ 0; NaN when not followed.
    demand: [f64; 2],
}

impl Probe {
    /// The probe at `(t, y)` on `side` with the demand `demand` there (NaN
    /// without it), the ground's jerks being `jerk` (horizontal, vertical).
    #[inline]
    fn new(t: f64, y: State, side: f64, jerk: [f64; 2], demand: Option<&Demand>) -> Self {
        let lean = [side * y[0], side * y[1]];
        let demand = match demand {
            None => [f64::NAN; 2],
            Some(d) => d.with_jerk(jerk),
        };
        Probe { t, lean, demand }
    }
}

/// f_x/f_z at a state and its rate less the jerk's part: all a sample needs,
/// the same on both sides of a record's sample.
#[derive(Clone, Copy, Debug)]
struct Demand {
    ratio: f64,
    /// d(f_x/f_z)/dt = rate[0] + rate[1] · jerk + rate_v · vertical jerk.
    rate: [f64; 2],
    rate_v: f64,
    /// f_z ≤ 0.
    lifted: bool,
}

impl Demand {
    /// The state of a block lifted off.
    const LIFTED: Demand = Demand {
        ratio: f64::INFINITY,
        rate: [0.0; 2],
        rate_v: 0.0,
        lifted: true,
    };

    #[inline]
    fn new(r: &ReactionRates) -> Self {
        Demand {
            ratio: r.ratio,
            rate: r.ratio_rate,
            rate_v: r.vertical_rate[2],
            lifted: r.fz <= 0.0 || r.fz.is_nan(),
        }
    }

    /// [|f_x/f_z|, its rate] under the jerks `jerk` (horizontal, vertical);
    /// [∞, 0] once lifted off.
    #[inline]
    fn with_jerk(&self, jerk: [f64; 2]) -> [f64; 2] {
        if self.lifted {
            // Lift-off: no friction sustains pure rocking.
            return [f64::INFINITY, 0.0];
        }
        let mut rate = self.rate[0] + self.rate[1] * jerk[0];
        if jerk[1] != 0.0 {
            rate += self.rate_v * jerk[1];
        }
        [
            self.ratio.abs(),
            if self.ratio < 0.0 { -rate } else { rate },
        ]
    }
}

/// The largest value found inside `(a.0, b.0)` of a smooth `f` (`f(t)` =
/// [value, derivative]) given value and derivative at both ends, or `None`
/// where no interior local maximum is to be looked for.
///
/// The criterion, on the derivative at the ends (f′ₐ, f′ᵦ):
/// - f′ₐ > 0 > f′ᵦ: a maximum is inside for certain; it is located as the
///   root of f′ ([`maximise`]).
/// - f′ₐ ≤ 0 ≤ f′ᵦ: none. A maximum would need f′ to change sign at least
///   three times in between (− + − +), f″ twice: the cubic Hermite
///   interpolant of the end values and rates, accurate to O(h⁴ f⁗) on an
///   interval short against f's time scales (which the sampling ensures),
///   has at most a minimum there.
/// - f′ of one sign at both ends: a maximum needs two interior critical
///   points. Where the Hermite cubic has them, f′ is evaluated at the
///   cubic's extreme slope, and a sign change found there brackets the
///   maximum; otherwise there is none, the interval being too short for f′
///   to change sign twice unseen by the cubic.
///
/// Every value returned is a value of f itself, never of a model: the
/// result never overstates a maximum.
fn interior_max<F: FnMut(f64) -> [f64; 2]>(
    a: (f64, [f64; 2]),
    b: (f64, [f64; 2]),
    mut f: F,
) -> Option<(f64, f64)> {
    let (da, db) = (a.1[1], b.1[1]);
    let (rising, falling) = (da > 0.0, db < 0.0);
    // The Hermite cubic's slope, in s = (t − tₐ)/h ∈ [0, 1]:
    // D(s) = m₀ + qb s + qa s², with D(1) = m₁ and ∫₀¹ D = fᵦ − fₐ.
    let h = b.0 - a.0;
    let (m0, m1, rise) = (h * da, h * db, b.1[0] - a.1[0]);
    let qa = 3.0 * (m0 + m1) - 6.0 * rise;
    let qb = 6.0 * rise - 4.0 * m0 - 2.0 * m1;
    // Its extreme at s = num/den (den > 0) must lie inside (0, 1), and its
    // value there, times den², have the sign that turns f back. All of it
    // is worked out without a division or a branch: nearly every interval
    // ends at the one test below.
    let flip = if qa < 0.0 { -1.0 } else { 1.0 };
    let (num, den) = (-qb * flip, 2.0 * qa * flip);
    let extreme = m0 * den * den + num * (qb * den + qa * num);
    let turns = if rising { -extreme } else { extreme } > 0.0;
    let certain = rising & falling;
    let inside = (num > 0.0) & (num < den);
    if !(certain | ((rising | falling) & inside & turns)) {
        return None;
    }
    if certain {
        return Some(maximise(a, b, &mut f));
    }
    let s = num / den;
    let tv = a.0 + s * h;
    let v = f(tv);
    let probe = (tv, v[0]);
    if !v[0].is_finite() {
        return Some(probe);
    }
    let inner = if rising && v[1] < 0.0 {
        Some(maximise(a, (tv, v), &mut f))
    } else if !rising && v[1] > 0.0 {
        Some(maximise((tv, v), b, &mut f))
    } else {
        None
    };
    Some(match inner {
        Some(m) if m.1 > probe.1 || !m.1.is_finite() => m,
        _ => probe,
    })
}

/// Most evaluations [`maximise`] spends.
const MAX_REFINE: usize = 60;

/// The maximum of a smooth `f` inside `(a.0, b.0)`, where f′(a) > 0 > f′(b):
/// the root of f′ by regula falsi (Illinois), stopping once the gain still
/// to be had, f′²/(2|f″|) with f″ the bracket's secant slope of f′, is below
/// the rounding of f, or the bracket cannot shrink. Returns the best
/// (t, f(t)) evaluated; stops at once on a non-finite value (a lift-off).
fn maximise<F: FnMut(f64) -> [f64; 2]>(
    mut a: (f64, [f64; 2]),
    mut b: (f64, [f64; 2]),
    f: &mut F,
) -> (f64, f64) {
    let mut best = (0.5 * (a.0 + b.0), f64::NEG_INFINITY);
    // The slopes used for the secant (Illinois halves a stale end's).
    let (mut sa, mut sb) = (a.1[1], b.1[1]);
    let mut kept = 0i8;
    for _ in 0..MAX_REFINE {
        let w = b.0 - a.0;
        let mut t = a.0 + w * (sa / (sa - sb));
        if !(t > a.0 && t < b.0) {
            t = a.0 + 0.5 * w;
            if !(t > a.0 && t < b.0) {
                break;
            }
        }
        let v = f(t);
        if v[0] > best.1 || !v[0].is_finite() {
            best = (t, v[0]);
        }
        if !v[0].is_finite() {
            break;
        }
        if v[1] > 0.0 {
            a = (t, v);
            sa = v[1];
            if kept > 0 {
                sb *= 0.5;
            }
            kept = 1;
        } else if v[1] < 0.0 {
            b = (t, v);
            sb = v[1];
            if kept < 0 {
                sa *= 0.5;
            }
            kept = -1;
        } else {
            break;
        }
        let curvature = (a.1[1] - b.1[1]) / (b.0 - a.0);
        if v[1] * v[1] <= 2.0 * f64::EPSILON * curvature * v[0].abs() {
            break;
        }
    }
    best
}

/// Golden-section search for the maximum of `f` on `[lo, hi]`: 40
/// reductions at most (a span shrinks by 0.618 each), or a span of 1e-14
/// relative.
fn golden_max<F: Fn(f64) -> f64>(lo: f64, hi: f64, f: F) -> (f64, f64) {
    golden_max_in(lo, hi, 40, f)
}

/// Golden-section search for the maximum of `f` on `[lo, hi]` in at most
/// `steps` reductions, or down to a span of 1e-14 relative.
pub(crate) fn golden_max_in<F: Fn(f64) -> f64>(
    mut lo: f64,
    mut hi: f64,
    steps: usize,
    f: F,
) -> (f64, f64) {
    const R: f64 = 0.618_033_988_749_894_8;
    let mut x1 = hi - R * (hi - lo);
    let mut x2 = lo + R * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..steps {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// [f, f′] of the cubic t³ − 1.5 t² + 0.6 t, scaled by `sign`: rising at
    /// both ends of [0, 1] (sign +1) with a maximum at (3 − √1.8)/6 and a
    /// minimum at (3 + √1.8)/6 inside; falling at both ends when negated.
    fn cubic(sign: f64) -> impl Fn(f64) -> [f64; 2] {
        move |t: f64| {
            [
                sign * (t * t * t - 1.5 * t * t + 0.6 * t),
                sign * (3.0 * t * t - 3.0 * t + 0.6),
            ]
        }
    }

    fn ends<F: Fn(f64) -> [f64; 2]>(f: &F, a: f64, b: f64) -> ((f64, [f64; 2]), (f64, [f64; 2])) {
        ((a, f(a)), (b, f(b)))
    }

    #[test]
    fn a_sign_change_of_the_derivative_is_located_to_rounding() {
        // f = cos(t) on [−1, 2]: the maximum 1 at t = 0, found in a few steps.
        let f = |t: f64| [t.cos(), -t.sin()];
        let calls = std::cell::Cell::new(0);
        let counted = |t: f64| {
            calls.set(calls.get() + 1);
            f(t)
        };
        let (a, b) = ends(&f, -1.0, 2.0);
        let (t, v) = interior_max(a, b, counted).expect("a maximum inside");
        assert!(t.abs() < 1e-7 && v == 1.0, "{t} {v}");
        assert!(calls.get() <= 12, "{} evaluations", calls.get());
    }

    #[test]
    fn a_maximum_between_two_rising_ends_is_found_where_the_cubic_turns() {
        let top = (3.0 - 1.8f64.sqrt()) / 6.0;
        let f = cubic(1.0);
        let (a, b) = ends(&f, 0.0, 1.0);
        let (t, v) = interior_max(a, b, &f).expect("a maximum inside");
        assert!(
            (t - top).abs() < 1e-7 && (v - f(top)[0]).abs() < 1e-15,
            "{t} {v}"
        );
        // Falling at both ends: the maximum is the later critical point.
        let f = cubic(-1.0);
        let (a, b) = ends(&f, 0.0, 1.0);
        let (t, v) = interior_max(a, b, &f).expect("a maximum inside");
        let top = 1.0 - top;
        assert!(
            (t - top).abs() < 1e-7 && (v - f(top)[0]).abs() < 1e-15,
            "{t} {v}"
        );
    }

    #[test]
    fn no_search_where_no_maximum_can_be_inside() {
        let never = |_: f64| -> [f64; 2] { panic!("no evaluation expected") };
        // Monotone, either way.
        let f = |t: f64| [t, 1.0];
        let (a, b) = ends(&f, 0.0, 1.0);
        assert_eq!(interior_max(a, b, never), None);
        let f = |t: f64| [-t * t, -2.0 * t];
        let (a, b) = ends(&f, 0.5, 1.0);
        assert_eq!(interior_max(a, b, never), None);
        // Falling then rising: a minimum only.
        let f = |t: f64| [t * t, 2.0 * t];
        let (a, b) = ends(&f, -1.0, 2.0);
        assert_eq!(interior_max(a, b, never), None);
        // The cubic on [0.5, 1]: falling, then rising past its minimum.
        let f = cubic(1.0);
        let (a, b) = ends(&f, 0.5, 1.0);
        assert_eq!(interior_max(a, b, never), None);
    }

    #[test]
    fn the_search_stops_on_a_non_finite_value() {
        // f_z reaching zero at t = 0.3: the demand is infinite from there on.
        let f = |t: f64| {
            if t >= 0.3 {
                [f64::INFINITY, 0.0]
            } else {
                [1.0 / (0.3 - t), 1.0 / (0.3 - t).powi(2)]
            }
        };
        let a = (0.0, f(0.0));
        let b = (1.0, [1.0, -1.0]);
        let (t, v) = interior_max(a, b, f).expect("lift-off inside");
        assert!(v.is_infinite() && (0.3..1.0).contains(&t), "{t} {v}");
    }
}
