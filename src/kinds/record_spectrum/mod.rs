//! The `record_spectrum` job: which blocks of which size a recorded motion
//! topples, at which scale (the rocking spectrum of Makris & Konstantinidis
//! 2003). One line per block size p (or R = 3g/(4p²)), each the overturning
//! set over the record's scale factor.
//!
//! Internally a scale factor s is the level s·PGA/(αg) of a pulse spectrum's
//! amplitude axis, so the defaults (scan step 0.02 αg, tolerance 1e-4 αg) are
//! the pulse spectra's, expressed in scale units: step 0.02·s_α and tolerance
//! 1e-4·s_α, with s_α = αg/PGA the scale at which the record's PGA reaches αg.

pub mod figure;
pub mod table;

use crate::jobs::mixed::{MixedDoc, minimum_place};
use serde::{Deserialize, Serialize};

use super::spectrum::ScanCost;
use super::time_history::GroundPeaksDoc;
use crate::dynamics::block::BlockError;
use crate::dynamics::{Block, Formulation, SimError, peaks};
use crate::jobs::error::JobError;
use crate::jobs::names::{EngineDoc, tag};
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, GroundMotionNorm, GroundMotionSpec, SolverNorm, SolverSpec, SpecError,
    at_most_one, in_one_unit, parse_formulation, validate_block,
};
use crate::jobs::vertical::ScaledVertical;
use crate::spectrum::Control;
use crate::spectrum::overturning::{Derived, LineScan, ScanGrid, threshold_alpha_g_of};
use crate::spectrum::record::{RecordSpectrumRequest, record_spectrum};
use crate::spectrum::scan::ScanStats;

pub mod part;
use crate::spectrum::scan::{Direction, ModeChange, ScanError, Transition};

/// Most block sizes in one record spectrum.
pub const MAX_SIZES: usize = 2_000;
/// Accepted block frequency parameters p, rad/s (R from about 1 µm to 7,000 km).
pub const P_RANGE: (f64, f64) = (1e-3, 1e3);
/// Highest level examined: the scaled PGA in α g, as for pulse spectra.
pub const MAX_LEVEL: f64 = 1e4;
/// Default bracket width, in units of s_α = αg/PGA.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// Default scan step, in units of s_α.
pub const DEFAULT_SCAN_STEP: f64 = 0.02;
/// Most scan points per block size.
pub const MAX_SCAN_POINTS: f64 = 1e6;

/// A range of scale factors (or of PGA in g).
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ScaleRangeSpec {
    /// Lowest value (default 0). A scan always starts where the block starts
    /// to rock, so that each overturning set is located, not assumed at `from`.
    #[schema(minimum = 0.0)]
    pub from: Option<f64>,
    /// Highest value.
    #[schema(required = true, value_type = f64, exclusive_minimum = 0.0)]
    pub to: Option<f64>,
}

impl ScaleRangeSpec {
    /// `(from, to)` of the axis named `name`: `from` defaults to 0; both
    /// finite, `from` ≥ 0 and `to` above it, or the field is named.
    pub fn ends(&self, name: &str) -> Result<(f64, f64), SpecError> {
        let to = self.to.ok_or_else(|| {
            SpecError::at(format!("/{name}/to"), "missing field: the highest value")
        })?;
        let from = self.from.unwrap_or(0.0);
        if !(from.is_finite() && from >= 0.0) {
            return Err(SpecError::at(
                format!("/{name}/from"),
                "must be a finite number >= 0",
            ));
        }
        if !(to.is_finite() && to > from) {
            return Err(SpecError::at(
                format!("/{name}/to"),
                "must be a finite number above from",
            ));
        }
        Ok((from, to))
    }
}

