//! The response of a block to a pulse: rocking starts, impacts, rest, the
//! overturning decision and its mode.
//!
//! The motion is a chain of smooth legs, each on one side (sign of θ) and either
//! forced (during the pulse) or free. A leg ends at the first of: an impact
//! (θ = 0, eqs. 13–15: θ̇ ← η θ̇), overturning (|θ| = π/2), or the pulse end.
//! Rocking starts whenever |ü_g| first exceeds the threshold (g tan α, or g α for
//! the linear formulation), located in closed form. Chattering (impacts piling
//! up in finite time) ends when the velocity after an impact falls below
//! `REST_VELOCITY · p α`: the block is then at rest and may be lifted again.
//! Once the pulse is over, overturning is decided exactly by
//! [`separatrix::decide`](super::separatrix::decide).
//!
//! The ground motion is any [`Forcing`]: a pulse, or a sampled record whose
//! end is the end of forcing and whose sample times (kinks of the linearly
//! interpolated acceleration) end Runge–Kutta steps without restarting the
//! step-size control, and end the exact solver's closed-form segments (one
//! per piece of the record, each re-anchored where the last one ended).
//!
//! With a vertical component ([`super::vertical`]) gravity is g + ü_v: the
//! threshold and the equation carry it, and the history ends where
//! g + ü_v ≤ 0 first (the ground falls away and the block leaves it).

use std::time::Instant;

use super::block::Block;
use super::chatter::settle;
use super::equations::{Formulation, Threshold};
use super::events::{first_nonpositive, return_and_overturn};
use super::exact::{SegmentEnd, first_event};
use super::excitation::Pulse;
use super::forcing::Forcing;
use super::integrator::{Method, State, StepError, Stepper, StepperStats, single_step};
use super::reactions::{reactions_per_mass, reactions_per_mass_vertical};
use super::response::{FrictionDemand, Impact, Numerics, OverturnMode, Response, Warning};
use super::separatrix::{FreeOutcome, decide};
use super::tracking::{TrackRequest, Tracker};

/// Velocity after an impact, relative to p·α, below which the block is at rest.
pub const REST_VELOCITY: f64 = 1e-12;

/// Impacts faster than this (relative to p α) count as rocking impacts.
pub const ROCKING_IMPACT_VELOCITY: f64 = 1e-2;

/// Most impacts stored in a response's list (the count is always complete).
pub const MAX_LISTED_IMPACTS: usize = 10_000;

use super::response::{Limit, MAX_IMPACTS};

/// A block, a ground motion (a [`Pulse`] unless said otherwise) and an
/// equation of motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Problem<G = Pulse> {
    /// The block.
    pub block: Block,
    /// The ground motion: a pulse, or a sampled record.
    pub pulse: G,
    /// The equation of motion.
    pub formulation: Formulation,
}

/// How the equations are solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solver {
    /// Closed form (linear formulation only).
    Exact,
    /// Adaptive Runge–Kutta pair.
    RungeKutta {
        /// The pair.
        method: Method,
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance, rad and rad/s.
        atol: f64,
    },
}

impl Solver {
    /// The name used in reports.
    pub fn name(&self) -> &'static str {
        match self {
            Solver::Exact => "exact",
            Solver::RungeKutta { method, .. } => method.name(),
        }
    }
}

/// What to compute.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Solver.
    pub solver: Solver,
    /// Follow f_x/f_z (peak, initiation, sliding and lift-off warnings).
    pub reactions: bool,
    /// Follow max |θ|.
    pub peak: bool,
    /// Number of uniformly spaced series samples over the simulated interval.
    pub series_points: Option<usize>,
    /// Explicit sorted sample times for the series (overrides `series_points`).
    pub series_at: Option<Vec<f64>>,
    /// Keep the list of impacts (otherwise only their count).
    pub record_impacts: bool,
    /// Stop as soon as the outcome is certain (at the pulse end at the latest).
    pub stop_at_decision: bool,
    /// Stop once pure rocking is known not to be the Coulomb answer: the
    /// friction it needs exceeds the block's μ, it lifts off, or rocking
    /// starts a second time (what [`super::floor::run_coulomb`] asks; the
    /// response then ends there, unfinished).
    pub stop_at_sliding: bool,
    /// After the pulse, follow free rocking for at most this many impacts.
    pub max_free_impacts: u64,
    /// Do not simulate past this time, s (free rocking only).
    pub horizon: Option<f64>,
    /// Start rocking at t = 0 from this `[θ, θ̇]` instead of from rest.
    pub initial_state: Option<State>,
    /// Leave out of the friction demand the fall of a block that overturns
    /// while the ground still moves: from where the free motion overturns
    /// at every step on (the verdict a pulse's end gives) to the
    /// overturning. What a record asks, which mostly lasts past it; a
    /// pulse's demand is followed while the pulse acts.
    pub fall_under_forcing: bool,
}

