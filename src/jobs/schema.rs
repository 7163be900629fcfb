//! Names the API description gives to fixed strings and to the union of
//! result documents. Schema only: nothing here is constructed; the documents
//! themselves are the types of the kind modules.

#![allow(dead_code, clippy::large_enum_variant)]

use utoipa::ToSchema;

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
    /// Samples of a normalised record are in m/s².
    MetresPerSecondSquared = "m/s2"
);

/// What a forensic query's unknowns belong to.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum ForensicExcitation {
    /// A pulse family: its frequency and amplitude.
    Pulse,
    /// A recorded motion: its scale.
    GroundMotion,
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
    /// The closed form (linear formulation; sinusoidal pulses and records).
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
    /// Housner's half-sine: a_p sin(ω_p t) for π/ω_p.
    HalfSine,
    /// Housner's rectangular pulse: a_p for t_d = π/ω_p.
    Rectangular,
    /// Ricker wavelet, symmetric or antisymmetric (`symmetric`).
    Ricker,
    /// Mavroeidis & Papageorgiou's (2003) near-fault pulse (`gamma`, `nu`).
    MavroeidisPapageorgiou,
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
    /// Housner's half-sine: a_p sin(ω_p t) for π/ω_p.
    #[schema(rename = "half_sine")]
    HalfSine,
    /// Housner's rectangular pulse: a_p for t_d = π/ω_p.
    #[schema(rename = "rectangular")]
    Rectangular,
    /// Ricker wavelet: symmetric (default) or antisymmetric (`"symmetric": false`),
    /// over 0 ≤ t ≤ 3/f_p.
    #[schema(rename = "ricker")]
    Ricker,
    /// Mavroeidis & Papageorgiou's (2003) near-fault pulse: ground velocity
    /// (V/2)[1 + cos(2π f_p τ/γ)] cos(2π f_p τ + ν) over 0 ≤ t ≤ γ/f_p
    /// (τ = t − γ/(2f_p)), scaled so that max |ü_g| = |a_p|; `gamma` required.
    #[schema(rename = "mavroeidis_papageorgiou")]
    MavroeidisPapageorgiou,
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
    /// The closed form (linear formulation; sinusoidal pulses and records).
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
    /// cm/s².
    #[schema(rename = "cm/s2")]
    CentimetresPerSecondSquared,
    /// Alias of cm/s2.
    #[schema(rename = "gal")]
    Gal,
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
    /// A bound on one history's work (impacts, steps, free motion) was
    /// reached: the history ends there, its outcome past it not followed.
    LimitReached,
    /// The state at the pulse end is within tolerance of the separatrix.
    NearSeparatrix,
    /// The block's size R = 3g/(4p²) lies outside 1 cm – 100 m (b and h are
    /// half-dimensions in metres; p is in rad/s).
    ImplausibleSize,
    /// The record's PGA exceeds 2 g: a strong record, or a unit read wrongly.
    LargePga,
    /// The record's final ground velocity is far from zero: its baseline
    /// drifts (an uncorrected record?).
    BaselineDrift,
    /// The record has fewer than 2 samples per 2π/(10p), the shortest ground
    /// period that matters to the block.
    CoarseDt,
    /// The record's PGA never exceeds the block's rocking threshold.
    NeverRocks,
    /// A forensic observation's residual slide (`slid_m`) reaches past
    /// 1 m: centimetres given as metres?
    ImplausibleSlide,
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

/// A positive number.
#[derive(ToSchema)]
#[schema(value_type = f64, exclusive_minimum = 0.0)]
pub struct PositiveNumber(f64);

/// The pulse family of a spectrum, friction spectrum or forensic query: the
/// frequency and the amplitude vary, so only the family is given.
#[derive(ToSchema, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PulseFamilyInput {
    /// "one_sine" | "one_cosine" | "cn" | "half_sine" | "rectangular" | "ricker"
    /// | "mavroeidis_papageorgiou" (aliases: "sine", "type_a", "cosine",
    /// "type_b", "type_cn").
    #[serde(rename = "type")]
    #[schema(value_type = PulseTypeInput)]
    kind: String,
    /// Displacement cycles of a Type-Cn pulse (default 1; cn only).
    #[schema(minimum = 1, maximum = 1000)]
    n: Option<u32>,
    /// Ricker only: the symmetric wavelet (default true) or its normalised
    /// derivative (false).
    symmetric: Option<bool>,
    /// Mavroeidis–Papageorgiou only (required there): γ, the carrier cycles
    /// under the bell, 1 < γ ≤ 20.
    #[schema(exclusive_minimum = 1.0, maximum = 20.0)]
    gamma: Option<f64>,
    /// Mavroeidis–Papageorgiou only: ν, the carrier's phase at the bell's
    /// centre, rad (default 0; any finite value, taken modulo 2π to (−π, π]).
    nu: Option<f64>,
}

