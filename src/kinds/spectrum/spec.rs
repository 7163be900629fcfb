//! A spectrum job's spec as users write it,
//! the validated job, and the validation from one to the other.

use crate::dynamics::{Formulation, PulseShape};
use crate::jobs::names::tag;
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, OMEGA_RATIO_RANGE, PulseSpec, ShapeParams, SolverNorm, SolverSpec,
    SpecError, family_of, in_one_unit, parse_formulation, parse_shape, shape_name,
};
use serde::{Deserialize, Serialize};
/// Default highest amplitude, αg.
pub const DEFAULT_A_MAX: f64 = 20.0;
/// Default bracket width, αg.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// Default scan step, αg.
pub const DEFAULT_SCAN_STEP: f64 = 0.02;
/// Default relative width below which the principal view drops bands.
pub const DEFAULT_PRINCIPAL_WIDTH: f64 = 0.01;
/// Most frequencies in one spectrum.
pub const MAX_FREQUENCIES: usize = 10_000;
/// Most scan points per frequency.
pub const MAX_SCAN_POINTS: f64 = 1e6;

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SpectrumSpec {
    /// "spectrum".
    #[schema(value_type = crate::jobs::names::tag::Spectrum)]
    pub kind: String,
    /// The block.
    #[schema(required = true, value_type = BlockSpec)]
    pub block: Option<BlockSpec>,
    /// The pulse family (`type`, `n`); frequency and amplitude vary.
    #[schema(required = true, value_type = crate::jobs::schema::PulseFamilyInput)]
    pub pulse: Option<PulseSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// ω_p/p values (give this, `omega_p` or `frequency_hz`).
    pub omega_ratio: Option<RangeSpec>,
    /// Pulse circular frequencies ω_p, rad/s.
    pub omega_p: Option<RangeSpec>,
    /// Pulse frequencies f_p = ω_p/2π, Hz.
    pub frequency_hz: Option<RangeSpec>,
    /// Highest amplitude, αg (1 to 1e4, default 20; or give `a_max` or `a_max_g`).
    #[schema(minimum = 1.0, maximum = 1e4)]
    pub a_max_alpha_g: Option<f64>,
    /// Highest amplitude, m/s² (1 to 1e4 αg).
    #[schema(exclusive_minimum = 0.0)]
    pub a_max: Option<f64>,
    /// Highest amplitude, g (1 to 1e4 αg).
    #[schema(exclusive_minimum = 0.0)]
    pub a_max_g: Option<f64>,
    /// Bracket width of each transition, αg (1e-9 to 0.1, default 1e-4).
    #[schema(minimum = 1e-9, maximum = 0.1)]
    pub tolerance: Option<f64>,
    /// Scan step, αg (the tolerance to 1, default 0.02): every band wider than this is found.
    #[schema(minimum = 1e-9, maximum = 1.0)]
    pub scan_step_alpha_g: Option<f64>,
    /// Principal view: drop bands narrower than this fraction of their amplitude (0 to 1, default 0.01).
    #[schema(minimum = 0.0, maximum = 1.0)]
    pub principal_relative_width: Option<f64>,
    /// Solver.
    pub solver: Option<SolverSpec>,
    /// The vertical ground acceleration (positive up), scaled with each
    /// pulse: `{"ratio": r}` (ü_v = r·ü_g), or a pulse of its own `{"type",
    /// "amplitude_ratio" (a_v/a_p), "frequency_ratio" (ω_v/ω_p) | "omega_p" |
    /// "frequency_hz", "delay_s"?}`.
    pub vertical: Option<crate::jobs::vertical::VerticalPulseSpec>,
    /// The contact with the floor: `{"model": "no_sliding"}` (pure rocking,
    /// the default) or `{"model": "coulomb", "mu", "mu_kinetic"?}` (the block
    /// may slide and slide-rock; every amplitude of every frequency is
    /// followed on that floor).
    pub contact: Option<crate::jobs::contact::ContactSpec>,
    /// On a Coulomb floor: also the residual slide at `steps` amplitudes
    /// a_max·k/steps (k = 1…steps) of every frequency, `{"steps": n}`
    /// (1 to 1000, default 40).
    pub residual_slide: Option<ResidualSlideSpec>,
    /// On a Coulomb floor: also the pure-rocking (no-sliding) spectrum over
    /// the same frequencies and amplitudes, in `no_sliding` beside
    /// `spectrum`, and a figure of both side by side (default false; refused
    /// without `contact.model` coulomb: pure rocking is already the
    /// no-sliding spectrum).
    pub no_sliding_beside: Option<bool>,
}

