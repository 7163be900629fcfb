//! The vertical ground motion of a time history: beside a pulse
//! (`"vertical"`: `{"ratio": r}` or a pulse of its own) and inside a record
//! (`"ground_motion": {…, "vertical": {"ratio": r} or samples}`).
//!
//! No vertical motion at all (a ratio of 0, a record of zeros) is the same
//! job as none given: normalised away, it leaves the canonical spec, the
//! cache key and every result as they are without it.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::names::tag;
use super::spec::{
    BlockNorm, GroundMotionNorm, GroundMotionSpec, PulseNorm, PulseSpec, ShapeParams, SolverNorm,
    SolverSpec, SpecError, family_of, parse_shape, validate_ground_motion, validate_pulse,
    validate_solver_for,
};
pub use super::vertical_record::{VerticalRecordNorm, VerticalRecordSpec};
use crate::dynamics::{Block, Formulation, Pulse, PulsePair, Record, RecordPair, SimError};
use crate::spectrum::overturning::{
    PulseVertical, VerticalFrequency, VerticalPulse, threshold_under_ratio, threshold_under_samples,
};
use crate::spectrum::scan::{ScanError, lift_off_level, lift_off_scale};

/// Largest |ratio| of ü_v to ü_g accepted.
pub const MAX_VERTICAL_RATIO: f64 = 100.0;
/// Longest delay of a vertical pulse accepted, s.
pub const MAX_VERTICAL_DELAY_S: f64 = 1e6;

/// The vertical ground acceleration (positive up) beside a pulse: either
/// `{"ratio": r}` (ü_v = r·ü_g, in phase, either sign) or a pulse of its own,
/// given as `pulse` is (type, a frequency, an amplitude), starting
/// `delay_s` after the horizontal one.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct VerticalPulseSpec {
    /// ü_v/ü_g (−100 to 100; 0 is no vertical motion). Alone.
    #[schema(minimum = -100.0, maximum = 100.0)]
    pub ratio: Option<f64>,
    /// Start of the vertical pulse after the horizontal one's, s (default 0).
    #[schema(minimum = 0.0, maximum = 1e6)]
    pub delay_s: Option<f64>,
    /// The vertical pulse's family, as for `pulse`.
    #[serde(rename = "type", alias = "shape")]
    #[schema(value_type = Option<crate::jobs::schema::PulseTypeInput>)]
    pub kind: Option<String>,
    /// Displacement cycles of a Type-Cn pulse.
    #[schema(minimum = 1, maximum = 1000)]
    pub n: Option<u32>,
    /// Ricker only: symmetric (default) or its derivative.
    pub symmetric: Option<bool>,
    /// Mavroeidis–Papageorgiou only: γ.
    #[schema(exclusive_minimum = 1.0, maximum = 20.0)]
    pub gamma: Option<f64>,
    /// Mavroeidis–Papageorgiou only: ν, rad.
    pub nu: Option<f64>,
    /// Circular frequency, rad/s.
    #[schema(exclusive_minimum = 0.0)]
    pub omega_p: Option<f64>,
    /// Frequency, Hz.
    #[schema(exclusive_minimum = 0.0)]
    pub frequency_hz: Option<f64>,
    /// Its ω/p.
    #[schema(minimum = 1e-3, maximum = 1e4)]
    pub omega_ratio: Option<f64>,
    /// Rectangular only: duration, s.
    #[schema(exclusive_minimum = 0.0)]
    pub duration_s: Option<f64>,
    /// Amplitude, m/s² (positive up).
    pub a_p: Option<f64>,
    /// Amplitude, g.
    pub a_p_g: Option<f64>,
    /// Amplitude, α g.
    #[schema(minimum = -1e8, maximum = 1e8)]
    pub a_p_alpha_g: Option<f64>,
    /// Spectra and pulse forensic queries: a_v/a_p, the vertical pulse's
    /// amplitude relative to each horizontal pulse's (either sign; 0 is no
    /// vertical motion).
    #[schema(minimum = -100.0, maximum = 100.0)]
    pub amplitude_ratio: Option<f64>,
    /// Spectra and pulse forensic queries: ω_v/ω_p, the vertical pulse's
    /// frequency relative to each horizontal pulse's (or give `omega_p` or
    /// `frequency_hz`, the same for every pulse).
    #[schema(minimum = 1e-3, maximum = 1e4)]
    pub frequency_ratio: Option<f64>,
}

