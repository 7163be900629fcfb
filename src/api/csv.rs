//! CSV renderings of result documents (`?format=csv`, `topple run --format
//! csv`). Every header names its quantity and unit: `_s` seconds, `_rad`,
//! `_rad_per_s`, `_m_per_s2`, `_hz`, `_g` (multiples of g), `_alpha_g`
//! (multiples of α g); ratios without a suffix are dimensionless.

use std::fmt::Write;

use serde_json::Value;

use crate::jobs::{JobKind, JobResult};

/// One CSV field: numbers as JSON writes them, text quoted when it needs to be.
fn f(v: Option<&Value>) -> String {
    match v {
        Some(Value::Null) | None => String::new(),
        Some(Value::String(s)) => quote(s),
        Some(x) => x.to_string(),
    }
}

/// `s` as a CSV field (RFC 4180), safe to open in a spreadsheet: text
/// starting with `=`, `+`, `-`, `@`, a tab or a carriage return would be read
/// as a formula, so it gets a leading `'` and quotes (OWASP's rule for CSV
/// injection). Only user text goes through here; numbers are written as they
/// are.
fn quote(s: &str) -> String {
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("\"'{}\"", s.replace('"', "\"\""))
    } else if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn row(out: &mut String, fields: &[String]) {
    let _ = writeln!(out, "{}", fields.join(","));
}

fn array<'a>(v: &'a Value, key: &str) -> &'a [Value] {
    v.get(key)
        .and_then(Value::as_array)
        .map(Vec::as_slice)
        .unwrap_or_default()
}

/// The CSV table of a result.
pub fn to_csv(result: &JobResult) -> String {
    to_csv_doc(&crate::plot::document(result)).unwrap_or_default()
}

/// The CSV table of a result document (being replaced by [`to_csv`]).
pub(crate) fn to_csv_doc(result: &Value) -> Result<String, String> {
    let mut out = String::new();
    let name = result.get("kind").and_then(Value::as_str);
    let Some(kind) = name.and_then(JobKind::from_name) else {
        return Err(format!("no CSV form for results of kind {name:?}"));
    };
    // Every kind has a table: the match is exhaustive.
    match kind {
        JobKind::TimeHistory => time_history(result, &mut out),
        JobKind::Spectrum => spectrum(result, &mut out),
        JobKind::FrictionSpectrum => friction(result, &mut out),
        JobKind::Forensic
            if result.get("excitation").and_then(Value::as_str) == Some("ground_motion") =>
        {
            forensic_record(result, &mut out)
        }
        JobKind::Forensic => forensic(result, &mut out),
        JobKind::RecordSpectrum => record_spectrum(result, &mut out),
        JobKind::Survival => survival(result, &mut out),
        JobKind::Fragility => fragility(result, &mut out),
    }
    Ok(out)
}

/// The columns of a time history's series: (key, header).
const SERIES_COLUMNS: [(&str, &str); 5] = [
    ("t", "t_s"),
    ("theta", "theta_rad"),
    ("theta_dot", "theta_dot_rad_per_s"),
    ("ground_acceleration", "ground_acceleration_m_per_s2"),
    ("fx_over_fz", "fx_over_fz"),
];