impl Options {
    /// Everything about one history (no series).
    pub fn history(solver: Solver) -> Self {
        Options {
            solver,
            reactions: true,
            peak: true,
            series_points: None,
            series_at: None,
            record_impacts: true,
            stop_at_decision: false,
            stop_at_sliding: false,
            max_free_impacts: 1_000,
            horizon: None,
            initial_state: None,
            fall_under_forcing: false,
        }
    }

    /// Only the outcome (overturned, mode, impact count): what spectra need.
    pub fn outcome(solver: Solver) -> Self {
        Options {
            solver,
            reactions: false,
            peak: false,
            series_points: None,
            series_at: None,
            record_impacts: false,
            stop_at_decision: true,
            stop_at_sliding: false,
            max_free_impacts: 0,
            horizon: None,
            initial_state: None,
            fall_under_forcing: false,
        }
    }
}

/// Why a simulation could not be carried out.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The closed form exists for the linear formulation only.
    #[error("the exact solver solves the linear formulation only")]
    ExactNeedsLinear,
    /// The closed form exists for sinusoidal pulses and records (linear
    /// between samples), not for wavelets.
    #[error(
        "the exact solver solves sinusoidal pulses and records only; use dopri5 or dop853 for a wavelet"
    )]
    ExactNeedsClosedForm,
    /// Under vertical ground motion the linear equation has a time-varying
    /// coefficient (1 + ü_v/g): it has no closed form.
    #[error(
        "the exact solver has no closed form under vertical ground motion; use dopri5 or dop853"
    )]
    ExactWithVertical,
    /// Tolerances must be positive and finite.
    #[error("rtol and atol must be positive and finite, rtol >= 1e-14")]
    Tolerance,
    /// The integrator failed.
    #[error("integration failed: {0}")]
    Integration(#[from] StepError),
    /// On a Coulomb floor the free motion after the ground motion came
    /// neither to rest nor to overturning within this time (s).
    #[error(
        "the free motion on the coulomb floor did not end by t = {0} s (neither rest nor overturning)"
    )]
    FreeMotionUnended(f64),
    /// The block is not a valid one.
    #[error("invalid block: {0}")]
    Block(#[from] super::block::BlockError),
}

/// Simulates `problem` as `options` ask.
pub fn simulate<G: Forcing>(problem: &Problem<G>, options: &Options) -> Result<Response, SimError> {
    let started = Instant::now();
    check(problem, options)?;
    let mut response = match (&options.series_at, options.series_points) {
        (Some(times), _) => run(problem, options, track_request(options, times.clone()))?,
        (None, Some(n)) if n > 0 => {
            // The series spans the simulated interval, known after a first pass.
            let first = run(problem, options, TrackRequest::default())?;
            let end = first.end_time;
            let times = (0..n)
                .map(|k| {
                    if n == 1 {
                        0.0
                    } else {
                        end * k as f64 / (n - 1) as f64
                    }
                })
                .collect();
            run(problem, options, track_request(options, times))?
        }
        _ => run(problem, options, track_request(options, Vec::new()))?,
    };
    response.numerics.wall_time = started.elapsed().as_secs_f64();
    Ok(response)
}

/// What a history asked by `options` follows, its series sampled at `times`.
fn track_request(options: &Options, times: Vec<f64>) -> TrackRequest {
    TrackRequest {
        peak: options.peak,
        reactions: options.reactions,
        series_times: times,
        fall_under_forcing: options.fall_under_forcing,
        // Pure rocking followed on a Coulomb floor for its outcome only
        // (what a scan asks of `floor::run_coulomb`) needs of the demand
        // only where it first exceeds μ or lifts off, and no peak at all.
        refine_peaks: options.peak || !(options.stop_at_sliding && options.stop_at_decision),
    }
}

