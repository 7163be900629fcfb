//! Checks against a record read wrongly without an error: time values taken
//! for accelerations, a unit off by 100 or by g, an uncorrected baseline.
//! Job-spec validation calls the same functions on arrays given inline, so
//! one rule holds however a record arrives.

use std::sync::Arc;

use super::RecordWarning;
use super::unit::Unit;
use crate::dynamics::Record;
use crate::dynamics::peaks::of_record;

/// Above this PGA (in g) a record is not believed without `allow_large_pga`:
/// the largest ever recorded are about 3–4 g.
pub const PGA_IMPLAUSIBLE_G: f64 = 5.0;
/// Above this PGA (in g) a record is accepted with a warning.
pub const PGA_LARGE_G: f64 = 2.0;
/// Relative tolerance of "a constant step".
const STEP_TOLERANCE: f64 = 1e-6;

/// Whether `values` rise by one constant positive step (to 1e-6 of it),
/// with at least 3 values.
fn constant_rise(values: impl Iterator<Item = f64>) -> bool {
    let mut count = 0usize;
    let mut previous = f64::NAN;
    let mut step = f64::NAN;
    for v in values {
        if count == 1 {
            step = v - previous;
            if !(step > 0.0 && step.is_finite()) {
                return false;
            }
        } else if count > 1 && ((v - previous) - step).abs() > STEP_TOLERANCE * step {
            return false;
        }
        previous = v;
        count += 1;
    }
    count >= 3
}

/// Whether `values` look like (time, acceleration) pairs flattened into one
/// series: the values at even indices, or those at odd indices, rise by a
/// constant positive step (at least 3 of them), and the other half does not.
pub fn looks_interleaved(values: &[f64]) -> bool {
    let half = |parity: usize| values.iter().copied().skip(parity).step_by(2);
    let (even, odd) = (constant_rise(half(0)), constant_rise(half(1)));
    even != odd
}

/// Whether `values` as a whole rise by one constant step (at least 3 of
/// them): a time column, not accelerations.
pub fn looks_like_time(values: &[f64]) -> bool {
    constant_rise(values.iter().copied())
}

/// What a record's PGA says about its unit.
#[derive(Clone, Debug, PartialEq)]
pub enum PgaCheck {
    /// Up to [`PGA_LARGE_G`].
    Fine,
    /// Above [`PGA_LARGE_G`], up to [`PGA_IMPLAUSIBLE_G`]: kept, with this
    /// warning (kind `large_pga`).
    Large(RecordWarning),
    /// Above [`PGA_IMPLAUSIBLE_G`]: most likely a unit read wrongly; the
    /// message says which.
    Implausible(String),
}

/// What a PGA of `pga_in_g` (in g, after reading the values in `unit`)
/// says: above 5 g a unit was most likely misread, and the message names
/// the unit that would make the record plausible.
pub fn check_pga(pga_in_g: f64, unit: Unit) -> PgaCheck {
    if pga_in_g <= PGA_LARGE_G {
        return PgaCheck::Fine;
    }
    if pga_in_g <= PGA_IMPLAUSIBLE_G {
        return PgaCheck::Large(RecordWarning {
            kind: "large_pga",
            message: format!(
                "the record's PGA is {pga_in_g:.3} g with its values read in {unit}: few records \
                 ever exceeded {PGA_LARGE_G} g; if the values are in another unit, upload it again \
                 with that unit"
            ),
        });
    }
    let found = format!(
        "the record's PGA is {pga_in_g:.3} g with its values read in {unit}, more than \
         {PGA_IMPLAUSIBLE_G} g"
    );
    // What the PGA would be had the values been in another unit.
    let as_unit = |other: Unit| match (unit, other) {
        (Unit::MetresPerSecondSquared, Unit::CentimetresPerSecondSquared) => pga_in_g / 100.0,
        (Unit::G, Unit::MetresPerSecondSquared) => pga_in_g / super::G_M_S2,
        (Unit::G, Unit::CentimetresPerSecondSquared) => pga_in_g / (100.0 * super::G_M_S2),
        _ => f64::INFINITY,
    };
    let hints: Vec<String> = [
        Unit::MetresPerSecondSquared,
        Unit::CentimetresPerSecondSquared,
    ]
    .into_iter()
    .filter(|&other| as_unit(other) <= PGA_IMPLAUSIBLE_G)
    .map(|other| {
        format!(
            "{} read as {}? In {} the PGA would be {:.3} g: upload it again with unit {}",
            pretty(other),
            pretty(unit),
            pretty(other),
            as_unit(other),
            other.as_str()
        )
    })
    .collect();
    let message = if !hints.is_empty() {
        format!("{found}. {}", hints.join("; or "))
    } else if unit == Unit::CentimetresPerSecondSquared {
        format!(
            "{found}, although cm/s² is already the smallest unit read: the values are not a \
             ground acceleration in g, m/s² or cm/s² (counts? mm/s²?); convert them first"
        )
    } else {
        format!(
            "{found}, and more than {PGA_IMPLAUSIBLE_G} g in every unit read (g, m/s², cm/s²): \
             the values are not a ground acceleration; check the file"
        )
    };
    PgaCheck::Implausible(message)
}

