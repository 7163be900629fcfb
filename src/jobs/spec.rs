//! The job-spec JSON: serde types as users write them, and their validation
//! into domain types with every default filled in.
//!
//! Errors name the offending field as a JSON pointer (RFC 6901), e.g.
//! `/block/alpha`.

use serde::{Deserialize, Serialize};

use std::sync::Arc;

use super::names::{SolverMethod, tag};
use crate::dynamics::block::BlockError;
use crate::dynamics::{Block, Formulation, Method, Pulse, PulseShape, Record, Solver};

pub use super::error::SpecError;

/// Stands in for the non-JSON tokens NaN / Infinity so that the error can name
/// the field that holds them.
const NON_FINITE_MARK: &str = "__non_finite_number__";

/// Replaces bare `NaN`, `Infinity` and `-Infinity` tokens (outside strings) by a
/// marker string, which validation then reports at its JSON pointer.
pub fn mark_non_finite(text: &str) -> std::borrow::Cow<'_, str> {
    if !(text.contains("NaN") || text.contains("Infinity")) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 32);
    let mut in_string = false;
    let mut escaped = false;
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        if in_string {
            out.push(c);
            if escaped {
                escaped = false;
            } else if c == '\\' {
                escaped = true;
            } else if c == '"' {
                in_string = false;
            }
            rest = &rest[c.len_utf8()..];
            continue;
        }
        let token = ["-Infinity", "Infinity", "NaN"]
            .into_iter()
            .find(|t| rest.starts_with(t));
        if let Some(t) = token {
            out.push('"');
            out.push_str(NON_FINITE_MARK);
            out.push('"');
            rest = &rest[t.len()..];
            continue;
        }
        if c == '"' {
            in_string = true;
        }
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    std::borrow::Cow::Owned(out)
}

/// How deep serde_json reads nested arrays and objects before it stops.
pub const MAX_JSON_DEPTH: usize = 128;

/// Parses JSON text into a value. NaN, ±Infinity and numbers beyond the range
/// of f64 (1e400) become a marker that validation reports at the field's
/// pointer; anything else that is not JSON is an error of the document.
pub fn parse_json(text: &str) -> Result<serde_json::Value, SpecError> {
    let mut text = mark_non_finite(text).into_owned();
    // Each pass replaces one out-of-range number; a document with very many
    // is refused as a whole.
    for _ in 0..64 {
        match serde_json::from_str(&text) {
            Ok(value) => return Ok(value),
            Err(e) if e.to_string().starts_with("number out of range") => {
                let Some(span) = number_at(&text, e.line(), e.column()) else {
                    return Err(SpecError::syntax(format!("not valid JSON: {e}")));
                };
                text.replace_range(span, &format!("\"{NON_FINITE_MARK}\""));
            }
            Err(e) if e.to_string().starts_with("recursion limit exceeded") => {
                return Err(SpecError::syntax(format!(
                    "not valid JSON: {e} (a job spec nests at most {MAX_JSON_DEPTH} levels)"
                )));
            }
            Err(e) => return Err(SpecError::syntax(format!("not valid JSON: {e}"))),
        }
    }
    Err(SpecError::syntax(
        "not valid JSON: too many numbers out of range",
    ))
}

/// The byte range of the number token that ends at or just before (1-based)
/// `line`, `column`, where serde_json reports an out-of-range number.
fn number_at(text: &str, line: usize, column: usize) -> Option<std::ops::Range<usize>> {
    let line_start = if line <= 1 {
        0
    } else {
        text.match_indices('\n').nth(line - 2)?.0 + 1
    };
    let bytes = text.as_bytes();
    let is_num = |b: u8| b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.' | b'e' | b'E');
    let mut end = (line_start + column).min(bytes.len());
    while end > line_start && !is_num(bytes[end - 1]) {
        end -= 1;
    }
    while end < bytes.len() && is_num(bytes[end]) {
        end += 1;
    }
    let mut start = end;
    while start > 0 && is_num(bytes[start - 1]) {
        start -= 1;
    }
    (start < end).then_some(start..end)
}

/// Longest quotation of the input an error message keeps, characters.
const MAX_ECHO: usize = 40;

/// `message` with every quoted part (between `"…"` or `` `…` ``) longer
/// than [`MAX_ECHO`] characters cut, saying how long it was: serde's
/// messages quote the offending value, which may be a megabyte of text.
pub fn shorten_echoes(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(512));
    let mut rest = message;
    while let Some(open) = rest.find(['"', '`']) {
        let quote = rest[open..].chars().next().unwrap_or('"');
        out.push_str(&rest[..=open]);
        let inner = &rest[open + 1..];
        let Some(close) = inner.find(quote) else {
            rest = inner;
            break;
        };
        let quoted = &inner[..close];
        let n = quoted.chars().count();
        if n > MAX_ECHO {
            out.extend(quoted.chars().take(MAX_ECHO));
            out.push_str(&format!("… ({n} characters)"));
        } else {
            out.push_str(quoted);
        }
        out.push(quote);
        rest = &inner[close + 1..];
    }
    let tail: String = rest.chars().take(10 * MAX_ECHO).collect();
    out.push_str(&tail);
    if tail.len() < rest.len() {
        out.push('…');
    }
    out
}

