//! The overturning set along one line of constant ω_p/p: a scan in a_p/(αg)
//! followed by adaptive bisection wherever neighbouring amplitudes differ in
//! outcome, mode or impact count.
//!
//! ## Guarantee
//! With scan step `h` and tolerance `tol`:
//! - every interval of amplitudes (overturning band or safe interval) wider than
//!   `h` contains a scan point and is found;
//! - every band wider than `tol` that lies between amplitudes differing in impact
//!   count is found too: the refinement keeps bisecting any interval whose ends
//!   differ in (overturned, mode, impact count) until it is narrower than `tol`.
//!   This is what finds the combs of narrow bands near the rocking threshold,
//!   whose impact counts step by two.
//!
//! A band narrower than `h` with the same impact count on both sides, at both
//! neighbouring scan points, can be missed.

use crate::dynamics::floor::run_coulomb;
use crate::dynamics::sliding::{Friction, Kinematics};
use crate::dynamics::{
    Block, Forcing, Options, Problem, Pulse, PulsePair, Record, RecordPair, SimError, Solver,
    simulate,
};

use super::control::{Canceled, Control};
use super::verify::{self, Mixed};

/// The discrete outcome of one simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signature {
    /// Overturned.
    pub overturned: bool,
    /// 1 or 2 when overturned.
    pub mode: Option<u8>,
    /// Impacts before overturning; for a block that survives, its rocking
    /// impacts during the pulse (not the chattering that ends each episode, whose
    /// count drifts with the amplitude without changing the motion's shape).
    pub impacts: u64,
    /// With a slide band ([`Model::slide_band`]): the block stood, on the
    /// floor, with its residual slide's size inside the band.
    pub in_band: bool,
    /// The history reached a bound on its work before its outcome was
    /// decided
    /// ([`Response::reached_limit`](crate::dynamics::Response::reached_limit)):
    /// undecided, its own outcome, left to a mixed zone, never a transition.
    pub undecided: bool,
}

/// Direction of a transition as the amplitude grows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Overturning begins.
    Up,
    /// A safe interval begins.
    Down,
    /// With a slide band: from here the block stands with its residual
    /// slide inside the band ([`Model::slide_band`]).
    SlideIn,
    /// With a slide band: from here it no longer does.
    SlideOut,
}

/// A change between surviving and overturning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition {
    /// Midpoint of the bracket, a_p/(αg).
    pub at: f64,
    /// Up or down.
    pub direction: Direction,
    /// Mode on the overturning side.
    pub mode: u8,
    /// Impact count on the overturning side.
    pub impacts: u64,
    /// [survives-or-overturns side, other side] in increasing amplitude; width ≤ tol.
    pub bracket: (f64, f64),
}

impl Transition {
    /// An edge of a slide band, not a change of overturning.
    pub fn is_slide(&self) -> bool {
        matches!(self.direction, Direction::SlideIn | Direction::SlideOut)
    }
}

/// A change of overturning mode inside an overturning region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeChange {
    /// Midpoint of the bracket, a_p/(αg).
    pub at: f64,
    /// Mode below.
    pub from: u8,
    /// Mode above.
    pub to: u8,
    /// Bracket.
    pub bracket: (f64, f64),
}

/// Statistics of a scan.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ScanStats {
    /// Simulations run.
    pub simulations: u64,
    /// Accepted steps (or closed-form segments).
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Events located.
    pub events: u64,
    /// Largest error estimate of a single simulation, rad.
    pub max_error_estimate: f64,
    /// Of the simulations, those that verified the pieces between changes
    /// and measured the mixed zones ([`super::verify`]).
    pub probes: u64,
    /// Of the simulations, those whose history reached a bound on its work
    /// before its outcome was decided ([`Signature::undecided`]).
    pub undecided: u64,
}

impl ScanStats {
    /// Adds another scan's statistics.
    pub fn absorb(&mut self, o: &ScanStats) {
        self.simulations += o.simulations;
        self.steps += o.steps;
        self.rejected += o.rejected;
        self.rhs_evaluations += o.rhs_evaluations;
        self.events += o.events;
        self.max_error_estimate = self.max_error_estimate.max(o.max_error_estimate);
        self.probes += o.probes;
        self.undecided += o.undecided;
    }
}

