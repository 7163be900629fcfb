//! The table of a time history's series read row by row from the stored
//! document, without parsing it whole: the same bytes as
//! [`to_csv`](super::to_csv), in pieces, holding only the document and the
//! piece at hand.

use serde::{Serialize, Serializer};
use serde_json::Value;
use serde_json::value::RawValue;

use crate::kinds::time_history::table::SeriesRow;
use crate::table::number::Number;
use crate::table::text::Text;
use crate::table::{Table, TableError};

/// A series table being read from a stored document.
///
/// It keeps, per column present, the offset in the document of the column's
/// next sample; each sample is parsed on its own and written as
/// [`to_csv`](super::to_csv) writes it.
#[derive(Clone, Debug)]
pub struct SeriesRows {
    /// Whether the header was written.
    begun: bool,
    /// Per column that can be streamed (t, θ, θ̇, ü_g, f_x/f_z): `None` when
    /// the table has no such column; else where its next sample starts
    /// (`None`: ended).
    next: [Option<Option<usize>>; 5],
}

/// The parts of a result document that decide its table; the rest (a
/// record in the spec, say) is skipped without being kept.
#[derive(serde::Deserialize)]
struct Head<'a> {
    #[serde(borrow)]
    kind: Option<&'a str>,
    #[serde(borrow)]
    series: Option<&'a RawValue>,
}

/// The columns of a series, as text.
#[derive(serde::Deserialize)]
struct Columns<'a> {
    #[serde(borrow)]
    t: Option<&'a RawValue>,
    #[serde(borrow)]
    theta: Option<&'a RawValue>,
    #[serde(borrow)]
    theta_dot: Option<&'a RawValue>,
    #[serde(borrow)]
    ground_acceleration: Option<&'a RawValue>,
    #[serde(borrow)]
    fx_over_fz: Option<&'a RawValue>,
    #[serde(borrow)]
    ground_vertical_acceleration: Option<&'a RawValue>,
    #[serde(borrow)]
    slide_m: Option<&'a RawValue>,
}

/// JSON's whitespace.
const WS: [char; 4] = [' ', '\t', '\n', '\r'];

impl SeriesRows {
    /// The series table of result document `text` when it is a time history
    /// with a series (`None` otherwise, or when the document is not one this
    /// reading is sure of: [`to_csv`](super::to_csv) renders those).
    pub fn of(text: &str) -> Option<SeriesRows> {
        let head: Head<'_> = serde_json::from_str(text).ok()?;
        if head.kind != Some("time_history") {
            return None;
        }
        let columns: Columns<'_> = serde_json::from_str(head.series?.get()).ok()?;
        // A vertical motion's column in g is worked out, not copied: such a
        // table is rendered whole.
        if columns.ground_vertical_acceleration.is_some() {
            return None;
        }
        // Nor is a Coulomb history's (its modes are text): rendered whole.
        if columns.slide_m.is_some() {
            return None;
        }
        let raw = [
            columns.t,
            columns.theta,
            columns.theta_dot,
            columns.ground_acceleration,
            columns.fx_over_fz,
        ];
        let mut next = [None; 5];
        for (raw, next) in raw.iter().zip(&mut next) {
            let Some(raw) = raw.map(RawValue::get) else {
                continue;
            };
            // The column's offset in the document (it is a slice of it).
            let at = (raw.as_ptr().addr()).checked_sub(text.as_ptr().addr())?;
            let inside = raw.strip_prefix('[')?;
            if !inside.trim_start_matches(WS).starts_with(']') {
                *next = Some(Some(at + 1));
            }
        }
        next.iter()
            .any(Option::is_some)
            .then_some(SeriesRows { begun: false, next })
    }

    /// Appends rows of document `text` (the one given to [`SeriesRows::of`])
    /// to `out` until it holds `min` bytes or the table ends; whether rows
    /// remain.
    pub fn fill(&mut self, text: &str, out: &mut String, min: usize) -> Result<bool, TableError> {
        let mut table = if self.begun {
            Table::headless()
        } else {
            Table::new()
        };
        let mut more = true;
        while out.len() + table.written()? < min {
            let [t, theta, theta_dot, ground, fx] = self
                .next
                .each_mut()
                .map(|column| column.as_mut().map(|at| Sample(next_sample(text, at))));
            if [&t, &theta, &theta_dot, &ground, &fx]
                .iter()
                .all(|s| s.as_ref().is_none_or(|s| s.0.is_none()))
            {
                more = false;
                break;
            }
            table.row(SeriesRow {
                t_s: t,
                theta_rad: theta,
                theta_dot_rad_per_s: theta_dot,
                ground_acceleration_m_per_s2: ground,
                fx_over_fz: fx,
                ground_vertical_acceleration_m_per_s2: None,
                ug_v_g: None,
                slide_m: None,
                mode: None,
            })?;
            self.begun = true;
        }
        out.push_str(&table.finish()?);
        Ok(more && self.next.iter().flatten().any(Option::is_some))
    }
}

/// A sample as the stored document holds it, as a cell: a number through
/// [`Number`] (an integer as stored is the double the typed result reads),
/// text through [`Text`]; null, or none past the column's end, empty.
struct Sample(Option<Value>);

impl Serialize for Sample {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match &self.0 {
            Some(Value::Null) | None => serializer.serialize_none(),
            Some(Value::Number(n)) => match n.as_f64() {
                Some(x) => Number(x).serialize(serializer),
                None => serializer.serialize_none(),
            },
            Some(Value::String(s)) => Text(s).serialize(serializer),
            Some(x) => serializer.serialize_str(&x.to_string()),
        }
    }
}