/// Deserialises `value` into `T`, reporting the failing field as a JSON pointer
/// below `base`.
pub fn from_value<T: for<'de> Deserialize<'de>>(
    value: &serde_json::Value,
    base: &str,
) -> Result<T, SpecError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let mut pointer = json_pointer(base, e.path());
        let mut message = shorten_echoes(&e.into_inner().to_string());
        if message.contains(NON_FINITE_MARK) {
            message = "must be a finite number (NaN, Infinity and numbers beyond ±1.8e308 are not accepted)"
                .to_string();
        }
        // serde names a missing field in its text, at its parent: point at it.
        if let Some(name) = message
            .strip_prefix("missing field `")
            .and_then(|rest| rest.split('`').next())
        {
            pointer.push('/');
            pointer.push_str(&name.replace('~', "~0").replace('/', "~1"));
            message = "missing field".to_string();
        }
        SpecError::at(pointer, message)
    })
}

/// A path of serde_path_to_error under `base`, as a JSON pointer
/// (`a.b[2]` under "" → `/a/b/2`).
pub fn json_pointer(base: &str, path: &serde_path_to_error::Path) -> String {
    let mut pointer = base.to_string();
    for seg in path.iter() {
        use serde_path_to_error::Segment;
        match seg {
            Segment::Seq { index } => pointer.push_str(&format!("/{index}")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                pointer.push('/');
                pointer.push_str(&key.replace('~', "~0").replace('/', "~1"));
            }
            Segment::Unknown => {}
        }
    }
    pointer
}

/// A field a spec must give, or the error that it is missing.
pub fn required<'a, T>(field: Option<&'a T>, pointer: &str) -> Result<&'a T, SpecError> {
    field.ok_or_else(|| SpecError::at(pointer, "missing field"))
}

/// The block of a single-block spec (`/block`), validated.
pub fn the_block(block: Option<&BlockSpec>) -> Result<BlockNorm, SpecError> {
    validate_block(required(block, "/block")?, "/block")
}

/// The block, by parameters or by geometry.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// Slenderness α, rad.
    #[serde(alias = "slenderness")]
    #[schema(exclusive_minimum = 0.0)]
    pub alpha: Option<f64>,
    /// Frequency parameter p, rad/s.
    #[serde(alias = "frequency_parameter")]
    #[schema(exclusive_minimum = 0.0)]
    pub p: Option<f64>,
    /// Half-width b, m (the full width is 2b).
    #[serde(alias = "half_width", alias = "half_width_m")]
    #[schema(exclusive_minimum = 0.0)]
    pub b: Option<f64>,
    /// Half-height h, m (the full height is 2h).
    #[serde(alias = "half_height", alias = "half_height_m")]
    #[schema(exclusive_minimum = 0.0)]
    pub h: Option<f64>,
    /// Coefficient of restitution η (default 1 − 1.5 sin²α, floored at 0).
    #[serde(alias = "restitution")]
    #[schema(minimum = 0.0, maximum = 1.0)]
    pub eta: Option<f64>,
    /// Friction coefficient μ (optional; enables sliding warnings).
    #[serde(alias = "friction")]
    #[schema(exclusive_minimum = 0.0)]
    pub mu: Option<f64>,
    /// Gravity, m/s² (default 9.81).
    #[serde(alias = "gravity")]
    #[schema(exclusive_minimum = 0.0)]
    pub g: Option<f64>,
}

/// The pulse: family, frequency and amplitude.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct PulseSpec {
    /// "one_sine" | "one_cosine" | "cn" | "half_sine" | "rectangular" | "ricker"
    /// | "mavroeidis_papageorgiou" (aliases: "sine", "type_a", "cosine",
    /// "type_b", "type_cn"). Half-sine: a_p sin(ω_p t) for π/ω_p; rectangular:
    /// a_p for t_d = π/ω_p (Housner 1963); ricker: with f_p = ω_p/2π, c = (π
    /// f_p)², τ = t − 1.5/f_p, a_p(1 − 2cτ²)e^(−cτ²) for 0 ≤ t ≤ 3/f_p, or
    /// (`"symmetric": false`) its derivative scaled to peak a_p;
    /// mavroeidis_papageorgiou (2003): ground velocity (V/2)[1 + cos(2π f_p
    /// τ/γ)] cos(2π f_p τ + ν), τ = t − γ/(2f_p), for 0 ≤ t ≤ γ/f_p, ü_g its
    /// derivative, V such that max |ü_g| = |a_p|.
    #[serde(rename = "type", alias = "shape")]
    #[schema(required = true, value_type = crate::jobs::schema::PulseTypeInput)]
    pub kind: Option<String>,
    /// Displacement cycles of a Type-Cn pulse (default 1; cn only).
    #[schema(minimum = 1, maximum = 1000)]
    pub n: Option<u32>,
    /// Ricker only: the symmetric wavelet (default true) or its normalised
    /// derivative, the antisymmetric one (false).
    pub symmetric: Option<bool>,
    /// Mavroeidis–Papageorgiou only (required there): γ, the carrier cycles
    /// under the bell, 1 < γ ≤ 20.
    #[schema(exclusive_minimum = 1.0, maximum = 20.0)]
    pub gamma: Option<f64>,
    /// Mavroeidis–Papageorgiou only: ν, the carrier's phase at the bell's
    /// centre, rad (default 0; any finite value, taken modulo 2π to (−π, π]).
    pub nu: Option<f64>,
    /// Circular frequency ω_p, rad/s.
    #[schema(exclusive_minimum = 0.0)]
    pub omega_p: Option<f64>,
    /// Frequency f = ω_p/(2π), Hz.
    #[schema(exclusive_minimum = 0.0)]
    pub frequency_hz: Option<f64>,
    /// ω_p/p (1e-3 to 1e4).
    #[schema(minimum = 1e-3, maximum = 1e4)]
    pub omega_ratio: Option<f64>,
    /// Rectangular pulses only: the duration t_d, s, instead of a frequency
    /// (ω_p = π/t_d).
    #[schema(exclusive_minimum = 0.0)]
    pub duration_s: Option<f64>,
    /// Amplitude, m/s² (non-zero; the sign sets the direction).
    pub a_p: Option<f64>,
    /// Amplitude in g (non-zero).
    pub a_p_g: Option<f64>,
    /// Amplitude in α g (non-zero, |a_p|/(αg) ≤ 1e8).
    #[schema(minimum = -1e8, maximum = 1e8)]
    pub a_p_alpha_g: Option<f64>,
}