/// Why a scan stopped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ScanError {
    /// Canceled by the owner.
    #[error(transparent)]
    Canceled(#[from] Canceled),
    /// A simulation failed.
    #[error(transparent)]
    Simulation(#[from] SimError),
    /// The simulation at one amplitude failed.
    #[error("at a_p = {level} αg: {source}")]
    At {
        /// Amplitude, a_p/(αg).
        level: f64,
        /// What failed.
        source: SimError,
    },
}

/// How every simulation of a scan runs: its solver, and the floor (pure
/// rocking, or Coulomb friction answered by [`run_coulomb`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model {
    /// Solver.
    pub solver: Solver,
    /// Coulomb friction; `None`: pure rocking.
    pub friction: Option<Friction>,
    /// On a Coulomb floor: the sizes `[lo, hi]` of the residual slide, m,
    /// whose edges the scan locates too ([`Direction::SlideIn`],
    /// [`Direction::SlideOut`]); `None`: none.
    pub slide_band: Option<[f64; 2]>,
}

impl From<Solver> for Model {
    fn from(solver: Solver) -> Self {
        Model {
            solver,
            friction: None,
            slide_band: None,
        }
    }
}

/// A ground motion that a scan sets to a level of peak acceleration.
pub trait Scalable: Forcing + Kinematics {
    /// The same motion with its peak acceleration at `level` α g (positive).
    fn at_level(&self, level: f64, block: &Block) -> Self;
}

impl Scalable for Pulse {
    #[inline]
    fn at_level(&self, level: f64, block: &Block) -> Self {
        self.with_amplitude(level * block.slenderness() * block.gravity())
    }
}

impl Scalable for Record {
    /// The record scaled so that its PGA is `level` α g (a record without
    /// motion stays one).
    fn at_level(&self, level: f64, block: &Block) -> Self {
        let pga = self.samples().iter().fold(0.0f64, |m, a| m.max(a.abs()));
        if pga > 0.0 {
            self.scaled(level * block.slenderness() * block.gravity() / pga)
        } else {
            self.clone()
        }
    }
}

impl Scalable for PulsePair {
    /// Both pulses scaled by one factor: the horizontal one's amplitude at
    /// `level` α g, the vertical one's in proportion (a vertical motion given
    /// relative to the horizontal one stays so).
    fn at_level(&self, level: f64, block: &Block) -> Self {
        let a = level * block.slenderness() * block.gravity();
        self.scaled(a / self.horizontal.amplitude)
    }
}

impl Scalable for RecordPair {
    /// Both records scaled by one factor: the horizontal one's PGA at `level`
    /// α g (a horizontal record without motion leaves the pair as it is).
    fn at_level(&self, level: f64, block: &Block) -> Self {
        let pga = self
            .horizontal
            .samples()
            .iter()
            .fold(0.0f64, |m, a| m.max(a.abs()));
        if pga > 0.0 {
            let factor = level * block.slenderness() * block.gravity() / pga;
            RecordPair {
                horizontal: self.horizontal.scaled(factor),
                vertical: self.vertical.scaled(factor),
            }
        } else {
            self.clone()
        }
    }
}

/// The lowest level (α g) from which a ground motion scaled by
/// [`Scalable::at_level`] falls away faster than gravity somewhere
/// (g + ü_v ≤ 0: the block leaves the ground, [`Forcing::next_weightless`]),
/// as a bracket `(lo, hi)` of width at most `to`·1e-12, `lo` still on the
/// ground; `None` when it does not up to `to` (always without a vertical
/// motion). The vertical acceleration scales with the level, so that once it
/// reaches −g it does at every level above.
pub fn lift_off_level<G: Scalable>(motion: &G, block: &Block, to: f64) -> Option<(f64, f64)> {
    if !G::VERTICAL {
        return None;
    }
    let g = block.gravity();
    let lifts = |level: f64| {
        motion
            .at_level(level, block)
            .next_weightless(0.0, g)
            .is_some()
    };
    if !lifts(to) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, to);
    while hi - lo > to * 1e-12 {
        let mid = 0.5 * (lo + hi);
        if lifts(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some((lo, hi))
}

/// The lowest scale factor of vertical samples `vertical` (m/s², positive
/// up) from which the ground falls away faster than gravity at a sample
/// (g + c v_j ≤ 0: c = g / max_j(−v_j); linear between samples, so nowhere
/// before), as a bracket `(lo, hi)`, `hi` that closed form and `lo` a
/// relative 1e-12 below it (still on the ground); `None` when no sample is
/// negative. [`lift_off_level`] without the bisection.
pub fn lift_off_scale(vertical: &[f64], gravity: f64) -> Option<(f64, f64)> {
    let fall = vertical.iter().fold(0.0f64, |m, &v| m.max(-v));
    (fall > 0.0).then(|| {
        let hi = gravity / fall;
        (hi * (1.0 - 1e-12), hi)
    })
}

/// One line of the spectrum (constant ω_p/p for a pulse, constant p for a
/// record): the problem whose ground motion is scaled per point.
pub struct Line<'a, G: Scalable = Pulse> {
    /// Block, ground motion (scaled per point) and formulation.
    pub problem: Problem<G>,
    /// Solver and floor.
    pub model: Model,
    /// Owner's control.
    pub control: &'a Control,
}

