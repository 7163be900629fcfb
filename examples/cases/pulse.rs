//! The pulses of the cross-check cases (`examples/*_cases.rs`): `shape`,
//! `a_g` (amplitude in g), `omega` (rad/s).

use serde_json::Value;
use topple::dynamics::{Pulse, PulseShape};

/// Standard gravity of the cases, m/s².
pub const G: f64 = 9.81;

/// The pulse family named `name`.
pub fn shape(name: &str) -> Result<PulseShape, String> {
    Ok(match name {
        "one_sine" => PulseShape::OneSine,
        "one_cosine" => PulseShape::OneCosine,
        "rectangular" => PulseShape::Rectangular,
        "ricker" => PulseShape::Ricker { symmetric: true },
        "c3" => PulseShape::Cn(3),
        other => return Err(format!("unknown shape {other}")),
    })
}

/// The pulse a case describes.
pub fn pulse(c: &Value) -> Result<Pulse, String> {
    let num = |k: &str| c[k].as_f64().ok_or(format!("{k} missing"));
    Pulse::new(
        shape(c["shape"].as_str().ok_or("shape missing")?)?,
        num("a_g")? * G,
        num("omega")?,
    )
    .map_err(|e| e.to_string())
}
