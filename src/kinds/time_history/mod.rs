//! The `time_history` job: one block, one ground motion (a pulse or a sampled
//! record), one response.

pub mod figure;
pub mod motion;
pub mod table;

use serde::{Deserialize, Serialize};

use crate::dynamics::PulsePair;
use crate::dynamics::response::{Limit, Response, Warning};
use crate::dynamics::sliding::Kinematics;
use crate::dynamics::{Formulation, Options, Problem, SimError, simulate};
use crate::jobs::contact::{
    ContactDoc, ContactNorm, ContactSpec, ModeDoc, run_coulomb, validate_contact,
};
use crate::jobs::names::{EngineDoc, tag};
use crate::jobs::numerics::NumericsDoc;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, GroundMotionNorm, GroundMotionSpec, PulseNorm, PulseSpec, SolverNorm,
    SolverSpec, SpecError, parse_formulation, validate_pulse,
};
use crate::jobs::vertical::{
    VerticalPulseNorm, VerticalPulseSpec, validate_record_with_vertical, validate_vertical_pulse,
};
pub use crate::jobs::warning::WarningDoc;

/// Largest series accepted.
pub const MAX_SERIES_POINTS: usize = 1_000_000;

/// What to compute and keep beyond the outcome.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputsSpec {
    /// Number of uniformly spaced samples of (t, θ, θ̇, ü_g, f_x/f_z, and ü_v under a vertical ground motion); none by default (at most 1e6).
    #[schema(maximum = 1_000_000)]
    pub series: Option<usize>,
    /// Follow the base reactions (peak friction demand, warnings); default true.
    pub reactions: Option<bool>,
    /// List the impacts (default true; the count is always given).
    pub impacts: Option<bool>,
    /// Follow free rocking after the pulse for at most this many impacts (default 1000).
    pub max_free_impacts: Option<u64>,
    /// Stop the simulation at this time, s (free rocking only).
    #[schema(exclusive_minimum = 0.0)]
    pub duration: Option<f64>,
}

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct TimeHistorySpec {
    /// "time_history".
    #[schema(value_type = crate::jobs::names::tag::TimeHistory)]
    pub kind: String,
    /// The block.
    #[schema(required = true, value_type = BlockSpec)]
    pub block: Option<BlockSpec>,
    /// The pulse (give this or `ground_motion`).
    pub pulse: Option<PulseSpec>,
    /// With `pulse`: the vertical ground acceleration (positive up),
    /// `{"ratio": r}` (ü_v = r·ü_g) or a pulse of its own (with `delay_s`).
    /// A record takes its own in `ground_motion.vertical`.
    pub vertical: Option<VerticalPulseSpec>,
    /// A sampled ground-acceleration record (give this or `pulse`).
    pub ground_motion: Option<GroundMotionSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// Solver (default: exact for the linear formulation of a sinusoidal pulse
    /// or a record, dop853 otherwise).
    pub solver: Option<SolverSpec>,
    /// Extra outputs.
    pub outputs: Option<OutputsSpec>,
    /// The contact with the floor: `{"model": "no_sliding"}` (pure rocking,
    /// the default) or `{"model": "coulomb", "mu": μ, "mu_kinetic": μ_k}`
    /// (the block sticks, slides, rocks, slide-rocks).
    pub contact: Option<ContactSpec>,
}

/// Outputs, normalised.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct OutputsNorm {
    /// Series samples (0: none).
    pub series: usize,
    /// Follow reactions.
    pub reactions: bool,
    /// List impacts.
    pub impacts: bool,
    /// Free-rocking impact limit.
    pub max_free_impacts: u64,
    /// End time, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
}

/// A validated time-history job; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct TimeHistoryJob {
    /// "time_history".
    pub kind: tag::TimeHistory,
    /// Block.
    pub block: BlockNorm,
    /// Pulse (when the ground motion is a pulse).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulse: Option<PulseNorm>,
    /// The vertical motion beside the pulse (when there is one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::vertical::VerticalPulseDoc>)]
    pub vertical: Option<VerticalPulseNorm>,
    /// Record (when the ground motion is a record).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_motion: Option<GroundMotionNorm>,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// Solver.
    pub solver: SolverNorm,
    /// Outputs.
    pub outputs: OutputsNorm,
    /// Coulomb friction (absent: pure rocking).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactNorm>,
}