/// The rules of a spec that span several fields (one of several units, a
/// block by parameters or by geometry, a pulse or a record), as JSON Schema
/// keywords on the request schemas. A field counts as given when it is
/// present and not null, as the server reads it.
pub mod rules {
    use serde_json::{Value, json};
    use utoipa::openapi::{OpenApi, RefOr, Schema, extensions::Extensions};

    /// `name` is present and not null.
    fn given(name: &str) -> Value {
        json!({"required": [name], "properties": {name: {"not": {"type": "null"}}}})
    }

    /// Exactly one of `names` is given.
    fn exactly_one(names: &[&str]) -> Value {
        json!({"oneOf": names.iter().map(|n| given(n)).collect::<Vec<_>>()})
    }

    /// At most one of `names` is given.
    fn at_most_one(names: &[&str]) -> Value {
        let mut pairs = Vec::new();
        for (i, a) in names.iter().enumerate() {
            for b in &names[i + 1..] {
                pairs.push(json!({"allOf": [given(a), given(b)]}));
            }
        }
        match <[Value; 1]>::try_from(pairs) {
            Ok([pair]) => json!({ "not": pair }),
            Err(pairs) => json!({"not": {"anyOf": pairs}}),
        }
    }

    /// None of `names` is given (each absent or null).
    fn none_of(names: &[&str]) -> Value {
        let nulls: serde_json::Map<String, Value> = names
            .iter()
            .map(|n| (n.to_string(), json!({"type": "null"})))
            .collect();
        json!({ "properties": nulls })
    }

    /// A forensic query on a pulse family (its frequency axis, at most one
    /// amplitude unit) or on a record (its scale axis, nothing of a pulse's).
    fn forensic_on_pulse_or_record(frequency: &[&str]) -> Value {
        let pulse_axes: Vec<&str> = frequency.iter().copied().chain(["a_p_g", "a_p"]).collect();
        json!({"oneOf": [
            {"allOf": [
                given("pulse"),
                exactly_one(frequency),
                at_most_one(&["a_p_g", "a_p"]),
                none_of(&["ground_motion", "scale", "pga_g", "tolerance", "scan_step"]),
            ]},
            {"allOf": [
                given("ground_motion"),
                exactly_one(&["scale", "pga_g"]),
                at_most_one(&["tolerance", "tolerance_g"]),
                at_most_one(&["scan_step", "scan_step_g"]),
                none_of(&[&["pulse"][..], &pulse_axes].concat()),
            ]},
        ]})
    }

    /// Each of `names` is given when any of them is.
    fn together(names: &[&str]) -> Value {
        json!({"anyOf": [
            {"allOf": names.iter().map(|n| given(n)).collect::<Vec<_>>()},
            {"not": {"anyOf": names.iter().map(|n| given(n)).collect::<Vec<_>>()}},
        ]})
    }

    /// `n` only for Type-Cn pulses.
    fn n_for_cn_only() -> Value {
        json!({"if": {"required": ["type"], "properties": {"type": {"not": {"enum": ["cn", "type_cn", "type_c", "c"]}}}},
               "then": {"properties": {"n": {"type": "null"}}}})
    }

    /// `symmetric` only for Ricker pulses.
    fn symmetric_for_ricker_only() -> Value {
        json!({"if": {"required": ["type"], "properties": {"type": {"not": {"enum": ["ricker"]}}}},
               "then": {"properties": {"symmetric": {"type": "null"}}}})
    }

