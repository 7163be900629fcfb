//! A record forensic query's table: a row per consistent interval of scale
//! factors (or one empty row when there is none), then a row per mixed
//! zone, first for every observation at once (`observation` empty), then
//! for each. An observation's rows carry the scale at which its block
//! starts to rock.

use serde::Serialize;

use crate::jobs::mixed::MixedDoc;
use crate::kinds::forensic::ForensicResult;
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Table, TableError};

/// The rows for all observations, then for each.
pub fn rows(r: &ForensicResult, table: &mut Table) -> Result<(), TableError> {
    let all = Observation {
        name: "",
        seen: None,
        threshold_scale: None,
    };
    all.rows(
        table,
        [
            r.consistent_scale.as_deref().unwrap_or_default(),
            r.consistent_pga_g.as_deref().unwrap_or_default(),
        ],
        [
            r.mixed_scale.as_deref().unwrap_or_default(),
            r.mixed_pga_g.as_deref().unwrap_or_default(),
        ],
    )?;
    for (k, o) in r
        .per_observation
        .as_deref()
        .unwrap_or_default()
        .iter()
        .enumerate()
    {
        let seen = r
            .observations
            .get(k)
            .filter(|x| x.name == o.name && x.overturned == o.overturned)
            .map_or_else(|| seen(o.overturned).to_string(), |x| x.seen());
        let each = Observation {
            name: &o.name,
            seen: Some(&seen),
            threshold_scale: Some(o.threshold_scale),
        };
        each.rows(
            table,
            [&o.consistent_scale, &o.consistent_pga_g],
            [&o.mixed_scale, &o.mixed_pga_g],
        )?;
    }
    Ok(())
}

/// "overturned" or "survived".
fn seen(overturned: bool) -> &'static str {
    if overturned { "overturned" } else { "survived" }
}

/// Whose rows: an observation's, or every observation's (no name).
struct Observation<'a> {
    name: &'a str,
    seen: Option<&'a str>,
    threshold_scale: Option<f64>,
}

impl Observation<'_> {
    /// A row per consistent interval (in scale factors and PGA, g), or one
    /// empty row; then a row per mixed zone (likewise).
    fn rows(
        &self,
        table: &mut Table,
        [scale, pga]: [&[[f64; 2]]; 2],
        [zones, zones_g]: [&[MixedDoc]; 2],
    ) -> Result<(), TableError> {
        if scale.is_empty() {
            table.row(self.row())?;
        }
        for (s, g) in scale.iter().zip(pga) {
            table.row(Row {
                consistent_lo_scale: Some(Number(s[0])),
                consistent_hi_scale: Some(Number(s[1])),
                consistent_lo_pga_g: Some(Number(g[0])),
                consistent_hi_pga_g: Some(Number(g[1])),
                ..self.row()
            })?;
        }
        for (z, g) in zones.iter().zip(zones_g) {
            table.row(Row {
                mixed_lo_scale: Some(Number(z.from)),
                mixed_hi_scale: Some(Number(z.to)),
                mixed_lo_pga_g: Some(Number(g.from)),
                mixed_hi_pga_g: Some(Number(g.to)),
                mixed_fraction: Some(Number(z.fraction)),
                mixed_probes: Some(z.probes),
                mixed_interval_95_lo: Some(Number(z.interval_95[0])),
                mixed_interval_95_hi: Some(Number(z.interval_95[1])),
                ..self.row()
            })?;
        }
        Ok(())
    }

    /// The observation's cells, the others empty.
    fn row(&self) -> Row<'_> {
        Row {
            observation: Text(self.name),
            observed: self.seen.map(Text),
            consistent_lo_scale: None,
            consistent_hi_scale: None,
            consistent_lo_pga_g: None,
            consistent_hi_pga_g: None,
            threshold_scale: self.threshold_scale.map(Number),
            mixed_lo_scale: None,
            mixed_hi_scale: None,
            mixed_lo_pga_g: None,
            mixed_hi_pga_g: None,
            mixed_fraction: None,
            mixed_probes: None,
            mixed_interval_95_lo: None,
            mixed_interval_95_hi: None,
        }
    }
}

