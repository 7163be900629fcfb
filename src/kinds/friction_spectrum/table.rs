//! A friction spectrum's table: one row per amplitude, with the pulse's
//! frequency on each.

use serde::Serialize;

use crate::kinds::friction_spectrum::{FrictionPointDoc, FrictionResult};
use crate::table::number::Number;
use crate::table::{Table, TableError};

/// A row per amplitude.
pub fn rows(r: &FrictionResult, table: &mut Table) -> Result<(), TableError> {
    for p in &r.points {
        table.row(Row::of(r, p))?;
    }
    Ok(())
}

/// The friction a block needs to rock without sliding, at one amplitude.
#[derive(Serialize)]
struct Row {
    /// The amplitude, a_p/(αg).
    a_alpha_g: Number,
    /// max |f_x/f_z| over the rocking history: the least μ for pure
    /// rocking (empty when the block lifts off).
    peak_friction_demand: Option<Number>,
    /// The same over tan α.
    peak_over_tan_alpha: Option<Number>,
    /// f_x/f_z when rocking starts.
    initiation_friction_demand: Option<Number>,
    /// Whether the block overturned.
    overturned: bool,
    /// The overturning mode.
    mode: Option<u8>,
    /// Whether f_z reached 0 (no μ sustains pure rocking).
    lift_off: bool,
    /// When it first did, s.
    lift_off_time_s: Option<Number>,
    /// The demand was followed up to this time only (the block was then
    /// bound to overturn), s.
    friction_demand_followed_until_s: Option<Number>,
    /// The amplitude a_p, g.
    a_p_g: Number,
    /// The pulse's ω_p/p.
    omega_ratio: Number,
    /// Its ω_p, rad/s.
    omega_p_rad_per_s: Number,
    /// Its f_p, Hz.
    frequency_hz: Number,
}

impl Row {
    /// Point `p` of spectrum `r`.
    fn of(r: &FrictionResult, p: &FrictionPointDoc) -> Row {
        Row {
            a_alpha_g: Number(p.a_alpha_g),
            peak_friction_demand: p.peak_friction_demand.map(Number),
            peak_over_tan_alpha: p.peak_over_tan_alpha.map(Number),
            initiation_friction_demand: p.initiation_friction_demand.map(Number),
            overturned: p.overturned,
            mode: p.mode,
            lift_off: p.lift_off,
            lift_off_time_s: p.lift_off_time.map(Number),
            friction_demand_followed_until_s: p.friction_demand_followed_until.map(Number),
            a_p_g: Number(p.a_p_g),
            omega_ratio: Number(r.omega_ratio),
            omega_p_rad_per_s: Number(r.omega_p),
            frequency_hz: Number(r.frequency_hz),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::api::csv::tests::{FRICTION, cell, csv_of, lines};
    use crate::kinds::JobResult;
    use crate::kinds::friction_spectrum::FrictionPointDoc;
    use crate::plot::tests::typed;

    #[test]
    fn friction_rows_per_amplitude() {
        let JobResult::FrictionSpectrum(mut r) = typed(FRICTION) else {
            panic!("a friction spectrum")
        };
        let csv = csv_of(&JobResult::FrictionSpectrum(r.clone()));
        let l = lines(&csv);
        assert_eq!(l.len(), 1 + r.points.len());
        let p = &r.points[0];
        assert_eq!(
            l[1].split(',').take(2).collect::<Vec<_>>(),
            vec![
                cell(&p.a_alpha_g),
                p.peak_friction_demand
                    .map_or_else(String::new, |x| cell(&x))
            ]
        );
        let point = |a: f64, peak: Option<f64>, over: Option<f64>, init: f64| FrictionPointDoc {
            a_alpha_g: a,
            a_p_g: a / 4.0,
            peak_friction_demand: peak,
            peak_over_tan_alpha: over,
            initiation_friction_demand: Some(init),
            overturned: false,
            mode: None,
            lift_off: false,
            lift_off_time: None,
            friction_demand_followed_until: None,
        };
        let mut lifted = point(6.0, None, None, 0.51);
        (lifted.overturned, lifted.mode) = (true, Some(2));
        (lifted.lift_off, lifted.lift_off_time) = (true, Some(0.41));
        let mut followed = point(8.0, Some(0.3), Some(1.2), 0.6);
        followed.friction_demand_followed_until = Some(0.5);
        r.points = vec![point(1.1, Some(0.26), Some(1.02), 0.255), lifted, followed];
        (r.omega_ratio, r.omega_p, r.frequency_hz) = (3.0, 6.42, 1.02);
        let csv = csv_of(&JobResult::FrictionSpectrum(r));
        assert_eq!(
            lines(&csv),
            vec![
                "a_alpha_g,peak_friction_demand,peak_over_tan_alpha,initiation_friction_demand,overturned,mode,lift_off,lift_off_time_s,friction_demand_followed_until_s,\
                 a_p_g,omega_ratio,omega_p_rad_per_s,frequency_hz",
                "1.1,0.26,1.02,0.255,false,,false,,,0.275,3.0,6.42,1.02",
                "6.0,,,0.51,true,2,true,0.41,,1.5,3.0,6.42,1.02",
                "8.0,0.3,1.2,0.6,false,,false,,0.5,2.0,3.0,6.42,1.02",
            ]
        );
    }
}
