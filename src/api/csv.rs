//! CSV renderings of result documents (`?format=csv`, `topple run --format
//! csv`). Every header names its quantity and unit: `_s` seconds, `_rad`,
//! `_rad_per_s`, `_m`, `_m_per_s`, `_m_per_s2`, `_hz`, `_g` (multiples of g),
//! `_alpha_g` (multiples of α g); ratios without a suffix are dimensionless.
//! A row holds every number the result document gives for what the row is
//! about; columns added later come at the end of the row, after the ones
//! scripts already read.
//!
//! Numbers are written to [`SIGNIFICANT_DIGITS`] ([`number`]): a value the
//! user wrote reads as written (a grid value 0.7999999999999999 as 0.8).

use std::fmt::Write;

use serde_json::Value;

use crate::jobs::names::Excitation;
use crate::kinds::JobResult;
use crate::kinds::forensic::ForensicResult;
use crate::kinds::fragility::FragilityResult;
use crate::kinds::friction_spectrum::FrictionResult;
use crate::kinds::record_spectrum::RecordSpectrumResult;
use crate::kinds::spectrum::{FrequencyDoc, SpectrumResult};
use crate::kinds::survival::SurvivalResult;
use crate::kinds::time_history::TimeHistoryResult;

#[cfg(test)]
mod every_field;
mod number;

pub use number::{SIGNIFICANT_DIGITS, number};

/// One CSV field of a JSON value read from a stored document: numbers
/// through [`number`] (an integer as stored is the double the typed result
/// reads), text quoted when it needs to be.
fn json_field(v: Option<&Value>) -> String {
    match v {
        Some(Value::Null) | None => String::new(),
        Some(Value::Number(n)) => n.as_f64().map_or_else(String::new, number),
        Some(Value::String(s)) => quote(s),
        Some(x) => x.to_string(),
    }
}

/// A value as a CSV field: numbers through [`number`], `None` as an empty
/// field, text through [`quote`].
trait Field {
    fn field(&self) -> String;
}