impl crate::jobs::kind::Validate for TimeHistorySpec {
    type Job = TimeHistoryJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<TimeHistoryJob, SpecError> {
        let block = crate::jobs::spec::the_block(self.block.as_ref())?;
        let (pulse, ground_motion) = match (&self.pulse, &self.ground_motion) {
            (Some(p), None) => (Some(validate_pulse(p, &block, "/pulse")?.0), None),
            (None, Some(g)) => (
                None,
                Some(validate_record_with_vertical(g, &block, "/ground_motion")?),
            ),
            (None, None) => {
                return Err(SpecError::at(
                    "/pulse",
                    "missing field: give pulse or ground_motion",
                ));
            }
            (Some(_), Some(_)) => {
                return Err(SpecError::at(
                    "/ground_motion",
                    "give either pulse or ground_motion, not both",
                ));
            }
        };
        let vertical = match (&self.vertical, &pulse) {
            (Some(v), Some(_)) => validate_vertical_pulse(v, &block, "/vertical")?,
            (Some(_), None) => {
                return Err(SpecError::at(
                    "/vertical",
                    "goes with a pulse: a record takes its vertical acceleration in ground_motion.vertical",
                ));
            }
            (None, _) => None,
        };
        let with_vertical =
            vertical.is_some() || ground_motion.as_ref().is_some_and(|g| g.vertical.is_some());
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        // The closed form covers the sinusoidal pulses and every record
        // (linear between samples); a wavelet has none, nor any motion with
        // a vertical component.
        let closed_form = pulse.as_ref().is_none_or(|p| p.shape.is_sinusoidal());
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            closed_form,
            with_vertical,
            "/solver",
        )?;
        let contact = validate_contact(self.contact.as_ref(), formulation, "/contact")?;
        let out = self.outputs.clone().unwrap_or_default();
        let series = out.series.unwrap_or(0);
        if contact.is_some() && out.duration.is_some() {
            return Err(SpecError::at(
                "/outputs/duration",
                "under the coulomb contact model the history is followed to rest, overturning or lift-off",
            ));
        }
        if series > MAX_SERIES_POINTS {
            return Err(SpecError::at(
                "/outputs/series",
                format!("at most {MAX_SERIES_POINTS} points"),
            ));
        }
        if let Some(d) = out.duration
            && !(d.is_finite() && d > 0.0)
        {
            return Err(SpecError::at(
                "/outputs/duration",
                "must be positive and finite (s)",
            ));
        }
        Ok(TimeHistoryJob {
            kind: tag::TimeHistory,
            block,
            pulse,
            vertical,
            ground_motion,
            formulation,
            solver,
            outputs: OutputsNorm {
                series,
                reactions: out.reactions.unwrap_or(true),
                impacts: out.impacts.unwrap_or(true),
                max_free_impacts: out.max_free_impacts.unwrap_or(1_000),
                duration: out.duration,
            },
            contact,
        })
    }
}

/// One impact in a result.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ImpactDoc {
    /// Time, s.
    pub t: f64,
    /// θ̇ before, rad/s.
    pub theta_dot_before: f64,
    /// θ̇ after, rad/s.
    pub theta_dot_after: f64,
}

/// The peaks of a ground motion from rest, over its duration (a pulse: from
/// its closed-form integrals; a record: exactly, linear between samples).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct GroundPeaksDoc {
    /// Peak ground acceleration, m/s².
    pub pga_m_s2: f64,
    /// Peak ground acceleration, g.
    pub pga_g: f64,
    /// Peak ground velocity, m/s.
    pub pgv_m_s: f64,
    /// Peak ground displacement, m.
    pub pgd_m: f64,
    /// PGV/PGA, s (the pulse's duration scale, independent of its amplitude).
    pub pgv_over_pga_s: f64,
    /// Peak vertical ground acceleration, m/s² (with a vertical motion).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pga_v_m_s2: Option<f64>,
    /// Peak vertical ground acceleration, g (with a vertical motion).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pga_v_g: Option<f64>,
}

impl GroundPeaksDoc {
    /// From the peaks and gravity `g`, m/s².
    pub fn new(p: &crate::dynamics::peaks::GroundPeaks, g: f64) -> Self {
        GroundPeaksDoc {
            pga_m_s2: p.pga,
            pga_g: p.pga / g,
            pgv_m_s: p.pgv,
            pgd_m: p.pgd,
            pgv_over_pga_s: if p.pga > 0.0 { p.pgv / p.pga } else { 0.0 },
            pga_v_m_s2: None,
            pga_v_g: None,
        }
    }

    /// With the vertical peak acceleration `pga_v`, m/s².
    pub fn with_vertical(self, pga_v: Option<f64>, g: f64) -> Self {
        GroundPeaksDoc {
            pga_v_m_s2: pga_v,
            pga_v_g: pga_v.map(|a| a / g),
            ..self
        }
    }
}