/// The series when there is one; else the impacts; else a one-row summary.
fn time_history(result: &Value, out: &mut String) {
    if let Some(s) = result.get("series") {
        let cols = SERIES_COLUMNS;
        let data: Vec<&[Value]> = cols.iter().map(|(key, _)| array(s, key)).collect();
        let present: Vec<usize> = (0..cols.len()).filter(|&i| !data[i].is_empty()).collect();
        if !present.is_empty() {
            row(
                out,
                &present
                    .iter()
                    .map(|&i| cols[i].1.to_string())
                    .collect::<Vec<_>>(),
            );
            let rows = present.iter().map(|&i| data[i].len()).max().unwrap_or(0);
            for r in 0..rows {
                let line: Vec<String> = present.iter().map(|&i| f(data[i].get(r))).collect();
                row(out, &line);
            }
            return;
        }
    }
    let impacts = array(result, "impacts");
    if !impacts.is_empty() {
        row(
            out,
            &[
                "impact".into(),
                "t_s".into(),
                "theta_dot_before_rad_per_s".into(),
                "theta_dot_after_rad_per_s".into(),
            ],
        );
        for (k, i) in impacts.iter().enumerate() {
            row(
                out,
                &[
                    (k + 1).to_string(),
                    f(i.get("t")),
                    f(i.get("theta_dot_before")),
                    f(i.get("theta_dot_after")),
                ],
            );
        }
        return;
    }
    let cols = [
        ("rocked", "rocked"),
        ("overturned", "overturned"),
        ("mode", "mode"),
        ("impact_count", "impact_count"),
        ("rocking_start", "rocking_start_s"),
        ("overturn_time", "overturn_time_s"),
        ("rest_time", "rest_time_s"),
        ("end_time", "end_time_s"),
        ("peak_theta_over_alpha", "peak_theta_over_alpha"),
        ("peak_friction_demand", "peak_friction_demand"),
        ("initiation_friction_demand", "initiation_friction_demand"),
        ("lift_off", "lift_off"),
        ("lift_off_time", "lift_off_time_s"),
    ];
    row(out, &cols.map(|c| c.1.to_string()));
    row(out, &cols.map(|c| f(result.get(c.0))));
}

/// One row per transition (a frequency without any: one row, transition
/// fields empty).
fn spectrum(result: &Value, out: &mut String) {
    row(
        out,
        &[
            "omega_ratio",
            "a_alpha_g",
            "direction",
            "mode",
            "impacts",
            "bracket_lo_alpha_g",
            "bracket_hi_alpha_g",
            "min_overturn_alpha_g",
            "eq21_alpha_g",
            "threshold_alpha_g",
            "closed_form_mode2_alpha_g",
        ]
        .map(String::from),
    );
    for line in array(result, "spectrum") {
        let tail = [
            f(line.get("min_overturn_alpha_g")),
            f(line.get("eq21_alpha_g")),
            f(line.get("threshold_alpha_g")),
            f(line.get("closed_form_mode2_alpha_g")),
        ];
        let head = [f(line.get("omega_ratio"))];
        transition_rows(out, line, &head, &["a_alpha_g"], &tail);
    }
}

/// A row per transition of `line` — `head`, the transition's `levels`,
/// direction, mode, impacts and bracket, then `tail` — or one row with those
/// cells empty when it has none.
fn transition_rows(
    out: &mut String,
    line: &Value,
    head: &[String],
    levels: &[&str],
    tail: &[String],
) {
    let ts = array(line, "transitions");
    if ts.is_empty() {
        let mut fields = head.to_vec();
        fields.extend(std::iter::repeat_n(String::new(), levels.len() + 5));
        fields.extend(tail.iter().cloned());
        row(out, &fields);
    }
    for t in ts {
        let b = t.get("bracket").and_then(Value::as_array);
        let mut fields = head.to_vec();
        fields.extend(levels.iter().map(|k| f(t.get(*k))));
        fields.extend([
            f(t.get("direction")),
            f(t.get("mode")),
            f(t.get("impacts")),
            f(b.and_then(|b| b.first())),
            f(b.and_then(|b| b.get(1))),
        ]);
        fields.extend(tail.iter().cloned());
        row(out, &fields);
    }
}

/// One row per transition of each block size (one empty row for a size
/// without any), with the size's minimum and rocking threshold.
fn record_spectrum(result: &Value, out: &mut String) {
    row(
        out,
        &[
            "p_rad_s",
            "R_m",
            "scale",
            "pga_g",
            "direction",
            "mode",
            "impacts",
            "bracket_lo_scale",
            "bracket_hi_scale",
            "min_overturn_scale",
            "min_overturn_pga_g",
            "threshold_scale",
        ]
        .map(String::from),
    );
    for line in array(result, "spectrum") {
        let head = [f(line.get("p")), f(line.get("R_m"))];
        let tail = [
            f(line.get("min_overturn_scale")),
            f(line.get("min_overturn_pga_g")),
            f(line.get("threshold_scale")),
        ];
        transition_rows(out, line, &head, &["scale", "pga_g"], &tail);
    }
}

