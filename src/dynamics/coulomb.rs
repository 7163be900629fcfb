//! The motion of a block on a floor with Coulomb friction: a chain of
//! contact modes ([`Mode`]), each transition an event located on the
//! solution.
//!
//! - **stick** → the first instant either threshold is passed
//!   ([`contact::onset`]): rock, slide or slide-rock by eq. 7;
//! - **rock** (pivot holds, eq. 12 with g + ü_v) → **slide-rock** where the
//!   friction it needs, |f_x|/f_z (eqs. 16–20), first exceeds μ_s; → an
//!   impact at θ = 0; → overturning at |θ| = π/2; → lift-off where f_z ≤ 0;
//! - **slide-rock** ([`slide_rock`]) → **rock** where the pivot's slip
//!   velocity returns to 0 and the pivot can hold (else it slides back);
//!   → an impact, overturning, lift-off (N ≤ 0) as rocking;
//! - **slide** (flat, [`sliding`]) → **stick** where it stops; a flat slide
//!   tips into slide-rock at once where μ_k > tan α;
//! - an **impact** ([`slide_rock::impact`]): the landing corner holds
//!   (Housner's η) or slides; a block whose rotation after it is below the
//!   rest velocity lands flat — sticking, or sliding on;
//! - **flight** ([`flight`]): where the floor would have to pull (f_z or
//!   N ≤ 0, or g + ü_v ≤ 0 under a flat block) the block leaves it, moves
//!   ballistically in closed form, and lands — on a corner, holding or
//!   sliding as at an impact, or flat — or overturns in the air.
//!
//! After the ground motion ends the block moves freely through the same
//! events until it rests or overturns. Sticking impacts of a chattering
//! rock are summed in closed form ([`settle`]).
//!
//! An impact's and overturning's root of θ is found on the step's dense
//! output ([`first_nonpositive`]) and placed by Newton corrections on full
//! Runge–Kutta steps, as under pure rocking. The sampled events (the
//! friction limit, the slip's return to 0, a vanishing normal force) are
//! detected at [`SAMPLES`] points of the step's dense output and located
//! on it, between the two samples around their sign change
//! ([`turns_positive`]; DOP853's interpolant of degree 7 is accurate to the
//! order of the integration tolerance): no step is taken again for them.

use super::Block;
use super::chatter::CHATTER_VELOCITY;
use super::chatter::settle;
use super::contact::{Mode, onset};
use super::equations::{Formulation, Threshold};
use super::events::{brent, first_nonpositive, return_and_overturn};
use super::flight::{self, Flight, FlightEnd, Landed, Pose};
use super::free_rocking;
use super::integrator::{DenseStep, Method, Rhs, State, Stepper, StepperStats, single_step};
use super::reactions::reactions_per_mass_vertical;
use super::response::{Limit, MAX_IMPACTS, MAX_STEPS, OverturnMode};
use super::separatrix::{FreeOutcome, decide};
use super::simulate::{REST_VELOCITY, ROCKING_IMPACT_VELOCITY, SimError};
use super::slide_rock::{self, SlideRockLeg, SlideRockRhs};
use super::sliding::{self, Friction, Kinematics};

/// Points per step at which sampled events are looked for.
pub const SAMPLES: usize = 8;

/// Most impacts at one instant (a sliding impact turning the rotation
/// back strikes the other corner).
const MAX_CHAINED: u32 = 1_000;

/// Impacts and landings at one instant after which the sequence is taken
/// at its limit: the block flat on the floor ([`Driver::repeats_at`]).
const MAX_AT_ONE_INSTANT: u64 = 64;

/// Periods 2π/p of free motion after the ground motion beyond which a
/// history is a fault ([`SimError::FreeMotionUnended`]).
const FREE_PERIODS: f64 = 10_000.0;

/// Impacts of a chattering sequence compared before it is summed: their
/// rebound ratios over two impacts (one on each side) must agree to
/// [`CHATTER_RATIO_AGREEMENT`] of 1 − ratio.
const CHATTER_WINDOW: usize = 5;

/// How closely successive rebound ratios of a sliding chatter must agree
/// (relative to 1 − ratio) before it is summed.
const CHATTER_RATIO_AGREEMENT: f64 = 1e-3;

/// The ground's accelerations (ü_g, ü_v) acting on a motion that is
/// `forced` (up to the forcing's end included) or free (from it on): what
/// decides a mode must see the ground its motion does.
fn ground<G: Kinematics>(forcing: &G, t: f64, forced: bool) -> (f64, f64) {
    if forced {
        (forcing.acceleration(t), forcing.vertical_acceleration(t))
    } else {
        (0.0, 0.0)
    }
}

/// [`ground`] for the motion from `t` on.
fn ground_after<G: Kinematics>(forcing: &G, t: f64) -> (f64, f64) {
    ground(forcing, t, t < forcing.duration())
}

/// One stretch of a mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeSpan {
    /// The mode.
    pub mode: Mode,
    /// Start, s.
    pub from: f64,
    /// End, s.
    pub to: f64,
    /// The direction the base slips in relative to the ground (slide,
    /// slide-rock: +1 towards +x), none otherwise.
    pub direction: Option<f64>,
    /// The base's slip at the start and the end, m.
    pub slip: (f64, f64),
}

/// An impact with friction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactImpact {
    /// Time, s.
    pub t: f64,
    /// θ̇ before and after, rad/s.
    pub theta_dot: (f64, f64),
    /// Whether the landing corner held.
    pub sticking: bool,
}

/// The history of a block on a Coulomb floor.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactResponse {
    /// The mode the block first left rest in (`None`: it never moved).
    pub initial_mode: Option<Mode>,
    /// The modes in time order (consecutive stretches of one mode merged).
    pub modes: Vec<ModeSpan>,
    /// Whether it overturned.
    pub overturned: bool,
    /// When |θ| reached π/2.
    pub overturn_time: Option<f64>,
    /// The side it overturned to: +1 about the corner at +b (θ > 0).
    pub overturn_side: Option<f64>,
    /// The paper's modes: after impacts, or without any.
    pub overturn_mode: Option<OverturnMode>,
    /// Impacts, in order (those of summed chattering are counted only).
    pub impacts: Vec<ContactImpact>,
    /// All impacts, summed chattering included.
    pub impact_count: u64,
    /// Impacts (landings included) with |θ̇| before of at least
    /// [`ROCKING_IMPACT_VELOCITY`](super::simulate::ROCKING_IMPACT_VELOCITY)
    /// p α: the rocking cycles, without the chattering that ends them (all
    /// counted, listed or not).
    pub rocking_impacts: u64,
    /// Of them, those of chattering summed in closed form.
    pub summed_impacts: u64,
    /// When the block first left the floor.
    pub first_flight: Option<f64>,
    /// Flights (each ends in a landing, counted among the impacts, or in
    /// overturning in the air).
    pub flights: u64,
    /// Time spent in the air, s.
    pub time_in_flight: f64,
    /// Time it came to rest for good.
    pub rest_time: Option<f64>,
    /// End of the history, s.
    pub end_time: f64,
    /// max |slip| of the base on the floor, m.
    pub peak_slide: f64,
    /// The base's slip at the end, m (positive towards +x).
    pub residual_slide: f64,
    /// Time spent sliding or slide-rocking, s.
    pub time_sliding: f64,
    /// max |θ|/α.
    pub peak_theta_over_alpha: f64,
    /// Integrator counters.
    pub stats: StepperStats,
    /// Events located.
    pub events: u64,
    /// The history at the times asked for ([`simulate_contact_sampled`]).
    pub series: Option<ContactSeries>,
    /// Where the history was cut short of rest or overturning: after
    /// `max_free_impacts` impacts of free motion (as asked, [`Asks`]), or at
    /// a bound on its work ([`Limit`]); `None`: followed to its end.
    pub cut: Option<Cut>,
}

/// Why a Coulomb history ends short of rest or overturning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cut {
    /// The free motion was followed for this many impacts, as asked.
    FreeImpacts(u64),
    /// A bound on the history's work.
    Limit(Limit),
}

/// A Coulomb history sampled at given times (those up to its end).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactSeries {
    /// Time, s.
    pub t: Vec<f64>,
    /// θ, rad (0 while the block is flat: stick, slide, a chattering
    /// tail summed in closed form).
    pub theta: Vec<f64>,
    /// θ̇, rad/s.
    pub theta_dot: Vec<f64>,
    /// The base's slip on the floor, m (+ towards +x).
    pub slide: Vec<f64>,
    /// The mode at each time.
    pub mode: Vec<Mode>,
}

/// Sample times still to be filled, and what was filled.
struct Sampler {
    times: Vec<f64>,
    next: usize,
    out: ContactSeries,
}

impl Sampler {
    /// Fills every time up to `upto` (included) with `state(t)` = (θ, θ̇, slip).
    fn fill(&mut self, upto: f64, mode: Mode, state: impl Fn(f64) -> (f64, f64, f64)) {
        while let Some(&t) = self.times.get(self.next) {
            if t > upto {
                break;
            }
            let (theta, theta_dot, slide) = state(t);
            self.out.t.push(t);
            self.out.theta.push(theta);
            self.out.theta_dot.push(theta_dot);
            self.out.slide.push(slide);
            self.out.mode.push(mode);
            self.next += 1;
        }
    }
}

/// How the block moves between events.
#[derive(Clone, Copy, Debug)]
enum Phase {
    Stick,
    /// Flat, sliding at `velocity` (its sign the direction; 0 with
    /// `direction` from the ground's push).
    Slide {
        direction: f64,
        velocity: f64,
    },
    Rock {
        side: f64,
        y: State,
    },
    SlideRock {
        side: f64,
        sigma: f64,
        y: State,
        slip_velocity: f64,
    },
    /// In the air from `pose`.
    Flight {
        pose: Pose,
    },
}