impl WarningDoc {
    fn from(w: &Warning) -> Self {
        let (kind, t, message) = match *w {
            Warning::Sliding(t) => (
                "sliding",
                Some(t),
                format!("|f_x/f_z| exceeds mu at t = {t:.6} s: pure rocking is violated (the block would slide); contact {{\"model\": \"coulomb\", \"mu\": mu}} follows the block as it slides"),
            ),
            Warning::LiftOff(t) => (
                "lift_off",
                Some(t),
                format!("f_z <= 0 at t = {t:.6} s: the block would lift off the base; no friction coefficient sustains pure rocking (peak_friction_demand is null: unbounded)"),
            ),
            Warning::GroundFallsAway(t) => (
                "lift_off",
                Some(t),
                format!("g + vertical ground acceleration <= 0 at t = {t:.6} s: the ground falls away faster than gravity pulls the block, which leaves the base; the simulation ends there, without a verdict on overturning (overturned is false, mode null)"),
            ),
            Warning::DemandExcludesFall(t) => (
                "demand_excludes_fall",
                Some(t),
                format!("the friction demand is followed up to t = {t:.6} s, the pulse end: the block was then bound to overturn, and its fall is not counted"),
            ),
            Warning::DemandExcludesForcedFall(t) => (
                "demand_excludes_fall",
                Some(t),
                format!("the friction demand is followed up to t = {t:.6} s: from then on the block, the ground still moving, was bound to overturn (the free motion from every state overturns) and overturned; its fall is not counted"),
            ),
            Warning::FreeRockingTruncated(n) => (
                "free_rocking_truncated",
                None,
                format!("free rocking after the ground motion followed for {n} impacts only (outputs.max_free_impacts); overturned is then the outcome decided in closed form from there where the free motion is pure rocking (overturn_time and rest_time null), else the outcome up to there"),
            ),
            Warning::ImpactListTruncated(n) => (
                "impact_list_truncated",
                None,
                format!("impact list truncated to {n} entries; impact_count is complete"),
            ),
            Warning::LimitReached(limit, t) => (
                "limit_reached",
                Some(t),
                format!(
                    "the history reached its bound on {} at t = {t:.6} s and ends there: {}; its outcome past it is not followed (overturned: false means not overturned by then)",
                    match limit {
                        Limit::Impacts(_) => "impacts",
                        Limit::Steps(_) => "integration steps",
                        Limit::FreeTime(_) => "free motion",
                    },
                    match limit {
                        Limit::Impacts(n) => format!("{n} impacts followed one by one, none of them ending in rest"),
                        Limit::Steps(n) => format!("{n} integration steps"),
                        Limit::FreeTime(s) => format!("the motion after the ground motion followed for {s:.6} s without rest or overturning"),
                    }
                ),
            ),
            Warning::NearSeparatrix => (
                "near_separatrix",
                None,
                "the state at the pulse end lies within integration tolerance of the separatrix; the outcome is the exact free-vibration decision".to_string(),
            ),
        };
        WarningDoc {
            kind: kind.to_string(),
            t,
            message,
        }
    }
}

/// Sampled series.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SeriesDoc {
    /// Time, s.
    pub t: Vec<f64>,
    /// θ, rad.
    pub theta: Vec<f64>,
    /// θ̇, rad/s.
    pub theta_dot: Vec<f64>,
    /// ü_g, m/s².
    pub ground_acceleration: Vec<f64>,
    /// ü_v (positive up), m/s²: under a vertical ground motion only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground_vertical_acceleration: Option<Vec<f64>>,
    /// f_x/f_z; null where pure rocking is impossible (f_z ≤ 0, from the
    /// first lift-off on).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fx_over_fz: Option<Vec<Option<f64>>>,
    /// On a Coulomb floor: the base's slip on the floor, m (+ towards +x).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slide_m: Option<Vec<f64>>,
    /// On a Coulomb floor: the mode at each time ("stick" | "slide" |
    /// "rock" | "slide_rock"; θ is 0 while flat, and while a chattering tail
    /// summed in closed form settles).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mode: Option<Vec<String>>,
}