/// The block of a record spectrum as users write it: everything but its
/// size, which is the spectrum's axis (a `p`, `b` or `h` here is refused
/// naming it).
#[derive(Clone, Debug, Deserialize, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
pub struct RecordBlockSpec {
    /// Slenderness α, rad.
    #[schema(exclusive_minimum = 0.0)]
    alpha: f64,
    /// Coefficient of restitution η (default 1 − 1.5 sin²α, floored at 0).
    #[schema(minimum = 0.0, maximum = 1.0)]
    eta: Option<f64>,
    /// Gravity, m/s² (default 9.81).
    #[schema(exclusive_minimum = 0.0)]
    g: Option<f64>,
}

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RecordSpectrumSpec {
    /// "record_spectrum".
    #[schema(value_type = crate::jobs::names::tag::RecordSpectrum)]
    pub kind: String,
    /// The record (`dt`, `acc`, `unit`).
    #[schema(required = true, value_type = GroundMotionSpec)]
    pub ground_motion: Option<GroundMotionSpec>,
    /// The block's slenderness, restitution and gravity (`alpha`, `eta`,
    /// `g`); its size is the spectrum's axis (`p` or `R_m`).
    #[schema(required = true, value_type = RecordBlockSpec)]
    pub block: Option<BlockSpec>,
    /// Block frequency parameters p, rad/s (give this or `R_m`).
    pub p: Option<RangeSpec>,
    /// Block sizes R = √(b² + h²), m (p = √(3g/(4R))).
    #[serde(rename = "R_m", alias = "r_m")]
    pub r_m: Option<RangeSpec>,
    /// Scale factors applied to the record: `{"from", "to"}` (give this or `pga_g`).
    pub scale: Option<ScaleRangeSpec>,
    /// The scaled record's PGA, g: `{"from", "to"}`.
    pub pga_g: Option<ScaleRangeSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// Bracket width of each transition, in scale units (default 1e-4 αg/PGA).
    #[schema(exclusive_minimum = 0.0)]
    pub tolerance: Option<f64>,
    /// Scan step, in scale units (default 0.02 αg/PGA): every band or safe
    /// interval wider than this is found.
    #[schema(exclusive_minimum = 0.0)]
    pub scan_step: Option<f64>,
    /// Principal view: drop bands narrower than this fraction of their scale (0 to 1, default 0.01).
    #[schema(minimum = 0.0, maximum = 1.0)]
    pub principal_relative_width: Option<f64>,
    /// Solver.
    pub solver: Option<SolverSpec>,
    /// The vertical ground acceleration (positive up) as a share of the
    /// horizontal one at every scale: `{"ratio": r}`, ü_v = r·ü_g (or give
    /// the record's own vertical samples as `ground_motion.vertical`, scaled
    /// with it; not both).
    pub vertical: Option<crate::jobs::vertical::VerticalPulseSpec>,
    /// The contact with the floor: `{"model": "no_sliding"}` (pure rocking,
    /// the default) or `{"model": "coulomb", "mu", "mu_kinetic"?}` (every
    /// size at every scale followed on that floor).
    pub contact: Option<crate::jobs::contact::ContactSpec>,
}

/// The block of a record spectrum, normalised: everything but its size.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordBlockNorm {
    /// α, rad.
    pub alpha: f64,
    /// η.
    pub eta: f64,
    /// g, m/s².
    pub g: f64,
}

/// A range of scale factors, normalised.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScaleRangeNorm {
    /// Lowest scale factor.
    pub from: f64,
    /// Highest scale factor.
    pub to: f64,
}

/// A validated record spectrum; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordSpectrumJob {
    /// "record_spectrum".
    pub kind: tag::RecordSpectrum,
    /// The record, m/s².
    pub ground_motion: GroundMotionNorm,
    /// Block (its size varies).
    pub block: RecordBlockNorm,
    /// Block frequency parameters, rad/s.
    pub p: Vec<f64>,
    /// Scale factors examined.
    pub scale: ScaleRangeNorm,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// Bracket width, scale units.
    pub tolerance: f64,
    /// Scan step, scale units.
    pub scan_step: f64,
    /// Principal relative width.
    pub principal_relative_width: f64,
    /// Solver.
    pub solver: SolverNorm,
    /// ü_v = r·ü_g (positive up), when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<crate::jobs::vertical::VerticalPulseDoc>)]
    pub vertical: Option<crate::jobs::vertical::VerticalPulseNorm>,
    /// Coulomb friction at the floor, when given (absent: pure rocking).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<crate::jobs::contact::ContactNorm>,
    /// A task's sizes and levels (absent: the whole job).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub part: Option<crate::jobs::scan_parts::Part>,
}

/// p of a block of size R, m, under gravity g (eq. 5: p = √(3g/(4R))).
pub fn p_of_size(r: f64, g: f64) -> f64 {
    (3.0 * g / (4.0 * r)).sqrt()
}

/// R of a block of frequency parameter p.
pub fn size_of_p(p: f64, g: f64) -> f64 {
    3.0 * g / (4.0 * p * p)
}

/// The rocking threshold, αg of the record's PGA, of a block of slenderness
/// `alpha` under gravity `g`, lowered by the vertical motion (a ratio, or the
/// record's own samples) where it lightens the block.
fn threshold_of(
    formulation: Formulation,
    alpha: f64,
    g: f64,
    ground_motion: &GroundMotionNorm,
    vertical: Option<&crate::jobs::vertical::VerticalPulseNorm>,
) -> f64 {
    let threshold = threshold_alpha_g_of(formulation, alpha, g);
    match ScaledVertical::of(vertical, Some(ground_motion)) {
        Some(v) => v.threshold(threshold, formulation, alpha, &ground_motion.acc),
        None => threshold,
    }
}

pub use crate::records::pga;

