//! The cache key of a job: two specs that mean the same thing share one key.

pub use crate::jobs::engine::{BUILD_COMMIT, ENGINE_VERSION, engine_doc, engine_info};

/// Rounds every number to 12 significant digits, so that the same quantity
/// given in other units (a_p_g vs a_p) normalises to one value.
fn canonical_numbers(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Number(n) => {
            if let Some(x) = n.as_f64()
                && !n.is_i64()
                && !n.is_u64()
                && x.is_finite()
            {
                let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
                if let Some(r) = serde_json::Number::from_f64(rounded) {
                    *n = r;
                }
            }
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(canonical_numbers),
        serde_json::Value::Object(o) => o.values_mut().for_each(canonical_numbers),
        _ => {}
    }
}

/// The canonical form of a validated job: its normalised spec (SI units,
/// every default filled in) with numbers rounded to 12 significant digits,
/// serialised by RFC 8785 (JSON Canonicalization Scheme).
pub fn canonical_spec(job: &impl serde::Serialize) -> String {
    let mut value = serde_json::to_value(job).unwrap_or(serde_json::Value::Null);
    canonical_numbers(&mut value);
    serde_jcs::to_string(&value).unwrap_or_default()
}

/// The cache key: blake3 of the engine version and the canonical spec.
pub fn cache_key(job: &impl serde::Serialize) -> String {
    let mut h = blake3::Hasher::new();
    h.update(ENGINE_VERSION.as_bytes());
    h.update(b"\n");
    h.update(canonical_spec(job).as_bytes());
    h.finalize().to_hex().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::Job;

    fn key(text: &str) -> String {
        cache_key(&Job::parse(text).expect("valid"))
    }

    #[test]
    fn specs_that_mean_the_same_share_a_key() {
        let a = key(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_p":10.7,"a_p_g":0.75}}"#,
        );
        // Field order, defaults written out, the amplitude in m/s².
        let b = key(
            r#"{"pulse":{"a_p":7.3575,"omega_p":10.7,"type":"sine"},"formulation":"nonlinear","kind":"time_history","block":{"p":2.14,"eta":0.9081869214177796,"alpha":0.25},"solver":{"method":"dop853","rtol":1e-10,"atol":1e-12},"outputs":{"reactions":true}}"#,
        );
        assert_eq!(a, b);
        // In αg and with the frequency as a ratio.
        let c = key(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":5.0,"a_p_alpha_g":3.0}}"#,
        );
        assert_eq!(a, c);
    }

    #[test]
    fn different_work_has_different_keys() {
        let a = key(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_p":10.7,"a_p_g":0.75}}"#,
        );
        let b = key(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_p":10.7,"a_p_g":0.76}}"#,
        );
        let c = key(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_p":10.7,"a_p_g":0.75},"outputs":{"series":10}}"#,
        );
        assert_ne!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn a_normalised_spec_validates_to_itself() {
        for text in [
            r#"{"kind":"time_history","block":{"b":0.5,"h":2.0},"pulse":{"type":"cn","n":2,"frequency_hz":1.7,"a_p_g":0.75},"outputs":{"series":5}}"#,
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_cosine"},"omega_ratio":{"from":1,"to":3,"steps":3}}"#,
            r#"{"kind":"friction_spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"omega_ratio":5,"a_alpha_g":[2,3]}"#,
        ] {
            let job = Job::parse(text).expect("valid");
            let again =
                Job::from_value(&serde_json::to_value(&job).expect("serialises")).expect("valid");
            assert_eq!(job, again);
        }
    }
}