    /// `gamma` and `nu` only for Mavroeidis–Papageorgiou pulses, and
    /// `gamma` required for them.
    fn gamma_and_nu_for_mavroeidis_papageorgiou_only() -> Value {
        json!({"if": {"required": ["type"], "properties": {"type": {"not": {"enum": ["mavroeidis_papageorgiou"]}}}},
               "then": {"properties": {"gamma": {"type": "null"}, "nu": {"type": "null"}}},
               "else": given("gamma")})
    }

    /// `duration_s` only for rectangular pulses.
    fn duration_for_rectangular_only() -> Value {
        json!({"if": {"required": ["type"], "properties": {"type": {"not": {"enum": ["rectangular"]}}}},
               "then": {"properties": {"duration_s": {"type": "null"}}}})
    }

    /// A record given by its samples, or a stored record named by id (a
    /// file is for `topple run` only: the service refuses it).
    fn samples_or_stored_record() -> Value {
        json!({"oneOf": [
            {"allOf": [given("dt"), given("acc"), given("unit"), none_of(&["record", "file"])]},
            {"allOf": [given("record"), none_of(&["dt", "acc", "unit", "file", "allow_large_pga"])]},
        ]})
    }

    /// A record's vertical acceleration: a ratio alone, samples, or a
    /// stored record named by id alone (a file is for `topple run` only).
    fn vertical_ratio_samples_or_stored_record() -> Value {
        json!({"oneOf": [
            {"allOf": [given("ratio"), none_of(&["dt", "acc", "unit", "allow_large_pga", "record", "file"])]},
            {"allOf": [given("acc"), given("unit"), none_of(&["ratio", "record", "file"])]},
            {"allOf": [given("record"), none_of(&["ratio", "dt", "acc", "unit", "allow_large_pga", "file"])]},
        ]})
    }

    /// The rules, by schema name.
    fn table() -> Vec<(&'static str, Vec<Value>)> {
        let frequency = ["omega_ratio", "omega_p", "frequency_hz"];
        let mut rules = block_and_pulse_rules();
        rules.extend(spectrum_and_forensic_rules(&frequency));
        rules.extend(probability_rules(&frequency));
        rules.extend(record_rules());
        rules
    }

    /// The rules of blocks, observations and pulses.
    fn block_and_pulse_rules() -> Vec<(&'static str, Vec<Value>)> {
        vec![
            (
                "BlockSpec",
                vec![
                    together(&["alpha", "p"]),
                    together(&["b", "h"]),
                    exactly_one(&["alpha", "b"]),
                ],
            ),
            (
                "ObservationSpec",
                vec![together(&["b", "h"]), exactly_one(&["block", "b"])],
            ),
            (
                "TimeHistorySpec",
                vec![exactly_one(&["pulse", "ground_motion"])],
            ),
            (
                "PulseSpec",
                vec![
                    exactly_one(&["omega_ratio", "omega_p", "frequency_hz", "duration_s"]),
                    exactly_one(&["a_p", "a_p_g", "a_p_alpha_g"]),
                    n_for_cn_only(),
                    duration_for_rectangular_only(),
                    symmetric_for_ricker_only(),
                    gamma_and_nu_for_mavroeidis_papageorgiou_only(),
                ],
            ),
            (
                "PulseFamilyInput",
                vec![
                    n_for_cn_only(),
                    symmetric_for_ricker_only(),
                    gamma_and_nu_for_mavroeidis_papageorgiou_only(),
                ],
            ),
        ]
    }

    /// The rules of spectra and forensic queries, `frequency` naming the
    /// fields of a frequency axis.
    fn spectrum_and_forensic_rules(frequency: &[&str]) -> Vec<(&'static str, Vec<Value>)> {
        vec![
            (
                "SpectrumSpec",
                vec![
                    exactly_one(frequency),
                    at_most_one(&["a_max_alpha_g", "a_max", "a_max_g"]),
                ],
            ),
            (
                "FrictionSpectrumSpec",
                vec![
                    exactly_one(frequency),
                    exactly_one(&["a_alpha_g", "a_p", "a_p_g"]),
                ],
            ),
            ("ForensicSpec", vec![forensic_on_pulse_or_record(frequency)]),
        ]
    }