impl VerticalPulseSpec {
    /// The pulse fields, as a pulse spec.
    fn pulse(&self) -> PulseSpec {
        PulseSpec {
            kind: self.kind.clone(),
            n: self.n,
            symmetric: self.symmetric,
            gamma: self.gamma,
            nu: self.nu,
            omega_p: self.omega_p,
            frequency_hz: self.frequency_hz,
            omega_ratio: self.omega_ratio,
            duration_s: self.duration_s,
            a_p: self.a_p,
            a_p_g: self.a_p_g,
            a_p_alpha_g: self.a_p_alpha_g,
        }
    }

    /// The first pulse field given, by name.
    fn first_pulse_field(&self) -> Option<&'static str> {
        let p = self.pulse();
        [
            (p.kind.is_some(), "type"),
            (p.n.is_some(), "n"),
            (p.symmetric.is_some(), "symmetric"),
            (p.gamma.is_some(), "gamma"),
            (p.nu.is_some(), "nu"),
            (p.omega_p.is_some(), "omega_p"),
            (p.frequency_hz.is_some(), "frequency_hz"),
            (p.omega_ratio.is_some(), "omega_ratio"),
            (p.duration_s.is_some(), "duration_s"),
            (p.a_p.is_some(), "a_p"),
            (p.a_p_g.is_some(), "a_p_g"),
            (p.a_p_alpha_g.is_some(), "a_p_alpha_g"),
            (self.amplitude_ratio.is_some(), "amplitude_ratio"),
            (self.frequency_ratio.is_some(), "frequency_ratio"),
            (self.delay_s.is_some(), "delay_s"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
    }
}

/// A ratio ü_v/ü_g, checked; `None` for 0 (no vertical motion).
fn ratio_at(r: f64, pointer: String) -> Result<Option<f64>, SpecError> {
    if !(r.is_finite() && r.abs() <= MAX_VERTICAL_RATIO) {
        return Err(SpecError::at(
            pointer,
            format!("must be a finite number with |ratio| <= {MAX_VERTICAL_RATIO}"),
        ));
    }
    Ok((r != 0.0).then_some(r))
}

/// The vertical motion beside a pulse, normalised.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "VerticalPulseDoc", try_from = "VerticalPulseDoc")]
pub enum VerticalPulseNorm {
    /// ü_v = r·ü_g.
    Ratio(f64),
    /// A pulse of its own.
    Pulse {
        /// The pulse (its ω_p and a_p, m/s², positive up).
        pulse: PulseNorm,
        /// Its start after the horizontal pulse's, s.
        delay_s: f64,
    },
    /// A pulse of its own scaled with each horizontal pulse of a kind that
    /// scales its ground motion (a_v = k a_p; ω_v absolute or ω_v/ω_p).
    Scaled(VerticalPulse),
}

impl VerticalPulseNorm {
    /// ü_v/ü_g when the vertical motion is given as a ratio.
    pub fn ratio(&self) -> Option<f64> {
        match *self {
            VerticalPulseNorm::Ratio(r) => Some(r),
            VerticalPulseNorm::Pulse { .. } | VerticalPulseNorm::Scaled(_) => None,
        }
    }