fn friction(result: &Value, out: &mut String) {
    let cols = [
        ("a_alpha_g", "a_alpha_g"),
        ("peak_friction_demand", "peak_friction_demand"),
        ("peak_over_tan_alpha", "peak_over_tan_alpha"),
        ("initiation_friction_demand", "initiation_friction_demand"),
        ("overturned", "overturned"),
        ("mode", "mode"),
        ("lift_off", "lift_off"),
        ("lift_off_time", "lift_off_time_s"),
        (
            "friction_demand_followed_until",
            "friction_demand_followed_until_s",
        ),
    ];
    row(out, &cols.map(|c| c.1.to_string()));
    for p in array(result, "points") {
        row(out, &cols.map(|c| f(p.get(c.0))));
    }
}

/// One row per frequency and interval of amplitudes consistent with every
/// observation (`observation` empty), then the same per observation; a
/// frequency with no consistent amplitude has one row with the interval empty.
fn forensic(result: &Value, out: &mut String) {
    row(
        out,
        &[
            "frequency_hz",
            "omega_p_rad_per_s",
            "observation",
            "observed",
            "consistent_lo_g",
            "consistent_hi_g",
        ]
        .map(String::from),
    );
    let observed = |name: &str| -> String {
        array(result, "observations")
            .iter()
            .find(|o| o.get("name").and_then(Value::as_str) == Some(name))
            .and_then(|o| o.get("overturned").and_then(Value::as_bool))
            .map_or(String::new(), |o| {
                if o { "overturned" } else { "survived" }.into()
            })
    };
    let frequencies = array(result, "frequencies");
    let mut emit = |freq: &Value, name: &str, seen: String, set: &[Value]| {
        let head = [f(freq.get("frequency_hz")), f(freq.get("omega_p"))];
        let intervals: Vec<(String, String)> = set
            .iter()
            .filter_map(|i| {
                let i = i.as_array()?;
                Some((f(i.first()), f(i.get(1))))
            })
            .collect();
        if intervals.is_empty() {
            row(
                out,
                &[
                    head[0].clone(),
                    head[1].clone(),
                    quote(name),
                    seen.clone(),
                    String::new(),
                    String::new(),
                ],
            );
        }
        for (lo, hi) in intervals {
            row(
                out,
                &[
                    head[0].clone(),
                    head[1].clone(),
                    quote(name),
                    seen.clone(),
                    lo,
                    hi,
                ],
            );
        }
    };
    for freq in frequencies {
        emit(freq, "", String::new(), array(freq, "consistent_g"));
    }
    for freq in frequencies {
        for o in array(freq, "per_observation") {
            let name = o.get("name").and_then(Value::as_str).unwrap_or("");
            emit(freq, name, observed(name), array(o, "consistent_g"));
        }
    }
}

/// A fragility: a row per stripe (intensity in the result's `im`).
fn fragility(result: &Value, out: &mut String) {
    let im = match result.get("im").and_then(Value::as_str) {
        Some("pgv_m_s") => "pgv_m_s",
        _ => "pga_g",
    };
    row(
        out,
        &[
            im,
            "n",
            "overturned",
            "p",
            "p_lo_95",
            "p_hi_95",
            "mode_1",
            "mode_2",
        ]
        .map(String::from),
    );
    for s in array(result, "stripes") {
        let interval = s.get("interval_95");
        row(
            out,
            &[
                f(s.get("im")),
                f(s.get("n")),
                f(s.get("overturned")),
                f(s.get("p")),
                f(interval.and_then(|i| i.get(0))),
                f(interval.and_then(|i| i.get(1))),
                f(s.get("mode_1")),
                f(s.get("mode_2")),
            ],
        );
    }
}

