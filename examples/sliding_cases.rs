//! Runs pure-sliding cases for `bench/sliding_scipy.py`: a JSON array of
//! cases on stdin (`shape`, `a_g`, `omega`, `mu`, `mu_k`, and optionally
//! `ratio` or a `vertical` pulse {`shape`, `a_g`, `omega`, `delay`}), each
//! one's slides, residual, peak and lift-off on stdout as JSON.

use serde_json::{Value, json};
use topple::dynamics::PulsePair;
use topple::dynamics::sliding::{Friction, Sliding, slide};

#[path = "cases/pulse.rs"]
mod pulse_cases;
use pulse_cases::{G, pulse};

fn run(c: &Value) -> Result<Sliding, String> {
    let num = |k: &str| c[k].as_f64().ok_or(format!("{k} missing"));
    let f = Friction::new(num("mu")?, c["mu_k"].as_f64()).map_err(|e| e.to_string())?;
    let h = pulse(c)?;
    Ok(if let Some(r) = c["ratio"].as_f64() {
        slide(&PulsePair::proportional(h, r).ok_or("ratio 0")?, G, f)
    } else if c["vertical"].is_object() {
        let v = &c["vertical"];
        slide(
            &PulsePair::new(h, pulse(v)?, v["delay"].as_f64().unwrap_or(0.0)),
            G,
            f,
        )
    } else {
        slide(&h, G, f)
    })
}

fn main() -> Result<(), String> {
    let cases: Vec<Value> = serde_json::from_reader(std::io::stdin()).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for c in &cases {
        let s = run(c)?;
        out.push(json!({
            "slides": s.slides.iter().map(|w| json!({"from": w.from, "to": w.to,
                "direction": w.direction, "x_to": w.x_to})).collect::<Vec<_>>(),
            "residual": s.residual, "peak": s.peak, "lift_off": s.lift_off,
        }));
    }
    println!("{}", Value::Array(out));
    Ok(())
}
