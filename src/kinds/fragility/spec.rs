//! A fragility job's spec as users write it,
//! the validated job, and the validation from one to the other.

use crate::dynamics::Formulation;
use crate::jobs::distribution::{DistributionNorm, DistributionSpec};
use crate::jobs::names::{Im, tag};
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, GroundMotionNorm, GroundMotionSpec, PulseSpec, SolverNorm, SolverSpec, SpecError,
    parse_formulation, parse_shape,
};
use crate::kinds::spectrum::PulseFamily;
use serde::{Deserialize, Serialize};
use serde_json::Value;
/// Samples per chunk: the unit of seeding (and of a task's work).
pub const CHUNK: usize = 64;
/// Most samples per stripe.
pub const MAX_SAMPLES: u32 = 100_000;
/// Most stripes.
pub const MAX_STRIPES: usize = 200;
/// Most records in a suite.
pub const MAX_MOTIONS: usize = 100;
/// Longest name of a suite's record, characters (as an uploaded record's).
pub(super) const MAX_NAME_CHARS: usize = crate::records::MAX_NAME_CHARS;
/// Bootstrap replicates of the fit.
pub const BOOTSTRAP: usize = 200;
/// The 95 % normal quantile.
pub(super) const Z95: f64 = 1.959_963_984_540_054;

/// A number, or a distribution of it.
#[derive(Deserialize, utoipa::ToSchema)]
#[serde(untagged)]
#[allow(dead_code)]
pub enum UncertainInput {
    /// A fixed value.
    Fixed(f64),
    /// A distribution.
    Distribution(DistributionSpec),
}

/// A value, or its distribution, normalised.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
#[serde(untagged)]
pub enum UncertainNorm {
    /// Fixed.
    Fixed(f64),
    /// Distributed.
    Distribution(DistributionNorm),
}

impl UncertainNorm {
    /// The value at probability `u`.
    pub(super) fn at(&self, u: f64) -> f64 {
        match self {
            UncertainNorm::Fixed(x) => *x,
            UncertainNorm::Distribution(d) => d.distribution().sample(u),
        }
    }
}

/// The block as users write it: each of α, p, η (or b, h, η) a number or a distribution.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct UncertainBlockSpec {
    /// Slenderness α, rad.
    #[schema(value_type = Option<UncertainInput>)]
    pub alpha: Option<Value>,
    /// Frequency parameter p, rad/s.
    #[schema(value_type = Option<UncertainInput>)]
    pub p: Option<Value>,
    /// Half-width b, m (with h, instead of α and p).
    #[schema(value_type = Option<UncertainInput>)]
    pub b: Option<Value>,
    /// Half-height h, m.
    #[schema(value_type = Option<UncertainInput>)]
    pub h: Option<Value>,
    /// Restitution η (default 1 − 1.5 sin²α of each sample).
    #[schema(value_type = Option<UncertainInput>)]
    pub eta: Option<Value>,
    /// Gravity, m/s² (default 9.81).
    #[schema(exclusive_minimum = 0.0)]
    pub g: Option<f64>,
}

/// The pulse family as users write it: its type and parameters, the frequency
/// a number or a distribution; the amplitude is the stripe's.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct UncertainPulseSpec {
    /// Pulse type, as for time histories.
    #[serde(rename = "type")]
    #[schema(required = true, value_type = crate::jobs::schema::PulseTypeInput)]
    pub kind: Option<String>,
    /// Cycles (cn).
    pub n: Option<u32>,
    /// Ricker: symmetric (default) or antisymmetric.
    pub symmetric: Option<bool>,
    /// Mavroeidis–Papageorgiou γ.
    pub gamma: Option<f64>,
    /// Mavroeidis–Papageorgiou ν, rad.
    pub nu: Option<f64>,
    /// ω_p, rad/s.
    #[schema(value_type = Option<UncertainInput>)]
    pub omega_p: Option<Value>,
    /// f_p, Hz.
    #[schema(value_type = Option<UncertainInput>)]
    pub frequency_hz: Option<Value>,
    /// ω_p/p (of each sample's block).
    #[schema(value_type = Option<UncertainInput>)]
    pub omega_ratio: Option<Value>,
}