fn check<G: Forcing>(problem: &Problem<G>, options: &Options) -> Result<(), SimError> {
    if matches!(options.solver, Solver::Exact) && !G::VERTICAL {
        let probe = problem
            .pulse
            .rhs(problem.formulation, &problem.block, 1.0, true);
        if G::linear_segment(&probe, 0.0, [0.0, 0.0]).is_none() {
            return Err(SimError::ExactNeedsClosedForm);
        }
    }
    match options.solver {
        Solver::Exact if G::VERTICAL => Err(SimError::ExactWithVertical),
        Solver::Exact if problem.formulation != Formulation::Linear => {
            Err(SimError::ExactNeedsLinear)
        }
        Solver::RungeKutta { rtol, atol, .. }
            if !(rtol >= 1e-14 && rtol.is_finite() && atol > 0.0 && atol.is_finite()) =>
        {
            Err(SimError::Tolerance)
        }
        _ => Ok(()),
    }
}

/// How a leg ended.
#[derive(Clone, Copy, Debug)]
enum LegEnd {
    Impact {
        t: f64,
        velocity: f64,
    },
    Overturn {
        t: f64,
    },
    Reached {
        t: f64,
        y: State,
    },
    /// Followed for the friction it needs (`stop_at_sliding`): pure rocking
    /// stopped being the Coulomb answer on the step ending at `t` (the
    /// demand exceeded μ, or the block lifted off).
    PastPureRocking {
        t: f64,
    },
}

/// Solver state carried across legs.
struct Engine {
    solver: Solver,
    stats: StepperStats,
    h_hint: f64,
    exact_error: f64,
    /// End a leg at the step where pure rocking stops being the Coulomb
    /// answer ([`Options::stop_at_sliding`]).
    stop_at_sliding: bool,
}

impl Engine {
    /// Runs one leg from `(t0, y0)` until the first event or `t_stop`; the impact
    /// event is armed only after `lift_until` (lift-off from rest).
    #[allow(clippy::too_many_arguments)]
    fn leg<G: Forcing>(
        &mut self,
        forcing: &G,
        rhs: &G::Rhs<'_>,
        side: f64,
        t0: f64,
        y0: State,
        t_stop: f64,
        lift_until: f64,
        forced: bool,
        tracker: &mut Tracker<G>,
    ) -> Result<LegEnd, SimError> {
        match self.solver {
            Solver::Exact => {
                self.leg_exact::<G>(rhs, side, t0, y0, t_stop, lift_until, forced, tracker)
            }
            Solver::RungeKutta { method, rtol, atol } => self.leg_rk(
                forcing, rhs, side, method, rtol, atol, t0, y0, t_stop, lift_until, forced, tracker,
            ),
        }
    }

