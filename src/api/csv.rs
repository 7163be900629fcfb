//! CSV renderings of result documents (`?format=csv`, `topple run --format
//! csv`). Every header names its quantity and unit: `_s` seconds, `_rad`,
//! `_rad_per_s`, `_m_per_s2`, `_hz`, `_g` (multiples of g), `_alpha_g`
//! (multiples of α g); ratios without a suffix are dimensionless.

use std::fmt::Write;

use serde_json::Value;

use crate::jobs::JobResult;
use crate::jobs::forensic::ForensicResult;
use crate::jobs::fragility::FragilityResult;
use crate::jobs::friction::FrictionResult;
use crate::jobs::names::Excitation;
use crate::jobs::record_spectrum::RecordSpectrumResult;
use crate::jobs::spectrum::SpectrumResult;
use crate::jobs::survival::SurvivalResult;
use crate::jobs::time_history::TimeHistoryResult;

/// One CSV field of a JSON value: numbers as JSON writes them, text quoted
/// when it needs to be.
fn f(v: Option<&Value>) -> String {
    match v {
        Some(Value::Null) | None => String::new(),
        Some(Value::String(s)) => quote(s),
        Some(x) => x.to_string(),
    }
}

/// A value as a CSV field, written as the result document writes it:
/// numbers as JSON writes them (`1.0`, `1e-7`), a number JSON cannot hold
/// (not finite) and `None` as an empty field, text through [`quote`].
trait Field {
    fn field(&self) -> String;
}

impl Field for f64 {
    fn field(&self) -> String {
        serde_json::Number::from_f64(*self).map_or_else(String::new, |n| n.to_string())
    }
}

macro_rules! plain_fields {
    ($($t:ty),*) => {
        $(impl Field for $t {
            fn field(&self) -> String {
                self.to_string()
            }
        })*
    };
}

plain_fields!(bool, u8, u32, u64, usize);

impl Field for str {
    fn field(&self) -> String {
        quote(self)
    }
}

impl Field for String {
    fn field(&self) -> String {
        quote(self)
    }
}

impl<T: Field> Field for Option<T> {
    fn field(&self) -> String {
        self.as_ref().map_or_else(String::new, Field::field)
    }
}

impl<T: Field + ?Sized> Field for &T {
    fn field(&self) -> String {
        (**self).field()
    }
}

