//! The `fragility` job: the probability that a block topples at each of
//! several intensity levels (stripes), by Monte Carlo over uncertain geometry
//! and pulse frequency (or over a suite of records), each simulation decided
//! exactly (events located, overturning from the separatrix); then the
//! lognormal fragility fitted to the stripes by maximum likelihood (Baker
//! 2015), with a bootstrap band.
//!
//! Reproducible whatever the split: stripe k's samples come in chunks of
//! [`CHUNK`], chunk c drawing from its own ChaCha8 stream seeded by (seed, k,
//! c); sample j of a chunk always takes the same four uniforms (α or b, p or
//! h, η, frequency) — a fifth when the vertical ratio is a distribution — so
//! a result depends on the spec only, and a campaign under a fixed vertical
//! ratio simulates the very blocks and pulses of the one without.
//!
//! Under a vertical ground motion (ü_v = r ü_g, or a suite's records with
//! their own vertical component) a sample whose ground falls away faster
//! than g lifts off: pure rocking has no verdict on it, so it is counted
//! apart (`lift_off`) and each stripe's probability is taken over the
//! samples decided.

pub mod figure;
pub mod table;

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::spectrum::PulseFamily;
use crate::dynamics::block::housner_restitution;
use crate::dynamics::{
    Block, Formulation, Options, Problem, Pulse, PulsePair, Record, RecordPair, Response, simulate,
};
use crate::jobs::JobError;
use crate::jobs::distribution::{DistributionNorm, DistributionSpec};
use crate::jobs::names::{EngineDoc, Im, tag};
use crate::jobs::range::RangeSpec;
use crate::jobs::spec::{
    BlockNorm, GroundMotionNorm, GroundMotionSpec, PulseSpec, SolverNorm, SolverSpec, SpecError,
    parse_formulation, parse_shape,
};
use crate::probability::fragility::{Stripe, fit_lognormal, log_likelihood, wilson};
use crate::probability::normal;
use crate::spectrum::Control;