/// The result document of a time-history job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct TimeHistoryResult {
    /// "time_history".
    pub kind: tag::TimeHistory,
    /// Whether rocking started at all.
    pub rocked: bool,
    /// First rocking start, s.
    #[schema(required = true)]
    pub rocking_start: Option<f64>,
    /// Number of rocking starts (restarts after rest included).
    pub rocking_starts: u32,
    /// Whether the block overturned.
    pub overturned: bool,
    /// 1 (after ≥ 1 impact), 2 (no impact) or null.
    #[schema(required = true)]
    pub mode: Option<u8>,
    /// Number of impacts.
    pub impact_count: u64,
    /// Impacts of chattering tails, summed in closed form: counted in
    /// `impact_count`, not listed.
    pub chatter_impacts_summed: u64,
    /// The impacts (when `outputs.impacts`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impacts: Option<Vec<ImpactDoc>>,
    /// Time |θ| reached π/2, s.
    #[schema(required = true)]
    pub overturn_time: Option<f64>,
    /// Time the block came to rest for good, s.
    #[schema(required = true)]
    pub rest_time: Option<f64>,
    /// Time the outcome became certain, s.
    pub decided_at: f64,
    /// End of the simulated interval, s.
    pub end_time: f64,
    /// max |θ|/α.
    pub peak_theta_over_alpha: f64,
    /// max |f_x/f_z| while rocking (minimum μ for pure rocking), when reactions
    /// are followed; null when the block lifts off (`lift_off`): no μ sustains
    /// pure rocking there, the demand is unbounded. Under the coulomb contact
    /// model: pure rocking's demand where pure rocking answered (it stayed
    /// within μ), null where the block slid (the floor's friction then acts
    /// at its limit, μ_k).
    #[schema(required = true)]
    pub peak_friction_demand: Option<f64>,
    /// Time of that peak, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_friction_demand_time: Option<f64>,
    /// Whether f_z reached 0 (the block would lift off; the friction demand is
    /// unbounded). Present when reactions are followed, and whenever a
    /// vertical ground acceleration reached −g (g + ü_v ≤ 0: the block left
    /// the ground and the simulation ended there, `overturned` false and
    /// `mode` null without a verdict; warning `lift_off`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lift_off: Option<bool>,
    /// First time f_z ≤ 0, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lift_off_time: Option<f64>,
    /// The demand was followed up to this time (the pulse end) only: the block
    /// was then bound to overturn, and its fall is not counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_demand_followed_until: Option<f64>,
    /// f_x/f_z when rocking starts (eq. 7 / 51).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub initiation_friction_demand: Option<f64>,
    /// The ground motion's peak acceleration, velocity and displacement.
    pub ground_peaks: GroundPeaksDoc,
    /// Notes.
    pub warnings: Vec<WarningDoc>,
    /// Series (when asked for).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub series: Option<SeriesDoc>,
    /// Cost and accuracy.
    pub numerics: NumericsDoc,
    /// The side it overturned to: +1 rotating about the corner at +x
    /// (θ > 0), −1 the other (present when it overturned).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overturn_direction: Option<f64>,
    /// Under the coulomb contact model: "coulomb".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_model: Option<String>,
    /// Coulomb: "pure_rocking" when the friction pure rocking needs never
    /// exceeded μ (the answer is pure rocking's, to the bit), "modes"
    /// otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub answered_by: Option<String>,
    /// Coulomb: the mode the block first left rest in ("rock" | "slide" |
    /// "slide_rock" | "flight"; absent: it never moved).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_mode: Option<String>,
    /// Coulomb: the modes in time order (stretches of one mode merged,
    /// rocking ones across impacts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modes: Option<Vec<ModeDoc>>,
    /// Coulomb: max |slip| of the base on the floor, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_slide_m: Option<f64>,
    /// Coulomb: the base's slip at the end, m (+ towards +x).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub residual_slide_m: Option<f64>,
    /// Coulomb: time spent sliding or slide-rocking, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_sliding_s: Option<f64>,
    /// Coulomb: times the block left the floor (where the floor would have
    /// had to pull it: the normal force fell to 0, or g + ü_v ≤ 0); each
    /// flight ends in a landing, counted among the impacts, or in
    /// overturning in the air.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flights: Option<u64>,
    /// Coulomb: time spent in the air, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_in_flight_s: Option<f64>,
    /// The normalised spec that was run.
    pub spec: TimeHistoryJob,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(TimeHistoryResult);

