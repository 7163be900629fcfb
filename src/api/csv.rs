//! CSV renderings of result documents (`?format=csv`).

use std::fmt::Write;

fn f(v: Option<&serde_json::Value>) -> String {
    match v {
        Some(serde_json::Value::Null) | None => String::new(),
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(x) => x.to_string(),
    }
}

/// The CSV table of a result, or why there is none.
pub fn to_csv(result: &serde_json::Value) -> Result<String, String> {
    let mut out = String::new();
    match result.get("kind").and_then(|k| k.as_str()) {
        Some("time_history") => {
            let s = result.get("series").ok_or(
                "this result has no series: submit the job with \"outputs\": {\"series\": N}",
            )?;
            let cols = [
                "t",
                "theta",
                "theta_dot",
                "ground_acceleration",
                "fx_over_fz",
            ];
            let data: Vec<Vec<serde_json::Value>> = cols
                .iter()
                .map(|c| {
                    s.get(*c)
                        .and_then(|a| a.as_array())
                        .cloned()
                        .unwrap_or_default()
                })
                .collect();
            let present: Vec<usize> = (0..cols.len()).filter(|&i| !data[i].is_empty()).collect();
            let _ = writeln!(
                out,
                "{}",
                present
                    .iter()
                    .map(|&i| cols[i])
                    .collect::<Vec<_>>()
                    .join(",")
            );
            for row in 0..data[0].len() {
                let line: Vec<String> = present.iter().map(|&i| f(data[i].get(row))).collect();
                let _ = writeln!(out, "{}", line.join(","));
            }
        }
        Some("spectrum") => {
            let _ = writeln!(
                out,
                "omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo,bracket_hi,min_overturn_alpha_g,eq21_alpha_g"
            );
            for line in result
                .get("spectrum")
                .and_then(|s| s.as_array())
                .into_iter()
                .flatten()
            {
                let r = f(line.get("omega_ratio"));
                let min = f(line.get("min_overturn_alpha_g"));
                let eq21 = f(line.get("eq21_alpha_g"));
                let ts = line.get("transitions").and_then(|t| t.as_array());
                if ts.is_none_or(|t| t.is_empty()) {
                    let _ = writeln!(out, "{r},,,,,,,{min},{eq21}");
                }
                for t in ts.into_iter().flatten() {
                    let b = t.get("bracket").and_then(|b| b.as_array());
                    let _ = writeln!(
                        out,
                        "{r},{},{},{},{},{},{},{min},{eq21}",
                        f(t.get("a_alpha_g")),
                        f(t.get("direction")),
                        f(t.get("mode")),
                        f(t.get("impacts")),
                        f(b.and_then(|b| b.first())),
                        f(b.and_then(|b| b.get(1))),
                    );
                }
            }
        }
        Some("friction_spectrum") => {
            let cols = [
                "a_alpha_g",
                "peak_friction_demand",
                "peak_over_tan_alpha",
                "initiation_friction_demand",
                "overturned",
                "mode",
                "lift_off_time",
            ];
            let _ = writeln!(out, "{}", cols.join(","));
            for p in result
                .get("points")
                .and_then(|s| s.as_array())
                .into_iter()
                .flatten()
            {
                let line: Vec<String> = cols.iter().map(|c| f(p.get(*c))).collect();
                let _ = writeln!(out, "{}", line.join(","));
            }
        }
        other => return Err(format!("no CSV form for results of kind {other:?}")),
    }
    Ok(out)
}
