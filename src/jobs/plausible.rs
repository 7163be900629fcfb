//! Warnings about inputs that are valid but unlikely to be meant: a block
//! whose size R (the half-diagonal, p = √(3g/(4R)) for a rectangular block)
//! lies outside 1 cm – 100 m — typically b and h in millimetres, or p in Hz
//! for rad/s (R then 4π² too large). Full width and height entered as b and
//! h (p off by √2) is not caught. And a record that is strong enough to be a
//! unit read wrongly, whose baseline drifts, that is sampled too coarsely
//! for the block, or that never rocks it. The result is computed as asked,
//! with the warning next to it.

use crate::numbers::fmt_num;

use super::spec::{BlockNorm, GroundMotionNorm};
use super::warning::WarningDoc;

/// The smallest plausible size R, m.
pub const R_MIN_M: f64 = 0.01;
/// The largest plausible size R, m.
pub const R_MAX_M: f64 = 100.0;

/// The size R of a rectangular block with frequency parameter p:
/// p² = 3g/(4R) (Makris & Zhang 2001, below eq. 1).
pub fn size_m(block: &BlockNorm) -> f64 {
    3.0 * block.g / (4.0 * block.p * block.p)
}

/// The warning for one block, at `pointer` in the spec.
pub fn size_warning(block: &BlockNorm, pointer: &str) -> Option<WarningDoc> {
    let r = size_m(block);
    if (R_MIN_M..=R_MAX_M).contains(&r) {
        return None;
    }
    let hint = if r > R_MAX_M {
        "b and h are half the width and half the height, in metres (millimetres?); p is in rad/s (Hz?)"
    } else {
        "b and h are half the width and half the height, in metres"
    };
    Some(WarningDoc {
        kind: "implausible_size".into(),
        t: None,
        message: format!(
            "{pointer}: the block's size R = sqrt(b^2 + h^2) = 3g/(4p^2) = {} m (p = {} rad/s) is outside {R_MIN_M} m to {R_MAX_M} m: {hint}",
            fmt_num(r, 6),
            fmt_num(block.p, 6)
        ),
    })
}

/// The warnings about blocks `(block, pointer)`.
pub fn size_warnings<'a>(
    blocks: impl IntoIterator<Item = (&'a BlockNorm, String)>,
) -> Vec<WarningDoc> {
    blocks
        .into_iter()
        .filter_map(|(b, at)| size_warning(b, &at))
        .collect()
}

/// The residual slide past which a seen slide (`slid_m`) is warned about,
/// m: furniture, equipment and tombstones thrown by strong shaking slide
/// centimetres to some tens of centimetres; a band reaching past a metre is
/// more often centimetres entered as metres.
pub const LARGE_SLIDE_M: f64 = 1.0;

/// The warning for a seen slide `[lo, hi]`, m, at `pointer` in the spec
/// (`implausible_slide`): computed as given, with a hint.
pub fn slide_warning(band: [f64; 2], pointer: &str) -> Option<WarningDoc> {
    let [lo, hi] = band;
    (hi > LARGE_SLIDE_M).then(|| WarningDoc {
        kind: "implausible_slide".into(),
        t: None,
        message: format!(
            "{pointer}: a residual slide of {}–{} m reaches past {LARGE_SLIDE_M} m, which a block's base rarely slides: slid_m is in metres (centimetres? {}–{} cm is [{}, {}])",
            fmt_num(lo, 6),
            fmt_num(hi, 6),
            fmt_num(lo, 6),
            fmt_num(hi, 6),
            fmt_num(lo / 100.0, 6),
            fmt_num(hi / 100.0, 6)
        ),
    })
}

/// The PGA past which a record carries a `large_pga` warning, g.
const LARGE_PGA_G: f64 = crate::records::PGA_LARGE_G;

/// Samples per period the record should have at least, for the shortest
/// ground period that still matters to a block of frequency parameter p:
/// 2π/(10p) (beyond ω = 10p the overturning acceleration grows as ω², and
/// the spectra stop there).
pub fn coarse_dt_warning(dt: f64, p: f64, at: &str) -> Option<WarningDoc> {
    let shortest = 2.0 * std::f64::consts::PI / (10.0 * p);
    (dt > shortest / 2.0).then(|| WarningDoc {
        kind: "coarse_dt".into(),
        t: None,
        message: format!(
            "{at}: dt = {dt} s gives fewer than 2 samples per {shortest:.4} s, the shortest ground period that matters to a block with p = {p:.4} rad/s (2π/(10p)): the record cannot carry the motion such a block responds to; use a record sampled at dt <= {:.4} s",
            shortest / 2.0
        ),
    })
}