impl TimeHistoryJob {
    /// Runs the job.
    pub fn run(&self) -> Result<TimeHistoryResult, SimError> {
        let block = self.block.block()?;
        let formulation = self.formulation;
        let options = Options {
            solver: self.solver.solver(),
            reactions: self.outputs.reactions,
            peak: true,
            series_points: (self.outputs.series > 0).then_some(self.outputs.series),
            series_at: None,
            record_impacts: self.outputs.impacts,
            stop_at_decision: false,
            stop_at_sliding: false,
            max_free_impacts: self.outputs.max_free_impacts,
            horizon: self.outputs.duration,
            initial_state: None,
            // A record mostly lasts past an overturning: the fall under it
            // is left out as the fall after a pulse's end is.
            fall_under_forcing: self.ground_motion.is_some(),
        };
        let mut pga_v = None;
        let (r, peaks) = match (&self.pulse, &self.ground_motion) {
            (Some(p), _) => {
                let pulse = crate::dynamics::Pulse::new(p.shape, p.a_p, p.omega_p)
                    .map_err(|_| SimError::Tolerance)?;
                let peaks = crate::dynamics::peaks::of_pulse(&pulse);
                if let Some(v) = &self.vertical {
                    let pair = match *v {
                        VerticalPulseNorm::Ratio(r) => PulsePair::proportional(pulse, r),
                        VerticalPulseNorm::Pulse { pulse: q, delay_s } => {
                            crate::dynamics::Pulse::new(q.shape, q.a_p, q.omega_p)
                                .ok()
                                .map(|v| PulsePair::new(pulse, v, delay_s))
                        }
                        VerticalPulseNorm::Scaled(v) => v.pair(pulse).ok(),
                    }
                    .ok_or(SimError::Tolerance)?;
                    pga_v = Some(pair.vertical.amplitude.abs());
                    let problem = Problem {
                        block,
                        pulse: pair,
                        formulation,
                    };
                    (self.respond(&problem, &options)?, peaks)
                } else {
                    let problem = Problem {
                        block,
                        pulse,
                        formulation,
                    };
                    (self.respond(&problem, &options)?, peaks)
                }
            }
            (None, Some(g)) if g.vertical.is_some() => {
                let pair = g.pair().and_then(Result::ok).ok_or(SimError::Tolerance)?;
                let peaks = crate::dynamics::peaks::of_record(&pair.horizontal);
                pga_v = Some(
                    pair.vertical
                        .samples()
                        .iter()
                        .fold(0.0f64, |m, a| m.max(a.abs())),
                );
                let problem = Problem {
                    block,
                    pulse: pair,
                    formulation,
                };
                (self.respond(&problem, &options)?, peaks)
            }
            (None, Some(g)) => {
                let record = g.record().map_err(|_| SimError::Tolerance)?;
                let peaks = crate::dynamics::peaks::of_record(&record);
                let problem = Problem {
                    block,
                    pulse: record,
                    formulation,
                };
                (self.respond(&problem, &options)?, peaks)
            }
            (None, None) => return Err(SimError::Tolerance),
        };
        let g = self.block.g;
        let (r, contact) = r;
        let mut doc = self.document(r, GroundPeaksDoc::new(&peaks, g).with_vertical(pga_v, g));
        if let Some(c) = contact {
            self.add_contact(&mut doc, c);
        }
        Ok(doc)
    }

    /// `doc` with what the Coulomb floor `c` adds: the contact model, who
    /// answered, the modes and slides, the flights, the slip and mode series;
    /// and, under a record that never reaches the rocking threshold, the
    /// `never_rocks` warning, which says whether the block slid (known only
    /// from the history, where pure rocking warns from the spec alone).
    fn add_contact(&self, doc: &mut TimeHistoryResult, c: ContactDoc) {
        doc.contact_model = Some(c.contact_model);
        doc.answered_by = Some(c.answered_by);
        doc.initial_mode = c.initial_mode;
        doc.modes = Some(c.modes);
        doc.peak_slide_m = Some(c.peak_slide_m);
        doc.residual_slide_m = Some(c.residual_slide_m);
        doc.time_sliding_s = Some(c.time_sliding_s);
        doc.flights = Some(c.flights);
        doc.time_in_flight_s = Some(c.time_in_flight_s);
        if let (Some(series), Some((slide, mode))) = (doc.series.as_mut(), c.series) {
            series.slide_m = Some(slide);
            series.mode = Some(mode);
        }
        if let Some(m) = self.ground_motion.as_ref().filter(|m| m.vertical.is_none()) {
            doc.warnings
                .extend(crate::jobs::plausible::never_rocks_warning(
                    m,
                    &self.block,
                    self.formulation == Formulation::Linear,
                    Some((c.peak_slide_m, c.residual_slide_m)),
                ));
        }
    }