/// A record of a suite.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct NamedMotionSpec {
    /// Its name (at most 200 characters).
    #[schema(max_length = 200)]
    pub name: Option<String>,
    /// Sampling interval, s (1e-5 <= dt <= 1).
    #[schema(minimum = 1e-5, maximum = 1.0)]
    pub dt: Option<f64>,
    /// Accelerations (2 to 1000000 samples).
    #[schema(min_items = 2, max_items = 1_000_000)]
    pub acc: Option<Vec<f64>>,
    /// "g" | "m/s2" | "cm/s2".
    #[schema(value_type = Option<crate::jobs::schema::UnitInput>)]
    pub unit: Option<String>,
    /// A stored record, by id, instead of the samples (as a `ground_motion`'s).
    #[schema(pattern = "^[0-9a-f]{32}$")]
    pub record: Option<String>,
    /// A record file (`topple run` only, as a `ground_motion`'s).
    pub file: Option<String>,
    /// A PGA above 5 g in the samples' unit is intended.
    pub allow_large_pga: Option<bool>,
    /// Its vertical acceleration (positive up): samples on its dt, a stored
    /// record by id, or `{"ratio": r}`; scaled with it.
    pub vertical: Option<crate::jobs::vertical::VerticalRecordSpec>,
}

/// The vertical ground motion of a campaign as users write it.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct UncertainVerticalSpec {
    /// ü_v/ü_g (−100 to 100), in phase with the horizontal motion: a number
    /// or a distribution (each sample draws its own).
    #[schema(required = true, value_type = UncertainInput)]
    pub ratio: Option<Value>,
}

/// The vertical ground motion of a campaign, normalised.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct UncertainVerticalNorm {
    /// ü_v/ü_g.
    pub ratio: UncertainNorm,
}

/// The spec as users write it.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FragilitySpec {
    /// "fragility".
    #[schema(value_type = crate::jobs::names::tag::Fragility)]
    pub kind: String,
    /// The block (uncertain).
    #[schema(required = true, value_type = UncertainBlockSpec)]
    pub block: Option<UncertainBlockSpec>,
    /// A pulse family with its (uncertain) frequency; or give `ground_motions`.
    pub pulse: Option<UncertainPulseSpec>,
    /// A suite of records, each scaled to the stripe's intensity; sample j
    /// of a stripe takes record j mod N.
    #[schema(min_items = 1, max_items = 100)]
    pub ground_motions: Option<Vec<NamedMotionSpec>>,
    /// The vertical ground acceleration as a share of the horizontal one,
    /// `{"ratio": r}` (r a number or a distribution), for the pulse family
    /// or every record of the suite; scaled with the stripe's intensity.
    pub vertical: Option<UncertainVerticalSpec>,
    /// The contact with the floor: `{"model": "no_sliding"}` (pure rocking,
    /// the default) or `{"model": "coulomb", "mu", "mu_kinetic"?}` (every
    /// sample followed on that floor; a sample whose block leaves the floor
    /// counts as lift-off, no verdict).
    pub contact: Option<crate::jobs::contact::ContactSpec>,
    /// "linear" | "nonlinear" (default).
    #[schema(value_type = Option<crate::jobs::schema::FormulationName>)]
    pub formulation: Option<String>,
    /// The intensity measure: "pga_g" (default) or "pgv_m_s".
    #[schema(value_type = Option<crate::kinds::survival::ImName>)]
    pub im: Option<String>,
    /// Intensity levels: a list or `{"from", "to", "steps"}` (at most 200).
    #[schema(required = true, value_type = RangeSpec)]
    pub stripes: Option<RangeSpec>,
    /// Simulations per stripe (default 200, at most 100,000).
    #[schema(minimum = 1, maximum = 100000)]
    pub samples: Option<u32>,
    /// Seed of the random streams (default 1; part of the cache key).
    pub seed: Option<u64>,
    /// Solver.
    pub solver: Option<SolverSpec>,
}

