//! The `spectrum` job: overturning spectra (paper Figs. 6, 10, 11).

pub mod figure;
pub mod table;

mod concatenate;

use serde::{Deserialize, Serialize};

use crate::dynamics::{Formulation, Pulse, PulseShape, SimError};
use crate::jobs::names::{EngineDoc, tag};
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, BlockSpec, OMEGA_RATIO_RANGE, PulseSpec, ShapeParams, SolverNorm, SolverSpec,
    SpecError, family_of, in_one_unit, parse_formulation, parse_shape, shape_name,
};
use crate::spectrum::overturning::Derived;
use crate::spectrum::scan::{Direction, ModeChange, ScanStats, Transition};
use crate::spectrum::{Control, SpectrumRequest, overturning_spectrum};

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
struct PulseFamilyDoc {
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

fn positive_in(v: f64, lo: f64, hi: f64, pointer: &str, unit: &str) -> Result<f64, SpecError> {
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
struct ScanSteps {
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
    fn new(t: &Transition, alpha: f64) -> Self {
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

fn intervals(d: &Derived) -> Vec<[f64; 2]> {
    d.safe_intervals.iter().map(|&(a, b)| [a, b]).collect()
}

impl SpectrumJob {
    /// ü_v/ü_g, when the job has a vertical motion.
    pub fn vertical_ratio(&self) -> Option<f64> {
        self.vertical.as_ref().and_then(|v| v.ratio())
    }

    /// The residual-slide lines, one per frequency, when asked for (on a
    /// Coulomb floor), and what they cost.
    #[allow(clippy::type_complexity)]
    fn residual_slides(
        &self,
        req: &SpectrumRequest,
        control: &Control,
    ) -> Result<Option<(Vec<Vec<SlidePointDoc>>, ScanStats)>, crate::spectrum::scan::ScanError>
    {
        use crate::dynamics::{Options, Problem, PulsePair};
        use crate::spectrum::scan::ScanError;
        use crate::spectrum::slide::{Fate, SlidePoint, residual_slide};
        let (Some(steps), Some(friction)) = (self.residual_slide_steps, req.friction) else {
            return Ok(None);
        };
        let levels: Vec<f64> = (1..=steps)
            .map(|k| req.a_max * f64::from(k) / f64::from(steps))
            .collect();
        let bad = || ScanError::Simulation(SimError::Tolerance);
        let pulses = crate::spectrum::overturning::line_pulses(req)?;
        fn on<G>(req: &SpectrumRequest, pulse: G) -> Problem<G> {
            Problem {
                block: req.block,
                pulse,
                formulation: req.formulation,
            }
        }
        let options = Options::outcome(req.solver);
        let own = self.vertical.as_ref().and_then(|v| v.scaled_pulse());
        let (lines, stats) = match (own, req.vertical_ratio) {
            (Some(v), _) => {
                let pairs = pulses
                    .into_iter()
                    .map(|p| v.pair(p).map(|q| on(req, q)))
                    .collect::<Result<Vec<_>, ScanError>>()?;
                residual_slide(&pairs, &options, friction, &levels, control)?
            }
            (None, Some(r)) => {
                let pairs = pulses
                    .into_iter()
                    .map(|p| {
                        PulsePair::proportional(p, r)
                            .map(|q| on(req, q))
                            .ok_or_else(bad)
                    })
                    .collect::<Result<Vec<_>, ScanError>>()?;
                residual_slide(&pairs, &options, friction, &levels, control)?
            }
            (None, None) => {
                let problems: Vec<_> = pulses.into_iter().map(|q| on(req, q)).collect();
                residual_slide(&problems, &options, friction, &levels, control)?
            }
        };
        let doc = |p: &SlidePoint| SlidePointDoc {
            a_alpha_g: p.level,
            residual_slide_m: p.residual,
            peak_slide_m: p.peak,
            outcome: match p.fate {
                Fate::Stands => "stands",
                Fate::Overturns => "overturns",
            }
            .to_string(),
        };
        Ok(Some((
            lines.iter().map(|l| l.iter().map(doc).collect()).collect(),
            stats,
        )))
    }

    /// The same job on a floor the block cannot slide on: what the same
    /// spec without `contact` validates to. `Some` when the spectrum beside
    /// this one is asked for.
    pub fn pure_rocking(&self) -> Option<SpectrumJob> {
        (self.no_sliding_beside && self.contact.is_some()).then(|| SpectrumJob {
            contact: None,
            residual_slide_steps: None,
            no_sliding_beside: false,
            ..self.clone()
        })
    }

    /// Runs the job under `control`: its lines, and with
    /// `no_sliding_beside` the lines of [`SpectrumJob::pure_rocking`] by the
    /// same path, their costs summed.
    pub fn run(
        &self,
        control: &Control,
    ) -> Result<SpectrumResult, crate::spectrum::scan::ScanError> {
        let (spectrum, mut stats, mut wall_time) = self.lines(control)?;
        let no_sliding = match self.pure_rocking() {
            Some(pure) => {
                let (lines, pure_stats, pure_wall) = pure.lines(control)?;
                stats.absorb(&pure_stats);
                wall_time += pure_wall;
                lines
            }
            None => Vec::new(),
        };
        Ok(SpectrumResult {
            warnings: Vec::new(),
            kind: tag::Spectrum,
            spectrum,
            no_sliding,
            numerics: SpectrumNumerics::new(
                &self.solver,
                &stats,
                self.tolerance,
                self.scan_step_alpha_g,
                wall_time,
            ),
            spec: self.clone(),
            engine: None,
        })
    }

    /// The lines of the job's spectrum (with their residual slides when
    /// asked for), what they cost and the scan's wall time, s.
    fn lines(
        &self,
        control: &Control,
    ) -> Result<(Vec<FrequencyDoc>, ScanStats, f64), crate::spectrum::scan::ScanError> {
        let formulation = self.formulation;
        let block = self.block.block().map_err(SimError::from)?;
        let req = SpectrumRequest {
            block,
            shape: self.pulse.shape(),
            formulation,
            solver: self.solver.solver(),
            omega_ratios: self.omega_ratio.clone(),
            a_max: self.a_max_alpha_g,
            tolerance: self.tolerance,
            scan_step: self.scan_step_alpha_g,
            principal_relative_width: self.principal_relative_width,
            vertical_ratio: self.vertical_ratio(),
            friction: self.contact.as_ref().map(|c| c.friction()),
        };
        let s = match self.vertical.as_ref().and_then(|v| v.scaled_pulse()) {
            Some(v) => crate::spectrum::overturning::overturning_spectrum_under(&req, &v, control)?,
            None => overturning_spectrum(&req, control)?,
        };
        let alpha = self.block.alpha;
        let mut stats = s.stats;
        let mut slides = match self.residual_slides(&req, control)? {
            Some((lines, slide_stats)) => {
                stats.absorb(&slide_stats);
                Some(lines.into_iter())
            }
            None => None,
        };
        let spectrum = s
            .lines
            .iter()
            .map(|l| FrequencyDoc {
                residual_slide: slides.as_mut().and_then(|lines| lines.next()),
                omega_ratio: l.omega_ratio,
                threshold_alpha_g: l.threshold,
                threshold_g: l.threshold * alpha,
                transitions: l
                    .transitions
                    .iter()
                    .map(|t| TransitionDoc::new(t, alpha))
                    .collect(),
                mode_changes: l.mode_changes.iter().map(ModeChangeDoc::from).collect(),
                min_overturn_alpha_g: l.derived.min_overturn,
                min_overturn_mode: l.derived.min_overturn_mode,
                safe_intervals: intervals(&l.derived),
                overturns_above_alpha_g: l.derived.overturns_above,
                principal: PrincipalDoc {
                    transitions: l
                        .principal_transitions
                        .iter()
                        .map(|t| TransitionDoc::new(t, alpha))
                        .collect(),
                    min_overturn_alpha_g: l.principal.min_overturn,
                    min_overturn_mode: l.principal.min_overturn_mode,
                    safe_intervals: intervals(&l.principal),
                    overturns_above_alpha_g: l.principal.overturns_above,
                },
                mixed: l
                    .mixed
                    .iter()
                    .map(|z| crate::jobs::mixed::MixedDoc::overturning(z, 1.0))
                    .collect(),
                min_overturn_in: crate::jobs::mixed::minimum_place(&l.derived, 1.0).0,
                min_overturn_zone: crate::jobs::mixed::minimum_place(&l.derived, 1.0).1,
                min_certain_overturn_alpha_g: l.derived.min_certain_overturn,
                eq21_alpha_g: l.eq21,
                closed_form_mode2_alpha_g: l.mode2_closed_form,
                lift_off_above_alpha_g: l.lift_off_above,
                omega_p: l.omega_ratio * self.block.p,
                frequency_hz: l.omega_ratio * self.block.p / std::f64::consts::TAU,
                min_overturn_g: l.derived.min_overturn.map(|a| a * self.block.alpha),
                min_overturn_m_s2: l
                    .derived
                    .min_overturn
                    .map(|a| a * self.block.alpha * self.block.g),
                ground: PulseScalesDoc::of(self.pulse.shape(), l.omega_ratio * self.block.p),
            })
            .collect();
        Ok((spectrum, stats, s.wall_time))
    }
}

/// The `spectrum` kind: the overturning spectrum of a block under a pulse
/// family.
pub struct Spectrum;

impl crate::kinds::kind::Kind for Spectrum {
    const NAME: &'static str = crate::jobs::names::tag::Spectrum::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Overturning spectrum";
    type Spec = SpectrumSpec;
    type Job = SpectrumJob;
    type Result = SpectrumResult;
    type Part = SpectrumResult;

    fn run(
        job: &SpectrumJob,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, crate::jobs::JobError> {
        Ok(crate::kinds::kind::Output::Whole(job.run(control)?))
    }
    fn table(
        result: &SpectrumResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &SpectrumResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    fn size(job: &SpectrumJob) -> crate::jobs::kind::Size {
        use crate::jobs::cost;
        let scan = (job.a_max_alpha_g / job.scan_step_alpha_g).ceil();
        let line = cost::pulse_line_simulations(scan, job.scan_step_alpha_g, job.tolerance);
        // A residual-slide line adds its amplitudes, each a whole history.
        let per_frequency = line + f64::from(job.residual_slide_steps.unwrap_or(0));
        let n = job.omega_ratio.len() as f64;
        let on_floor = n * per_frequency;
        // The pure-rocking spectrum beside it scans the same grid again, at
        // pure rocking's cost, after the other (the lanes stay).
        let beside = job.pure_rocking().map_or(0.0, |_| n * line);
        let per_simulation = cost::contact_factor(job.contact.as_ref());
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: (n * scan).min(usize::MAX as f64) as usize,
            work: on_floor + beside,
            record_work: 0.0,
            cpu_s: (on_floor * per_simulation + beside * cost::contact_factor(None))
                * cost::pulse_simulation_s(&job.pulse.shape(), job.formulation, job.solver.method),
            lanes: n * (scan / 48.0).ceil(),
        }
    }

    fn grid_field(_job: &SpectrumJob) -> &'static str {
        "/omega_ratio"
    }

    fn warnings(job: &SpectrumJob) -> Vec<crate::jobs::warning::WarningDoc> {
        crate::jobs::plausible::size_warning(&job.block, "/block")
            .into_iter()
            .collect()
    }

    /// One task per chunk of frequencies of about
    /// [`crate::jobs::split::TASK_CPU_S`].
    fn split(job: &SpectrumJob, size: &crate::jobs::kind::Size) -> Vec<SpectrumJob> {
        let n = job.omega_ratio.len();
        if n <= 1 {
            return vec![job.clone()];
        }
        let per = crate::jobs::split::per_task(n, size.cpu_s / n as f64);
        job.omega_ratio
            .chunks(per)
            .map(|chunk| SpectrumJob {
                omega_ratio: chunk.to_vec(),
                ..job.clone()
            })
            .collect()
    }

    fn assemble(
        job: &SpectrumJob,
        parts: Vec<SpectrumResult>,
    ) -> Result<SpectrumResult, crate::jobs::JobError> {
        Ok(concatenate::concatenate(job, parts))
    }
}

#[cfg(test)]
mod tests {
    use serde_json::{Value, json};

    use crate::kinds::Job;
    use crate::kinds::key::cache_key;
    use crate::spectrum::Control;

    fn spectrum(axes: Value) -> Result<Job, crate::jobs::spec::SpecError> {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.0, "eta": 0.9},
                              "pulse": {"type": "one_sine"}, "formulation": "linear"});
        for (k, v) in axes.as_object().expect("object") {
            spec[k] = v.clone();
        }
        Job::from_value(&spec)
    }

    #[test]
    fn frequencies_and_amplitudes_in_any_unit_make_the_same_job() {
        let tau = std::f64::consts::TAU;
        let reference =
            spectrum(json!({"omega_ratio": [1.0, 3.0], "a_max_alpha_g": 8.0})).expect("valid");
        for axes in [
            json!({"omega_p": [2.0, 6.0], "a_max_g": 2.0}),
            json!({"frequency_hz": [2.0 / tau, 6.0 / tau], "a_max": 8.0 * 0.25 * 9.81}),
            json!({"omega_ratio": {"from": 1, "to": 3, "steps": 2}, "a_max_alpha_g": 8}),
        ] {
            let job = spectrum(axes.clone()).expect("valid");
            assert_eq!(cache_key(&job), cache_key(&reference), "{axes}");
        }
    }

    #[test]
    fn a_frequency_axis_is_given_once_and_named_when_wrong() {
        let e = spectrum(json!({"omega_ratio": [1.0], "frequency_hz": [0.5]})).expect_err("twice");
        assert_eq!(e.pointer, "/frequency_hz");
        let e = spectrum(json!({"a_max_alpha_g": 5, "a_max_g": 1})).expect_err("no frequencies");
        assert_eq!(e.pointer, "/omega_ratio");
        let e = spectrum(json!({"omega_p": [2.0], "a_max_alpha_g": 5, "a_max_g": 1}))
            .expect_err("two maxima");
        assert_eq!(e.pointer, "/a_max_g");
        // 1e5 rad/s on a block of p = 2 is ω_p/p = 5e4, above the accepted range.
        let e = spectrum(json!({"omega_p": [1e5]})).expect_err("out of range");
        assert_eq!(e.pointer, "/omega_p");
        assert!(e.message.contains("p = 2 rad/s"), "{}", e.message);
    }

    fn coulomb(mu: Option<f64>, alpha: f64, shape: &str, ratios: Value, a_max: f64) -> Value {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": alpha, "p": 2.14},
                              "pulse": {"type": shape}, "omega_ratio": ratios,
                              "a_max_alpha_g": a_max, "tolerance": 1e-3, "scan_step_alpha_g": 0.05});
        if let Some(mu) = mu {
            spec["contact"] = json!({"model": "coulomb", "mu": mu});
        }
        let job = Job::from_value(&spec).expect("valid");
        job.run(&Control::new()).expect("runs")
    }

    #[test]
    fn a_coulomb_spectrum_follows_the_floor() {
        // μ = 10 is never reached below these minima: the same lowest
        // overturning amplitude as pure rocking.
        let (pure, rough) = (
            coulomb(None, 0.25, "one_sine", json!([2.0, 4.0]), 6.0),
            coulomb(Some(10.0), 0.25, "one_sine", json!([2.0, 4.0]), 6.0),
        );
        for k in 0..2 {
            let (a, b) = (
                &pure["spectrum"][k]["min_overturn_alpha_g"],
                &rough["spectrum"][k]["min_overturn_alpha_g"],
            );
            assert!(a.as_f64().is_some() && a == b, "{a} vs {b}");
        }
        assert_eq!(rough["spec"]["contact"]["mu"], 10.0);
        // Below tan α the block only slides: nothing overturns.
        let smooth = coulomb(Some(0.2), 0.25, "one_sine", json!([2.0, 4.0]), 6.0);
        for line in smooth["spectrum"].as_array().expect("lines") {
            assert!(line["min_overturn_alpha_g"].is_null(), "{line}");
            assert!(line["transitions"].as_array().expect("list").is_empty());
        }
        // The residual slide on a grid of amplitudes: none below μg (nothing
        // moves), the block's slip growing with the pulse above, as the
        // history on that floor says.
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine"}, "omega_ratio": [3.0], "a_max_alpha_g": 4.0,
            "contact": {"model": "coulomb", "mu": 0.2}, "residual_slide": {"steps": 8}});
        let doc = Job::from_value(&spec)
            .expect("valid")
            .run(&Control::new())
            .expect("runs");
        let line = doc["spectrum"][0]["residual_slide"]
            .as_array()
            .expect("asked");
        assert_eq!(line.len(), 8);
        let at = |k: usize| line[k]["residual_slide_m"].as_f64().expect("m");
        assert_eq!(line[0]["a_alpha_g"], 0.5);
        assert_eq!(at(0), 0.0, "0.5 αg = 0.125 g < μ g");
        assert!(line.iter().all(|p| p["outcome"] == "stands"));
        let th = Job::from_value(&json!({"kind": "time_history",
            "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0},
            "contact": {"model": "coulomb", "mu": 0.2}}))
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
        assert_eq!(at(7), th["residual_slide_m"].as_f64().expect("m"));
        assert!(at(7).abs() > at(3).abs() && at(3).abs() > 0.0);
        // Only on a floor the block can slide on.
        spec.as_object_mut().expect("object").remove("contact");
        let e = Job::from_value(&spec).expect_err("no floor");
        assert_eq!(e.pointer, "/residual_slide");
        // A squat block under strong one-cosine pulses leaves the floor
        // (the normal force reaches 0): its flights are followed, so the
        // line claims the whole range, and where its history flies the
        // line says what that history says.
        let contact = json!({"model": "coulomb", "mu": 0.6, "mu_kinetic": 0.5});
        let squat = Job::from_value(&json!({"kind": "spectrum",
            "block": {"alpha": 0.4, "p": 2.14}, "pulse": {"type": "one_cosine"},
            "omega_ratio": [2.0], "a_max_alpha_g": 10.0, "tolerance": 1e-3,
            "scan_step_alpha_g": 0.05, "contact": contact}))
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
        let line = &squat["spectrum"][0];
        assert!(line["lift_off_above_alpha_g"].is_null(), "{line}");
        let th = Job::from_value(&json!({"kind": "time_history",
            "block": {"alpha": 0.4, "p": 2.14},
            "pulse": {"type": "one_cosine", "omega_ratio": 2.0, "a_p_alpha_g": 8.0},
            "contact": contact}))
        .expect("valid")
        .run(&Control::new())
        .expect("runs");
        assert!(th["flights"].as_u64().expect("counted") >= 1, "{th}");
        assert!(th["time_in_flight_s"].as_f64().expect("s") > 0.1, "{th}");
        let overturns_at_8 = line["transitions"]
            .as_array()
            .expect("list")
            .iter()
            .rfind(|t| t["a_alpha_g"].as_f64().expect("at") < 8.0)
            .is_some_and(|t| t["direction"] == "up");
        assert!(overturns_at_8 && th["overturned"] == true, "{line}");
    }

    /// The locomotive's one-sine spectrum on a coarse grid (tolerance
    /// 1e-3 αg, step 0.05 αg) at `ratios` up to `a_max` αg, on a Coulomb
    /// floor of `mu` when given, with `extra` fields.
    fn locomotive(mu: Option<f64>, ratios: Value, a_max: f64, extra: Value) -> Value {
        let mut spec = json!({"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
                              "pulse": {"type": "one_sine"}, "omega_ratio": ratios,
                              "a_max_alpha_g": a_max, "tolerance": 1e-3, "scan_step_alpha_g": 0.05});
        if let Some(mu) = mu {
            spec["contact"] = json!({"model": "coulomb", "mu": mu});
        }
        for (k, v) in extra.as_object().expect("object") {
            spec[k] = v.clone();
        }
        spec
    }

    fn run(spec: &Value) -> Value {
        Job::from_value(spec)
            .expect("valid")
            .run(&Control::new())
            .expect("runs")
    }

    #[test]
    fn the_spectrum_beside_a_floor_never_reached_is_the_pure_rocking_spectrum() {
        let beside = json!({"no_sliding_beside": true});
        let rough = run(&locomotive(Some(10.0), json!([2.0, 4.0]), 6.0, beside));
        let alone = run(&locomotive(Some(10.0), json!([2.0, 4.0]), 6.0, json!({})));
        let pure = run(&locomotive(None, json!([2.0, 4.0]), 6.0, json!({})));
        // Bit for bit what the same spec without contact computes; the
        // spectrum on the floor unchanged by asking.
        assert_eq!(rough["no_sliding"], pure["spectrum"]);
        assert_eq!(rough["spectrum"], alone["spectrum"]);
        assert_eq!(rough["spec"]["no_sliding_beside"], true);
        // Its cost counted: the simulations of both spectra.
        let simulations = |doc: &Value| doc["numerics"]["simulations"].as_u64().expect("count");
        assert_eq!(
            simulations(&rough),
            simulations(&alone) + simulations(&pure)
        );
        // Not asked: no field, neither in the result nor in its spec.
        assert!(alone.get("no_sliding").is_none());
        assert!(alone["spec"].get("no_sliding_beside").is_none());
    }

    #[test]
    fn the_spectrum_beside_mu_0_3_is_pure_rocking_and_differs_from_the_floor() {
        // The locomotive (README): on μ = 0.3 the same lowest overturning
        // as pure rocking at ω_p/p = 3, none up to 6 αg at ω_p/p = 6
        // (pure rocking: 4.737 αg).
        let beside = json!({"no_sliding_beside": true});
        let doc = run(&locomotive(Some(0.3), json!([3.0, 6.0]), 6.0, beside));
        let pure = run(&locomotive(None, json!([3.0, 6.0]), 6.0, json!({})));
        assert_eq!(doc["no_sliding"], pure["spectrum"]);
        assert_ne!(doc["no_sliding"], doc["spectrum"]);
        let min = |lines: &Value, k: usize| lines[k]["min_overturn_alpha_g"].as_f64();
        let (sliding, rocking) = (&doc["spectrum"], &doc["no_sliding"]);
        assert_eq!(min(sliding, 0), min(rocking, 0));
        assert!(min(rocking, 1).is_some_and(|a| (a - 4.737).abs() < 0.01));
        assert_eq!(min(sliding, 1), None);
    }

    #[test]
    fn the_spectrum_beside_needs_a_coulomb_floor_and_not_asking_keeps_the_key() {
        let ratios = json!([2.0]);
        let e = Job::from_value(&locomotive(
            None,
            ratios.clone(),
            4.0,
            json!({"no_sliding_beside": true}),
        ))
        .expect_err("pure rocking is already the no-sliding spectrum");
        assert_eq!(e.pointer, "/no_sliding_beside");
        let e = Job::from_value(&locomotive(
            None,
            ratios.clone(),
            4.0,
            json!({"contact": {"model": "no_sliding"}, "no_sliding_beside": true}),
        ))
        .expect_err("pure rocking by name");
        assert_eq!(e.pointer, "/no_sliding_beside");
        // false (or null) is the default: the job and its key unchanged.
        for mu in [None, Some(0.3)] {
            let plain =
                Job::from_value(&locomotive(mu, ratios.clone(), 4.0, json!({}))).expect("valid");
            for off in [json!(false), Value::Null] {
                let job = Job::from_value(&locomotive(
                    mu,
                    ratios.clone(),
                    4.0,
                    json!({"no_sliding_beside": off}),
                ))
                .expect("valid");
                assert_eq!(job, plain);
                assert_eq!(cache_key(&job), cache_key(&plain));
                assert!(!crate::kinds::key::canonical_spec(&job).contains("no_sliding_beside"));
            }
        }
        // Asked for: another job, another key; its normalised spec
        // validates to itself.
        let asked = locomotive(Some(0.3), ratios, 4.0, json!({"no_sliding_beside": true}));
        let job = Job::from_value(&asked).expect("valid");
        let plain =
            Job::from_value(&locomotive(Some(0.3), json!([2.0]), 4.0, json!({}))).expect("valid");
        assert_ne!(cache_key(&job), cache_key(&plain));
        let again =
            Job::from_value(&serde_json::to_value(&job).expect("serialises")).expect("valid");
        assert_eq!(again, job);
        // Its cost: the floor's scans and pure rocking's, at 1×.
        let (with, without) = (job.size(), plain.size());
        assert!(with.work > without.work && with.cpu_s > without.cpu_s);
        let pure = Job::from_value(&locomotive(None, json!([2.0]), 4.0, json!({}))).expect("valid");
        let size = pure.size();
        assert!((with.cpu_s - without.cpu_s - size.cpu_s).abs() < 1e-12 * with.cpu_s);
        assert_eq!(with.work - without.work, size.work);
        // What runs beside it is that job: the spec without `contact`.
        let (Job::Spectrum(asked), Job::Spectrum(pure)) = (&job, &pure) else {
            panic!("spectra");
        };
        assert_eq!(asked.pure_rocking().as_ref(), Some(pure.as_ref()));
    }

    #[test]
    fn every_frequency_echoes_its_dimensional_values() {
        let job = spectrum(json!({"frequency_hz": [0.5], "a_max_g": 2.0})).expect("valid");
        let doc = job.run(&Control::new()).expect("runs");
        let line = &doc["spectrum"][0];
        let ratio = line["omega_ratio"].as_f64().expect("ratio");
        assert!(
            (ratio - std::f64::consts::PI / 2.0).abs() < 1e-12,
            "{ratio}"
        );
        assert!((line["omega_p"].as_f64().expect("omega_p") - std::f64::consts::PI).abs() < 1e-12);
        assert!((line["frequency_hz"].as_f64().expect("hz") - 0.5).abs() < 1e-12);
        let min = line["min_overturn_alpha_g"]
            .as_f64()
            .expect("overturns below 8 αg");
        let g = line["min_overturn_g"].as_f64().expect("in g");
        let si = line["min_overturn_m_s2"].as_f64().expect("in m/s²");
        assert!((g - 0.25 * min).abs() < 1e-12 && (si - 0.25 * 9.81 * min).abs() < 1e-9);
        // Every transition and the rocking threshold in g as well as αg.
        let transitions = line["transitions"].as_array().expect("transitions");
        assert!(!transitions.is_empty());
        for t in transitions {
            let (a, a_g) = (t["a_alpha_g"].as_f64(), t["a_g"].as_f64());
            let (a, a_g) = (a.expect("αg"), a_g.expect("g"));
            assert!((a_g - 0.25 * a).abs() < 1e-12, "{a} αg, {a_g} g");
        }
        let threshold = line["threshold_alpha_g"].as_f64().expect("αg");
        assert!((line["threshold_g"].as_f64().expect("g") - 0.25 * threshold).abs() < 1e-12);
    }
}