/// The residual-slide spectrum asked for.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ResidualSlideSpec {
    /// Amplitudes per frequency (1 to 1000, default 40).
    #[schema(minimum = 1, maximum = 1000)]
    pub steps: Option<u32>,
}

/// Most amplitudes of a residual-slide line.
pub const MAX_SLIDE_STEPS: u32 = 1000;

/// The pulse family of a spectrum, normalised.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, utoipa::ToSchema)]
pub struct PulseFamily {
    /// Family name.
    #[serde(rename = "type")]
    #[schema(value_type = crate::jobs::schema::PulseTypeName)]
    pub kind: &'static str,
    /// Cycles (cn only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub n: Option<u32>,
    /// Symmetric wavelet or its derivative (ricker only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetric: Option<bool>,
    /// γ (mavroeidis_papageorgiou only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gamma: Option<f64>,
    /// ν, rad, in (−π, π] (mavroeidis_papageorgiou only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nu: Option<f64>,
    /// The family these fields name.
    #[serde(skip)]
    shape: PulseShape,
}

impl PulseFamily {
    /// The family of `shape`, as normalised specs write it.
    pub fn of(shape: PulseShape) -> Self {
        let params = ShapeParams::of(shape);
        PulseFamily {
            kind: shape_name(shape),
            n: params.n,
            symmetric: params.symmetric,
            gamma: params.gamma,
            nu: params.nu,
            shape,
        }
    }

    /// The domain shape.
    pub fn shape(&self) -> PulseShape {
        self.shape
    }
}

/// A [`PulseFamily`] as documents hold it: its name and parameters.
#[derive(Deserialize)]
pub(super) struct PulseFamilyDoc {
    #[serde(rename = "type")]
    kind: String,
    n: Option<u32>,
    symmetric: Option<bool>,
    gamma: Option<f64>,
    nu: Option<f64>,
}

impl<'de> Deserialize<'de> for PulseFamily {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let d = PulseFamilyDoc::deserialize(d)?;
        let params = ShapeParams {
            n: d.n,
            symmetric: d.symmetric,
            gamma: d.gamma,
            nu: d.nu,
        };
        family_of(&d.kind, params)
            .map(PulseFamily::of)
            .map_err(serde::de::Error::custom)
    }
}

/// Validates the pulse of a spectrum job: the family only.
pub fn validate_family(spec: Option<&PulseSpec>, base: &str) -> Result<PulseFamily, SpecError> {
    let spec = crate::jobs::spec::required(spec, base)?;
    for (v, name) in [
        (spec.omega_p, "omega_p"),
        (spec.frequency_hz, "frequency_hz"),
        (spec.omega_ratio, "omega_ratio"),
        (spec.duration_s, "duration_s"),
        (spec.a_p, "a_p"),
        (spec.a_p_g, "a_p_g"),
        (spec.a_p_alpha_g, "a_p_alpha_g"),
    ] {
        if v.is_some() {
            return Err(SpecError::at(
                format!("{base}/{name}"),
                "a spectrum varies frequency and amplitude: give them at the top level (omega_ratio, a_alpha_g / a_max_alpha_g)",
            ));
        }
    }
    Ok(PulseFamily::of(parse_shape(spec, base)?))
}