impl<G: Scalable> Line<'_, G> {
    /// The outcome at amplitude `level` (a_p/(αg)).
    pub fn classify(&self, level: f64, stats: &mut ScanStats) -> Result<Signature, ScanError> {
        self.control.check()?;
        let block = self.problem.block;
        let problem = Problem {
            pulse: self.problem.pulse.at_level(level, &block),
            block,
            formulation: self.problem.formulation,
        };
        let options = Options::outcome(self.model.solver);
        let (r, slide) = match self.model.friction {
            None => (simulate(&problem, &options), 0.0),
            Some(friction) => match run_coulomb(&problem, &options, friction) {
                Ok(h) => (Ok(h.response), h.contact.residual_slide.abs()),
                Err(e) => (Err(e), 0.0),
            },
        };
        let r = r.map_err(|source| ScanError::At { level, source })?;
        stats.simulations += 1;
        stats.steps += r.numerics.steps_accepted;
        stats.rejected += r.numerics.steps_rejected;
        stats.rhs_evaluations += r.numerics.rhs_evaluations;
        stats.events += r.numerics.events;
        stats.max_error_estimate = stats.max_error_estimate.max(r.numerics.error_estimate);
        let undecided = r.reached_limit();
        stats.undecided += u64::from(undecided);
        Ok(Signature {
            undecided,
            overturned: r.overturned,
            mode: r.mode.map(|m| m.number()),
            impacts: if r.overturned {
                r.impact_count
            } else {
                r.rocking_impacts
            },
            in_band: !r.overturned
                && self
                    .model
                    .slide_band
                    .is_some_and(|[lo, hi]| lo <= slide && slide <= hi),
        })
    }

    /// Scans `levels[0..]` (increasing, a scan step `step` apart) and
    /// refines every neighbouring pair that differs, down to `tol`; then
    /// verifies every piece between the changes found and reports where the
    /// outcome alternates finer than that ([`super::verify`]). Returns
    /// transitions, mode changes and mixed zones, in order.
    pub fn scan<I: IntoIterator<Item = f64>>(
        &self,
        levels: I,
        step: f64,
        tol: f64,
        stats: &mut ScanStats,
    ) -> Result<Found, ScanError> {
        let mut trace = Trace {
            stats,
            found: Found::default(),
            seen: Vec::new(),
            tol,
        };
        let mut levels = levels.into_iter();
        let Some(first) = levels.next() else {
            return Ok(trace.found);
        };
        let mut prev = (first, self.classify(first, trace.stats)?);
        trace.seen.push(prev);
        self.control.add_done(1);
        for level in levels {
            let cur = (level, self.classify(level, trace.stats)?);
            trace.seen.push(cur);
            self.control.add_done(1);
            if cur.1 != prev.1 {
                self.refine(prev, cur, &mut trace, |a, b| a == b)?;
            }
            prev = cur;
        }
        self.verify(&mut trace, step)?;
        Ok(trace.found)
    }

    /// What the scan spends on the bracket `[lo, hi]` of two neighbouring
    /// levels: both classified and, where they differ, bisected down to
    /// `tol` as [`Line::scan`] bisects it (without verification). Its cost
    /// is added to `stats`; a sample of a scan's brackets foresees what the
    /// whole scan costs ([`super::pilot`]).
    pub fn bracket(
        &self,
        lo: f64,
        hi: f64,
        tol: f64,
        stats: &mut ScanStats,
    ) -> Result<(), ScanError> {
        let mut trace = Trace {
            stats,
            found: Found::default(),
            seen: Vec::new(),
            tol,
        };
        let a = (lo, self.classify(lo, trace.stats)?);
        let b = (hi, self.classify(hi, trace.stats)?);
        if a.1 != b.1 {
            self.refine(a, b, &mut trace, |a, b| a == b)?;
        }
        Ok(())
    }

    /// Bisects `[a, b]` (whose ends differ) until each change is bracketed within
    /// `tol`, examining the left half first so that results come out in order;
    /// `same` says which signatures need no further bisection.
    fn refine(
        &self,
        a: (f64, Signature),
        b: (f64, Signature),
        trace: &mut Trace<'_>,
        same: fn(&Signature, &Signature) -> bool,
    ) -> Result<(), ScanError> {
        if b.0 - a.0 <= trace.tol {
            record(a, b, &mut trace.found);
            return Ok(());
        }
        let mid = 0.5 * (a.0 + b.0);
        let m = (mid, self.classify(mid, trace.stats)?);
        trace.seen.push(m);
        if !same(&m.1, &a.1) {
            self.refine(a, m, trace, same)?;
        }
        if !same(&m.1, &b.1) {
            self.refine(m, b, trace, same)?;
        }
        Ok(())
    }

    /// The outcome at `level` for verification: `None` where the
    /// simulation fails (the level is left undecided, its piece uncertain);
    /// only a cancellation stops the scan.
    fn probe(&self, level: f64, stats: &mut ScanStats) -> Result<Option<Signature>, ScanError> {
        match self.classify(level, stats) {
            Ok(s) if s.undecided => Ok(None),
            Ok(s) => Ok(Some(s)),
            Err(ScanError::Canceled(c)) => Err(ScanError::Canceled(c)),
            Err(_) => Ok(None),
        }
    }

    /// Probes every piece between the changes found ([`super::verify`]),
    /// bisects what a wide piece's probes find, and turns what stays
    /// uncertain into mixed zones.
    fn verify(&self, trace: &mut Trace<'_>, step: f64) -> Result<(), ScanError> {
        let mut settled: std::collections::HashSet<(u64, u64)> = Default::default();
        let mut uncertain: Vec<[f64; 2]> = Vec::new();
        let same = |a: &Signature, b: &Signature| outcome(a) == outcome(b);
        for round in 0..2 {
            trace.sort_seen();
            let seen = trace.seen.clone();
            for [i0, i1] in verify::pieces(&seen, outcome) {
                let (l, r) = (seen[i0].0, seen[i1].0);
                let known = uncertain.iter().any(|u| u[0] <= l && r <= u[1]);
                if known || !settled.insert((l.to_bits(), r.to_bits())) {
                    continue;
                }
                let between = i0 > 0 && i1 + 1 < seen.len();
                if seen[i0].1.undecided || (between && r - l <= 2.0 * trace.tol) {
                    // Narrower than the resolution: a sliver found between
                    // two switches, whose inside cannot be verified.
                    uncertain.push([l, r]);
                    continue;
                }
                let expected = outcome(&seen[i0].1);
                let mut failed = Vec::new();
                let mut undecided = false;
                for x in verify::probe_levels(&seen[i0..=i1], step, trace.tol) {
                    trace.stats.probes += 1;
                    let Some(s) = self.probe(x, trace.stats)? else {
                        undecided = true;
                        continue;
                    };
                    trace.seen.push((x, s));
                    if outcome(&s) != expected {
                        failed.push((x, s));
                    }
                }
                if failed.is_empty() && !undecided {
                    continue;
                }
                if round > 0 || r - l < step || undecided {
                    uncertain.push([l, r]);
                    continue;
                }
                // A band hidden in a wide piece: bisect it against its
                // neighbouring levels like a scan point.
                trace.sort_seen();
                for (x, s) in failed {
                    let at = trace.seen.partition_point(|p| p.0 < x);
                    let left = at
                        .checked_sub(1)
                        .and_then(|i| trace.seen.get(i))
                        .filter(|p| p.0 >= l && !same(&p.1, &s))
                        .copied();
                    let right = trace
                        .seen
                        .get(at + 1)
                        .filter(|p| p.0 <= r && !same(&p.1, &s))
                        .copied();
                    let mut bisect =
                        |a, b, trace: &mut Trace<'_>| match self.refine(a, b, trace, same) {
                            Err(ScanError::Canceled(c)) => Err(ScanError::Canceled(c)),
                            // A level that cannot be simulated: the piece is
                            // left uncertain.
                            Err(_) => {
                                uncertain.push([l, r]);
                                Ok(())
                            }
                            Ok(()) => Ok(()),
                        };
                    if let Some(a) = left {
                        bisect(a, (x, s), trace)?;
                    }
                    if let Some(b) = right {
                        bisect((x, s), b, trace)?;
                    }
                    trace.sort_seen();
                }
            }
        }
        trace.sort_seen();
        let zones = verify::clusters(uncertain, step)
            .into_iter()
            .map(|zone| {
                let [from, to] = trace.to_switches(zone);
                self.zone(from, to, step, trace)
            })
            .collect::<Result<Vec<_>, ScanError>>()?;
        trace.found.mixed = zones;
        Ok(())
    }

    /// The zone `[from, to]` probed on its lattice for its fractions.
    fn zone(
        &self,
        from: f64,
        to: f64,
        step: f64,
        trace: &mut Trace<'_>,
    ) -> Result<Mixed, ScanError> {
        let mut zone = Mixed {
            from,
            to,
            probes: 0,
            overturned: 0,
            in_band: 0,
            first_overturn: trace
                .seen
                .iter()
                .find(|p| zone_has(from, to, p.0) && p.1.overturned)
                .map(|p| p.0),
        };
        for x in verify::lattice(from, to, step) {
            trace.stats.probes += 1;
            let Some(s) = self.probe(x, trace.stats)? else {
                continue;
            };
            zone.probes += 1;
            zone.overturned += u64::from(s.overturned);
            zone.in_band += u64::from(s.in_band);
            if s.overturned && zone.first_overturn.is_none_or(|f| x < f) {
                zone.first_overturn = Some(x);
            }
        }
        Ok(zone)
    }
}