    /// The vertical pulse scaled with each horizontal one, when given so.
    pub fn scaled_pulse(&self) -> Option<VerticalPulse> {
        match *self {
            VerticalPulseNorm::Scaled(v) => Some(v),
            _ => None,
        }
    }
}

/// [`VerticalPulseNorm`] as documents hold it: `{"ratio": r}`, or the
/// pulse's fields with `delay_s`.
#[derive(Clone, Debug, Default, Serialize, Deserialize, utoipa::ToSchema)]
pub struct VerticalPulseDoc {
    /// ü_v/ü_g.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// Family name.
    #[serde(rename = "type", skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    /// Cycles (cn only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub n: Option<u32>,
    /// Symmetric wavelet or its derivative (ricker only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetric: Option<bool>,
    /// γ (mavroeidis_papageorgiou only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gamma: Option<f64>,
    /// ν, rad (mavroeidis_papageorgiou only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nu: Option<f64>,
    /// ω_p, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub omega_p: Option<f64>,
    /// a_p, m/s².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_p: Option<f64>,
    /// a_v/a_p (a pulse scaled with each horizontal one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude_ratio: Option<f64>,
    /// ω_v/ω_p (a pulse scaled with each horizontal one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency_ratio: Option<f64>,
    /// Start after the horizontal pulse, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delay_s: Option<f64>,
}

impl From<VerticalPulseNorm> for VerticalPulseDoc {
    fn from(v: VerticalPulseNorm) -> Self {
        match v {
            VerticalPulseNorm::Ratio(r) => VerticalPulseDoc {
                ratio: Some(r),
                ..Default::default()
            },
            VerticalPulseNorm::Pulse { pulse, delay_s } => VerticalPulseDoc {
                ratio: None,
                kind: Some(pulse.kind.to_string()),
                n: pulse.n,
                symmetric: pulse.symmetric,
                gamma: pulse.gamma,
                nu: pulse.nu,
                omega_p: Some(pulse.omega_p),
                a_p: Some(pulse.a_p),
                delay_s: Some(delay_s),
                ..Default::default()
            },
            VerticalPulseNorm::Scaled(v) => {
                let family = PulseNorm::of(v.shape, 0.0, 0.0);
                let (omega_p, frequency_ratio) = match v.frequency {
                    VerticalFrequency::Omega(w) => (Some(w), None),
                    VerticalFrequency::Ratio(x) => (None, Some(x)),
                };
                VerticalPulseDoc {
                    kind: Some(family.kind.to_string()),
                    n: family.n,
                    symmetric: family.symmetric,
                    gamma: family.gamma,
                    nu: family.nu,
                    omega_p,
                    amplitude_ratio: Some(v.amplitude_ratio),
                    frequency_ratio,
                    delay_s: Some(v.delay),
                    ..Default::default()
                }
            }
        }
    }
}

impl TryFrom<VerticalPulseDoc> for VerticalPulseNorm {
    type Error = String;