/// Why one sample of a fragility could not be simulated: its sampled block
/// or pulse is not one the engine takes, or the engine refused it.
#[derive(Debug, thiserror::Error)]
pub enum SampleError {
    /// The sampled block.
    #[error(transparent)]
    Block(#[from] crate::dynamics::block::BlockError),
    /// The sampled pulse.
    #[error(transparent)]
    Pulse(#[from] crate::dynamics::excitation::PulseError),
    /// The engine.
    #[error(transparent)]
    Simulation(#[from] crate::dynamics::SimError),
    /// A sample without what it needs (a validated job always has it).
    #[error("{0}")]
    Incomplete(&'static str),
}

/// Samples per chunk: the unit of seeding (and of a task's work).
pub const CHUNK: usize = 64;
/// Most samples per stripe.
pub const MAX_SAMPLES: u32 = 100_000;
/// Most stripes.
pub const MAX_STRIPES: usize = 200;
/// Most records in a suite.
pub const MAX_MOTIONS: usize = 100;
/// Longest name of a suite's record, characters (as an uploaded record's).
const MAX_NAME_CHARS: usize = crate::records::MAX_NAME_CHARS;
/// Bootstrap replicates of the fit.
pub const BOOTSTRAP: usize = 200;
/// The 95 % normal quantile.
const Z95: f64 = 1.959_963_984_540_054;

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
    fn at(&self, u: f64) -> f64 {
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
    /// The units `[from, to)` of the job's (stripe, chunk) list this task
    /// computes: set by the service when it splits a job into tasks, refused
    /// in a submitted spec.
    #[schema(ignore)]
    pub part: Option<[usize; 2]>,
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
    /// A task's units `[from, to)` of [`FragilityJob::units`] (absent: the
    /// whole job).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub part: Option<[usize; 2]>,
}

fn uncertain(
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
            part: None,
        };
        if let Some([from, to]) = self.part {
            let units = job.units();
            if !(from < to && to <= units) {
                return Err(SpecError::at(
                    "/part",
                    format!("must be [from, to) with from < to ≤ {units} (the job's units)"),
                ));
            }
            return Ok(FragilityJob {
                part: Some([from, to]),
                ..job
            });
        }
        Ok(job)
    }
}

/// `d` with its values multiplied by `s` > 0.
fn scaled(d: DistributionNorm, s: f64) -> DistributionNorm {
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

/// One stripe's counts.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct StripeResult {
    /// Intensity (g or m/s).
    pub im: f64,
    /// Simulations.
    pub n: u64,
    /// How many toppled.
    pub overturned: u64,
    /// overturned / the samples decided (n − lift_off); null when none was.
    #[serde(deserialize_with = "nan_for_null_one")]
    #[schema(value_type = Option<f64>, required = true)]
    pub p: f64,
    /// 95 % Wilson score interval of p (nulls when no sample was decided).
    #[serde(deserialize_with = "nan_for_null")]
    #[schema(value_type = [Option<f64>; 2])]
    pub interval_95: [f64; 2],
    /// Topplings after at least one impact (mode 1).
    pub mode_1: u64,
    /// Topplings without impact (mode 2).
    pub mode_2: u64,
    /// Under a vertical ground motion: samples whose ground fell away faster
    /// than g (lift-off), with no verdict on overturning and left out of p
    /// and the fit. Absent without a vertical motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lift_off: Option<u64>,
    /// Samples whose history reached a bound on its work (impacts, steps,
    /// free motion) before its outcome was decided: undecided, left out of
    /// p and the fit like `lift_off`. Absent when none was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub undecided: Option<u64>,
}

impl StripeResult {
    /// The samples with a verdict.
    pub fn decided(&self) -> u64 {
        self.n - self.lift_off.unwrap_or(0) - self.undecided.unwrap_or(0)
    }
}

/// A number that was NaN, serialised as null.
fn nan_for_null_one<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A point of the fitted curve and its bootstrap band.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct CurvePoint {
    /// Intensity.
    pub im: f64,
    /// Φ(ln(im/θ)/β).
    pub p: f64,
    /// 2.5 % of the bootstrap curves there.
    pub lo: f64,
    /// 97.5 % of the bootstrap curves there.
    pub hi: f64,
}

/// The lognormal fragility fitted to the stripes.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct LognormalFit {
    /// Median θ (g or m/s).
    pub median: f64,
    /// Dispersion β.
    pub beta: f64,
    /// 95 % bootstrap interval of θ.
    // NaN ends (no replicate fitted) are written as null.
    #[serde(deserialize_with = "nan_for_null")]
    pub median_interval_95: [f64; 2],
    /// 95 % bootstrap interval of β.
    #[serde(deserialize_with = "nan_for_null")]
    pub beta_interval_95: [f64; 2],
    /// ln L at the fit.
    pub log_likelihood: f64,
    /// The fitted curve with its 95 % bootstrap band.
    pub curve: Vec<CurvePoint>,
}

/// An interval whose ends were NaN, serialised as null.
fn nan_for_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let [a, b] = <[Option<f64>; 2]>::deserialize(d)?;
    Ok([a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN)])
}

/// Cost.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FragilityNumerics {
    /// Solver method.
    pub method: String,
    /// Simulations run.
    pub simulations: u64,
    /// Simulations per second (all cores).
    pub simulations_per_second: f64,
    /// Wall time, s.
    pub wall_time_s: f64,
    /// Bootstrap replicates of the fit.
    pub bootstrap: usize,
    /// Tasks the job was computed as (several: `wall_time_s` is their wall
    /// times summed, wherever they ran, plus the assembly's).
    pub tasks: usize,
}

/// The result document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct FragilityResult {
    /// "fragility".
    pub kind: tag::Fragility,
    /// The intensity measure.
    #[schema(value_type = crate::kinds::survival::ImName)]
    pub im: Im,
    /// One entry per stripe, in the order of `spec.stripes`: the empirical
    /// fragility, the primary answer.
    pub stripes: Vec<StripeResult>,
    /// "wilson": the score interval at 95 %.
    pub interval_method: String,
    /// Whether the empirical probabilities never fall as the intensity rises
    /// (safe regions make a fall real).
    pub monotone: bool,
    /// Intensities whose probability is below the previous stripe's.
    pub falls_at: Vec<f64>,
    /// The maximum-likelihood lognormal fragility (null when the counts do
    /// not bound it: every stripe all standing or all toppled, or a step
    /// without spread).
    #[schema(required = true)]
    pub lognormal: Option<LognormalFit>,
    /// Cost.
    pub numerics: FragilityNumerics,
    /// The normalised spec.
    pub spec: FragilityJob,
    /// Notes on the suite's records (`large_pga`, `baseline_drift`), added
    /// as the document leaves [`crate::kinds::Job::run`]; absent when there
    /// are none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schema(ignore)]
    pub warnings: Vec<crate::kinds::time_history::WarningDoc>,
    /// What computed it (set as the document leaves [`crate::kinds::Job::run`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(ignore)]
    pub engine: Option<EngineDoc>,
}