/// The block, normalised.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct UncertainBlockNorm {
    /// α (with p), rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<UncertainNorm>,
    /// p, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p: Option<UncertainNorm>,
    /// b (with h), m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub b: Option<UncertainNorm>,
    /// h, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h: Option<UncertainNorm>,
    /// η (absent: each sample's 1 − 1.5 sin²α).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eta: Option<UncertainNorm>,
    /// g, m/s².
    pub g: f64,
}

/// The pulse, normalised.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct UncertainPulseNorm {
    /// The family.
    #[serde(flatten)]
    pub family: PulseFamily,
    /// ω_p, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub omega_p: Option<UncertainNorm>,
    /// ω_p/p.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub omega_ratio: Option<UncertainNorm>,
}

/// A record of the suite, normalised.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct NamedMotionNorm {
    /// Its name.
    pub name: String,
    /// The record.
    #[serde(flatten)]
    pub motion: GroundMotionNorm,
}

/// A validated fragility job; serialises to the canonical spec.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FragilityJob {
    /// "fragility".
    pub kind: tag::Fragility,
    /// The block.
    pub block: UncertainBlockNorm,
    /// The pulse family.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulse: Option<UncertainPulseNorm>,
    /// The suite.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_motions: Option<Vec<NamedMotionNorm>>,
    /// ü_v = r ü_g (absent: none, or each record's own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical: Option<UncertainVerticalNorm>,
    /// "linear" | "nonlinear".
    #[serde(with = "crate::jobs::names::formulation")]
    #[schema(value_type = crate::jobs::schema::FormulationName)]
    pub formulation: Formulation,
    /// "pga_g" | "pgv_m_s".
    #[schema(value_type = crate::kinds::survival::ImName)]
    pub im: Im,
    /// Intensity levels.
    pub stripes: Vec<f64>,
    /// Simulations per stripe.
    pub samples: u32,
    /// Seed.
    pub seed: u64,
    /// Solver.
    pub solver: SolverNorm,
    /// Coulomb friction at the floor, when given (absent: pure rocking).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<crate::jobs::contact::ContactNorm>,
}

pub(super) fn uncertain(
    v: Option<&Value>,
    at: &str,
    range: (f64, f64),
    open_lo: bool,
    what: &str,
) -> Result<Option<UncertainNorm>, SpecError> {
    match v {
        None | Some(Value::Null) => Ok(None),
        Some(Value::Number(n)) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            let inside = (if open_lo { x > range.0 } else { x >= range.0 }) && x <= range.1;
            if x.is_finite() && inside {
                Ok(Some(UncertainNorm::Fixed(x)))
            } else {
                Err(SpecError::at(
                    at,
                    format!(
                        "{what} must lie in {}{}, {}] (got {x})",
                        if open_lo { "(" } else { "[" },
                        range.0,
                        range.1
                    ),
                ))
            }
        }
        Some(obj @ Value::Object(_)) => {
            let d: DistributionSpec = crate::jobs::spec::from_value(obj, at)?;
            Ok(Some(UncertainNorm::Distribution(
                d.validate(at, range, open_lo, what)?,
            )))
        }
        Some(_) => Err(SpecError::at(
            at,
            "must be a number or a distribution {\"dist\", …}",
        )),
    }
}