/// Solver choice.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// "exact" | "dopri5" | "dop853".
    #[schema(value_type = Option<crate::jobs::schema::MethodInput>)]
    pub method: Option<String>,
    /// Relative tolerance (1e-14 to 0.1; default 1e-10).
    #[schema(minimum = 1e-14, maximum = 0.1)]
    pub rtol: Option<f64>,
    /// Absolute tolerance (above 0, at most 0.1; default 1e-12).
    #[schema(exclusive_minimum = 0.0, maximum = 0.1)]
    pub atol: Option<f64>,
}

/// Default relative tolerance of the Runge–Kutta solvers.
pub const DEFAULT_RTOL: f64 = 1e-10;
/// Default absolute tolerance of the Runge–Kutta solvers.
pub const DEFAULT_ATOL: f64 = 1e-12;

/// The solver, normalised.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct SolverNorm {
    /// "exact" | "dopri5" | "dop853".
    #[schema(value_type = crate::jobs::schema::MethodName)]
    pub method: SolverMethod,
    /// Relative tolerance (Runge–Kutta only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rtol: Option<f64>,
    /// Absolute tolerance (Runge–Kutta only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub atol: Option<f64>,
}

impl SolverNorm {
    /// The domain solver.
    pub fn solver(&self) -> Solver {
        match (self.method, self.rtol, self.atol) {
            (SolverMethod::RungeKutta(method), Some(rtol), Some(atol)) => {
                Solver::RungeKutta { method, rtol, atol }
            }
            _ => Solver::Exact,
        }
    }
}

/// The block, normalised (SI units, defaults filled).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct BlockNorm {
    /// α, rad.
    pub alpha: f64,
    /// p, rad/s.
    pub p: f64,
    /// η.
    pub eta: f64,
    /// μ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// g, m/s².
    pub g: f64,
}

impl BlockNorm {
    /// The domain block (an error for values no validated spec holds).
    pub fn block(&self) -> Result<Block, BlockError> {
        Block::new(self.alpha, self.p, Some(self.eta), self.mu, Some(self.g))
    }
}

/// Validates a block spec found at `base`.
pub fn validate_block(spec: &BlockSpec, base: &str) -> Result<BlockNorm, SpecError> {
    let by_params = spec.alpha.is_some() || spec.p.is_some();
    let by_geometry = spec.b.is_some() || spec.h.is_some();
    let finite = |v: Option<f64>, name: &str| -> Result<(), SpecError> {
        match v {
            Some(x) if !x.is_finite() => Err(SpecError::at(
                format!("{base}/{name}"),
                "must be a finite number",
            )),
            _ => Ok(()),
        }
    };
    for (v, name) in [
        (spec.alpha, "alpha"),
        (spec.p, "p"),
        (spec.b, "b"),
        (spec.h, "h"),
        (spec.eta, "eta"),
        (spec.mu, "mu"),
        (spec.g, "g"),
    ] {
        finite(v, name)?;
    }
    use crate::dynamics::block::BlockError as E;
    let map = |e: E| -> SpecError {
        let field = match e {
            E::Slenderness(_) => "alpha",
            E::FrequencyParameter(_) => "p",
            E::Restitution(_) => "eta",
            E::Friction(_) => "mu",
            E::Gravity(_) => "g",
            E::Geometry(b, _) => {
                if b > 0.0 {
                    "h"
                } else {
                    "b"
                }
            }
        };
        SpecError::at(format!("{base}/{field}"), e.to_string())
    };
    let block = match (by_params, by_geometry) {
        (true, true) => {
            return Err(SpecError::at(
                base,
                "give either alpha and p, or b and h (half-width and half-height), not both",
            ));
        }
        (false, false) => {
            return Err(SpecError::at(
                base,
                "missing block: give alpha (rad) and p (rad/s), or b and h (m)",
            ));
        }
        (true, false) => {
            let alpha = spec
                .alpha
                .ok_or_else(|| SpecError::at(format!("{base}/alpha"), "missing field (rad)"))?;
            let p = spec
                .p
                .ok_or_else(|| SpecError::at(format!("{base}/p"), "missing field (rad/s)"))?;
            Block::new(alpha, p, spec.eta, spec.mu, spec.g).map_err(map)?
        }
        (false, true) => {
            let b = spec
                .b
                .ok_or_else(|| SpecError::at(format!("{base}/b"), "missing field (m)"))?;
            let h = spec
                .h
                .ok_or_else(|| SpecError::at(format!("{base}/h"), "missing field (m)"))?;
            Block::from_geometry(b, h, spec.eta, spec.mu, spec.g).map_err(map)?
        }
    };
    Ok(BlockNorm {
        alpha: block.slenderness(),
        p: block.frequency_parameter(),
        eta: block.restitution(),
        mu: block.friction(),
        g: block.gravity(),
    })
}

