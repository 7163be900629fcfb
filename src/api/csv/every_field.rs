//! Every row of every kind's table holds every number of the JSON objects
//! it is made of, and the values a user gave read as given.

use serde_json::Value;

use super::SIGNIFICANT_DIGITS;
use super::tests::{
    FORENSIC, FORENSIC_RECORD, FRAGILITY, FRICTION, RECORD_SPECTRUM, SPECTRUM, SURVIVAL,
    TIME_HISTORY, cell, csv_of, json_text, lines,
};
use crate::kinds::{JobKind, JobResult};
use crate::table::number::significant_digits;
use crate::table::text::quote;

/// The pointers of every scalar of `v` under `at`: objects are entered,
/// arrays are not (a list is the table's rows, or is left out of it).
fn scalar_fields(v: &Value, at: &str, out: &mut Vec<String>) {
    match v {
        Value::Object(fields) => {
            for (key, x) in fields {
                scalar_fields(x, &format!("{at}/{key}"), out);
            }
        }
        Value::Array(_) => {}
        _ => out.push(at.to_string()),
    }
}

/// Whether CSV field `field` holds JSON value `v` (absent: null): a number
/// to 15 significant digits (within half a unit of the 15th digit and
/// half an ulp of it).
fn holds(field: &str, v: Option<&Value>) -> bool {
    match v {
        None | Some(Value::Null) => field.is_empty(),
        Some(Value::Number(n)) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            significant_digits(field) <= SIGNIFICANT_DIGITS
                && field
                    .parse::<f64>()
                    .is_ok_and(|c| (c - x).abs() <= 5.2e-15 * x.abs())
        }
        Some(Value::Bool(b)) => field == b.to_string(),
        Some(Value::String(text)) => field == quote(text),
        Some(_) => false,
    }
}

/// Part of a row: the JSON object it is made of (`None`: its cells are
/// empty), the column of each of its fields (pointer, header), and the
/// fields that are not the row's (pointer prefixes).
struct Part<'a> {
    of: Option<&'a Value>,
    columns: &'a [(&'a str, &'a str)],
    not_the_rows: &'a [&'a str],
}

fn part<'a>(of: Option<&'a Value>, columns: &'a [(&'a str, &'a str)]) -> Part<'a> {
    Part {
        of,
        columns,
        not_the_rows: &[],
    }
}

/// Checks table `csv` row by row against the parts each row is made of:
/// every scalar field of a part has a column, holding the field's value;
/// every column is some part's, or one of `derived` (checked by the
/// kind's own test).
fn holds_every_field(csv: &str, rows: &[Vec<Part<'_>>], derived: &[&str]) {
    assert!(!csv.contains('"'), "names here have no commas: {csv}");
    let l = lines(csv);
    let header: Vec<&str> = l[0].split(',').collect();
    assert_eq!(l.len(), 1 + rows.len(), "{csv}");
    let mut covered: Vec<&str> = derived.to_vec();
    for (line, parts) in l[1..].iter().zip(rows) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), header.len(), "{line}");
        for part in parts {
            if let Some(v) = part.of {
                let mut fields = Vec::new();
                scalar_fields(v, "", &mut fields);
                for field in fields {
                    let ours = part.columns.iter().any(|c| c.0 == field)
                        || part.not_the_rows.iter().any(|p| field.starts_with(p));
                    assert!(ours, "{field} of {v} has no column in {}", l[0]);
                }
            }
            for &(pointer, name) in part.columns {
                let k = header.iter().position(|h| *h == name).expect(name);
                let value = part.of.and_then(|v| v.pointer(pointer));
                assert!(
                    holds(cells[k], value),
                    "{name}: {:?} for {value:?} in {line}",
                    cells[k]
                );
                covered.push(name);
            }
        }
    }
    for name in header {
        assert!(covered.contains(&name), "column {name} is nobody's");
    }
}

