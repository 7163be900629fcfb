//! Fuzzing of the job-spec parser and of the engine behind it.
//!
//! Parser: `Job::parse` returns, and never panics, for arbitrary text,
//! arbitrary JSON (with the non-JSON tokens `NaN` / `Infinity`, numbers that
//! overflow `f64` or the integer fields, and keys drawn from the real field
//! names), and for valid specs with fields replaced, removed, added or
//! duplicated. Its errors name the field at fault by a JSON pointer ("" or
//! starting with "/") and carry a message. A spec it accepts serialises to a
//! canonical spec that parses back to the same job.
//!
//! Engine: every valid spec drawn from wide but bounded ranges either runs to a
//! result whose numbers are all finite or fails with a `JobError`; it never
//! panics.

use proptest::prelude::*;
use proptest::sample::{Index, select};
use serde_json::{Map, Value, json};
use topple::jobs::JobError;
use topple::kinds::Job;
use topple::kinds::key::cache_key;
use topple::spectrum::Control;

/// Every field name the spec types know, aliases included.
const FIELD_NAMES: &[&str] = &[
    "kind",
    "block",
    "pulse",
    "formulation",
    "solver",
    "outputs",
    "omega_ratio",
    "a_max_alpha_g",
    "tolerance",
    "scan_step_alpha_g",
    "principal_relative_width",
    "a_alpha_g",
    "alpha",
    "slenderness",
    "p",
    "frequency_parameter",
    "b",
    "half_width",
    "h",
    "half_height",
    "eta",
    "restitution",
    "mu",
    "friction",
    "g",
    "gravity",
    "type",
    "shape",
    "n",
    "omega_p",
    "frequency_hz",
    "a_p",
    "a_p_g",
    "a_p_alpha_g",
    "method",
    "rtol",
    "atol",
    "series",
    "reactions",
    "impacts",
    "max_free_impacts",
    "duration",
    "from",
    "to",
    "steps",
];

/// String values the spec types give a meaning to, and a few near misses.
const WORDS: &[&str] = &[
    "time_history",
    "spectrum",
    "friction_spectrum",
    "one_sine",
    "one_cosine",
    "cn",
    "sine",
    "cosine",
    "type_a",
    "type_b",
    "type_c",
    "type_cn",
    "A",
    "b",
    "C",
    "linear",
    "NONLINEAR",
    "nonlinear",
    "exact",
    "dopri5",
    "dop853",
    "RK45",
    "__non_finite_number__",
    "",
    "NaN",
    "Infinity",
    "\\",
    "\"",
    "~0/~1",
    "\u{0}",
    "é€𝄞",
];

/// Number tokens at the edges of what JSON, `f64`, `u32`, `u64` and the
/// validators accept, and tokens that are not JSON at all.
const NUMBER_TOKENS: &[&str] = &[
    "0",
    "-0",
    "0.0",
    "-0.0",
    "1",
    "-1",
    "0.5",
    "2",
    "1e400",
    "-1e400",
    "1e-400",
    "-1e-400",
    "1E+999",
    "2e308",
    "1.7976931348623157e308",
    "-1.7976931348623157e308",
    "4.9e-324",
    "5e-324",
    "2.2250738585072014e-308",
    "1.5707963267948966",
    "1.5707963267948968",
    "1e-3",
    "0.000999",
    "1e4",
    "10000.000001",
    "1e6",
    "1000001",
    "1e8",
    "100000001",
    "1e-14",
    "0.1",
    "1000",
    "1001",
    "10000",
    "10001",
    "100000",
    "100001",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775809",
    "18446744073709551615",
    "18446744073709551616",
    "123456789012345678901234567890123456789",
    "0.00000000000000000000000000000000000000001",
    "NaN",
    "-NaN",
    "Infinity",
    "-Infinity",
    "+Infinity",
    "inf",
    "-inf",
    "+1",
    ".5",
    "01",
    "1.",
    "1e",
    "--1",
    "0x10",
];

/// A JSON string literal holding `s`.
fn quoted(s: &str) -> String {
    Value::String(s.to_string()).to_string()
}