/// Parses the pulse family name.
pub fn parse_shape(spec: &PulseSpec, base: &str) -> Result<PulseShape, SpecError> {
    let kind = spec.kind.as_deref().ok_or_else(|| {
        SpecError::at(
            format!("{base}/type"),
            format!("missing field: {PULSE_TYPES}"),
        )
    })?;
    let shape = match kind.to_ascii_lowercase().as_str() {
        "one_sine" | "sine" | "type_a" | "a" => PulseShape::OneSine,
        "one_cosine" | "cosine" | "type_b" | "b" => PulseShape::OneCosine,
        "cn" | "type_cn" | "type_c" | "c" => PulseShape::Cn(spec.n.unwrap_or(1)),
        "half_sine" => PulseShape::HalfSine,
        "rectangular" => PulseShape::Rectangular,
        "ricker" => PulseShape::Ricker {
            symmetric: spec.symmetric.unwrap_or(true),
        },
        "mavroeidis_papageorgiou" => mavroeidis_papageorgiou(spec, base)?,
        other => {
            return Err(SpecError::at(
                format!("{base}/type"),
                format!("unknown pulse type {other:?}: expected {PULSE_TYPES}"),
            ));
        }
    };
    if let PulseShape::Cn(n) = shape {
        if !(1..=1000).contains(&n) {
            return Err(SpecError::at(
                format!("{base}/n"),
                "n must satisfy 1 <= n <= 1000",
            ));
        }
    } else if spec.n.is_some() {
        return Err(SpecError::at(
            format!("{base}/n"),
            "n applies to cn pulses only",
        ));
    }
    if spec.symmetric.is_some() && !matches!(shape, PulseShape::Ricker { .. }) {
        return Err(SpecError::at(
            format!("{base}/symmetric"),
            "symmetric applies to ricker pulses only",
        ));
    }
    if !matches!(shape, PulseShape::MavroeidisPapageorgiou { .. }) {
        for (v, name) in [(spec.gamma, "gamma"), (spec.nu, "nu")] {
            if v.is_some() {
                return Err(SpecError::at(
                    format!("{base}/{name}"),
                    format!("{name} applies to mavroeidis_papageorgiou pulses only"),
                ));
            }
        }
    }
    Ok(shape)
}

/// The Mavroeidis–Papageorgiou family of a spec: γ required, 1 < γ ≤ 20; ν
/// finite, default 0, taken modulo 2π.
fn mavroeidis_papageorgiou(spec: &PulseSpec, base: &str) -> Result<PulseShape, SpecError> {
    use crate::dynamics::mavroeidis_papageorgiou::GAMMA_MAX;
    let gamma = spec.gamma.ok_or_else(|| {
        SpecError::at(
            format!("{base}/gamma"),
            format!("missing field: the carrier cycles under the bell, 1 < gamma <= {GAMMA_MAX}"),
        )
    })?;
    if !(gamma.is_finite() && gamma > 1.0 && gamma <= GAMMA_MAX) {
        return Err(SpecError::at(
            format!("{base}/gamma"),
            format!("must satisfy 1 < gamma <= {GAMMA_MAX} (got {gamma})"),
        ));
    }
    let nu = spec.nu.unwrap_or(0.0);
    PulseShape::mavroeidis_papageorgiou(gamma, nu)
        .ok_or_else(|| SpecError::at(format!("{base}/nu"), "must be a finite number (rad)"))
}

/// The pulse types a spec may name.
pub const PULSE_TYPES: &str =
    "one_sine | one_cosine | cn | half_sine | rectangular | ricker | mavroeidis_papageorgiou";

/// Name of a pulse family in normalised specs.
pub fn shape_name(shape: PulseShape) -> &'static str {
    match shape {
        PulseShape::OneSine => "one_sine",
        PulseShape::OneCosine => "one_cosine",
        PulseShape::Cn(_) => "cn",
        PulseShape::HalfSine => "half_sine",
        PulseShape::Rectangular => "rectangular",
        PulseShape::Ricker { .. } => "ricker",
        PulseShape::MavroeidisPapageorgiou { .. } => "mavroeidis_papageorgiou",
    }
}

/// What picks a pulse within its family besides the family's name, as
/// normalised specs write it: `n` (cn), `symmetric` (ricker), `gamma` and
/// `nu` (mavroeidis_papageorgiou); `None` where the family has no such
/// parameter.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShapeParams {
    /// Cycles of a Type-Cn pulse.
    pub n: Option<u32>,
    /// Symmetric Ricker wavelet or its derivative.
    pub symmetric: Option<bool>,
    /// γ of a Mavroeidis–Papageorgiou pulse.
    pub gamma: Option<f64>,
    /// ν of a Mavroeidis–Papageorgiou pulse, rad, in (−π, π].
    pub nu: Option<f64>,
}