/// A spec's result as its document and its table.
fn document_and_table(spec: &str) -> (Value, String) {
    let doc = crate::plot::tests::computed(spec);
    let table = csv_of(&JobResult::from_value(doc.clone()).expect("typed"));
    (doc, table)
}

fn items(v: &Value) -> &[Value] {
    v.as_array().map_or(&[], Vec::as_slice)
}

/// Each item of `v` (one `None` when there is none): the rows of a list.
fn each_or_none(v: &Value) -> Vec<Option<&Value>> {
    let all: Vec<Option<&Value>> = items(v).iter().map(Some).collect();
    if all.is_empty() { vec![None] } else { all }
}

const SPECTRUM_LINE: &[(&str, &str)] = &[
    ("/omega_ratio", "omega_ratio"),
    ("/min_overturn_alpha_g", "min_overturn_alpha_g"),
    ("/eq21_alpha_g", "eq21_alpha_g"),
    ("/threshold_alpha_g", "threshold_alpha_g"),
    ("/closed_form_mode2_alpha_g", "closed_form_mode2_alpha_g"),
    ("/omega_p", "omega_p_rad_per_s"),
    ("/frequency_hz", "frequency_hz"),
    ("/threshold_g", "threshold_g"),
    ("/min_overturn_g", "min_overturn_g"),
    ("/min_overturn_m_s2", "min_overturn_m_per_s2"),
    ("/min_overturn_mode", "min_overturn_mode"),
    ("/overturns_above_alpha_g", "overturns_above_alpha_g"),
    ("/ground/pgv_over_pga_s", "pgv_over_pga_s"),
    ("/ground/pgd_over_pga_s2", "pgd_over_pga_s2"),
    (
        "/principal/min_overturn_alpha_g",
        "principal_min_overturn_alpha_g",
    ),
    (
        "/principal/min_overturn_mode",
        "principal_min_overturn_mode",
    ),
    (
        "/principal/overturns_above_alpha_g",
        "principal_overturns_above_alpha_g",
    ),
    ("/min_overturn_in", "min_overturn_in"),
    (
        "/min_certain_overturn_alpha_g",
        "min_certain_overturn_alpha_g",
    ),
];
/// A mixed zone's row: its fields past the level column (named by the
/// row's kind).
const MIXED_ZONE: &[(&str, &str)] = &[
    ("/to", "mixed_to"),
    ("/fraction", "mixed_fraction"),
    ("/probes", "mixed_probes"),
    ("/interval_95/0", "mixed_interval_95_lo"),
    ("/interval_95/1", "mixed_interval_95_hi"),
];
/// A line's zone, repeated from its `mixed` rows.
const ZONE_OF_THE_MINIMUM: &[&str] = &["/min_overturn_zone"];
/// The zone columns: a zone's where the result has one (checked then).
const ZONE_COLUMNS: &[&str] = &[
    "mixed_to",
    "mixed_fraction",
    "mixed_probes",
    "mixed_interval_95_lo",
    "mixed_interval_95_hi",
];
/// A zone's row holds only the line's place, not its other fields.
const ONLY_THE_PLACE: &[&str] = &["/"];
const SPECTRUM_TRANSITION: &[(&str, &str)] = &[
    ("/a_alpha_g", "a_alpha_g"),
    ("/direction", "direction"),
    ("/mode", "mode"),
    ("/impacts", "impacts"),
    ("/bracket/0", "bracket_lo_alpha_g"),
    ("/bracket/1", "bracket_hi_alpha_g"),
    ("/a_g", "a_g"),
];