/// The array element of `text` at or after `at` (just past the `[` or the
/// previous element), moving `at` past it; `None`, and `at` cleared, at the
/// array's end.
fn next_sample(text: &str, at: &mut Option<usize>) -> Option<Value> {
    let rest = text.get((*at)?..)?.trim_start_matches(WS);
    let rest = rest
        .strip_prefix(',')
        .unwrap_or(rest)
        .trim_start_matches(WS);
    if rest.starts_with(']') {
        *at = None;
        return None;
    }
    let start = text.len() - rest.len();
    let mut values = serde_json::Deserializer::from_str(rest).into_iter::<Value>();
    match values.next() {
        Some(Ok(v)) => {
            *at = Some(start + values.byte_offset());
            Some(v)
        }
        _ => {
            *at = None;
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::super::tests::{th_table, time_history_result};
    use super::*;
    use crate::kinds::time_history::SeriesDoc;

    /// The table [`SeriesRows`] writes for `text`, in pieces of `piece` bytes.
    fn streamed(text: &str, piece: usize) -> Option<String> {
        let mut rows = SeriesRows::of(text)?;
        let mut out = String::new();
        let mut pieces = 0;
        loop {
            let mut chunk = String::new();
            let more = rows.fill(text, &mut chunk, piece).expect("rows");
            out.push_str(&chunk);
            pieces += 1;
            assert!(pieces < 100_000, "no end");
            if !more {
                return Some(out);
            }
        }
    }

    #[test]
    fn series_read_row_by_row_are_the_whole_table() {
        let computed = time_history_result();
        let mut odd = computed.clone();
        // Columns of different lengths, one empty, odd numbers, and samples
        // JSON cannot hold (written null).
        odd.series = Some(SeriesDoc {
            t: vec![
                0.0,
                1e-300,
                -0.0,
                1.7976931348623157e308,
                12345678901234567890.0,
                0.7999999999999999,
            ],
            theta: vec![],
            theta_dot: vec![-5.0, 0.30000000000000004],
            ground_acceleration: vec![f64::NAN],
            ground_vertical_acceleration: None,
            fx_over_fz: Some(vec![Some(f64::INFINITY), None, Some(0.3)]),
            slide_m: None,
            mode: None,
        });
        assert_eq!(
            th_table(&odd),
            "t_s,theta_dot_rad_per_s,ground_acceleration_m_per_s2,fx_over_fz\n\
             0.0,-5.0,,\n\
             1e-300,0.3,,\n\
             -0.0,,,0.3\n\
             1.7976931348623157e+308,,,\n\
             1.23456789012346e+19,,,\n\
             0.8,,,\n"
        );
        let mut no_ratio = computed.clone();
        if let Some(s) = &mut no_ratio.series {
            s.fx_over_fz = None;
        }
        for r in [computed, odd, no_ratio] {
            let whole = th_table(&r);
            for text in [
                serde_json::to_string(&r).expect("json"),
                serde_json::to_string_pretty(&r).expect("json"),
            ] {
                for piece in [1, 7, 64, 1 << 16] {
                    assert_eq!(
                        streamed(&text, piece).as_deref(),
                        Some(whole.as_str()),
                        "{text}"
                    );
                }
            }
        }
        // A long series, as a result holds it.
        let mut long = time_history_result();
        let n = 20_000;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 0.0005).collect();
        let theta: Vec<f64> = t.iter().map(|t| (t * 7.0).sin() * 1e-3).collect();
        let ratio: Vec<Option<f64>> = t.iter().map(|t| (*t < 5.0).then_some(t / 3.0)).collect();
        long.series = Some(SeriesDoc {
            t: t.clone(),
            theta: theta.clone(),
            theta_dot: theta,
            ground_acceleration: t,
            ground_vertical_acceleration: None,
            fx_over_fz: Some(ratio),
            slide_m: None,
            mode: None,
        });
        let whole = th_table(&long);
        assert_eq!(whole.lines().count(), n + 1);
        let text = serde_json::to_string(&long).expect("json");
        assert_eq!(streamed(&text, 1 << 16).as_deref(), Some(whole.as_str()));
    }

    #[test]
    fn series_are_read_from_any_stored_document() {
        // Integers as stored, a key order other than the engine's, a null:
        // every number is written as the double a typed result reads, to 15
        // digits.
        let text = r#"{"series": {"t": [0.0, 12345678901234567890], "theta": [],
            "theta_dot": [-5, 0.30000000000000004], "ground_acceleration": [null]},
            "kind": "time_history"}"#;
        let table = "t_s,theta_dot_rad_per_s,ground_acceleration_m_per_s2\n\
                     0.0,-5.0,\n\
                     1.23456789012346e+19,0.3,\n";
        for piece in [1, 7, 1 << 16] {
            assert_eq!(streamed(text, piece).as_deref(), Some(table));
        }
    }

    #[test]
    fn other_tables_are_left_to_the_whole_document() {
        for doc in [
            json!({"kind": "time_history", "impacts": [{"t": 1.0}]}),
            json!({"kind": "time_history", "series": null, "impacts": []}),
            json!({"kind": "time_history", "series": {"t": [], "theta": 3}}),
            json!({"kind": "time_history", "series": [1, 2]}),
            json!({"kind": "spectrum", "series": {"t": [1.0]}}),
        ] {
            assert!(SeriesRows::of(&doc.to_string()).is_none(), "{doc}");
        }
        // An escaped kind, or a repeated key: the whole document decides.
        for text in [
            r#"{"kind":"time_\u0068istory","series":{"t":[1.0]}}"#,
            r#"{"kind":"time_history","series":{"t":[1.0]},"series":{"t":[2.0]}}"#,
        ] {
            assert!(SeriesRows::of(text).is_none(), "{text}");
        }
    }
}