impl ShapeParams {
    /// The parameters of `shape`.
    pub fn of(shape: PulseShape) -> Self {
        match shape {
            PulseShape::Cn(n) => ShapeParams {
                n: Some(n),
                ..Self::default()
            },
            PulseShape::Ricker { symmetric } => ShapeParams {
                symmetric: Some(symmetric),
                ..Self::default()
            },
            PulseShape::MavroeidisPapageorgiou { gamma, nu } => ShapeParams {
                gamma: Some(gamma.get()),
                nu: Some(nu.get()),
                ..Self::default()
            },
            _ => Self::default(),
        }
    }
}

/// The family a normalised name ([`shape_name`]) and its parameters stand
/// for; `None` for an unknown name or a Mavroeidis–Papageorgiou family
/// without a valid γ.
pub fn shape_of(name: &str, params: ShapeParams) -> Option<PulseShape> {
    Some(match name {
        "one_sine" => PulseShape::OneSine,
        "one_cosine" => PulseShape::OneCosine,
        "cn" => PulseShape::Cn(params.n.unwrap_or(1)),
        "half_sine" => PulseShape::HalfSine,
        "rectangular" => PulseShape::Rectangular,
        "ricker" => PulseShape::Ricker {
            symmetric: params.symmetric.unwrap_or(true),
        },
        "mavroeidis_papageorgiou" => {
            PulseShape::mavroeidis_papageorgiou(params.gamma?, params.nu.unwrap_or(0.0))?
        }
        _ => return None,
    })
}

/// The one of `options` (a value and its field name under `base`) that is
/// given, with its index; `None` when none is. Two given are an error at the
/// second, naming every alternative: a quantity is given in one unit only.
pub fn at_most_one<T: Copy>(
    base: &str,
    options: &[(Option<T>, &str)],
    what: &str,
) -> Result<Option<(T, usize)>, SpecError> {
    let given: Vec<(usize, T, &str)> = options
        .iter()
        .enumerate()
        .filter_map(|(i, (v, n))| v.map(|v| (i, v, *n)))
        .collect();
    match given.as_slice() {
        [] => Ok(None),
        [(i, v, _)] => Ok(Some((*v, *i))),
        [_, (_, _, second), ..] => {
            let names: Vec<&str> = options.iter().map(|(_, n)| *n).collect();
            Err(SpecError::at(
                format!("{base}/{second}"),
                format!(
                    "give exactly one {what} ({}), not several",
                    names.join(", ")
                ),
            ))
        }
    }
}