/// A survival result: a row per rock and age (an uncertain age: its median,
/// marked), then the joint probability of several rocks (rock "all").
fn survival(result: &Value, out: &mut String) {
    row(
        out,
        &[
            "rock",
            "annual_toppling_rate_per_yr",
            "age_years",
            "age_uncertain",
            "survival_probability",
            "rate_scale_at_5_percent",
        ]
        .map(String::from),
    );
    for r in array(result, "rocks") {
        let name = quote(r.get("name").and_then(Value::as_str).unwrap_or(""));
        let rate = f(r.get("annual_toppling_rate"));
        for a in array(r, "ages") {
            row(
                out,
                &[
                    name.clone(),
                    rate.clone(),
                    f(a.get("age_years")),
                    "false".into(),
                    f(a.get("survival_probability")),
                    f(a.get("rate_scale_at_5_percent")),
                ],
            );
        }
        if let Some(d) = r.get("age_distribution") {
            row(
                out,
                &[
                    name.clone(),
                    rate.clone(),
                    f(d.get("median_age_years")),
                    "true".into(),
                    f(d.get("survival_probability")),
                    f(d.get("rate_scale_at_5_percent")),
                ],
            );
        }
    }
    if let Some(j) = result.get("joint") {
        row(
            out,
            &[
                "all".into(),
                String::new(),
                String::new(),
                String::new(),
                f(j.get("survival_probability")),
                f(j.get("rate_scale_at_5_percent")),
            ],
        );
    }
}

/// A record query: a row per consistent interval, first those consistent
/// with every observation (observation empty), then each observation's; an
/// observation that allows nothing has one row with empty ends.
fn forensic_record(result: &Value, out: &mut String) {
    row(
        out,
        &[
            "observation",
            "observed",
            "consistent_lo_scale",
            "consistent_hi_scale",
            "consistent_lo_pga_g",
            "consistent_hi_pga_g",
        ]
        .map(String::from),
    );
    let mut emit = |name: &str, seen: String, scale: &[Value], pga: &[Value]| {
        if scale.is_empty() {
            row(
                out,
                &[
                    quote(name),
                    seen.clone(),
                    String::new(),
                    String::new(),
                    String::new(),
                    String::new(),
                ],
            );
        }
        for (s, g) in scale.iter().zip(pga) {
            row(
                out,
                &[
                    quote(name),
                    seen.clone(),
                    f(s.get(0)),
                    f(s.get(1)),
                    f(g.get(0)),
                    f(g.get(1)),
                ],
            );
        }
    };
    emit(
        "",
        String::new(),
        array(result, "consistent_scale"),
        array(result, "consistent_pga_g"),
    );
    for o in array(result, "per_observation") {
        let seen = match o.get("overturned").and_then(Value::as_bool) {
            Some(true) => "overturned",
            Some(false) => "survived",
            None => "",
        };
        emit(
            o.get("name").and_then(Value::as_str).unwrap_or(""),
            seen.into(),
            array(o, "consistent_scale"),
            array(o, "consistent_pga_g"),
        );
    }
}

/// The table of a time history's series read row by row from the stored
/// document, without parsing it whole: the same bytes as [`to_csv`], in
/// pieces, holding only the document and the piece at hand.
///
/// It keeps, per column present, the offset in the document of the column's
/// next sample; each sample is parsed on its own and written as [`to_csv`]
/// writes it.
#[derive(Clone, Debug)]
pub struct SeriesRows {
    /// The header row, until written.
    header: Option<String>,
    /// Per column present: where its next sample starts (`None`: ended).
    next: Vec<Option<usize>>,
}

/// The parts of a result document that decide its table; the rest (a
/// record in the spec, say) is skipped without being kept.
#[derive(serde::Deserialize)]
struct Head<'a> {
    #[serde(borrow)]
    kind: Option<&'a str>,
    #[serde(borrow)]
    series: Option<&'a serde_json::value::RawValue>,
}