/// Every row of every kind's table holds every number of the JSON
/// objects it is made of (a kind without its check here does not compile).
/// Lists inside them (a spectrum line's `mode_changes`, `safe_intervals`,
/// its principal view's transitions and safe intervals; a record
/// observation's `overturning_scale`) are not columns: the table's rows are
/// its transitions, intervals, stripes or ages.
#[test]
fn every_row_holds_every_field_of_its_json() {
    for kind in JobKind::ALL {
        match kind {
            JobKind::TimeHistory => time_history_rows(),
            JobKind::Spectrum => spectrum_rows(),
            JobKind::FrictionSpectrum => friction_rows(),
            JobKind::Forensic => {
                forensic_rows();
                forensic_record_rows();
            }
            JobKind::RecordSpectrum => record_spectrum_rows(),
            JobKind::Survival => survival_rows(),
            JobKind::Fragility => fragility_rows(),
        }
    }
}

/// A pulse spectrum: a row per line and transition, then per mixed zone.
fn spectrum_rows() {
    const PLACE: &[(&str, &str)] = &[
        ("/omega_ratio", "omega_ratio"),
        ("/omega_p", "omega_p_rad_per_s"),
        ("/frequency_hz", "frequency_hz"),
    ];
    const FROM: &[(&str, &str)] = &[("/from", "a_alpha_g")];
    let (doc, csv) = document_and_table(SPECTRUM);
    let mut rows: Vec<Vec<Part>> = Vec::new();
    for line in items(&doc["spectrum"]) {
        for t in each_or_none(&line["transitions"]) {
            rows.push(vec![
                Part {
                    of: Some(line),
                    columns: SPECTRUM_LINE,
                    not_the_rows: ZONE_OF_THE_MINIMUM,
                },
                part(t, SPECTRUM_TRANSITION),
            ]);
        }
        for z in items(&line["mixed"]) {
            rows.push(vec![
                Part {
                    of: Some(line),
                    columns: PLACE,
                    not_the_rows: ONLY_THE_PLACE,
                },
                part(Some(z), FROM),
                part(Some(z), MIXED_ZONE),
            ]);
        }
    }
    assert!(rows.len() > 1);
    holds_every_field(&csv, &rows, ZONE_COLUMNS);
}

/// A record spectrum: a row per size and transition.
fn record_spectrum_rows() {
    const SIZE: &[(&str, &str)] = &[
        ("/p", "p_rad_s"),
        ("/R_m", "R_m"),
        ("/threshold_scale", "threshold_scale"),
        ("/min_overturn_scale", "min_overturn_scale"),
        ("/min_overturn_pga_g", "min_overturn_pga_g"),
        ("/min_overturn_mode", "min_overturn_mode"),
        ("/overturns_above_scale", "overturns_above_scale"),
        (
            "/principal/min_overturn_scale",
            "principal_min_overturn_scale",
        ),
        (
            "/principal/min_overturn_mode",
            "principal_min_overturn_mode",
        ),
        (
            "/principal/overturns_above_scale",
            "principal_overturns_above_scale",
        ),
        ("/min_overturn_in", "min_overturn_in"),
        ("/min_certain_overturn_scale", "min_certain_overturn_scale"),
        ("/min_certain_overturn_pga_g", "min_certain_overturn_pga_g"),
    ];
    const SCALE_TRANSITION: &[(&str, &str)] = &[
        ("/scale", "scale"),
        ("/pga_g", "pga_g"),
        ("/direction", "direction"),
        ("/mode", "mode"),
        ("/impacts", "impacts"),
        ("/bracket/0", "bracket_lo_scale"),
        ("/bracket/1", "bracket_hi_scale"),
    ];
    const PLACE: &[(&str, &str)] = &[("/p", "p_rad_s"), ("/R_m", "R_m")];
    const FROM: &[(&str, &str)] = &[("/from", "scale")];
    let (doc, csv) = document_and_table(RECORD_SPECTRUM);
    let mut rows: Vec<Vec<Part>> = Vec::new();
    for size in items(&doc["spectrum"]) {
        for t in each_or_none(&size["transitions"]) {
            rows.push(vec![
                Part {
                    of: Some(size),
                    columns: SIZE,
                    not_the_rows: ZONE_OF_THE_MINIMUM,
                },
                part(t, SCALE_TRANSITION),
            ]);
        }
        for z in items(&size["mixed"]) {
            rows.push(vec![
                Part {
                    of: Some(size),
                    columns: PLACE,
                    not_the_rows: ONLY_THE_PLACE,
                },
                part(Some(z), FROM),
                part(Some(z), MIXED_ZONE),
            ]);
        }
    }
    holds_every_field(&csv, &rows, ZONE_COLUMNS);
}