/// What verification compares: overturned, standing in the slide band, and
/// undecided.
fn outcome(s: &Signature) -> (bool, bool, bool) {
    (s.overturned, s.in_band, s.undecided)
}

fn zone_has(from: f64, to: f64, x: f64) -> bool {
    from <= x && x <= to
}

/// What a line's scan gathers as it goes: the simulated levels, what they
/// imply, and its cost.
struct Trace<'s> {
    stats: &'s mut ScanStats,
    found: Found,
    /// Every simulated level and its outcome.
    seen: Vec<(f64, Signature)>,
    /// Bracket width of every transition.
    tol: f64,
}

impl Trace<'_> {
    fn sort_seen(&mut self) {
        self.seen.sort_by(|a, b| a.0.total_cmp(&b.0));
        self.seen.dedup_by(|a, b| a.0 == b.0);
    }

    /// A zone `[l, r]` (simulated levels, `seen` sorted) reaching over the
    /// switches beside it: to the simulated level below `l` and above `r`
    /// where the outcome changes there, so that the certain intervals beside
    /// a zone begin at a simulated level of their own outcome, not inside a
    /// bracket.
    fn to_switches(&self, [l, r]: [f64; 2]) -> [f64; 2] {
        let at = |x: f64| self.seen.partition_point(|p| p.0 < x);
        let (i, j) = (at(l), at(r));
        let lower = i
            .checked_sub(1)
            .and_then(|k| Some((self.seen.get(k)?, self.seen.get(i)?)))
            .filter(|(a, b)| outcome(&a.1) != outcome(&b.1))
            .map_or(l, |(a, _)| a.0);
        let upper = self
            .seen
            .get(j + 1)
            .zip(self.seen.get(j))
            .filter(|(a, b)| outcome(&a.1) != outcome(&b.1))
            .map_or(r, |(a, _)| a.0);
        [lower, upper]
    }
}