    fn try_from(d: VerticalPulseDoc) -> Result<Self, String> {
        if let Some(r) = d.ratio {
            return Ok(VerticalPulseNorm::Ratio(r));
        }
        if let (Some(kind), Some(k)) = (&d.kind, d.amplitude_ratio) {
            let params = ShapeParams {
                n: d.n,
                symmetric: d.symmetric,
                gamma: d.gamma,
                nu: d.nu,
            };
            let frequency = match (d.omega_p, d.frequency_ratio) {
                (Some(w), None) => VerticalFrequency::Omega(w),
                (None, Some(x)) => VerticalFrequency::Ratio(x),
                _ => return Err("a scaled vertical pulse needs omega_p or frequency_ratio".into()),
            };
            return Ok(VerticalPulseNorm::Scaled(VerticalPulse {
                shape: family_of(kind, params)?,
                amplitude_ratio: k,
                frequency,
                delay: d.delay_s.unwrap_or(0.0),
            }));
        }
        let (Some(kind), Some(omega_p), Some(a_p)) = (d.kind, d.omega_p, d.a_p) else {
            return Err("a vertical pulse needs ratio, or type, omega_p and a_p".to_string());
        };
        let params = ShapeParams {
            n: d.n,
            symmetric: d.symmetric,
            gamma: d.gamma,
            nu: d.nu,
        };
        let shape = family_of(&kind, params)?;
        Ok(VerticalPulseNorm::Pulse {
            pulse: PulseNorm::of(shape, omega_p, a_p),
            delay_s: d.delay_s.unwrap_or(0.0),
        })
    }
}

/// Validates the vertical motion beside a pulse, at `base`; `None` for no
/// vertical motion (a ratio of 0).
pub fn validate_vertical_pulse(
    spec: &VerticalPulseSpec,
    block: &BlockNorm,
    base: &str,
) -> Result<Option<VerticalPulseNorm>, SpecError> {
    if let Some(r) = spec.ratio {
        if let Some(other) = spec.first_pulse_field() {
            return Err(SpecError::at(
                format!("{base}/{other}"),
                "give either ratio alone, or a pulse of its own (type, a frequency, an amplitude, optionally delay_s)",
            ));
        }
        return Ok(ratio_at(r, format!("{base}/ratio"))?.map(VerticalPulseNorm::Ratio));
    }
    if spec.kind.is_none() {
        return Err(SpecError::at(
            format!("{base}/type"),
            "missing field: give ratio (ü_v = ratio·ü_g), or a pulse of its own (type, a frequency, an amplitude)",
        ));
    }
    for (given, name) in [
        (spec.amplitude_ratio.is_some(), "amplitude_ratio"),
        (spec.frequency_ratio.is_some(), "frequency_ratio"),
    ] {
        if given {
            return Err(SpecError::at(
                format!("{base}/{name}"),
                "relative to the horizontal pulse only in kinds that scale it (spectra, forensic queries): a time history's vertical pulse has its own amplitude (a_p, a_p_g, a_p_alpha_g) and frequency (omega_p, frequency_hz, omega_ratio)",
            ));
        }
    }
    let delay_s = validate_delay(spec, base)?;
    let (pulse, _) = validate_pulse(&spec.pulse(), block, base)?;
    Ok(Some(VerticalPulseNorm::Pulse { pulse, delay_s }))
}

/// The delay of a vertical pulse, at `base/delay_s` (default 0).
fn validate_delay(spec: &VerticalPulseSpec, base: &str) -> Result<f64, SpecError> {
    let delay_s = spec.delay_s.unwrap_or(0.0);
    if !(delay_s.is_finite() && (0.0..=MAX_VERTICAL_DELAY_S).contains(&delay_s)) {
        return Err(SpecError::at(
            format!("{base}/delay_s"),
            format!("must satisfy 0 <= delay_s <= {MAX_VERTICAL_DELAY_S:e} (s)"),
        ));
    }
    Ok(delay_s)
}

/// Validates the vertical motion of a kind that scales a pulse (spectra,
/// pulse forensic queries), at `base`: `{"ratio": r}` (ü_v = r·ü_g), or a
/// pulse of its own scaled with each horizontal pulse: `type` (and its
/// family's parameters), `amplitude_ratio` k (a_v = k·a_p, either sign), a
/// frequency (`omega_p` or `frequency_hz`, absolute; or `frequency_ratio`,
/// ω_v/ω_p of each pulse) and optionally `delay_s`. Absolute amplitudes
/// (`a_p`, `a_p_g`, `a_p_alpha_g`), `omega_ratio` and `duration_s` are
/// refused naming them; `None` without a vertical motion (absent, or a
/// ratio or amplitude ratio of 0).
pub fn validate_scaled_vertical(
    spec: Option<&VerticalPulseSpec>,
    base: &str,
) -> Result<Option<VerticalPulseNorm>, SpecError> {
    let Some(v) = spec else {
        return Ok(None);
    };
    if v.ratio.is_some() || v.kind.is_none() {
        if v.ratio.is_none() {
            return Err(SpecError::at(
                format!("{base}/ratio"),
                "missing field: give ratio (ü_v = ratio·ü_g), or a pulse of its own (type, amplitude_ratio, omega_p | frequency_hz | frequency_ratio, optionally delay_s)",
            ));
        }
        return Ok(validate_vertical_ratio(spec, base)?.map(VerticalPulseNorm::Ratio));
    }
    for (given, name, what) in [
        (v.a_p.is_some(), "a_p", "amplitude"),
        (v.a_p_g.is_some(), "a_p_g", "amplitude"),
        (v.a_p_alpha_g.is_some(), "a_p_alpha_g", "amplitude"),
        (v.omega_ratio.is_some(), "omega_ratio", "frequency"),
        (v.duration_s.is_some(), "duration_s", "frequency"),
    ] {
        if given {
            return Err(SpecError::at(
                format!("{base}/{name}"),
                format!(
                    "this kind scales its pulses, and the vertical one with each: give its {what} relative to the horizontal pulse's (amplitude_ratio: a_v/a_p; frequency_ratio: ω_v/ω_p, or an absolute omega_p or frequency_hz)"
                ),
            ));
        }
    }
    let family = PulseSpec {
        kind: v.kind.clone(),
        n: v.n,
        symmetric: v.symmetric,
        gamma: v.gamma,
        nu: v.nu,
        ..Default::default()
    };
    let shape = parse_shape(&family, base)?;
    let k = v.amplitude_ratio.ok_or_else(|| {
        SpecError::at(
            format!("{base}/amplitude_ratio"),
            "missing field: a_v/a_p, the vertical pulse's amplitude relative to each horizontal pulse's",
        )
    })?;
    let k = ratio_at(k, format!("{base}/amplitude_ratio"))?;
    let frequency = match (v.omega_p, v.frequency_hz, v.frequency_ratio) {
        (Some(w), None, None) => VerticalFrequency::Omega(positive(w, format!("{base}/omega_p"))?),
        (None, Some(f), None) => VerticalFrequency::Omega(
            std::f64::consts::TAU * positive(f, format!("{base}/frequency_hz"))?,
        ),
        (None, None, Some(x)) => {
            if !(x.is_finite() && (1e-3..=1e4).contains(&x)) {
                return Err(SpecError::at(
                    format!("{base}/frequency_ratio"),
                    "must satisfy 1e-3 <= frequency_ratio <= 1e4",
                ));
            }
            VerticalFrequency::Ratio(x)
        }
        (None, None, None) => {
            return Err(SpecError::at(
                format!("{base}/frequency_ratio"),
                "missing field: the vertical pulse's frequency, as frequency_ratio (ω_v/ω_p) or an absolute omega_p or frequency_hz",
            ));
        }
        (_, _, x) => {
            let second = if x.is_some() {
                "frequency_ratio"
            } else {
                "frequency_hz"
            };
            return Err(SpecError::at(
                format!("{base}/{second}"),
                "give one frequency: omega_p, frequency_hz or frequency_ratio",
            ));
        }
    };
    let delay = validate_delay(v, base)?;
    Ok(k.map(|amplitude_ratio| {
        VerticalPulseNorm::Scaled(VerticalPulse {
            shape,
            amplitude_ratio,
            frequency,
            delay,
        })
    }))
}

/// A positive finite number, or the field named.
fn positive(x: f64, pointer: String) -> Result<f64, SpecError> {
    if x.is_finite() && x > 0.0 && x <= 1e6 {
        Ok(x)
    } else {
        Err(SpecError::at(
            pointer,
            "must be a finite number in (0, 1e6]",
        ))
    }
}

/// The solver of a job, at `base` (`/solver`): a vertical motion has no
/// closed form (the linear equation's coefficient 1 + ü_v/g varies in time),
/// so `exact` is refused naming `base/method` and the default is dop853;
/// without one, as [`validate_solver_for`] decides.
pub fn validate_solver_with_vertical(
    spec: Option<&SolverSpec>,
    formulation: Formulation,
    closed_form: bool,
    with_vertical: bool,
    base: &str,
) -> Result<SolverNorm, SpecError> {
    if with_vertical
        && spec
            .and_then(|s| s.method.as_deref())
            .is_some_and(|m| m.eq_ignore_ascii_case("exact"))
    {
        return Err(SpecError::at(
            format!("{base}/method"),
            "the exact solver has no closed form under vertical ground motion (the linear equation's coefficient 1 + ü_v/g varies in time): use dop853 (the default) or dopri5",
        ));
    }
    validate_solver_for(spec, formulation, closed_form && !with_vertical, base)
}

/// Validates the vertical motion of a kind that scales its ground motion
/// (spectra, forensic queries, fragility): `{"ratio": r}`, ü_v = r ü_g at
/// every level; `None` without one (absent, or a ratio of 0).
pub fn validate_vertical_ratio(
    spec: Option<&VerticalPulseSpec>,
    base: &str,
) -> Result<Option<f64>, SpecError> {
    let Some(spec) = spec else {
        return Ok(None);
    };
    if let Some(other) = spec.first_pulse_field() {
        return Err(SpecError::at(
            format!("{base}/{other}"),
            "this kind scales its ground motion, and the vertical with it: give {\"ratio\": r} (ü_v = r·ü_g at every level); a vertical pulse of its own is taken beside pulses (time histories, spectra, friction spectra, pulse forensic queries), and a record's own vertical samples in ground_motion.vertical",
        ));
    }
    match spec.ratio {
        Some(r) => ratio_at(r, format!("{base}/ratio")),
        None => Err(SpecError::at(
            format!("{base}/ratio"),
            "missing field: give ratio (ü_v = ratio·ü_g)",
        )),
    }
}

/// Validates a record and its vertical acceleration, at `base`: the record
/// as [`validate_ground_motion`] does, the vertical samples likewise (at
/// `base/vertical`), on the same dt. A ratio of 0 and samples all zero are
/// no vertical motion.
pub fn validate_record_with_vertical(
    spec: &GroundMotionSpec,
    block: &BlockNorm,
    base: &str,
) -> Result<GroundMotionNorm, SpecError> {
    let horizontal = GroundMotionSpec {
        vertical: None,
        ..spec.clone()
    };
    let (mut norm, _) = validate_ground_motion(&horizontal, block, base)?;
    let Some(v) = &spec.vertical else {
        return Ok(norm);
    };
    let at = format!("{base}/vertical");
    if v.record.is_some() {
        return Err(SpecError::at(
            format!("{at}/record"),
            "names a stored record, which only the service reads (POST /v1/records): offline, give the samples or a file",
        ));
    }
    if v.file.is_some() {
        return Err(SpecError::at(
            format!("{at}/file"),
            "a file is read by `topple run` only: upload it (POST /v1/records) and name it with {\"record\": id}",
        ));
    }
    if let Some(r) = v.ratio {
        let other = [
            (v.dt.is_some(), "dt"),
            (v.acc.is_some(), "acc"),
            (v.unit.is_some(), "unit"),
            (v.allow_large_pga.is_some(), "allow_large_pga"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name));
        if let Some(other) = other {
            return Err(SpecError::at(
                format!("{at}/{other}"),
                "give either ratio alone, or the vertical samples (acc, unit, optionally dt)",
            ));
        }
        norm.vertical = ratio_at(r, format!("{at}/ratio"))?.map(|r| VerticalRecordNorm {
            ratio: Some(r),
            dt: None,
            acc: None,
            unit: None,
        });
        return Ok(norm);
    }
    if v.acc.is_none() {
        return Err(SpecError::at(
            format!("{at}/acc"),
            "missing field: give ratio (ü_v = ratio·ü_g), or the vertical samples (acc, unit)",
        ));
    }
    if let Some(dt) = v.dt
        && dt != norm.dt
    {
        return Err(SpecError::at(
            format!("{at}/dt"),
            format!(
                "must be the horizontal record's dt ({} s; got {dt} s): resample one of them",
                norm.dt
            ),
        ));
    }
    let samples = GroundMotionSpec {
        dt: Some(norm.dt),
        acc: v.acc.clone(),
        unit: v.unit.clone(),
        allow_large_pga: v.allow_large_pga,
        ..Default::default()
    };
    let (vertical, _) = validate_ground_motion(&samples, block, &at)?;
    if vertical.acc.iter().any(|&a| a != 0.0) {
        norm.vertical = Some(VerticalRecordNorm {
            ratio: None,
            dt: Some(vertical.dt),
            acc: Some(vertical.acc),
            unit: Some(tag::MetresPerSecondSquared),
        });
    }
    Ok(norm)
}

/// Validates the record of a kind that scales it (record spectra, record
/// forensic queries) with its vertical motion: a top-level `vertical`
/// (`{"ratio": r}`, at `/vertical`) or the record's own
/// (`ground_motion.vertical`: `{"ratio": r}`, the same as the top-level one,
/// or samples on the record's dt), not both (refused naming
/// `base/vertical`). A ratio, wherever given, is returned as the job's
/// `vertical` (one canonical form); samples stay in the record. Ratios of 0
/// and samples all zero are no vertical motion.
pub fn validate_scaled_record(
    top: Option<&VerticalPulseSpec>,
    spec: &GroundMotionSpec,
    block: &BlockNorm,
    base: &str,
) -> Result<(GroundMotionNorm, Option<VerticalPulseNorm>), SpecError> {
    if top.is_some() && spec.vertical.is_some() {
        return Err(SpecError::at(
            format!("{base}/vertical"),
            "the vertical motion is given twice: give either the top-level vertical {\"ratio\": r} or the record's own (ground_motion.vertical: {\"ratio\": r} or samples)",
        ));
    }
    let ratio = validate_vertical_ratio(top, "/vertical")?;
    let mut norm = validate_record_with_vertical(spec, block, base)?;
    let own_ratio = norm.vertical.as_ref().and_then(|v| v.ratio);
    if own_ratio.is_some() {
        norm.vertical = None;
    }
    Ok((norm, ratio.or(own_ratio).map(VerticalPulseNorm::Ratio)))
}

/// The vertical motion of a kind that scales its ground motion (spectra,
/// forensic queries, record spectra) as its scan lines take it: both
/// components scale by one factor along the amplitude or scale axis.
#[derive(Clone, Copy, Debug)]
pub enum ScaledVertical<'a> {
    /// ü_v = r·ü_g.
    Ratio(f64),
    /// A pulse of its own scaled with each horizontal pulse.
    Pulse(VerticalPulse),
    /// A record's own vertical samples, m/s², on its dt.
    Samples(&'a Arc<[f64]>),
}

impl<'a> ScaledVertical<'a> {
    /// The vertical motion of a job: its `vertical` ratio, or its record's
    /// own samples; `None` without one.
    pub fn of(
        vertical: Option<&VerticalPulseNorm>,
        ground_motion: Option<&'a GroundMotionNorm>,
    ) -> Option<Self> {
        match vertical {
            Some(VerticalPulseNorm::Ratio(r)) => return Some(ScaledVertical::Ratio(*r)),
            Some(VerticalPulseNorm::Scaled(v)) => return Some(ScaledVertical::Pulse(*v)),
            _ => {}
        }
        let samples = ground_motion?.vertical.as_ref()?.acc.as_ref()?;
        Some(ScaledVertical::Samples(samples))
    }