    /// The closed-form leg: segment after segment of the forcing's
    /// [`linear_segment`](Forcing::linear_segment), each re-anchored at the
    /// state where the previous one ended (a kink of the forcing, or p τ = 20).
    #[allow(clippy::too_many_arguments)]
    fn leg_exact<G: Forcing>(
        &mut self,
        rhs: &G::Rhs<'_>,
        side: f64,
        t0: f64,
        y0: State,
        t_stop: f64,
        lift_until: f64,
        forced: bool,
        tracker: &mut Tracker<G>,
    ) -> Result<LegEnd, SimError> {
        let (mut seg, mut holds_until) =
            G::linear_segment(rhs, t0, y0).ok_or(SimError::ExactNeedsClosedForm)?;
        loop {
            let end = first_event(&seg, t_stop.min(holds_until), lift_until);
            self.stats.accepted += 1;
            let (t_end, y_end) = match end {
                SegmentEnd::Impact(t) | SegmentEnd::Overturn(t) => (t, seg.at(t)),
                SegmentEnd::Reached(t, y) => (t, y),
            };
            self.exact_error += seg.rounding_error(t_end - seg.t0);
            tracker.rocking((seg.t0, seg.y0), (t_end, y_end), side, forced, |t| {
                seg.at(t)
            });
            match end {
                SegmentEnd::Impact(t) => {
                    return Ok(LegEnd::Impact {
                        t,
                        velocity: y_end[1],
                    });
                }
                SegmentEnd::Overturn(t) => return Ok(LegEnd::Overturn { t }),
                SegmentEnd::Reached(t, y) if t >= t_stop => return Ok(LegEnd::Reached { t, y }),
                SegmentEnd::Reached(t, y) => {
                    (seg, holds_until) =
                        G::linear_segment(rhs, t, y).ok_or(SimError::ExactNeedsClosedForm)?;
                }
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn leg_rk<G: Forcing>(
        &mut self,
        forcing: &G,
        rhs: &G::Rhs<'_>,
        side: f64,
        method: Method,
        rtol: f64,
        atol: f64,
        t0: f64,
        y0: State,
        t_stop: f64,
        lift_until: f64,
        forced: bool,
        tracker: &mut Tracker<G>,
    ) -> Result<LegEnd, SimError> {
        let mut stepper = Stepper::new(method, rtol, atol, rhs, t0, y0, f64::INFINITY, self.h_hint);
        let s = side;
        let result = loop {
            let armed = stepper.t >= lift_until;
            let mut target = if armed {
                t_stop
            } else {
                lift_until.min(t_stop)
            };
            if forced {
                // No step crosses a kink of the forcing; the stepper (and its
                // step size) carries on past it.
                target = target.min(forcing.breakpoint_after(stepper.t));
            }
            if stepper.t >= t_stop {
                break LegEnd::Reached {
                    t: t_stop,
                    y: stepper.y,
                };
            }
            let step = match stepper.step(rhs, target) {
                Ok(step) => step,
                Err(e) => {
                    self.stats.absorb(&stepper.stats);
                    return Err(e.into());
                }
            };
            let (g, top) = return_and_overturn(&step.coeffs[0], step.len, s);
            let impact = if armed { first_nonpositive(&g) } else { None };
            let over = first_nonpositive(&top);
            let event = match (impact, over) {
                (Some(i), Some(o)) if o < i => Some((o, false)),
                (Some(i), _) => Some((i, true)),
                (None, Some(o)) => Some((o, false)),
                (None, None) => None,
            };
            if let Some((sigma, is_impact)) = event {
                // The dense output locates the event; Newton corrections on
                // full Runge–Kutta steps from the step start then place it to
                // the integration tolerance (the interpolant is less accurate
                // than the step itself).
                let level = if is_impact {
                    0.0
                } else {
                    std::f64::consts::FRAC_PI_2
                };
                let mut t = step.t0 + sigma * step.h;
                let mut y = step.at_sigma(sigma);
                for _ in 0..3 {
                    let (ye, nfev) = single_step(method, rhs, step.t0, step.y0, t - step.t0);
                    self.stats.rhs_evals += u64::from(nfev);
                    y = ye;
                    if ye[1] == 0.0 {
                        break;
                    }
                    let dt = -(s * ye[0] - level) / (s * ye[1]);
                    let t_new = (t + dt).clamp(step.t0, step.t1());
                    if (t_new - t).abs() <= 4.0 * f64::EPSILON * t.abs().max(step.h) {
                        t = t_new;
                        break;
                    }
                    t = t_new;
                }
                tracker.rocking((step.t0, step.y0), (t, step.at(t)), s, forced, |t| {
                    step.at(t)
                });
                break if is_impact {
                    LegEnd::Impact { t, velocity: y[1] }
                } else {
                    LegEnd::Overturn { t }
                };
            }
            tracker.rocking((step.t0, step.y0), (step.t1(), step.y1), s, forced, |t| {
                step.at(t)
            });
            if self.stop_at_sliding && tracker.past_pure_rocking() {
                break LegEnd::PastPureRocking { t: step.t1() };
            }
        };
        self.h_hint = stepper.next_step_size();
        self.stats.absorb(&stepper.stats);
        Ok(result)
    }
}

/// The ground falls away at `t` (g + ü_v ≤ 0): the block leaves it, and
/// the rocking model ends there without a verdict on overturning.
fn lift_off<G: Forcing>(r: &mut Response, tracker: &mut Tracker<G>, t: f64) {
    r.lift_off = Some(t);
    r.warnings.push(Warning::GroundFallsAway(t));
    r.rest_time = None;
    r.decided_at = t;
    r.end_time = t;
    tracker.finish(t);
}

/// A leg of rocking to come: its start, side, whether the ground still
/// moves, and until when no impact is looked for (lift-off from rest).
#[derive(Clone, Copy, Debug)]
struct Leg {
    y: State,
    side: f64,
    forced: bool,
    lift_until: f64,
}

/// Whether the history goes on after a step of the driver.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Next {
    /// Another step.
    Go,
    /// The history ends here.
    Stop,
}

/// One history being driven leg after leg: the problem, what is asked, the
/// solver's state, what is tracked and the response as it grows.
struct Driver<'a, G: Forcing> {
    problem: &'a Problem<G>,
    options: &'a Options,
    /// The end of the ground motion, s.
    duration: f64,
    threshold: Threshold,
    /// Past this time (g + ü_v ≤ 0) nothing holds the block on the ground.
    weightless: Option<f64>,
    /// Velocity after an impact below which the block is at rest, rad/s.
    v_rest: f64,
    engine: Engine,
    tracker: Tracker<'a, G>,
    r: Response,
    events: u64,
    /// f_x/f_z when rocking first starts.
    initiation: Option<f64>,
    t: f64,
    /// None while at rest on the base.
    rocking: Option<Leg>,
    /// The closed-form verdict on the free motion, once the ground stops.
    decision: Option<FreeOutcome>,
    /// The side it then overturns to.
    decided_side: Option<f64>,
    free_impacts: u64,
    forced_impacts: u64,
}

impl<'a, G: Forcing> Driver<'a, G> {
    /// A block at rest at t = 0 (or rocking from `options.initial_state`).
    fn new(problem: &'a Problem<G>, options: &'a Options, req: TrackRequest) -> Self {
        let block = &problem.block;
        let formulation = problem.formulation;
        let pulse = &problem.pulse;
        let duration = pulse.duration();
        let tracker = Tracker::new(formulation, block, pulse, req);
        let threshold = formulation.threshold(block);
        let weightless = pulse.next_weightless(0.0, block.gravity());
        let v_rest = REST_VELOCITY * block.frequency_parameter() * block.slenderness();
        let engine = Engine {
            solver: options.solver,
            stats: StepperStats::default(),
            h_hint: 0.0,
            exact_error: 0.0,
            stop_at_sliding: options.stop_at_sliding,
        };
        let mut r = Response {
            rocked: false,
            rocking_start: None,
            rocking_starts: 0,
            overturned: false,
            mode: None,
            impact_count: 0,
            impacts: Vec::new(),
            summed_impacts: 0,
            rocking_impacts: 0,
            overturn_time: None,
            overturn_side: None,
            rest_time: None,
            decided_at: duration,
            end_time: duration,
            peak_theta_over_alpha: 0.0,
            friction: None,
            lift_off: None,
            series: None,
            warnings: Vec::new(),
            numerics: Numerics::default(),
        };
        let mut rocking = None;
        if let Some(y0) = options.initial_state
            && (y0[0] != 0.0 || y0[1] != 0.0)
        {
            let side = if y0[0] != 0.0 {
                y0[0].signum()
            } else {
                y0[1].signum()
            };
            r.rocked = true;
            r.rocking_starts = 1;
            r.rocking_start = Some(0.0);
            rocking = Some(Leg {
                y: y0,
                side,
                forced: true,
                lift_until: 0.0,
            });
        }
        Driver {
            problem,
            options,
            duration,
            threshold,
            weightless,
            v_rest,
            engine,
            tracker,
            r,
            events: 0,
            initiation: None,
            t: 0.0,
            rocking,
            decision: None,
            decided_side: None,
            free_impacts: 0,
            forced_impacts: 0,
        }
    }