/// A quantity a spec may give in any of several units: `(value, field, factor
/// to the canonical unit)` for each. The one given, with its field and factor
/// (`None` when none is); two given are an error at the second.
pub fn in_one_unit<T: Copy>(
    options: &[(Option<T>, &'static str, f64)],
    what: &str,
) -> Result<Option<(T, &'static str, f64)>, SpecError> {
    let named: Vec<(Option<T>, &str)> = options.iter().map(|o| (o.0, o.1)).collect();
    Ok(at_most_one("", &named, what)?.map(|(v, i)| (v, options[i].1, options[i].2)))
}

fn exactly_one(
    base: &str,
    options: &[(Option<f64>, &str)],
    what: &str,
) -> Result<(f64, usize), SpecError> {
    let names: Vec<&str> = options.iter().map(|(_, n)| *n).collect();
    match at_most_one(base, options, what)? {
        None => Err(SpecError::at(
            base,
            format!("missing {what}: give exactly one of {}", names.join(", ")),
        )),
        Some((v, i)) if v.is_finite() => Ok((v, i)),
        Some((_, i)) => Err(SpecError::at(
            format!("{base}/{}", names[i]),
            "must be a finite number",
        )),
    }
}

/// The pulse of a time history, normalised.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, utoipa::ToSchema)]
pub struct PulseNorm {
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
    /// ω_p, rad/s.
    pub omega_p: f64,
    /// a_p, m/s².
    pub a_p: f64,
    /// The family these fields name.
    #[serde(skip)]
    pub shape: PulseShape,
}

impl PulseNorm {
    /// The pulse of family `shape`, ω_p and a_p, as normalised specs write it.
    pub fn of(shape: PulseShape, omega_p: f64, a_p: f64) -> Self {
        let params = ShapeParams::of(shape);
        PulseNorm {
            kind: shape_name(shape),
            n: params.n,
            symmetric: params.symmetric,
            gamma: params.gamma,
            nu: params.nu,
            omega_p,
            a_p,
            shape,
        }
    }
}

/// A [`PulseNorm`] as documents hold it: its family by name and parameters.
#[derive(Deserialize)]
struct PulseNormDoc {
    #[serde(rename = "type")]
    kind: String,
    n: Option<u32>,
    symmetric: Option<bool>,
    gamma: Option<f64>,
    nu: Option<f64>,
    omega_p: f64,
    a_p: f64,
}

impl<'de> Deserialize<'de> for PulseNorm {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let d = PulseNormDoc::deserialize(d)?;
        let params = ShapeParams {
            n: d.n,
            symmetric: d.symmetric,
            gamma: d.gamma,
            nu: d.nu,
        };
        let shape = family_of(&d.kind, params).map_err(serde::de::Error::custom)?;
        Ok(PulseNorm::of(shape, d.omega_p, d.a_p))
    }
}

/// The family a normalised spec names by `name` and `params`, which must be
/// exactly the ones it writes ([`ShapeParams::of`]).
pub(crate) fn family_of(name: &str, params: ShapeParams) -> Result<PulseShape, String> {
    let shape = shape_of(name, params)
        .ok_or_else(|| format!("unknown pulse type {name:?} or parameters {params:?}"))?;
    if ShapeParams::of(shape) != params {
        return Err(format!(
            "the parameters {params:?} are not those of a {name} pulse"
        ));
    }
    Ok(shape)
}

/// Range checked for ω_p/p.
pub const OMEGA_RATIO_RANGE: (f64, f64) = (1e-3, 1e4);
/// Largest |a_p|/(α g) accepted.
pub const MAX_AMPLITUDE_ALPHA_G: f64 = 1e8;

/// Validates a fully specified pulse (time histories).
pub fn validate_pulse(
    spec: &PulseSpec,
    block: &BlockNorm,
    base: &str,
) -> Result<(PulseNorm, Pulse), SpecError> {
    let shape = parse_shape(spec, base)?;
    let (w, which) = exactly_one(
        base,
        &[
            (spec.omega_p, "omega_p"),
            (spec.frequency_hz, "frequency_hz"),
            (spec.omega_ratio, "omega_ratio"),
            (spec.duration_s, "duration_s"),
        ],
        "frequency",
    )?;
    if which == 3 && shape != PulseShape::Rectangular {
        return Err(SpecError::at(
            format!("{base}/duration_s"),
            "duration_s applies to rectangular pulses only: give omega_p, frequency_hz or omega_ratio",
        ));
    }
    if which == 3 && w <= 0.0 {
        return Err(SpecError::at(
            format!("{base}/duration_s"),
            format!("must be positive (got {w})"),
        ));
    }
    let (field, omega) = match which {
        0 => ("omega_p", w),
        1 => ("frequency_hz", 2.0 * std::f64::consts::PI * w),
        2 => ("omega_ratio", w * block.p),
        _ => ("duration_s", std::f64::consts::PI / w),
    };
    let ratio = omega / block.p;
    if omega <= 0.0 || ratio < OMEGA_RATIO_RANGE.0 || ratio > OMEGA_RATIO_RANGE.1 {
        return Err(SpecError::at(
            format!("{base}/{field}"),
            format!(
                "must be positive with {} <= omega_p/p <= {} (got omega_p/p = {ratio})",
                OMEGA_RATIO_RANGE.0, OMEGA_RATIO_RANGE.1
            ),
        ));
    }
    let (a, which) = exactly_one(
        base,
        &[
            (spec.a_p, "a_p"),
            (spec.a_p_g, "a_p_g"),
            (spec.a_p_alpha_g, "a_p_alpha_g"),
        ],
        "amplitude",
    )?;
    let (field, a_p) = match which {
        0 => ("a_p", a),
        1 => ("a_p_g", a * block.g),
        _ => ("a_p_alpha_g", a * block.alpha * block.g),
    };
    if a_p == 0.0 || (a_p / (block.alpha * block.g)).abs() > MAX_AMPLITUDE_ALPHA_G {
        return Err(SpecError::at(
            format!("{base}/{field}"),
            format!("must be non-zero with |a_p|/(alpha g) <= {MAX_AMPLITUDE_ALPHA_G:e}"),
        ));
    }
    let pulse = Pulse::new(shape, a_p, omega).map_err(|e| SpecError::at(base, e.to_string()))?;
    Ok((PulseNorm::of(shape, omega, a_p), pulse))
}

/// Parses the formulation (default nonlinear).
pub fn parse_formulation(v: Option<&str>, pointer: &str) -> Result<Formulation, SpecError> {
    let Some(name) = v.map(|s| s.to_ascii_lowercase()) else {
        return Ok(Formulation::Nonlinear);
    };
    super::names::formulation::from_name(&name).ok_or_else(|| {
        SpecError::at(
            pointer,
            format!("unknown formulation {name:?}: expected linear | nonlinear"),
        )
    })
}

/// Validates the solver for a ground motion that has (`closed_form`: a
/// sinusoidal pulse or a record) or lacks (a wavelet) the closed-form linear
/// solution. Default: exact for the linear formulation where it exists,
/// dop853 otherwise.
pub fn validate_solver_for(
    spec: Option<&SolverSpec>,
    formulation: Formulation,
    closed_form: bool,
    base: &str,
) -> Result<SolverNorm, SpecError> {
    let default = SolverSpec::default();
    let spec = spec.unwrap_or(&default);
    let method = match spec
        .method
        .as_deref()
        .map(|s| s.to_ascii_lowercase())
        .as_deref()
    {
        None => {
            if formulation == Formulation::Linear && closed_form {
                SolverMethod::Exact
            } else {
                SolverMethod::RungeKutta(Method::Dop853)
            }
        }
        Some("exact") => SolverMethod::Exact,
        Some("dopri5") | Some("rk45") => SolverMethod::RungeKutta(Method::Dopri5),
        Some("dop853") => SolverMethod::RungeKutta(Method::Dop853),
        Some(other) => {
            return Err(SpecError::at(
                format!("{base}/method"),
                format!("unknown method {other:?}: expected exact | dopri5 | dop853"),
            ));
        }
    };
    if method == SolverMethod::Exact {
        if !closed_form {
            return Err(SpecError::at(
                format!("{base}/method"),
                "the exact solver solves sinusoidal pulses (one_sine, one_cosine, cn, half_sine, rectangular) and ground-motion records only: use dopri5 or dop853 (the default) for a ricker or mavroeidis_papageorgiou pulse",
            ));
        }
        if formulation != Formulation::Linear {
            return Err(SpecError::at(
                format!("{base}/method"),
                "the exact solver solves the linear formulation only",
            ));
        }
        if spec.rtol.is_some() || spec.atol.is_some() {
            let f = if spec.rtol.is_some() { "rtol" } else { "atol" };
            return Err(SpecError::at(
                format!("{base}/{f}"),
                "tolerances apply to dopri5 and dop853 only",
            ));
        }
        return Ok(SolverNorm {
            method,
            rtol: None,
            atol: None,
        });
    }
    let rtol = spec.rtol.unwrap_or(DEFAULT_RTOL);
    let atol = spec.atol.unwrap_or(DEFAULT_ATOL);
    if !(rtol.is_finite() && (1e-14..=0.1).contains(&rtol)) {
        return Err(SpecError::at(
            format!("{base}/rtol"),
            "must satisfy 1e-14 <= rtol <= 0.1",
        ));
    }
    if !(atol.is_finite() && atol > 0.0 && atol <= 0.1) {
        return Err(SpecError::at(
            format!("{base}/atol"),
            "must satisfy 0 < atol <= 0.1",
        ));
    }
    Ok(SolverNorm {
        method,
        rtol: Some(rtol),
        atol: Some(atol),
    })
}

/// A sampled ground-acceleration record: its samples (`dt`, `acc`, `unit`),
/// or a stored record named by id (`record`; the service reads it), or a file
/// (`file`; `topple run` reads it).
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct GroundMotionSpec {
    /// Sampling interval, s (1e-5 <= dt <= 1).
    #[schema(minimum = 1e-5, maximum = 1.0)]
    pub dt: Option<f64>,
    /// Accelerations at t_k = k·dt, k = 0..N−1 (2 <= N <= 1000000), linear in between.
    #[schema(min_items = 2, max_items = 1_000_000)]
    pub acc: Option<Vec<f64>>,
    /// Unit of `acc`: "g" (the block's g) | "m/s2" | "cm/s2" (also "gal").
    #[schema(value_type = Option<crate::jobs::schema::UnitInput>)]
    pub unit: Option<String>,
    /// A stored record (`POST /v1/records`), by id, instead of the samples:
    /// the same computation as the spec holding its samples.
    #[schema(pattern = "^[0-9a-f]{32}$")]
    pub record: Option<String>,
    /// A record file read by `topple run` (offline only; the service refuses
    /// it): `{"file": "path", "format"?, "unit"?, "dt"?, "time_column"?,
    /// "acc_column"?}` as for `topple record`.
    pub file: Option<String>,
    /// The samples' PGA above 5 g in their unit is intended (without it such a
    /// record is refused as a likely unit mistake). Not part of the
    /// computation: it does not change the cache key.
    pub allow_large_pga: Option<bool>,
    /// Time histories, record spectra and record forensic queries: the
    /// vertical ground acceleration (positive up), `{"ratio": r}` (ü_v =
    /// r·ü_g) or samples on the same dt (`{"acc": [...], "unit": ...}`; the
    /// shorter record is padded with zeros), scaled with the record where
    /// the kind scales it.
    pub vertical: Option<super::vertical_record::VerticalRecordSpec>,
}

pub use crate::records::{MAX_RECORD_SAMPLES, RECORD_DT_RANGE};

/// A record, normalised: samples in m/s².
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, utoipa::ToSchema)]
pub struct GroundMotionNorm {
    /// Sampling interval, s.
    pub dt: f64,
    /// Accelerations, m/s².
    #[serde(
        serialize_with = "serialize_samples",
        deserialize_with = "deserialize_samples"
    )]
    #[schema(value_type = Vec<f64>)]
    pub acc: Arc<[f64]>,
    /// Always "m/s2".
    #[schema(value_type = crate::jobs::schema::MetresPerSecondSquared)]
    pub unit: tag::MetresPerSecondSquared,
    /// The vertical acceleration (samples; a ratio is the job's `vertical`
    /// in the kinds that scale the record).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical: Option<super::vertical_record::VerticalRecordNorm>,
}