crate::envelope!(FragilityResult);

/// The ChaCha8 stream of stripe `k`, chunk `c`.
fn stream(seed: u64, k: usize, c: usize) -> ChaCha8Rng {
    // SplitMix64 of the three, so that neighbouring chunks get unrelated seeds.
    let mut x = seed
        ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (c as u64).wrapping_mul(0xD1B5_4A32_D192_ED03);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ChaCha8Rng::seed_from_u64(x ^ (x >> 31))
}

/// A uniform in (0, 1).
fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// One simulation of `block` under `ground` (a motion, or a pair with its
/// vertical component), on a Coulomb floor when `friction` is given.
fn run<G: crate::dynamics::sliding::Kinematics>(
    block: Block,
    ground: G,
    formulation: Formulation,
    options: &Options,
    friction: Option<crate::dynamics::sliding::Friction>,
) -> Result<Response, crate::dynamics::SimError> {
    let problem = Problem {
        block,
        pulse: ground,
        formulation,
    };
    match friction {
        None => simulate(&problem, options),
        Some(f) => crate::dynamics::floor::run_coulomb(&problem, options, f).map(|h| h.response),
    }
}

/// A record of the suite, ready to scale.
struct SuiteRecord {
    /// ü_g.
    record: Record,
    /// Its own ü_v, on the same samples.
    vertical: Option<Record>,
    /// Its PGA (m/s²) or PGV (m/s).
    per_unit: f64,
}

/// What one sample did.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    /// Still standing at the end.
    Stands,
    /// Toppled, in mode 1 (after an impact) or 2 (without one).
    Topples(u8),
    /// The ground fell away faster than g: no verdict.
    LiftOff,
    /// The history reached a bound on its work first: no verdict.
    Undecided,
}

impl Verdict {
    fn of(r: &Response) -> Verdict {
        if r.lift_off.is_some() {
            Verdict::LiftOff
        } else if r.reached_limit() {
            Verdict::Undecided
        } else if r.overturned {
            Verdict::Topples(r.mode.map_or(0, |m| m.number()))
        } else {
            Verdict::Stands
        }
    }
}

/// What some units of a stripe counted.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct StripeCounts {
    /// Simulations.
    pub n: u64,
    /// Toppled.
    pub overturned: u64,
    /// Toppled after an impact.
    pub mode_1: u64,
    /// Toppled without one.
    pub mode_2: u64,
    /// Lifted off (no verdict).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub lift_off: u64,
    /// Reached a bound on its work first (no verdict).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub undecided: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl StripeCounts {
    fn add(&mut self, other: &StripeCounts) {
        self.n += other.n;
        self.overturned += other.overturned;
        self.mode_1 += other.mode_1;
        self.mode_2 += other.mode_2;
        self.lift_off += other.lift_off;
        self.undecided += other.undecided;
    }

    /// The samples with a verdict.
    fn decided(&self) -> u64 {
        self.n - self.lift_off - self.undecided
    }
}

/// A task's result: its units' counts per stripe (not a job's result: the
/// service assembles the parts into one).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FragilityPart {
    /// "fragility".
    pub kind: String,
    /// The units `[from, to)` it counted.
    pub part: [usize; 2],
    /// Per stripe, in the job's order.
    pub counts: Vec<StripeCounts>,
    /// Simulations run.
    pub simulations: u64,
    /// Its compute time, s.
    pub wall_time_s: f64,
}

/// The tasks a result was assembled from.
struct Tasks {
    count: usize,
    compute_s: f64,
}

