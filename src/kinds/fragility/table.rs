//! A fragility's table: a row per stripe, its intensity in a first column
//! named after the result's measure (`pga_g`, `pgv_m_s`).
//!
//! Under a vertical motion a column `lift_off` counts the samples without
//! a verdict (p is over the others; empty when none was decided); where a
//! sample's history reached a bound on its work, a last column `undecided`
//! counts those.

use serde::Serialize;

use crate::kinds::fragility::{FragilityResult, StripeResult};
use crate::table::number::Number;
use crate::table::{Columns, Named, Table, TableError};

/// A row per stripe.
pub fn rows(r: &FragilityResult, table: &mut Table) -> Result<(), TableError> {
    let lift_off = r.stripes.iter().any(|s| s.lift_off.is_some());
    let undecided = r.stripes.iter().any(|s| s.undecided.is_some());
    for s in &r.stripes {
        let intensity = Named {
            name: r.im.name(),
            value: Number(s.im),
        };
        table.row((
            intensity,
            Stripe::of(s),
            Columns(lift_off.then_some(LiftOff {
                lift_off: s.lift_off,
            })),
            Columns(undecided.then_some(Undecided {
                undecided: s.undecided.unwrap_or(0),
            })),
        ))?;
    }
    Ok(())
}

/// The outcomes of a stripe's samples (after its intensity).
#[derive(Serialize)]
struct Stripe {
    /// Samples simulated.
    n: u64,
    /// How many toppled.
    overturned: u64,
    /// overturned / the samples decided (empty when none was).
    p: Number,
    /// p's 95 % Wilson score interval.
    p_lo_95: Number,
    p_hi_95: Number,
    /// Topplings after at least one impact.
    mode_1: u64,
    /// Topplings without impact.
    mode_2: u64,
}

impl Stripe {
    fn of(s: &StripeResult) -> Stripe {
        Stripe {
            n: s.n,
            overturned: s.overturned,
            p: Number(s.p),
            p_lo_95: Number(s.interval_95[0]),
            p_hi_95: Number(s.interval_95[1]),
            mode_1: s.mode_1,
            mode_2: s.mode_2,
        }
    }
}

/// Under a vertical ground motion: the samples that lifted off, without a
/// verdict.
#[derive(Serialize)]
struct LiftOff {
    lift_off: Option<u64>,
}

/// The samples whose history reached a bound on its work before their
/// outcome was decided.
#[derive(Serialize)]
struct Undecided {
    undecided: u64,
}

#[cfg(test)]
mod tests {
    use crate::api::csv::tests::{FRAGILITY, cell, csv_of, lines};
    use crate::jobs::names::Im;
    use crate::kinds::JobResult;
    use crate::kinds::fragility::StripeResult;
    use crate::plot::tests::typed;

    /// Under a vertical motion a last column counts the lift-offs, and a
    /// stripe whose every sample lifted off has an empty p and interval.
    #[test]
    fn fragility_rows_count_lift_offs_under_a_vertical_motion() {
        let JobResult::Fragility(r) = typed(
            r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","frequency_hz":0.8},"vertical":{"ratio":-0.5},"stripes":[0.3,3.0],"samples":4,"seed":1}"#,
        ) else {
            panic!("a fragility")
        };
        let csv = csv_of(&JobResult::Fragility(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "pga_g,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2,lift_off"
        );
        assert_eq!(r.stripes[0].lift_off, Some(0));
        assert!(l[1].ends_with(",0"), "{}", l[1]);
        assert_eq!(r.stripes[1].lift_off, Some(4), "{:?}", r.stripes[1]);
        assert_eq!(l[2], "3.0,4,0,,,,0,0,4");
    }

    #[test]
    fn fragility_rows_per_stripe() {
        let JobResult::Fragility(mut r) = typed(FRAGILITY) else {
            panic!("a fragility")
        };
        let csv = csv_of(&JobResult::Fragility(r.clone()));
        let l = lines(&csv);
        assert_eq!(l[0], "pga_g,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2");
        assert_eq!(l.len(), 1 + r.stripes.len());
        let s = &r.stripes[1];
        assert_eq!(
            l[2],
            format!(
                "{},{},{},{},{},{},{},{}",
                cell(&s.im),
                s.n,
                s.overturned,
                cell(&s.p),
                cell(&s.interval_95[0]),
                cell(&s.interval_95[1]),
                s.mode_1,
                s.mode_2
            )
        );
        r.stripes = vec![StripeResult {
            im: 0.3,
            n: 200,
            overturned: 58,
            p: 0.29,
            interval_95: [0.23, 0.35],
            mode_1: 58,
            mode_2: 0,
            lift_off: None,
            undecided: None,
        }];
        r.im = Im::PgvMS;
        let csv = csv_of(&JobResult::Fragility(r.clone()));
        assert_eq!(
            lines(&csv),
            vec![
                "pgv_m_s,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2",
                "0.3,200,58,0.29,0.23,0.35,58,0",
            ]
        );
        // Samples whose history reached a bound on its work: a last column.
        r.stripes[0].undecided = Some(3);
        let csv = csv_of(&JobResult::Fragility(r));
        assert_eq!(
            lines(&csv),
            vec![
                "pgv_m_s,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2,undecided",
                "0.3,200,58,0.29,0.23,0.35,58,0,3",
            ]
        );
    }
}