    /// One history: pure rocking, or on the Coulomb floor of the spec.
    fn respond<G: Kinematics>(
        &self,
        problem: &Problem<G>,
        options: &Options,
    ) -> Result<(Response, Option<ContactDoc>), SimError> {
        match &self.contact {
            None => Ok((simulate(problem, options)?, None)),
            Some(c) => {
                let started = std::time::Instant::now();
                let h = run_coulomb(problem, options, c.friction())?;
                let doc = ContactDoc::new(&h);
                let mut r = h.response;
                r.numerics.wall_time = started.elapsed().as_secs_f64();
                Ok((r, Some(doc)))
            }
        }
    }

    /// The result document of response `r`.
    fn document(&self, r: Response, ground_peaks: GroundPeaksDoc) -> TimeHistoryResult {
        TimeHistoryResult {
            kind: tag::TimeHistory,
            ground_peaks,
            rocked: r.rocked,
            rocking_start: r.rocking_start,
            rocking_starts: r.rocking_starts,
            overturned: r.overturned,
            mode: r.mode.map(|m| m.number()),
            impact_count: r.impact_count,
            chatter_impacts_summed: r.summed_impacts,
            impacts: self.outputs.impacts.then(|| {
                r.impacts
                    .iter()
                    .map(|i| ImpactDoc {
                        t: i.time,
                        theta_dot_before: i.velocity_before,
                        theta_dot_after: i.velocity_after,
                    })
                    .collect()
            }),
            overturn_time: r.overturn_time,
            rest_time: r.rest_time,
            decided_at: r.decided_at,
            end_time: r.end_time,
            peak_theta_over_alpha: r.peak_theta_over_alpha,
            peak_friction_demand: r.friction.and_then(|f| f.peak),
            peak_friction_demand_time: r.friction.and_then(|f| f.peak_time),
            lift_off: r
                .friction
                .map(|f| f.first_lift_off.is_some() || r.lift_off.is_some())
                .or(r.lift_off.map(|_| true)),
            lift_off_time: match (r.friction.and_then(|f| f.first_lift_off), r.lift_off) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
            friction_demand_followed_until: r
                .friction
                .and_then(|f| f.followed_until)
                .filter(|_| r.overturned),
            initiation_friction_demand: r.friction.and_then(|f| f.initiation),
            warnings: r.warnings.iter().map(WarningDoc::from).collect(),
            series: r.series.map(|s| SeriesDoc {
                t: s.t,
                theta: s.theta,
                theta_dot: s.theta_dot,
                ground_acceleration: s.ground_acceleration,
                ground_vertical_acceleration: s.vertical_acceleration,
                fx_over_fz: s.reaction_ratio,
                slide_m: None,
                mode: None,
            }),
            numerics: NumericsDoc::from(&r.numerics),
            overturn_direction: r.overturn_side,
            contact_model: None,
            answered_by: None,
            initial_mode: None,
            modes: None,
            peak_slide_m: None,
            residual_slide_m: None,
            time_sliding_s: None,
            flights: None,
            time_in_flight_s: None,
            spec: self.clone(),
            engine: None,
        }
    }
}

/// The `time_history` kind: one simulation of a block under a pulse or a
/// record.
pub struct TimeHistory;

impl crate::kinds::kind::Kind for TimeHistory {
    const NAME: &'static str = crate::jobs::names::tag::TimeHistory::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Time history";
    type Spec = TimeHistorySpec;
    type Job = TimeHistoryJob;
    type Result = TimeHistoryResult;
    type Part = crate::jobs::kind::NoPart;

    fn run(
        job: &TimeHistoryJob,
        control: &crate::spectrum::Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        crate::kinds::kind::run_one::<Self>(control, || Ok(job.run()?))
    }
    fn table(
        result: &TimeHistoryResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &TimeHistoryResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        figure::svg(result, window).map_err(crate::plot::FigureError::Result)
    }

    fn size(job: &TimeHistoryJob) -> crate::jobs::kind::Size {
        use crate::jobs::cost;
        let cpu_s = match (&job.ground_motion, &job.pulse) {
            (Some(g), _) => cost::record_simulation_s(&g.acc),
            (None, Some(p)) => {
                cost::pulse_simulation_s(&p.shape, job.formulation, job.solver.method)
            }
            (None, None) => 0.0,
        };
        // On a Coulomb floor: pure rocking first, then the modes, whose
        // events cost more per step.
        let cpu_s = if job.contact.is_some() {
            4.0 * cpu_s
        } else {
            cpu_s
        };
        crate::jobs::kind::Size {
            series_points: job.outputs.series,
            record_work: job
                .ground_motion
                .as_ref()
                .map_or(0.0, |g| g.acc.len() as f64),
            ..crate::jobs::kind::Size::one(cpu_s)
        }
    }