    /// ü_v/ü_g, for a ratio.
    pub fn ratio(&self) -> Option<f64> {
        match *self {
            ScaledVertical::Ratio(r) => Some(r),
            ScaledVertical::Pulse(_) | ScaledVertical::Samples(_) => None,
        }
    }

    /// The rocking threshold `threshold` (α g, of the horizontal motion's
    /// peak) lowered by the vertical motion, for a block of `slenderness`
    /// under the horizontal samples `horizontal` (records only): exact for
    /// a ratio ([`threshold_under_ratio`]) and for samples
    /// ([`threshold_under_samples`]); a lower bound under a pulse of its own
    /// ([`VerticalPulse::scan_from`]), where a scan starts.
    pub fn threshold(
        &self,
        threshold: f64,
        formulation: Formulation,
        slenderness: f64,
        horizontal: &[f64],
    ) -> f64 {
        match *self {
            ScaledVertical::Ratio(r) => {
                threshold_under_ratio(threshold, formulation, slenderness, Some(r))
            }
            ScaledVertical::Pulse(v) => v.scan_from(threshold, formulation, slenderness),
            ScaledVertical::Samples(v) => {
                threshold_under_samples(threshold, formulation, slenderness, horizontal, v)
            }
        }
    }

    /// The vertical motion beside a pulse (`None` for samples).
    pub fn of_pulses(&self) -> Option<PulseVertical> {
        match *self {
            ScaledVertical::Ratio(r) => Some(PulseVertical::Ratio(r)),
            ScaledVertical::Pulse(v) => Some(PulseVertical::Pulse(v)),
            ScaledVertical::Samples(_) => None,
        }
    }