/// An interval of scale factors of the record consistent with what was
/// seen, or a mixed zone. Levels are scale factors (`_scale`) or the
/// scaled record's PGA (`_pga_g`, g).
#[derive(Serialize)]
struct Row<'a> {
    /// The observation's name; empty for all observations at once.
    observation: Text<&'a str>,
    /// What was seen of it: `overturned`, `survived`, or `survived, slid …`.
    observed: Option<Text<&'a str>>,
    /// The consistent interval's ends.
    consistent_lo_scale: Option<Number>,
    consistent_hi_scale: Option<Number>,
    consistent_lo_pga_g: Option<Number>,
    consistent_hi_pga_g: Option<Number>,
    /// The scale at which the observation's block starts to rock.
    threshold_scale: Option<Number>,
    /// A mixed zone's ends: where the outcome alternates finer than the
    /// scan resolves.
    mixed_lo_scale: Option<Number>,
    mixed_hi_scale: Option<Number>,
    mixed_lo_pga_g: Option<Number>,
    mixed_hi_pga_g: Option<Number>,
    /// The fraction of its probed scales whose outcome is the observation's.
    mixed_fraction: Option<Number>,
    /// Scales probed.
    mixed_probes: Option<u64>,
    /// The fraction's 95 % interval.
    mixed_interval_95_lo: Option<Number>,
    mixed_interval_95_hi: Option<Number>,
}

#[cfg(test)]
mod tests {
    use crate::api::csv::tests::{FORENSIC_RECORD, cell, csv_of, lines};
    use crate::jobs::names::Excitation;
    use crate::kinds::JobResult;
    use crate::kinds::forensic::RecordObservationSet;
    use crate::plot::tests::typed;

    #[test]
    fn a_record_querys_rows_per_interval_and_observation() {
        let JobResult::Forensic(mut r) = typed(FORENSIC_RECORD) else {
            panic!("a forensic query")
        };
        assert_eq!(r.excitation, Excitation::GroundMotion);
        let csv = csv_of(&JobResult::Forensic(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "observation,observed,consistent_lo_scale,consistent_hi_scale,consistent_lo_pga_g,consistent_hi_pga_g,threshold_scale,\
             mixed_lo_scale,mixed_hi_scale,mixed_lo_pga_g,mixed_hi_pga_g,mixed_fraction,mixed_probes,mixed_interval_95_lo,mixed_interval_95_hi"
        );
        let all = r.consistent_scale.clone().expect("a record query's scales");
        let mine = &r.per_observation.as_ref().expect("per observation")[0];
        let rows = |n: usize| n.max(1);
        let zones = r.mixed_scale.as_ref().map_or(0, Vec::len);
        assert_eq!(
            l.len(),
            1 + rows(all.len())
                + zones
                + rows(mine.consistent_scale.len())
                + mine.mixed_scale.len()
        );
        let first = mine.consistent_scale.first().expect("a survived scale");
        let first_g = mine.consistent_pga_g[0];
        assert_eq!(
            l[1 + rows(all.len()) + zones],
            format!(
                "transformer,survived,{},{},{},{},{},,,,,,,,",
                cell(&first[0]),
                cell(&first[1]),
                cell(&first_g[0]),
                cell(&first_g[1]),
                cell(&mine.threshold_scale)
            )
        );
        let set = |name: &str, overturned: bool, scale: Vec<[f64; 2]>, pga: Vec<[f64; 2]>| {
            RecordObservationSet {
                name: name.into(),
                overturned,
                consistent_scale: scale,
                consistent_pga_g: pga,
                mixed_scale: vec![],
                mixed_pga_g: vec![],
                overturning_scale: vec![],
                threshold_scale: if overturned { 0.5 } else { 0.25 },
                lift_off_above_scale: None,
            }
        };
        r.consistent_scale = Some(vec![[0.7, 1.4], [2.8, 3.2]]);
        r.consistent_pga_g = Some(vec![[0.35, 0.7], [1.4, 1.6]]);
        r.per_observation = Some(vec![
            set("locomotive", true, vec![[0.7, 6.0]], vec![[0.35, 3.0]]),
            set("=cmd", false, vec![], vec![]),
        ]);
        let csv = csv_of(&JobResult::Forensic(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                ",,0.7,1.4,0.35,0.7,,,,,,,,,",
                ",,2.8,3.2,1.4,1.6,,,,,,,,,",
                "locomotive,overturned,0.7,6.0,0.35,3.0,0.5,,,,,,,,",
                "\"'=cmd\",survived,,,,,0.25,,,,,,,,",
            ]
        );
    }
}