impl crate::jobs::kind::Validate for RecordSpectrumSpec {
    type Job = RecordSpectrumJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<RecordSpectrumJob, SpecError> {
        let block = self.sizeless_block()?;
        let (ground_motion, vertical, peak) = self.scaled_record(&block)?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let contact =
            crate::jobs::contact::validate_contact(self.contact.as_ref(), formulation, "/contact")?;
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            true,
            vertical.is_some() || ground_motion.vertical.is_some(),
            "/solver",
        )?;
        let g = block.g;
        let p = self.sizes_as_p(g)?;
        // Scale factors, normalised; a level is the scaled PGA in α g.
        let unit = block.alpha * g / peak; // s_α: the scale at which PGA = αg
        let (scale, s_name) = self.scale_range(g, peak)?;
        let levels = RecordLevels {
            peak,
            g,
            alpha: block.alpha,
            unit,
            threshold: threshold_of(
                formulation,
                block.alpha,
                g,
                &ground_motion,
                vertical.as_ref(),
            ),
        };
        check_highest_scale(&scale, s_name, formulation, &levels)?;
        let steps = self.search_steps(unit, scale.to)?;
        Ok(RecordSpectrumJob {
            kind: tag::RecordSpectrum,
            ground_motion,
            block: RecordBlockNorm {
                alpha: block.alpha,
                eta: block.eta,
                g,
            },
            p,
            scale,
            formulation,
            tolerance: steps.tolerance,
            scan_step: steps.scan_step,
            principal_relative_width: steps.principal,
            solver,
            vertical,
            contact,
            part: None,
        })
    }
}

/// A record's scale factors against its levels (a level is the scaled PGA
/// in αg).
struct RecordLevels {
    /// The record's PGA, m/s².
    peak: f64,
    /// g, m/s².
    g: f64,
    /// The block's α, rad.
    alpha: f64,
    /// The scale factor at which the PGA is αg (s_α).
    unit: f64,
    /// The rocking threshold, αg.
    threshold: f64,
}

/// The search along the scale factor of a record spectrum, validated.
struct SearchSteps {
    /// Bracket width, scale units.
    tolerance: f64,
    /// Scan step, scale units.
    scan_step: f64,
    /// Principal relative width.
    principal: f64,
}

impl RecordSpectrumSpec {
    /// The block without its size (the sizes are an axis): no p, b, h nor
    /// mu given; validated with p = 1.
    fn sizeless_block(&self) -> Result<BlockNorm, SpecError> {
        let block_spec = crate::jobs::spec::required(self.block.as_ref(), "/block")?;
        for (v, name) in [
            (block_spec.p, "p"),
            (block_spec.b, "b"),
            (block_spec.h, "h"),
        ] {
            if v.is_some() {
                return Err(SpecError::at(
                    format!("/block/{name}"),
                    "a record spectrum varies the block's size: give alpha (and eta, g) in the block and the sizes as p (rad/s) or R_m (m) at the top level",
                ));
            }
        }
        if block_spec.mu.is_some() {
            return Err(SpecError::at(
                "/block/mu",
                "a record spectrum computes overturning only: mu is not used (a floor with friction: contact {\"model\": \"coulomb\", \"mu\": …})",
            ));
        }
        validate_block(
            &BlockSpec {
                p: Some(1.0),
                ..block_spec.clone()
            },
            "/block",
        )
    }

    /// The record, scaled, with its vertical motion and its PGA (not 0).
    #[allow(clippy::type_complexity)]
    fn scaled_record(
        &self,
        block: &BlockNorm,
    ) -> Result<
        (
            GroundMotionNorm,
            Option<crate::jobs::vertical::VerticalPulseNorm>,
            f64,
        ),
        SpecError,
    > {
        let gm = self.ground_motion.as_ref().ok_or_else(|| {
            SpecError::at(
                "/ground_motion",
                "missing field: {\"dt\", \"acc\", \"unit\"}",
            )
        })?;
        let (ground_motion, vertical) = crate::jobs::vertical::validate_scaled_record(
            self.vertical.as_ref(),
            gm,
            block,
            "/ground_motion",
        )?;
        let peak = pga(&ground_motion.acc);
        if peak == 0.0 {
            return Err(SpecError::at(
                "/ground_motion/acc",
                "the record has no motion (every sample is 0)",
            ));
        }
        Ok((ground_motion, vertical, peak))
    }