/// How a leg ended.
#[derive(Clone, Copy, Debug)]
enum LegEnd {
    /// θ returned to 0.
    Impact(f64, State),
    /// |θ| reached π/2.
    Overturn(f64, State),
    /// Sampled event `k` became positive.
    Sampled(usize, f64, State),
    /// The leg's end (a kink of the forcing or its end).
    Reached(f64, State),
    /// The forcing's end, from which a rock is pure rocking to its end
    /// ([`free_rocking::stays_pure`]): decided there.
    Decided(f64, State),
    /// The forcing's end, where no free motion is asked for
    /// ([`Asks::max_free_impacts`] 0).
    Cut(f64, State),
}

impl LegEnd {
    fn state(&self) -> (f64, State) {
        match *self {
            LegEnd::Impact(t, y)
            | LegEnd::Overturn(t, y)
            | LegEnd::Sampled(_, t, y)
            | LegEnd::Reached(t, y)
            | LegEnd::Decided(t, y)
            | LegEnd::Cut(t, y) => (t, y),
        }
    }

    fn time(&self) -> f64 {
        self.state().0
    }
}

struct Driver<'a, G> {
    block: Block,
    forcing: &'a G,
    friction: Friction,
    method: Method,
    rtol: f64,
    atol: f64,
    h_hint: f64,
    out: ContactResponse,
    /// The next instant from which g + ü_v ≤ 0, as last looked for.
    weightless: Option<f64>,
    /// Where a chattering rock summed in closed form comes to rest.
    settled_at: Option<f64>,
    /// The series being sampled, when asked for.
    sampler: Option<Sampler>,
    /// A slip that stopped where it started: the pivot holds from there
    /// (the friction limit is looked for once the demand has fallen back
    /// within it), so that no mode is entered and left at one instant.
    hold: bool,
    /// Whether the peak |θ| is located.
    peak: bool,
    /// Whether to stop where the outcome is decided: free rocking that is
    /// pure rocking to its end ([`Driver::decides`]).
    decide: bool,
    /// Whether free rocking can never be pure rocking on this floor (its
    /// impacts slip, or the least rocking needs more than μ_s); `None`
    /// until asked.
    never_pure: Option<bool>,
    /// The energy of the last free rock found not to be pure rocking: a
    /// later one is examined once it has half as much.
    impure_energy: f64,
    /// Free impacts to follow at most ([`Asks::max_free_impacts`]).
    max_free_impacts: Option<u64>,
    /// Impacts after the ground motion's end so far.
    free_impacts: u64,
    /// Impacts followed one by one so far.
    simulated_impacts: u64,
    /// The last impacts of a chattering sequence, (t, |θ̇| after, slip),
    /// for [`Driver::sum_chatter`].
    chatter: Vec<(f64, f64, f64)>,
    /// The time of the last impact, and how many more followed at it.
    last_impact: (f64, u64),
}

/// Simulates `block` on a floor with `friction` under `forcing` from rest,
/// with the Runge–Kutta pair `method` at (`rtol`, `atol`), to rest,
/// overturning or lift-off.
pub fn simulate_contact<G: Kinematics>(
    block: &Block,
    forcing: &G,
    friction: Friction,
    method: Method,
    rtol: f64,
    atol: f64,
) -> Result<ContactResponse, SimError> {
    simulate_contact_sampled(block, forcing, friction, method, rtol, atol, None)
}

/// [`simulate_contact`], also sampling the history at `times` (sorted;
/// those after its end are left out) into [`ContactResponse::series`]: θ
/// and θ̇ on the integrator's dense output, the slip in closed form.
pub fn simulate_contact_sampled<G: Kinematics>(
    block: &Block,
    forcing: &G,
    friction: Friction,
    method: Method,
    rtol: f64,
    atol: f64,
    times: Option<Vec<f64>>,
) -> Result<ContactResponse, SimError> {
    simulate_contact_with(
        block,
        forcing,
        friction,
        (method, rtol, atol),
        times,
        Asks::HISTORY,
    )
}

/// What a Coulomb history is asked for beyond its outcome and slide.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Asks {
    /// The peak |θ| ([`ContactResponse::peak_theta_over_alpha`]; 0 when not
    /// asked).
    pub peak: bool,
    /// Stop once the outcome is decided: at the ground motion's end or a
    /// later impact, where the block is at rest, or rocks on a holding
    /// pivot that free rocking never makes slip or lift
    /// ([`free_rocking::stays_pure`]), decided then in closed form
    /// ([`decide`]). The residual slide is then final; the rest time is
    /// not known (`None`), nor an overturning's time, and the impacts
    /// listed are those up to there.
    pub stop_at_decision: bool,
    /// Follow the free motion after the ground motion for at most this many
    /// impacts (as pure rocking's `max_free_impacts`; 0: end at the ground
    /// motion's end); `None`: to rest or overturning.
    pub max_free_impacts: Option<u64>,
}

impl Asks {
    /// The whole history.
    pub const HISTORY: Asks = Asks {
        peak: true,
        stop_at_decision: false,
        max_free_impacts: None,
    };
}

/// [`simulate_contact_sampled`] with the Runge–Kutta pair and its
/// tolerances as `(method, rtol, atol)`, asked for `asks` (a scan of
/// outcomes needs neither the peak nor the motion after its decision).
pub fn simulate_contact_with<G: Kinematics>(
    block: &Block,
    forcing: &G,
    friction: Friction,
    (method, rtol, atol): (Method, f64, f64),
    times: Option<Vec<f64>>,
    asks: Asks,
) -> Result<ContactResponse, SimError> {
    if !(rtol >= 1e-14 && rtol.is_finite() && atol > 0.0 && atol.is_finite()) {
        return Err(SimError::Tolerance);
    }
    let mut d = Driver {
        block: *block,
        forcing,
        friction,
        method,
        rtol,
        atol,
        h_hint: 0.0,
        out: ContactResponse {
            initial_mode: None,
            modes: Vec::new(),
            overturned: false,
            overturn_time: None,
            overturn_side: None,
            overturn_mode: None,
            impacts: Vec::new(),
            impact_count: 0,
            rocking_impacts: 0,
            summed_impacts: 0,
            first_flight: None,
            flights: 0,
            time_in_flight: 0.0,
            rest_time: None,
            end_time: forcing.duration(),
            peak_slide: 0.0,
            residual_slide: 0.0,
            time_sliding: 0.0,
            peak_theta_over_alpha: 0.0,
            stats: StepperStats::default(),
            events: 0,
            series: None,
            cut: None,
        },
        weightless: forcing.next_weightless(0.0, block.gravity()),
        settled_at: None,
        sampler: times.map(|times| Sampler {
            times,
            next: 0,
            out: ContactSeries::default(),
        }),
        hold: false,
        peak: asks.peak,
        decide: asks.stop_at_decision,
        never_pure: None,
        impure_energy: f64::INFINITY,
        max_free_impacts: asks.max_free_impacts,
        free_impacts: 0,
        simulated_impacts: 0,
        chatter: Vec::new(),
        last_impact: (f64::NAN, 0),
    };
    d.run()?;
    if let Some(mut s) = d.sampler.take() {
        // At the end: at rest where it stopped, or where it overturned.
        let x = d.out.residual_slide;
        if !d.out.overturned {
            s.fill(f64::INFINITY, Mode::Stick, |_| (0.0, 0.0, x));
        }
        d.out.series = Some(s.out);
    }
    Ok(d.out)
}

