//! What one simulation reports.

/// One impact (eqs. 13–15): θ = 0 with θ̇ multiplied by η.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// Time of impact, s (from the start of the ground motion).
    pub time: f64,
    /// θ̇ just before, rad/s.
    pub velocity_before: f64,
    /// θ̇ just after (η × before), rad/s.
    pub velocity_after: f64,
}

/// How the block overturned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverturnMode {
    /// Mode 1: after one or more impacts.
    AfterImpacts(u64),
    /// Mode 2: without any impact.
    WithoutImpact,
}

impl OverturnMode {
    /// The paper's mode number.
    pub fn number(self) -> u8 {
        match self {
            OverturnMode::AfterImpacts(_) => 1,
            OverturnMode::WithoutImpact => 2,
        }
    }
}

/// Friction needed for pure rocking along the history.
///
/// The demand is |f_x/f_z| of the rocking block (eq. 20; eqs. 16–19 for the
/// linear formulation) and |ü_g|/g while the block rests on the base. The
/// instant rocking starts belongs to the rocking motion: its demand is eq. 7
/// (eq. 51 for one-cosine), never the at-rest |ü_g|/g.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionDemand {
    /// max |f_x/f_z| over the motion (the minimum μ for pure rocking); `None`
    /// when f_z reached 0 (lift-off): no μ sustains pure rocking, the demand is
    /// unbounded.
    pub peak: Option<f64>,
    /// When the peak occurs, s (`None` with `peak`).
    pub peak_time: Option<f64>,
    /// Demand at the first rocking start (eq. 7; eq. 51 for one-cosine).
    pub initiation: Option<f64>,
    /// First time |f_x/f_z| exceeds the given μ (the block would slide).
    pub first_sliding: Option<f64>,
    /// First time f_z ≤ 0 (the block would lift off): the demand is unbounded.
    pub first_lift_off: Option<f64>,
    /// The demand was followed up to this time only: the block was then
    /// bound to overturn (the pulse was over, or under a record the free
    /// motion from there on overturned, and the block did), so its fall is
    /// not counted.
    pub followed_until: Option<f64>,
}

/// Sampled histories at uniform times.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Time, s.
    pub t: Vec<f64>,
    /// Rotation θ, rad.
    pub theta: Vec<f64>,
    /// Angular velocity θ̇, rad/s.
    pub theta_dot: Vec<f64>,
    /// Ground acceleration ü_g, m/s².
    pub ground_acceleration: Vec<f64>,
    /// Vertical ground acceleration ü_v (positive up), m/s²: present under a
    /// vertical ground motion only.
    pub vertical_acceleration: Option<Vec<f64>>,
    /// f_x/f_z (present when reactions are asked for); `None` at samples
    /// where pure rocking is impossible (from the first lift-off on).
    pub reaction_ratio: Option<Vec<Option<f64>>>,
}

/// Something the caller should know about the result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Warning {
    /// |f_x/f_z| first exceeds μ at this time: pure rocking is violated (sliding).
    Sliding(f64),
    /// f_z ≤ 0 first at this time: the block would lift off.
    LiftOff(f64),
    /// g + ü_v ≤ 0 first at this time: the ground falls away faster than
    /// gravity pulls the block, which leaves it; the simulation ends there.
    GroundFallsAway(f64),
    /// The friction demand was followed up to this time (the pulse end): the
    /// block was then bound to overturn, and its fall is not counted.
    DemandExcludesFall(f64),
    /// The friction demand was followed up to this time, the ground still
    /// moving: from then on the free motion from every state overturned, and
    /// the block overturned; its fall is not counted.
    DemandExcludesForcedFall(f64),
    /// Free rocking after the pulse was followed only up to this many impacts.
    FreeRockingTruncated(u64),
    /// The impact list was truncated to this many entries (the count is complete).
    ImpactListTruncated(usize),
    /// A bound on one history's work was reached at this time: the history
    /// ends there, its outcome past it not followed.
    LimitReached(Limit, f64),
    /// Integrating the free motion disagreed with the exact separatrix decision
    /// (the state is within the integration tolerance of the separatrix).
    NearSeparatrix,
}

/// The most impacts one history follows one by one (those summed in closed
/// form aside): where they are reached it ends there, cut short
/// ([`Limit::Impacts`]), on any floor.
pub const MAX_IMPACTS: u64 = 100_000;