/// A number token: special, formatted from any `f64` (NaN and infinities
/// included), any integer, or an ordinary value.
fn number_token() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => select(NUMBER_TOKENS).prop_map(str::to_string),
        1 => any::<f64>().prop_map(|x| format!("{x}")),
        1 => any::<f64>().prop_map(|x| format!("{x:e}")),
        1 => any::<f64>().prop_map(|x| format!("{x:?}")),
        1 => any::<i64>().prop_map(|x| x.to_string()),
        1 => any::<u64>().prop_map(|x| x.to_string()),
        2 => (-1e4..1e4f64).prop_map(|x| x.to_string()),
        2 => (0u32..2000).prop_map(|x| x.to_string()),
    ]
}

/// A string literal: a meaningful word, a field name or anything at all.
fn string_token() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => select(WORDS).prop_map(quoted),
        1 => select(FIELD_NAMES).prop_map(quoted),
        2 => any::<String>().prop_map(|s| quoted(&s)),
    ]
}

/// An object key, mostly a real field name.
fn key_token() -> impl Strategy<Value = String> {
    prop_oneof![
        5 => select(FIELD_NAMES).prop_map(quoted),
        1 => select(WORDS).prop_map(quoted),
        1 => any::<String>().prop_map(|s| quoted(&s)),
    ]
}

/// JSON text for one value, nested up to `depth` levels. Keys may repeat and
/// number tokens may lie outside JSON (`NaN`, `Infinity`, `inf`, `+1`, …).
fn json_text(depth: u32) -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        1 => select(&["null", "true", "false"][..]).prop_map(str::to_string),
        4 => number_token(),
        2 => string_token(),
    ];
    leaf.prop_recursive(depth, 48, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(|v| format!("[{}]", v.join(","))),
            prop::collection::vec((key_token(), inner), 0..8).prop_map(|kv| {
                let members: Vec<String> = kv.iter().map(|(k, v)| format!("{k}:{v}")).collect();
                format!("{{{}}}", members.join(","))
            }),
        ]
    })
}

/// An object with a real `kind`, so that validation goes past the kind check,
/// and arbitrary members (mostly real field names) besides.
fn spec_shaped_text() -> impl Strategy<Value = String> {
    (
        select(&["time_history", "spectrum", "friction_spectrum"][..]),
        prop::collection::vec((key_token(), json_text(3)), 0..8),
        any::<Index>(),
    )
        .prop_map(|(kind, kv, at)| {
            let mut members: Vec<String> = kv.iter().map(|(k, v)| format!("{k}:{v}")).collect();
            let i = at.index(members.len() + 1);
            members.insert(i, format!("\"kind\":{}", quoted(kind)));
            format!("{{{}}}", members.join(","))
        })
}

/// Text from the characters JSON is made of, in no particular order.
fn json_alphabet_text() -> impl Strategy<Value = String> {
    "[{}\\[\\]\":,0-9eE+\\-. \\\\ntrufalsNIiy_/~]{0,64}"
}

/// Parses `text`; if it is refused, checks that the error names a field by a
/// JSON pointer and says what is wrong.
fn parse_checked(text: &str) -> Result<Option<Job>, TestCaseError> {
    match Job::parse(text) {
        Ok(job) => Ok(Some(job)),
        Err(e) => {
            prop_assert!(
                e.pointer.is_empty() || e.pointer.starts_with('/'),
                "pointer {:?} is not a JSON pointer (spec {})",
                e.pointer,
                text
            );
            prop_assert!(
                !e.message.trim().is_empty(),
                "empty message at {:?} (spec {})",
                e.pointer,
                text
            );
            Ok(None)
        }
    }
}

/// The canonical spec of an accepted job parses back to the same job, with the
/// same cache key.
fn check_canonical(job: &Job, text: &str) -> Result<(), TestCaseError> {
    let canonical = serde_json::to_string(job).expect("a job serialises");
    let again = Job::parse(&canonical);
    prop_assert!(
        again.is_ok(),
        "canonical spec {} of {} is refused: {:?}",
        canonical,
        text,
        again
    );
    let again = again.expect("checked above");
    prop_assert_eq!(&again, job, "canonical spec {} of {}", canonical, text);
    prop_assert_eq!(cache_key(&again), cache_key(job));
    Ok(())
}

// ---------------------------------------------------------------------------
// Valid specs
// ---------------------------------------------------------------------------