    fn grid_field(_job: &TimeHistoryJob) -> &'static str {
        "/omega_ratio"
    }

    fn warnings(job: &TimeHistoryJob) -> Vec<WarningDoc> {
        use crate::jobs::plausible::{
            coarse_dt_warning, never_rocks_warning, record_warnings, size_warning,
        };
        let mut found: Vec<WarningDoc> = size_warning(&job.block, "/block").into_iter().collect();
        if let Some(m) = &job.ground_motion {
            found.extend(record_warnings(m, "/ground_motion"));
            found.extend(coarse_dt_warning(m.dt, job.block.p, "/ground_motion"));
            // (A vertical acceleration moves the threshold: the PGA alone
            // does not tell. On a Coulomb floor the result says whether the
            // block slid: `TimeHistoryJob::run` warns there.)
            if m.vertical.is_none() && job.contact.is_none() {
                found.extend(never_rocks_warning(
                    m,
                    &job.block,
                    job.formulation == crate::dynamics::Formulation::Linear,
                    None,
                ));
            }
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::Forcing;
    use crate::jobs::kind::Validate;
    use serde_json::json;

    /// The result of the time-history spec `doc`.
    fn run(doc: serde_json::Value) -> TimeHistoryResult {
        serde_json::from_value::<TimeHistorySpec>(doc)
            .expect("a spec")
            .validate()
            .expect("a valid spec")
            .run()
            .expect("a result")
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-9)
    }

    fn pulse_spec(vertical: Option<serde_json::Value>) -> serde_json::Value {
        let mut doc = json!({"kind": "time_history",
            "block": {"alpha": 0.2, "p": 2.0, "eta": 0.9},
            "pulse": {"type": "one_sine", "omega_ratio": 4.0, "a_p_alpha_g": 3.0},
            "outputs": {"series": 300, "duration": 4.0}});
        if let Some(v) = vertical {
            doc["vertical"] = v;
        }
        doc
    }

    #[test]
    fn the_series_carries_the_vertical_acceleration_only_with_a_vertical_motion() {
        let plain = run(pulse_spec(None));
        let s = plain.series.as_ref().expect("a series");
        assert_eq!(s.ground_vertical_acceleration, None);
        let text = serde_json::to_string(&plain).expect("json");
        assert!(!text.contains("ground_vertical_acceleration"));

        // ü_v = r·ü_g at every sample.
        let r = -0.4;
        let ratio = run(pulse_spec(Some(json!({"ratio": r}))));
        let s = ratio.series.as_ref().expect("a series");
        let v = s.ground_vertical_acceleration.as_ref().expect("ü_v");
        assert_eq!(v.len(), s.t.len());
        assert!(v.iter().any(|a| *a != 0.0));
        for (k, (&av, &ag)) in v.iter().zip(&s.ground_acceleration).enumerate() {
            assert!(close(av, r * ag), "sample {k}: {av} vs {}", r * ag);
        }
        let text = serde_json::to_string(&ratio).expect("json");
        let back: TimeHistoryResult = serde_json::from_str(&text).expect("reads back");
        assert_eq!(back.series, ratio.series);
    }

    #[test]
    fn a_delayed_vertical_pulse_is_sampled_where_it_acts() {
        let delay = 0.5;
        let result = run(pulse_spec(Some(json!({"type": "one_sine",
            "omega_p": 12.0, "a_p_g": 0.3, "delay_s": delay}))));
        let s = result.series.as_ref().expect("a series");
        let v = s.ground_vertical_acceleration.as_ref().expect("ü_v");
        let pulse = crate::dynamics::Pulse::new(
            crate::dynamics::PulseShape::OneSine,
            0.3 * result.spec.block.g,
            12.0,
        )
        .expect("a pulse");
        let mut acting = 0;
        for (&t, &a) in s.t.iter().zip(v) {
            if t < delay || t > delay + pulse.duration {
                assert_eq!(a, 0.0, "still at t = {t}");
            } else {
                acting += 1;
                assert!(close(a, pulse.acceleration(t - delay)), "t = {t}: {a}");
            }
        }
        assert!(acting > 10, "{acting} samples while it acts");
    }

    #[test]
    fn a_vertical_record_is_sampled_from_its_samples() {
        let dt = 0.01;
        let h: Vec<f64> = (0..400)
            .map(|k| 3.0 * (f64::from(k) * dt * 9.0).sin())
            .collect();
        let v: Vec<f64> = (0..250)
            .map(|k| -2.0 * (f64::from(k) * dt * 5.0).cos())
            .collect();
        let result = run(json!({"kind": "time_history",
            "block": {"alpha": 0.2, "p": 2.0, "eta": 0.9},
            "ground_motion": {"dt": dt, "acc": h, "unit": "m/s2",
                              "vertical": {"acc": v, "unit": "m/s2"}},
            "outputs": {"series": 333}}));
        let s = result.series.as_ref().expect("a series");
        let sampled = s.ground_vertical_acceleration.as_ref().expect("ü_v");
        let record = crate::dynamics::Record::new(v.into(), dt).expect("a record");
        for (&t, &a) in s.t.iter().zip(sampled) {
            // Padded with zeros past its end.
            let expected = if t <= 249.0 * dt {
                record.acceleration(t)
            } else {
                0.0
            };
            assert!((a - expected).abs() <= 1e-12, "t = {t}: {a} vs {expected}");
        }
    }

    /// The ridge station record of `specs/records` (3000 samples, dt =
    /// 0.01 s, in g) scaled by `scale`, under a slender block (α = 0.25,
    /// p = 2 rad/s).
    fn ridge_spec(scale: f64) -> serde_json::Value {
        let acc: Vec<f64> = include_str!("../../../specs/records/ridge_station_090.at2")
            .lines()
            .skip(4)
            .flat_map(str::split_whitespace)
            .map(|a| scale * a.parse::<f64>().expect("a sample"))
            .collect();
        assert_eq!(acc.len(), 3000);
        json!({"kind": "time_history", "block": {"alpha": 0.25, "p": 2.0},
            "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc}})
    }

    /// Under a record, as after a pulse's end, the fall of a block bound to
    /// overturn is not counted in the friction demand: from the first step
    /// of the last unbroken stretch where the free motion overturns
    /// (`separatrix::decide`) to the overturning. Counted, it gave 103.4 at
    /// t = 6.72 s, 0.06 s before the block overturns (2.7 × the record);
    /// and at 1.5 × a lift-off at 7.258 s, 0.06 s before, nulled the peak.
    #[test]
    fn under_a_record_the_friction_demand_leaves_out_the_fall() {
        // (scale, followed until, peak and its time; counted with the fall:
        // the peak and its time, or the lift-off).
        let cases = [
            (2.7, 4.8, (0.343_621_4, 3.183_149), (Some(103.420_2), 6.72)),
            (1.5, 4.36, (0.307_209_2, 4.351_792), (None, 7.258_121)),
        ];
        for (scale, until, (peak, at), (counted, counted_at)) in cases {
            let job = serde_json::from_value::<TimeHistorySpec>(ridge_spec(scale))
                .expect("a spec")
                .validate()
                .expect("a valid spec");
            let r = job.run().expect("a result");
            let to = r.overturn_time.expect("overturns");
            assert!(r.overturned && r.mode == Some(1), "{scale}");
            let followed = r.friction_demand_followed_until.expect("the fall left out");
            assert!((followed - until).abs() < 1e-9, "{scale}: {followed}");
            let found = r.peak_friction_demand.expect("bounded");
            let found_at = r.peak_friction_demand_time.expect("a time");
            assert!((found - peak).abs() < 1e-6, "{scale}: {found}");
            assert!((found_at - at).abs() < 1e-5, "{scale}: {found_at}");
            assert_eq!((r.lift_off, r.lift_off_time), (Some(false), None));
            let fall: Vec<&WarningDoc> = r
                .warnings
                .iter()
                .filter(|w| w.kind == "demand_excludes_fall")
                .collect();
            assert_eq!(fall.len(), 1, "{scale}: {:?}", r.warnings);
            assert_eq!(fall[0].t, Some(followed));
            assert!(
                !fall[0].message.contains("pulse end"),
                "{}",
                fall[0].message
            );
            // The same history with the fall counted.
            let problem = Problem {
                block: job.block.block().expect("a block"),
                pulse: job
                    .ground_motion
                    .as_ref()
                    .and_then(|g| g.record().ok())
                    .expect("a record"),
                formulation: job.formulation,
            };
            let all = simulate(&problem, &Options::history(job.solver.solver())).expect("runs");
            assert_eq!(all.overturn_time, Some(to));
            let f = all.friction.expect("followed");
            assert_eq!(f.followed_until, None);
            match counted {
                Some(d) => {
                    assert!((f.peak.expect("bounded") - d).abs() < 1e-3, "{f:?}");
                    assert!((f.peak_time.expect("a time") - counted_at).abs() < 1e-5);
                }
                None => {
                    assert_eq!(f.peak, None);
                    assert!((f.first_lift_off.expect("lifts off") - counted_at).abs() < 1e-5);
                }
            }
        }
    }
}