/// The most integration steps of one history ([`Limit::Steps`]).
pub const MAX_STEPS: u64 = 2_000_000;

impl Response {
    /// Whether the history reached a bound on its work before its outcome
    /// was decided ([`Warning::LimitReached`]): undecided past there.
    pub fn reached_limit(&self) -> bool {
        self.warnings
            .iter()
            .any(|w| matches!(w, Warning::LimitReached(..)))
    }
}

/// A bound on the work of one history ([`Warning::LimitReached`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Limit {
    /// Impacts followed one by one (those summed in closed form aside).
    Impacts(u64),
    /// Integration steps.
    Steps(u64),
    /// Time of free motion after the ground motion's end, s.
    FreeTime(f64),
}

impl Limit {
    /// The limit's name in reports.
    pub fn name(&self) -> &'static str {
        match self {
            Limit::Impacts(_) => "impacts",
            Limit::Steps(_) => "steps",
            Limit::FreeTime(_) => "free_time",
        }
    }
}

/// Cost and accuracy of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Numerics {
    /// "exact", "dopri5" or "dop853".
    pub method: &'static str,
    /// Relative tolerance (RK only).
    pub rtol: Option<f64>,
    /// Absolute tolerance (RK only).
    pub atol: Option<f64>,
    /// Accepted steps (RK) or closed-form segments (exact).
    pub steps_accepted: u64,
    /// Rejected steps.
    pub steps_rejected: u64,
    /// Right-hand-side evaluations (closed-form evaluations for exact).
    pub rhs_evaluations: u64,
    /// Events located: rocking starts, impacts, pulse end, overturning.
    pub events: u64,
    /// Estimated error in θ, rad: the sum of local error estimates (RK) or the
    /// rounding amplification of the closed form (exact).
    pub error_estimate: f64,
    /// Wall time of the computation, s.
    pub wall_time: f64,
}

/// The response of one block to one pulse.
#[derive(Clone, Debug, PartialEq)]
pub struct Response {
    /// Whether the ground ever exceeded the rocking threshold.
    pub rocked: bool,
    /// First rocking start, s.
    pub rocking_start: Option<f64>,
    /// Number of times rocking started (restarts after coming to rest count).
    pub rocking_starts: u32,
    /// Whether the block overturned.
    pub overturned: bool,
    /// Overturning mode.
    pub mode: Option<OverturnMode>,
    /// Impacts that happened (or, when stopped at the decision, are certain to
    /// happen) before the end of the simulation.
    pub impact_count: u64,
    /// The impacts, when asked for (possibly truncated, see warnings).
    pub impacts: Vec<Impact>,
    /// Impacts with |θ̇| before of at least [`ROCKING_IMPACT_VELOCITY`]·p α:
    /// the rocking cycles, without the chattering that ends them.
    ///
    /// [`ROCKING_IMPACT_VELOCITY`]: super::simulate::ROCKING_IMPACT_VELOCITY
    pub rocking_impacts: u64,
    /// Impacts of chattering tails summed in closed form: counted in
    /// `impact_count`, not listed (see [`chatter`](super::chatter)).
    pub summed_impacts: u64,
    /// Time |θ| reaches π/2, when followed to the end.
    pub overturn_time: Option<f64>,
    /// The side it overturns to, the sign of θ (+1: about the corner at +x).
    pub overturn_side: Option<f64>,
    /// Time the block came to rest for good, when it did.
    pub rest_time: Option<f64>,
    /// Time at which the outcome became certain (the pulse end at the latest).
    pub decided_at: f64,
    /// End of the simulated interval, s.
    pub end_time: f64,
    /// max |θ| / α over the simulated interval.
    pub peak_theta_over_alpha: f64,
    /// Friction demand, when asked for.
    pub friction: Option<FrictionDemand>,
    /// When the vertical ground acceleration reached −g (g + ü_v ≤ 0): the
    /// block left the ground there and the simulation ended, with no
    /// verdict on overturning (`overturned` is false, `mode` none).
    pub lift_off: Option<f64>,
    /// Sampled series, when asked for.
    pub series: Option<Series>,
    /// Notes on the result.
    pub warnings: Vec<Warning>,
    /// Cost and accuracy.
    pub numerics: Numerics,
}
