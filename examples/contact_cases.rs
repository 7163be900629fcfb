//! Runs cases of a block on a Coulomb floor for `bench/contact_scipy.py`: a
//! JSON array of cases on stdin — `alpha`, `p` (rad/s), `mu`, optional
//! `mu_k`, and the ground motion: either the horizontal pulse `shape`, `a_g`
//! (amplitude in g), `omega` (rad/s), optionally with `ratio` (ü_v = r ü_g)
//! or a `vertical` pulse {`shape`, `a_g`, `omega`, `delay`}; or a horizontal
//! record `record` {`dt` (s), `acc` (samples, m/s²)} (linear between
//! samples, [`Record`]), optionally with `ratio` or a `vertical_record`
//! {`dt` (the same), `acc`} of its own (the shorter padded with zeros,
//! [`RecordPair`]) — each one's history on stdout as JSON:
//! `initial_mode`, `modes` [{mode, from, to, direction, slip_from,
//! slip_to}], `overturned`, `overturn_time`, `overturn_side`, `impacts`
//! [{t, theta_dot_before, theta_dot_after, sticking}], `impact_count`,
//! `first_flight`, `flights`, `time_in_flight`, `rest_time`, `peak_slide`,
//! `residual_slide`, `time_sliding`, `peak_theta_over_alpha`.

use serde_json::{Value, json};
use topple::dynamics::coulomb::{ContactResponse, simulate_contact};
use topple::dynamics::integrator::Method;
use topple::dynamics::sliding::{Friction, Kinematics};
use topple::dynamics::{Block, PulsePair, Record, RecordPair};

#[path = "cases/pulse.rs"]
mod pulse_cases;
use pulse_cases::{G, pulse};

fn simulate<G: Kinematics>(
    block: &Block,
    forcing: &G,
    f: Friction,
) -> Result<ContactResponse, String> {
    simulate_contact(block, forcing, f, Method::Dop853, 1e-12, 1e-14).map_err(|e| e.to_string())
}

/// The record `{dt, acc}` a case field describes.
fn record(r: &Value) -> Result<Record, String> {
    let dt = r["dt"].as_f64().ok_or("record dt missing")?;
    let acc = r["acc"]
        .as_array()
        .ok_or("record acc missing")?
        .iter()
        .map(|a| a.as_f64().ok_or("record sample not a number"))
        .collect::<Result<Vec<f64>, _>>()?;
    Record::new(acc.into(), dt).map_err(|e| e.to_string())
}

fn run(c: &Value) -> Result<ContactResponse, String> {
    let num = |k: &str| c[k].as_f64().ok_or(format!("{k} missing"));
    let block =
        Block::new(num("alpha")?, num("p")?, None, None, Some(G)).map_err(|e| e.to_string())?;
    let f = Friction::new(num("mu")?, c["mu_k"].as_f64()).map_err(|e| e.to_string())?;
    if c["record"].is_object() {
        let h = record(&c["record"])?;
        return if let Some(r) = c["ratio"].as_f64() {
            simulate(&block, &RecordPair::proportional(h, r).ok_or("ratio 0")?, f)
        } else if c["vertical_record"].is_object() {
            let v = record(&c["vertical_record"])?;
            simulate(
                &block,
                &RecordPair::new(h, v).map_err(|e| e.to_string())?,
                f,
            )
        } else {
            simulate(&block, &h, f)
        };
    }
    let h = pulse(c)?;
    if let Some(r) = c["ratio"].as_f64() {
        simulate(&block, &PulsePair::proportional(h, r).ok_or("ratio 0")?, f)
    } else if c["vertical"].is_object() {
        let v = &c["vertical"];
        simulate(
            &block,
            &PulsePair::new(h, pulse(v)?, v["delay"].as_f64().unwrap_or(0.0)),
            f,
        )
    } else {
        simulate(&block, &h, f)
    }
}

fn main() -> Result<(), String> {
    let cases: Vec<Value> = serde_json::from_reader(std::io::stdin()).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for c in &cases {
        let r = run(c)?;
        out.push(json!({
            "initial_mode": r.initial_mode.map(|m| m.name()),
            "modes": r.modes.iter().map(|m| json!({
                "mode": m.mode.name(), "from": m.from, "to": m.to, "direction": m.direction,
                "slip_from": m.slip.0, "slip_to": m.slip.1,
            })).collect::<Vec<_>>(),
            "overturned": r.overturned,
            "overturn_time": r.overturn_time,
            "overturn_side": r.overturn_side,
            "impacts": r.impacts.iter().map(|i| json!({
                "t": i.t, "theta_dot_before": i.theta_dot.0, "theta_dot_after": i.theta_dot.1,
                "sticking": i.sticking,
            })).collect::<Vec<_>>(),
            "impact_count": r.impact_count,
            "first_flight": r.first_flight,
            "flights": r.flights,
            "time_in_flight": r.time_in_flight,
            "rest_time": r.rest_time,
            "peak_slide": r.peak_slide,
            "residual_slide": r.residual_slide,
            "time_sliding": r.time_sliding,
            "peak_theta_over_alpha": r.peak_theta_over_alpha,
        }));
    }
    println!("{}", Value::Array(out));
    Ok(())
}