/// A friction spectrum: a row per amplitude, with the pulse's frequency.
fn friction_rows() {
    const POINT: &[(&str, &str)] = &[
        ("/a_alpha_g", "a_alpha_g"),
        ("/a_p_g", "a_p_g"),
        ("/peak_friction_demand", "peak_friction_demand"),
        ("/peak_over_tan_alpha", "peak_over_tan_alpha"),
        ("/initiation_friction_demand", "initiation_friction_demand"),
        ("/overturned", "overturned"),
        ("/mode", "mode"),
        ("/lift_off", "lift_off"),
        ("/lift_off_time", "lift_off_time_s"),
        (
            "/friction_demand_followed_until",
            "friction_demand_followed_until_s",
        ),
    ];
    const FREQUENCY: &[(&str, &str)] = &[
        ("/omega_ratio", "omega_ratio"),
        ("/omega_p", "omega_p_rad_per_s"),
        ("/frequency_hz", "frequency_hz"),
    ];
    let document = ["/kind", "/numerics", "/spec", "/engine"];
    let (doc, csv) = document_and_table(FRICTION);
    let rows: Vec<Vec<Part>> = items(&doc["points"])
        .iter()
        .map(|p| {
            vec![
                part(Some(p), POINT),
                Part {
                    of: Some(&doc),
                    columns: FREQUENCY,
                    not_the_rows: &document,
                },
            ]
        })
        .collect();
    holds_every_field(&csv, &rows, &[]);
}

/// A pulse forensic query: a row per frequency and interval, for all
/// observations (observation empty), then for each.
fn forensic_rows() {
    const AT: &[(&str, &str)] = &[
        ("/frequency_hz", "frequency_hz"),
        ("/omega_p", "omega_p_rad_per_s"),
    ];
    const INTERVAL_G: &[(&str, &str)] = &[("/0", "consistent_lo_g"), ("/1", "consistent_hi_g")];
    const NAMED: &[(&str, &str)] = &[("/name", "observation")];
    let (doc, csv) = document_and_table(FORENSIC);
    let frequencies = items(&doc["frequencies"]);
    let mut rows: Vec<Vec<Part>> = Vec::new();
    for f in frequencies {
        for i in each_or_none(&f["consistent_g"]) {
            rows.push(vec![
                part(Some(f), AT),
                part(None, NAMED),
                part(i, INTERVAL_G),
            ]);
        }
    }
    for f in frequencies {
        for o in items(&f["per_observation"]) {
            for i in each_or_none(&o["consistent_g"]) {
                rows.push(vec![
                    part(Some(f), AT),
                    part(Some(o), NAMED),
                    part(i, INTERVAL_G),
                ]);
            }
        }
    }
    holds_every_field(&csv, &rows, &["observed"]);
}