    /// The pulse `pulse` with this vertical motion (`None` for samples).
    pub fn pulse_pair(&self, pulse: Pulse) -> Option<Result<PulsePair, ScanError>> {
        self.of_pulses().map(|v| v.pair(pulse))
    }

    /// The record `record` with this vertical motion.
    pub fn record_pair(&self, record: Record) -> Result<RecordPair, ScanError> {
        let bad = || ScanError::Simulation(SimError::Tolerance);
        match *self {
            ScaledVertical::Ratio(r) => RecordPair::proportional(record, r).ok_or_else(bad),
            ScaledVertical::Samples(v) => {
                let vertical = Record::new(v.clone(), record.dt()).map_err(|_| bad())?;
                RecordPair::new(record, vertical).map_err(|_| bad())
            }
            ScaledVertical::Pulse(_) => Err(bad()),
        }
    }

    /// The level (the record's PGA in α g of `block`) from which the ground
    /// falls away faster than gravity under `record` scaled with this
    /// vertical motion, bracketed, when it does up to `to`: by bisection
    /// under a ratio ([`lift_off_level`]), in closed form under samples
    /// ([`lift_off_scale`]).
    pub fn record_lift_off(&self, record: &Record, block: &Block, to: f64) -> Option<(f64, f64)> {
        match *self {
            ScaledVertical::Ratio(_) => {
                lift_off_level(&self.record_pair(record.clone()).ok()?, block, to)
            }
            ScaledVertical::Samples(v) => {
                let pga = record.samples().iter().fold(0.0f64, |m, a| m.max(a.abs()));
                let level = pga / (block.slenderness() * block.gravity());
                let (lo, hi) = lift_off_scale(v, block.gravity())?;
                (hi * level <= to).then_some((lo * level, hi * level))
            }
            ScaledVertical::Pulse(_) => None,
        }
    }
}