/// Log-uniform values in [lo, hi].
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.ln()..=hi.ln()).prop_map(move |x| x.exp().clamp(lo, hi))
}

/// A block object with its α, p and g.
type DrawnBlock = (Value, f64, f64, f64);

/// A block, a formulation (if given) and a solver object (if given).
type Setup = (DrawnBlock, Option<&'static str>, Option<Value>);

/// Any restitution η, or none (Housner's, close to 1 for slender blocks).
fn any_eta() -> BoxedStrategy<Option<f64>> {
    prop::option::of(prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0f64]).boxed()
}

/// A restitution η ≤ 0.95. Spectra scan long pulses, under which a nearly
/// elastic block can make millions of impacts before the engine gives up: a
/// cost, not a failure, that would dominate the run time.
fn dissipative_eta() -> BoxedStrategy<Option<f64>> {
    (0.0..=0.95f64).prop_map(Some).boxed()
}

/// A block given by (α, p) or by (b, h), under any alias, with η drawn from
/// `eta` and optional μ and g. Returns the block object and its (α, p, g).
fn block(eta: BoxedStrategy<Option<f64>>) -> impl Strategy<Value = DrawnBlock> {
    (
        log_uniform(1e-3, 1.5),
        log_uniform(0.1, 50.0),
        eta,
        prop::option::of(log_uniform(0.01, 2.0)),
        prop::option::of(log_uniform(0.1, 100.0)),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(alpha, p, eta, mu, g, geometry, alias)| {
            let mut m = Map::new();
            let gravity = g.unwrap_or(9.81);
            if geometry {
                let radius = 3.0 * gravity / (4.0 * p * p);
                let (b, h) = if alias {
                    ("half_width", "half_height")
                } else {
                    ("b", "h")
                };
                m.insert(b.into(), json!(radius * alpha.sin()));
                m.insert(h.into(), json!(radius * alpha.cos()));
            } else {
                let (a, f) = if alias {
                    ("slenderness", "frequency_parameter")
                } else {
                    ("alpha", "p")
                };
                m.insert(a.into(), json!(alpha));
                m.insert(f.into(), json!(p));
            }
            if let Some(eta) = eta {
                m.insert(if alias { "restitution" } else { "eta" }.into(), json!(eta));
            }
            if let Some(mu) = mu {
                m.insert(if alias { "friction" } else { "mu" }.into(), json!(mu));
            }
            if let Some(g) = g {
                m.insert(if alias { "gravity" } else { "g" }.into(), json!(g));
            }
            (Value::Object(m), alpha, p, gravity)
        })
}

/// A pulse family: `type` (any spelling) and, for cn, an optional `n` in 1..=4.
fn family() -> impl Strategy<Value = Map<String, Value>> {
    (
        prop_oneof![
            select(&["one_sine", "sine", "type_a", "A"][..]).prop_map(|t| (t, None)),
            select(&["one_cosine", "cosine", "type_b", "B"][..]).prop_map(|t| (t, None)),
            (
                select(&["cn", "type_cn", "type_c", "C"][..]),
                prop::option::of(1u32..=4)
            ),
        ],
        any::<bool>(),
    )
        .prop_map(|((t, n), shape_alias)| {
            let mut m = Map::new();
            m.insert(if shape_alias { "shape" } else { "type" }.into(), json!(t));
            if let Some(n) = n {
                m.insert("n".into(), json!(n));
            }
            m
        })
}

/// "linear", "nonlinear" or nothing (nonlinear).
fn formulation() -> impl Strategy<Value = Option<&'static str>> {
    prop::option::of(select(&["linear", "nonlinear"][..]))
}