    /// The block sizes, given as p or R_m, as frequency parameters p, rad/s.
    fn sizes_as_p(&self, g: f64) -> Result<Vec<f64>, SpecError> {
        let names = ["p", "R_m"];
        let (sizes, which) = at_most_one(
            "",
            &[(self.p.as_ref(), names[0]), (self.r_m.as_ref(), names[1])],
            "block-size axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/p",
                "missing field: the block sizes as p (rad/s) or R_m (m): {\"from\", \"to\", \"steps\"} or a list",
            )
        })?;
        let (name, is_r) = (names[which], which == 1);
        let pointer = format!("/{name}");
        let (lo, hi) = if is_r {
            (size_of_p(P_RANGE.1, g), size_of_p(P_RANGE.0, g))
        } else {
            P_RANGE
        };
        Ok(sizes
            .values(&pointer, lo, hi, MAX_SIZES)?
            .into_iter()
            .map(|v| if is_r { p_of_size(v, g) } else { v })
            .collect())
    }

    /// The scale factors, given as scale or pga_g, normalised to scale
    /// factors, with the name of the field that gave them.
    fn scale_range(&self, g: f64, peak: f64) -> Result<(ScaleRangeNorm, &'static str), SpecError> {
        let (range, s_name, to_scale) = in_one_unit(
            &[
                (self.scale.as_ref(), "scale", 1.0),
                (self.pga_g.as_ref(), "pga_g", g / peak),
            ],
            "scale axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/scale",
                "missing field: the scale factors as scale {\"from\", \"to\"} or the PGA as pga_g {\"from\", \"to\"}",
            )
        })?;
        let (from, to) = range.ends(s_name)?;
        Ok((
            ScaleRangeNorm {
                from: from * to_scale,
                to: to * to_scale,
            },
            s_name,
        ))
    }

    /// The tolerance, scan step and principal relative width, each in its
    /// range (the first two in units of `unit`, αg/PGA).
    fn search_steps(&self, unit: f64, highest: f64) -> Result<SearchSteps, SpecError> {
        let tolerance = self.tolerance.unwrap_or(DEFAULT_TOLERANCE * unit);
        if !(tolerance.is_finite() && tolerance >= 1e-9 * unit && tolerance <= 0.1 * unit) {
            return Err(SpecError::at(
                "/tolerance",
                format!(
                    "must lie in [{:.3e}, {:.3e}] (1e-9 to 0.1 times αg/PGA = {unit:.6e}); got {tolerance}",
                    1e-9 * unit,
                    0.1 * unit
                ),
            ));
        }
        let scan_step = self.scan_step.unwrap_or(DEFAULT_SCAN_STEP * unit);
        if !(scan_step.is_finite() && scan_step >= tolerance && scan_step <= unit) {
            return Err(SpecError::at(
                "/scan_step",
                format!(
                    "must lie in [tolerance, αg/PGA] = [{tolerance:.3e}, {unit:.6e}]; got {scan_step}"
                ),
            ));
        }
        if highest / scan_step > MAX_SCAN_POINTS {
            return Err(SpecError::at(
                "/scan_step",
                format!("the highest scale over scan_step must not exceed {MAX_SCAN_POINTS:e}"),
            ));
        }
        let principal = self.principal_relative_width.unwrap_or(0.01);
        if !(principal.is_finite() && (0.0..=1.0).contains(&principal)) {
            return Err(SpecError::at(
                "/principal_relative_width",
                "must lie in [0, 1]",
            ));
        }
        Ok(SearchSteps {
            tolerance,
            scan_step,
            principal,
        })
    }
}

/// The highest scale factor of `scale` (given as the field `s_name`) scales
/// the record above its rocking threshold, and not above `MAX_LEVEL`.
fn check_highest_scale(
    scale: &ScaleRangeNorm,
    s_name: &str,
    formulation: Formulation,
    levels: &RecordLevels,
) -> Result<(), SpecError> {
    let RecordLevels {
        peak,
        g,
        alpha,
        unit,
        threshold,
    } = *levels;
    let level_to = scale.to / unit;
    if level_to <= threshold {
        return Err(SpecError::at(
            format!("/{s_name}/to"),
            format!(
                "the record scaled by {} has a PGA of {:.4} g, below the rocking threshold {:.4} g (g tan α{}): no block of this slenderness rocks; the scale must exceed {:.6}",
                scale.to,
                scale.to * peak / g,
                threshold * alpha,
                if formulation == Formulation::Linear {
                    ", linear: g α"
                } else {
                    ""
                },
                threshold * unit
            ),
        ));
    }
    if level_to > MAX_LEVEL {
        return Err(SpecError::at(
            format!("/{s_name}/to"),
            format!(
                "the scaled PGA must not exceed {MAX_LEVEL:e} αg (scale {:.6e})",
                MAX_LEVEL * unit
            ),
        ));
    }
    Ok(())
}

/// A survive ↔ overturn transition over the scale factor.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScaleTransitionDoc {
    /// Scale factor (bracket midpoint).
    pub scale: f64,
    /// The scaled record's PGA there, g.
    pub pga_g: f64,
    /// "up": overturning begins as the scale grows; "down": a safe interval begins.
    #[schema(value_type = crate::jobs::schema::TransitionDirection)]
    pub direction: String,
    /// Mode on the overturning side.
    pub mode: u8,
    /// Impacts on the overturning side.
    pub impacts: u64,
    /// [lo, hi] scale factors, width ≤ tolerance.
    pub bracket: [f64; 2],
}

/// A change of overturning mode over the scale factor.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScaleModeChangeDoc {
    /// Scale factor.
    pub scale: f64,
    /// Mode below.
    pub from_mode: u8,
    /// Mode above.
    pub to_mode: u8,
    /// Bracket, scale factors.
    pub bracket: [f64; 2],
}

