//! A record spectrum's table: one row per transition of each block size (a
//! size without any: one row, its transition's cells empty), then a row per
//! mixed zone of the size.

use serde::Serialize;

use crate::jobs::mixed::MixedDoc;
use crate::kinds::record_spectrum::{RecordSpectrumResult, ScaleTransitionDoc, SizeDoc};
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Table, TableError};

/// The rows of every block size.
pub fn rows(r: &RecordSpectrumResult, table: &mut Table) -> Result<(), TableError> {
    for size in &r.spectrum {
        if size.transitions.is_empty() {
            table.row(Row::of_line(size))?;
        }
        for t in &size.transitions {
            table.row(Row::of_transition(size, t))?;
        }
        for z in &size.mixed {
            table.row(Row::of_zone(size, z))?;
        }
    }
    Ok(())
}

/// A row of a record spectrum's table: a block size's, with a transition
/// or a mixed zone. Levels are scale factors of the record (`_scale`) or
/// the scaled record's PGA (`_pga_g`, g).
#[derive(Serialize)]
struct Row<'a> {
    /// The size's frequency parameter p, rad/s.
    p_rad_s: Number,
    /// Its size R = 3g/(4p²), m.
    #[serde(rename = "R_m")]
    r_m: Number,
    /// The transition's scale (bracket midpoint), or a mixed zone's lowest.
    scale: Option<Number>,
    /// The transition's PGA.
    pga_g: Option<Number>,
    /// `up` (overturning begins as the scale grows) or `down` (a safe
    /// interval begins); `mixed` on a mixed zone's row.
    direction: Option<Text<&'a str>>,
    /// The transition's mode on the overturning side.
    mode: Option<u8>,
    /// Its impacts on the overturning side.
    impacts: Option<u64>,
    /// Its bracket's ends.
    bracket_lo_scale: Option<Number>,
    bracket_hi_scale: Option<Number>,
    /// The size's lowest overturning scale, and the PGA there.
    min_overturn_scale: Option<Number>,
    min_overturn_pga_g: Option<Number>,
    /// The scale at which the block starts to rock.
    threshold_scale: Option<Number>,
    /// The lowest overturning scale's mode.
    min_overturn_mode: Option<u8>,
    /// Every scale above this overturns (up to the highest examined).
    overturns_above_scale: Option<Number>,
    /// The same three without bands narrower than the principal width.
    principal_min_overturn_scale: Option<Number>,
    principal_min_overturn_mode: Option<u8>,
    principal_overturns_above_scale: Option<Number>,
    /// Where `min_overturn_scale` lies: `band` or `mixed`.
    min_overturn_in: Option<Text<&'a str>>,
    /// The lowest scale from which overturning is certain, and the PGA
    /// there.
    min_certain_overturn_scale: Option<Number>,
    min_certain_overturn_pga_g: Option<Number>,
    /// A mixed zone's highest scale.
    mixed_to: Option<Number>,
    /// The fraction of its probed scales at which the block overturns.
    mixed_fraction: Option<Number>,
    /// Scales probed.
    mixed_probes: Option<u64>,
    /// The fraction's 95 % interval.
    mixed_interval_95_lo: Option<Number>,
    mixed_interval_95_hi: Option<Number>,
}