/// `x` as a CSV field ([`Field`]).
fn cell<T: Field + ?Sized>(x: &T) -> String {
    x.field()
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

/// The CSV table of a result.
pub fn to_csv(result: &JobResult) -> String {
    let mut out = String::new();
    // Every kind has a table: the match is exhaustive.
    match result {
        JobResult::TimeHistory(r) => time_history(r, &mut out),
        JobResult::Spectrum(r) => spectrum(r, &mut out),
        JobResult::FrictionSpectrum(r) => friction(r, &mut out),
        JobResult::Forensic(r) if r.excitation == Excitation::GroundMotion => {
            forensic_record(r, &mut out)
        }
        JobResult::Forensic(r) => forensic(r, &mut out),
        JobResult::RecordSpectrum(r) => record_spectrum(r, &mut out),
        JobResult::Survival(r) => survival(r, &mut out),
        JobResult::Fragility(r) => fragility(r, &mut out),
    }
    out
}

/// The columns of a time history's series: (key, header).
const SERIES_COLUMNS: [(&str, &str); 5] = [
    ("t", "t_s"),
    ("theta", "theta_rad"),
    ("theta_dot", "theta_dot_rad_per_s"),
    ("ground_acceleration", "ground_acceleration_m_per_s2"),
    ("fx_over_fz", "fx_over_fz"),
];

/// One column of a series: samples, or samples that may be missing.
#[derive(Clone, Copy)]
enum Column<'a> {
    Samples(&'a [f64]),
    Gappy(&'a [Option<f64>]),
}

impl Column<'_> {
    fn len(self) -> usize {
        match self {
            Column::Samples(s) => s.len(),
            Column::Gappy(s) => s.len(),
        }
    }

    /// Sample `k` as a field (empty past the column's end).
    fn at(self, k: usize) -> String {
        match self {
            Column::Samples(s) => cell(&s.get(k)),
            Column::Gappy(s) => cell(&s.get(k).copied().flatten()),
        }
    }
}

/// The series when there is one; else the impacts; else a one-row summary.
fn time_history(r: &TimeHistoryResult, out: &mut String) {
    if let Some(s) = &r.series {
        let data = [
            Column::Samples(&s.t),
            Column::Samples(&s.theta),
            Column::Samples(&s.theta_dot),
            Column::Samples(&s.ground_acceleration),
            Column::Gappy(s.fx_over_fz.as_deref().unwrap_or_default()),
        ];
        let present: Vec<usize> = (0..data.len()).filter(|&i| data[i].len() > 0).collect();
        if !present.is_empty() {
            row(
                out,
                &present
                    .iter()
                    .map(|&i| SERIES_COLUMNS[i].1.to_string())
                    .collect::<Vec<_>>(),
            );
            let rows = present.iter().map(|&i| data[i].len()).max().unwrap_or(0);
            for k in 0..rows {
                let line: Vec<String> = present.iter().map(|&i| data[i].at(k)).collect();
                row(out, &line);
            }
            return;
        }
    }
    let impacts = r.impacts.as_deref().unwrap_or_default();
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
                    cell(&(k + 1)),
                    cell(&i.t),
                    cell(&i.theta_dot_before),
                    cell(&i.theta_dot_after),
                ],
            );
        }
        return;
    }
    let cols: [(&str, String); 13] = [
        ("rocked", cell(&r.rocked)),
        ("overturned", cell(&r.overturned)),
        ("mode", cell(&r.mode)),
        ("impact_count", cell(&r.impact_count)),
        ("rocking_start_s", cell(&r.rocking_start)),
        ("overturn_time_s", cell(&r.overturn_time)),
        ("rest_time_s", cell(&r.rest_time)),
        ("end_time_s", cell(&r.end_time)),
        ("peak_theta_over_alpha", cell(&r.peak_theta_over_alpha)),
        ("peak_friction_demand", cell(&r.peak_friction_demand)),
        (
            "initiation_friction_demand",
            cell(&r.initiation_friction_demand),
        ),
        ("lift_off", cell(&r.lift_off)),
        ("lift_off_time_s", cell(&r.lift_off_time)),
    ];
    row(out, &cols.each_ref().map(|c| c.0.to_string()));
    row(out, &cols.map(|c| c.1));
}

/// A survive ↔ overturn transition as the cells of its row: its levels
/// (amplitude, or scale and PGA), direction, mode, impacts and bracket.
struct Crossing<'a> {
    levels: Vec<String>,
    direction: &'a str,
    mode: u8,
    impacts: u64,
    bracket: [f64; 2],
}

/// One row per transition (a frequency without any: one row, transition
/// fields empty).
fn spectrum(r: &SpectrumResult, out: &mut String) {
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
    for line in &r.spectrum {
        let tail = [
            cell(&line.min_overturn_alpha_g),
            cell(&line.eq21_alpha_g),
            cell(&line.threshold_alpha_g),
            cell(&line.closed_form_mode2_alpha_g),
        ];
        let head = [cell(&line.omega_ratio)];
        let crossings = line.transitions.iter().map(|t| Crossing {
            levels: vec![cell(&t.a_alpha_g)],
            direction: &t.direction,
            mode: t.mode,
            impacts: t.impacts,
            bracket: t.bracket,
        });
        transition_rows(out, &head, 1, crossings, &tail);
    }
}

/// A row per transition of a line — `head`, the transition's `levels`
/// (`level_count` cells), direction, mode, impacts and bracket, then `tail`
/// — or one row with those cells empty when it has none.
fn transition_rows<'a>(
    out: &mut String,
    head: &[String],
    level_count: usize,
    crossings: impl ExactSizeIterator<Item = Crossing<'a>>,
    tail: &[String],
) {
    if crossings.len() == 0 {
        let mut fields = head.to_vec();
        fields.extend(std::iter::repeat_n(String::new(), level_count + 5));
        fields.extend(tail.iter().cloned());
        row(out, &fields);
    }
    for t in crossings {
        let mut fields = head.to_vec();
        fields.extend(t.levels);
        fields.extend([
            cell(t.direction),
            cell(&t.mode),
            cell(&t.impacts),
            cell(&t.bracket[0]),
            cell(&t.bracket[1]),
        ]);
        fields.extend(tail.iter().cloned());
        row(out, &fields);
    }
}