/// The principal view of one block size.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct ScalePrincipalDoc {
    /// Transitions without narrow bands.
    pub transitions: Vec<ScaleTransitionDoc>,
    /// Lowest overturning scale factor.
    #[schema(required = true)]
    pub min_overturn_scale: Option<f64>,
    /// Its mode.
    #[schema(required = true)]
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum, [lo, hi] scale factors.
    pub safe_intervals: Vec<[f64; 2]>,
    /// Every scale above this overturns (up to the highest examined).
    #[schema(required = true)]
    pub overturns_above_scale: Option<f64>,
}

/// One block size of a record spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SizeDoc {
    /// Frequency parameter p, rad/s.
    pub p: f64,
    /// Size R = 3g/(4p²), m.
    #[serde(rename = "R_m")]
    pub r_m: f64,
    /// Scale factor at which the block starts to rock (PGA = g tan α, or g α linear).
    pub threshold_scale: f64,
    /// Every transition (fine structure).
    pub transitions: Vec<ScaleTransitionDoc>,
    /// Mode changes inside overturning regions.
    pub mode_changes: Vec<ScaleModeChangeDoc>,
    /// Lowest overturning scale factor.
    #[schema(required = true)]
    pub min_overturn_scale: Option<f64>,
    /// The scaled record's PGA there, g.
    #[schema(required = true)]
    pub min_overturn_pga_g: Option<f64>,
    /// Its mode.
    #[schema(required = true)]
    pub min_overturn_mode: Option<u8>,
    /// Safe intervals above the minimum, [lo, hi] scale factors.
    pub safe_intervals: Vec<[f64; 2]>,
    /// Every scale above this overturns (up to the highest examined).
    #[schema(required = true)]
    pub overturns_above_scale: Option<f64>,
    /// Without bands narrower than the principal relative width.
    pub principal: ScalePrincipalDoc,
    /// On a Coulomb floor: the lowest scale found (within the tolerance) at
    /// which the normal force reaches 0 and the block leaves the floor; this
    /// size claims nothing above it (absent when it never does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_scale: Option<f64>,
    /// Where the outcome alternates finer than the scan resolves (scale
    /// factors), with the fraction of probed scales at which the block
    /// overturns: no transition, band or safe interval is certain inside.
    #[serde(default)]
    #[schema(required = true)]
    pub mixed: Vec<crate::jobs::mixed::MixedDoc>,
    /// Where `min_overturn_scale` lies: "band" (a certain overturning band)
    /// or "mixed" (a mixed zone, `min_overturn_zone`); null when the block
    /// never overturns.
    #[serde(default)]
    #[schema(required = true)]
    pub min_overturn_in: Option<String>,
    /// The mixed zone holding `min_overturn_scale`, with its fraction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_overturn_zone: Option<crate::jobs::mixed::MixedDoc>,
    /// The lowest scale from which overturning is certain (verified, outside
    /// every mixed zone) over a band at least `principal_relative_width` of
    /// its scale wide.
    #[serde(default)]
    #[schema(required = true)]
    pub min_certain_overturn_scale: Option<f64>,
    /// The scaled record's PGA there, g.
    #[serde(default)]
    #[schema(required = true)]
    pub min_certain_overturn_pga_g: Option<f64>,
}

/// The record as given: its peaks and sampling.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordDoc {
    /// PGA, PGV, PGD of the unscaled record (from rest, no baseline correction).
    #[serde(flatten)]
    pub peaks: GroundPeaksDoc,
    /// Sampling interval, s.
    pub dt_s: f64,
    /// Samples.
    pub samples: usize,
    /// Duration (N − 1)·dt, s.
    pub duration_s: f64,
}

/// Cost and accuracy of a record spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordSpectrumNumerics {
    /// Solver, cost and worst error estimate.
    #[serde(flatten)]
    pub cost: ScanCost,
    /// Bracket width of transitions, scale units.
    pub tolerance: f64,
    /// Scan step, scale units.
    pub scan_step: f64,
    /// Wall time, s (of a job computed in several tasks: their total
    /// compute time).
    pub wall_time_s: f64,
    /// Tasks the job was computed in (absent: one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tasks: Option<usize>,
}

/// The result document of a record spectrum.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct RecordSpectrumResult {
    /// "record_spectrum".
    pub kind: tag::RecordSpectrum,
    /// The record's PGA, PGV, PGD and sampling.
    pub record: RecordDoc,
    /// One entry per block size, in the order of `spec.p`.
    pub spectrum: Vec<SizeDoc>,
    /// Under a vertical motion: from this scale factor the ground falls away
    /// faster than gravity (g + ü_v ≤ 0) and the block leaves it; every size
    /// is scanned up to just below it and claims nothing above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off_above_scale: Option<f64>,
    /// Cost and accuracy.
    pub numerics: RecordSpectrumNumerics,
    /// The normalised spec.
    pub spec: RecordSpectrumJob,
    /// Notes on the inputs; absent when there are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(RecordSpectrumResult);