fn serialize_samples<S: serde::Serializer>(v: &Arc<[f64]>, s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(v.iter())
}

fn deserialize_samples<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Arc<[f64]>, D::Error> {
    Vec::<f64>::deserialize(d).map(Arc::from)
}

impl GroundMotionNorm {
    /// The domain record.
    pub fn record(&self) -> Result<Record, crate::dynamics::RecordError> {
        Record::new(self.acc.clone(), self.dt)
    }

    /// The record with its vertical acceleration, when it has one.
    pub fn pair(
        &self,
    ) -> Option<Result<crate::dynamics::RecordPair, crate::dynamics::vertical::PairError>> {
        use crate::dynamics::RecordPair;
        use crate::dynamics::vertical::PairError;
        let v = self.vertical.as_ref()?;
        let pair = || -> Result<RecordPair, PairError> {
            let horizontal = self.record()?;
            match (&v.acc, v.ratio) {
                (Some(acc), _) => RecordPair::new(horizontal, Record::new(acc.clone(), self.dt)?),
                (None, r) => {
                    RecordPair::proportional(horizontal, r.unwrap_or(0.0)).ok_or(PairError::Empty)
                }
            }
        };
        Some(pair())
    }
}

/// Validates a ground-motion record found at `base`.
pub fn validate_ground_motion(
    spec: &GroundMotionSpec,
    block: &BlockNorm,
    base: &str,
) -> Result<(GroundMotionNorm, Record), SpecError> {
    samples_only(spec, base)?;
    let dt = record_dt(spec, base)?;
    let unit = record_unit(spec, base)?;
    let acc = record_acc(spec, base)?;
    let samples = samples_in_m_s2(acc, unit, block, base)?;
    let pga_g = samples.iter().fold(0.0f64, |m, a| m.max(a.abs())) / crate::records::G_M_S2;
    if let crate::records::PgaCheck::Implausible(hint) = crate::records::check_pga(pga_g, unit)
        && spec.allow_large_pga != Some(true)
    {
        return Err(SpecError::at(
            format!("{base}/unit"),
            format!("{hint} (set \"allow_large_pga\": true if this PGA is intended)"),
        ));
    }
    let samples: Arc<[f64]> = samples.into();
    let record =
        Record::new(samples.clone(), dt).map_err(|e| SpecError::at(base, e.to_string()))?;
    Ok((
        GroundMotionNorm {
            dt,
            acc: samples,
            unit: tag::MetresPerSecondSquared,
            vertical: None,
        },
        record,
    ))
}