impl<G: Kinematics> Driver<'_, G> {
    fn g_z(&self, t: f64) -> f64 {
        self.block.gravity() + ground_after(self.forcing, t).1
    }

    /// Appends `mode` over [from, to] (merged with a preceding stretch of it
    /// in the same direction; no stretch of no duration but flight — a stick
    /// of none is a reversal).
    fn span(
        &mut self,
        mode: Mode,
        (from, to): (f64, f64),
        direction: Option<f64>,
        slip: (f64, f64),
    ) {
        if mode != Mode::Flight && to <= from {
            return;
        }
        if let Some(last) = self.out.modes.last_mut()
            && last.mode == mode
            && last.direction == direction
            && last.to >= from
        {
            last.to = last.to.max(to);
            last.slip.1 = slip.1;
            return;
        }
        self.out.modes.push(ModeSpan {
            mode,
            from,
            to,
            direction,
            slip,
        });
    }

    /// Samples the series (when asked for) up to `upto` with `state`.
    fn fill(&mut self, upto: f64, mode: Mode, state: impl Fn(f64) -> (f64, f64, f64)) {
        if let Some(s) = self.sampler.as_mut() {
            s.fill(upto, mode, state);
        }
    }

    fn slid(&mut self, x: f64) {
        self.out.peak_slide = self.out.peak_slide.max(x.abs());
        self.out.residual_slide = x;
    }

    /// The first instant at or after `t` from which g + ü_v ≤ 0.
    fn weightless_from(&mut self, t: f64) -> Option<f64> {
        if self.weightless.is_some_and(|l| l < t) {
            self.weightless = self.forcing.next_weightless(t, self.block.gravity());
        }
        self.weightless.map(|l| l.max(t))
    }

    /// The block leaves the floor at `t` in `pose`.
    fn take_off(&mut self, t: f64, pose: Pose) -> Phase {
        self.out.first_flight.get_or_insert(t);
        self.out.flights += 1;
        self.out.events += 1;
        Phase::Flight { pose }
    }

    /// A take-off from the corner `side` in state `y`, the slip at `x`
    /// moving at `slip_velocity`.
    fn take_off_from_corner(
        &mut self,
        t: f64,
        side: f64,
        y: State,
        x: f64,
        slip_velocity: f64,
    ) -> Phase {
        let pose = Pose::on_corner(&self.block, side, y[0], y[1], x, slip_velocity);
        self.take_off(t, pose)
    }

    /// Runs the history to its end, or to where it is cut short: free
    /// impacts as asked, or a bound on its work ([`Cut`]).
    fn run(&mut self) -> Result<(), SimError> {
        match self.run_phases() {
            Err(SimError::FreeMotionUnended(at)) => {
                self.out.end_time = at;
                self.out.rest_time = None;
                self.out.cut = Some(Cut::Limit(Limit::FreeTime(at - self.forcing.duration())));
                Ok(())
            }
            r => r,
        }
    }

    /// The bound the history has reached before its next phase, if any.
    fn reached(&self, t: f64) -> Option<Cut> {
        if let Some(n) = self.max_free_impacts
            && t >= self.forcing.duration()
            && self.free_impacts >= n
        {
            return Some(Cut::FreeImpacts(n));
        }
        if self.simulated_impacts >= MAX_IMPACTS {
            return Some(Cut::Limit(Limit::Impacts(self.simulated_impacts)));
        }
        if self.out.stats.accepted >= MAX_STEPS {
            return Some(Cut::Limit(Limit::Steps(self.out.stats.accepted)));
        }
        None
    }

    /// Ends the history at `t` in `phase`, cut short by `cut`: a rock in
    /// free motion that is pure rocking to its end is decided in closed
    /// form ([`decide`]); otherwise its outcome past `t` is not followed.
    fn cut_short(&mut self, t: f64, phase: Phase, cut: Cut) {
        self.out.cut = Some(cut);
        self.out.end_time = t;
        self.out.rest_time = None;
        if let Phase::Rock { side, y } = phase
            && t >= self.forcing.duration()
            && free_rocking::within_limits(
                &self.block,
                self.friction.static_coefficient,
                y[0],
                y[1],
            )
        {
            self.decided(t, side, y);
        }
    }

    /// The history phase after phase from rest at t = 0, to its end: rest
    /// for good, overturning, or a cut.
    fn run_phases(&mut self) -> Result<(), SimError> {
        let block = self.block;
        let v_rest = REST_VELOCITY * block.frequency_parameter() * block.slenderness();
        let (mut t, mut x) = (0.0f64, 0.0f64);
        let mut phase = Phase::Stick;
        loop {
            if !matches!(phase, Phase::Stick)
                && let Some(cut) = self.reached(t)
            {
                self.cut_short(t, phase, cut);
                return Ok(());
            }
            match phase {
                Phase::Stick => match self.stick(t, x) {
                    Some((t1, next)) => (t, phase) = (t1, next),
                    None => return Ok(()),
                },
                Phase::Slide {
                    direction,
                    velocity,
                } => (t, x, phase) = self.slide(t, x, direction, velocity),
                Phase::Rock { side, y } => {
                    let (next, t1) = self.rock(t, side, y, v_rest)?;
                    t = t1;
                    match next {
                        Some(p) => phase = p,
                        None => return Ok(()),
                    }
                }
                Phase::SlideRock {
                    side,
                    sigma,
                    y,
                    slip_velocity,
                } => {
                    let (next, t1, x1) =
                        self.slide_rock(t, x, side, sigma, y, slip_velocity, v_rest)?;
                    (t, x) = (t1, x1);
                    match next {
                        Some(p) => phase = p,
                        None => return Ok(()),
                    }
                }
                Phase::Flight { pose } => {
                    let (next, t1, x1) = self.fly(t, pose, v_rest)?;
                    (t, x) = (t1, x1);
                    match next {
                        Some(p) => phase = p,
                        None => return Ok(()),
                    }
                }
            }
        }
    }

    /// At rest from `t` (or from where a chatter settled, if later), the
    /// base at `x`: until the ground moves the block (eq. 7), then when and
    /// in what phase it leaves rest; `None` where it stays at rest to the
    /// end of the history.
    fn stick(&mut self, t: f64, x: f64) -> Option<(f64, Phase)> {
        let block = self.block;
        let duration = self.forcing.duration();
        let tan = block.slenderness().tan();
        let mut t = t;
        self.chatter.clear();
        if let Some(rest) = self.settled_at.take() {
            t = t.max(rest);
        }
        let next = onset(self.forcing, &block, self.friction, t);
        let Some((t1, mode)) = next else {
            let end = t.max(duration);
            self.fill(end, Mode::Stick, |_| (0.0, 0.0, x));
            self.span(Mode::Stick, (t, end), None, (x, x));
            if self.out.initial_mode.is_some() {
                self.out.rest_time = Some(t);
            }
            self.out.end_time = end;
            return None;
        };
        self.fill(t1, Mode::Stick, |_| (0.0, 0.0, x));
        self.span(Mode::Stick, (t, t1), None, (x, x));
        self.out.events += 1;
        self.out.initial_mode.get_or_insert(mode);
        let t = t1;
        let push = -self.forcing.acceleration(t).signum();
        let side = if push == 0.0 { 1.0 } else { push };
        let phase = match mode {
            Mode::Flight => self.take_off(t, Pose::flat(&block, x, 0.0)),
            Mode::Rock => Phase::Rock {
                side,
                y: [0.0, 0.0],
            },
            Mode::Slide if self.friction.kinetic_coefficient > tan => Phase::SlideRock {
                side,
                sigma: side,
                y: [0.0, 0.0],
                slip_velocity: 0.0,
            },
            Mode::Slide => Phase::Slide {
                direction: side,
                velocity: 0.0,
            },
            Mode::SlideRock | Mode::Stick => self.slide_rock_from_rest(t, side),
        };
        Some((t, phase))
    }

    /// A flat slide from `t`, the base at `x`, in `direction` at `velocity`:
    /// when it ends, the slip there, and the next phase (sticking, or a
    /// flight where the floor lets go).
    fn slide(&mut self, t: f64, x: f64, direction: f64, velocity: f64) -> (f64, f64, Phase) {
        let (end, x_end, lifted) = self.flat_slide(t, x, direction, velocity);
        self.span(Mode::Slide, (t, end), Some(direction), (x, x_end));
        self.out.time_sliding += end - t;
        self.slid(x_end);
        let phase = match lifted {
            Some(v) => self.take_off(end, Pose::flat(&self.block, x_end, v)),
            None => {
                self.out.events += 1;
                Phase::Stick
            }
        };
        (end, x_end, phase)
    }

    /// The slide-rock a block at rest on `side` enters at `t` (its pivot
    /// slipping the way its acceleration takes it), or rock where no slip
    /// is consistent (Painlevé: the pivot holds).
    fn slide_rock_from_rest(&self, t: f64, side: f64) -> Phase {
        match self.slip_direction(t, side, [0.0, 0.0]) {
            Some(sigma) => Phase::SlideRock {
                side,
                sigma,
                y: [0.0, 0.0],
                slip_velocity: 0.0,
            },
            None => Phase::Rock {
                side,
                y: [0.0, 0.0],
            },
        }
    }

    /// The direction σ a pivot at rest in state `y` on `side` slips in: the
    /// one whose slide-rock acceleration of the pivot has its sign.
    fn slip_direction(&self, t: f64, side: f64, y: State) -> Option<f64> {
        let (alpha, r) = (self.block.slenderness(), self.block.half_diagonal());
        let mu = self.friction.kinetic_coefficient;
        let g_z = self.g_z(t);
        let ug = ground_after(self.forcing, t).0;
        let accel = |sigma: f64| {
            let kappa = sigma * mu;
            let acc = slide_rock::angular_acceleration(alpha, r, side, kappa, g_z, y[0], y[1])?;
            let n = slide_rock::normal_per_mass(alpha, r, side, g_z, y[0], y, acc);
            let (s, c) = (side * alpha - y[0]).sin_cos();
            Some(-ug - kappa * n - r * s * y[1] * y[1] - r * c * acc)
        };
        // The rock's friction demand points the way the floor must push;
        // the pivot slips the other way (at the limit its acceleration
        // starts from 0: the sign of the demand decides).
        let (fx, _) = self.reactions(t, side, y);
        let sigma = if fx > 0.0 { -1.0 } else { 1.0 };
        accel(sigma).map(|_| sigma)
    }

    fn reactions(&self, t: f64, side: f64, y: State) -> (f64, f64) {
        let (ug, uv) = ground_after(self.forcing, t);
        reactions_per_mass_vertical(
            Formulation::Nonlinear,
            &self.block,
            side,
            y[0],
            y[1],
            ug,
            uv,
        )
    }

    /// A flat slide from `t` at slip `x` until it stops or the block leaves
    /// the floor: (end, slip there, the velocity it left the floor with).
    fn flat_slide(
        &mut self,
        t: f64,
        x: f64,
        direction: f64,
        velocity: f64,
    ) -> (f64, f64, Option<f64>) {
        let g = self.block.gravity();
        let leg = sliding::Leg::new(
            self.forcing,
            g,
            self.friction.kinetic_coefficient,
            direction,
            t,
            x,
            velocity,
        );
        let drive = Threshold {
            level: self.friction.kinetic_coefficient * g,
            factor: self.friction.kinetic_coefficient,
            gravity: g,
        };
        let end = sliding::stop(&leg, &drive);
        // (A slide still running where the ground falls away ends there:
        // `stop` returns that instant.)
        if let Some(l) = self.weightless_from(t).filter(|&l| l <= end) {
            self.fill(l, Mode::Slide, |t| (0.0, 0.0, leg.displacement(t)));
            return (l, leg.displacement(l), Some(leg.velocity(l)));
        }
        self.fill(end, Mode::Slide, |t| (0.0, 0.0, leg.displacement(t)));
        (end, leg.displacement(end), None)
    }

    /// A rocking stretch from `t` on `side` in state `y`: the next phase
    /// (`None`: the history ended) and when.
    fn rock(
        &mut self,
        t: f64,
        side: f64,
        y: State,
        v_rest: f64,
    ) -> Result<(Option<Phase>, f64), SimError> {
        let mu_s = self.friction.static_coefficient;
        let block = self.block;
        let x0 = self.out.residual_slide;
        // Already beyond the friction limit (after an impact, or at once).
        let (fx, fz) = self.reactions(t, side, y);
        if fz <= 0.0 {
            return Ok((Some(self.take_off_from_corner(t, side, y, x0, 0.0)), t));
        }
        let hold = std::mem::take(&mut self.hold);
        if !hold
            && fx.abs() > mu_s * fz
            && let Some(sigma) = self.slip_direction(t, side, y)
        {
            return Ok((
                Some(Phase::SlideRock {
                    side,
                    sigma,
                    y,
                    slip_velocity: 0.0,
                }),
                t,
            ));
        }
        if t >= self.forcing.duration() && self.decides(y) {
            self.decided(t, side, y);
            return Ok((None, t));
        }
        let forcing = self.forcing;
        let start = t;
        let events = |t: f64, y: State, forced: bool| {
            let (ug, uv) = ground(forcing, t, forced);
            let (fx, fz) = reactions_per_mass_vertical(
                Formulation::Nonlinear,
                &block,
                side,
                y[0],
                y[1],
                ug,
                uv,
            );
            let limit = fx.abs() - mu_s * fz;
            // Held: the limit is not armed by its value at the start (at
            // the limit to rounding), only once the demand has fallen back.
            let limit = if hold && t == start {
                limit.abs().max(f64::MIN_POSITIVE)
            } else {
                limit
            };
            [limit, -fz]
        };
        let end = self.leg(
            |forced| forcing.rhs(Formulation::Nonlinear, &block, side, forced),
            side,
            t,
            y,
            &events,
            [false, false],
            (Mode::Rock, &|_, _| x0),
        )?;
        let x = self.out.residual_slide;
        self.span(Mode::Rock, (t, end.time()), None, (x, x));
        match end {
            LegEnd::Impact(t1, y1) => Ok((self.impact(t1, side, y1[1], 0.0, v_rest), t1)),
            LegEnd::Overturn(t1, _) => {
                self.overturn(t1, side);
                Ok((None, t1))
            }
            LegEnd::Sampled(k, t1, y1) => {
                self.out.events += 1;
                let (_, fz) = self.reactions(t1, side, y1);
                if k == 1 || fz <= 0.0 {
                    return Ok((Some(self.take_off_from_corner(t1, side, y1, x, 0.0)), t1));
                }
                Ok((self.slip(t1, side, y1), t1))
            }
            LegEnd::Reached(t1, y1) => {
                // The ground falls away (g + ü_v ≤ 0).
                Ok((Some(self.take_off_from_corner(t1, side, y1, x, 0.0)), t1))
            }
            LegEnd::Decided(t1, y1) => {
                self.decided(t1, side, y1);
                Ok((None, t1))
            }
            LegEnd::Cut(t1, y1) => {
                self.cut_short(t1, Phase::Rock { side, y: y1 }, Cut::FreeImpacts(0));
                Ok((None, t1))
            }
        }
    }

    /// The pivot of a rocking block starts to slip at `t`.
    fn slip(&mut self, t: f64, side: f64, y: State) -> Option<Phase> {
        Some(match self.slip_direction(t, side, y) {
            Some(sigma) => Phase::SlideRock {
                side,
                sigma,
                y,
                slip_velocity: 0.0,
            },
            // No slip is consistent (Painlevé): the pivot holds, and the
            // friction limit is looked for again once the demand has
            // fallen back within it (else the limit, passed at the leg's
            // start, would end every leg there).
            None => {
                self.hold = true;
                Phase::Rock { side, y }
            }
        })
    }

    fn overturn(&mut self, t: f64, side: f64) {
        self.out.overturn_time = Some(t);
        self.overturned_to(side);
        self.out.end_time = t;
        self.out.peak_theta_over_alpha = self
            .out
            .peak_theta_over_alpha
            .max(std::f64::consts::FRAC_PI_2 / self.block.slenderness());
    }

    /// The block overturns to `side`: the paper's mode 1 after impacts
    /// (those counted so far), mode 2 without.
    fn overturned_to(&mut self, side: f64) {
        self.out.overturned = true;
        self.out.overturn_side = Some(side);
        self.out.overturn_mode = Some(if self.out.impact_count > 0 {
            OverturnMode::AfterImpacts(self.out.impact_count)
        } else {
            OverturnMode::WithoutImpact
        });
    }

    /// Whether a rock in free motion at `y` is decided here: asked to stop
    /// at the decision, and pure rocking to its end
    /// ([`free_rocking::stays_pure`]).
    fn decides(&mut self, y: State) -> bool {
        if !self.decide || self.sampler.is_some() {
            return false;
        }
        let (block, mu_s) = (self.block, self.friction.static_coefficient);
        let never = *self
            .never_pure
            .get_or_insert_with(|| !free_rocking::stays_pure(&block, mu_s, 0.0, 0.0));
        let energy = free_rocking::energy(&block, y[0], y[1]);
        if never || energy > 0.5 * self.impure_energy {
            return false;
        }
        let pure = free_rocking::within_limits(&block, mu_s, y[0], y[1]);
        if !pure {
            self.impure_energy = energy;
        }
        pure
    }

    /// The outcome of pure rocking from `y` on `side` at `t`, in closed
    /// form (eq. 33's nonlinear counterpart, [`decide`]).
    fn decided(&mut self, t: f64, side: f64, y: State) {
        self.out.events += 1;
        self.out.end_time = t;
        if let FreeOutcome::Overturns { impacts } =
            decide(Formulation::Nonlinear, &self.block, y[0], y[1], side)
        {
            self.out.impact_count += u64::from(impacts);
            // Each impact turns the block over to the other side.
            self.overturned_to(if impacts % 2 == 0 { side } else { -side });
        }
    }

    /// The impact at `t` of a block on `side` with θ̇ = `theta_dot` whose
    /// pivot slips at `slip_velocity`: the phase after it.
    fn impact(
        &mut self,
        t: f64,
        side: f64,
        theta_dot: f64,
        slip_velocity: f64,
        v_rest: f64,
    ) -> Option<Phase> {
        let f = self.friction;
        let (mut side, mut theta_dot, mut slip_velocity) = (side, theta_dot, slip_velocity);
        let mut hit;
        let mut chained = 0;
        loop {
            hit = slide_rock::impact(
                &self.block,
                f.static_coefficient,
                f.kinetic_coefficient,
                side,
                theta_dot,
                slip_velocity,
            );
            self.out.impact_count += 1;
            self.out.events += 1;
            self.list_impact(ContactImpact {
                t,
                theta_dot: (theta_dot, hit.theta_dot),
                sticking: hit.sticking,
            });
            // A sliding impact may turn the rotation back towards the corner
            // that just left: that corner, still on the floor, is struck in
            // turn (same instant, the roles swapped), until the rotation
            // leaves the floor or dies out.
            chained += 1;
            if hit.theta_dot * side > 0.0 && hit.theta_dot.abs() > v_rest && chained < MAX_CHAINED {
                (side, theta_dot, slip_velocity) = (-side, hit.theta_dot, hit.slip_velocity);
                continue;
            }
            break;
        }
        self.count_impacts(t, u64::from(chained));
        let new_side = -side;
        let forced = t < self.forcing.duration();
        if hit.sticking && hit.theta_dot.abs() > v_rest {
            // A chattering rock settles in closed form.
            if let Some(settled) = settle(
                Formulation::Nonlinear,
                &self.block,
                self.forcing,
                forced,
                t,
                hit.theta_dot,
                v_rest,
            ) {
                self.out.impact_count += settled.impacts;
                self.out.summed_impacts += settled.impacts;
                let x = self.out.residual_slide;
                self.fill(settled.rest_time, Mode::Rock, |_| (0.0, 0.0, x));
                self.span(Mode::Rock, (t, settled.rest_time), None, (x, x));
                self.settled_at = Some(settled.rest_time);
                return Some(Phase::Stick);
            }
        }
        if let Some(phase) = self.sum_chatter(t, &hit, forced, v_rest) {
            return Some(phase);
        }
        let stalled = self.repeats_at(t, t);
        if hit.theta_dot.abs() <= v_rest || hit.theta_dot * new_side < 0.0 || stalled {
            // Lands flat.
            if hit.slip_velocity == 0.0 {
                return Some(Phase::Stick);
            }
            let direction = hit.slip_velocity.signum();
            return Some(if f.kinetic_coefficient > self.block.slenderness().tan() {
                Phase::SlideRock {
                    side: direction,
                    sigma: direction,
                    y: [0.0, 0.0],
                    slip_velocity: hit.slip_velocity,
                }
            } else {
                Phase::Slide {
                    direction,
                    velocity: hit.slip_velocity,
                }
            });
        }
        let y = [0.0, hit.theta_dot];
        Some(if hit.sticking {
            Phase::Rock { side: new_side, y }
        } else {
            Phase::SlideRock {
                side: new_side,
                sigma: hit.slip_velocity.signum(),
                y,
                slip_velocity: hit.slip_velocity,
            }
        })
    }

    /// Lists an impact (a landing) followed one by one, up to
    /// [`MAX_LISTED_IMPACTS`](super::simulate::MAX_LISTED_IMPACTS), and
    /// counts it among the rocking impacts where its θ̇ before reaches
    /// [`ROCKING_IMPACT_VELOCITY`](super::simulate::ROCKING_IMPACT_VELOCITY)
    /// p α (the rule of pure rocking's count).
    fn list_impact(&mut self, impact: ContactImpact) {
        let v_rest = REST_VELOCITY * self.block.frequency_parameter() * self.block.slenderness();
        if impact.theta_dot.0.abs() >= ROCKING_IMPACT_VELOCITY * v_rest / REST_VELOCITY {
            self.out.rocking_impacts += 1;
        }
        if self.out.impacts.len() < super::simulate::MAX_LISTED_IMPACTS {
            self.out.impacts.push(impact);
        }
    }

    /// Whether impacts (landings) have repeated at the instant `t` so
    /// often ([`MAX_AT_ONE_INSTANT`]) that the sequence, each corner striking in
    /// turn or the block leaving the floor and landing again without
    /// turning away, has reached its limit: the block flat on the floor.
    /// `since` is when the motion that ended in this impact began (a
    /// flight's take-off, or the impact itself for a chained one).
    fn repeats_at(&mut self, t: f64, since: f64) -> bool {
        // (A chattering sequence's impacts come ever closer, but never at
        // one instant: only impacts after no motion at all count.)
        if t == self.last_impact.0
            || (since == self.last_impact.0 && t - since <= 1e-12 * t.abs().max(1.0))
        {
            self.last_impact.1 += 1;
        } else {
            self.last_impact.1 = 0;
        }
        self.last_impact.0 = t;
        self.last_impact.1 >= MAX_AT_ONE_INSTANT
    }

    /// Counts `n` impacts followed one by one at `t` (free ones after the
    /// ground motion's end).
    fn count_impacts(&mut self, t: f64, n: u64) {
        self.simulated_impacts += n;
        if t >= self.forcing.duration() {
            self.free_impacts += n;
        }
    }

    /// A chattering sequence of impacts that slide (or hold with η = 1) in
    /// free motion, summed in closed form where it has become geometric:
    /// below
    /// [`CHATTER_VELOCITY`] p α the motion between impacts scales with the
    /// rebound (times and slip velocities as θ̇, slips as θ̇²) while the
    /// ground's pull stays what it is, so that the rebound over two
    /// impacts (one on each side) shrinks by one ratio q. Where the last
    /// [`CHATTER_WINDOW`] impacts show it, the rest of the sequence takes
    /// the time of the last two times q/(1 − q), slips their slip times
    /// q²/(1 − q²), and makes the impacts that bring the rebound below the
    /// rest velocity; the block then stands.
    fn sum_chatter(
        &mut self,
        t: f64,
        hit: &slide_rock::ImpactOutcome,
        forced: bool,
        v_rest: f64,
    ) -> Option<Phase> {
        let block = self.block;
        let speed = hit.theta_dot.abs();
        let scale = block.frequency_parameter() * block.slenderness();
        // (Holding impacts with η < 1 are summed by `settle` where that is
        // exact, else followed one by one.)
        // Under the ground motion the pull changes while the sequence runs:
        // it is summed in free motion only, where it is exactly geometric
        // in the limit.
        let holds = hit.sticking && block.restitution() < 1.0;
        if forced || holds || !(speed > v_rest && speed <= CHATTER_VELOCITY * scale) {
            self.chatter.clear();
            return None;
        }
        let x = self.out.residual_slide;
        self.chatter.push((t, speed, x));
        if self.chatter.len() > CHATTER_WINDOW {
            self.chatter.remove(0);
        }
        let [a, _, b, _, n] = self.chatter[..] else {
            return None;
        };
        let q = n.1 / b.1;
        let agree = |r: f64| (r - q).abs() <= CHATTER_RATIO_AGREEMENT * (1.0 - q);
        let cycle = n.0 - b.0;
        let geometric = q > 0.0 && q < 1.0 && cycle > 0.0;
        if !(geometric && agree(b.1 / a.1) && agree(cycle / (b.0 - a.0))) {
            return None;
        }
        let remaining = cycle * q / (1.0 - q);
        let rest = t + remaining;
        let impacts = (2.0 * (v_rest / speed).ln() / q.ln()).ceil().max(1.0) as u64;
        let x_end = x + (n.2 - b.2) * q * q / (1.0 - q * q);
        self.out.impact_count += impacts;
        self.out.summed_impacts += impacts;
        self.fill(rest, Mode::Rock, |_| (0.0, 0.0, x_end));
        self.span(Mode::Rock, (t, rest), None, (x, x_end));
        self.slid(x_end);
        self.settled_at = Some(rest);
        self.chatter.clear();
        Some(Phase::Stick)
    }

    /// A flight from `pose` at `t` to its landing (the next phase, when, and
    /// the slip there) or to overturning in the air (`None`).
    fn fly(
        &mut self,
        t: f64,
        pose: Pose,
        v_rest: f64,
    ) -> Result<(Option<Phase>, f64, f64), SimError> {
        let block = self.block;
        let p = block.frequency_parameter();
        let duration = self.forcing.duration();
        let flight = Flight::new(self.forcing, &block, t, pose);
        // The clearance is sampled finely against both the block's and the
        // forcing's time scales.
        let dt = std::f64::consts::TAU / p.max(self.forcing.resolving_frequency()) / 64.0;
        let limit = duration + FREE_PERIODS * std::f64::consts::TAU / p;
        let Some(end) = flight.end(dt, limit) else {
            return Err(SimError::FreeMotionUnended(limit));
        };
        let t1 = match end {
            FlightEnd::Landing(t1) | FlightEnd::Overturn(t1) => t1,
        };
        let pose1 = self.flown(&flight, (t, pose), t1);
        let x1 = pose1.slip(&block);
        if let FlightEnd::Overturn(t1) = end {
            self.overturn(t1, pose1.theta.signum());
            return Ok((None, t1, x1));
        }
        let (next, x) = self.land(t, t1, pose1, v_rest);
        Ok((Some(next), t1, x))
    }

    /// Records the `flight` from `pose` at `t` to `t1`: its samples, its
    /// stretch and slip, the time in the air and the peak rotation; its
    /// pose at `t1`.
    fn flown(&mut self, flight: &Flight<'_, G>, (t, pose): (f64, Pose), t1: f64) -> Pose {
        let block = self.block;
        let alpha = block.slenderness();
        self.fill(t1, Mode::Flight, |t| {
            let q = flight.pose(t);
            (q.theta, q.omega, q.slip(&block))
        });
        let x0 = pose.slip(&block);
        let pose1 = flight.pose(t1);
        let x1 = pose1.slip(&block);
        self.out.peak_slide = self.out.peak_slide.max(flight.peak_slip(t1));
        self.slid(x1);
        self.span(Mode::Flight, (t, t1), None, (x0, x1));
        self.out.time_in_flight += t1 - t;
        self.out.peak_theta_over_alpha = self.out.peak_theta_over_alpha.max(
            pose.theta
                .abs()
                .max(pose1.theta.abs())
                .min(std::f64::consts::FRAC_PI_2)
                / alpha,
        );
        pose1
    }

    /// A landing at `t1` from `pose1` (a flight that left at `t`): counted
    /// and listed as an impact; the next phase and the slip there. On a
    /// corner it holds or slides as at an impact; flat, or level and not
    /// turning up onto the corner, the block sticks or slides on.
    fn land(&mut self, t: f64, t1: f64, pose1: Pose, v_rest: f64) -> (Phase, f64) {
        let block = self.block;
        let f = self.friction;
        let landing = if self.repeats_at(t1, t) {
            flight::land_flat(&block, f.static_coefficient, f.kinetic_coefficient, &pose1)
        } else {
            flight::land(&block, f.static_coefficient, f.kinetic_coefficient, &pose1)
        };
        self.out.impact_count += 1;
        self.count_impacts(t1, 1);
        self.out.events += 1;
        let omega_after = match landing.landed {
            Landed::Corner { theta_dot, .. } => theta_dot,
            Landed::Flat { .. } => 0.0,
        };
        self.list_impact(ContactImpact {
            t: t1,
            theta_dot: (pose1.omega, omega_after),
            sticking: match landing.landed {
                Landed::Corner { sticking, .. } => sticking,
                Landed::Flat { velocity } => velocity == 0.0,
            },
        });
        match landing.landed {
            Landed::Flat { velocity } => {
                let x = pose1.x;
                self.slid(x);
                (self.landed_flat(velocity), x)
            }
            Landed::Corner {
                side,
                theta_dot,
                slip_velocity,
                sticking,
            } => {
                // The slip of the corner that landed.
                let x = pose1.corner_slip(&block, side);
                self.slid(x);
                let y = [pose1.theta, theta_dot];
                if pose1.theta == 0.0 && (theta_dot * side <= 0.0 || theta_dot.abs() <= v_rest) {
                    // Level and not turning up onto the corner: flat.
                    (self.landed_flat(slip_velocity), x)
                } else if sticking {
                    (Phase::Rock { side, y }, x)
                } else {
                    (
                        Phase::SlideRock {
                            side,
                            sigma: slip_velocity.signum(),
                            y,
                            slip_velocity,
                        },
                        x,
                    )
                }
            }
        }
    }

    /// A block landed flat, its base slipping at `velocity`: sticking, or
    /// sliding on (tipping into slide-rock at once where μ_k > tan α).
    fn landed_flat(&self, velocity: f64) -> Phase {
        if velocity == 0.0 {
            Phase::Stick
        } else if self.friction.kinetic_coefficient > self.block.slenderness().tan() {
            let direction = velocity.signum();
            Phase::SlideRock {
                side: direction,
                sigma: direction,
                y: [0.0, 0.0],
                slip_velocity: velocity,
            }
        } else {
            Phase::Slide {
                direction: velocity.signum(),
                velocity,
            }
        }
    }

    /// A slide-rock on `side` jamming at `t` in state `y`, its pivot at `x`
    /// slipping at `v`: the pivot stops at once (an impulse of friction,
    /// [`flight::jam`]), and the block rocks on it, or leaves the floor
    /// where that impulse would pull.
    fn jam(&mut self, t: f64, side: f64, y: State, x: f64, v: f64) -> Phase {
        self.out.events += 1;
        let pose = Pose::on_corner(&self.block, side, y[0], y[1], x, v);
        match flight::jam(&self.block, side, &pose) {
            Some(w) => {
                self.hold = true;
                Phase::Rock { side, y: [y[0], w] }
            }
            None => self.take_off_from_corner(t, side, y, x, v),
        }
    }

    /// A slide-rock stretch: the next phase, when, and the slip there.
    #[allow(clippy::too_many_arguments)]
    fn slide_rock(
        &mut self,
        t: f64,
        x: f64,
        side: f64,
        sigma: f64,
        y: State,
        slip_velocity: f64,
        v_rest: f64,
    ) -> Result<(Option<Phase>, f64, f64), SimError> {
        let block = self.block;
        let (alpha, r, g) = (block.slenderness(), block.half_diagonal(), block.gravity());
        let kappa = sigma * self.friction.kinetic_coefficient;
        if let Some(next) = self.no_slide_rock(t, x, side, kappa, y, slip_velocity) {
            return Ok((Some(next), t, x));
        }
        let forcing = self.forcing;
        let leg = SlideRockLeg::new(forcing, &block, side, kappa, t, y, x, slip_velocity);
        let events = |t: f64, y: State, forced: bool| {
            let g_z = g + ground(forcing, t, forced).1;
            let phi = slide_rock::phase(alpha, side, y[0]);
            let acc = slide_rock::angular_acceleration_at(phi, r, kappa, g_z, y[1]).unwrap_or(0.0);
            let n = slide_rock::normal_per_mass_at(phi, r, g_z, y, acc);
            // The normal force reaching 0 (take-off), or the reduced
            // inertia nearing 0 (a jam): one event, told apart at its end.
            let jam = slide_rock::JAM_INERTIA - slide_rock::inertia_at(phi, kappa);
            [-sigma * leg.slip_at(t, y, phi).1, (-n).max(jam)]
        };
        let end = self.leg(
            |forced| SlideRockRhs {
                forcing,
                forced,
                alpha,
                r,
                g,
                side,
                kappa,
            },
            side,
            t,
            y,
            &events,
            // A slip starting from 0 runs the way σ says (its acceleration
            // has that sign): its stop is watched from the start, so that a
            // slip that turns back before the first sample is not followed
            // with the friction the wrong way.
            [slip_velocity == 0.0, false],
            (Mode::SlideRock, &|t, y| leg.slip(t, y).0),
        )?;
        let (t1, y1) = end.state();
        let (x1, _) = leg.slip(t1, y1);
        self.span(Mode::SlideRock, (t, t1), Some(sigma), (x, x1));
        self.out.time_sliding += t1 - t;
        self.slid(x1);
        match end {
            LegEnd::Impact(t1, y1) => {
                let (x1, v1) = leg.slip(t1, y1);
                Ok((self.impact(t1, side, y1[1], v1, v_rest), t1, x1))
            }
            LegEnd::Overturn(t1, y1) => {
                let (x1, _) = leg.slip(t1, y1);
                self.overturn(t1, side);
                Ok((None, t1, x1))
            }
            LegEnd::Sampled(0, t1, y1) => {
                let (x1, v1) = leg.slip(t1, y1);
                Ok((Some(self.slip_stops(t, side, (t1, y1), (x1, v1))), t1, x1))
            }
            LegEnd::Cut(t1, y1) => {
                let (x1, v1) = leg.slip(t1, y1);
                let phase = Phase::SlideRock {
                    side,
                    sigma,
                    y: y1,
                    slip_velocity: v1,
                };
                self.cut_short(t1, phase, Cut::FreeImpacts(0));
                Ok((None, t1, x1))
            }
            LegEnd::Sampled(1, t1, y1)
                if slide_rock::inertia(alpha, side, kappa, y1[0])
                    <= 2.0 * slide_rock::JAM_INERTIA =>
            {
                let (x1, v1) = leg.slip(t1, y1);
                Ok((Some(self.jam(t1, side, y1, x1, v1)), t1, x1))
            }
            // (A leg is decided on a rock only; a slide-rock's would be a
            // take-off as its end.)
            LegEnd::Sampled(_, t1, y1) | LegEnd::Reached(t1, y1) | LegEnd::Decided(t1, y1) => {
                let (x1, v1) = leg.slip(t1, y1);
                let next = self.take_off_from_corner(t1, side, y1, x1, v1);
                Ok((Some(next), t1, x1))
            }
        }
    }

    /// Where a slide-rock on `side` (friction κ = σ μ_k) cannot start at
    /// `t` from `y`, the pivot at `x` slipping at `slip_velocity`: the phase
    /// it enters instead. Painlevé: no slip is consistent, and the pivot
    /// holds; or the floor would have to pull at once (after an impact),
    /// and the block leaves it.
    fn no_slide_rock(
        &mut self,
        t: f64,
        x: f64,
        side: f64,
        kappa: f64,
        y: State,
        slip_velocity: f64,
    ) -> Option<Phase> {
        let block = self.block;
        let (alpha, r) = (block.slenderness(), block.half_diagonal());
        let g_z = self.g_z(t);
        let Some(acc) = slide_rock::angular_acceleration(alpha, r, side, kappa, g_z, y[0], y[1])
        else {
            // Painlevé: the pivot holds.
            self.hold = true;
            return Some(Phase::Rock { side, y });
        };
        if slide_rock::normal_per_mass(alpha, r, side, g_z, y[0], y, acc) <= 0.0 {
            // The floor would have to pull at once (after an impact).
            return Some(self.take_off_from_corner(t, side, y, x, slip_velocity));
        }
        None
    }

    /// The slip of a slide-rock on `side` (begun at `t`) stops at `t1` in
    /// state `y1`, the pivot at `x1` slipping at `v1`: the pivot holds if
    /// it can, else slips on the way the block's acceleration takes it; or
    /// the block leaves the floor where it would have to pull.
    fn slip_stops(
        &mut self,
        t: f64,
        side: f64,
        (t1, y1): (f64, State),
        (x1, v1): (f64, f64),
    ) -> Phase {
        self.out.events += 1;
        let (fx, fz) = self.reactions(t1, side, y1);
        if fz <= 0.0 {
            return self.take_off_from_corner(t1, side, y1, x1, v1);
        }
        if t1 - t <= 1e-12 * t.abs().max(1.0) {
            // Stopped where it started: the pivot holds (no slip
            // is consistent there, whatever the demand rounds to).
            self.hold = true;
            Phase::Rock { side, y: y1 }
        } else if fx.abs() <= self.friction.static_coefficient * fz {
            Phase::Rock { side, y: y1 }
        } else {
            match self.slip_direction(t1, side, y1) {
                Some(s) => Phase::SlideRock {
                    side,
                    sigma: s,
                    y: y1,
                    slip_velocity: 0.0,
                },
                None => Phase::Rock { side, y: y1 },
            }
        }
    }

    /// Integrates from (t, y) on `side` with the right-hand side `make(forced)`
    /// until θ returns to 0, |θ| reaches π/2, an armed sampled event turns
    /// positive (armed once it has been negative), or the ground falls away.
    #[allow(clippy::too_many_arguments)]
    fn leg<R: Rhs, M: Fn(bool) -> R, E: Fn(f64, State, bool) -> [f64; 2]>(
        &mut self,
        make: M,
        side: f64,
        t0: f64,
        y0: State,
        events: &E,
        arm: [bool; 2],
        (mode, slip): (Mode, &dyn Fn(f64, State) -> f64),
    ) -> Result<LegEnd, SimError> {
        let duration = self.forcing.duration();
        let s = side;
        let mut t = t0;
        let mut y = y0;
        let mut armed = {
            let e = events(t0, y0, t0 < self.forcing.duration());
            [arm[0] || e[0] < 0.0, arm[1] || e[1] < 0.0]
        };
        // A leg leaving θ = 0 with a velocity (after an impact) has a simple
        // root of s θ at the step's start, exactly: `first_nonpositive`
        // factors it out and finds the return even within the first step.
        // From rest the impact is looked for once θ has left 0 at a step's
        // end, and at the latest once the ground no longer exceeds the
        // rocking threshold (as under pure rocking: until then the block is
        // driven away from θ = 0, and no step crosses that instant, so that
        // a lift too small to outlast a step is not missed).
        let mut left_zero = y0[0] != 0.0 || y0[1] != 0.0;
        let lift_until = if left_zero {
            t0
        } else {
            let g = self.block.gravity();
            let k = self.block.slenderness().tan();
            let threshold = Threshold {
                level: k * g,
                factor: k,
                gravity: g,
            };
            // (The window the onset found: it opens at t0, or within
            // rounding after it where the search restarts inside a segment.)
            self.forcing
                .next_rocking(t0, &threshold)
                .filter(|w| w.start - t0 <= 1e-12 * t0.abs().max(1.0))
                .map_or(t0, |w| w.end)
        };
        let stop_at = self.weightless_from(t0).unwrap_or(f64::INFINITY);
        // A safeguard: free rocking loses energy at every impact and rests
        // within tens of periods; this many is a fault, not motion.
        let free_until =
            duration + FREE_PERIODS * std::f64::consts::TAU / self.block.frequency_parameter();
        loop {
            let forced = t < duration;
            let rhs = make(forced);
            // The events see the ground this segment's motion does (a
            // forced one up to the forcing's end included).
            let events = |t: f64, y: State| events(t, y, forced);
            let mut stepper = Stepper::new(
                self.method,
                self.rtol,
                self.atol,
                &rhs,
                t,
                y,
                f64::INFINITY,
                self.h_hint,
            );
            let segment_end = if forced {
                duration.min(stop_at)
            } else {
                stop_at
            };
            loop {
                if stepper.t >= segment_end {
                    break;
                }
                let mut target = segment_end;
                if forced {
                    target = target.min(self.forcing.breakpoint_after(stepper.t));
                }
                if !left_zero {
                    if stepper.t >= lift_until {
                        left_zero = true;
                    } else {
                        target = target.min(lift_until);
                    }
                }
                if !forced && stepper.t > free_until {
                    return Err(SimError::FreeMotionUnended(free_until));
                }
                let step = stepper.step(&rhs, target)?;
                // Impact and overturning on the dense output's polynomial.
                let (g, top) = return_and_overturn(&step.coeffs[0], step.len, s);
                let impact = if left_zero {
                    first_nonpositive(&g)
                } else {
                    None
                };
                let over = first_nonpositive(&top);
                let mut first: Option<(f64, u8)> = match (impact, over) {
                    (Some(i), Some(o)) if o < i => Some((o, 1)),
                    (Some(i), _) => Some((i, 0)),
                    (None, Some(o)) => Some((o, 1)),
                    (None, None) => None,
                };
                // Sampled events up to there.
                let limit = first.map_or(1.0, |f| f.0);
                if let Some((k, sigma)) = self.sampled(&step, &events, &mut armed, limit) {
                    first = Some((sigma, 2 + k as u8));
                }
                let upto = first.map_or(1.0, |f| f.0);
                if self.peak {
                    self.peak_on(&step, upto);
                }
                self.fill(step.t0 + upto * step.h, mode, |t| {
                    let y = step.at_sigma(((t - step.t0) / step.h).clamp(0.0, 1.0));
                    (y[0], y[1], slip(t, y))
                });
                if s * step.y1[0] > 0.0 {
                    left_zero = true;
                }
                if let Some((sigma, kind)) = first {
                    let (te, ye) = if kind < 2 {
                        self.place_on_steps(&rhs, &step, sigma, kind, s)
                    } else {
                        // A sampled event where the dense output puts it.
                        (step.t0 + sigma * step.h, step.at_sigma(sigma))
                    };
                    self.out.stats.absorb(&stepper.stats);
                    self.h_hint = stepper.next_step_size();
                    return Ok(match kind {
                        0 => LegEnd::Impact(te, ye),
                        1 => LegEnd::Overturn(te, ye),
                        k => LegEnd::Sampled(usize::from(k - 2), te, ye),
                    });
                }
            }
            self.out.stats.absorb(&stepper.stats);
            self.h_hint = stepper.next_step_size();
            (t, y) = (stepper.t, stepper.y);
            if t >= stop_at {
                return Ok(LegEnd::Reached(t, y));
            }
            // The forcing's end.
            if forced && self.max_free_impacts == Some(0) {
                return Ok(LegEnd::Cut(t, y));
            }
            if forced && mode == Mode::Rock && self.decides(y) {
                return Ok(LegEnd::Decided(t, y));
            }
        }
    }

    /// max |θ| on the step up to `upto` (σ): at its ends, and where the
    /// dense output's θ̇ changes sign inside.
    fn peak_on(&mut self, step: &DenseStep, upto: f64) {
        let mut peak = step.y0[0].abs().max(step.at_sigma(upto)[0].abs());
        if step.y0[1] * step.at_sigma(upto)[1] < 0.0 {
            let (mut a, mut b) = (0.0, upto);
            let sign = step.y0[1].signum();
            for _ in 0..60 {
                let m = 0.5 * (a + b);
                if step.at_sigma(m)[1] * sign > 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            peak = peak.max(step.at_sigma(0.5 * (a + b))[0].abs());
        }
        self.out.peak_theta_over_alpha = self
            .out
            .peak_theta_over_alpha
            .max(peak.min(std::f64::consts::FRAC_PI_2) / self.block.slenderness());
    }

    /// Places an impact (`kind` 0: θ = 0) or overturning (1: |θ| = π/2)
    /// found at `sigma` of `step` on the dense output by Newton corrections
    /// on full Runge–Kutta steps from the step's start, as pure rocking
    /// does: the interpolant is less accurate than the step itself, and an
    /// impact of a small rotation (|θ̇| small) is ill-conditioned in time,
    /// δt ≈ δθ/|θ̇|.
    fn place_on_steps<R: Rhs>(
        &mut self,
        rhs: &R,
        step: &DenseStep,
        sigma: f64,
        kind: u8,
        s: f64,
    ) -> (f64, State) {
        let full = |this: &mut Self, t: f64| {
            let (y, n) = single_step(this.method, rhs, step.t0, step.y0, t - step.t0);
            this.out.stats.rhs_evals += u64::from(n);
            y
        };
        let level = if kind == 0 {
            0.0
        } else {
            std::f64::consts::FRAC_PI_2
        };
        let mut t = step.t0 + sigma * step.h;
        let mut y = full(self, t);
        for _ in 0..3 {
            if y[1] == 0.0 {
                break;
            }
            let dt = -(s * y[0] - level) / (s * y[1]);
            let t_new = (t + dt).clamp(step.t0, step.t1());
            if t_new == t {
                break;
            }
            t = t_new;
            y = full(self, t);
        }
        (t, y)
    }

    /// The first armed sampled event turning positive on the step before
    /// `limit` (σ): (which, σ). The event functions are sampled at
    /// [`SAMPLES`] points of the dense output; where one has turned
    /// positive since the last sample, where it did so between the two is
    /// solved on the dense output ([`turns_positive`]) — to rounding in σ, on the
    /// interpolant of the step's solution (DOP853's is of degree 7, its
    /// error of the order of the integration tolerance, as the impacts'
    /// and overturning's roots found by [`first_nonpositive`]).
    fn sampled<E: Fn(f64, State) -> [f64; 2]>(
        &self,
        step: &DenseStep,
        events: &E,
        armed: &mut [bool; 2],
        limit: f64,
    ) -> Option<(usize, f64)> {
        let at = |sigma: f64| events(step.t0 + sigma * step.h, step.at_sigma(sigma));
        let mut prev = 0.0;
        // The events at `prev`, once evaluated (σ = 0 only where needed).
        let mut e_prev: Option<[f64; 2]> = None;
        for i in 1..=SAMPLES {
            let sigma = (i as f64 / SAMPLES as f64).min(limit);
            let e = at(sigma);
            let mut hit: Option<(usize, f64)> = None;
            for k in 0..2 {
                if armed[k] && e[k] > 0.0 {
                    let ea = e_prev.get_or_insert_with(|| at(prev))[k];
                    let root = turns_positive(|x| at(x)[k], (prev, ea), (sigma, e[k]));
                    if hit.is_none_or(|h| root < h.1) {
                        hit = Some((k, root));
                    }
                }
            }
            if hit.is_some() {
                return hit;
            }
            for k in 0..2 {
                if e[k] < 0.0 {
                    armed[k] = true;
                }
            }
            if sigma >= limit {
                break;
            }
            prev = sigma;
            e_prev = Some(e);
        }
        None
    }
}