    /// The rules of survival and fragility, and their uncertain blocks and
    /// pulses (`frequency` naming the fields of a frequency axis).
    fn probability_rules(frequency: &[&str]) -> Vec<(&'static str, Vec<Value>)> {
        vec![
            (
                "SurvivalSpec",
                vec![json!({"oneOf": [
                    {"allOf": [given("fragility"), given("age_years"), none_of(&["rocks"])]},
                    {"allOf": [given("rocks"), none_of(&["fragility", "age_years"])]},
                ]})],
            ),
            (
                "FragilityInput",
                vec![json!({"oneOf": [
                    {"allOf": [exactly_one(&["median_g", "median"]), given("beta"), none_of(&["job"])]},
                    {"allOf": [given("job"), none_of(&["median_g", "median", "beta"])]},
                ]})],
            ),
            (
                "FragilitySpec",
                vec![exactly_one(&["pulse", "ground_motions"])],
            ),
            (
                "UncertainBlockSpec",
                vec![
                    together(&["alpha", "p"]),
                    together(&["b", "h"]),
                    exactly_one(&["alpha", "b"]),
                ],
            ),
            (
                "UncertainPulseSpec",
                vec![
                    exactly_one(frequency),
                    n_for_cn_only(),
                    symmetric_for_ricker_only(),
                    gamma_and_nu_for_mavroeidis_papageorgiou_only(),
                ],
            ),
        ]
    }

    /// The rules of records and record spectra.
    fn record_rules() -> Vec<(&'static str, Vec<Value>)> {
        vec![
            ("GroundMotionSpec", vec![samples_or_stored_record()]),
            ("NamedMotionSpec", vec![samples_or_stored_record()]),
            (
                "VerticalRecordSpec",
                vec![vertical_ratio_samples_or_stored_record()],
            ),
            (
                "RecordSpectrumSpec",
                vec![exactly_one(&["p", "R_m"]), exactly_one(&["scale", "pga_g"])],
            ),
        ]
    }

    /// Adds the rules (as `allOf`) to the request schemas of `api`, and
    /// `minItems: 1` to lists of values.
    pub fn add(api: &mut OpenApi) {
        let Some(components) = api.components.as_mut() else {
            return;
        };
        for (name, rules) in table() {
            if let Some(RefOr::T(Schema::Object(o))) = components.schemas.get_mut(name) {
                let mut extensions = o.extensions.take().unwrap_or_default();
                extensions.merge(Extensions::from_iter([("allOf", Value::Array(rules))]));
                o.extensions = Some(extensions);
            }
        }
        // An event's data is a JobView written as JSON.
        if let Some(RefOr::T(Schema::Object(event))) = components.schemas.get_mut("JobEvent")
            && let Some(RefOr::T(Schema::Object(data))) = event.properties.get_mut("data")
        {
            data.content_media_type = "application/json".into();
            data.content_schema = Some(Box::new(
                utoipa::openapi::Ref::from_schema_name("JobView").into(),
            ));
        }
        // α < π/2 (an attribute would take the constant as a literal only).
        for name in ["BlockSpec", "RecordBlockSpec"] {
            if let Some(RefOr::T(Schema::Object(block))) = components.schemas.get_mut(name)
                && let Some(RefOr::T(Schema::Object(alpha))) = block.properties.get_mut("alpha")
            {
                alpha.exclusive_maximum = Some(std::f64::consts::FRAC_PI_2.into());
            }
        }
        if let Some(RefOr::T(Schema::OneOf(one_of))) = components.schemas.get_mut("RangeSpec") {
            for item in one_of.items.iter_mut() {
                if let RefOr::T(Schema::Array(list)) = item {
                    list.min_items = Some(1);
                }
            }
        }
    }
}

/// The name of an event of a job's stream.
#[derive(ToSchema)]
#[schema(rename_all = "snake_case")]
pub enum JobEventName {
    /// The job's state now (the first event, then each change).
    Status,
    /// The finished job (the last event).
    Done,
}

/// One Server-Sent Event of `GET /v1/jobs/{id}/events`, as a client parses
/// it from the stream (comments, which keep the connection alive, carry none).
#[derive(ToSchema)]
pub struct JobEvent {
    /// `status` while the job runs, `done` for the last event.
    event: JobEventName,
    /// The job status's ETag (send it as `Last-Event-ID` to resume).
    id: String,
    /// The job as JSON: a light JobView while it runs, the whole JobView when done.
    data: String,
}