/// Levels (αg over the record's PGA) read as scale factors and as the scaled
/// record's PGA, g.
#[derive(Clone, Copy)]
struct ToScale {
    /// The scale factor of a level of 1 (αg/PGA).
    unit: f64,
    /// The record's PGA, m/s².
    peak: f64,
    /// g, m/s².
    g: f64,
}

impl ToScale {
    /// The scale factor of `level`.
    fn scale(self, level: f64) -> f64 {
        level * self.unit
    }

    /// The PGA, g, of the record scaled to `level`.
    fn pga_g(self, level: f64) -> f64 {
        self.scale(level) * self.peak / self.g
    }

    /// A transition over the scale factor.
    fn transition(self, t: &Transition) -> ScaleTransitionDoc {
        ScaleTransitionDoc {
            scale: self.scale(t.at),
            pga_g: self.pga_g(t.at),
            direction: match t.direction {
                Direction::Up => "up",
                Direction::Down => "down",
                Direction::SlideIn => "slide_in",
                Direction::SlideOut => "slide_out",
            }
            .to_string(),
            mode: t.mode,
            impacts: t.impacts,
            bracket: [self.scale(t.bracket.0), self.scale(t.bracket.1)],
        }
    }

    /// A change of overturning mode over the scale factor.
    fn mode_change(self, m: &ModeChange) -> ScaleModeChangeDoc {
        ScaleModeChangeDoc {
            scale: self.scale(m.at),
            from_mode: m.from,
            to_mode: m.to,
            bracket: [self.scale(m.bracket.0), self.scale(m.bracket.1)],
        }
    }

    /// The safe intervals of `d` as scale factors.
    fn intervals(self, d: &Derived) -> Vec<[f64; 2]> {
        d.safe_intervals
            .iter()
            .map(|&(a, b)| [self.scale(a), self.scale(b)])
            .collect()
    }
}

impl RecordSpectrumJob {
    /// The block at frequency parameter `p` (an error for values no
    /// validated spec holds).
    pub fn block_at(&self, p: f64) -> Result<Block, BlockError> {
        Block::new(
            self.block.alpha,
            p,
            Some(self.block.eta),
            None,
            Some(self.block.g),
        )
    }

    /// The rocking threshold of every block size, αg (lowered where the
    /// vertical motion lightens the block).
    pub fn threshold_alpha_g(&self) -> f64 {
        threshold_of(
            self.formulation,
            self.block.alpha,
            self.block.g,
            &self.ground_motion,
            self.vertical.as_ref(),
        )
    }

    /// ü_v/ü_g, when the job has a vertical motion given as a ratio.
    pub fn vertical_ratio(&self) -> Option<f64> {
        self.vertical.as_ref().and_then(|v| v.ratio())
    }

    /// Coulomb friction at the floor, when the job has it.
    pub fn friction(&self) -> Option<crate::dynamics::sliding::Friction> {
        self.contact.as_ref().map(|c| c.friction())
    }