    /// Followed for the friction pure rocking needs (`stop_at_sliding`),
    /// the history is no longer pure rocking's: it slid, lifted off or
    /// started rocking a second time.
    fn past_pure_rocking(&self) -> bool {
        self.options.stop_at_sliding
            && (self.tracker.past_pure_rocking() || self.r.rocking_starts > 1)
    }

    /// At rest: waits for the ground to exceed the threshold and starts
    /// rocking there; or the ground falls away first, or never exceeds it
    /// again (the block stays at rest to the end).
    fn at_rest(&mut self) -> Next {
        let pulse = &self.problem.pulse;
        let duration = self.duration;
        let t = self.t;
        let next = pulse.next_rocking(t, &self.threshold);
        if let Some(tw) = self.weightless
            && next.as_ref().is_none_or(|ex| ex.start >= tw)
        {
            self.tracker.resting(t, tw, true);
            lift_off(&mut self.r, &mut self.tracker, tw);
            return Next::Stop;
        }
        let r = &mut self.r;
        match next {
            None => {
                self.tracker.resting(t, duration.max(t), false);
                if r.rocked {
                    r.rest_time = Some(t);
                }
                r.decided_at = t.max(if r.rocked { t } else { duration });
                r.end_time = if r.rocked {
                    t.max(r.decided_at)
                } else {
                    duration
                };
                self.tracker.finish(r.end_time);
                Next::Stop
            }
            Some(ex) => {
                self.tracker.resting(t, ex.start, true);
                let t = ex.start;
                self.t = t;
                self.events += 1;
                r.rocked = true;
                r.rocking_starts += 1;
                r.rocking_start.get_or_insert(t);
                if self.initiation.is_none() {
                    self.initiation = Some(self.initiation_demand(ex.side, t));
                }
                self.rocking = Some(Leg {
                    y: [0.0, 0.0],
                    side: ex.side,
                    forced: true,
                    lift_until: ex.end,
                });
                Next::Go
            }
        }
    }