impl FragilityJob {
    /// The block of one sample from its uniforms.
    fn block_at(&self, u: [f64; 3]) -> Result<Block, SampleError> {
        let b = &self.block;
        let (alpha, p) = match (&b.alpha, &b.p, &b.b, &b.h) {
            (Some(a), Some(p), _, _) => (a.at(u[0]), p.at(u[1])),
            (_, _, Some(bb), Some(hh)) => {
                let (half_b, half_h) = (bb.at(u[0]), hh.at(u[1]));
                let r = half_b.hypot(half_h);
                ((half_b / half_h).atan(), (3.0 * b.g / (4.0 * r)).sqrt())
            }
            _ => {
                return Err(SampleError::Incomplete(
                    "the block has neither α and p nor b and h",
                ));
            }
        };
        let eta = b
            .eta
            .map_or_else(|| housner_restitution(alpha), |e| e.at(u[2]));
        Ok(Block::new(alpha, p, Some(eta), None, Some(b.g))?)
    }

    /// What one sample does: stands, topples (and its mode), or lifts off
    /// (the ground falls away faster than g: no verdict). `ratio` is its
    /// ü_v/ü_g, when the campaign has one.
    fn sample(
        &self,
        im: f64,
        j: usize,
        u: [f64; 4],
        ratio: Option<f64>,
        records: &[SuiteRecord],
    ) -> Result<Verdict, SampleError> {
        let block = self.block_at([u[0], u[1], u[2]])?;
        let options = Options::outcome(self.solver.solver());
        let formulation = self.formulation;
        let friction = self.contact.as_ref().map(|c| c.friction());
        let ratio = ratio.filter(|r| *r != 0.0);
        let r = if let Some(pulse) = &self.pulse {
            let omega = match (&pulse.omega_p, &pulse.omega_ratio) {
                (Some(w), _) => w.at(u[3]),
                (_, Some(ratio)) => ratio.at(u[3]) * block.frequency_parameter(),
                _ => return Err(SampleError::Incomplete("the pulse has no frequency")),
            };
            let unit = Pulse::new(pulse.family.shape(), 1.0, omega)?;
            let a_p = if self.im == Im::PgaG {
                im * block.gravity()
            } else {
                im / unit.peak_velocity()
            };
            let pulse = unit.with_amplitude(a_p);
            match ratio.and_then(|r| PulsePair::proportional(pulse, r)) {
                Some(pair) => run(block, pair, formulation, &options, friction)?,
                None => run(block, pulse, formulation, &options, friction)?,
            }
        } else {
            let suite = &records[j % records.len()];
            let factor = if self.im == Im::PgaG {
                im * block.gravity() / suite.per_unit
            } else {
                im / suite.per_unit
            };
            let record = suite.record.scaled(factor);
            let pair = match (&suite.vertical, ratio) {
                (Some(v), _) => Some(RecordPair {
                    horizontal: record.clone(),
                    vertical: v.scaled(factor),
                }),
                (None, Some(r)) => RecordPair::proportional(record.clone(), r),
                (None, None) => None,
            };
            match pair {
                Some(pair) => run(block, pair, formulation, &options, friction)?,
                None => run(block, record, formulation, &options, friction)?,
            }
        };
        Ok(Verdict::of(&r))
    }

    /// Chunks of [`CHUNK`] samples per stripe.
    pub fn chunks(&self) -> usize {
        (self.samples as usize).div_ceil(CHUNK)
    }

    /// The job's units of work and of seeding: (stripe k, chunk c) in the
    /// order unit `k · chunks + c`. A task computes a range of them.
    pub fn units(&self) -> usize {
        self.stripes.len() * self.chunks()
    }

    /// Each record of the suite with its vertical component (padded to the
    /// same length) and its PGA (m/s²) or PGV (m/s): what one unit of scale
    /// gives.
    fn records(&self) -> Vec<SuiteRecord> {
        self.ground_motions
            .iter()
            .flatten()
            .filter_map(|m| {
                let (record, vertical) = match m.motion.pair() {
                    Some(pair) => {
                        let pair = pair.ok()?;
                        (pair.horizontal, Some(pair.vertical))
                    }
                    None => (m.motion.record().ok()?, None),
                };
                let peaks = crate::dynamics::peaks::of_record(&record);
                let per_unit = if self.im == Im::PgaG {
                    peaks.pga
                } else {
                    peaks.pgv
                };
                (per_unit > 0.0).then_some(SuiteRecord {
                    record,
                    vertical,
                    per_unit,
                })
            })
            .collect()
    }

