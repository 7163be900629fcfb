//! A spectrum job's result document.

use super::spec::SpectrumJob;
use crate::dynamics::{Pulse, PulseShape};
use crate::jobs::names::{EngineDoc, tag};
use crate::jobs::spec::SolverNorm;
use crate::spectrum::scan::{Direction, ModeChange, ScanStats, Transition};
use serde::{Deserialize, Serialize};
/// The residual slide of one amplitude.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SlidePointDoc {
    /// Amplitude, αg.
    pub a_alpha_g: f64,
    /// The base's slip at the end, m (+ towards +x).
    pub residual_slide_m: f64,
    /// max |slip|, m.
    pub peak_slide_m: f64,
    /// "stands" | "overturns" | "lift_off" (left the floor: no verdict).
    pub outcome: String,
}

/// One transition in a result.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct TransitionDoc {
    /// Amplitude, αg (bracket midpoint).
    pub a_alpha_g: f64,
    /// "up": overturning begins as a_p grows; "down": a safe interval begins.
    #[schema(value_type = crate::jobs::schema::TransitionDirection)]
    pub direction: String,
    /// Mode on the overturning side.
    pub mode: u8,
    /// Impacts on the overturning side.
    pub impacts: u64,
    /// [lo, hi], width ≤ tolerance.
    pub bracket: [f64; 2],
    /// `a_alpha_g` in g.
    #[serde(default)]
    #[schema(required = true)]
    pub a_g: f64,
}

impl TransitionDoc {
    /// The transition `t` of a block of slenderness `alpha`.
    pub(super) fn new(t: &Transition, alpha: f64) -> Self {
        TransitionDoc {
            a_alpha_g: t.at,
            a_g: t.at * alpha,
            direction: match t.direction {
                Direction::Up => "up",
                Direction::Down => "down",
                Direction::SlideIn => "slide_in",
                Direction::SlideOut => "slide_out",
            }
            .to_string(),
            mode: t.mode,
            impacts: t.impacts,
            bracket: [t.bracket.0, t.bracket.1],
        }
    }
}

/// A change of overturning mode.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ModeChangeDoc {
    /// Amplitude, αg.
    pub a_alpha_g: f64,
    /// Mode below.
    pub from_mode: u8,
    /// Mode above.
    pub to_mode: u8,
    /// Bracket.
    pub bracket: [f64; 2],
}

impl From<&ModeChange> for ModeChangeDoc {
    fn from(m: &ModeChange) -> Self {
        ModeChangeDoc {
            a_alpha_g: m.at,
            from_mode: m.from,
            to_mode: m.to,
            bracket: [m.bracket.0, m.bracket.1],
        }
    }
}

/// The principal view of one frequency.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct PrincipalDoc {
    /// Transitions without narrow bands.
    pub transitions: Vec<TransitionDoc>,
    /// Lowest overturning amplitude, αg.
    #[schema(required = true)]
    pub min_overturn_alpha_g: Option<f64>,
    /// Its mode.
    #[schema(required = true)]
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum.
    pub safe_intervals: Vec<[f64; 2]>,
    /// All amplitudes above this overturn (up to a_max).
    #[schema(required = true)]
    pub overturns_above_alpha_g: Option<f64>,
}

/// A pulse's ground velocity and displacement per unit acceleration: PGV/PGA
/// and PGD/PGA (from rest, over the pulse; the same for any amplitude).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct PulseScalesDoc {
    /// PGV/PGA, s.
    pub pgv_over_pga_s: f64,
    /// PGD/PGA, s².
    pub pgd_over_pga_s2: f64,
}

impl PulseScalesDoc {
    /// Of a pulse of family `shape` at circular frequency `omega_p`, rad/s.
    pub fn of(shape: PulseShape, omega_p: f64) -> Self {
        match Pulse::new(shape, 1.0, omega_p) {
            Ok(p) => {
                let peaks = crate::dynamics::peaks::of_pulse(&p);
                PulseScalesDoc {
                    pgv_over_pga_s: peaks.pgv,
                    pgd_over_pga_s2: peaks.pgd,
                }
            }
            Err(_) => PulseScalesDoc {
                pgv_over_pga_s: 0.0,
                pgd_over_pga_s2: 0.0,
            },
        }
    }
}