    /// |f_x/f_z| as rocking starts at `t` on `side`: eq. 7 (eq. 51 for
    /// one-cosine) is eq. 20 at the start state.
    fn initiation_demand(&self, side: f64, t: f64) -> f64 {
        let Problem {
            block,
            pulse,
            formulation,
        } = self.problem;
        let (fx, fz) = if G::VERTICAL {
            reactions_per_mass_vertical(
                *formulation,
                block,
                side,
                0.0,
                0.0,
                pulse.acceleration(t),
                pulse.vertical_acceleration(t),
            )
        } else {
            reactions_per_mass(*formulation, block, side, 0.0, 0.0, pulse.acceleration(t))
        };
        (fx / fz).abs()
    }

    /// Rocks through `leg` to its first event: an impact, overturning, or
    /// the end of the ground motion (or of the time followed).
    fn rock(&mut self, leg: Leg) -> Result<Next, SimError> {
        let problem = self.problem;
        let Leg {
            y,
            side,
            forced,
            lift_until,
        } = leg;
        let t = self.t;
        let t_stop = if forced {
            self.weightless
                .map_or(self.duration, |tw| tw.min(self.duration))
        } else {
            self.options.horizon.unwrap_or(f64::INFINITY).max(t)
        };
        let rhs = problem
            .pulse
            .rhs(problem.formulation, &problem.block, side, forced);
        let end = self.engine.leg(
            &problem.pulse,
            &rhs,
            side,
            t,
            y,
            t_stop,
            lift_until,
            forced,
            &mut self.tracker,
        )?;
        Ok(match end {
            LegEnd::Impact { t: ti, velocity } => self.impact(ti, velocity, forced),
            LegEnd::Overturn { t: to } => {
                self.events += 1;
                let r = &mut self.r;
                r.overturned = true;
                r.overturn_time = Some(to);
                r.overturn_side = Some(side);
                r.end_time = to;
                if forced {
                    r.decided_at = to;
                    self.tracker.bound_to_overturn(None);
                }
                Next::Stop
            }
            LegEnd::PastPureRocking { t: tp } => {
                // The history ends here ([`Driver::past_pure_rocking`]).
                self.t = tp;
                self.rocking = None;
                Next::Go
            }
            LegEnd::Reached { t: tr, y } => {
                self.t = tr;
                if forced && self.weightless.is_some_and(|tw| tr >= tw) {
                    lift_off(&mut self.r, &mut self.tracker, tr);
                    Next::Stop
                } else if forced {
                    self.ground_stops(tr, y, side)
                } else {
                    self.r.end_time = tr;
                    Next::Stop
                }
            }
        })
    }

    /// An impact at `ti`, reached at `velocity` (eqs. 13–15: θ̇ ← η θ̇):
    /// counted and listed; the block comes to rest, chatters to rest (a
    /// tail summed in closed form), or rocks on to the other side.
    fn impact(&mut self, ti: f64, velocity: f64, forced: bool) -> Next {
        let problem = self.problem;
        let v_rest = self.v_rest;
        self.events += 1;
        let r = &mut self.r;
        r.impact_count += 1;
        if velocity.abs() >= ROCKING_IMPACT_VELOCITY * v_rest / REST_VELOCITY {
            r.rocking_impacts += 1;
        }
        let after = problem.block.restitution() * velocity;
        if self.options.record_impacts {
            list_impact(r, ti, velocity, after);
        }
        self.t = ti;
        if forced {
            self.forced_impacts += 1;
        } else {
            self.free_impacts += 1;
        }
        if self.forced_impacts + self.free_impacts >= MAX_IMPACTS {
            // A bound on the work of one history: it ends here.
            r.warnings
                .push(Warning::LimitReached(Limit::Impacts(MAX_IMPACTS), ti));
            r.end_time = ti;
            r.rest_time = None;
            return Next::Stop;
        }
        if after.abs() <= v_rest {
            return self.comes_to_rest(ti, forced);
        }
        if let Some(settled) = settle(
            problem.formulation,
            &problem.block,
            &problem.pulse,
            forced,
            ti,
            after,
            v_rest,
        ) {
            // A chattering tail, summed in closed form.
            r.impact_count += settled.impacts;
            r.summed_impacts += settled.impacts;
            self.events += settled.impacts;
            self.t = settled.rest_time;
            return self.comes_to_rest(settled.rest_time, forced);
        }
        if !forced && self.free_impacts >= self.options.max_free_impacts {
            r.warnings
                .push(Warning::FreeRockingTruncated(self.free_impacts));
            r.end_time = ti;
            return Next::Stop;
        }
        self.rocking = Some(Leg {
            y: [0.0, after],
            side: after.signum(),
            forced,
            lift_until: ti,
        });
        Next::Go
    }