impl<'a> Row<'a> {
    /// The cells of the size alone (p and R), the others empty.
    fn of_size(size: &SizeDoc) -> Row<'a> {
        Row {
            p_rad_s: Number(size.p),
            r_m: Number(size.r_m),
            scale: None,
            pga_g: None,
            direction: None,
            mode: None,
            impacts: None,
            bracket_lo_scale: None,
            bracket_hi_scale: None,
            min_overturn_scale: None,
            min_overturn_pga_g: None,
            threshold_scale: None,
            min_overturn_mode: None,
            overturns_above_scale: None,
            principal_min_overturn_scale: None,
            principal_min_overturn_mode: None,
            principal_overturns_above_scale: None,
            min_overturn_in: None,
            min_certain_overturn_scale: None,
            min_certain_overturn_pga_g: None,
            mixed_to: None,
            mixed_fraction: None,
            mixed_probes: None,
            mixed_interval_95_lo: None,
            mixed_interval_95_hi: None,
        }
    }

    /// Every cell of the size, the transition's empty.
    fn of_line(size: &'a SizeDoc) -> Row<'a> {
        Row {
            min_overturn_scale: size.min_overturn_scale.map(Number),
            min_overturn_pga_g: size.min_overturn_pga_g.map(Number),
            threshold_scale: Some(Number(size.threshold_scale)),
            min_overturn_mode: size.min_overturn_mode,
            overturns_above_scale: size.overturns_above_scale.map(Number),
            principal_min_overturn_scale: size.principal.min_overturn_scale.map(Number),
            principal_min_overturn_mode: size.principal.min_overturn_mode,
            principal_overturns_above_scale: size.principal.overturns_above_scale.map(Number),
            min_overturn_in: size.min_overturn_in.as_deref().map(Text),
            min_certain_overturn_scale: size.min_certain_overturn_scale.map(Number),
            min_certain_overturn_pga_g: size.min_certain_overturn_pga_g.map(Number),
            ..Row::of_size(size)
        }
    }

    /// Transition `t` of the size, with every cell of the size.
    fn of_transition(size: &'a SizeDoc, t: &'a ScaleTransitionDoc) -> Row<'a> {
        Row {
            scale: Some(Number(t.scale)),
            pga_g: Some(Number(t.pga_g)),
            direction: Some(Text(&t.direction)),
            mode: Some(t.mode),
            impacts: Some(t.impacts),
            bracket_lo_scale: Some(Number(t.bracket[0])),
            bracket_hi_scale: Some(Number(t.bracket[1])),
            ..Row::of_line(size)
        }
    }

    /// Mixed zone `z` of the size.
    fn of_zone(size: &SizeDoc, z: &MixedDoc) -> Row<'a> {
        Row {
            scale: Some(Number(z.from)),
            direction: Some(Text("mixed")),
            mixed_to: Some(Number(z.to)),
            mixed_fraction: Some(Number(z.fraction)),
            mixed_probes: Some(z.probes),
            mixed_interval_95_lo: Some(Number(z.interval_95[0])),
            mixed_interval_95_hi: Some(Number(z.interval_95[1])),
            ..Row::of_size(size)
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::api::csv::tests::{RECORD_SPECTRUM, cell, csv_of, lines};
    use crate::kinds::JobResult;
    use crate::plot::tests::typed;

    #[test]
    fn record_spectrum_rows_per_transition_and_size() {
        let JobResult::RecordSpectrum(mut r) = typed(RECORD_SPECTRUM) else {
            panic!("a record spectrum")
        };
        let csv = csv_of(&JobResult::RecordSpectrum(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "p_rad_s,R_m,scale,pga_g,direction,mode,impacts,bracket_lo_scale,bracket_hi_scale,min_overturn_scale,min_overturn_pga_g,threshold_scale,\
             min_overturn_mode,overturns_above_scale,principal_min_overturn_scale,principal_min_overturn_mode,principal_overturns_above_scale,\
             min_overturn_in,min_certain_overturn_scale,min_certain_overturn_pga_g,mixed_to,mixed_fraction,mixed_probes,mixed_interval_95_lo,mixed_interval_95_hi"
        );
        let rows: usize = r
            .spectrum
            .iter()
            .map(|s| s.transitions.len().max(1) + s.mixed.len())
            .sum();
        assert_eq!(l.len(), 1 + rows);
        let size = &r.spectrum[0];
        let head = format!("{},{},", cell(&size.p), cell(&size.r_m));
        assert!(l[1].starts_with(&head), "{} against {head}", l[1]);
        let fields: Vec<&str> = l[1].split(',').collect();
        assert_eq!(fields[11], cell(&size.threshold_scale), "{}", l[1]);
        // Set values: a size with a transition, one without.
        let mut first = r.spectrum[0].clone();
        let mut second = first.clone();
        (first.p, first.r_m, first.threshold_scale) = (1.5, 4.36, 0.4);
        (first.min_overturn_scale, first.min_overturn_pga_g) = (Some(2.5), Some(0.75));
        (first.min_overturn_mode, first.overturns_above_scale) = (Some(2), Some(2.5));
        first.principal.min_overturn_scale = Some(2.5);
        first.principal.min_overturn_mode = Some(2);
        first.principal.overturns_above_scale = Some(2.5);
        let up = crate::kinds::record_spectrum::ScaleTransitionDoc {
            scale: 2.5,
            pga_g: 0.75,
            direction: "up".into(),
            mode: 2,
            impacts: 0,
            bracket: [2.49, 2.51],
        };
        first.transitions = vec![up];
        (second.p, second.r_m, second.threshold_scale) = (3.0, 1.09, 0.5);
        (second.min_overturn_scale, second.min_overturn_pga_g) = (None, None);
        (second.min_overturn_mode, second.overturns_above_scale) = (None, None);
        second.principal.min_overturn_scale = None;
        second.principal.min_overturn_mode = None;
        second.principal.overturns_above_scale = None;
        (first.mixed, second.mixed) = (vec![], vec![]);
        (first.min_overturn_in, first.min_certain_overturn_scale) =
            (Some("band".into()), Some(2.5));
        first.min_certain_overturn_pga_g = Some(0.75);
        (second.min_overturn_in, second.min_certain_overturn_scale) = (None, None);
        second.min_certain_overturn_pga_g = None;
        second.transitions = vec![];
        r.spectrum = vec![first, second];
        let csv = csv_of(&JobResult::RecordSpectrum(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "1.5,4.36,2.5,0.75,up,2,0,2.49,2.51,2.5,0.75,0.4,2,2.5,2.5,2,2.5,band,2.5,0.75,,,,,",
                "3.0,1.09,,,,,,,,,,0.5,,,,,,,,,,,,,",
            ]
        );
    }
}