impl FragilitySpec {
    /// The block: α and p, or b and h, each a number or a distribution.
    fn validate_block(&self) -> Result<UncertainBlockNorm, SpecError> {
        let b = crate::jobs::spec::required(self.block.as_ref(), "/block")?;
        let g = b.g.unwrap_or(9.81);
        if !(g.is_finite() && g > 0.0) {
            return Err(SpecError::at("/block/g", "must be a finite number > 0"));
        }
        let block = UncertainBlockNorm {
            alpha: uncertain(
                b.alpha.as_ref(),
                "/block/alpha",
                (0.0, std::f64::consts::FRAC_PI_2 - 1e-9),
                true,
                "α (rad)",
            )?,
            p: uncertain(
                b.p.as_ref(),
                "/block/p",
                (0.0, f64::INFINITY),
                true,
                "p (rad/s)",
            )?,
            b: uncertain(
                b.b.as_ref(),
                "/block/b",
                (0.0, f64::INFINITY),
                true,
                "b (m)",
            )?,
            h: uncertain(
                b.h.as_ref(),
                "/block/h",
                (0.0, f64::INFINITY),
                true,
                "h (m)",
            )?,
            eta: uncertain(b.eta.as_ref(), "/block/eta", (0.0, 1.0), false, "η")?,
            g,
        };
        match (&block.alpha, &block.p, &block.b, &block.h) {
            (Some(_), Some(_), None, None) | (None, None, Some(_), Some(_)) => {}
            (Some(_), _, Some(_), _) | (Some(_), _, _, Some(_)) | (_, Some(_), Some(_), _) => {
                return Err(SpecError::at(
                    "/block",
                    "give α and p, or b and h, not both",
                ));
            }
            (Some(_), None, _, _) => return Err(SpecError::at("/block/p", "missing field")),
            (None, Some(_), _, _) => return Err(SpecError::at("/block/alpha", "missing field")),
            (_, _, Some(_), None) => return Err(SpecError::at("/block/h", "missing field")),
            (_, _, None, Some(_)) => return Err(SpecError::at("/block/b", "missing field")),
            _ => {
                return Err(SpecError::at(
                    "/block",
                    "missing field: α and p, or b and h (each a number or a distribution)",
                ));
            }
        }
        Ok(block)
    }

    /// The vertical motion in proportion: its ratio, a number or a
    /// distribution (a fixed 0 is none).
    fn validate_vertical(&self) -> Result<Option<UncertainVerticalNorm>, SpecError> {
        Ok(match &self.vertical {
            None => None,
            Some(v) => {
                let ratio = uncertain(
                    Some(v.ratio.as_ref().ok_or_else(|| {
                        SpecError::at(
                            "/vertical/ratio",
                            "missing field: give ratio (ü_v = ratio·ü_g), a number or a distribution",
                        )
                    })?),
                    "/vertical/ratio",
                    (
                        -crate::jobs::vertical::MAX_VERTICAL_RATIO,
                        crate::jobs::vertical::MAX_VERTICAL_RATIO,
                    ),
                    false,
                    "ü_v/ü_g",
                )?;
                // A fixed ratio of 0 is no vertical motion.
                ratio
                    .filter(|r| *r != UncertainNorm::Fixed(0.0))
                    .map(|ratio| UncertainVerticalNorm { ratio })
            }
        })
    }

    /// The ground: a pulse family with its frequency (a number or a
    /// distribution), or named records (read with gravity `g`); whether a
    /// closed form exists.
    #[allow(clippy::type_complexity)]
    fn validate_ground(
        &self,
        g: f64,
    ) -> Result<
        (
            Option<UncertainPulseNorm>,
            Option<Vec<NamedMotionNorm>>,
            bool,
        ),
        SpecError,
    > {
        Ok(match (&self.pulse, &self.ground_motions) {
            (Some(_), Some(_)) => {
                return Err(SpecError::at(
                    "/ground_motions",
                    "give a pulse family or ground_motions, not both",
                ));
            }
            (None, None) => {
                return Err(SpecError::at(
                    "/pulse",
                    "missing field: a pulse family {\"type\", \"omega_p\" | \"frequency_hz\" | \"omega_ratio\"} or ground_motions [{\"dt\", \"acc\", \"unit\"}, …]",
                ));
            }
            (Some(p), None) => {
                let (pulse, closed_form) = Self::validate_pulse(p)?;
                (Some(pulse), None, closed_form)
            }
            (None, Some(list)) => (None, Some(self.named_motions(list, g)?), true),
        })
    }