    /// The block at rest at `t`: for good once the ground has stopped (the
    /// history ends), else until the ground lifts it again.
    fn comes_to_rest(&mut self, t: f64, forced: bool) -> Next {
        self.rocking = None;
        if forced {
            return Next::Go;
        }
        self.r.rest_time = Some(t);
        self.r.end_time = t;
        self.tracker.finish(t);
        Next::Stop
    }

    /// The ground motion ends at `tr` with the block rocking at `y` on
    /// `side`: from here on the outcome follows from the state
    /// ([`decide`]). The history ends with that verdict when only the
    /// outcome is asked (or no free rocking), else the free motion is
    /// followed.
    fn ground_stops(&mut self, tr: f64, y: State, side: f64) -> Next {
        let options = self.options;
        let block = &self.problem.block;
        self.events += 1;
        let outcome = decide(self.problem.formulation, block, y[0], y[1], side);
        if let FreeOutcome::Overturns { impacts } = outcome {
            // Each impact turns the block over to the other side.
            self.decided_side = Some(if impacts % 2 == 0 { side } else { -side });
        }
        let r = &mut self.r;
        r.decided_at = tr;
        // Followed for the friction it needs (`stop_at_sliding`),
        // the free motion is decided here only where it is pure
        // rocking on that floor to its end.
        let pure_on_floor = || {
            !options.stop_at_sliding
                || block
                    .friction()
                    .is_none_or(|mu| super::free_rocking::stays_pure(block, mu, y[0], y[1]))
        };
        // (A history asked for no free rocking ends here on
        // any floor, as asked.)
        if (options.stop_at_decision && pure_on_floor())
            || (!options.stop_at_decision && options.max_free_impacts == 0)
        {
            r.end_time = tr;
            if !options.stop_at_decision {
                // Asked for no free rocking: the history ends
                // here, its outcome decided in closed form.
                r.warnings.push(Warning::FreeRockingTruncated(0));
            }
            if let FreeOutcome::Overturns { impacts } = outcome {
                r.overturned = true;
                r.overturn_side = self.decided_side;
                r.impact_count += u64::from(impacts);
                r.rocking_impacts += u64::from(impacts);
            }
            return Next::Stop;
        }
        if matches!(outcome, FreeOutcome::Overturns { .. }) {
            self.tracker.bound_to_overturn(Some(tr));
        }
        self.decision = Some(outcome);
        self.rocking = Some(Leg {
            y,
            side,
            forced: false,
            lift_until: tr,
        });
        Next::Go
    }

    /// The response once the history has ended: the exact verdict over the
    /// integrated free motion, the mode, the peak rotation, the friction
    /// demand, the series and the cost.
    fn finish(mut self) -> Response {
        self.prefer_decision();
        let r = &mut self.r;
        if r.overturned {
            r.mode = Some(if r.impact_count > 0 {
                OverturnMode::AfterImpacts(r.impact_count)
            } else {
                OverturnMode::WithoutImpact
            });
            r.rest_time = None;
        }
        // An overturned block is followed up to |θ| = π/2 exactly.
        let peak = if r.overturned && r.overturn_time.is_some() {
            std::f64::consts::FRAC_PI_2
        } else {
            self.tracker.peak_theta.min(std::f64::consts::FRAC_PI_2)
        };
        r.peak_theta_over_alpha = peak / self.problem.block.slenderness();
        if self.options.reactions {
            friction_demand(r, &self.tracker, self.initiation);
        }
        if !self.tracker.series.t.is_empty() {
            r.series = Some(self.tracker.take_series());
        }
        r.numerics = numerics(self.options.solver, &self.engine, self.events);
        self.r
    }