/// A record forensic query: a row per interval, for all, then for each.
fn forensic_record_rows() {
    const OBSERVATION: &[(&str, &str)] = &[
        ("/name", "observation"),
        ("/threshold_scale", "threshold_scale"),
    ];
    const INTERVAL_SCALE: &[(&str, &str)] =
        &[("/0", "consistent_lo_scale"), ("/1", "consistent_hi_scale")];
    const INTERVAL_PGA: &[(&str, &str)] =
        &[("/0", "consistent_lo_pga_g"), ("/1", "consistent_hi_pga_g")];
    const ZONE: &[(&str, &str)] = &[
        ("/from", "mixed_lo_scale"),
        ("/to", "mixed_hi_scale"),
        ("/fraction", "mixed_fraction"),
        ("/probes", "mixed_probes"),
        ("/interval_95/0", "mixed_interval_95_lo"),
        ("/interval_95/1", "mixed_interval_95_hi"),
    ];
    const ZONE_PGA: &[(&str, &str)] = &[("/from", "mixed_lo_pga_g"), ("/to", "mixed_hi_pga_g")];
    let (doc, csv) = document_and_table(FORENSIC_RECORD);
    let observed = ["/overturned"];
    let mut rows: Vec<Vec<Part>> = Vec::new();
    for (s, g) in each_or_none(&doc["consistent_scale"])
        .into_iter()
        .zip(each_or_none(&doc["consistent_pga_g"]))
    {
        rows.push(vec![
            part(None, OBSERVATION),
            part(s, INTERVAL_SCALE),
            part(g, INTERVAL_PGA),
        ]);
    }
    for (z, g) in items(&doc["mixed_scale"])
        .iter()
        .zip(items(&doc["mixed_pga_g"]))
    {
        rows.push(vec![
            part(None, OBSERVATION),
            part(Some(z), ZONE),
            part(Some(g), ZONE_PGA),
        ]);
    }
    for o in items(&doc["per_observation"]) {
        for (s, g) in each_or_none(&o["consistent_scale"])
            .into_iter()
            .zip(each_or_none(&o["consistent_pga_g"]))
        {
            rows.push(vec![
                Part {
                    of: Some(o),
                    columns: OBSERVATION,
                    not_the_rows: &observed,
                },
                part(s, INTERVAL_SCALE),
                part(g, INTERVAL_PGA),
            ]);
        }
        for (z, g) in items(&o["mixed_scale"])
            .iter()
            .zip(items(&o["mixed_pga_g"]))
        {
            rows.push(vec![
                Part {
                    of: Some(o),
                    columns: OBSERVATION,
                    not_the_rows: &observed,
                },
                part(Some(z), ZONE),
                part(Some(g), ZONE_PGA),
            ]);
        }
    }
    holds_every_field(
        &csv,
        &rows,
        &[
            "observed",
            "mixed_lo_scale",
            "mixed_hi_scale",
            "mixed_lo_pga_g",
            "mixed_hi_pga_g",
            "mixed_fraction",
            "mixed_probes",
            "mixed_interval_95_lo",
            "mixed_interval_95_hi",
        ],
    );
}

/// A fragility: a row per stripe.
fn fragility_rows() {
    const STRIPE: &[(&str, &str)] = &[
        ("/im", "pga_g"),
        ("/n", "n"),
        ("/overturned", "overturned"),
        ("/p", "p"),
        ("/interval_95/0", "p_lo_95"),
        ("/interval_95/1", "p_hi_95"),
        ("/mode_1", "mode_1"),
        ("/mode_2", "mode_2"),
    ];
    let (doc, csv) = document_and_table(FRAGILITY);
    let rows: Vec<Vec<Part>> = items(&doc["stripes"])
        .iter()
        .map(|s| vec![part(Some(s), STRIPE)])
        .collect();
    holds_every_field(&csv, &rows, &[]);
}

/// A survival: a row per rock and age.
fn survival_rows() {
    const ROCK: &[(&str, &str)] = &[
        ("/name", "rock"),
        ("/annual_toppling_rate", "annual_toppling_rate_per_yr"),
        ("/fragility/median", "fragility_median_pga_g"),
        ("/fragility/beta", "fragility_beta"),
        (
            "/mean_years_between_topplings",
            "mean_years_between_topplings",
        ),
        ("/extrapolated_share", "extrapolated_share"),
    ];
    const AGE: &[(&str, &str)] = &[
        ("/age_years", "age_years"),
        ("/survival_probability", "survival_probability"),
        ("/rate_scale_at_5_percent", "rate_scale_at_5_percent"),
    ];
    let (doc, csv) = document_and_table(SURVIVAL);
    let rows: Vec<Vec<Part>> = items(&doc["rocks"])
        .iter()
        .flat_map(|rock| {
            items(&rock["ages"])
                .iter()
                .map(move |a| vec![part(Some(rock), ROCK), part(Some(a), AGE)])
        })
        .collect();
    holds_every_field(&csv, &rows, &["age_uncertain"]);
}