/// Where `f`, positive at `b` (`fb` > 0), turns positive after `a`: the
/// root of a sign change (`fa` < 0) by [`brent`]; from a start at 0 or
/// above (a leg's start, where an event function is 0 by construction) by
/// bisection for the first point where it is positive, to rounding.
fn turns_positive<F: Fn(f64) -> f64>(f: F, (a, fa): (f64, f64), (b, fb): (f64, f64)) -> f64 {
    if fa < 0.0 {
        return brent(&f, a, b, fa, fb, 0.0);
    }
    let (mut a, mut b) = (a, b);
    for _ in 0..64 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if f(m) > 0.0 {
            b = m;
        } else {
            a = m;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::sliding::slide;
    use crate::dynamics::{Pulse, PulseShape};

    /// The paper's locomotive.
    fn locomotive() -> Block {
        Block::new(0.25, 2.14, None, None, None).expect("valid")
    }

    fn one_sine(block: &Block, level: f64) -> Pulse {
        let a = level * block.slenderness() * block.gravity();
        Pulse::new(PulseShape::OneSine, a, 3.0 * block.frequency_parameter()).expect("valid")
    }

    fn run(block: &Block, pulse: &Pulse, mu: f64) -> ContactResponse {
        let f = Friction::new(mu, None).expect("valid");
        simulate_contact(block, pulse, f, Method::Dop853, 1e-10, 1e-12).expect("runs")
    }

    #[test]
    fn a_block_that_cannot_rock_slides_as_the_pure_sliding_closed_forms() {
        // μ = 0.2 < tan α: it slides from |ü_g| = μ g, sticks at 1.25 s and
        // 1.47 s, 0.02 m and 0.45 m from where it stood, and stands.
        let b = locomotive();
        for (level, stop, residual) in [(2.0, 1.25, 0.02), (4.0, 1.47, 0.45)] {
            let pulse = one_sine(&b, level);
            let r = run(&b, &pulse, 0.2);
            let alone = slide(
                &pulse,
                b.gravity(),
                Friction::new(0.2, None).expect("valid"),
            );
            assert_eq!(r.initial_mode, Some(Mode::Slide));
            assert!(!r.overturned && r.impacts.is_empty() && r.peak_theta_over_alpha == 0.0);
            let slides: Vec<_> = r.modes.iter().filter(|m| m.mode == Mode::Slide).collect();
            assert_eq!(slides.len(), alone.slides.len(), "{:?}", r.modes);
            for (m, s) in slides.iter().zip(&alone.slides) {
                assert_eq!(
                    (m.from, m.to, m.direction),
                    (s.from, s.to, Some(s.direction))
                );
            }
            assert_eq!(r.residual_slide, alone.residual);
            assert_eq!(r.peak_slide, alone.peak);
            assert!((r.time_sliding - alone.time_sliding).abs() < 1e-12);
            let end = r.rest_time.expect("rests");
            assert!((end - stop).abs() < 0.005, "stops at {end}");
            assert!(
                (r.residual_slide.abs() - residual).abs() < 0.005,
                "{}",
                r.residual_slide
            );
        }
    }

    #[test]
    fn on_mu_0_3_the_locomotive_slides_while_rocking_and_overturns_the_other_way() {
        // Pure rocking: mode 2 towards θ < 0 at 2.39 s, no impact. On μ =
        // 0.3 the pivot slides 0.28 m, which caps the rotation; one impact,
        // and it overturns towards θ > 0 at 2.86 s.
        let b = locomotive();
        let r = run(&b, &one_sine(&b, 4.0), 0.3);
        assert_eq!(r.initial_mode, Some(Mode::Rock));
        assert!(r.overturned);
        assert_eq!(r.overturn_side, Some(1.0));
        assert_eq!(r.impact_count, 1);
        assert_eq!(r.overturn_mode, Some(OverturnMode::AfterImpacts(1)));
        let t = r.overturn_time.expect("overturns");
        assert!((t - 2.86).abs() < 0.005, "{t}");
        let first = r
            .modes
            .iter()
            .position(|m| m.mode == Mode::SlideRock)
            .expect("slide-rocks");
        assert_eq!(r.modes[first + 1].mode, Mode::Rock);
        // Its slip while rocking, before the impact.
        let slip_before_impact = r.modes[first].slip.1;
        assert!(
            (slip_before_impact.abs() - 0.28).abs() < 0.005,
            "{slip_before_impact}"
        );
    }

    #[test]
    fn where_the_pivot_always_holds_the_modes_follow_pure_rocking() {
        // μ = 10 is never reached by these rocking histories: every impact
        // and the rest time agree with the pure-rocking engine to its
        // tolerance, and the chattering tails sum to the same count.
        use crate::dynamics::{Formulation, Options, Problem, Solver, simulate};
        let b = locomotive();
        let g = b.gravity();
        for (shape, level, ratio) in [
            (PulseShape::OneSine, 3.0, 6.0),
            (PulseShape::OneCosine, 2.0, 4.0),
            (PulseShape::Cn(3), 4.0, 5.0),
            // Barely above the threshold: two lifts, each of micro-radians
            // and shorter than a step, each ending in its own impact.
            (PulseShape::OneSine, 1.0001, 3.0),
        ] {
            let pulse =
                Pulse::new(shape, level * b.slenderness().tan() * g, ratio * 2.14).expect("valid");
            let r = run(&b, &pulse, 10.0);
            let solver = Solver::RungeKutta {
                method: Method::Dop853,
                rtol: 1e-10,
                atol: 1e-12,
            };
            let problem = Problem {
                block: b,
                pulse,
                formulation: Formulation::Nonlinear,
            };
            let p = simulate(&problem, &Options::history(solver)).expect("runs");
            assert!(!r.overturned && !p.overturned, "{shape:?}");
            assert_eq!(r.impact_count, p.impact_count, "{shape:?}");
            for (a, q) in r.impacts.iter().zip(&p.impacts) {
                assert!(
                    (a.t - q.time).abs() < 1e-9,
                    "{shape:?}: {} vs {}",
                    a.t,
                    q.time
                );
                assert!((a.theta_dot.1 - q.velocity_after).abs() < 1e-9);
                assert!(a.sticking);
            }
            let (x, y) = (r.rest_time.expect("rests"), p.rest_time.expect("rests"));
            assert!((x - y).abs() < 1e-8, "{shape:?}: {x} vs {y}");
            assert!((r.peak_theta_over_alpha - p.peak_theta_over_alpha).abs() < 1e-9);
            assert_eq!(r.peak_slide, 0.0);
            assert_eq!(r.initial_mode, Some(Mode::Rock));
        }
    }

    #[test]
    fn every_slip_runs_the_way_its_friction_opposes() {
        // Friction does no positive work: over each stretch of slide or
        // slide-rock the base slips the way the stretch says. A slip that
        // turns back within a step once ran on with the friction the wrong
        // way (the locomotive at 1.76 αg, ω_p/p = 10, overturned after
        // slipping 2.9 m on a floor at rest).
        let b = locomotive();
        let g = b.gravity();
        for (shape, ratio) in [
            (PulseShape::OneSine, 10.0),
            (PulseShape::OneSine, 3.0),
            (PulseShape::OneCosine, 6.0),
        ] {
            for i in 0..=60 {
                let level = 1.05 + 0.025 * f64::from(i);
                let pulse =
                    Pulse::new(shape, level * b.slenderness() * g, ratio * 2.14).expect("valid");
                let r = run(&b, &pulse, 0.3);
                for m in &r.modes {
                    if let Some(d) = m.direction {
                        assert!(
                            (m.slip.1 - m.slip.0) * d >= -1e-12,
                            "{shape:?} ω_p/p {ratio}, {level} αg: {m:?}"
                        );
                    }
                }
                if shape == PulseShape::OneSine && ratio == 10.0 {
                    assert!(r.peak_slide < 0.05, "{level} αg: {}", r.peak_slide);
                }
            }
        }
    }

    #[test]
    fn a_block_the_ground_drops_under_flies_and_lands_where_its_parabola_says() {
        // A rectangular vertical pulse of −1.5 g for 0.2 s: g + ü_v < 0 at
        // once, so the block at rest leaves the floor flat at t = 0, rises
        // with 0.5 g, falls with g after the pulse and lands flat at
        // t_d + τ₁ + √(τ₁² + 2 h₁/g); its fall is stopped and it sticks.
        use crate::dynamics::PulsePair;
        let b = Block::new(0.25, 2.0, None, None, None).expect("valid");
        let g = b.gravity();
        let t_d = 0.2;
        let w = std::f64::consts::PI / t_d;
        let pair = PulsePair::new(
            Pulse::new(PulseShape::Rectangular, 1e-9, w).expect("valid"),
            Pulse::new(PulseShape::Rectangular, -1.5 * g, w).expect("valid"),
            0.0,
        );
        let f = Friction::new(0.5, None).expect("valid");
        let r = simulate_contact(&b, &pair, f, Method::Dop853, 1e-10, 1e-12).expect("runs");
        let (v1, h1) = (0.5 * g * t_d, 0.25 * g * t_d * t_d);
        let tau = v1 / g;
        let landing = t_d + tau + (tau * tau + 2.0 * h1 / g).sqrt();
        assert_eq!(r.initial_mode, Some(Mode::Flight));
        assert_eq!((r.flights, r.first_flight), (1, Some(0.0)));
        let modes: Vec<Mode> = r.modes.iter().map(|m| m.mode).collect();
        // (It lands after the ground has stopped: at rest from there.)
        assert_eq!(modes, [Mode::Flight], "{:?}", r.modes);
        assert_eq!(r.rest_time, Some(r.modes[0].to));
        assert!(
            (r.modes[0].to - landing).abs() < 1e-12,
            "{} vs {landing}",
            r.modes[0].to
        );
        assert!((r.time_in_flight - landing).abs() < 1e-12);
        assert_eq!(r.impact_count, 1);
        assert!(r.impacts[0].sticking && !r.overturned);
        assert!(r.residual_slide.abs() < 1e-9 && r.peak_theta_over_alpha == 0.0);
    }

    #[test]
    fn a_squat_block_spun_off_its_corner_flies_and_overturns_in_the_air() {
        // α = 0.4 on μ = 0.6 (μ_k = 0.5) under a one-cosine pulse of 3.2 g
        // at ω_p = 2p: it slide-rocks, strikes sliding, and the normal
        // force under its new pivot is negative at once: it takes off at
        // 1.1986 s, turns through π/2 in the air at 1.7964 s (as the SciPy
        // model of bench/contact_scipy.py, case 45, finds to 1e-12 s).
        let b = Block::new(0.4, 2.14, None, None, None).expect("valid");
        let pulse =
            Pulse::new(PulseShape::OneCosine, 3.2 * b.gravity(), 2.0 * 2.14).expect("valid");
        let f = Friction::new(0.6, Some(0.5)).expect("valid");
        let r = simulate_contact(&b, &pulse, f, Method::Dop853, 1e-10, 1e-12).expect("runs");
        let last = r.modes.last().expect("modes");
        assert_eq!(last.mode, Mode::Flight);
        assert!(r.overturned && r.flights == 1);
        assert_eq!(r.overturn_time, Some(last.to));
        let take_off = r.first_flight.expect("flies");
        assert!((take_off - 1.1986).abs() < 1e-4, "{take_off}");
        assert!((last.to - 1.7964).abs() < 1e-4, "{}", last.to);
        assert!((r.time_in_flight - (last.to - last.from)).abs() < 1e-15);
    }

    #[test]
    fn a_demand_jumping_past_mu_at_the_pulse_end_slips_the_way_the_free_motion_goes() {
        // α = 0.2, μ = 0.7, one-cosine at 2 tan α g, ω_p = 1.5 p: rocking
        // needs 0.51 μ-units just before the pulse ends and more than μ
        // just after. The pivot slips from the end on, the way the free
        // motion takes it, until the block overturns (2.2799 s, as the SciPy
        // model finds); this once alternated rock and slide-rock there
        // without end.
        let b = Block::new(0.2, 2.0, None, None, None).expect("valid");
        let g = b.gravity();
        let pulse = Pulse::new(PulseShape::OneCosine, 2.0 * 0.2f64.tan() * g, 3.0).expect("valid");
        let r = run(&b, &pulse, 0.7);
        let modes: Vec<(Mode, Option<f64>)> =
            r.modes.iter().map(|m| (m.mode, m.direction)).collect();
        assert_eq!(modes, [(Mode::Rock, None), (Mode::SlideRock, Some(1.0))]);
        assert!((r.modes[1].from - pulse.duration).abs() < 1e-12);
        assert!(r.overturned);
        let t = r.overturn_time.expect("overturns");
        assert!((t - 2.2799).abs() < 1e-4, "{t}");
    }

    #[test]
    fn no_impact_gains_energy_and_a_holding_corner_gives_housners_eta() {
        for alpha in [0.1, 0.25, 0.45] {
            let b = Block::new(alpha, 2.0, None, None, None).expect("valid");
            for mu in [0.05, 0.2, 0.5, 1.0] {
                for side in [1.0, -1.0] {
                    for w in [0.01, 0.5, 3.0] {
                        for slip in [-2.0, -0.3, 0.0, 0.3, 2.0] {
                            let theta_dot = -side * w;
                            let hit = slide_rock::impact(&b, mu, 0.8 * mu, side, theta_dot, slip);
                            let (before, after) = hit.energy;
                            assert!(
                                after <= before * (1.0 + 1e-12),
                                "α {alpha} μ {mu} s {side} θ̇ {theta_dot} slip {slip}: {before} → {after}"
                            );
                            if hit.sticking {
                                assert_eq!(hit.slip_velocity, 0.0);
                            } else {
                                // The landing corner slides on the way its
                                // impulse could not stop.
                                assert!(hit.slip_velocity != 0.0);
                            }
                            if slip == 0.0 && mu >= 1.0 {
                                assert!(hit.sticking, "α {alpha} θ̇ {theta_dot}");
                                assert!(
                                    (hit.theta_dot - b.restitution() * theta_dot).abs()
                                        < 1e-15 * w.max(1.0)
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