    /// Whether its samples may lift off: a vertical motion is given.
    pub fn has_vertical(&self) -> bool {
        self.vertical.is_some()
            || self
                .ground_motions
                .iter()
                .flatten()
                .any(|m| m.motion.vertical.is_some())
    }

    /// Samples of the suite's longest record (0 for a pulse family).
    pub fn longest_record(&self) -> usize {
        self.ground_motions
            .iter()
            .flatten()
            .map(|m| m.motion.acc.len())
            .max()
            .unwrap_or(0)
    }

    /// Expected CPU seconds of one of its simulations ([`crate::jobs::cost`]): a
    /// record of the suite's on average, or a pulse of its family: at
    /// stripes many of which do not rock the block, about 0.6 of a
    /// spectrum's average simulation (measured 35 µs for a one-sine), or of
    /// a record's whole shaking.
    pub fn simulation_s(&self) -> f64 {
        use crate::jobs::cost;
        (match (&self.ground_motions, &self.pulse) {
            (Some(suite), _) if !suite.is_empty() => {
                0.6 * suite
                    .iter()
                    .map(|m| cost::record_simulation_s(&m.motion.acc))
                    .sum::<f64>()
                    / suite.len() as f64
            }
            (_, Some(p)) => {
                0.6 * cost::pulse_simulation_s(
                    &p.family.shape(),
                    self.formulation,
                    self.solver.method,
                )
            }
            _ => 0.0,
        }) * crate::jobs::cost::contact_factor(self.contact.as_ref())
    }

    /// Simulations this job (or task) runs.
    pub fn simulations(&self) -> u64 {
        let [from, to] = self.part.unwrap_or([0, self.units()]);
        self.samples_in(from, to)
    }

    /// Samples in units `from..to`.
    fn samples_in(&self, from: usize, to: usize) -> u64 {
        let (chunks, samples) = (self.chunks(), self.samples as usize);
        (from..to)
            .map(|i| {
                let c = i % chunks;
                ((c + 1) * CHUNK).min(samples) - c * CHUNK
            })
            .sum::<usize>() as u64
    }

    /// Simulates units `from..to` (rayon over them) and counts per stripe
    /// (stripes outside the range count zero).
    fn count(
        &self,
        from: usize,
        to: usize,
        control: &Control,
    ) -> Result<Vec<StripeCounts>, JobError> {
        let (chunks, samples) = (self.chunks(), self.samples as usize);
        let records = self.records();
        control.add_total(self.samples_in(from, to));
        let counted: Vec<Result<(usize, StripeCounts), JobError>> = (from..to)
            .into_par_iter()
            .map(|i| {
                let (k, c) = (i / chunks, i % chunks);
                let mut rng = stream(self.seed, k, c);
                let mut counts = StripeCounts::default();
                for j in c * CHUNK..((c + 1) * CHUNK).min(samples) {
                    control.check().map_err(|_| JobError::Canceled)?;
                    let u = [
                        uniform(&mut rng),
                        uniform(&mut rng),
                        uniform(&mut rng),
                        uniform(&mut rng),
                    ];
                    // A fifth uniform only for a distributed ratio: a fixed
                    // one (or none) keeps every other sample's stream.
                    let ratio = self.vertical.map(|v| match v.ratio {
                        UncertainNorm::Fixed(r) => r,
                        d => d.at(uniform(&mut rng)),
                    });
                    let outcome = self
                        .sample(self.stripes[k], j, u, ratio, &records)
                        .map_err(|e| JobError::AtSample {
                            stripe: k,
                            level: format!("{} {}", self.stripes[k], self.im),
                            sample: j,
                            source: Box::new(e),
                        })?;
                    counts.n += 1;
                    match outcome {
                        Verdict::Stands => {}
                        Verdict::LiftOff => counts.lift_off += 1,
                        Verdict::Undecided => counts.undecided += 1,
                        Verdict::Topples(mode) => {
                            counts.overturned += 1;
                            if mode == 2 {
                                counts.mode_2 += 1;
                            } else {
                                counts.mode_1 += 1;
                            }
                        }
                    }
                    control.add_done(1);
                }
                Ok((k, counts))
            })
            .collect();
        let mut per_stripe = vec![StripeCounts::default(); self.stripes.len()];
        for r in counted {
            let (k, counts) = r?;
            per_stripe[k].add(&counts);
        }
        Ok(per_stripe)
    }