    /// The exact decision prevails over the integrated free motion.
    fn prefer_decision(&mut self) {
        let Some(outcome) = self.decision else {
            return;
        };
        let r = &mut self.r;
        let integrated = r.overturned;
        let decided = matches!(outcome, FreeOutcome::Overturns { .. });
        if decided != integrated && r.end_time > r.decided_at {
            let truncated = r.warnings.iter().any(|w| {
                matches!(
                    w,
                    Warning::FreeRockingTruncated(_) | Warning::LimitReached(..)
                )
            }) || self.options.horizon.is_some();
            if !(truncated && !integrated && decided) {
                r.warnings.push(Warning::NearSeparatrix);
            }
            r.overturned = decided;
            r.overturn_side = if decided { self.decided_side } else { None };
            if !decided {
                r.overturn_time = None;
            }
        }
    }
}

/// Lists the impact at `ti` (θ̇ `velocity` before, `after` after) in `r`,
/// up to [`MAX_LISTED_IMPACTS`] (then warns once).
fn list_impact(r: &mut Response, ti: f64, velocity: f64, after: f64) {
    if r.impacts.len() < MAX_LISTED_IMPACTS {
        r.impacts.push(Impact {
            time: ti,
            velocity_before: velocity,
            velocity_after: after,
        });
    } else if !r
        .warnings
        .iter()
        .any(|w| matches!(w, Warning::ImpactListTruncated(_)))
    {
        r.warnings
            .push(Warning::ImpactListTruncated(MAX_LISTED_IMPACTS));
    }
}

/// The friction demand of the history `tracker` followed (with `initiation`,
/// f_x/f_z as rocking started) into `r`, with its warnings.
fn friction_demand<G: Forcing>(r: &mut Response, tracker: &Tracker<G>, initiation: Option<f64>) {
    let (peak, peak_time) = tracker.peak_demand;
    // Past lift-off (f_z → 0⁺) no friction coefficient sustains pure
    // rocking: the demand is unbounded, not the large number reached.
    let bounded = tracker.first_lift_off.is_none() && r.lift_off.is_none();
    r.friction = Some(FrictionDemand {
        peak: bounded.then_some(peak),
        peak_time: bounded.then_some(peak_time),
        initiation,
        first_sliding: tracker.first_sliding,
        first_lift_off: tracker.first_lift_off,
        followed_until: tracker.reactions_stopped_at,
    });
    if let Some(ts) = tracker.first_sliding {
        r.warnings.push(Warning::Sliding(ts));
    }
    if let Some(tl) = tracker.first_lift_off
        && r.lift_off.is_none_or(|tw| tl < tw)
    {
        r.warnings.push(Warning::LiftOff(tl));
    }
    if let Some(tf) = tracker.reactions_stopped_at
        && r.overturned
    {
        r.warnings.push(if tracker.stopped_while_forced {
            Warning::DemandExcludesForcedFall(tf)
        } else {
            Warning::DemandExcludesFall(tf)
        });
    }
}

/// The cost and accuracy of a history solved by `solver`, with `events`
/// located.
fn numerics(solver: Solver, engine: &Engine, events: u64) -> Numerics {
    let (rtol, atol) = match solver {
        Solver::RungeKutta { rtol, atol, .. } => (Some(rtol), Some(atol)),
        Solver::Exact => (None, None),
    };
    Numerics {
        method: solver.name(),
        rtol,
        atol,
        steps_accepted: engine.stats.accepted,
        steps_rejected: engine.stats.rejected,
        rhs_evaluations: engine.stats.rhs_evals,
        events,
        error_estimate: match solver {
            Solver::Exact => engine.exact_error,
            Solver::RungeKutta { .. } => engine.stats.local_error_sum,
        },
        wall_time: 0.0,
    }
}

/// The history of `problem` as `options` ask, tracking what `req` asks:
/// at rest until the ground exceeds the threshold, then leg after leg of
/// rocking to the end.
fn run<G: Forcing>(
    problem: &Problem<G>,
    options: &Options,
    req: TrackRequest,
) -> Result<Response, SimError> {
    let mut driver = Driver::new(problem, options, req);
    loop {
        if driver.past_pure_rocking() {
            driver.r.end_time = driver.t;
            break;
        }
        let next = match driver.rocking {
            None => driver.at_rest(),
            Some(leg) => driver.rock(leg)?,
        };
        if next == Next::Stop {
            break;
        }
    }
    Ok(driver.finish())
}