/// One frequency of the spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FrequencyDoc {
    /// The pulse's velocity and displacement per unit acceleration at this
    /// frequency (PGV/PGA, PGD/PGA), whatever its amplitude.
    #[serde(default)]
    #[schema(required = true)]
    pub ground: PulseScalesDoc,
    /// ω_p/p.
    pub omega_ratio: f64,
    /// Rocking threshold, αg (under a vertical pulse of its own: where the
    /// scan starts, a lower bound of it, a_p (1 + k |a_v/a_p|) = k g).
    pub threshold_alpha_g: f64,
    /// `threshold_alpha_g` in g.
    #[serde(default)]
    #[schema(required = true)]
    pub threshold_g: f64,
    /// Every transition (fine structure).
    pub transitions: Vec<TransitionDoc>,
    /// Mode changes inside overturning regions.
    pub mode_changes: Vec<ModeChangeDoc>,
    /// Lowest overturning amplitude, αg.
    #[schema(required = true)]
    pub min_overturn_alpha_g: Option<f64>,
    /// Its mode.
    #[schema(required = true)]
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum, [lo, hi] αg.
    pub safe_intervals: Vec<[f64; 2]>,
    /// All amplitudes above this overturn (up to a_max), αg.
    #[schema(required = true)]
    pub overturns_above_alpha_g: Option<f64>,
    /// Without bands narrower than the principal relative width.
    pub principal: PrincipalDoc,
    /// Where the outcome alternates finer than the scan resolves, αg, with
    /// the fraction of probed amplitudes at which the block overturns: no
    /// transition, band or safe interval is certain inside.
    #[serde(default)]
    #[schema(required = true)]
    pub mixed: Vec<crate::jobs::mixed::MixedDoc>,
    /// Where `min_overturn_alpha_g` lies: "band" (a certain overturning
    /// band) or "mixed" (a mixed zone, `min_overturn_zone`); null when the
    /// block never overturns.
    #[serde(default)]
    #[schema(required = true)]
    pub min_overturn_in: Option<String>,
    /// The mixed zone holding `min_overturn_alpha_g`, with its fraction, αg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_overturn_zone: Option<crate::jobs::mixed::MixedDoc>,
    /// The lowest amplitude from which overturning is certain (verified,
    /// outside every mixed zone) over a band at least
    /// `principal_relative_width` of its amplitude wide, αg.
    #[serde(default)]
    #[schema(required = true)]
    pub min_certain_overturn_alpha_g: Option<f64>,
    /// Eq. 21: 1 + β ω_p/p (cycloidal pulses; null for the others, which it
    /// does not describe).
    #[schema(required = true)]
    pub eq21_alpha_g: Option<f64>,
    /// Linear one-sine mode-2 boundary from the corrected eq. 47 (linear one-sine only).
    #[schema(required = true)]
    pub closed_form_mode2_alpha_g: Option<f64>,
    /// With a vertical motion: from this amplitude (αg) on, the ground falls
    /// away faster than gravity (g + ü_v ≤ 0) and the block leaves it. On a
    /// Coulomb floor also: the lowest amplitude found (within the tolerance)
    /// at which the normal force reaches 0 and the block leaves the floor.
    /// The line is scanned up to just below it and claims nothing above
    /// (absent when the block never leaves the floor up to a_max).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_alpha_g: Option<f64>,
    /// ω_p, rad/s (ω_p/p × p).
    #[serde(default)]
    #[schema(required = true)]
    pub omega_p: f64,
    /// f_p = ω_p/2π, Hz.
    #[serde(default)]
    #[schema(required = true)]
    pub frequency_hz: f64,
    /// `min_overturn_alpha_g` in g.
    #[serde(default)]
    #[schema(required = true)]
    pub min_overturn_g: Option<f64>,
    /// `min_overturn_alpha_g` in m/s².
    #[serde(default)]
    #[schema(required = true)]
    pub min_overturn_m_s2: Option<f64>,
    /// On a Coulomb floor, when asked (`residual_slide`): the residual slide
    /// at a_max·k/steps, k = 1…steps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub residual_slide: Option<Vec<SlidePointDoc>>,
}