    /// Runs the Monte Carlo and the fit (rayon over chunks): the whole job,
    /// whatever its `part`.
    pub fn run(&self, control: &Control) -> Result<FragilityResult, JobError> {
        let started = std::time::Instant::now();
        let whole = FragilityJob {
            part: None,
            ..self.clone()
        };
        let counts = whole.count(0, whole.units(), control)?;
        whole.finish(&counts, None, started)
    }

    /// Runs this task's units: their counts per stripe, for
    /// [`FragilityJob::assemble`].
    pub fn run_part(&self, control: &Control) -> Result<FragilityPart, JobError> {
        let started = std::time::Instant::now();
        let [from, to] = self.part.unwrap_or([0, self.units()]);
        let counts = self.count(from, to, control)?;
        let wall = started.elapsed().as_secs_f64();
        Ok(FragilityPart {
            kind: "fragility".into(),
            part: [from, to],
            simulations: counts.iter().map(|c| c.n).sum(),
            wall_time_s: wall,
            counts,
        })
    }

    /// The whole job's result from its tasks' parts (in any order): each
    /// unit counted exactly once, else an error naming the first gap or
    /// overlap.
    pub fn assemble(&self, parts: &[FragilityPart]) -> Result<FragilityResult, JobError> {
        let started = std::time::Instant::now();
        let mut ranges: Vec<[usize; 2]> = parts.iter().map(|p| p.part).collect();
        ranges.sort_unstable();
        let mut next = 0;
        for [from, to] in &ranges {
            if *from != next {
                return Err(JobError::Task(if *from > next {
                    format!("the tasks' parts do not tile the job: unit {next} is missing")
                } else {
                    format!("the tasks' parts do not tile the job: unit {from} is counted twice")
                }));
            }
            next = *to;
        }
        if next != self.units() {
            return Err(JobError::Task(format!(
                "the tasks' parts do not tile the job: units {next}..{} are missing",
                self.units()
            )));
        }
        let mut counts = vec![StripeCounts::default(); self.stripes.len()];
        for part in parts {
            if part.counts.len() != counts.len() {
                return Err(JobError::Task(
                    "a task's counts do not match the job's stripes".into(),
                ));
            }
            for (total, c) in counts.iter_mut().zip(&part.counts) {
                total.add(c);
            }
        }
        let tasks = Tasks {
            count: parts.len(),
            compute_s: parts.iter().map(|p| p.wall_time_s).sum(),
        };
        self.finish(&counts, Some(tasks), started)
    }

