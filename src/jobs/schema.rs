//! Names the API description gives to fixed strings and to the union of
//! result documents. Schema only: nothing here is constructed; the documents
//! themselves are the types of the kind modules.

#![allow(dead_code, clippy::large_enum_variant)]

use utoipa::ToSchema;

use super::forensic::ForensicResult;
use super::friction::FrictionResult;
use super::spectrum::SpectrumResult;
use super::time_history::TimeHistoryResult;

/// A one-value enum: the `kind` of a spec or result.
macro_rules! literal {
    ($(#[$doc:meta])* $name:ident = $value:literal) => {
        $(#[$doc])*
        #[derive(ToSchema)]
        pub enum $name {
            #[schema(rename = $value)]
            Value,
        }
    };
}

literal!(
    /// `"time_history"`.
    TimeHistoryKind = "time_history"
);
literal!(
    /// `"spectrum"`.
    SpectrumKind = "spectrum"
);
literal!(
    /// `"friction_spectrum"`.
    FrictionSpectrumKind = "friction_spectrum"
);
literal!(
    /// `"forensic"`.
    ForensicKind = "forensic"
);
literal!(
    /// Samples of a normalised record are in m/s².
    MetresPerSecondSquared = "m/s2"
);

/// The kind of a job.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum JobKind {
    /// A time history.
    TimeHistory,
    /// An overturning spectrum.
    Spectrum,
    /// A friction-demand spectrum.
    FrictionSpectrum,
    /// A forensic query.
    Forensic,
}

/// The equation of motion (eq. 12/49 or eqs. 23–24/50).
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum FormulationName {
    /// The linearised equation.
    Linear,
    /// The exact rigid-body equation.
    Nonlinear,
}

/// How a normalised spec is solved.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum MethodName {
    /// The closed form (linear formulation, pulses).
    Exact,
    /// Dormand–Prince 5(4).
    Dopri5,
    /// Dormand–Prince 8(5,3).
    Dop853,
}

/// A pulse family in normalised specs.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum PulseTypeName {
    /// Type A, eq. 22.
    OneSine,
    /// Type B, eq. 53.
    OneCosine,
    /// Type Cn.
    Cn,
}

/// A pulse family as a spec names it (canonical names first, then aliases).
#[derive(ToSchema)]
pub enum PulseTypeInput {
    /// Type A, eq. 22.
    #[schema(rename = "one_sine")]
    OneSine,
    /// Type B, eq. 53.
    #[schema(rename = "one_cosine")]
    OneCosine,
    /// Type Cn (with `n`).
    #[schema(rename = "cn")]
    Cn,
    /// Alias of one_sine.
    #[schema(rename = "sine")]
    Sine,
    /// Alias of one_sine.
    #[schema(rename = "type_a")]
    TypeA,
    /// Alias of one_sine.
    #[schema(rename = "a")]
    A,
    /// Alias of one_cosine.
    #[schema(rename = "cosine")]
    Cosine,
    /// Alias of one_cosine.
    #[schema(rename = "type_b")]
    TypeB,
    /// Alias of one_cosine.
    #[schema(rename = "b")]
    B,
    /// Alias of cn.
    #[schema(rename = "type_cn")]
    TypeCn,
    /// Alias of cn.
    #[schema(rename = "type_c")]
    TypeC,
    /// Alias of cn.
    #[schema(rename = "c")]
    C,
}

/// A solver as a spec names it.
#[derive(ToSchema)]
pub enum MethodInput {
    /// The closed form (linear formulation, pulses).
    #[schema(rename = "exact")]
    Exact,
    /// Dormand–Prince 5(4).
    #[schema(rename = "dopri5")]
    Dopri5,
    /// Alias of dopri5.
    #[schema(rename = "rk45")]
    Rk45,
    /// Dormand–Prince 8(5,3).
    #[schema(rename = "dop853")]
    Dop853,
}

/// The unit of a record's samples.
#[derive(ToSchema)]
pub enum UnitInput {
    /// Multiples of g (the block's g).
    #[schema(rename = "g")]
    G,
    /// m/s².
    #[schema(rename = "m/s2")]
    MetresPerSecondSquared,
    /// Alias of m/s2.
    #[schema(rename = "m/s^2")]
    Caret,
    /// Alias of m/s2.
    #[schema(rename = "m/s²")]
    Superscript,
}

/// Direction of a transition: "up" where overturning begins as the amplitude
/// grows, "down" where a safe interval begins.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum TransitionDirection {
    /// Overturning begins.
    Up,
    /// A safe interval begins.
    Down,
}

/// What a warning on a time history says.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum WarningKind {
    /// |f_x/f_z| exceeds μ: the block would slide.
    Sliding,
    /// f_z reaches 0: the block would lift off; the friction demand is unbounded.
    LiftOff,
    /// The friction demand is not followed through the fall of a doomed block.
    DemandExcludesFall,
    /// Free rocking was followed for `outputs.max_free_impacts` impacts only.
    FreeRockingTruncated,
    /// The impact list was truncated (the count is complete).
    ImpactListTruncated,
    /// The state at the pulse end is within tolerance of the separatrix.
    NearSeparatrix,
}

/// A normalised spec (SI units, every default filled in), by `kind`: what a
/// job view and a result document echo.
#[derive(ToSchema)]
#[serde(untagged)]
#[schema(discriminator(property_name = "kind", mapping(
    ("time_history" = "#/components/schemas/TimeHistoryJob"),
    ("spectrum" = "#/components/schemas/SpectrumJob"),
    ("friction_spectrum" = "#/components/schemas/FrictionSpectrumJob"),
    ("forensic" = "#/components/schemas/ForensicJob"),
)))]
pub enum NormalizedSpec {
    /// `"kind": "time_history"`.
    TimeHistory(super::time_history::TimeHistoryJob),
    /// `"kind": "spectrum"`.
    Spectrum(super::spectrum::SpectrumJob),
    /// `"kind": "friction_spectrum"`.
    FrictionSpectrum(super::friction::FrictionJob),
    /// `"kind": "forensic"`.
    Forensic(super::forensic::ForensicJob),
}

/// A result document, by `kind`.
#[derive(ToSchema)]
#[serde(untagged)]
#[schema(discriminator(property_name = "kind", mapping(
    ("time_history" = "#/components/schemas/TimeHistoryResult"),
    ("spectrum" = "#/components/schemas/SpectrumResult"),
    ("friction_spectrum" = "#/components/schemas/FrictionSpectrumResult"),
    ("forensic" = "#/components/schemas/ForensicResult"),
)))]
pub enum JobResult {
    /// `"kind": "time_history"`.
    TimeHistory(TimeHistoryResult),
    /// `"kind": "spectrum"`.
    Spectrum(SpectrumResult),
    /// `"kind": "friction_spectrum"`.
    FrictionSpectrum(FrictionResult),
    /// `"kind": "forensic"`.
    Forensic(ForensicResult),
}

/// A figure: an SVG document.
#[derive(ToSchema)]
#[schema(value_type = String, format = Binary)]
pub struct SvgFigure(String);

/// A table: CSV whose header row names each quantity and its unit.
#[derive(ToSchema)]
#[schema(value_type = String, format = Binary)]
pub struct CsvTable(String);

/// What computed a result (every result document carries it).
#[derive(ToSchema)]
pub struct Engine {
    /// "topple".
    pub name: String,
    /// The release.
    pub version: String,
    /// The version of the numerics (part of every cache key).
    pub numerics: String,
    /// The build's commit, when known.
    pub commit: Option<String>,
}