/// The columns of a series, as text.
#[derive(serde::Deserialize)]
struct Columns<'a> {
    #[serde(borrow)]
    t: Option<&'a serde_json::value::RawValue>,
    #[serde(borrow)]
    theta: Option<&'a serde_json::value::RawValue>,
    #[serde(borrow)]
    theta_dot: Option<&'a serde_json::value::RawValue>,
    #[serde(borrow)]
    ground_acceleration: Option<&'a serde_json::value::RawValue>,
    #[serde(borrow)]
    fx_over_fz: Option<&'a serde_json::value::RawValue>,
}

/// JSON's whitespace.
const WS: [char; 4] = [' ', '\t', '\n', '\r'];

impl SeriesRows {
    /// The series table of result document `text` when it is a time history
    /// with a series (`None` otherwise, or when the document is not one this
    /// reading is sure of: [`to_csv`] renders those).
    pub fn of(text: &str) -> Option<SeriesRows> {
        let head: Head<'_> = serde_json::from_str(text).ok()?;
        if head.kind != Some("time_history") {
            return None;
        }
        let columns: Columns<'_> = serde_json::from_str(head.series?.get()).ok()?;
        let raw = [
            columns.t,
            columns.theta,
            columns.theta_dot,
            columns.ground_acceleration,
            columns.fx_over_fz,
        ];
        let mut headers = Vec::new();
        let mut next = Vec::new();
        for (raw, (_, name)) in raw.iter().zip(SERIES_COLUMNS) {
            let Some(raw) = raw.map(|r| r.get()) else {
                continue;
            };
            // The column's offset in the document (it is a slice of it).
            let at = (raw.as_ptr().addr()).checked_sub(text.as_ptr().addr())?;
            let inside = raw.strip_prefix('[')?;
            if inside.trim_start_matches(WS).starts_with(']') {
                continue;
            }
            headers.push(name.to_string());
            next.push(Some(at + 1));
        }
        if next.is_empty() {
            return None;
        }
        let mut header = String::new();
        row(&mut header, &headers);
        Some(SeriesRows {
            header: Some(header),
            next,
        })
    }

    /// Appends rows of document `text` (the one given to [`SeriesRows::of`])
    /// to `out` until it holds `min` bytes or the table ends; whether rows
    /// remain.
    pub fn fill(&mut self, text: &str, out: &mut String, min: usize) -> bool {
        if let Some(header) = self.header.take() {
            out.push_str(&header);
        }
        let mut fields = Vec::with_capacity(self.next.len());
        while out.len() < min {
            fields.clear();
            let mut any = false;
            for at in &mut self.next {
                let sample = next_sample(text, at);
                any |= sample.is_some();
                fields.push(f(sample.as_ref()));
            }
            if !any {
                return false;
            }
            row(out, &fields);
        }
        self.next.iter().any(Option::is_some)
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
    use super::*;
    use serde_json::json;

    fn lines(csv: &str) -> Vec<&str> {
        csv.lines().collect()
    }

    #[test]
    fn time_history_series_with_units() {
        let doc = json!({"kind": "time_history", "series": {
            "t": [0.0, 0.1, 0.2], "theta": [0.0, -0.01, -0.02], "theta_dot": [0.0, -0.1, -0.2],
            "ground_acceleration": [0.0, 1.0, 2.0], "fx_over_fz": [0.0, 0.25, 0.3]}});
        let csv = to_csv_doc(&doc).expect("csv");
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2,fx_over_fz"
        );
        assert_eq!(l.len(), 4);
        assert_eq!(l[2], "0.1,-0.01,-0.1,1.0,0.25");
        // Without reactions the ratio column is left out.
        let mut doc = doc;
        doc["series"]
            .as_object_mut()
            .map(|s| s.remove("fx_over_fz"));
        let csv = to_csv_doc(&doc).expect("csv");
        assert!(
            csv.starts_with("t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2\n")
        );
    }