/// A solver that suits `formulation`: nothing, exact (linear only) or a
/// Runge–Kutta pair with optional tolerances, rtol ≤ 1e-4 and atol ≤ 1e-7.
/// (Validation accepts up to 0.1 for both, but an absolute tolerance far above
/// the response of a slender block lets spurious impacts pile up for seconds.)
fn solver(linear: bool) -> impl Strategy<Value = Option<Value>> {
    let rk = (
        select(&["dopri5", "dop853", "rk45", "DOP853"][..]),
        prop::option::of(log_uniform(1e-12, 1e-4)),
        prop::option::of(log_uniform(1e-14, 1e-7)),
    )
        .prop_map(|(method, rtol, atol)| {
            let mut m = Map::new();
            m.insert("method".into(), json!(method));
            if let Some(rtol) = rtol {
                m.insert("rtol".into(), json!(rtol));
            }
            if let Some(atol) = atol {
                m.insert("atol".into(), json!(atol));
            }
            Some(Value::Object(m))
        });
    if linear {
        prop_oneof![
            Just(None),
            Just(Some(json!({"method": "exact"}))),
            Just(Some(json!({}))),
            rk,
        ]
        .boxed()
    } else {
        prop_oneof![Just(None), Just(Some(json!({}))), rk].boxed()
    }
}

/// Block (η drawn from `eta`), formulation and a solver that suits it.
fn block_and_solver(eta: BoxedStrategy<Option<f64>>) -> impl Strategy<Value = Setup> {
    (block(eta), formulation()).prop_flat_map(|(block, formulation)| {
        (
            Just(block),
            Just(formulation),
            solver(formulation == Some("linear")),
        )
    })
}

/// Inserts the formulation and solver, when given.
fn finish(mut m: Map<String, Value>, formulation: Option<&str>, solver: Option<Value>) -> Value {
    if let Some(f) = formulation {
        m.insert("formulation".into(), json!(f));
    }
    if let Some(s) = solver {
        m.insert("solver".into(), s);
    }
    Value::Object(m)
}

/// Optional outputs of a time history, each field optional.
fn outputs() -> impl Strategy<Value = Option<Value>> {
    prop::option::of(
        (
            prop::option::of(0usize..64),
            prop::option::of(any::<bool>()),
            prop::option::of(any::<bool>()),
            prop::option::of(0u64..2000),
            prop::option::of(log_uniform(1e-2, 1e3)),
        )
            .prop_map(|(series, reactions, impacts, max_free, duration)| {
                let mut m = Map::new();
                let mut put = |k: &str, v: Option<Value>| {
                    if let Some(v) = v {
                        m.insert(k.into(), v);
                    }
                };
                put("series", series.map(|x| json!(x)));
                put("reactions", reactions.map(|x| json!(x)));
                put("impacts", impacts.map(|x| json!(x)));
                put("max_free_impacts", max_free.map(|x| json!(x)));
                put("duration", duration.map(|x| json!(x)));
                Value::Object(m)
            }),
    )
}

/// A valid time-history spec: ω_p/p in [0.01, 1000] and |a_p|/(αg) in
/// [1e-3, 1e4] (either sign), each given in any of its units.
fn time_history_spec() -> impl Strategy<Value = Value> {
    (
        block_and_solver(any_eta()),
        family(),
        log_uniform(0.01, 1000.0),
        0usize..3,
        log_uniform(1e-3, 1e4),
        any::<bool>(),
        0usize..3,
        outputs(),
    )
        .prop_map(
            |(
                ((block, alpha, p, g), formulation, solver),
                mut pulse,
                ratio,
                frequency_unit,
                amplitude,
                negative,
                amplitude_unit,
                outputs,
            )| {
                match frequency_unit {
                    0 => pulse.insert("omega_ratio".into(), json!(ratio)),
                    1 => pulse.insert("omega_p".into(), json!(ratio * p)),
                    _ => pulse.insert(
                        "frequency_hz".into(),
                        json!(ratio * p / (2.0 * std::f64::consts::PI)),
                    ),
                };
                let a = if negative { -amplitude } else { amplitude };
                match amplitude_unit {
                    0 => pulse.insert("a_p_alpha_g".into(), json!(a)),
                    1 => pulse.insert("a_p_g".into(), json!(a * alpha)),
                    _ => pulse.insert("a_p".into(), json!(a * alpha * g)),
                };
                let mut m = Map::new();
                m.insert("kind".into(), json!("time_history"));
                m.insert("block".into(), block);
                m.insert("pulse".into(), Value::Object(pulse));
                if let Some(o) = outputs {
                    m.insert("outputs".into(), o);
                }
                finish(m, formulation, solver)
            },
        )
}