    /// The pulse family, at `/pulse`, with its frequency; whether a closed
    /// form exists.
    fn validate_pulse(p: &UncertainPulseSpec) -> Result<(UncertainPulseNorm, bool), SpecError> {
        let shape = parse_shape(
            &PulseSpec {
                kind: p.kind.clone(),
                n: p.n,
                symmetric: p.symmetric,
                gamma: p.gamma,
                nu: p.nu,
                ..PulseSpec::default()
            },
            "/pulse",
        )?;
        let (omega_p, omega_ratio) = Self::pulse_frequency(p)?;
        Ok((
            UncertainPulseNorm {
                family: PulseFamily::of(shape),
                omega_p,
                omega_ratio,
            },
            shape.is_sinusoidal(),
        ))
    }

    /// The pulse's frequency, a number or a distribution, given as exactly
    /// one of omega_p (rad/s), frequency_hz (turned into rad/s) or omega_ratio:
    /// `(omega_p, omega_ratio)`.
    #[allow(clippy::type_complexity)]
    fn pulse_frequency(
        p: &UncertainPulseSpec,
    ) -> Result<(Option<UncertainNorm>, Option<UncertainNorm>), SpecError> {
        let given: Vec<(&str, &Value)> = [
            ("omega_p", p.omega_p.as_ref()),
            ("frequency_hz", p.frequency_hz.as_ref()),
            ("omega_ratio", p.omega_ratio.as_ref()),
        ]
        .into_iter()
        .filter_map(|(n, v)| v.filter(|v| !v.is_null()).map(|v| (n, v)))
        .collect();
        let (name, value) = match given.as_slice() {
            [one] => *one,
            [] => {
                return Err(SpecError::at(
                    "/pulse/omega_p",
                    "missing field: the pulse frequency as omega_p (rad/s), frequency_hz or omega_ratio, a number or a distribution",
                ));
            }
            [_, second, ..] => {
                return Err(SpecError::at(
                    format!("/pulse/{}", second.0),
                    "give exactly one frequency (omega_p, frequency_hz, omega_ratio), not several",
                ));
            }
        };
        let at = format!("/pulse/{name}");
        let v = uncertain(Some(value), &at, (0.0, f64::INFINITY), true, name)?;
        let scale = if name == "frequency_hz" {
            std::f64::consts::TAU
        } else {
            1.0
        };
        let v = v.map(|u| match u {
            UncertainNorm::Fixed(x) => UncertainNorm::Fixed(x * scale),
            UncertainNorm::Distribution(d) if scale == 1.0 => UncertainNorm::Distribution(d),
            UncertainNorm::Distribution(d) => UncertainNorm::Distribution(scaled(d, scale)),
        });
        Ok(if name == "omega_ratio" {
            (None, v)
        } else {
            (v, None)
        })
    }

    /// The named records of `/ground_motions`, 1 to `MAX_MOTIONS`, read with
    /// gravity `g`.
    fn named_motions(
        &self,
        list: &[NamedMotionSpec],
        g: f64,
    ) -> Result<Vec<NamedMotionNorm>, SpecError> {
        if list.is_empty() || list.len() > MAX_MOTIONS {
            return Err(SpecError::at(
                "/ground_motions",
                format!("give 1 to {MAX_MOTIONS} records"),
            ));
        }
        let nominal = BlockNorm {
            alpha: 1.0,
            p: 1.0,
            eta: 0.0,
            mu: None,
            g,
        };
        list.iter()
            .enumerate()
            .map(|(i, m)| self.named_motion(i, m, &nominal))
            .collect()
    }