/// A time history: a row per sample of its series; without one, a row per
/// impact; without impacts, a one-row summary.
fn time_history_rows() {
    time_history_rows_of(TIME_HISTORY, false);
    // Under a vertical ground motion: its series and its peak too.
    let vertical = TIME_HISTORY.replace(r#""outputs":"#, r#""vertical":{"ratio":0.4},"outputs":"#);
    time_history_rows_of(&vertical, true);
}

/// The rows of the time history of `spec`, with a vertical ground motion
/// or without.
fn time_history_rows_of(spec: &str, vertical: bool) {
    // The series: a row per sample.
    let mut sample = vec![
        ("/t", "t_s"),
        ("/theta", "theta_rad"),
        ("/theta_dot", "theta_dot_rad_per_s"),
        ("/ground_acceleration", "ground_acceleration_m_per_s2"),
        ("/fx_over_fz", "fx_over_fz"),
    ];
    if vertical {
        sample.push((
            "/ground_vertical_acceleration",
            "ground_vertical_acceleration_m_per_s2",
        ));
    }
    let sample = sample.as_slice();
    let (mut doc, csv) = document_and_table(spec);
    let series = doc["series"].as_object().expect("a series").clone();
    let samples: Vec<Value> = (0..items(&series["t"]).len())
        .map(|k| {
            Value::Object(
                series
                    .iter()
                    .map(|(name, column)| (name.clone(), column[k].clone()))
                    .collect(),
            )
        })
        .collect();
    let rows: Vec<Vec<Part>> = samples
        .iter()
        .map(|s| vec![part(Some(s), sample)])
        .collect();
    // (ug_v_g is ü_v in g, worked out: checked by the table's own test.)
    holds_every_field(&csv, &rows, if vertical { &["ug_v_g"] } else { &[] });

    // Without the series: a row per impact.
    const IMPACT: &[(&str, &str)] = &[
        ("/t", "t_s"),
        ("/theta_dot_before", "theta_dot_before_rad_per_s"),
        ("/theta_dot_after", "theta_dot_after_rad_per_s"),
    ];
    let fields = doc.as_object_mut().expect("a document");
    fields.remove("series");
    let table = |doc: &Value| csv_of(&JobResult::from_value(doc.clone()).expect("typed"));
    let csv = table(&doc);
    let rows: Vec<Vec<Part>> = items(&doc["impacts"])
        .iter()
        .map(|i| vec![part(Some(i), IMPACT)])
        .collect();
    assert!(!rows.is_empty(), "the block impacts");
    holds_every_field(&csv, &rows, &["impact"]);

    // Without impacts either: the one-row summary of the document.
    let mut summary = vec![
        ("/rocked", "rocked"),
        ("/overturned", "overturned"),
        ("/mode", "mode"),
        ("/impact_count", "impact_count"),
        ("/rocking_start", "rocking_start_s"),
        ("/overturn_time", "overturn_time_s"),
        ("/rest_time", "rest_time_s"),
        ("/end_time", "end_time_s"),
        ("/peak_theta_over_alpha", "peak_theta_over_alpha"),
        ("/peak_friction_demand", "peak_friction_demand"),
        ("/initiation_friction_demand", "initiation_friction_demand"),
        ("/lift_off", "lift_off"),
        ("/lift_off_time", "lift_off_time_s"),
        ("/rocking_starts", "rocking_starts"),
        ("/chatter_impacts_summed", "chatter_impacts_summed"),
        ("/decided_at", "decided_at_s"),
        ("/peak_friction_demand_time", "peak_friction_demand_time_s"),
        (
            "/friction_demand_followed_until",
            "friction_demand_followed_until_s",
        ),
        ("/ground_peaks/pga_m_s2", "pga_m_per_s2"),
        ("/ground_peaks/pga_g", "pga_g"),
        ("/ground_peaks/pgv_m_s", "pgv_m_per_s"),
        ("/ground_peaks/pgd_m", "pgd_m"),
        ("/ground_peaks/pgv_over_pga_s", "pgv_over_pga_s"),
        ("/overturn_direction", "overturn_direction"),
    ];
    if vertical {
        summary.push(("/ground_peaks/pga_v_m_s2", "pga_v_m_per_s2"));
        summary.push(("/ground_peaks/pga_v_g", "pga_v_g"));
    }
    if let Some(fields) = doc.as_object_mut() {
        fields.remove("impacts");
    }
    let csv = table(&doc);
    let document = ["/kind", "/numerics", "/spec", "/engine"];
    let summary = Part {
        of: Some(&doc),
        columns: &summary,
        not_the_rows: &document,
    };
    holds_every_field(&csv, &[vec![summary]], &[]);
}

/// The cells of column `name` of `csv`.
fn column<'a>(csv: &'a str, name: &str) -> Vec<&'a str> {
    let l = lines(csv);
    let k = l[0].split(',').position(|h| h == name).expect(name);
    l[1..]
        .iter()
        .map(|r| r.split(',').nth(k).unwrap_or(""))
        .collect()
}