/// What a run of many simulations cost, and the accuracy of the worst one.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScanCost {
    /// "exact" | "dopri5" | "dop853".
    #[schema(value_type = crate::jobs::schema::MethodName)]
    pub method: String,
    /// Relative tolerance.
    #[schema(required = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance.
    #[schema(required = true)]
    pub atol: Option<f64>,
    /// Simulations run.
    pub simulations: u64,
    /// Accepted steps (segments for exact), all simulations.
    pub steps_accepted: u64,
    /// Rejected steps.
    pub steps_rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Events located.
    pub events: u64,
    /// Largest error estimate of a single simulation, rad.
    pub error_estimate: f64,
    /// Of `simulations`, those that verified the intervals between the
    /// changes found and measured the mixed zones (the cost of the
    /// verification).
    #[serde(default)]
    #[schema(required = true)]
    pub verification_simulations: u64,
    /// Of `simulations`, those whose history reached a bound on its work
    /// (impacts, steps, free motion) before its outcome was decided: each
    /// such level is undecided and lies in a mixed zone, never at a
    /// transition.
    #[serde(default)]
    #[schema(required = true)]
    pub undecided_simulations: u64,
}

impl ScanCost {
    /// From scan statistics.
    pub fn new(solver: &SolverNorm, s: &ScanStats) -> Self {
        ScanCost {
            method: solver.method.name().to_string(),
            rtol: solver.rtol,
            atol: solver.atol,
            simulations: s.simulations,
            steps_accepted: s.steps,
            steps_rejected: s.rejected,
            rhs_evaluations: s.rhs_evaluations,
            events: s.events,
            error_estimate: s.max_error_estimate,
            verification_simulations: s.probes,
            undecided_simulations: s.undecided,
        }
    }
}

/// Cost and accuracy of a spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SpectrumNumerics {
    /// Solver, cost and worst error estimate.
    #[serde(flatten)]
    pub cost: ScanCost,
    /// Bracket width of transitions, αg.
    pub tolerance: f64,
    /// Scan step: every band or safe interval wider than this is found, αg.
    pub scan_step_alpha_g: f64,
    /// Wall time, s.
    pub wall_time_s: f64,
    /// Tasks the spectrum was computed in, when more than one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tasks: Option<usize>,
}

impl SpectrumNumerics {
    /// From scan statistics.
    pub fn new(solver: &SolverNorm, s: &ScanStats, tolerance: f64, step: f64, wall: f64) -> Self {
        SpectrumNumerics {
            cost: ScanCost::new(solver, s),
            tolerance,
            scan_step_alpha_g: step,
            wall_time_s: wall,
            tasks: None,
        }
    }
}

/// The result document of a spectrum job.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SpectrumResult {
    /// "spectrum".
    pub kind: tag::Spectrum,
    /// One entry per frequency.
    pub spectrum: Vec<FrequencyDoc>,
    /// When asked (`no_sliding_beside`, on a Coulomb floor): the same
    /// frequencies under pure rocking (the base never slips), as the same
    /// spec without `contact` computes them; absent otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub no_sliding: Vec<FrequencyDoc>,
    /// Cost and accuracy (with `no_sliding`: of both spectra).
    pub numerics: SpectrumNumerics,
    /// The normalised spec.
    pub spec: SpectrumJob,
    /// Notes on the inputs (`implausible_size`: a block smaller than 1 cm or
    /// larger than 100 m); absent when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(SpectrumResult);