    /// The vertical motion scaled with the record, when the job has one.
    pub fn scaled_vertical(&self) -> Option<ScaledVertical<'_>> {
        ScaledVertical::of(self.vertical.as_ref(), Some(&self.ground_motion))
    }

    /// Under a vertical motion: the level (scaled PGA in α g) from which the
    /// ground falls away faster than gravity (g + ü_v ≤ 0), bracketed; `None`
    /// when it does not up to `scale.to` (or without a vertical motion).
    pub fn lift_off_level(&self) -> Option<(f64, f64)> {
        // On a Coulomb floor the block's flights are followed.
        if self.contact.is_some() {
            return None;
        }
        let block = self.block_at(1.0).ok()?;
        self.scaled_vertical()?.record_lift_off(
            &self.record().ok()?,
            &block,
            self.scale.to / self.unit_scale(),
        )
    }

    /// s_α = αg/PGA: the scale factor of one level (scaled PGA of α g).
    pub fn unit_scale(&self) -> f64 {
        self.block.alpha * self.block.g / pga(&self.ground_motion.acc)
    }

    /// The scan grid in levels (scaled PGA in α g).
    pub fn grid(&self) -> ScanGrid {
        let unit = self.unit_scale();
        let threshold = self.threshold_alpha_g();
        ScanGrid {
            // From the threshold whatever `scale.from` is: a line that already
            // overturns at `from` would otherwise lose where overturning begins.
            from: threshold,
            // Under a vertical motion, up to just below the lift-off.
            to: self
                .lift_off_level()
                .map_or(self.scale.to / unit, |(lo, _)| lo.max(threshold)),
            step: self.scan_step / unit,
            tolerance: self.tolerance / unit,
            principal_relative_width: self.principal_relative_width,
        }
    }

    /// Scan points of one block size.
    pub fn points_per_size(&self) -> f64 {
        let grid = self.grid();
        ((grid.to - grid.from) / grid.step).ceil().max(0.0) + 1.0
    }

    /// The record as the engine takes it.
    pub fn record(&self) -> Result<crate::dynamics::Record, ScanError> {
        self.ground_motion
            .record()
            .map_err(|_| ScanError::Simulation(crate::dynamics::SimError::Tolerance))
    }

    /// The problems of the blocks of frequency parameters `ps` under the
    /// record (scaled per level by the scan).
    pub fn problems(
        &self,
        ps: &[f64],
    ) -> Result<Vec<crate::dynamics::Problem<crate::dynamics::Record>>, ScanError> {
        let record = self.record()?;
        ps.iter()
            .map(|&p| {
                Ok(crate::dynamics::Problem {
                    block: self.block_at(p).map_err(SimError::from)?,
                    pulse: record.clone(),
                    formulation: self.formulation,
                })
            })
            .collect()
    }

    /// Runs the whole job under `control` (whatever its `part`).
    pub fn run(&self, control: &Control) -> Result<RecordSpectrumResult, ScanError> {
        let req = RecordSpectrumRequest {
            record: self.record()?,
            block: self.block_at(1.0).map_err(SimError::from)?,
            ps: self.p.clone(),
            formulation: self.formulation,
            solver: self.solver.solver(),
            friction: self.friction(),
            grid: self.grid(),
        };
        let s = match self.scaled_vertical() {
            None => record_spectrum(&req, control)?,
            Some(v) => {
                let pair = v.record_pair(req.record.clone())?;
                record_spectrum(
                    &RecordSpectrumRequest {
                        record: pair,
                        block: req.block,
                        ps: req.ps.clone(),
                        formulation: req.formulation,
                        solver: req.solver,
                        friction: req.friction,
                        grid: req.grid,
                    },
                    control,
                )?
            }
        };
        self.result(&s.lines, &s.stats, s.wall_time, None)
    }

    /// The whole job's result from its tasks' parts (in any order).
    pub fn result_of(
        &self,
        parts: &[crate::jobs::scan_parts::PartDoc],
    ) -> Result<RecordSpectrumResult, JobError> {
        let (found, stats, wall) = part::assemble(self, parts)?;
        let grid = self.grid();
        let lines: Vec<LineScan> = found.into_iter().map(|f| grid.line(f)).collect();
        self.result(&lines, &stats, wall, Some(parts.len()))
            .map_err(|e| JobError::Task(e.to_string()))
    }

    /// The result document of the lines found.
    fn result(
        &self,
        lines: &[LineScan],
        stats: &ScanStats,
        wall_time: f64,
        tasks: Option<usize>,
    ) -> Result<RecordSpectrumResult, ScanError> {
        let record = self.record()?;
        let unit = self.unit_scale();
        let g = self.block.g;
        let peak = pga(&self.ground_motion.acc);
        let threshold = self.threshold_alpha_g();
        let to = ToScale { unit, peak, g };
        let spectrum = self
            .p
            .iter()
            .zip(lines)
            .map(|(&p, l): (&f64, &LineScan)| self.size_doc(p, l, to, threshold))
            .collect();
        let n = self.ground_motion.acc.len();
        Ok(RecordSpectrumResult {
            kind: tag::RecordSpectrum,
            record: RecordDoc {
                peaks: GroundPeaksDoc::new(&peaks::of_record(&record), g),
                dt_s: self.ground_motion.dt,
                samples: n,
                duration_s: (n - 1) as f64 * self.ground_motion.dt,
            },
            spectrum,
            lift_off_above_scale: self.lift_off_level().map(|(_, hi)| to.scale(hi)),
            numerics: RecordSpectrumNumerics {
                cost: ScanCost::new(&self.solver, stats),
                tolerance: self.tolerance,
                scan_step: self.scan_step,
                wall_time_s: wall_time,
                tasks,
            },
            spec: RecordSpectrumJob {
                part: None,
                ..self.clone()
            },
            warnings: Vec::new(),
            engine: None,
        })
    }

    /// The document of the block size `p` from its line `l` (levels read as
    /// scales by `to`; the rocking threshold `threshold`, αg).
    fn size_doc(&self, p: f64, l: &LineScan, to: ToScale, threshold: f64) -> SizeDoc {
        let g = self.block.g;
        SizeDoc {
            p,
            r_m: size_of_p(p, g),
            threshold_scale: to.scale(threshold),
            transitions: l.transitions.iter().map(|t| to.transition(t)).collect(),
            mode_changes: l.mode_changes.iter().map(|m| to.mode_change(m)).collect(),
            min_overturn_scale: l.derived.min_overturn.map(|a| to.scale(a)),
            min_overturn_pga_g: l.derived.min_overturn.map(|a| to.pga_g(a)),
            min_overturn_mode: l.derived.min_overturn_mode,
            safe_intervals: to.intervals(&l.derived),
            overturns_above_scale: l.derived.overturns_above.map(|a| to.scale(a)),
            principal: ScalePrincipalDoc {
                transitions: l
                    .principal_transitions
                    .iter()
                    .map(|t| to.transition(t))
                    .collect(),
                min_overturn_scale: l.principal.min_overturn.map(|a| to.scale(a)),
                min_overturn_mode: l.principal.min_overturn_mode,
                safe_intervals: to.intervals(&l.principal),
                overturns_above_scale: l.principal.overturns_above.map(|a| to.scale(a)),
            },
            lift_off_above_scale: self.lift_off_level().map(|(_, hi)| to.scale(hi)),
            mixed: l
                .mixed
                .iter()
                .map(|z| MixedDoc::overturning(z, to.unit))
                .collect(),
            min_overturn_in: minimum_place(&l.derived, to.unit).0,
            min_overturn_zone: minimum_place(&l.derived, to.unit).1,
            min_certain_overturn_scale: l.derived.min_certain_overturn.map(|a| to.scale(a)),
            min_certain_overturn_pga_g: l.derived.min_certain_overturn.map(|a| to.pga_g(a)),
        }
    }
}