    #[test]
    fn time_history_without_series_gives_impacts_then_a_summary() {
        let doc = json!({"kind": "time_history", "overturned": false, "mode": null,
            "impacts": [{"t": 1.5, "theta_dot_before": 0.5, "theta_dot_after": -0.45}],
            "impact_count": 1, "end_time": 9.0});
        let csv = to_csv_doc(&doc).expect("csv");
        assert_eq!(
            lines(&csv),
            vec![
                "impact,t_s,theta_dot_before_rad_per_s,theta_dot_after_rad_per_s",
                "1,1.5,0.5,-0.45"
            ]
        );
        let doc = json!({"kind": "time_history", "rocked": false, "overturned": false,
            "impact_count": 0, "end_time": 1.0, "peak_theta_over_alpha": 0.0});
        let csv = to_csv_doc(&doc).expect("csv");
        let l = lines(&csv);
        assert_eq!(l.len(), 2);
        assert!(l[0].starts_with("rocked,overturned,mode,impact_count,rocking_start_s,"));
        assert!(l[1].starts_with("false,false,,0,,,,1.0,0.0"), "{}", l[1]);
    }

    #[test]
    fn spectrum_rows_per_transition() {
        let doc = json!({"kind": "spectrum", "spectrum": [
            {"omega_ratio": 2.0, "threshold_alpha_g": 1.0, "min_overturn_alpha_g": 1.25, "eq21_alpha_g": 1.33,
             "closed_form_mode2_alpha_g": null,
             "transitions": [{"a_alpha_g": 1.25, "direction": "up", "mode": 1, "impacts": 1, "bracket": [1.2499, 1.2501]},
                             {"a_alpha_g": 2.37, "direction": "down", "mode": 1, "impacts": 1, "bracket": [2.3699, 2.3701]}]},
            {"omega_ratio": 10.0, "threshold_alpha_g": 1.0, "min_overturn_alpha_g": null, "eq21_alpha_g": 2.67,
             "transitions": []}]});
        let csv = to_csv_doc(&doc).expect("csv");
        let l = lines(&csv);
        assert!(
            l[0].starts_with("omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo_alpha_g")
        );
        assert_eq!(l.len(), 4);
        assert_eq!(l[1], "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,");
        assert_eq!(l[3], "10.0,,,,,,,,2.67,1.0,");
    }

    #[test]
    fn friction_rows_per_amplitude() {
        let doc = json!({"kind": "friction_spectrum", "points": [
            {"a_alpha_g": 1.1, "peak_friction_demand": 0.26, "peak_over_tan_alpha": 1.02,
             "initiation_friction_demand": 0.255, "overturned": false, "mode": null,
             "lift_off": false, "lift_off_time": null},
            {"a_alpha_g": 6.0, "peak_friction_demand": null, "peak_over_tan_alpha": null,
             "initiation_friction_demand": 0.51, "overturned": true, "mode": 2,
             "lift_off": true, "lift_off_time": 0.41}]});
        let csv = to_csv_doc(&doc).expect("csv");
        assert_eq!(
            lines(&csv),
            vec![
                "a_alpha_g,peak_friction_demand,peak_over_tan_alpha,initiation_friction_demand,overturned,mode,lift_off,lift_off_time_s,friction_demand_followed_until_s",
                "1.1,0.26,1.02,0.255,false,,false,,",
                "6.0,,,0.51,true,2,true,0.41,"
            ]
        );
    }

    #[test]
    fn fragility_rows_per_stripe() {
        let doc = json!({"kind": "fragility", "im": "pga_g", "stripes": [
            {"im": 0.3, "n": 200, "overturned": 58, "p": 0.29, "interval_95": [0.23, 0.35],
             "mode_1": 58, "mode_2": 0}]});
        let csv = to_csv_doc(&doc).expect("csv");
        assert_eq!(
            csv.lines().collect::<Vec<_>>(),
            vec![
                "pga_g,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2",
                "0.3,200,58,0.29,0.23,0.35,58,0",
            ]
        );
    }

