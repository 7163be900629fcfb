//! A record spectrum job's spec as users write it,
//! the validated job, and the validation from one to the other.

use crate::dynamics::Formulation;
use crate::jobs::names::tag;
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, GroundMotionNorm, GroundMotionSpec, SolverNorm, SolverSpec, SpecError,
    at_most_one, in_one_unit, parse_formulation, validate_block,
};
use crate::jobs::vertical::ScaledVertical;
use crate::spectrum::overturning::threshold_alpha_g_of;
use serde::{Deserialize, Serialize};
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
pub(super) fn threshold_of(
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
        })
    }
}

/// A record's scale factors against its levels (a level is the scaled PGA
/// in αg).
pub(super) struct RecordLevels {
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
pub(super) struct SearchSteps {
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
pub(super) fn check_highest_scale(
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
