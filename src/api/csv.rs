//! CSV renderings of result documents (`?format=csv`, `topple run --format
//! csv`). Every header names its quantity and unit: `_s` seconds, `_rad`,
//! `_rad_per_s`, `_m_per_s2`, `_hz`, `_g` (multiples of g), `_alpha_g`
//! (multiples of α g); ratios without a suffix are dimensionless.

use std::fmt::Write;

use serde_json::Value;

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

/// The CSV table of a result, or why there is none.
pub fn to_csv(result: &Value) -> Result<String, String> {
    let mut out = String::new();
    match result.get("kind").and_then(Value::as_str) {
        Some("time_history") => time_history(result, &mut out),
        Some("spectrum") => spectrum(result, &mut out),
        Some("friction_spectrum") => friction(result, &mut out),
        Some("forensic") => forensic(result, &mut out),
        other => return Err(format!("no CSV form for results of kind {other:?}")),
    }
    Ok(out)
}

/// The series when there is one; else the impacts; else a one-row summary.
fn time_history(result: &Value, out: &mut String) {
    if let Some(s) = result.get("series") {
        let cols = [
            ("t", "t_s"),
            ("theta", "theta_rad"),
            ("theta_dot", "theta_dot_rad_per_s"),
            ("ground_acceleration", "ground_acceleration_m_per_s2"),
            ("fx_over_fz", "fx_over_fz"),
        ];
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
        let r = f(line.get("omega_ratio"));
        let ts = array(line, "transitions");
        if ts.is_empty() {
            let mut fields = vec![r.clone(); 1];
            fields.extend(std::iter::repeat_n(String::new(), 6));
            fields.extend(tail.iter().cloned());
            row(out, &fields);
        }
        for t in ts {
            let b = t.get("bracket").and_then(Value::as_array);
            let mut fields = vec![
                r.clone(),
                f(t.get("a_alpha_g")),
                f(t.get("direction")),
                f(t.get("mode")),
                f(t.get("impacts")),
                f(b.and_then(|b| b.first())),
                f(b.and_then(|b| b.get(1))),
            ];
            fields.extend(tail.iter().cloned());
            row(out, &fields);
        }
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
        let csv = to_csv(&doc).expect("csv");
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
        let csv = to_csv(&doc).expect("csv");
        assert!(
            csv.starts_with("t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2\n")
        );
    }

    #[test]
    fn time_history_without_series_gives_impacts_then_a_summary() {
        let doc = json!({"kind": "time_history", "overturned": false, "mode": null,
            "impacts": [{"t": 1.5, "theta_dot_before": 0.5, "theta_dot_after": -0.45}],
            "impact_count": 1, "end_time": 9.0});
        let csv = to_csv(&doc).expect("csv");
        assert_eq!(
            lines(&csv),
            vec![
                "impact,t_s,theta_dot_before_rad_per_s,theta_dot_after_rad_per_s",
                "1,1.5,0.5,-0.45"
            ]
        );
        let doc = json!({"kind": "time_history", "rocked": false, "overturned": false,
            "impact_count": 0, "end_time": 1.0, "peak_theta_over_alpha": 0.0});
        let csv = to_csv(&doc).expect("csv");
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
        let csv = to_csv(&doc).expect("csv");
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
        let csv = to_csv(&doc).expect("csv");
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
        let csv = to_csv(&doc).expect("csv");
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
        let csv = to_csv(&doc).expect("csv");
        let l = lines(&csv);
        assert_eq!(l[1], "1.0,6.3,,,-0.5,0.7");
        assert_eq!(
            l[2],
            "1.0,6.3,\"'=HYPERLINK(\"\"http://evil\"\",\"\"x\"\")\",overturned,-0.5,3.0"
        );
    }

    #[test]
    fn unknown_kinds_are_refused() {
        assert!(to_csv(&json!({"kind": "teapot"})).is_err());
    }
}