    /// The result from the counts per stripe: the Wilson intervals, the
    /// monotonicity flag, the fit and its band.
    fn finish(
        &self,
        per_stripe: &[StripeCounts],
        tasks: Option<Tasks>,
        started: std::time::Instant,
    ) -> Result<FragilityResult, JobError> {
        if let Some((k, c)) = per_stripe
            .iter()
            .enumerate()
            .find(|(_, c)| c.n != u64::from(self.samples))
        {
            return Err(JobError::Task(format!(
                "stripe {k} counted {} simulations, not {}",
                c.n, self.samples
            )));
        }
        let stripes: Vec<StripeResult> = self
            .stripes
            .iter()
            .zip(per_stripe)
            .map(|(&im, c)| {
                // Over the samples decided (all of them without a vertical
                // motion); none decided: no probability (null).
                let decided = c.decided();
                let (lo, hi) = if decided > 0 {
                    wilson(c.overturned, decided, Z95)
                } else {
                    (f64::NAN, f64::NAN)
                };
                StripeResult {
                    im,
                    n: c.n,
                    overturned: c.overturned,
                    p: if decided > 0 {
                        c.overturned as f64 / decided as f64
                    } else {
                        f64::NAN
                    },
                    interval_95: [lo, hi],
                    mode_1: c.mode_1,
                    mode_2: c.mode_2,
                    lift_off: self.has_vertical().then_some(c.lift_off),
                    undecided: (c.undecided > 0).then_some(c.undecided),
                }
            })
            .collect();
        // Monotone in rising intensity (stripes with a probability).
        let mut order: Vec<&StripeResult> = stripes.iter().filter(|s| s.p.is_finite()).collect();
        order.sort_by(|a, b| a.im.total_cmp(&b.im));
        let falls_at: Vec<f64> = order
            .windows(2)
            .filter(|w| w[1].p < w[0].p)
            .map(|w| w[1].im)
            .collect();
        let counts: Vec<Stripe> = stripes
            .iter()
            .filter(|s| s.decided() > 0)
            .map(|s| Stripe {
                im: s.im,
                n: s.decided(),
                k: s.overturned,
            })
            .collect();
        let lognormal = fit_lognormal(&counts).map(|(theta, beta)| self.band(theta, beta, &counts));
        let simulations: u64 = per_stripe.iter().map(|c| c.n).sum();
        // One task: its wall time; several: the tasks' compute time summed
        // (wherever they ran) plus the assembly's.
        let wall = started.elapsed().as_secs_f64() + tasks.as_ref().map_or(0.0, |t| t.compute_s);
        Ok(FragilityResult {
            kind: tag::Fragility,
            im: self.im,
            stripes,
            interval_method: "wilson".into(),
            monotone: falls_at.is_empty(),
            falls_at,
            lognormal,
            numerics: FragilityNumerics {
                method: self.solver.method.name().to_string(),
                simulations,
                simulations_per_second: simulations as f64 / wall.max(1e-9),
                wall_time_s: wall,
                bootstrap: BOOTSTRAP,
                tasks: tasks.map_or(1, |t| t.count),
            },
            spec: FragilityJob {
                part: None,
                ..self.clone()
            },
            warnings: Vec::new(),
            engine: None,
        })
    }

    /// The fit with its parametric bootstrap: each replicate redraws every
    /// stripe's count from Binomial(n, p̂) (p̂ the fitted curve there) with
    /// its own seeded stream, and is refitted.
    fn band(&self, theta: f64, beta: f64, counts: &[Stripe]) -> LognormalFit {
        let fitted = |x: f64, t: f64, b: f64| normal::cdf((x / t).ln() / b);
        let fits: Vec<(f64, f64)> = (0..BOOTSTRAP)
            .into_par_iter()
            .filter_map(|r| {
                let mut rng = stream(self.seed ^ 0xB007_57A9, usize::MAX, r);
                let redrawn: Vec<Stripe> = counts
                    .iter()
                    .map(|s| {
                        let p = fitted(s.im, theta, beta);
                        let k = if s.n <= 2_000 {
                            (0..s.n).filter(|_| uniform(&mut rng) < p).count() as u64
                        } else {
                            let z = normal::quantile(uniform(&mut rng));
                            let mean = s.n as f64 * p;
                            (mean + z * (mean * (1.0 - p)).sqrt())
                                .round()
                                .clamp(0.0, s.n as f64) as u64
                        };
                        Stripe { k, ..*s }
                    })
                    .collect();
                fit_lognormal(&redrawn)
            })
            .collect();
        let quantiles = |mut v: Vec<f64>| -> [f64; 2] {
            v.sort_by(f64::total_cmp);
            if v.is_empty() {
                return [f64::NAN, f64::NAN];
            }
            let at = |q: f64| v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
            [at(0.025), at(0.975)]
        };
        let (lo, hi) = counts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), s| {
            (a.min(s.im), b.max(s.im))
        });
        let (lo, hi) = (
            lo.min(theta * (-2.5 * beta).exp()),
            hi.max(theta * (2.5 * beta).exp()),
        );
        let curve = (0..=60)
            .map(|i| {
                let x = lo * (hi / lo).powf(f64::from(i) / 60.0);
                let [a, b] = quantiles(fits.iter().map(|&(t, b)| fitted(x, t, b)).collect());
                CurvePoint {
                    im: x,
                    p: fitted(x, theta, beta),
                    lo: if a.is_finite() { a } else { 0.0 },
                    hi: if b.is_finite() { b } else { 1.0 },
                }
            })
            .collect();
        LognormalFit {
            median: theta,
            beta,
            median_interval_95: quantiles(fits.iter().map(|f| f.0).collect()),
            beta_interval_95: quantiles(fits.iter().map(|f| f.1).collect()),
            log_likelihood: log_likelihood(theta, beta, counts),
            curve,
        }
    }
}