/// Warnings about a record as it reaches a job (whichever way it came: its
/// samples in the spec, a stored record, a file): a large PGA, a baseline
/// that drifts.
pub fn record_warnings(motion: &GroundMotionNorm, at: &str) -> Vec<WarningDoc> {
    let mut found = Vec::new();
    let pga_g = motion.acc.iter().fold(0.0f64, |m, a| m.max(a.abs())) / crate::records::G_M_S2;
    if pga_g > LARGE_PGA_G {
        found.push(WarningDoc {
            kind: "large_pga".into(),
            t: None,
            message: format!(
                "{at}: the record's PGA is {pga_g:.3} g: a strong record, or a unit read wrongly (cm/s² as m/s², m/s² as g)?"
            ),
        });
    }
    if let Some(w) = crate::records::baseline_drift(motion.dt, &motion.acc) {
        found.push(WarningDoc {
            kind: w.kind.into(),
            t: None,
            message: format!("{at}: {}", w.message),
        });
    }
    found
}

/// The warning that a record at `/ground_motion` never rocks a block of
/// slenderness α under gravity g: rocking starts once |ü_g| exceeds g·tan α
/// (g·α linear).
///
/// `slide_m`: on a Coulomb floor, the block's (peak, residual) slip on it,
/// m (`None` in pure rocking, where the block cannot slide). A block that
/// did not rock may still have slid: the warning then says so, with the
/// peak slide, and says it stays at rest only where it did not move.
pub fn never_rocks_warning(
    motion: &GroundMotionNorm,
    block: &BlockNorm,
    linear: bool,
    slide_m: Option<(f64, f64)>,
) -> Option<WarningDoc> {
    let threshold = if linear {
        block.g * block.alpha
    } else {
        block.g * block.alpha.tan()
    };
    let pga = motion.acc.iter().fold(0.0f64, |x, a| x.max(a.abs()));
    let what = match slide_m {
        Some((peak, residual)) if peak.abs() > 0.0 || residual.abs() > 0.0 => format!(
            "the block did not rock but slid on the floor (peak slide {} m, residual {} m)",
            fmt_num(peak.abs().max(residual.abs()), 4),
            fmt_num(residual, 4)
        ),
        _ => "the block stays at rest".to_string(),
    };
    (pga <= threshold).then(|| WarningDoc {
        kind: "never_rocks".into(),
        t: None,
        message: format!(
            "/ground_motion: the record's PGA ({:.4} g) never exceeds the block's rocking threshold ({:.4} g, {}): {what}; scale the record (a record spectrum or a forensic query) to see where it would rock",
            pga / block.g,
            threshold / block.g,
            if linear { "g·α" } else { "g·tan α" }
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinds::Job;
    use crate::spectrum::Control;
    use serde_json::Value;

    fn run(spec: &str) -> Value {
        Job::parse(spec)
            .expect("valid")
            .run(&Control::default())
            .expect("runs")
    }

    fn kinds(doc: &Value) -> Vec<String> {
        doc.get("warnings")
            .and_then(Value::as_array)
            .map(|a| {
                a.iter()
                    .filter_map(|w| w.get("kind").and_then(Value::as_str).map(String::from))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// A block of 600 by 1200 entered in millimetres: computed, and warned
    /// about (R = 1341.6 m, p = 0.074 rad/s).
    #[test]
    fn millimetres_for_metres_are_warned_about() {
        let doc = run(
            r#"{"kind":"time_history","block":{"b":600,"h":1200},"pulse":{"type":"one_sine","a_p_g":0.5,"omega_p":3}}"#,
        );
        assert_eq!(kinds(&doc), ["implausible_size"]);
        let msg = doc["warnings"][0]["message"].as_str().unwrap_or("");
        assert!(msg.starts_with("/block: "), "{msg}");
        assert!(msg.contains("1341.6"), "{msg}");
    }

    /// A slide of 5–30 cm entered as metres is warned about, named at its
    /// observation, with the band in metres it probably meant; the same
    /// band in metres carries no warning.
    #[test]
    fn a_seen_slide_in_centimetres_is_warned_about() {
        let query = |slid: &str| {
            run(&format!(
                r#"{{"kind":"forensic","pulse":{{"type":"one_sine"}},"frequency_hz":[1.0],"a_p_g":{{"from":0.05,"to":0.3}},"contact":{{"model":"coulomb","mu":0.3}},"observations":[{{"name":"a","overturned":true,"block":{{"alpha":0.25,"p":2.14}}}},{{"name":"b","overturned":false,"slid_m":{slid},"block":{{"alpha":0.25,"p":2.14}}}}]}}"#
            ))
        };
        let cm = query("[5, 30]");
        assert_eq!(kinds(&cm), ["implausible_slide"]);
        let msg = cm["warnings"][0]["message"].as_str().unwrap_or("");
        assert!(msg.starts_with("/observations/1/slid_m: "), "{msg}");
        assert!(msg.contains("[0.05, 0.3]"), "{msg}");
        assert!(kinds(&query("[0.05, 0.3]")).is_empty());
    }

    /// The paper's locomotive (p = 2.14 rad/s: R = 1.61 m) carries none; a
    /// block under 1 cm (p = 300 rad/s: R = 0.08 mm) does.
    #[test]
    fn plausible_blocks_carry_no_warning_and_tiny_ones_do() {
        let ok = run(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","a_p_g":0.5,"omega_p":3}}"#,
        );
        assert!(
            !kinds(&ok).iter().any(|k| k == "implausible_size"),
            "{:?}",
            ok.get("warnings")
        );
        let tiny = run(
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":300},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":{"from":1,"to":3,"steps":3}}"#,
        );
        assert_eq!(kinds(&tiny), ["implausible_size"]);
    }

    /// Each observation of a forensic query is looked at, named by pointer.
    #[test]
    fn forensic_observations_are_each_looked_at() {
        let job = Job::parse(
            r#"{"kind":"forensic","pulse":{"type":"one_sine"},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false},{"name":"cabinet in mm","b":300,"h":900,"overturned":true}],"frequency_hz":{"from":0.5,"to":2,"steps":3},"a_p_g":{"from":0.05,"to":3.0}}"#,
        )
        .expect("valid");
        let w = job.input_warnings();
        assert_eq!(w.len(), 1);
        assert!(
            w[0].message.starts_with("/observations/1/block"),
            "{}",
            w[0].message
        );
    }

    /// A squat block (b = h = 0.5 m: rocking threshold 1 g) under the ridge
    /// record of `specs/records` at twice its size (PGA 0.686 g) never
    /// rocks. On a Coulomb floor of μ = 0.1 it slides (0.31 m at most, 0.13
    /// m left): the warning says so, with the peak slide, where it said the
    /// block stays at rest. On μ = 0.9, and in pure rocking, it does stay
    /// at rest.
    #[test]
    fn a_record_that_never_rocks_a_block_says_whether_it_slid() {
        let acc: Vec<f64> = include_str!("../../specs/records/ridge_station_090.at2")
            .lines()
            .skip(4)
            .flat_map(str::split_whitespace)
            .map(|a| 2.0 * a.parse::<f64>().expect("a sample"))
            .collect();
        let history = |contact: Option<Value>| {
            let mut spec = serde_json::json!({"kind": "time_history",
                "block": {"b": 0.5, "h": 0.5},
                "ground_motion": {"dt": 0.01, "unit": "g", "acc": acc}});
            if let Some(c) = contact {
                spec["contact"] = c;
            }
            run(&spec.to_string())
        };
        let never_rocks = |doc: &Value| -> Vec<String> {
            doc["warnings"]
                .as_array()
                .into_iter()
                .flatten()
                .filter(|w| w["kind"] == "never_rocks")
                .filter_map(|w| w["message"].as_str().map(String::from))
                .collect()
        };
        let slid = history(Some(serde_json::json!({"model": "coulomb", "mu": 0.1})));
        assert_eq!(slid["rocked"], false);
        let peak = slid["peak_slide_m"].as_f64().expect("a slide");
        let residual = slid["residual_slide_m"].as_f64().expect("a slide");
        assert!((peak - 0.310_03).abs() < 1e-4, "{peak}");
        assert!((residual - 0.131_35).abs() < 1e-4, "{residual}");
        let said = never_rocks(&slid);
        assert_eq!(said.len(), 1, "{said:?}");
        assert!(
            said[0].contains(&format!(
                "the block did not rock but slid on the floor (peak slide {} m, residual {} m)",
                fmt_num(peak, 4),
                fmt_num(residual, 4)
            )),
            "{}",
            said[0]
        );
        assert!(said[0].contains("(peak slide 0.31 m"), "{}", said[0]);
        assert!(!said[0].contains("at rest"), "{}", said[0]);
        let held = history(Some(serde_json::json!({"model": "coulomb", "mu": 0.9})));
        assert_eq!(held["peak_slide_m"], 0.0);
        let pure = history(None);
        for doc in [held, pure] {
            let said = never_rocks(&doc);
            assert_eq!(said.len(), 1, "{said:?}");
            assert!(
                said[0].contains("): the block stays at rest;"),
                "{}",
                said[0]
            );
        }
    }
}