/// The `record_spectrum` kind: the rocking spectrum of a recorded motion.
pub struct RecordSpectrum;

impl crate::kinds::kind::Kind for RecordSpectrum {
    const NAME: &'static str = crate::jobs::names::tag::RecordSpectrum::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Record spectrum";
    type Spec = RecordSpectrumSpec;
    type Job = RecordSpectrumJob;
    type Result = RecordSpectrumResult;
    type Part = crate::jobs::scan_parts::PartDoc;

    fn run(
        job: &RecordSpectrumJob,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        use crate::kinds::kind::Output;
        Ok(match job.part {
            // A task's transitions, assembled by the service.
            Some(p) => Output::Part(part::run(job, p, control)?),
            None => Output::Whole(job.run(control)?),
        })
    }

    fn table(
        result: &RecordSpectrumResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &RecordSpectrumResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    /// Scan points of every size, each bisected down to the tolerance
    /// ([`crate::jobs::cost::record_line_simulations`]), at the cost of a
    /// simulation of the record.
    fn size(job: &RecordSpectrumJob) -> crate::jobs::kind::Size {
        let scan = job.points_per_size();
        let grid = job.grid();
        let (n, points) = match job.part {
            Some(p) => (
                (p.lines[1] - p.lines[0]) as f64,
                (p.levels[1] - p.levels[0] + 1) as f64,
            ),
            None => (job.p.len() as f64, scan),
        };
        let work =
            n * crate::jobs::cost::record_line_simulations(points, grid.step, grid.tolerance);
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: (n * points).min(usize::MAX as f64) as usize,
            work,
            record_work: work * job.ground_motion.acc.len() as f64,
            cpu_s: work
                * crate::jobs::cost::record_simulation_s(&job.ground_motion.acc)
                * crate::jobs::cost::contact_factor(job.contact.as_ref()),
            lanes: n * (points / 48.0).ceil(),
        }
    }

    fn grid_field(_job: &RecordSpectrumJob) -> &'static str {
        "/p"
    }

    fn warnings(job: &RecordSpectrumJob) -> Vec<crate::jobs::warning::WarningDoc> {
        use crate::jobs::plausible::{coarse_dt_warning, record_warnings};
        let mut found = record_warnings(&job.ground_motion, "/ground_motion");
        if let Some(p) = job.p.iter().copied().reduce(f64::max) {
            found.extend(coarse_dt_warning(job.ground_motion.dt, p, "/ground_motion"));
        }
        found
    }

    /// Tasks of about [`crate::jobs::cost::TASK_CPU_S`]: sizes grouped, or a
    /// size split along the scale axis ([`part`]); each task names its part
    /// of the job, whose record is stored once.
    fn split(job: &RecordSpectrumJob, _size: &crate::jobs::kind::Size) -> Vec<RecordSpectrumJob> {
        crate::jobs::scan_parts::split(job)
    }

    fn task_payload(job: &RecordSpectrumJob) -> Option<String> {
        crate::jobs::scan_parts::task_payload(job)
    }

    fn part_of(
        whole: &RecordSpectrumJob,
        payload: &serde_json::Value,
    ) -> Option<Result<RecordSpectrumJob, JobError>> {
        crate::jobs::scan_parts::part_of(whole, payload)
    }

    fn is_part(job: &RecordSpectrumJob) -> bool {
        job.part.is_some()
    }

    /// The parts' transitions gathered per size, and everything derived
    /// from them as one task would.
    fn assemble(
        job: &RecordSpectrumJob,
        parts: Vec<crate::jobs::scan_parts::PartDoc>,
    ) -> Result<RecordSpectrumResult, JobError> {
        job.result_of(&parts)
    }
}