    /// The `i`th named record, read for the block `nominal`: its vertical
    /// motion its own or the spec's (not both), some sample not 0, its name
    /// (`record i+1` when blank) at most `MAX_NAME_CHARS` characters.
    fn named_motion(
        &self,
        i: usize,
        m: &NamedMotionSpec,
        nominal: &BlockNorm,
    ) -> Result<NamedMotionNorm, SpecError> {
        let at = format!("/ground_motions/{i}");
        if m.vertical.is_some() && self.vertical.is_some() {
            return Err(SpecError::at(
                format!("{at}/vertical"),
                "give each record's vertical motion, or one ratio for all (/vertical), not both",
            ));
        }
        let motion = crate::jobs::vertical::validate_record_with_vertical(
            &GroundMotionSpec {
                dt: m.dt,
                acc: m.acc.clone(),
                unit: m.unit.clone(),
                record: m.record.clone(),
                file: m.file.clone(),
                allow_large_pga: m.allow_large_pga,
                vertical: m.vertical.clone(),
            },
            nominal,
            &at,
        )?;
        if motion.acc.iter().all(|a| *a == 0.0) {
            return Err(SpecError::at(
                format!("{at}/acc"),
                "the record has no motion (every sample is 0)",
            ));
        }
        if m.name
            .as_ref()
            .is_some_and(|n| n.chars().count() > MAX_NAME_CHARS)
        {
            return Err(SpecError::at(
                format!("{at}/name"),
                format!("a record's name is at most {MAX_NAME_CHARS} characters"),
            ));
        }
        Ok(NamedMotionNorm {
            name: m
                .name
                .clone()
                .filter(|n| !n.trim().is_empty())
                .unwrap_or_else(|| format!("record {}", i + 1)),
            motion,
        })
    }
}

impl crate::jobs::kind::Validate for FragilitySpec {
    type Job = FragilityJob;

    /// Validates into a runnable job.
    fn validate(&self) -> Result<FragilityJob, SpecError> {
        let block = self.validate_block()?;
        let formulation = parse_formulation(self.formulation.as_deref(), "/formulation")?;
        let vertical = self.validate_vertical()?;
        let (pulse, ground_motions, closed_form) = self.validate_ground(block.g)?;
        let with_vertical = vertical.is_some()
            || ground_motions
                .iter()
                .flatten()
                .any(|m| m.motion.vertical.is_some());
        let solver = crate::jobs::vertical::validate_solver_with_vertical(
            self.solver.as_ref(),
            formulation,
            closed_form,
            with_vertical,
            "/solver",
        )?;
        let im = match self.im.as_deref() {
            None | Some("pga_g") => Im::PgaG,
            Some("pgv_m_s") => Im::PgvMS,
            Some(other) => {
                return Err(SpecError::at(
                    "/im",
                    format!("unknown intensity measure {other:?}: expected pga_g | pgv_m_s"),
                ));
            }
        };
        let stripes = self
            .stripes
            .as_ref()
            .ok_or_else(|| {
                SpecError::at(
                    "/stripes",
                    "missing field: the intensity levels, a list or {\"from\", \"to\", \"steps\"}",
                )
            })?
            .values("/stripes", 0.0, 100.0, MAX_STRIPES)?;
        if let Some((k, bad)) = stripes
            .iter()
            .enumerate()
            .find(|(_, x)| x.partial_cmp(&&0.0) != Some(std::cmp::Ordering::Greater))
        {
            return Err(SpecError::at(
                format!("/stripes/{k}"),
                format!("an intensity must be > 0 (got {bad})"),
            ));
        }
        let samples = self.samples.unwrap_or(200);
        if !(1..=MAX_SAMPLES).contains(&samples) {
            return Err(SpecError::at(
                "/samples",
                format!("must lie in [1, {MAX_SAMPLES}]"),
            ));
        }
        let job = FragilityJob {
            kind: tag::Fragility,
            block,
            pulse,
            ground_motions,
            vertical,
            formulation,
            im,
            stripes,
            samples,
            seed: self.seed.unwrap_or(1),
            solver,
            contact: crate::jobs::contact::validate_contact(
                self.contact.as_ref(),
                formulation,
                "/contact",
            )?,
        };
        Ok(job)
    }
}

/// `d` with its values multiplied by `s` > 0.
pub(super) fn scaled(d: DistributionNorm, s: f64) -> DistributionNorm {
    match d {
        DistributionNorm::Normal { mean, sd, min, max } => DistributionNorm::Normal {
            mean: mean * s,
            sd: sd * s,
            min: min.map(|m| m * s),
            max: max.map(|m| m * s),
        },
        DistributionNorm::Lognormal { median, beta } => DistributionNorm::Lognormal {
            median: median * s,
            beta,
        },
        DistributionNorm::Uniform { min, max } => DistributionNorm::Uniform {
            min: min * s,
            max: max * s,
        },
    }
}
