//! A pulse forensic query's table: one row per frequency and interval of
//! amplitudes consistent with every observation (`observation` empty), then
//! the same per observation; a frequency with no consistent amplitude has
//! one row with the interval empty.

use serde::Serialize;

use crate::kinds::forensic::{ForensicFrequency, ForensicResult};
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Table, TableError};

/// The rows for all observations, then for each.
pub fn rows(r: &ForensicResult, table: &mut Table) -> Result<(), TableError> {
    for f in &r.frequencies {
        intervals(table, f, "", None, &f.consistent_g)?;
    }
    for f in &r.frequencies {
        for o in &f.per_observation {
            let seen = r
                .observations
                .iter()
                .find(|x| x.name == o.name)
                .map(|x| x.seen());
            intervals(table, f, &o.name, seen.as_deref(), &o.consistent_g)?;
        }
    }
    Ok(())
}

/// A row per interval of `set` at frequency `f`, for observation `name`
/// (seen as `seen`); one row with the interval empty when `set` has none.
fn intervals(
    table: &mut Table,
    f: &ForensicFrequency,
    name: &str,
    seen: Option<&str>,
    set: &[[f64; 2]],
) -> Result<(), TableError> {
    let row = |ends: Option<[f64; 2]>| Row {
        frequency_hz: Number(f.frequency_hz),
        omega_p_rad_per_s: Number(f.omega_p),
        observation: Text(name),
        observed: seen.map(Text),
        consistent_lo_g: ends.map(|e| Number(e[0])),
        consistent_hi_g: ends.map(|e| Number(e[1])),
    };
    if set.is_empty() {
        table.row(row(None))?;
    }
    for ends in set {
        table.row(row(Some(*ends)))?;
    }
    Ok(())
}

/// An interval of pulse amplitudes consistent with what was seen, at one
/// frequency.
#[derive(Serialize)]
struct Row<'a> {
    /// The pulse's f_p, Hz.
    frequency_hz: Number,
    /// Its ω_p, rad/s.
    omega_p_rad_per_s: Number,
    /// The observation's name; empty for all observations at once.
    observation: Text<&'a str>,
    /// What was seen of it: `overturned`, `survived`, or `survived, slid …`.
    observed: Option<Text<&'a str>>,
    /// The interval's ends, g.
    consistent_lo_g: Option<Number>,
    consistent_hi_g: Option<Number>,
}

#[cfg(test)]
mod tests {
    use crate::api::csv::tests::{FORENSIC, cell, csv_of, lines};
    use crate::jobs::names::Excitation;
    use crate::kinds::JobResult;
    use crate::kinds::forensic::{ForensicFrequency, Observation, ObservationSet};
    use crate::plot::tests::typed;

    /// A pulse query's observations and frequencies set to `observations`
    /// (name, overturned) and `frequencies`.
    fn forensic_with(
        observations: &[(&str, bool)],
        frequencies: Vec<ForensicFrequency>,
    ) -> JobResult {
        let JobResult::Forensic(mut r) = typed(FORENSIC) else {
            panic!("a forensic query")
        };
        let block = r.observations[0].block;
        r.observations = observations
            .iter()
            .map(|&(name, overturned)| Observation {
                name: name.into(),
                overturned,
                block,
                slid_m: None,
            })
            .collect();
        r.frequencies = frequencies;
        JobResult::Forensic(r)
    }

    fn frequency(
        frequency_hz: f64,
        omega_p: f64,
        consistent_g: Vec<[f64; 2]>,
        per_observation: &[(&str, Vec<[f64; 2]>)],
    ) -> ForensicFrequency {
        ForensicFrequency {
            frequency_hz,
            omega_p,
            consistent_g,
            mixed_g: vec![],
            per_observation: per_observation
                .iter()
                .map(|(name, set)| ObservationSet {
                    name: (*name).into(),
                    consistent_g: set.clone(),
                    mixed_g: vec![],
                    lift_off_above_g: None,
                })
                .collect(),
        }
    }

    #[test]
    fn forensic_rows_per_frequency_interval_and_observation() {
        let JobResult::Forensic(r) = typed(FORENSIC) else {
            panic!("a forensic query")
        };
        assert_eq!(r.excitation, Excitation::Pulse);
        let csv = csv_of(&JobResult::Forensic(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "frequency_hz,omega_p_rad_per_s,observation,observed,consistent_lo_g,consistent_hi_g"
        );
        let rows = |sets: &[[f64; 2]]| sets.len().max(1);
        let whole: usize = r.frequencies.iter().map(|f| rows(&f.consistent_g)).sum();
        let each: usize = r
            .frequencies
            .iter()
            .flat_map(|f| &f.per_observation)
            .map(|o| rows(&o.consistent_g))
            .sum();
        assert_eq!(l.len(), 1 + whole + each);
        let f0 = &r.frequencies[0];
        let head = format!("{},{},,,", cell(&f0.frequency_hz), cell(&f0.omega_p));
        assert!(l[1].starts_with(&head), "{} against {head}", l[1]);
        let mine = &f0.per_observation[0];
        let head = format!(
            "{},{},transformer,survived,",
            cell(&f0.frequency_hz),
            cell(&f0.omega_p)
        );
        assert_eq!(mine.name, "transformer");
        assert!(l[1 + whole].starts_with(&head), "{}", l[1 + whole]);

        let doc = forensic_with(
            &[("loco, 1906", true), ("transformer", false)],
            vec![
                frequency(
                    1.0,
                    6.3,
                    vec![[0.5, 0.7], [0.9, 1.1]],
                    &[
                        ("loco, 1906", vec![[0.5, 3.0]]),
                        ("transformer", vec![[0.1, 0.7], [0.9, 1.1]]),
                    ],
                ),
                frequency(
                    2.0,
                    12.566,
                    vec![],
                    &[("loco, 1906", vec![]), ("transformer", vec![[0.1, 3.0]])],
                ),
            ],
        );
        let csv = csv_of(&doc);
        assert_eq!(
            lines(&csv)[1..],
            [
                "1.0,6.3,,,0.5,0.7",
                "1.0,6.3,,,0.9,1.1",
                "2.0,12.566,,,,",
                "1.0,6.3,\"loco, 1906\",overturned,0.5,3.0",
                "1.0,6.3,transformer,survived,0.1,0.7",
                "1.0,6.3,transformer,survived,0.9,1.1",
                "2.0,12.566,\"loco, 1906\",overturned,,",
                "2.0,12.566,transformer,survived,0.1,3.0",
            ]
        );
    }

    #[test]
    fn user_text_in_a_table_cannot_be_a_spreadsheet_formula() {
        // In a forensic table the name is text; the numbers stay numbers.
        let evil = "=HYPERLINK(\"http://evil\",\"x\")";
        let doc = forensic_with(
            &[(evil, true)],
            vec![frequency(
                1.0,
                6.3,
                vec![[-0.5, 0.7]],
                &[(evil, vec![[-0.5, 3.0]])],
            )],
        );
        let csv = csv_of(&doc);
        let l = lines(&csv);
        assert_eq!(l[1], "1.0,6.3,,,-0.5,0.7");
        assert_eq!(
            l[2],
            "1.0,6.3,\"'=HYPERLINK(\"\"http://evil\"\",\"\"x\"\")\",overturned,-0.5,3.0"
        );
    }
}