/// The unit as written in prose.
fn pretty(unit: Unit) -> &'static str {
    match unit {
        Unit::G => "g",
        Unit::MetresPerSecondSquared => "m/s²",
        Unit::CentimetresPerSecondSquared => "cm/s²",
    }
}

/// A warning when the ground does not come back to rest: the final ground
/// velocity of the piecewise-linear acceleration `acc_m_s2` (sampled every
/// `dt` s, from rest) exceeds max(0.1·PGV, 0.01 m/s). An uncorrected
/// baseline makes the ground drift, and a block on it sees a spurious pulse.
/// `None` when the velocity returns near zero, or the record is not valid.
pub fn baseline_drift(dt: f64, acc_m_s2: &[f64]) -> Option<RecordWarning> {
    let record = Record::new(Arc::from(acc_m_s2), dt).ok()?;
    // The trapezoid rule is exact for a piecewise-linear acceleration.
    let v_end: f64 = acc_m_s2.windows(2).map(|w| 0.5 * (w[0] + w[1]) * dt).sum();
    let pgv = of_record(&record).pgv;
    let limit = (0.1 * pgv).max(0.01);
    (v_end.abs() > limit).then(|| RecordWarning {
        kind: "baseline_drift",
        message: format!(
            "the ground velocity at the end of the record is {v_end:.4} m/s (PGV {pgv:.4} m/s), \
             more than {limit:.4} m/s: the baseline is not corrected, so the ground drifts; \
             use a baseline-corrected (processed) record, or correct it before uploading"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_and_acceleration_pairs_flattened_are_interleaved() {
        // (t, a) pairs: 0, 0.1, 0.01, -0.2, 0.02, 0.05, 0.03, 0.0
        let pairs = [0.0, 0.1, 0.01, -0.2, 0.02, 0.05, 0.03, 0.0];
        assert!(looks_interleaved(&pairs));
        // The same with acceleration first.
        let swapped = [0.1, 0.0, -0.2, 0.01, 0.05, 0.02, 0.0, 0.03];
        assert!(looks_interleaved(&swapped));
    }

    #[test]
    fn an_acceleration_series_is_not_interleaved() {
        let acc: Vec<f64> = (0..400).map(|k| (0.37 * k as f64).sin()).collect();
        assert!(!looks_interleaved(&acc));
        // Both halves rising by a constant step is a ramp, not pairs.
        let ramp: Vec<f64> = (0..10).map(f64::from).collect();
        assert!(!looks_interleaved(&ramp));
        // Two pairs are not enough to tell.
        assert!(!looks_interleaved(&[0.0, 0.3, 0.01, -0.2]));
        // A step that wanders by more than 1e-6 of itself is not constant.
        assert!(!looks_interleaved(&[0.0, 0.1, 0.01, -0.2, 0.0200001, 0.05]));
        assert!(looks_interleaved(&[
            0.0,
            0.1,
            0.01,
            -0.2,
            0.02000000001,
            0.05
        ]));
    }

    #[test]
    fn a_column_rising_by_a_constant_step_looks_like_time() {
        let t: Vec<f64> = (0..1000).map(|k| 12.5 + k as f64 * 0.005).collect();
        assert!(looks_like_time(&t));
        let acc: Vec<f64> = (0..1000).map(|k| (0.1 * k as f64).cos()).collect();
        assert!(!looks_like_time(&acc));
        assert!(!looks_like_time(&[0.0, 0.01]));
        assert!(!looks_like_time(&[0.0, 0.0, 0.0]));
    }

    #[test]
    fn pga_bands_are_fine_large_and_implausible() {
        assert_eq!(check_pga(0.3, Unit::G), PgaCheck::Fine);
        assert_eq!(check_pga(2.0, Unit::G), PgaCheck::Fine);
        match check_pga(3.0, Unit::G) {
            PgaCheck::Large(w) => {
                assert_eq!(w.kind, "large_pga");
                assert!(w.message.contains("3.000 g"), "{}", w.message);
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(check_pga(5.0, Unit::G), PgaCheck::Large(_)));
        assert!(matches!(check_pga(5.01, Unit::G), PgaCheck::Implausible(_)));
    }

    #[test]
    fn a_cm_record_read_as_metres_is_named_in_the_hint() {
        // El Centro's 0.348 g in cm/s² (341.6) read as m/s²: 34.8 g.
        let PgaCheck::Implausible(m) = check_pga(341.6 / 9.81, Unit::MetresPerSecondSquared) else {
            panic!("not implausible")
        };
        assert!(m.contains("cm/s² read as m/s²?"), "{m}");
        assert!(m.contains("0.348 g"), "{m}");
        assert!(m.contains("unit cm/s2"), "{m}");
    }

    #[test]
    fn a_record_in_g_too_large_suggests_metres_or_centimetres() {
        // 3.4 m/s² read as g: 3.4 g is only large, not implausible.
        // 34 m/s² read as g: /9.81 = 3.47 g, /981 = 0.035 g: both plausible.
        let PgaCheck::Implausible(m) = check_pga(34.0, Unit::G) else {
            panic!("not implausible")
        };
        assert!(m.contains("In m/s² the PGA would be 3.466 g"), "{m}");
        assert!(m.contains("In cm/s² the PGA would be 0.035 g"), "{m}");
        // 341.6 cm/s² read as g: only cm/s² is plausible (34.8 g in m/s²).
        let PgaCheck::Implausible(m) = check_pga(341.6, Unit::G) else {
            panic!("not implausible")
        };
        assert!(!m.contains("In m/s²"), "{m}");
        assert!(m.contains("cm/s² read as g?"), "{m}");
        assert!(m.contains("0.348 g"), "{m}");
    }

    #[test]
    fn a_record_in_cm_too_large_is_said_plainly() {
        let PgaCheck::Implausible(m) = check_pga(40.0, Unit::CentimetresPerSecondSquared) else {
            panic!("not implausible")
        };
        assert!(m.contains("smallest unit"), "{m}");
        assert!(!m.contains("read as"), "{m}");
        let PgaCheck::Implausible(m) = check_pga(1.0e6, Unit::G) else {
            panic!("not implausible")
        };
        assert!(m.contains("in every unit"), "{m}");
    }

    #[test]
    fn a_constant_acceleration_drifts_and_a_sine_cycle_does_not() {
        // 0.1 m/s² for 10 s ends at 1 m/s (PGV 1 m/s, limit 0.1 m/s).
        let dt = 0.01;
        let constant = vec![0.1; 1001];
        let w = baseline_drift(dt, &constant).expect("drifts");
        assert_eq!(w.kind, "baseline_drift");
        assert!(w.message.contains("1.0000 m/s"), "{}", w.message);
        // One full sine cycle: v ends at 0.
        let n = 1000;
        let sine: Vec<f64> = (0..=n)
            .map(|k| (2.0 * std::f64::consts::PI * k as f64 / n as f64).sin())
            .collect();
        assert_eq!(baseline_drift(dt, &sine), None);
        // Too short to be a record: nothing to say.
        assert_eq!(baseline_drift(dt, &[1.0]), None);
    }

    #[test]
    fn a_small_drift_under_one_centimetre_per_second_passes() {
        // v_end = 0.005 m/s > 0.1·PGV but below the 0.01 m/s floor.
        let acc = vec![0.001; 501];
        assert_eq!(baseline_drift(0.01, &acc), None);
    }
}
