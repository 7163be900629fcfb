//! A time history job's result document.

use super::spec::TimeHistoryJob;
use crate::jobs::contact::ModeDoc;
use crate::jobs::names::{EngineDoc, tag};
use crate::jobs::numerics::NumericsDoc;
use crate::jobs::warning::WarningDoc;
use serde::{Deserialize, Serialize};
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