    #[test]
    fn survival_rows_per_rock_and_age_then_the_joint() {
        let doc = json!({"kind": "survival", "rocks": [
            {"name": "Grass Valley", "annual_toppling_rate": 1.5e-4,
             "ages": [{"age_years": 1000.0, "survival_probability": 0.86, "rate_scale_at_5_percent": 20.0}]},
            {"name": "b", "annual_toppling_rate": 1e-4, "ages": [],
             "age_distribution": {"median_age_years": 9000.0, "survival_probability": 0.4,
                                  "rate_scale_at_5_percent": null}}],
            "joint": {"survival_probability": 0.344, "rate_scale_at_5_percent": 2.5}});
        let csv = to_csv_doc(&doc).expect("csv");
        assert_eq!(
            csv.lines().collect::<Vec<_>>(),
            vec![
                "rock,annual_toppling_rate_per_yr,age_years,age_uncertain,survival_probability,rate_scale_at_5_percent",
                "Grass Valley,0.00015,1000.0,false,0.86,20.0",
                "b,0.0001,9000.0,true,0.4,",
                "all,,,,0.344,2.5",
            ]
        );
    }

    #[test]
    fn a_record_querys_rows_per_interval_and_observation() {
        let doc = json!({"kind": "forensic", "excitation": "ground_motion",
            "consistent_scale": [[0.7, 1.4], [2.8, 3.2]],
            "consistent_pga_g": [[0.35, 0.7], [1.4, 1.6]],
            "per_observation": [
                {"name": "locomotive", "overturned": true,
                 "consistent_scale": [[0.7, 6.0]], "consistent_pga_g": [[0.35, 3.0]]},
                {"name": "=cmd", "overturned": false,
                 "consistent_scale": [], "consistent_pga_g": []}]});
        let csv = to_csv_doc(&doc).expect("csv");
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines,
            vec![
                "observation,observed,consistent_lo_scale,consistent_hi_scale,consistent_lo_pga_g,consistent_hi_pga_g",
                ",,0.7,1.4,0.35,0.7",
                ",,2.8,3.2,1.4,1.6",
                "locomotive,overturned,0.7,6.0,0.35,3.0",
                "\"'=cmd\",survived,,,,",
            ]
        );
    }

    #[test]
    fn forensic_rows_per_frequency_interval_and_observation() {
        let doc = json!({"kind": "forensic",
            "observations": [{"name": "loco, 1906", "overturned": true}, {"name": "transformer", "overturned": false}],
            "frequencies": [
                {"frequency_hz": 1.0, "omega_p": 6.3, "consistent_g": [[0.5, 0.7], [0.9, 1.1]],
                 "per_observation": [{"name": "loco, 1906", "consistent_g": [[0.5, 3.0]]},
                                     {"name": "transformer", "consistent_g": [[0.1, 0.7], [0.9, 1.1]]}]},
                {"frequency_hz": 2.0, "omega_p": 12.566, "consistent_g": [],
                 "per_observation": [{"name": "loco, 1906", "consistent_g": []},
                                     {"name": "transformer", "consistent_g": [[0.1, 3.0]]}]}]});
        let csv = to_csv_doc(&doc).expect("csv");
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "frequency_hz,omega_p_rad_per_s,observation,observed,consistent_lo_g,consistent_hi_g"
        );
        assert_eq!(l[1], "1.0,6.3,,,0.5,0.7");
        assert_eq!(l[3], "2.0,12.566,,,,");
        assert_eq!(l[4], "1.0,6.3,\"loco, 1906\",overturned,0.5,3.0");
        assert_eq!(l[5], "1.0,6.3,transformer,survived,0.1,0.7");
        // 3 rows for the intersection, 3 + 2 per observation.
        assert_eq!(l.len(), 1 + 3 + 5);
    }

    #[test]
    fn user_text_cannot_be_a_spreadsheet_formula() {
        for (name, cell) in [
            (
                "=HYPERLINK(\"http://evil\",\"x\")",
                "\"'=HYPERLINK(\"\"http://evil\"\",\"\"x\"\")\"",
            ),
            ("+1+2", "\"'+1+2\""),
            ("-2+3", "\"'-2+3\""),
            ("@SUM(A1)", "\"'@SUM(A1)\""),
            ("\t=1", "\"'\t=1\""),
            ("\r=1", "\"'\r=1\""),
            ("a=1", "a=1"),
            ("loco, 1906", "\"loco, 1906\""),
        ] {
            assert_eq!(quote(name), cell, "{name:?}");
        }
        // In a forensic table the name is text; the numbers stay numbers.
        let doc = json!({"kind": "forensic",
            "observations": [{"name": "=HYPERLINK(\"http://evil\",\"x\")", "overturned": true}],
            "frequencies": [{"frequency_hz": 1.0, "omega_p": 6.3, "consistent_g": [[-0.5, 0.7]],
                "per_observation": [{"name": "=HYPERLINK(\"http://evil\",\"x\")",
                                     "consistent_g": [[-0.5, 3.0]]}]}]});
        let csv = to_csv_doc(&doc).expect("csv");
        let l = lines(&csv);
        assert_eq!(l[1], "1.0,6.3,,,-0.5,0.7");
        assert_eq!(
            l[2],
            "1.0,6.3,\"'=HYPERLINK(\"\"http://evil\"\",\"\"x\"\")\",overturned,-0.5,3.0"
        );
    }

    /// The table [`SeriesRows`] writes for `text`, in pieces of `piece` bytes.
    fn streamed(text: &str, piece: usize) -> Option<String> {
        let mut rows = SeriesRows::of(text)?;
        let mut out = String::new();
        let mut pieces = 0;
        loop {
            let mut chunk = String::new();
            let more = rows.fill(text, &mut chunk, piece);
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
        let docs = [
            json!({"kind": "time_history", "spec": {"acc": [1.0, 2.0]}, "series": {
                "t": [0.0, 0.1, 0.2], "theta": [0.0, -0.01, -0.02], "theta_dot": [0.0, -0.1, -0.2],
                "ground_acceleration": [0.0, 1.0, 2.0], "fx_over_fz": [0.0, null, 0.3]}}),
            // Columns of different lengths, one empty, one missing, odd numbers.
            json!({"kind": "time_history", "series": {
                "t": [0.0, 1e-300, -0.0, 1.7976931348623157e308, 12345678901234567890u64],
                "theta": [], "theta_dot": [-5, 0.30000000000000004],
                "ground_acceleration": [null]}, "impacts": []}),
            json!({"series": {"t": [1.0]}, "kind": "time_history"}),
        ];
        for doc in docs {
            let whole = to_csv_doc(&doc).expect("csv");
            for text in [
                serde_json::to_string(&doc).expect("json"),
                serde_json::to_string_pretty(&doc).expect("json"),
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
        let n = 20_000;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 0.0005).collect();
        let theta: Vec<f64> = t.iter().map(|t| (t * 7.0).sin() * 1e-3).collect();
        let ratio: Vec<Option<f64>> = t.iter().map(|t| (*t < 5.0).then_some(t / 3.0)).collect();
        let doc = json!({"kind": "time_history", "series": {"t": t, "theta": theta,
            "theta_dot": theta, "ground_acceleration": t, "fx_over_fz": ratio}});
        let whole = to_csv_doc(&doc).expect("csv");
        assert_eq!(whole.lines().count(), n + 1);
        let text = serde_json::to_string(&doc).expect("json");
        assert_eq!(streamed(&text, 1 << 16).as_deref(), Some(whole.as_str()));
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

    #[test]
    fn unknown_kinds_are_refused() {
        assert!(to_csv_doc(&json!({"kind": "teapot"})).is_err());
    }
}