/// One row per transition of each block size (one empty row for a size
/// without any), with the size's minimum and rocking threshold.
fn record_spectrum(r: &RecordSpectrumResult, out: &mut String) {
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
    for line in &r.spectrum {
        let head = [cell(&line.p), cell(&line.r_m)];
        let tail = [
            cell(&line.min_overturn_scale),
            cell(&line.min_overturn_pga_g),
            cell(&line.threshold_scale),
        ];
        let crossings = line.transitions.iter().map(|t| Crossing {
            levels: vec![cell(&t.scale), cell(&t.pga_g)],
            direction: &t.direction,
            mode: t.mode,
            impacts: t.impacts,
            bracket: t.bracket,
        });
        transition_rows(out, &head, 2, crossings, &tail);
    }
}

fn friction(r: &FrictionResult, out: &mut String) {
    row(
        out,
        &[
            "a_alpha_g",
            "peak_friction_demand",
            "peak_over_tan_alpha",
            "initiation_friction_demand",
            "overturned",
            "mode",
            "lift_off",
            "lift_off_time_s",
            "friction_demand_followed_until_s",
        ]
        .map(String::from),
    );
    for p in &r.points {
        row(
            out,
            &[
                cell(&p.a_alpha_g),
                cell(&p.peak_friction_demand),
                cell(&p.peak_over_tan_alpha),
                cell(&p.initiation_friction_demand),
                cell(&p.overturned),
                cell(&p.mode),
                cell(&p.lift_off),
                cell(&p.lift_off_time),
                cell(&p.friction_demand_followed_until),
            ],
        );
    }
}

/// "overturned" or "survived".
fn seen(overturned: bool) -> String {
    if overturned { "overturned" } else { "survived" }.into()
}

/// One row per frequency and interval of amplitudes consistent with every
/// observation (`observation` empty), then the same per observation; a
/// frequency with no consistent amplitude has one row with the interval empty.
fn forensic(r: &ForensicResult, out: &mut String) {
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
        r.observations
            .iter()
            .find(|o| o.name == name)
            .map_or(String::new(), |o| seen(o.overturned))
    };
    let mut emit = |head: &[String; 2], name: &str, seen: String, set: &[[f64; 2]]| {
        if set.is_empty() {
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
        for [lo, hi] in set {
            row(
                out,
                &[
                    head[0].clone(),
                    head[1].clone(),
                    quote(name),
                    seen.clone(),
                    cell(lo),
                    cell(hi),
                ],
            );
        }
    };
    let heads: Vec<[String; 2]> = r
        .frequencies
        .iter()
        .map(|freq| [cell(&freq.frequency_hz), cell(&freq.omega_p)])
        .collect();
    for (freq, head) in r.frequencies.iter().zip(&heads) {
        emit(head, "", String::new(), &freq.consistent_g);
    }
    for (freq, head) in r.frequencies.iter().zip(&heads) {
        for o in &freq.per_observation {
            emit(head, &o.name, observed(&o.name), &o.consistent_g);
        }
    }
}