/// A record read here is given by its samples: no vertical motion, no stored
/// record, no file.
fn samples_only(spec: &GroundMotionSpec, base: &str) -> Result<(), SpecError> {
    if spec.vertical.is_some() {
        return Err(SpecError::at(
            format!("{base}/vertical"),
            "vertical ground motion is simulated by time_history jobs only",
        ));
    }
    if spec.record.is_some() {
        return Err(SpecError::at(
            format!("{base}/record"),
            "names a stored record, which only the service reads (POST /v1/records): offline, give the samples or a file",
        ));
    }
    if spec.file.is_some() {
        return Err(SpecError::at(
            format!("{base}/file"),
            "a file is read by `topple run` only: upload it (POST /v1/records) and name it with {\"record\": id}",
        ));
    }
    Ok(())
}

/// The record's time step, s, in `RECORD_DT_RANGE`.
fn record_dt(spec: &GroundMotionSpec, base: &str) -> Result<f64, SpecError> {
    let dt = spec
        .dt
        .ok_or_else(|| SpecError::at(format!("{base}/dt"), "missing field (s)"))?;
    if !(dt.is_finite() && (RECORD_DT_RANGE.0..=RECORD_DT_RANGE.1).contains(&dt)) {
        return Err(SpecError::at(
            format!("{base}/dt"),
            format!(
                "must satisfy {:e} <= dt <= {} (s)",
                RECORD_DT_RANGE.0, RECORD_DT_RANGE.1
            ),
        ));
    }
    Ok(dt)
}

/// The unit of the record's samples.
fn record_unit(spec: &GroundMotionSpec, base: &str) -> Result<crate::records::Unit, SpecError> {
    let unit_text = spec
        .unit
        .as_deref()
        .ok_or_else(|| SpecError::at(format!("{base}/unit"), "missing field: g | m/s2 | cm/s2"))?;
    crate::records::Unit::parse(unit_text).ok_or_else(|| {
        SpecError::at(
            format!("{base}/unit"),
            format!("unknown unit {unit_text:?}: expected g | m/s2 | cm/s2 (gal)"),
        )
    })
}

/// The record's samples as given: 2 to `MAX_RECORD_SAMPLES` of them, not
/// (time, acceleration) pairs read as one series.
fn record_acc<'a>(spec: &'a GroundMotionSpec, base: &str) -> Result<&'a [f64], SpecError> {
    let acc = spec
        .acc
        .as_ref()
        .ok_or_else(|| SpecError::at(format!("{base}/acc"), "missing field"))?;
    if acc.len() < 2 || acc.len() > MAX_RECORD_SAMPLES {
        return Err(SpecError::at(
            format!("{base}/acc"),
            format!(
                "must hold 2 to {MAX_RECORD_SAMPLES} samples (got {})",
                acc.len()
            ),
        ));
    }
    if crate::records::looks_interleaved(acc) {
        return Err(SpecError::at(
            format!("{base}/acc"),
            "every other value rises by a constant step: these look like (time, acceleration) pairs read as one series; give the accelerations alone with dt, or upload the file (POST /v1/records) as two columns",
        ));
    }
    Ok(acc)
}

/// The samples `acc`, given in `unit`, in m/s², each finite and within
/// `MAX_AMPLITUDE_ALPHA_G` αg of `block`.
fn samples_in_m_s2(
    acc: &[f64],
    unit: crate::records::Unit,
    block: &BlockNorm,
    base: &str,
) -> Result<Vec<f64>, SpecError> {
    // A record in g is in the block's g (as a pulse's a_p_g is).
    let to_m_s2 = |a: f64| match unit {
        crate::records::Unit::G => a * block.g,
        crate::records::Unit::MetresPerSecondSquared => a,
        crate::records::Unit::CentimetresPerSecondSquared => a / 100.0,
    };
    let bound = MAX_AMPLITUDE_ALPHA_G * block.alpha * block.g;
    let mut samples = Vec::with_capacity(acc.len());
    for (k, &a) in acc.iter().enumerate() {
        let a = to_m_s2(a);
        if !(a.is_finite() && a.abs() <= bound) {
            return Err(SpecError::at(
                format!("{base}/acc/{k}"),
                format!(
                    "must be a finite number with |acc|/(alpha g) <= {MAX_AMPLITUDE_ALPHA_G:e}"
                ),
            ));
        }
        samples.push(a);
    }
    Ok(samples)
}