impl Field for f64 {
    fn field(&self) -> String {
        number(*self)
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

/// The columns of a time history's series: (key, header). The vertical
/// ground acceleration (under a vertical ground motion only) comes last, as
/// columns added later do, in m/s² and in g (`ug_v_g`, worked out from the
/// first with the block's g).
const SERIES_COLUMNS: [(&str, &str); 9] = [
    ("t", "t_s"),
    ("theta", "theta_rad"),
    ("theta_dot", "theta_dot_rad_per_s"),
    ("ground_acceleration", "ground_acceleration_m_per_s2"),
    ("fx_over_fz", "fx_over_fz"),
    (
        "ground_vertical_acceleration",
        "ground_vertical_acceleration_m_per_s2",
    ),
    ("ug_v_g", "ug_v_g"),
    ("slide_m", "slide_m"),
    ("mode", "mode"),
];

/// One column of a series: samples, or samples that may be missing.
#[derive(Clone, Copy)]
enum Column<'a> {
    Samples(&'a [f64]),
    Gappy(&'a [Option<f64>]),
    Text(&'a [String]),
}

impl Column<'_> {
    fn len(self) -> usize {
        match self {
            Column::Samples(s) => s.len(),
            Column::Gappy(s) => s.len(),
            Column::Text(s) => s.len(),
        }
    }

    /// Sample `k` as a field (empty past the column's end).
    fn at(self, k: usize) -> String {
        match self {
            Column::Samples(s) => cell(&s.get(k)),
            Column::Gappy(s) => cell(&s.get(k).copied().flatten()),
            Column::Text(s) => s.get(k).cloned().unwrap_or_default(),
        }
    }
}

/// The series when there is one; else the impacts; else a one-row summary.
fn time_history(r: &TimeHistoryResult, out: &mut String) {
    if let Some(s) = &r.series {
        let g = r.spec.block.g;
        let in_g: Vec<f64> = s
            .ground_vertical_acceleration
            .as_deref()
            .unwrap_or_default()
            .iter()
            .map(|a| a / g)
            .collect();
        let data = [
            Column::Samples(&s.t),
            Column::Samples(&s.theta),
            Column::Samples(&s.theta_dot),
            Column::Samples(&s.ground_acceleration),
            Column::Gappy(s.fx_over_fz.as_deref().unwrap_or_default()),
            Column::Samples(
                s.ground_vertical_acceleration
                    .as_deref()
                    .unwrap_or_default(),
            ),
            Column::Samples(&in_g),
            Column::Samples(s.slide_m.as_deref().unwrap_or_default()),
            Column::Text(s.mode.as_deref().unwrap_or_default()),
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
    let peaks = &r.ground_peaks;
    let mut cols: Vec<(&str, String)> = vec![
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
        ("rocking_starts", cell(&r.rocking_starts)),
        ("chatter_impacts_summed", cell(&r.chatter_impacts_summed)),
        ("decided_at_s", cell(&r.decided_at)),
        (
            "peak_friction_demand_time_s",
            cell(&r.peak_friction_demand_time),
        ),
        (
            "friction_demand_followed_until_s",
            cell(&r.friction_demand_followed_until),
        ),
        ("pga_m_per_s2", cell(&peaks.pga_m_s2)),
        ("pga_g", cell(&peaks.pga_g)),
        ("pgv_m_per_s", cell(&peaks.pgv_m_s)),
        ("pgd_m", cell(&peaks.pgd_m)),
        ("pgv_over_pga_s", cell(&peaks.pgv_over_pga_s)),
        ("overturn_direction", cell(&r.overturn_direction)),
    ];
    // Under a vertical ground motion only: its peak.
    if peaks.pga_v_m_s2.is_some() || peaks.pga_v_g.is_some() {
        cols.push(("pga_v_m_per_s2", cell(&peaks.pga_v_m_s2)));
        cols.push(("pga_v_g", cell(&peaks.pga_v_g)));
    }
    // On a Coulomb floor only: how it moved on it.
    if r.contact_model.is_some() {
        cols.push(("contact_model", cell(&r.contact_model)));
        cols.push(("answered_by", cell(&r.answered_by)));
        cols.push(("initial_mode", cell(&r.initial_mode)));
        cols.push(("peak_slide_m", cell(&r.peak_slide_m)));
        cols.push(("residual_slide_m", cell(&r.residual_slide_m)));
        cols.push(("time_sliding_s", cell(&r.time_sliding_s)));
    }
    row(
        out,
        &cols.iter().map(|c| c.0.to_string()).collect::<Vec<_>>(),
    );
    row(out, &cols.into_iter().map(|c| c.1).collect::<Vec<_>>());
}

/// A survive ↔ overturn transition as the cells of its row: its levels
/// (amplitude, or scale and PGA), direction, mode, impacts and bracket, and
/// the cells it adds at the row's end.
struct Crossing<'a> {
    levels: Vec<String>,
    direction: &'a str,
    mode: u8,
    impacts: u64,
    bracket: [f64; 2],
    added: Vec<String>,
}

/// The cells of a spectrum line's rows that are the line's: `head` before
/// the transition's, `tail` after them, then (after the transition's added
/// cells) `added`.
struct LineCells {
    head: Vec<String>,
    tail: Vec<String>,
    added: Vec<String>,
}

/// The number of cells a transition fills: `levels` before its direction,
/// `added` at the row's end.
#[derive(Clone, Copy)]
struct CrossingShape {
    levels: usize,
    added: usize,
}

/// The columns of a spectrum's table before any added for a Coulomb floor.
const SPECTRUM_COLUMNS: [&str; 31] = [
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
    "a_g",
    "omega_p_rad_per_s",
    "frequency_hz",
    "threshold_g",
    "min_overturn_g",
    "min_overturn_m_per_s2",
    "min_overturn_mode",
    "overturns_above_alpha_g",
    "pgv_over_pga_s",
    "pgd_over_pga_s2",
    "principal_min_overturn_alpha_g",
    "principal_min_overturn_mode",
    "principal_overturns_above_alpha_g",
    "min_overturn_in",
    "min_certain_overturn_alpha_g",
    "mixed_to",
    "mixed_fraction",
    "mixed_probes",
    "mixed_interval_95_lo",
    "mixed_interval_95_hi",
];

/// The zone columns a mixed zone's row fills (`mixed_to` … ), empty on the
/// other rows.
const MIXED_COLUMNS: usize = 5;

/// A row of `header` from named cells (the others empty).
fn named_row(out: &mut String, header: &[&str], cells: &[(&str, String)]) {
    let fields: Vec<String> = header
        .iter()
        .map(|h| {
            cells
                .iter()
                .find(|(name, _)| name == h)
                .map_or_else(String::new, |(_, v)| v.clone())
        })
        .collect();
    row(out, &fields);
}

/// The cells of a mixed zone's row: its ends (`from` in the row's level
/// column `level`, `to`), its fraction, probes and interval.
fn mixed_cells<'a>(level: &'a str, z: &crate::jobs::mixed::MixedDoc) -> Vec<(&'a str, String)> {
    vec![
        (level, cell(&z.from)),
        ("direction", cell("mixed")),
        ("mixed_to", cell(&z.to)),
        ("mixed_fraction", cell(&z.fraction)),
        ("mixed_probes", cell(&z.probes)),
        ("mixed_interval_95_lo", cell(&z.interval_95[0])),
        ("mixed_interval_95_hi", cell(&z.interval_95[1])),
    ]
}

/// The columns a residual-slide point adds at the end of a spectrum's rows.
const SLIDE_COLUMNS: [&str; 3] = ["residual_slide_m", "peak_slide_m", "outcome"];

/// The columns a spectrum's table ends with, past [`SPECTRUM_COLUMNS`]:
/// [`SLIDE_COLUMNS`] when a line has residual-slide points, then `floor`
/// when the pure-rocking spectrum is beside.
#[derive(Clone, Copy)]
struct SpectrumTail {
    slides: bool,
    floor: bool,
}

/// One row per transition of each frequency (a frequency without any: one
/// row, transition fields empty), in [`SPECTRUM_COLUMNS`].
///
/// On a Coulomb floor the table may grow at its end (a table without
/// residual slides or the pure-rocking spectrum is as it was):
/// - with residual slides (`residual_slide`), three columns
///   `residual_slide_m`, `peak_slide_m` (m) and `outcome` (`stands`,
///   `overturns` or `lift_off`), and after a frequency's transition rows one
///   row per amplitude of its residual-slide line: `direction`
///   `residual_slide`, `a_alpha_g` and `a_g` its amplitude, `omega_ratio`,
///   `omega_p_rad_per_s` and `frequency_hz` the frequency's, the three
///   columns the point's, the other cells empty (the three are empty on the
///   transition rows);
/// - with the pure-rocking spectrum beside (`no_sliding_beside`), a last
///   column `floor`: `coulomb` on the rows of `spectrum`, then the rows of
///   `no_sliding`, built the same way, with `floor` `no_sliding`.
fn spectrum(r: &SpectrumResult, out: &mut String) {
    let tail = SpectrumTail {
        slides: r
            .spectrum
            .iter()
            .chain(&r.no_sliding)
            .any(|l| l.residual_slide.as_ref().is_some_and(|p| !p.is_empty())),
        floor: !r.no_sliding.is_empty(),
    };
    let mut header: Vec<String> = SPECTRUM_COLUMNS.map(String::from).to_vec();
    if tail.slides {
        header.extend(SLIDE_COLUMNS.map(String::from));
    }
    if tail.floor {
        header.push("floor".into());
    }
    row(out, &header);
    let alpha = r.spec.block.alpha;
    for line in &r.spectrum {
        spectrum_line_rows(out, line, alpha, tail, "coulomb");
    }
    for line in &r.no_sliding {
        spectrum_line_rows(out, line, alpha, tail, "no_sliding");
    }
}

/// The rows of one frequency of a spectrum of a block of slenderness
/// `alpha` ([`spectrum`]): its transitions' rows, then its residual-slide
/// points' rows, ending with the columns of `tail` (`floor` as given).
fn spectrum_line_rows(
    out: &mut String,
    line: &FrequencyDoc,
    alpha: f64,
    tail: SpectrumTail,
    floor: &str,
) {
    // The cells past the original columns of a row that is not a point's.
    let mut end = Vec::new();
    if tail.slides {
        end.extend(std::iter::repeat_n(String::new(), SLIDE_COLUMNS.len()));
    }
    if tail.floor {
        end.push(cell(floor));
    }
    let mut added = vec![
        cell(&line.omega_p),
        cell(&line.frequency_hz),
        cell(&line.threshold_g),
        cell(&line.min_overturn_g),
        cell(&line.min_overturn_m_s2),
        cell(&line.min_overturn_mode),
        cell(&line.overturns_above_alpha_g),
        cell(&line.ground.pgv_over_pga_s),
        cell(&line.ground.pgd_over_pga_s2),
        cell(&line.principal.min_overturn_alpha_g),
        cell(&line.principal.min_overturn_mode),
        cell(&line.principal.overturns_above_alpha_g),
        cell(&line.min_overturn_in),
        cell(&line.min_certain_overturn_alpha_g),
    ];
    added.extend(std::iter::repeat_n(String::new(), MIXED_COLUMNS));
    added.extend(end.iter().cloned());
    let cells = LineCells {
        head: vec![cell(&line.omega_ratio)],
        tail: vec![
            cell(&line.min_overturn_alpha_g),
            cell(&line.eq21_alpha_g),
            cell(&line.threshold_alpha_g),
            cell(&line.closed_form_mode2_alpha_g),
        ],
        added,
    };
    let crossings = line.transitions.iter().map(|t| Crossing {
        levels: vec![cell(&t.a_alpha_g)],
        direction: &t.direction,
        mode: t.mode,
        impacts: t.impacts,
        bracket: t.bracket,
        added: vec![cell(&t.a_g)],
    });
    let shape = CrossingShape {
        levels: 1,
        added: 1,
    };
    transition_rows(out, &cells, shape, crossings);
    let mut header: Vec<&str> = SPECTRUM_COLUMNS.to_vec();
    if tail.slides {
        header.extend(SLIDE_COLUMNS);
    }
    if tail.floor {
        header.push("floor");
    }
    for z in &line.mixed {
        let mut cells = mixed_cells("a_alpha_g", z);
        cells.extend([
            ("omega_ratio", cell(&line.omega_ratio)),
            ("a_g", cell(&(z.from * alpha))),
            ("omega_p_rad_per_s", cell(&line.omega_p)),
            ("frequency_hz", cell(&line.frequency_hz)),
            ("floor", cell(floor)),
        ]);
        named_row(out, &header, &cells);
    }
    for p in line.residual_slide.iter().flatten() {
        let mut fields = vec![
            cell(&line.omega_ratio),
            cell(&p.a_alpha_g),
            cell("residual_slide"),
        ];
        // mode … closed_form_mode2_alpha_g: the transition's and the line's.
        fields.extend(std::iter::repeat_n(String::new(), 8));
        fields.extend([
            cell(&(p.a_alpha_g * alpha)),
            cell(&line.omega_p),
            cell(&line.frequency_hz),
        ]);
        // threshold_g … mixed_interval_95_hi: the line's and a zone's.
        fields.extend(std::iter::repeat_n(String::new(), 17));
        fields.extend([
            cell(&p.residual_slide_m),
            cell(&p.peak_slide_m),
            cell(&p.outcome),
        ]);
        if tail.floor {
            fields.push(cell(floor));
        }
        debug_assert_eq!(
            fields.len(),
            SPECTRUM_COLUMNS.len() + SLIDE_COLUMNS.len() + usize::from(tail.floor)
        );
        row(out, &fields);
    }
}

/// A row per transition of a line — the line's `head`, the transition's
/// levels, direction, mode, impacts and bracket, the line's `tail`, the
/// transition's added cells, the line's `added` — or one row with the
/// transition's cells empty when it has none.
fn transition_rows<'a>(
    out: &mut String,
    line: &LineCells,
    shape: CrossingShape,
    crossings: impl ExactSizeIterator<Item = Crossing<'a>>,
) {
    if crossings.len() == 0 {
        let mut fields = line.head.clone();
        fields.extend(std::iter::repeat_n(String::new(), shape.levels + 5));
        fields.extend(line.tail.iter().cloned());
        fields.extend(std::iter::repeat_n(String::new(), shape.added));
        fields.extend(line.added.iter().cloned());
        row(out, &fields);
    }
    for t in crossings {
        let mut fields = line.head.clone();
        fields.extend(t.levels);
        fields.extend([
            cell(t.direction),
            cell(&t.mode),
            cell(&t.impacts),
            cell(&t.bracket[0]),
            cell(&t.bracket[1]),
        ]);
        fields.extend(line.tail.iter().cloned());
        fields.extend(t.added);
        fields.extend(line.added.iter().cloned());
        row(out, &fields);
    }
}

/// One row per transition of each block size (one empty row for a size
/// without any), with the size's minimum and rocking threshold.
/// The columns of a record spectrum's table.
const RECORD_SPECTRUM_COLUMNS: [&str; 25] = [
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
    "min_overturn_mode",
    "overturns_above_scale",
    "principal_min_overturn_scale",
    "principal_min_overturn_mode",
    "principal_overturns_above_scale",
    "min_overturn_in",
    "min_certain_overturn_scale",
    "min_certain_overturn_pga_g",
    "mixed_to",
    "mixed_fraction",
    "mixed_probes",
    "mixed_interval_95_lo",
    "mixed_interval_95_hi",
];

fn record_spectrum(r: &RecordSpectrumResult, out: &mut String) {
    row(out, &RECORD_SPECTRUM_COLUMNS.map(String::from));
    for line in &r.spectrum {
        let cells = LineCells {
            head: vec![cell(&line.p), cell(&line.r_m)],
            tail: vec![
                cell(&line.min_overturn_scale),
                cell(&line.min_overturn_pga_g),
                cell(&line.threshold_scale),
            ],
            added: vec![
                cell(&line.min_overturn_mode),
                cell(&line.overturns_above_scale),
                cell(&line.principal.min_overturn_scale),
                cell(&line.principal.min_overturn_mode),
                cell(&line.principal.overturns_above_scale),
                cell(&line.min_overturn_in),
                cell(&line.min_certain_overturn_scale),
                cell(&line.min_certain_overturn_pga_g),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
            ],
        };
        let crossings = line.transitions.iter().map(|t| Crossing {
            levels: vec![cell(&t.scale), cell(&t.pga_g)],
            direction: &t.direction,
            mode: t.mode,
            impacts: t.impacts,
            bracket: t.bracket,
            added: vec![],
        });
        let shape = CrossingShape {
            levels: 2,
            added: 0,
        };
        transition_rows(out, &cells, shape, crossings);
        for z in &line.mixed {
            let mut cells = mixed_cells("scale", z);
            cells.extend([("p_rad_s", cell(&line.p)), ("R_m", cell(&line.r_m))]);
            named_row(out, &RECORD_SPECTRUM_COLUMNS, &cells);
        }
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
            "a_p_g",
            "omega_ratio",
            "omega_p_rad_per_s",
            "frequency_hz",
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
                cell(&p.a_p_g),
                cell(&r.omega_ratio),
                cell(&r.omega_p),
                cell(&r.frequency_hz),
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
            .map_or(String::new(), |o| quote(&o.seen()))
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
/// Under a vertical motion a column `lift_off` counts the samples without
/// a verdict (p is over the others; empty when none was decided); where a
/// sample's history reached a bound on its work, a last column `undecided`
/// counts those.
fn fragility(r: &FragilityResult, out: &mut String) {
    let lift_off = r.stripes.iter().any(|s| s.lift_off.is_some());
    let undecided = r.stripes.iter().any(|s| s.undecided.is_some());
    let mut head: Vec<String> = [
        r.im.name(),
        "n",
        "overturned",
        "p",
        "p_lo_95",
        "p_hi_95",
        "mode_1",
        "mode_2",
    ]
    .map(String::from)
    .to_vec();
    if lift_off {
        head.push("lift_off".into());
    }
    if undecided {
        head.push("undecided".into());
    }
    row(out, &head);
    for s in &r.stripes {
        let mut cells = vec![
            cell(&s.im),
            cell(&s.n),
            cell(&s.overturned),
            cell(&s.p),
            cell(&s.interval_95[0]),
            cell(&s.interval_95[1]),
            cell(&s.mode_1),
            cell(&s.mode_2),
        ];
        if lift_off {
            cells.push(cell(&s.lift_off));
        }
        if undecided {
            cells.push(cell(&s.undecided.unwrap_or(0)));
        }
        row(out, &cells);
    }
}

/// A survival result: a row per rock and age (an uncertain age: its median,
/// marked), then the joint probability of several rocks (rock "all"); a
/// rock's fragility and rates are on each of its rows.
fn survival(r: &SurvivalResult, out: &mut String) {
    let median = format!("fragility_median_{}", r.im.name());
    row(
        out,
        &[
            "rock",
            "annual_toppling_rate_per_yr",
            "age_years",
            "age_uncertain",
            "survival_probability",
            "rate_scale_at_5_percent",
            &median,
            "fragility_beta",
            "mean_years_between_topplings",
            "extrapolated_share",
        ]
        .map(String::from),
    );
    for rock in &r.rocks {
        let ages = rock.ages.iter().map(|a| {
            (
                a.age_years,
                false,
                a.survival_probability,
                a.rate_scale_at_5_percent,
            )
        });
        let uncertain = rock.age_distribution.iter().map(|d| {
            (
                d.median_age_years,
                true,
                d.survival_probability,
                d.rate_scale_at_5_percent,
            )
        });
        for (age, uncertain, survival, scale) in ages.chain(uncertain) {
            row(
                out,
                &[
                    cell(&rock.name),
                    cell(&rock.annual_toppling_rate),
                    cell(&age),
                    cell(&uncertain),
                    cell(&survival),
                    cell(&scale),
                    cell(&rock.fragility.median),
                    cell(&rock.fragility.beta),
                    cell(&rock.mean_years_between_topplings),
                    cell(&rock.extrapolated_share),
                ],
            );
        }
    }
    if let Some(j) = &r.joint {
        let mut fields = vec![String::new(); 10];
        fields[0] = "all".into();
        fields[4] = cell(&j.survival_probability);
        fields[5] = cell(&j.rate_scale_at_5_percent);
        row(out, &fields);
    }
}

/// A record query: a row per consistent interval, first those consistent
/// with every observation (observation empty), then each observation's; an
/// observation that allows nothing has one row with empty ends. An
/// observation's rows carry the scale at which its block starts to rock.
/// The columns of a record forensic query's table.
const FORENSIC_RECORD_COLUMNS: [&str; 15] = [
    "observation",
    "observed",
    "consistent_lo_scale",
    "consistent_hi_scale",
    "consistent_lo_pga_g",
    "consistent_hi_pga_g",
    "threshold_scale",
    "mixed_lo_scale",
    "mixed_hi_scale",
    "mixed_lo_pga_g",
    "mixed_hi_pga_g",
    "mixed_fraction",
    "mixed_probes",
    "mixed_interval_95_lo",
    "mixed_interval_95_hi",
];

/// A row per certain interval (or one empty row when there is none), then
/// a row per mixed zone, for all observations (observation empty), then
/// for each.
fn forensic_record(r: &ForensicResult, out: &mut String) {
    row(out, &FORENSIC_RECORD_COLUMNS.map(String::from));
    let mut emit = |name: &str,
                    seen: String,
                    threshold: Option<f64>,
                    sets: [&[[f64; 2]]; 2],
                    zones: [&[crate::jobs::mixed::MixedDoc]; 2]| {
        let [scale, pga] = sets;
        let ends = scale
            .iter()
            .zip(pga)
            .map(|(s, g)| [s[0], s[1], g[0], g[1]].map(|x| cell(&x)));
        let none = scale.is_empty().then(<[String; 4]>::default);
        let blank = std::iter::repeat_n(String::new(), 8);
        for [scale_lo, scale_hi, pga_lo, pga_hi] in none.into_iter().chain(ends) {
            let mut fields = vec![
                quote(name),
                seen.clone(),
                scale_lo,
                scale_hi,
                pga_lo,
                pga_hi,
                cell(&threshold),
            ];
            fields.extend(blank.clone());
            row(out, &fields);
        }
        for (z, g) in zones[0].iter().zip(zones[1]) {
            let mut fields = vec![quote(name), seen.clone()];
            fields.extend(std::iter::repeat_n(String::new(), 4));
            fields.extend([
                cell(&threshold),
                cell(&z.from),
                cell(&z.to),
                cell(&g.from),
                cell(&g.to),
                cell(&z.fraction),
                cell(&z.probes),
                cell(&z.interval_95[0]),
                cell(&z.interval_95[1]),
            ]);
            row(out, &fields);
        }
    };
    emit(
        "",
        String::new(),
        None,
        [
            r.consistent_scale.as_deref().unwrap_or_default(),
            r.consistent_pga_g.as_deref().unwrap_or_default(),
        ],
        [
            r.mixed_scale.as_deref().unwrap_or_default(),
            r.mixed_pga_g.as_deref().unwrap_or_default(),
        ],
    );
    for (k, o) in r
        .per_observation
        .as_deref()
        .unwrap_or_default()
        .iter()
        .enumerate()
    {
        emit(
            &o.name,
            r.observations
                .get(k)
                .filter(|x| x.name == o.name && x.overturned == o.overturned)
                .map_or_else(|| seen(o.overturned), |o| quote(&o.seen())),
            Some(o.threshold_scale),
            [&o.consistent_scale, &o.consistent_pga_g],
            [&o.mixed_scale, &o.mixed_pga_g],
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
    #[serde(borrow)]
    ground_vertical_acceleration: Option<&'a serde_json::value::RawValue>,
    #[serde(borrow)]
    slide_m: Option<&'a serde_json::value::RawValue>,
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
        // A vertical motion's column in g is worked out, not copied: such a
        // table is rendered whole ([`to_csv`]).
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
            columns.ground_vertical_acceleration,
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
                fields.push(json_field(sample.as_ref()));
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
    use crate::jobs::names::Im;
    use crate::kinds::forensic::{
        ForensicFrequency, Observation, ObservationSet, RecordObservationSet,
    };
    use crate::kinds::fragility::StripeResult;
    use crate::kinds::friction_spectrum::FrictionPointDoc;
    use crate::kinds::spectrum::{PulseScalesDoc, SlidePointDoc};
    use crate::kinds::survival::{AgeDistributionResult, AgeResult, JointResult};
    use crate::kinds::time_history::{ImpactDoc, SeriesDoc};
    use crate::plot::tests::typed;
    use serde_json::json;

    pub(super) const TIME_HISTORY: &str = r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","omega_ratio":3,"a_p_alpha_g":2.5},"outputs":{"series":20}}"#;
    pub(super) const SPECTRUM: &str = r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"formulation":"linear","omega_ratio":[2,4],"a_max_alpha_g":6}"#;
    pub(super) const FRICTION: &str = r#"{"kind":"friction_spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},"omega_ratio":3,"a_alpha_g":[1.5,3]}"#;
    pub(super) const FORENSIC: &str = r#"{"kind":"forensic","pulse":{"type":"one_sine"},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false}],"frequency_hz":{"from":0.5,"to":2,"steps":3},"a_p_g":{"from":0.05,"to":2.0}}"#;
    pub(super) const FORENSIC_RECORD: &str = r#"{"kind":"forensic","ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]},"observations":[{"name":"transformer","b":0.6,"h":1.2,"overturned":false}],"pga_g":{"from":0.05,"to":2.0}}"#;
    pub(super) const RECORD_SPECTRUM: &str = r#"{"kind":"record_spectrum","block":{"alpha":0.2},"p":[1.5,3],"scale":{"from":0.5,"to":3},"ground_motion":{"dt":0.02,"unit":"g","acc":[0,0.1,0.3,0.2,-0.3,-0.2,0.1,0]}}"#;
    pub(super) const SURVIVAL: &str = r#"{"kind":"survival","hazard":{"im":"pga_g","points":[[0.1,0.01],[0.5,0.0005],[1.0,0.00005]]},"fragility":{"median_g":0.4,"beta":0.4},"age_years":[1000]}"#;
    pub(super) const FRAGILITY: &str = r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","omega_ratio":3},"stripes":[0.2,0.4],"samples":8,"seed":1}"#;

    pub(super) fn lines(csv: &str) -> Vec<&str> {
        csv.lines().collect()
    }

    /// `x` as serde_json writes it.
    pub(super) fn json_text<T: serde::Serialize>(x: &T) -> String {
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
    fn fields_of_options_flags_and_counts() {
        assert_eq!(cell(&1.0), "1.0");
        assert_eq!(cell(&0.30000000000000004), "0.3");
        assert_eq!(cell(&f64::NAN), "");
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
                cell(&s.t[k]),
                cell(&s.theta[k]),
                cell(&s.theta_dot[k]),
                cell(&s.ground_acceleration[k]),
                ratio[k].map_or_else(String::new, |x| cell(&x)),
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
            ground_vertical_acceleration: None,
            fx_over_fz: Some(vec![Some(0.0), Some(0.25), None]),
            slide_m: None,
            mode: None,
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
    fn a_vertical_ground_motion_adds_its_column_at_the_end() {
        let spec = TIME_HISTORY.replace(r#""outputs":"#, r#""vertical":{"ratio":-0.6},"outputs":"#);
        let r = match typed(&spec) {
            JobResult::TimeHistory(r) => *r,
            other => panic!("not a time history: {:?}", other.job_kind()),
        };
        let s = r.series.clone().expect("a series");
        let vertical = s
            .ground_vertical_acceleration
            .clone()
            .expect("the vertical acceleration");
        assert_eq!(vertical.len(), s.t.len());
        let csv = th_table(&r);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "t_s,theta_rad,theta_dot_rad_per_s,ground_acceleration_m_per_s2,fx_over_fz,ground_vertical_acceleration_m_per_s2,ug_v_g"
        );
        assert_eq!(l.len(), s.t.len() + 1);
        let g = r.spec.block.g;
        for k in 0..s.t.len() {
            let mut fields = l[k + 1].rsplit(',');
            let in_g = fields.next().expect("a field");
            let m_s2 = fields.next().expect("a field");
            assert_eq!(m_s2, cell(&vertical[k]), "row {k}");
            assert_eq!(in_g, cell(&(vertical[k] / g)), "row {k}");
        }
        // ü_v = −0.6 ü_g while the pulse lasts: some rows hold both.
        assert!(vertical.iter().any(|v| *v != 0.0));
        // Not streamed from the stored document: its column in g is worked out.
        let text = serde_json::to_string(&r).expect("json");
        assert!(SeriesRows::of(&text).is_none());
        // Without a vertical motion there is no such column.
        assert!(!th_table(&time_history_result()).contains("vertical"));
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
                cell(&i.t),
                cell(&i.theta_dot_before),
                cell(&i.theta_dot_after)
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
            ground_vertical_acceleration: None,
            fx_over_fz: None,
            slide_m: None,
            mode: None,
        });
        r.impacts = None;
        r.rocked = false;
        r.overturned = false;
        r.overturn_direction = None;
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
        (r.rocking_starts, r.chatter_impacts_summed, r.decided_at) = (0, 0, 1.0);
        r.peak_friction_demand_time = None;
        r.friction_demand_followed_until = None;
        r.ground_peaks.pga_m_s2 = 2.5 * 0.25 * 9.81;
        r.ground_peaks.pga_g = 0.625;
        r.ground_peaks.pgv_m_s = 0.43;
        r.ground_peaks.pgd_m = 0.07;
        r.ground_peaks.pgv_over_pga_s = 0.07;
        assert_eq!(
            lines(&th_table(&r)),
            vec![
                "rocked,overturned,mode,impact_count,rocking_start_s,overturn_time_s,rest_time_s,end_time_s,peak_theta_over_alpha,peak_friction_demand,initiation_friction_demand,lift_off,lift_off_time_s,\
                 rocking_starts,chatter_impacts_summed,decided_at_s,peak_friction_demand_time_s,friction_demand_followed_until_s,pga_m_per_s2,pga_g,pgv_m_per_s,pgd_m,pgv_over_pga_s,overturn_direction",
                "false,false,,0,,,,1.0,0.0,,,,,0,0,1.0,,,6.13125,0.625,0.43,0.07,0.07,",
            ]
        );
        r.overturned = true;
        r.mode = Some(2);
        r.overturn_time = Some(0.75);
        r.peak_friction_demand = Some(0.3);
        r.lift_off = Some(false);
        (r.rocking_starts, r.chatter_impacts_summed, r.decided_at) = (1, 3, 0.5);
        r.peak_friction_demand_time = Some(0.25);
        r.friction_demand_followed_until = Some(0.6);
        r.overturn_direction = Some(-1.0);
        assert_eq!(
            lines(&th_table(&r))[1],
            "false,true,2,0,,0.75,,1.0,0.0,0.3,,false,,1,3,0.5,0.25,0.6,6.13125,0.625,0.43,0.07,0.07,-1.0"
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
            "omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo_alpha_g,bracket_hi_alpha_g,min_overturn_alpha_g,eq21_alpha_g,threshold_alpha_g,closed_form_mode2_alpha_g,\
             a_g,omega_p_rad_per_s,frequency_hz,threshold_g,min_overturn_g,min_overturn_m_per_s2,min_overturn_mode,overturns_above_alpha_g,\
             pgv_over_pga_s,pgd_over_pga_s2,principal_min_overturn_alpha_g,principal_min_overturn_mode,principal_overturns_above_alpha_g,\
             min_overturn_in,min_certain_overturn_alpha_g,mixed_to,mixed_fraction,mixed_probes,mixed_interval_95_lo,mixed_interval_95_hi"
        );
        let rows: usize = r
            .spectrum
            .iter()
            .map(|f| f.transitions.len().max(1) + f.mixed.len())
            .sum();
        assert_eq!(l.len(), 1 + rows);
        let line = &r.spectrum[0];
        let t = line.transitions.first().expect("a transition below a_max");
        assert!(
            l[1].starts_with(&format!(
                "{},{},{},{},{},{},{},{},{},{},{},",
                cell(&line.omega_ratio),
                cell(&t.a_alpha_g),
                t.direction,
                t.mode,
                t.impacts,
                cell(&t.bracket[0]),
                cell(&t.bracket[1]),
                line.min_overturn_alpha_g
                    .map_or_else(String::new, |x| cell(&x)),
                line.eq21_alpha_g.map_or_else(String::new, |x| cell(&x)),
                cell(&line.threshold_alpha_g),
                line.closed_form_mode2_alpha_g
                    .map_or_else(String::new, |x| cell(&x)),
            )),
            "{}",
            l[1]
        );
        // Set values: one line with two transitions, one without any.
        let mut second = r.spectrum[0].clone();
        let (mut first, up) = set_line(&r.spectrum[0]);
        let mut down = up.clone();
        (down.a_alpha_g, down.direction, down.bracket) = (2.37, "down".into(), [2.3699, 2.3701]);
        down.a_g = 0.5925;
        first.transitions = vec![up, down];
        (second.omega_ratio, second.threshold_alpha_g) = (10.0, 1.0);
        (second.min_overturn_alpha_g, second.eq21_alpha_g) = (None, Some(2.67));
        second.closed_form_mode2_alpha_g = None;
        (second.omega_p, second.frequency_hz, second.threshold_g) = (21.4, 3.4, 0.25);
        (second.min_overturn_g, second.min_overturn_m_s2) = (None, None);
        (second.min_overturn_mode, second.overturns_above_alpha_g) = (None, None);
        second.ground = PulseScalesDoc {
            pgv_over_pga_s: 0.046,
            pgd_over_pga_s2: 0.0015,
        };
        second.principal.min_overturn_alpha_g = None;
        second.principal.min_overturn_mode = None;
        second.principal.overturns_above_alpha_g = None;
        (second.min_overturn_in, second.min_certain_overturn_alpha_g) = (None, None);
        (second.mixed, second.min_overturn_zone) = (vec![], None);
        second.transitions = vec![];
        r.spectrum = vec![first, second];
        let csv = to_csv(&JobResult::Spectrum(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,",
                "2.0,2.37,down,1,1,2.3699,2.3701,1.25,1.33,1.0,,\
                 0.5925,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,",
                "10.0,,,,,,,,2.67,1.0,,,21.4,3.4,0.25,,,,,0.046,0.0015,,,,,,,,,,",
            ]
        );
    }

    /// `line` with set values (ω_p/p = 2, overturning from 1.25 αg in mode 1
    /// up to 2.37 αg), and its first transition set to an "up" at 1.25 αg.
    fn set_line(
        line: &crate::kinds::spectrum::FrequencyDoc,
    ) -> (
        crate::kinds::spectrum::FrequencyDoc,
        crate::kinds::spectrum::TransitionDoc,
    ) {
        let mut first = line.clone();
        let mut up = first.transitions[0].clone();
        (first.omega_ratio, first.threshold_alpha_g) = (2.0, 1.0);
        (first.min_overturn_alpha_g, first.eq21_alpha_g) = (Some(1.25), Some(1.33));
        first.closed_form_mode2_alpha_g = None;
        (first.omega_p, first.frequency_hz, first.threshold_g) = (4.28, 0.68, 0.25);
        (first.min_overturn_g, first.min_overturn_m_s2) = (Some(0.3125), Some(3.07));
        (first.min_overturn_mode, first.overturns_above_alpha_g) = (Some(1), Some(2.37));
        first.ground = PulseScalesDoc {
            pgv_over_pga_s: 0.23,
            pgd_over_pga_s2: 0.037,
        };
        first.principal.min_overturn_alpha_g = Some(1.25);
        first.principal.min_overturn_mode = Some(1);
        first.principal.overturns_above_alpha_g = Some(1.25);
        (first.min_overturn_in, first.min_certain_overturn_alpha_g) =
            (Some("band".into()), Some(1.25));
        (first.mixed, first.min_overturn_zone) = (vec![], None);
        (up.a_alpha_g, up.direction, up.mode, up.impacts) = (1.25, "up".into(), 1, 1);
        (up.bracket, up.a_g) = ([1.2499, 1.2501], 0.3125);
        (first, up)
    }

    /// The header of a spectrum's table without residual slides or the
    /// pure-rocking spectrum beside: as it has always been.
    const SPECTRUM_HEADER: &str = "omega_ratio,a_alpha_g,direction,mode,impacts,bracket_lo_alpha_g,bracket_hi_alpha_g,min_overturn_alpha_g,eq21_alpha_g,threshold_alpha_g,closed_form_mode2_alpha_g,\
         a_g,omega_p_rad_per_s,frequency_hz,threshold_g,min_overturn_g,min_overturn_m_per_s2,min_overturn_mode,overturns_above_alpha_g,\
         pgv_over_pga_s,pgd_over_pga_s2,principal_min_overturn_alpha_g,principal_min_overturn_mode,principal_overturns_above_alpha_g,\
         min_overturn_in,min_certain_overturn_alpha_g,mixed_to,mixed_fraction,mixed_probes,mixed_interval_95_lo,mixed_interval_95_hi";

    #[test]
    fn spectrum_residual_slides_and_the_lines_beside_have_rows_of_their_own() {
        let JobResult::Spectrum(mut r) = typed(SPECTRUM) else {
            panic!("a spectrum")
        };
        assert_eq!(r.spec.block.alpha, 0.25);
        // One line with a transition and two residual-slide points; beside
        // it, one line without any transition.
        let mut beside = r.spectrum[0].clone();
        let (mut first, up) = set_line(&r.spectrum[0]);
        first.transitions = vec![up];
        first.residual_slide = Some(vec![
            SlidePointDoc {
                a_alpha_g: 1.0,
                residual_slide_m: 0.0,
                peak_slide_m: 0.0,
                outcome: "stands".into(),
            },
            SlidePointDoc {
                a_alpha_g: 2.0,
                residual_slide_m: -0.0123,
                peak_slide_m: 0.0456,
                outcome: "overturns".into(),
            },
        ]);
        (beside.omega_ratio, beside.threshold_alpha_g) = (10.0, 1.0);
        (beside.min_overturn_alpha_g, beside.eq21_alpha_g) = (None, Some(2.67));
        beside.closed_form_mode2_alpha_g = None;
        (beside.omega_p, beside.frequency_hz, beside.threshold_g) = (21.4, 3.4, 0.25);
        (beside.min_overturn_g, beside.min_overturn_m_s2) = (None, None);
        (beside.min_overturn_mode, beside.overturns_above_alpha_g) = (None, None);
        beside.ground = PulseScalesDoc {
            pgv_over_pga_s: 0.046,
            pgd_over_pga_s2: 0.0015,
        };
        beside.principal.min_overturn_alpha_g = None;
        beside.principal.min_overturn_mode = None;
        beside.principal.overturns_above_alpha_g = None;
        (beside.min_overturn_in, beside.min_certain_overturn_alpha_g) = (None, None);
        (beside.mixed, beside.min_overturn_zone) = (vec![], None);
        beside.transitions = vec![];
        beside.residual_slide = None;
        r.spectrum = vec![first];
        r.no_sliding = vec![beside];
        let table = |r: &SpectrumResult| to_csv(&JobResult::Spectrum(Box::new(r.clone())));
        let csv = table(&r);
        assert_eq!(
            lines(&csv),
            [
                format!("{SPECTRUM_HEADER},residual_slide_m,peak_slide_m,outcome,floor").as_str(),
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,,,,,coulomb",
                "2.0,1.0,residual_slide,,,,,,,,,0.25,4.28,0.68,,,,,,,,,,,,,,,,,,0.0,0.0,stands,coulomb",
                "2.0,2.0,residual_slide,,,,,,,,,0.5,4.28,0.68,,,,,,,,,,,,,,,,,,-0.0123,0.0456,overturns,coulomb",
                "10.0,,,,,,,,2.67,1.0,,,21.4,3.4,0.25,,,,,0.046,0.0015,,,,,,,,,,,,,,no_sliding",
            ]
        );
        // Residual slides alone: no `floor`.
        let mut alone = r.clone();
        alone.no_sliding = vec![];
        let csv = table(&alone);
        let l = lines(&csv);
        assert_eq!(
            l[0],
            format!("{SPECTRUM_HEADER},residual_slide_m,peak_slide_m,outcome")
        );
        assert_eq!(l.len(), 4);
        assert_eq!(
            l[3],
            "2.0,2.0,residual_slide,,,,,,,,,0.5,4.28,0.68,,,,,,,,,,,,,,,,,,-0.0123,0.0456,overturns"
        );
        // The lines beside alone: `floor` right after the usual columns.
        let mut beside_only = r.clone();
        beside_only.spectrum[0].residual_slide = None;
        let csv = table(&beside_only);
        assert_eq!(
            lines(&csv),
            [
                format!("{SPECTRUM_HEADER},floor").as_str(),
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,,coulomb",
                "10.0,,,,,,,,2.67,1.0,,,21.4,3.4,0.25,,,,,0.046,0.0015,,,,,,,,,,,no_sliding",
            ]
        );
        // Neither: the table as it was.
        let mut neither = beside_only;
        neither.no_sliding = vec![];
        let csv = table(&neither);
        assert_eq!(
            lines(&csv),
            [
                SPECTRUM_HEADER,
                "2.0,1.25,up,1,1,1.2499,1.2501,1.25,1.33,1.0,,\
                 0.3125,4.28,0.68,0.25,0.3125,3.07,1,2.37,0.23,0.037,1.25,1,1.25,band,1.25,,,,,",
            ]
        );
    }

    #[test]
    fn a_coulomb_spectrum_lists_its_residual_slides_and_the_pure_rocking_lines() {
        // The locomotive on μ = 0.3 on a coarse grid (as the spectrum's own
        // tests run it), with its residual slides and pure rocking beside.
        let doc = crate::plot::tests::computed(
            r#"{"kind":"spectrum","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine"},
                "omega_ratio":[3,6],"a_max_alpha_g":4,"tolerance":1e-3,"scan_step_alpha_g":0.05,
                "contact":{"model":"coulomb","mu":0.3},"residual_slide":{"steps":4},"no_sliding_beside":true}"#,
        );
        let JobResult::Spectrum(r) = JobResult::from_value(doc.clone()).expect("typed") else {
            panic!("a spectrum")
        };
        let csv = to_csv(&JobResult::Spectrum(r.clone()));
        let l = lines(&csv);
        let header: Vec<&str> = l[0].split(',').collect();
        assert_eq!(
            l[0],
            format!("{SPECTRUM_HEADER},residual_slide_m,peak_slide_m,outcome,floor")
        );
        let at = |name: &str| header.iter().position(|h| *h == name).expect(name);
        let rows: Vec<Vec<&str>> = l[1..].iter().map(|r| r.split(',').collect()).collect();
        assert!(rows.iter().all(|c| c.len() == header.len()), "{csv}");
        // A row per transition (or one) of each line, a row per point of
        // its residual slide; then the lines beside, without residual slides.
        let lines_of = |key: &str| doc[key].as_array().expect("lines").clone();
        let (floor, beside) = (lines_of("spectrum"), lines_of("no_sliding"));
        assert_eq!((floor.len(), beside.len()), (2, 2));
        let count = |line: &Value, key: &str| line[key].as_array().map_or(0, Vec::len);
        let points: usize = floor.iter().map(|f| count(f, "residual_slide")).sum();
        assert_eq!(points, 2 * 4);
        let transition_rows = |lines: &[Value]| -> usize {
            lines.iter().map(|f| count(f, "transitions").max(1)).sum()
        };
        let on_floor = transition_rows(&floor) + points;
        assert_eq!(rows.len(), on_floor + transition_rows(&beside));
        let direction = at("direction");
        let residual: Vec<&Vec<&str>> = rows
            .iter()
            .filter(|c| c[direction] == "residual_slide")
            .collect();
        assert_eq!(residual.len(), points);
        assert!(beside.iter().all(|f| f.get("residual_slide").is_none()));
        // `floor`: coulomb, then no_sliding.
        let floors: Vec<&str> = rows.iter().map(|c| c[at("floor")]).collect();
        assert!(floors[..on_floor].iter().all(|f| *f == "coulomb"), "{csv}");
        assert!(
            floors[on_floor..].iter().all(|f| *f == "no_sliding"),
            "{csv}"
        );
        // A residual row holds its point and its frequency; nothing else.
        let number = |v: &Value| cell(&v.as_f64().expect("a number"));
        for (k, line) in floor.iter().enumerate() {
            let mine: Vec<&&Vec<&str>> = residual
                .iter()
                .filter(|c| c[0] == number(&line["omega_ratio"]))
                .collect();
            let line_points = line["residual_slide"].as_array().expect("asked");
            assert_eq!(mine.len(), line_points.len(), "line {k}");
            for (c, p) in mine.iter().zip(line_points) {
                let a = p["a_alpha_g"].as_f64().expect("αg");
                let text = p["outcome"].as_str().expect("outcome").to_string();
                let expected = [
                    ("omega_ratio", number(&line["omega_ratio"])),
                    ("a_alpha_g", number(&p["a_alpha_g"])),
                    ("a_g", cell(&(a * 0.25))),
                    ("omega_p_rad_per_s", number(&line["omega_p"])),
                    ("frequency_hz", number(&line["frequency_hz"])),
                    ("residual_slide_m", number(&p["residual_slide_m"])),
                    ("peak_slide_m", number(&p["peak_slide_m"])),
                    ("outcome", text),
                    ("floor", "coulomb".to_string()),
                ];
                for (name, value) in &expected {
                    assert_eq!(c[at(name)], value.as_str(), "{name} in {c:?}");
                }
                for (j, field) in c.iter().enumerate() {
                    let filled = expected.iter().any(|(n, _)| at(n) == j) || j == direction;
                    assert!(filled || field.is_empty(), "{} in {c:?}", header[j]);
                }
            }
        }
        // The points are at a_max·k/4, k = 1…4, of each line in turn.
        let levels: Vec<&str> = residual.iter().map(|c| c[at("a_alpha_g")]).collect();
        assert_eq!(
            levels,
            ["1.0", "2.0", "3.0", "4.0", "1.0", "2.0", "3.0", "4.0"]
        );
        // Transition rows leave the slide columns empty.
        for c in rows.iter().filter(|c| c[direction] != "residual_slide") {
            for name in ["residual_slide_m", "peak_slide_m", "outcome"] {
                assert!(c[at(name)].is_empty(), "{name} in {c:?}");
            }
        }
        // Without them, the table of the floor's lines as it always was.
        let mut plain = *r;
        plain.no_sliding = vec![];
        for line in &mut plain.spectrum {
            line.residual_slide = None;
        }
        let csv = to_csv(&JobResult::Spectrum(Box::new(plain.clone())));
        let l = lines(&csv);
        assert_eq!(l[0], SPECTRUM_HEADER);
        assert_eq!(l.len(), 1 + transition_rows(&floor));
        assert!(l.iter().all(|r| r.split(',').count() == 31), "{csv}");
        assert!(!csv.contains("residual_slide") && !csv.contains("coulomb"));
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
        let csv = to_csv(&JobResult::RecordSpectrum(r));
        assert_eq!(
            lines(&csv)[1..],
            [
                "1.5,4.36,2.5,0.75,up,2,0,2.49,2.51,2.5,0.75,0.4,2,2.5,2.5,2,2.5,band,2.5,0.75,,,,,",
                "3.0,1.09,,,,,,,,,,0.5,,,,,,,,,,,,,",
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
        let csv = to_csv(&JobResult::FrictionSpectrum(r));
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

    /// Under a vertical motion a last column counts the lift-offs, and a
    /// stripe whose every sample lifted off has an empty p and interval.
    #[test]
    fn fragility_rows_count_lift_offs_under_a_vertical_motion() {
        let JobResult::Fragility(r) = typed(
            r#"{"kind":"fragility","block":{"alpha":0.2,"p":2.0},"pulse":{"type":"one_sine","frequency_hz":0.8},"vertical":{"ratio":-0.5},"stripes":[0.3,3.0],"samples":4,"seed":1}"#,
        ) else {
            panic!("a fragility")
        };
        let csv = to_csv(&JobResult::Fragility(r.clone()));
        let l = lines(&csv);
        assert_eq!(
            l[0],
            "pga_g,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2,lift_off"
        );
        assert_eq!(r.stripes[0].lift_off, Some(0));
        assert!(l[1].ends_with(",0"), "{}", l[1]);
        assert_eq!(r.stripes[1].lift_off, Some(4), "{:?}", r.stripes[1]);
        assert_eq!(l[2], "3.0,4,0,,,,0,0,4");
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
                cell(&s.im),
                s.n,
                s.overturned,
                cell(&s.p),
                cell(&s.interval_95[0]),
                cell(&s.interval_95[1]),
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
            lift_off: None,
            undecided: None,
        }];
        r.im = Im::PgvMS;
        let csv = to_csv(&JobResult::Fragility(r.clone()));
        assert_eq!(
            lines(&csv),
            vec![
                "pgv_m_s,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2",
                "0.3,200,58,0.29,0.23,0.35,58,0",
            ]
        );
        // Samples whose history reached a bound on its work: a last column.
        r.stripes[0].undecided = Some(3);
        let csv = to_csv(&JobResult::Fragility(r));
        assert_eq!(
            lines(&csv),
            vec![
                "pgv_m_s,n,overturned,p,p_lo_95,p_hi_95,mode_1,mode_2,undecided",
                "0.3,200,58,0.29,0.23,0.35,58,0,3",
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
                "rock,annual_toppling_rate_per_yr,age_years,age_uncertain,survival_probability,rate_scale_at_5_percent,\
                 fragility_median_pga_g,fragility_beta,mean_years_between_topplings,extrapolated_share".to_string(),
                format!(
                    "{},{},1000.0,false,{},{},0.4,0.4,{},{}",
                    rock.name,
                    cell(&rock.annual_toppling_rate),
                    cell(&age.survival_probability),
                    cell(&age.rate_scale_at_5_percent.expect("it can topple")),
                    cell(&rock.mean_years_between_topplings.expect("it can topple")),
                    cell(&rock.extrapolated_share),
                ),
            ]
        );
        let mut grass = rock.clone();
        (grass.name, grass.annual_toppling_rate) = ("Grass Valley".into(), 1.5e-4);
        (grass.fragility.median, grass.fragility.beta) = (0.3, 0.5);
        grass.mean_years_between_topplings = Some(6666.7);
        grass.extrapolated_share = 0.01;
        grass.ages = vec![AgeResult {
            age_years: 1000.0,
            survival_probability: 0.86,
            rate_scale_at_5_percent: Some(20.0),
        }];
        grass.age_distribution = None;
        let mut b = rock.clone();
        (b.name, b.annual_toppling_rate, b.ages) = ("b".into(), 1e-4, vec![]);
        (b.fragility.median, b.fragility.beta) = (5.0, 0.0);
        (b.mean_years_between_topplings, b.extrapolated_share) = (None, 0.0);
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
                "Grass Valley,0.00015,1000.0,false,0.86,20.0,0.3,0.5,6666.7,0.01",
                "b,0.0001,9000.0,true,0.4,,5.0,0.0,,0.0",
                "all,,,,0.344,2.5,,,,",
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
        let csv = to_csv(&JobResult::Forensic(r));
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

    #[test]
    fn unknown_kinds_have_no_table() {
        // A table is made of a result of a known kind; a document of another
        // kind is not read into one.
        assert!(JobResult::from_value(json!({"kind": "teapot"})).is_err());
    }
}