/// Values as a range `{from, to, steps}` (1 to 4 steps), a list of 1 to 4
/// values or one value, all in [lo, hi].
fn values(lo: f64, hi: f64) -> impl Strategy<Value = Value> {
    prop_oneof![
        (log_uniform(lo, hi), log_uniform(lo, hi), 1usize..=4).prop_map(|(a, b, steps)| {
            json!({"from": a.min(b), "to": a.max(b), "steps": steps})
        }),
        prop::collection::vec(log_uniform(lo, hi), 1..=4).prop_map(|v| json!(v)),
        log_uniform(lo, hi).prop_map(|x| json!(x)),
    ]
}

/// A valid spectrum spec, kept small: at most 4 frequencies in [0.2, 100] ω_p/p
/// and at most 40 scan points each.
fn spectrum_spec() -> impl Strategy<Value = Value> {
    (
        block_and_solver(dissipative_eta()),
        family(),
        values(0.2, 100.0),
        log_uniform(1.0, 4.0),
        prop::option::of(log_uniform(1e-6, 1e-2)),
        log_uniform(0.1, 1.0),
        prop::option::of(prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0f64]),
    )
        .prop_map(
            |(
                ((block, ..), formulation, solver),
                pulse,
                omega_ratio,
                a_max,
                tolerance,
                step,
                principal,
            )| {
                let mut m = Map::new();
                m.insert("kind".into(), json!("spectrum"));
                m.insert("block".into(), block);
                m.insert("pulse".into(), Value::Object(pulse));
                m.insert("omega_ratio".into(), omega_ratio);
                m.insert("a_max_alpha_g".into(), json!(a_max));
                if let Some(t) = tolerance {
                    m.insert("tolerance".into(), json!(t));
                }
                m.insert("scan_step_alpha_g".into(), json!(step));
                if let Some(w) = principal {
                    m.insert("principal_relative_width".into(), json!(w));
                }
                finish(m, formulation, solver)
            },
        )
}

/// A valid friction-spectrum spec with 1 to 4 amplitudes anywhere in the
/// accepted [1e-6, 1e6] αg.
fn friction_spec() -> impl Strategy<Value = Value> {
    (
        block_and_solver(any_eta()),
        family(),
        log_uniform(0.01, 1000.0),
        values(1e-6, 1e6),
    )
        .prop_map(
            |(((block, ..), formulation, solver), pulse, omega_ratio, amplitudes)| {
                let mut m = Map::new();
                m.insert("kind".into(), json!("friction_spectrum"));
                m.insert("block".into(), block);
                m.insert("pulse".into(), Value::Object(pulse));
                m.insert("omega_ratio".into(), json!(omega_ratio));
                m.insert("a_alpha_g".into(), amplitudes);
                finish(m, formulation, solver)
            },
        )
}

/// Hand-written valid specs of each kind.
fn examples() -> Vec<Value> {
    vec![
        json!({"kind": "time_history",
               "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
               "pulse": {"type": "one_cosine", "omega_ratio": 3.0, "a_p_alpha_g": 2.5},
               "formulation": "nonlinear"}),
        json!({"kind": "time_history",
               "block": {"b": 0.2, "h": 0.8, "mu": 0.5},
               "pulse": {"type": "cn", "n": 2, "frequency_hz": 1.5, "a_p_g": 0.4},
               "formulation": "linear",
               "solver": {"method": "exact"},
               "outputs": {"series": 10, "reactions": true, "impacts": true,
                           "max_free_impacts": 20, "duration": 5.0}}),
        json!({"kind": "spectrum",
               "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
               "pulse": {"type": "one_sine"},
               "formulation": "nonlinear",
               "omega_ratio": {"from": 0.25, "to": 10.0, "steps": 3}}),
        json!({"kind": "spectrum",
               "block": {"alpha": 0.2, "p": 1.5},
               "pulse": {"type": "cn", "n": 3},
               "formulation": "linear",
               "omega_ratio": [1.0, 4.0],
               "a_max_alpha_g": 5.0, "tolerance": 1e-3, "scan_step_alpha_g": 0.1,
               "principal_relative_width": 0.05,
               "solver": {"method": "dopri5", "rtol": 1e-9, "atol": 1e-11}}),
        json!({"kind": "friction_spectrum",
               "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
               "pulse": {"type": "one_sine"},
               "omega_ratio": 5.0,
               "a_alpha_g": {"from": 2, "to": 8, "steps": 4}}),
    ]
}