/// A validated spectrum job; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SpectrumJob {
    /// "spectrum".
    pub kind: tag::Spectrum,
    /// Block.
    pub block: BlockNorm,
    /// Pulse family.
    pub pulse: PulseFamily,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// ω_p/p values.
    pub omega_ratio: Vec<f64>,
    /// Highest amplitude, αg.
    pub a_max_alpha_g: f64,
    /// Bracket width, αg.
    pub tolerance: f64,
    /// Scan step, αg.
    pub scan_step_alpha_g: f64,
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
    /// Amplitudes of the residual-slide spectrum, when asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub residual_slide_steps: Option<u32>,
    /// The pure-rocking spectrum over the same grid too (on a Coulomb
    /// floor), when asked for; absent when not, so a job that does not ask
    /// keeps its key.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub no_sliding_beside: bool,
}

pub(super) fn positive_in(
    v: f64,
    lo: f64,
    hi: f64,
    pointer: &str,
    unit: &str,
) -> Result<f64, SpecError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(SpecError::at(
            pointer,
            format!("must lie in [{lo:e}, {hi}] {unit} (got {v})"),
        ))
    }
}

impl crate::jobs::kind::Validate for SpectrumSpec {
    type Job = SpectrumJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<SpectrumJob, SpecError> {
        let block = crate::jobs::spec::the_block(self.block.as_ref())?;
        let pulse = validate_family(self.pulse.as_ref(), "/pulse")?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let vertical =
            crate::jobs::vertical::validate_scaled_vertical(self.vertical.as_ref(), "/vertical")?;
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            pulse.shape().is_sinusoidal(),
            vertical.is_some(),
            "/solver",
        )?;
        let contact =
            crate::jobs::contact::validate_contact(self.contact.as_ref(), formulation, "/contact")?;
        let residual_slide_steps = self.residual_slide_steps(contact.is_some())?;
        let no_sliding_beside = self.no_sliding_beside(contact.is_some())?;
        let omega_ratio = self.omega_ratios(&block)?;
        let a_max = self.a_max(&block)?;
        let steps = self.scan_steps(a_max)?;
        Ok(SpectrumJob {
            kind: tag::Spectrum,
            block,
            pulse,
            formulation,
            omega_ratio,
            a_max_alpha_g: a_max,
            tolerance: steps.tolerance,
            scan_step_alpha_g: steps.step,
            principal_relative_width: steps.principal,
            solver,
            vertical,
            contact,
            residual_slide_steps,
            no_sliding_beside,
        })
    }
}

/// The scan of a spectrum along the amplitude, validated.
pub(super) struct ScanSteps {
    /// Bracket width, αg.
    tolerance: f64,
    /// Scan step, αg.
    step: f64,
    /// Principal relative width.
    principal: f64,
}

impl SpectrumSpec {
    /// The steps of the residual slide, when asked (only on a floor the
    /// block can slide on, `sliding`).
    fn residual_slide_steps(&self, sliding: bool) -> Result<Option<u32>, SpecError> {
        Ok(match &self.residual_slide {
            None => None,
            Some(_) if !sliding => {
                return Err(SpecError::at(
                    "/residual_slide",
                    "a residual slide needs a floor the block can slide on: give contact {\"model\": \"coulomb\", \"mu\": …}",
                ));
            }
            Some(r) => {
                let steps = r.steps.unwrap_or(40);
                if !(1..=MAX_SLIDE_STEPS).contains(&steps) {
                    return Err(SpecError::at(
                        "/residual_slide/steps",
                        format!("must lie in [1, {MAX_SLIDE_STEPS}]"),
                    ));
                }
                Some(steps)
            }
        })
    }

    /// Whether the spectrum without sliding is asked beside (only on a floor
    /// the block can slide on, `sliding`).
    fn no_sliding_beside(&self, sliding: bool) -> Result<bool, SpecError> {
        let no_sliding_beside = self.no_sliding_beside.unwrap_or(false);
        if no_sliding_beside && !sliding {
            return Err(SpecError::at(
                "/no_sliding_beside",
                "the spectrum without sliding goes beside one on a floor the block can slide on: give contact {\"model\": \"coulomb\", \"mu\": …} (pure rocking is already the no-sliding spectrum)",
            ));
        }
        Ok(no_sliding_beside)
    }