/// A fragility: a row per stripe (intensity in the result's `im`).
fn fragility(r: &FragilityResult, out: &mut String) {
    row(
        out,
        &[
            r.im.name(),
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
    for s in &r.stripes {
        row(
            out,
            &[
                cell(&s.im),
                cell(&s.n),
                cell(&s.overturned),
                cell(&s.p),
                cell(&s.interval_95[0]),
                cell(&s.interval_95[1]),
                cell(&s.mode_1),
                cell(&s.mode_2),
            ],
        );
    }
}

/// A survival result: a row per rock and age (an uncertain age: its median,
/// marked), then the joint probability of several rocks (rock "all").
fn survival(r: &SurvivalResult, out: &mut String) {
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
    for rock in &r.rocks {
        let name = cell(&rock.name);
        let rate = cell(&rock.annual_toppling_rate);
        for a in &rock.ages {
            row(
                out,
                &[
                    name.clone(),
                    rate.clone(),
                    cell(&a.age_years),
                    cell(&false),
                    cell(&a.survival_probability),
                    cell(&a.rate_scale_at_5_percent),
                ],
            );
        }
        if let Some(d) = &rock.age_distribution {
            row(
                out,
                &[
                    name.clone(),
                    rate.clone(),
                    cell(&d.median_age_years),
                    cell(&true),
                    cell(&d.survival_probability),
                    cell(&d.rate_scale_at_5_percent),
                ],
            );
        }
    }
    if let Some(j) = &r.joint {
        row(
            out,
            &[
                "all".into(),
                String::new(),
                String::new(),
                String::new(),
                cell(&j.survival_probability),
                cell(&j.rate_scale_at_5_percent),
            ],
        );
    }
}

/// A record query: a row per consistent interval, first those consistent
/// with every observation (observation empty), then each observation's; an
/// observation that allows nothing has one row with empty ends.
fn forensic_record(r: &ForensicResult, out: &mut String) {
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
    let mut emit = |name: &str, seen: String, scale: &[[f64; 2]], pga: &[[f64; 2]]| {
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
                    cell(&s[0]),
                    cell(&s[1]),
                    cell(&g[0]),
                    cell(&g[1]),
                ],
            );
        }
    };
    emit(
        "",
        String::new(),
        r.consistent_scale.as_deref().unwrap_or_default(),
        r.consistent_pga_g.as_deref().unwrap_or_default(),
    );
    for o in r.per_observation.as_deref().unwrap_or_default() {
        emit(
            &o.name,
            seen(o.overturned),
            &o.consistent_scale,
            &o.consistent_pga_g,
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
    use crate::jobs::forensic::{
        ForensicFrequency, Observation, ObservationSet, RecordObservationSet,
    };
    use crate::jobs::fragility::StripeResult;
    use crate::jobs::friction::FrictionPointDoc;
    use crate::jobs::names::Im;
    use crate::jobs::survival::{AgeDistributionResult, AgeResult, JointResult};
    use crate::jobs::time_history::{ImpactDoc, SeriesDoc};
    use crate::plot::tests::typed;
    use serde_json::json;

    const TIME_HISTORY: &str = r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":3,"a_p_alpha_g":2.5},"outputs":{"series":20}}"#;
    const SPECTRUM: &str = r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":[2,4],"a_max_alpha_g":6}"#;
    const FRICTION: &str = r#"{"kind":"friction_spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"omega_ratio":3,"a_alpha_g":[1.5,3]}"#;
    const FORENSIC: &str = r#"{"kind":"forensic","pulse":{"type":"one_sine"},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false}],"frequency_hz":{"from":0.5,"to":2,"steps":3},"a_p_g":{"from":0.05,"to":2.0}}"#;
    const FORENSIC_RECORD: &str = r#"{"kind":"forensic","ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false}],"pga_g":{"from":0.05,"to":2.0}}"#;
    const RECORD_SPECTRUM: &str = r#"{"kind":"record_spectrum","block":{"alpha":0.2},"p":[1.5,3],"scale":{"from":0.5,"to":3},"ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]}}"#;
    const SURVIVAL: &str = r#"{"kind":"survival","hazard":{"im":"pga_g","points":[[0.1,0.01],[0.5,0.0005],[1.0,0.00005]]},"fragility":{"median_g":0.4,"beta":0.4},"age_years":[1000]}"#;
    const FRAGILITY: &str = r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","omega_ratio":3},"stripes":[0.2,0.4],"samples":8,"seed":1}"#;

    fn lines(csv: &str) -> Vec<&str> {
        csv.lines().collect()
    }

    /// `x` as serde_json writes it.
    fn json_text<T: serde::Serialize>(x: &T) -> String {
        serde_json::to_string(x).expect("json")
    }

    fn time_history_result() -> TimeHistoryResult {
        match typed(TIME_HISTORY) {
            JobResult::TimeHistory(r) => *r,
            other => panic!("not a time history: {:?}", other.job_kind()),
        }
    }

    fn th_table(r: &TimeHistoryResult) -> String {
        to_csv(&JobResult::TimeHistory(Box::new(r.clone())))
    }

    #[test]
    fn numbers_are_written_as_json_writes_them() {
        for x in [
            1.0,
            -0.0,
            1e-7,
            0.1,
            1.5e-4,
            0.30000000000000004,
            1e300,
            1.7976931348623157e308,
            12345678901234567890.0,
        ] {
            assert_eq!(cell(&x), json_text(&x), "{x:e}");
        }
        assert_eq!(cell(&1.0), "1.0");
        assert_eq!(cell(&1e-7), "1e-7");
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(cell(&x), "", "{x}");
        }
        assert_eq!(cell(&None::<f64>), "");
        assert_eq!(cell(&Some(2u8)), "2");
        assert_eq!(cell(&Some(false)), "false");
        assert_eq!(cell(&u64::MAX), "18446744073709551615");
    }

    #[test]
    fn time_history_series_with_units() {
        let r = time_history_result();
        let s = r.series.clone().expect("a series");
        let ratio = s.fx_over_fz.clone().expect("reactions are followed");
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2,fx_over_fz"
        );
        assert_eq!(l.len(), s.t.len() + 1);
        assert!(s.t.len() > 2);
        let k = 2;
        assert_eq!(
            l[k + 1],
            [
                json_text(&s.t[k]),
                json_text(&s.theta[k]),
                json_text(&s.theta_dot[k]),
                json_text(&s.ground_acceleration[k]),
                ratio[k].map_or_else(String::new, |x| json_text(&x)),
            ]
            .join(",")
        );
        // Numbers as JSON writes them.
        let mut r = r;
        r.series = Some(SeriesDoc {
            t: vec![0.0, 0.1, 0.2],
            theta: vec![0.0, -0.01, -0.02],
            theta_dot: vec![0.0, -0.1, -0.2],
            ground_acceleration: vec![0.0, 1.0, 2.0],
            fx_over_fz: Some(vec![Some(0.0), Some(0.25), None]),
        });
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(l.len(), 4);
        assert_eq!(l[2], "0.1,-0.01,-0.1,1.0,0.25");
        assert_eq!(l[3], "0.2,-0.02,-0.2,2.0,");
        // Without reactions the ratio column is left out.
        if let Some(s) = &mut r.series {
            s.fx_over_fz = None;
        }
        let csv = th_table(&r);
        assert!(
            csv.starts_with("t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2\n")
        );
    }

    #[test]
    fn time_history_without_series_gives_impacts_then_a_summary() {
        let mut r = time_history_result();
        r.series = None;
        let impacts = r.impacts.clone().expect("impacts are listed");
        assert!(!impacts.is_empty(), "the block rocks and impacts");
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "impact,t_s,theta_dot_before_rad_per_s,theta_dot_after_rad_per_s"
        );
        assert_eq!(l.len(), impacts.len() + 1);
        let i = impacts[0];
        assert_eq!(
            l[1],
            format!(
                "1,{},{},{}",
                json_text(&i.t),
                json_text(&i.theta_dot_before),
                json_text(&i.theta_dot_after)
            )
        );
        r.impacts = Some(vec![ImpactDoc {
            t: 1.5,
            theta_dot_before: 0.5,
            theta_dot_after: -0.45,
        }]);
        assert_eq!(
            lines(&th_table(&r)),
            vec![
                "impact,t_s,theta_dot_before_rad_per_s,theta_dot_after_rad_per_s",
                "1,1.5,0.5,-0.45"
            ]
        );
        // An empty series and no impacts: the summary.
        r.series = Some(SeriesDoc {
            t: vec![],
            theta: vec![],
            theta_dot: vec![],
            ground_acceleration: vec![],
            fx_over_fz: None,
        });
        r.impacts = None;
        r.rocked = false;
        r.overturned = false;
        r.mode = None;
        r.impact_count = 0;
        r.rocking_start = None;
        r.overturn_time = None;
        r.rest_time = None;
        r.end_time = 1.0;
        r.peak_theta_over_alpha = 0.0;
        r.peak_friction_demand = None;
        r.initiation_friction_demand = None;
        r.lift_off = None;
        r.lift_off_time = None;
        assert_eq!(
            lines(&th_table(&r)),
            vec![
                "rocked,overturned,mode,impact_count,rocking_start_s,overturn_time_s,rest_time_s,end_time_s,peak_theta_over_alpha,peak_friction_demand,initiation_friction_demand,lift_off,lift_off_time_s",
                "false,false,,0,,,,1.0,0.0,,,,",
            ]
        );
        r.overturned = true;
        r.mode = Some(2);
        r.overturn_time = Some(0.75);
        r.peak_friction_demand = Some(0.3);
        r.lift_off = Some(false);
        assert_eq!(
            lines(&th_table(&r))[1],
            "false,true,2,0,,0.75,,1.0,0.0,0.3,,false,"
        );
    }

    #[test]
    fn spectrum_rows_per_transition() {
        let JobResult::Spectrum(mut r) = typed(SPECTRUM) else {
            panic!("a spectrum")
        };
        let csv = to_csv(&JobResult::Spectrum(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo_alpha_g,bracket_hi_alpha_g,min_overturn_alpha_g,eq21_alpha_g,threshold_alpha_g,closed_form_mode2_alpha_g"
        );
        let rows: usize = r.spectrum.iter().map(|f| f.transitions.len().max(1)).sum();
        assert_eq!(l.len(), 1 + rows);
        let line = &r.spectrum[0];
        let t = line.transitions.first().expect("a transition below a_max");
        assert_eq!(
            l[1],
            format!(
                "{},{},{},{},{},{},{},{},{},{},{}",
                json_text(&line.omega_ratio),
                json_text(&t.a_alpha_g),
                t.direction,
                t.mode,
                t.impacts,
                json_text(&t.bracket[0]),
                json_text(&t.bracket[1]),
                line.min_overturn_alpha_g
                    .map_or_else(String::new, |x| json_text(&x)),
                line.eq21_alpha_g
                    .map_or_else(String::new, |x| json_text(&x)),
                json_text(&line.threshold_alpha_g),
                line.closed_form_mode2_alpha_g
                    .map_or_else(String::new, |x| json_text(&x)),
            )
        );
        // Set values: one line with two transitions, one without any.
        let mut first = r.spectrum[0].clone();
        let mut second = first.clone();
        let mut up = first.transitions[0].clone();
        (first.omega_ratio, first.threshold_alpha_g) = (2.0, 1.0);
        (first.min_overturn_alpha_g, first.eq21_alpha_g) = (Some(1.25), Some(1.33));
        first.closed_form_mode2_alpha_g = None;
        (up.a_alpha_g, up.direction, up.mode, up.impacts) = (1.25, "up".into(), 1, 1);
        up.bracket = [1.2499, 1.2501];
        let mut down = up.clone();
        (down.a_alpha_g, down.direction, down.bracket) = (2.37, "down".into(), [2.3699, 2.3701]);
        first.transitions = vec![up, down];
        (second.omega_ratio, second.threshold_alpha_g) = (10.0, 1.0);
        (second.min_overturn_alpha_g, second.eq21_alpha_g) = (None, Some(2.67));
        second.closed_form_mode2_alpha_g = None;
        second.transitions = vec![];
        r.spectrum = vec![first, second];
        let csv = to_csv(&JobResult::Spectrum(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,",
                "2.0,2.37,down,1,1,2.3699,2.3701,1.25,1.33,1.0,",
                "10.0,,,,,,,,2.67,1.0,",
            ]
        );
    }

    #[test]
    fn record_spectrum_rows_per_transition_and_size() {
        let JobResult::RecordSpectrum(mut r) = typed(RECORD_SPECTRUM) else {
            panic!("a record spectrum")
        };
        let csv = to_csv(&JobResult::RecordSpectrum(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "p_rad_s,R_m,scale,pga_g,direction,mode,impacts,bracket_lo_scale,bracket_hi_scale,min_overturn_scale,min_overturn_pga_g,threshold_scale"
        );
        let rows: usize = r.spectrum.iter().map(|s| s.transitions.len().max(1)).sum();
        assert_eq!(l.len(), 1 + rows);
        let size = &r.spectrum[0];
        let head = format!("{},{},", json_text(&size.p), json_text(&size.r_m));
        assert!(l[1].starts_with(&head), "{} against {head}", l[1]);
        assert!(
            l[1].ends_with(&format!(",{}", json_text(&size.threshold_scale))),
            "{}",
            l[1]
        );
        // Set values: a size with a transition, one without.
        let mut first = r.spectrum[0].clone();
        let mut second = first.clone();
        (first.p, first.r_m, first.threshold_scale) = (1.5, 4.36, 0.4);
        (first.min_overturn_scale, first.min_overturn_pga_g) = (Some(2.5), Some(0.75));
        let up = crate::jobs::record_spectrum::ScaleTransitionDoc {
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
        second.transitions = vec![];
        r.spectrum = vec![first, second];
        let csv = to_csv(&JobResult::RecordSpectrum(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "1.5,4.36,2.5,0.75,up,2,0,2.49,2.51,2.5,0.75,0.4",
                "3.0,1.09,,,,,,,,,,0.5",
            ]
        );
    }

    #[test]
    fn friction_rows_per_amplitude() {
        let JobResult::FrictionSpectrum(mut r) = typed(FRICTION) else {
            panic!("a friction spectrum")
        };
        let csv = to_csv(&JobResult::FrictionSpectrum(r.clone()));
        let l = lines(&csv);
        assert_eq!(l.len(), 1 + r.points.len());
        let p = &r.points[0];
        assert_eq!(
            l[1].split(',').take(2).collect::<Vec<_>>(),
            vec![
                json_text(&p.a_alpha_g),
                p.peak_friction_demand
                    .map_or_else(String::new, |x| json_text(&x))
            ]
        );
        let point = |a: f64, peak: Option<f64>, over: Option<f64>, init: f64| FrictionPointDoc {
            a_alpha_g: a,
            a_p_g: a * 0.25,
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
        let csv = to_csv(&JobResult::FrictionSpectrum(r));
        assert_eq!(
            lines(&csv),
            vec![
                "a_alpha_g,peak_friction_demand,peak_over_tan_alpha,initiation_friction_demand,overturned,mode,lift_off,lift_off_time_s,friction_demand_followed_until_s",
                "1.1,0.26,1.02,0.255,false,,false,,",
                "6.0,,,0.51,true,2,true,0.41,",
                "8.0,0.3,1.2,0.6,false,,false,,0.5",
            ]
        );
    }

    #[test]
    fn fragility_rows_per_stripe() {
        let JobResult::Fragility(mut r) = typed(FRAGILITY) else {
            panic!("a fragility")
        };
        let csv = to_csv(&JobResult::Fragility(r.clone()));
        let l = lines(&csv);
        assert_eq!(l[0], "pga_g,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2");
        assert_eq!(l.len(), 1 + r.stripes.len());
        let s = &r.stripes[1];
        assert_eq!(
            l[2],
            format!(
                "{},{},{},{},{},{},{},{}",
                json_text(&s.im),
                s.n,
                s.overturned,
                json_text(&s.p),
                json_text(&s.interval_95[0]),
                json_text(&s.interval_95[1]),
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
        }];
        r.im = Im::PgvMS;
        let csv = to_csv(&JobResult::Fragility(r));
        assert_eq!(
            lines(&csv),
            vec![
                "pgv_m_s,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2",
                "0.3,200,58,0.29,0.23,0.35,58,0",
            ]
        );
    }

    #[test]
    fn survival_rows_per_rock_and_age_then_the_joint() {
        let JobResult::Survival(mut r) = typed(SURVIVAL) else {
            panic!("a survival")
        };
        let csv = to_csv(&JobResult::Survival(r.clone()));
        let rock = &r.rocks[0];
        let age = &rock.ages[0];
        assert_eq!(
            lines(&csv),
            vec![
                "rock,annual_toppling_rate_per_yr,age_years,age_uncertain,survival_probability,rate_scale_at_5_percent".to_string(),
                format!(
                    "{},{},1000.0,false,{},{}",
                    rock.name,
                    json_text(&rock.annual_toppling_rate),
                    json_text(&age.survival_probability),
                    json_text(&age.rate_scale_at_5_percent.expect("it can topple")),
                ),
            ]
        );
        let mut grass = rock.clone();
        (grass.name, grass.annual_toppling_rate) = ("Grass Valley".into(), 1.5e-4);
        grass.ages = vec![AgeResult {
            age_years: 1000.0,
            survival_probability: 0.86,
            rate_scale_at_5_percent: Some(20.0),
        }];
        grass.age_distribution = None;
        let mut b = rock.clone();
        (b.name, b.annual_toppling_rate, b.ages) = ("b".into(), 1e-4, vec![]);
        b.age_distribution = Some(AgeDistributionResult {
            median_age_years: 9000.0,
            survival_probability: 0.4,
            rate_scale_at_5_percent: None,
        });
        r.rocks = vec![grass, b];
        r.joint = Some(JointResult {
            survival_probability: 0.344,
            rate_scale_at_5_percent: Some(2.5),
        });
        let csv = to_csv(&JobResult::Survival(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "Grass Valley,0.00015,1000.0,false,0.86,20.0",
                "b,0.0001,9000.0,true,0.4,",
                "all,,,,0.344,2.5",
            ]
        );
    }

    #[test]
    fn a_record_querys_rows_per_interval_and_observation() {
        let JobResult::Forensic(mut r) = typed(FORENSIC_RECORD) else {
            panic!("a forensic query")
        };
        assert_eq!(r.excitation, Excitation::GroundMotion);
        let csv = to_csv(&JobResult::Forensic(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "observation,observed,consistent_lo_scale,consistent_hi_scale,consistent_lo_pga_g,consistent_hi_pga_g"
        );
        let all = r.consistent_scale.clone().expect("a record query's scales");
        let mine = &r.per_observation.as_ref().expect("per observation")[0];
        let rows = |n: usize| n.max(1);
        assert_eq!(
            l.len(),
            1 + rows(all.len()) + rows(mine.consistent_scale.len())
        );
        let first = mine.consistent_scale.first().expect("a survived scale");
        let first_g = mine.consistent_pga_g[0];
        assert_eq!(
            l[1 + rows(all.len())],
            format!(
                "transformer,survived,{},{},{},{}",
                json_text(&first[0]),
                json_text(&first[1]),
                json_text(&first_g[0]),
                json_text(&first_g[1])
            )
        );
        let set = |name: &str, overturned: bool, scale: Vec<[f64; 2]>, pga: Vec<[f64; 2]>| {
            RecordObservationSet {
                name: name.into(),
                overturned,
                consistent_scale: scale,
                consistent_pga_g: pga,
                overturning_scale: vec![],
                threshold_scale: 0.5,
            }
        };
        r.consistent_scale = Some(vec![[0.7, 1.4], [2.8, 3.2]]);
        r.consistent_pga_g = Some(vec![[0.35, 0.7], [1.4, 1.6]]);
        r.per_observation = Some(vec![
            set("locomotive", true, vec![[0.7, 6.0]], vec![[0.35, 3.0]]),
            set("=cmd", false, vec![], vec![]),
        ]);
        let csv = to_csv(&JobResult::Forensic(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                ",,0.7,1.4,0.35,0.7",
                ",,2.8,3.2,1.4,1.6",
                "locomotive,overturned,0.7,6.0,0.35,3.0",
                "\"'=cmd\",survived,,,,",
            ]
        );
    }

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
            per_observation: per_observation
                .iter()
                .map(|(name, set)| ObservationSet {
                    name: (*name).into(),
                    consistent_g: set.clone(),
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
        let csv = to_csv(&JobResult::Forensic(r.clone()));
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
        let head = format!(
            "{},{},,,",
            json_text(&f0.frequency_hz),
            json_text(&f0.omega_p)
        );
        assert!(l[1].starts_with(&head), "{} against {head}", l[1]);
        let mine = &f0.per_observation[0];
        let head = format!(
            "{},{},transformer,survived,",
            json_text(&f0.frequency_hz),
            json_text(&f0.omega_p)
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
        let csv = to_csv(&doc);
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
        let csv = to_csv(&doc);
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
            ],
            theta: vec![],
            theta_dot: vec![-5.0, 0.30000000000000004],
            ground_acceleration: vec![f64::NAN],
            fx_over_fz: Some(vec![Some(f64::INFINITY), None, Some(0.3)]),
        });
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
            fx_over_fz: Some(ratio),
        });
        let whole = th_table(&long);
        assert_eq!(whole.lines().count(), n + 1);
        let text = serde_json::to_string(&long).expect("json");
        assert_eq!(streamed(&text, 1 << 16).as_deref(), Some(whole.as_str()));
    }

    #[test]
    fn series_are_read_from_any_stored_document() {
        // Integers as stored, a key order other than the engine's, a null.
        let text = r#"{"series": {"t": [0.0, 12345678901234567890], "theta": [],
            "theta_dot": [-5, 0.30000000000000004], "ground_acceleration": [null]},
            "kind": "time_history"}"#;
        let table = "t_s,theta_dot_rad_per_s,ground_acceleration_m_per_s2\n\
                     0.0,-5,\n\
                     12345678901234567890,0.30000000000000004,\n";
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

    #[test]
    fn unknown_kinds_have_no_table() {
        // A table is made of a result of a known kind; a document of another
        // kind is not read into one.
        assert!(JobResult::from_value(json!({"kind": "teapot"})).is_err());
    }
}