/// Any valid spec.
fn valid_spec() -> impl Strategy<Value = Value> {
    prop_oneof![
        2 => select(examples()),
        3 => time_history_spec(),
        2 => spectrum_spec(),
        2 => friction_spec(),
    ]
}

// ---------------------------------------------------------------------------
// Mutations of valid specs
// ---------------------------------------------------------------------------

/// One step of a path into a JSON value.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Key(String),
    Item(usize),
}

/// Every path in `v`, the root (empty path) first.
fn paths(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match v {
        Value::Object(m) => {
            for (k, child) in m {
                here.push(Step::Key(k.clone()));
                paths(child, here, out);
                here.pop();
            }
        }
        Value::Array(a) => {
            for (i, child) in a.iter().enumerate() {
                here.push(Step::Item(i));
                paths(child, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

fn at_mut<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, step| match step {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Item(i) => v.get_mut(*i),
    })
}

/// The element of `items` that `i` points at, if there is any.
fn pick<T: Clone>(i: &Index, items: &[T]) -> Option<T> {
    (!items.is_empty()).then(|| i.get(items).clone())
}

/// A change to a spec.
#[derive(Clone, Debug)]
enum Mutation {
    /// The value at a path becomes the given JSON text.
    Replace(Index, String),
    /// The member or item at a path goes.
    Delete(Index),
    /// An object gains a member with the given key and JSON text.
    Add(Index, String, String),
    /// An object gains a second member under one of its keys, with the given
    /// JSON text.
    Duplicate(Index, Index, String),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let key = prop_oneof![
        4 => select(FIELD_NAMES).prop_map(str::to_string),
        1 => any::<String>(),
    ];
    prop_oneof![
        4 => (any::<Index>(), json_text(3)).prop_map(|(i, t)| Mutation::Replace(i, t)),
        2 => any::<Index>().prop_map(Mutation::Delete),
        2 => (any::<Index>(), key, json_text(2)).prop_map(|(i, k, t)| Mutation::Add(i, k, t)),
        2 => (any::<Index>(), any::<Index>(), json_text(2))
            .prop_map(|(i, k, t)| Mutation::Duplicate(i, k, t)),
    ]
}

/// Applies `mutations` to `spec` and renders the result as JSON text. Raw JSON
/// text (which may hold non-JSON tokens) and duplicate keys go in through
/// marker strings that are substituted after serialisation.
fn mutate(spec: &Value, mutations: &[Mutation]) -> String {
    let mut v = spec.clone();
    let mut holes: Vec<(String, String)> = Vec::new();
    for (n, m) in mutations.iter().enumerate() {
        let mut all = Vec::new();
        paths(&v, &mut Vec::new(), &mut all);
        let objects: Vec<Vec<Step>> = all
            .iter()
            .filter(|p| at_mut(&mut v, p).is_some_and(|x| x.is_object()))
            .cloned()
            .collect();
        let hole = format!("@@hole{n}@@");
        match m {
            Mutation::Replace(i, text) => {
                let Some(path) = pick(i, &all) else { continue };
                if let Some(x) = at_mut(&mut v, &path) {
                    *x = Value::String(hole.clone());
                    holes.push((quoted(&hole), text.clone()));
                }
            }
            Mutation::Delete(i) => {
                let Some(path) = pick(i, &all) else { continue };
                if let Some((last, parent)) = path.split_last()
                    && let Some(parent) = at_mut(&mut v, parent)
                {
                    match (last, parent) {
                        (Step::Key(k), Value::Object(o)) => {
                            o.shift_remove(k.as_str());
                        }
                        (Step::Item(i), Value::Array(a)) => {
                            a.remove(*i);
                        }
                        _ => {}
                    }
                }
            }
            Mutation::Add(i, key, text) => {
                let Some(path) = pick(i, &objects) else {
                    continue;
                };
                if let Some(Value::Object(o)) = at_mut(&mut v, &path) {
                    o.insert(key.clone(), Value::String(hole.clone()));
                    holes.push((quoted(&hole), text.clone()));
                }
            }
            Mutation::Duplicate(i, k, text) => {
                let Some(path) = pick(i, &objects) else {
                    continue;
                };
                if let Some(Value::Object(o)) = at_mut(&mut v, &path)
                    && !o.is_empty()
                {
                    let keys: Vec<String> = o.keys().cloned().collect();
                    let Some(key) = pick(k, &keys) else { continue };
                    let marker = format!("@@key{n}@@");
                    o.insert(marker.clone(), Value::String(hole.clone()));
                    holes.push((quoted(&marker), quoted(&key)));
                    holes.push((quoted(&hole), text.clone()));
                }
            }
        }
    }
    let mut text = v.to_string();
    for (marker, raw) in &holes {
        text = text.replace(marker.as_str(), raw);
    }
    text
}

// ---------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------

/// Result fields that are `null` when they do not apply.
const NULLABLE: &[&str] = &[
    "rocking_start",
    "mode",
    "overturn_time",
    "rest_time",
    "peak_friction_demand",
    "peak_friction_demand_time",
    "initiation_friction_demand",
    "min_overturn_alpha_g",
    "min_overturn_in",
    "min_certain_overturn_alpha_g",
    "min_certain_overturn_scale",
    "min_certain_overturn_pga_g",
    "min_overturn_g",
    "min_overturn_m_s2",
    "min_overturn_mode",
    "overturns_above_alpha_g",
    "closed_form_mode2_alpha_g",
    "lift_off_time",
    "peak_over_tan_alpha",
    "friction_demand_followed_until",
    // Series entries: f_x/f_z has no value from lift-off on.
    "fx_over_fz",
    "rtol",
    "atol",
];

/// Collects the pointers of numbers that are not finite in `v`, and of nulls
/// outside [`NULLABLE`] fields: a non-finite `f64` serialises to `null`.
fn non_finite(v: &Value, pointer: &str, key: Option<&str>, out: &mut Vec<String>) {
    match v {
        Value::Number(n) => {
            if !n.as_f64().is_some_and(f64::is_finite) {
                out.push(format!("{pointer} = {n}"));
            }
        }
        Value::Null => {
            if !key.is_some_and(|k| NULLABLE.contains(&k)) {
                out.push(format!("{pointer} = null"));
            }
        }
        Value::Array(a) => {
            // Entries of a nullable series are nullable too.
            let inner = key.filter(|k| *k == "fx_over_fz");
            for (i, x) in a.iter().enumerate() {
                non_finite(x, &format!("{pointer}/{i}"), inner, out);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                non_finite(x, &format!("{pointer}/{k}"), Some(k), out);
            }
        }
        Value::Bool(_) | Value::String(_) => {}
    }
}

/// The typed result of `job`, serialised by RFC 8785, which refuses
/// non-finite numbers (unlike `serde_json`, which writes them as `null`);
/// `None` when the engine refuses the job.
fn strict_result(job: &Job) -> Option<Result<String, serde_json::Error>> {
    let typed = job.run_typed(&Control::new()).ok().flatten()?;
    Some(serde_jcs::to_string(&typed))
}

/// Runs `job`: it ends in a result with finite numbers only, or in an engine
/// error (never in cancellation, which nobody asked for).
fn check_run(job: &Job, text: &str) -> Result<(), TestCaseError> {
    match job.run(&Control::new()) {
        Ok(result) => {
            let mut bad = Vec::new();
            non_finite(&result, "", None, &mut bad);
            prop_assert!(bad.is_empty(), "non-finite {:?} for spec {}", bad, text);
            let strict = strict_result(job);
            prop_assert!(
                matches!(strict, Some(Ok(_))),
                "non-finite number in the {} result of spec {}: {:?}",
                job.kind(),
                text,
                strict.map(|r| r.map_err(|e| e.to_string()))
            );
        }
        Err(e) => prop_assert!(
            !matches!(e, JobError::Canceled),
            "canceled without a cancel (spec {})",
            text
        ),
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------

/// Cases of each parser property (about a millisecond each, or less).
const PARSE_CASES: u32 = 30_000;
/// Cases of the time-history property (each run twice).
const TIME_HISTORY_CASES: u32 = 6_000;
/// Cases of the spectrum property: the costly one, up to seconds a case.
const SPECTRUM_CASES: u32 = 250;
/// Cases of the friction-spectrum property.
const FRICTION_CASES: u32 = 1_000;

fn cases(n: u32) -> ProptestConfig {
    ProptestConfig {
        cases: n,
        ..ProptestConfig::default()
    }
}

/// Parses a spec that is valid by construction, checks its canonical form and
/// runs it.
fn check_valid(spec: &Value) -> Result<(), TestCaseError> {
    let text = spec.to_string();
    let job = Job::parse(&text);
    prop_assert!(job.is_ok(), "valid spec {} refused: {:?}", text, job);
    let job = job.expect("checked above");
    check_canonical(&job, &text)?;
    check_run(&job, &text)
}

proptest! {
    #![proptest_config(cases(PARSE_CASES))]

    #[test]
    fn parse_survives_any_string(text in any::<String>()) {
        parse_checked(&text)?;
    }

    #[test]
    fn parse_survives_any_bytes(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        parse_checked(&String::from_utf8_lossy(&bytes))?;
    }

    #[test]
    fn parse_survives_json_characters(text in json_alphabet_text()) {
        parse_checked(&text)?;
    }

    #[test]
    fn parse_survives_any_json(text in json_text(5)) {
        if let Some(job) = parse_checked(&text)? {
            check_canonical(&job, &text)?;
        }
    }

    #[test]
    fn parse_survives_any_json_with_a_kind(text in spec_shaped_text()) {
        if let Some(job) = parse_checked(&text)? {
            check_canonical(&job, &text)?;
        }
    }

    #[test]
    fn parse_survives_mutated_specs(
        spec in valid_spec(),
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let text = mutate(&spec, &mutations);
        if let Some(job) = parse_checked(&text)? {
            check_canonical(&job, &text)?;
        }
    }
}

proptest! {
    #![proptest_config(cases(TIME_HISTORY_CASES))]

    #[test]
    fn time_histories_run_to_finite_results(spec in time_history_spec()) {
        check_valid(&spec)?;
    }
}

proptest! {
    #![proptest_config(cases(SPECTRUM_CASES))]

    #[test]
    fn spectra_run_to_finite_results(spec in spectrum_spec()) {
        check_valid(&spec)?;
    }
}

proptest! {
    #![proptest_config(cases(FRICTION_CASES))]

    #[test]
    fn friction_spectra_run_to_finite_results(spec in friction_spec()) {
        check_valid(&spec)?;
    }
}

#[test]
fn the_examples_parse_and_run() {
    for spec in examples() {
        let text = spec.to_string();
        let job = Job::parse(&text).expect("the examples are valid");
        let result = job.run(&Control::new()).expect("the examples run");
        let mut bad = Vec::new();
        non_finite(&result, "", None, &mut bad);
        assert!(bad.is_empty(), "non-finite {bad:?} for spec {text}");
    }
}

/// A spectrum that simulates a_p one ulp above g tan α (1.0240311545673373 αg
/// for this block, at ω_p/p ≈ 0.397): the nonlinear history there grazes the
/// rocking threshold at the pulse peak, which once looped to the impact limit
/// and failed the whole spectrum.
#[test]
fn a_spectrum_through_a_grazing_threshold_runs() {
    let text = r#"{"kind":"spectrum",
        "block":{"half_width":0.00980798167978087,"half_height":0.03618211389652038,
                 "restitution":0.23062033893371037},
        "pulse":{"shape":"sine"},
        "omega_ratio":{"from":0.39689304351627386,"to":3.8773567483347757,"steps":3},
        "a_max_alpha_g":3.0552812405393404,"tolerance":3.016803511598678e-6,
        "scan_step_alpha_g":0.2148052678189171,"principal_relative_width":1.0,
        "solver":{"method":"DOP853","rtol":4.560122987011337e-9}}"#;
    let job = Job::parse(text).expect("valid");
    let result = job.run(&Control::new()).expect("the spectrum runs");
    let mut bad = Vec::new();
    non_finite(&result, "", None, &mut bad);
    assert!(bad.is_empty(), "non-finite {bad:?}");
    assert!(matches!(strict_result(&job), Some(Ok(_))));
}