/// The numbers at `pointer` of each item of list `v`.
fn numbers_at(v: &Value, pointer: &str) -> Vec<f64> {
    items(v)
        .iter()
        .filter_map(|x| x.pointer(pointer).and_then(Value::as_f64))
        .collect()
}

const TENTHS: [&str; 10] = [
    "0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1.0",
];

#[test]
fn a_spectrum_in_hz_shows_the_frequencies_given() {
    let (doc, csv) = document_and_table(
        r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"formulation":"linear",
            "frequency_hz":{"from":0.1,"to":1,"steps":10},"a_max_alpha_g":3,"scan_step_alpha_g":0.1}"#,
    );
    let hz = numbers_at(&doc["spectrum"], "/frequency_hz");
    // The document holds the grid's doubles, some a little off the tenths.
    assert!(hz.iter().map(json_text).any(|t| t.len() > 5), "{hz:?}");
    let mut shown = column(&csv, "frequency_hz");
    shown.dedup();
    assert_eq!(shown, TENTHS);
    // The other frequency columns are those of the document.
    let omega: Vec<String> = numbers_at(&doc["spectrum"], "/omega_p")
        .iter()
        .map(cell)
        .collect();
    let mut shown = column(&csv, "omega_p_rad_per_s");
    shown.dedup();
    assert_eq!(shown, omega);
}

#[test]
fn stripes_and_sizes_show_the_values_given() {
    let (doc, csv) = document_and_table(
        r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","omega_ratio":3},
            "stripes":{"from":0.1,"to":1,"steps":10},"samples":8,"seed":1}"#,
    );
    let im = numbers_at(&doc["stripes"], "/im");
    assert!(im.iter().map(json_text).any(|t| t.len() > 5), "{im:?}");
    assert_eq!(column(&csv, "pga_g"), TENTHS);

    let (doc, csv) = document_and_table(
        r#"{"kind":"record_spectrum","block":{"alpha":0.2},"R_m":{"from":0.1,"to":1,"steps":10},"scale":{"from":0.5,"to":3},
            "ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]}}"#,
    );
    let sizes = numbers_at(&doc["spectrum"], "/R_m");
    assert!(sizes.contains(&0.5000000000000001), "{sizes:?}");
    let mut shown = column(&csv, "R_m");
    shown.dedup();
    assert_eq!(shown, TENTHS);
}