/// The `fragility` kind: the probability of overturning against an
/// intensity measure, by Monte Carlo; split into parts of whole units.
pub struct Fragility;

impl crate::kinds::kind::Kind for Fragility {
    const NAME: &'static str = crate::jobs::names::tag::Fragility::NAME;
    const EXAMPLE: &'static str = include_str!("example.json");
    const LABEL: &'static str = "Fragility";
    type Spec = FragilitySpec;
    type Job = FragilityJob;
    type Result = FragilityResult;
    type Part = FragilityPart;

    fn run(
        job: &FragilityJob,
        control: &Control,
    ) -> Result<crate::kinds::kind::Output<Self>, JobError> {
        use crate::kinds::kind::Output;
        if job.part.is_some() {
            // A task's counts, assembled by the service.
            return Ok(Output::Part(job.run_part(control)?));
        }
        Ok(Output::Whole(job.run(control)?))
    }
    fn table(
        result: &FragilityResult,
        table: &mut crate::table::Table,
    ) -> Result<(), crate::table::TableError> {
        table::rows(result, table)
    }

    fn figure(
        result: &FragilityResult,
        window: Option<crate::plot::Window>,
    ) -> Result<String, crate::plot::FigureError> {
        crate::kinds::kind::whole_figure::<Self>(window, || figure::svg(result))
    }

    fn size(job: &FragilityJob) -> crate::jobs::kind::Size {
        let work = job.simulations() as f64;
        crate::jobs::kind::Size {
            series_points: 0,
            grid_points: work as usize,
            work,
            record_work: work * job.longest_record() as f64,
            cpu_s: work * job.simulation_s(),
            lanes: work,
        }
    }

    fn grid_field(_job: &FragilityJob) -> &'static str {
        "/samples"
    }

    fn warnings(job: &FragilityJob) -> Vec<crate::jobs::warning::WarningDoc> {
        job.ground_motions
            .iter()
            .flatten()
            .enumerate()
            .flat_map(|(i, m)| {
                crate::jobs::plausible::record_warnings(&m.motion, &format!("/ground_motions/{i}"))
            })
            .collect()
    }

    fn is_part(job: &FragilityJob) -> bool {
        job.part.is_some()
    }

    /// Parts of whole units; a task's payload names its units only (the
    /// suite is stored once, with the job).
    fn split(job: &FragilityJob, _size: &crate::jobs::kind::Size) -> Vec<FragilityJob> {
        if job.part.is_some() {
            return vec![job.clone()];
        }
        let units = job.units();
        let per = crate::jobs::split::per_task(units, CHUNK as f64 * job.simulation_s());
        if per >= units {
            return vec![job.clone()];
        }
        (0..units)
            .step_by(per)
            .map(|from| FragilityJob {
                part: Some([from, (from + per).min(units)]),
                ..job.clone()
            })
            .collect()
    }

    fn task_payload(job: &FragilityJob) -> Option<String> {
        job.part
            .map(|part| serde_json::json!({ "part": part }).to_string())
    }

    fn part_of(whole: &FragilityJob, payload: &Value) -> Option<Result<FragilityJob, JobError>> {
        let part = payload.get("part")?;
        if payload.get("kind").is_some() {
            return None;
        }
        Some(match serde_json::from_value::<[usize; 2]>(part.clone()) {
            Ok([from, to]) if from < to && to <= whole.units() => Ok(FragilityJob {
                part: Some([from, to]),
                ..whole.clone()
            }),
            _ => Err(JobError::Task(format!(
                "a task's part {part} does not fit its {} job",
                Self::NAME
            ))),
        })
    }

    /// The parts' counts summed per stripe, and the fit made on the sums.
    fn assemble(
        job: &FragilityJob,
        parts: Vec<FragilityPart>,
    ) -> Result<FragilityResult, JobError> {
        job.assemble(&parts)
    }
}