    /// The frequencies, given in any unit, as ω_p/p of `block`, each in
    /// `OMEGA_RATIO_RANGE`.
    fn omega_ratios(&self, block: &BlockNorm) -> Result<Vec<f64>, SpecError> {
        // Frequencies in any unit, normalised to ω_p/p: one job, one cache key.
        let p = block.p;
        let (range, name, to_ratio) = in_one_unit(
            &[
                (self.omega_ratio.as_ref(), "omega_ratio", 1.0),
                (self.omega_p.as_ref(), "omega_p", 1.0 / p),
                (self.frequency_hz.as_ref(), "frequency_hz", std::f64::consts::TAU / p),
            ],
            "frequency axis",
        )?
        .ok_or_else(|| {
            SpecError::at(
                "/omega_ratio",
                "missing field: the frequencies as omega_ratio (ω_p/p), omega_p (rad/s) or frequency_hz: {\"from\", \"to\", \"steps\"} or a list",
            )
        })?;
        let pointer = format!("/{name}");
        let omega_ratio: Vec<f64> = range
            .values(&pointer, 0.0, f64::MAX, MAX_FREQUENCIES)?
            .into_iter()
            .map(|v| v * to_ratio)
            .collect();
        if let Some(bad) = omega_ratio
            .iter()
            .find(|r| !(OMEGA_RATIO_RANGE.0..=OMEGA_RATIO_RANGE.1).contains(*r))
        {
            return Err(SpecError::at(
                pointer,
                format!(
                    "every frequency must give ω_p/p in [{}, {}] for this block (p = {p} rad/s); one gives {bad}",
                    OMEGA_RATIO_RANGE.0, OMEGA_RATIO_RANGE.1
                ),
            ));
        }
        Ok(omega_ratio)
    }

    /// The highest amplitude, αg of `block`, given in αg, m/s² or g, in
    /// [1, 1e4].
    fn a_max(&self, block: &BlockNorm) -> Result<f64, SpecError> {
        let unit_g = block.alpha * block.g;
        let (a_max, a_name) = match in_one_unit(
            &[
                (self.a_max_alpha_g, "a_max_alpha_g", 1.0),
                (self.a_max, "a_max", 1.0 / unit_g),
                (self.a_max_g, "a_max_g", block.g / unit_g),
            ],
            "highest amplitude",
        )? {
            None => (DEFAULT_A_MAX, "a_max_alpha_g"),
            Some((v, name, factor)) => (v * factor, name),
        };
        positive_in(a_max, 1.0, 1e4, &format!("/{a_name}"), "αg")
    }

    /// The tolerance, scan step and principal relative width, each in its
    /// range (the scan up to `a_max`, αg).
    fn scan_steps(&self, a_max: f64) -> Result<ScanSteps, SpecError> {
        let tolerance = positive_in(
            self.tolerance.unwrap_or(DEFAULT_TOLERANCE),
            1e-9,
            0.1,
            "/tolerance",
            "αg",
        )?;
        let step = positive_in(
            self.scan_step_alpha_g.unwrap_or(DEFAULT_SCAN_STEP),
            tolerance,
            1.0,
            "/scan_step_alpha_g",
            "αg (and at least the tolerance)",
        )?;
        if a_max / step > MAX_SCAN_POINTS {
            return Err(SpecError::at(
                "/scan_step_alpha_g",
                format!("a_max_alpha_g / scan_step_alpha_g must not exceed {MAX_SCAN_POINTS:e}"),
            ));
        }
        let principal = positive_in(
            self.principal_relative_width
                .unwrap_or(DEFAULT_PRINCIPAL_WIDTH),
            0.0,
            1.0,
            "/principal_relative_width",
            "",
        )?;
        Ok(ScanSteps {
            tolerance,
            step,
            principal,
        })
    }
}
