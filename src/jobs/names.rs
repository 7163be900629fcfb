//! The fixed names of normalised specs and result documents, typed. Each
//! serialises as the string the documents hold (`"time_history"`,
//! `"linear"`, `"dop853"`, `"pga_g"` …) and deserialises from that string
//! only, refusing any other. The domain enums ([`Formulation`], [`Method`])
//! stay free of serde: the adapters are here.

use serde::de::{Error, Unexpected};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::dynamics::{Formulation, Method};

/// The `kind` of each document, and other one-value strings: unit types that
/// (de)serialise as their string and refuse another.
pub mod tag {
    use super::*;

    macro_rules! tag {
        ($(#[doc = $doc:literal])* $name:ident = $value:literal, schema $schema:ident) => {
            tag!($(#[doc = $doc])* $name = $value);

            impl utoipa::PartialSchema for $name {
                fn schema() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
                    utoipa::openapi::ObjectBuilder::new()
                        .schema_type(utoipa::openapi::schema::Type::String)
                        .description(Some(concat!($($doc),*).trim()))
                        .enum_values(Some([$value]))
                        .into()
                }
            }

            impl utoipa::ToSchema for $name {
                fn name() -> std::borrow::Cow<'static, str> {
                    stringify!($schema).into()
                }
            }
        };
        ($(#[$doc:meta])* $name:ident = $value:literal) => {
            $(#[$doc])*
            #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
            pub struct $name;

            impl $name {
                /// The string it stands for.
                pub const NAME: &'static str = $value;
            }

            impl Serialize for $name {
                fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                    s.serialize_str($value)
                }
            }

            impl<'de> Deserialize<'de> for $name {
                fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                    let s = String::deserialize(d)?;
                    if s == $value {
                        Ok($name)
                    } else {
                        Err(D::Error::invalid_value(
                            Unexpected::Str(&s),
                            &concat!("\"", $value, "\""),
                        ))
                    }
                }
            }
        };
    }

    tag!(
        /// `"time_history"`.
        TimeHistory = "time_history", schema TimeHistoryKind
    );
    tag!(
        /// `"spectrum"`.
        Spectrum = "spectrum", schema SpectrumKind
    );
    tag!(
        /// `"friction_spectrum"`.
        FrictionSpectrum = "friction_spectrum", schema FrictionSpectrumKind
    );
    tag!(
        /// `"forensic"`.
        Forensic = "forensic", schema ForensicKind
    );
    tag!(
        /// `"record_spectrum"`.
        RecordSpectrum = "record_spectrum", schema RecordSpectrumKind
    );
    tag!(
        /// `"survival"`.
        Survival = "survival", schema SurvivalKind
    );
    tag!(
        /// `"fragility"`.
        Fragility = "fragility", schema FragilityKind
    );
    tag!(
        /// `"m/s2"`: the unit of a normalised record's samples.
        MetresPerSecondSquared = "m/s2"
    );
}

/// The formulation of a normalised spec or a result, as `"linear"` |
/// `"nonlinear"` (`#[serde(with = "crate::jobs::names::formulation")]`).
pub mod formulation {
    use super::*;

    /// The names, in the order of [`Formulation`]'s variants.
    pub const NAMES: &[&str] = &["linear", "nonlinear"];

    /// The formulation named exactly `name`.
    pub fn from_name(name: &str) -> Option<Formulation> {
        match name {
            "linear" => Some(Formulation::Linear),
            "nonlinear" => Some(Formulation::Nonlinear),
            _ => None,
        }
    }

    /// Serialises `f` as its name.
    pub fn serialize<S: Serializer>(f: &Formulation, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(f.name())
    }

    /// Deserialises a formulation from its name.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Formulation, D::Error> {
        let s = String::deserialize(d)?;
        from_name(&s).ok_or_else(|| D::Error::unknown_variant(&s, NAMES))
    }
}

/// How a normalised spec is solved: the closed form, or a Runge–Kutta pair.
/// Serialised as `"exact"` | `"dopri5"` | `"dop853"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolverMethod {
    /// The closed form (linear formulation; sinusoidal pulses and records).
    Exact,
    /// A Runge–Kutta pair.
    RungeKutta(Method),
}

impl SolverMethod {
    /// The names, as specs and results write them.
    pub const NAMES: &[&str] = &["exact", "dopri5", "dop853"];

    /// The name used in specs and reports.
    pub fn name(self) -> &'static str {
        match self {
            SolverMethod::Exact => "exact",
            SolverMethod::RungeKutta(m) => m.name(),
        }
    }

    /// The method named exactly `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "exact" => Some(SolverMethod::Exact),
            "dopri5" => Some(SolverMethod::RungeKutta(Method::Dopri5)),
            "dop853" => Some(SolverMethod::RungeKutta(Method::Dop853)),
            _ => None,
        }
    }
}

impl From<Method> for SolverMethod {
    fn from(m: Method) -> Self {
        SolverMethod::RungeKutta(m)
    }
}

impl std::fmt::Display for SolverMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for SolverMethod {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for SolverMethod {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        SolverMethod::from_name(&s).ok_or_else(|| D::Error::unknown_variant(&s, Self::NAMES))
    }
}

/// The intensity measure of hazard curves and fragilities.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Im {
    /// Peak ground acceleration, g.
    #[serde(rename = "pga_g")]
    PgaG,
    /// Peak ground velocity, m/s.
    #[serde(rename = "pgv_m_s")]
    PgvMS,
}

impl Im {
    /// The name used in specs and reports.
    pub fn name(self) -> &'static str {
        match self {
            Im::PgaG => "pga_g",
            Im::PgvMS => "pgv_m_s",
        }
    }

    /// The measure named exactly `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "pga_g" => Some(Im::PgaG),
            "pgv_m_s" => Some(Im::PgvMS),
            _ => None,
        }
    }
}

impl std::fmt::Display for Im {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a forensic query's unknowns belong to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Excitation {
    /// A pulse family: its frequency and amplitude.
    Pulse,
    /// A recorded motion: its scale.
    GroundMotion,
}

/// What computed a result (`key::engine_info`), as every result document
/// carries it under `engine`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct EngineDoc {
    /// "topple".
    pub name: String,
    /// The release.
    pub version: String,
    /// The version of the numerics.
    pub numerics: String,
    /// The build's commit, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub commit: Option<String>,
}