/// What a scan of part of a line's levels found, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Found {
    /// Survive ↔ overturn transitions (and slide-band edges).
    pub transitions: Vec<Transition>,
    /// Changes of overturning mode.
    pub mode_changes: Vec<ModeChange>,
    /// Where the outcome alternates finer than the scan resolves.
    pub mixed: Vec<Mixed>,
}

impl Found {
    /// Adds what another range of the same line found.
    pub fn extend(&mut self, other: Found) {
        self.transitions.extend(other.transitions);
        self.mode_changes.extend(other.mode_changes);
        self.mixed.extend(other.mixed);
    }
}

fn record(a: (f64, Signature), b: (f64, Signature), found: &mut Found) {
    if a.1.undecided || b.1.undecided {
        // Left to the mixed zone the undecided level lies in.
        return;
    }
    let transitions = &mut found.transitions;
    let modes = &mut found.mode_changes;
    let at = 0.5 * (a.0 + b.0);
    if a.1.in_band != b.1.in_band {
        transitions.push(Transition {
            at,
            direction: if b.1.in_band {
                Direction::SlideIn
            } else {
                Direction::SlideOut
            },
            mode: 0,
            impacts: 0,
            bracket: (a.0, b.0),
        });
    }
    match (a.1.overturned, b.1.overturned) {
        (false, true) => transitions.push(Transition {
            at,
            direction: Direction::Up,
            mode: b.1.mode.unwrap_or(0),
            impacts: b.1.impacts,
            bracket: (a.0, b.0),
        }),
        (true, false) => transitions.push(Transition {
            at,
            direction: Direction::Down,
            mode: a.1.mode.unwrap_or(0),
            impacts: a.1.impacts,
            bracket: (a.0, b.0),
        }),
        (true, true) if a.1.mode != b.1.mode => modes.push(ModeChange {
            at,
            from: a.1.mode.unwrap_or(0),
            to: b.1.mode.unwrap_or(0),
            bracket: (a.0, b.0),
        }),
        _ => {}
    }
}
