//! Forensic maps: in the (pulse frequency, amplitude) plane, the pulses
//! consistent with every observation filled; what each observation rules out
//! tinted in its colour and its boundary drawn in that colour; the bounds of
//! the consistent region framed.
//!
//! Each computed frequency is a cell of its own, reaching half-way to its
//! neighbours; the map ends at the first and last computed frequencies.
//! Nothing is interpolated between frequencies: a forensic query samples
//! the frequencies it was asked for, and what lies between them is unknown.

use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::jobs::contact::ContactNorm;
use crate::kinds::forensic::{ForensicFrequency, ForensicResult, Observation};
use crate::plot::bands::{Band, Column, Piece, cell_edges, cells, simplify, tile};
use crate::plot::style::{
    AXIS, Area, CONSISTENT, Chart, Drawn, INK, LEGEND, LEGEND_WIDTH, Legend, MIXED, OBSERVATIONS,
    Swatch, TICKS, X_LABEL_AREA, axis_range, chart_on, draw_legend, fmt_num, text, tick, tint,
};
use crate::plot::{block_text, render, shape_title};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;

/// The intervals `[lo, hi]` of a list, those with `hi` below `lo` left out.
pub(crate) fn intervals(list: &[[f64; 2]]) -> Vec<(f64, f64)> {
    list.iter()
        .map(|&[lo, hi]| (lo, hi))
        .filter(|(lo, hi)| hi >= lo)
        .collect()
}

fn contains(set: &[(f64, f64)], a: f64) -> bool {
    set.iter().any(|&(lo, hi)| a >= lo && a <= hi)
}

/// How many separate consistent intervals the frequencies hold in all.
fn envelope_count(frequencies: &[ForensicFrequency]) -> usize {
    frequencies
        .iter()
        .map(|f| intervals(&f.consistent_g).len())
        .sum()
}

/// The class of a mixed zone: the outcome alternates finer than the scan
/// resolves, and no observation rules it out with certainty.
pub const MIXED_CLASS: usize = usize::MAX - 1;

/// The colour of an observation.
pub fn colour(k: usize) -> RGBColor {
    OBSERVATIONS[k % OBSERVATIONS.len()]
}

/// The fill of the amplitudes ruled out by the observations in `mask`
/// (0: consistent with all).
pub fn fill(mask: usize) -> RGBColor {
    if mask == 0 {
        return CONSISTENT;
    }
    if mask == MIXED_CLASS {
        return MIXED;
    }
    let members: Vec<RGBColor> = (0..usize::BITS as usize)
        .filter(|k| mask >> k & 1 == 1)
        .map(colour)
        .collect();
    if members.len() == 1 {
        return tint(members[0], 0.33);
    }
    let n = members.len() as f64;
    let avg = |f: fn(&RGBColor) -> u8| {
        (members.iter().map(|c| f64::from(f(c))).sum::<f64>() / n).round() as u8
    };
    tint(RGBColor(avg(|c| c.0), avg(|c| c.1), avg(|c| c.2)), 0.55)
}

/// Cuts `[from, to]` where any observation's consistent set begins or ends;
/// each piece is labelled with the observations that rule it out.
pub fn partition(sets: &[Vec<(f64, f64)>], from: f64, to: f64) -> Vec<Band> {
    let mut cuts: Vec<f64> = sets
        .iter()
        .flatten()
        .flat_map(|&(lo, hi)| [lo, hi])
        .filter(|a| *a > from && *a < to)
        .chain([from, to])
        .collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut out: Vec<Band> = Vec::new();
    for w in cuts.windows(2) {
        let mid = 0.5 * (w[0] + w[1]);
        let mask = sets
            .iter()
            .enumerate()
            .filter(|(_, s)| !contains(s, mid))
            .fold(0usize, |m, (k, _)| m | 1 << (k % usize::BITS as usize));
        match out.last_mut() {
            Some(last) if last.class == mask => last.hi = w[1],
            _ => out.push(Band {
                lo: w[0],
                hi: w[1],
                class: mask,
            }),
        }
    }
    out
}

/// One column per computed frequency: its amplitudes `from`–`to` g cut into
/// bands labelled with the observations (of `names`) that rule them out (0:
/// consistent with all).
fn columns(frequencies: &[ForensicFrequency], names: &[String], from: f64, to: f64) -> Vec<Column> {
    let gap = (to - from) / 900.0;
    let mut map = Vec::new();
    for f in frequencies {
        let listed = &f.per_observation;
        let sets: Vec<Vec<(f64, f64)>> = names
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let entry = listed.iter().find(|o| &o.name == name).or(listed.get(k));
                entry
                    .map(|o| intervals(&o.consistent_g))
                    .unwrap_or_default()
            })
            .collect();
        let zones: Vec<[f64; 2]> = f.mixed_g.iter().map(|z| [z.from, z.to]).collect();
        let mut bands = if sets.is_empty() {
            let all: Vec<Band> = intervals(&f.consistent_g)
                .into_iter()
                .map(|(lo, hi)| Band { lo, hi, class: 0 })
                .collect();
            tile(from, to, &all, 1)
        } else {
            partition(&sets, from, to)
        };
        // Where every observation is consistent or mixed: a mixed zone.
        if !zones.is_empty() {
            bands = tile(
                from,
                to,
                &crate::plot::bands::over(&bands, &zones, MIXED_CLASS),
                0,
            );
        }
        // Slivers of consistent pulses, and mixed zones, stay however narrow.
        simplify(&mut bands, gap, |class| class == 0 || class == MIXED_CLASS);
        map.push(Column {
            x: f.frequency_hz,
            bands,
        });
    }
    map
}

/// The frame drawn around the bounds of the consistent region, dashed, its
/// highest and lowest levels labelled inside the chart.
pub(crate) struct Frame {
    /// Its left and right edges.
    pub x: (f64, f64),
    /// Its lowest and highest levels.
    pub y: (f64, f64),
    /// The chart's range of levels: a label too near one of its ends
    /// stands on the other side of its level.
    pub range: (f64, f64),
    /// Where the labels stand: at x, moved right by px, aligned.
    pub labels_at: (f64, i32, HPos),
    /// The labels of the highest and the lowest level.
    pub labels: [String; 2],
}

/// Draws `frame` on `chart`.
pub(crate) fn draw_frame(chart: &mut Chart<'_, '_>, frame: Frame) -> Drawn {
    let ((a, b), (lo, hi), (from, to)) = (frame.x, frame.y, frame.range);
    chart.draw_series(std::iter::once(DashedPathElement::new(
        vec![(a, lo), (b, lo), (b, hi), (a, hi), (a, lo)],
        8,
        5,
        INK.stroke_width(2),
    )))?;
    let (x, dx, align) = frame.labels_at;
    let label = |s: String, y: f64, above: bool| {
        let (v, dy) = if above {
            (VPos::Bottom, -5)
        } else {
            (VPos::Top, 5)
        };
        EmptyElement::at((x, y)) + Text::new(s, (dx, dy), text(LEGEND, INK).pos(Pos::new(align, v)))
    };
    let room = 0.06 * (to - from);
    let [highest, lowest] = frame.labels;
    chart.draw_series([
        label(highest, hi, hi < to - room),
        label(lowest, lo, lo < from + room),
    ])?;
    Ok(())
}

/// The legend's note of each observation's block.
pub(crate) fn block_notes(legend: &mut Legend, names: &[String], observations: &[Observation]) {
    for (name, o) in names.iter().zip(observations) {
        legend.note(format!("{name}: {}", block_text(&o.block)));
    }
}

/// The legend's note on a Coulomb floor under the observed blocks.
pub(crate) fn sliding_note(contact: &ContactNorm) -> String {
    format!(
        "{}: the blocks may slide and slide-rock",
        crate::plot::floor_note(contact)
    )
}

/// A forensic map as drawn: its cells, the observations' boundaries and
/// the bounds of the consistent region.
struct Map<'a> {
    result: &'a ForensicResult,
    /// The observations' names.
    names: Vec<String>,
    /// The amplitude range, g.
    from: f64,
    to: f64,
    /// The computed frequencies in order, Hz.
    xs: Vec<f64>,
    /// The cell of each frequency, Hz.
    edges: Vec<(f64, f64)>,
    /// The frequency range drawn, Hz.
    x0: f64,
    x1: f64,
    /// The cells' pieces, the consistent ones last.
    shaded: Vec<Piece>,
    /// The boundary of each observation: where its verdict changes across
    /// an edge.
    boundaries: Vec<Vec<[(f64, f64); 2]>>,
    /// Some pulse is consistent with every observation.
    consistent_anywhere: bool,
}

impl<'a> Map<'a> {
    fn of(result: &'a ForensicResult) -> Result<Map<'a>, String> {
        let (from, to) = (result.a_p_g.from, result.a_p_g.to);
        if to.partial_cmp(&from) != Some(std::cmp::Ordering::Greater) {
            return Err(format!("empty amplitude range {from}–{to} g"));
        }
        let names: Vec<String> = result.observations.iter().map(|o| o.name.clone()).collect();
        let frequencies = &result.frequencies;
        if frequencies.is_empty() {
            return Err("the forensic result has no frequencies".into());
        }
        let mut map = columns(frequencies, &names, from, to);
        map.sort_by(|a, b| a.x.total_cmp(&b.x));
        let xs: Vec<f64> = map.iter().map(|c| c.x).collect();
        // A lone frequency is a cell a fifth of itself wide.
        let half = 0.1 * xs[0].max(0.01);
        let edges = cell_edges(&xs, half);
        let (x0, x1) = (edges[0].0, edges[edges.len() - 1].1);
        let drawn = cells(&map, half);
        let mut shaded = drawn.pieces;
        // The consistent region on top: nothing hides a sliver of it.
        shaded.sort_by_key(|p| p.class == 0);
        let boundaries: Vec<Vec<[(f64, f64); 2]>> = (0..names.len())
            .map(|k| {
                let bit = 1usize << (k % usize::BITS as usize);
                drawn
                    .edges
                    .iter()
                    .filter(|e| (e.a ^ e.b) & bit != 0)
                    .map(|e| e.segment)
                    .collect()
            })
            .collect();
        let consistent_anywhere = shaded.iter().any(|p| p.class == 0);
        Ok(Map {
            result,
            names,
            from,
            to,
            xs,
            edges,
            x0,
            x1,
            shaded,
            boundaries,
            consistent_anywhere,
        })
    }

    /// The lowest and highest computed frequencies, Hz.
    fn frequency_range(&self) -> (f64, f64) {
        (self.xs[0], self.xs[self.xs.len() - 1])
    }
}

/// The pulse family's name in the figure: "one-sine".
fn pulse_name(result: &ForensicResult) -> String {
    result
        .pulse
        .as_ref()
        .or(result.spec.pulse.as_ref())
        .map_or_else(|| "pulse".to_string(), |p| shape_title(p.shape()))
}

/// The legend of a forensic map: its fills and lines, then the notes on
/// the observations, the pulses and the frequencies.
fn legend(map: &Map) -> Legend {
    let result = map.result;
    let names = &map.names;
    let observations = &result.observations;
    let mut legend = Legend::default();
    legend.entry(
        Swatch::Fill(CONSISTENT),
        "consistent with every observation",
    );
    legend.entry(Swatch::Heading, "ruled out by (shade), boundary (line):");
    for (k, (name, o)) in names.iter().zip(observations).enumerate() {
        let seen = o.seen();
        legend.entry(
            Swatch::Boxed(fill(1 << k), colour(k)),
            format!("{name} {seen}"),
        );
    }
    if map.shaded.iter().any(|p| p.class.count_ones() > 1) {
        legend.entry(
            Swatch::Fill(fill((1 << names.len().min(2)) - 1)),
            "ruled out by several (mixed shade)",
        );
    }
    bounds_entries(&mut legend, result);
    block_notes(&mut legend, names, observations);
    notes(&mut legend, map);
    legend
}

/// The legend's entry of the bounds of the consistent region, and of the
/// mixed zones with a note on them.
fn bounds_entries(legend: &mut Legend, result: &ForensicResult) {
    let frequencies = &result.frequencies;
    let (min_g, max_g) = (result.bounds.min_g, result.bounds.max_g);
    let f_bounds = result.bounds.frequency_hz.map(|[a, b]| (a, b));
    if let (Some(lo), Some(hi)) = (min_g, max_g) {
        let count = envelope_count(frequencies);
        let with_any = frequencies
            .iter()
            .filter(|f| !intervals(&f.consistent_g).is_empty())
            .count();
        legend.entry(
            Swatch::Dashed(INK, 2),
            format!(
                "{}: {}–{} g{}",
                if count > 1 {
                    format!(
                        "envelope of {count} consistent intervals at {with_any} of {} frequencies",
                        frequencies.len()
                    )
                } else {
                    "consistent".to_string()
                },
                fmt_num(lo, 3),
                fmt_num(hi, 3),
                f_bounds.map_or(String::new(), |(a, b)| if fmt_num(a, 3) == fmt_num(b, 3) {
                    format!(" at {} Hz", fmt_num(a, 3))
                } else {
                    format!(" at {}–{} Hz", fmt_num(a, 3), fmt_num(b, 3))
                })
            ),
        );
    }
    let zones: Vec<&crate::jobs::mixed::MixedDoc> =
        frequencies.iter().flat_map(|f| &f.mixed_g).collect();
    if !zones.is_empty() {
        legend.entry(
            Swatch::Fill(MIXED),
            "mixed: the outcome alternates finer than the scan resolves",
        );
        legend.note(format!(
            "{} certain consistent interval{}, {} mixed zone{} ({} g wide in all)",
            envelope_count(frequencies),
            if envelope_count(frequencies) == 1 {
                ""
            } else {
                "s"
            },
            zones.len(),
            if zones.len() == 1 { "" } else { "s" },
            fmt_num(zones.iter().map(|z| z.to - z.from).sum::<f64>(), 3),
        ));
    }
    if min_g.is_some() && envelope_count(frequencies) > 1 {
        legend.note(
            "not every pulse inside the envelope is consistent: only the filled cells are (CSV lists each interval)",
        );
    }
}

/// The legend's notes on the pulses, the floor, the vertical motion and
/// the frequencies computed.
fn notes(legend: &mut Legend, map: &Map) {
    let result = map.result;
    let frequencies = &result.frequencies;
    let (fmin, fmax) = map.frequency_range();
    legend.note(format!(
        "{} pulses, {} formulation; {} frequenc{}, amplitudes {}–{} g",
        pulse_name(result),
        result.formulation.name(),
        frequencies.len(),
        if frequencies.len() == 1 { "y" } else { "ies" },
        fmt_num(map.from, 3),
        fmt_num(map.to, 3)
    ));
    if let Some(c) = &result.spec.contact {
        legend.note(sliding_note(c));
    }
    if let Some(v) = result.spec.scaled_vertical() {
        let g = result.observations.first().map_or(9.81, |o| o.block.g);
        legend.note(format!(
            "vertical ground motion {} (positive up), scaled with each pulse",
            crate::plot::scaled_vertical_text(&v, g)
        ));
    }
    legend.note(if map.xs.len() > 1 {
        format!(
            "each computed frequency is a cell reaching half-way to its neighbours; the map spans the computed {}–{} Hz; nothing is interpolated between frequencies",
            fmt_num(fmin, 3),
            fmt_num(fmax, 3)
        )
    } else {
        format!("one frequency computed: {} Hz", fmt_num(fmin, 3))
    });
    if !map.consistent_anywhere {
        legend.note("no pulse of this family is consistent with every observation");
    }
}

/// Draws the chart of `map` in `area`: its cells, the axes (f_p and ω_p,
/// a_p in g), the observations' boundaries and the frame of the bounds.
fn draw_map(area: &Area, map: &Map) -> Drawn {
    let (x0, x1, from, to) = (map.x0, map.x1, map.from, map.to);
    let chart = chart_on(area)
        .top_x_label_area_size(X_LABEL_AREA)
        .build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", from, to)?)?;
    let tau = std::f64::consts::TAU;
    let mut chart = chart.set_secondary_coord(axis_range("top", x0 * tau, x1 * tau)?, from..to);
    for piece in &map.shaded {
        chart.draw_series(std::iter::once(Polygon::new(
            piece.polygon.clone(),
            fill(piece.class).filled(),
        )))?;
    }
    chart
        .configure_mesh()
        .x_desc("pulse frequency f_p (Hz)")
        .y_desc("pulse amplitude a_p (g)")
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(120, 120, 120).mix(0.25))
        .draw()?;
    chart
        .configure_secondary_axes()
        .x_desc("ω_p (rad/s)")
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;
    for (k, lines) in map.boundaries.iter().enumerate() {
        chart.draw_series(
            lines
                .iter()
                .map(|e| PathElement::new(e.to_vec(), colour(k).stroke_width(2))),
        )?;
    }
    let bounds = &map.result.bounds;
    if let (Some(lo), Some(hi), Some([fa, fb])) = (bounds.min_g, bounds.max_g, bounds.frequency_hz)
    {
        // Around the cells of the bounding frequencies.
        let cell = |f: f64| {
            map.xs
                .iter()
                .position(|x| (x - f).abs() <= 1e-9 * f.abs().max(1.0))
                .map(|k| map.edges[k])
        };
        let fa = cell(fa).map_or(fa, |c| c.0);
        let fb = cell(fb).map_or(fb, |c| c.1);
        draw_frame(
            &mut chart,
            Frame {
                x: (fa, fb),
                y: (lo, hi),
                range: (from, to),
                labels_at: (fa, 5, HPos::Left),
                labels: [
                    format!("highest {} g", fmt_num(hi, 3)),
                    format!("lowest {} g", fmt_num(lo, 3)),
                ],
            },
        )?;
    }
    if !map.consistent_anywhere {
        let mid = (0.5 * (x0 + x1), 0.5 * (from + to));
        chart.draw_series(std::iter::once(
            EmptyElement::at(mid)
                + Text::new(
                    "no consistent pulse".to_string(),
                    (0, 0),
                    text(AXIS + 4, INK).pos(Pos::new(HPos::Center, VPos::Center)),
                ),
        ))?;
    }
    Ok(())
}

/// The figure of a `forensic` result.
pub fn svg(result: &ForensicResult) -> Result<String, String> {
    let map = Map::of(result)?;
    let legend = legend(&map);
    let title = format!(
        "Forensic map: {} pulses consistent with what was seen ({})",
        pulse_name(result),
        result.formulation.name()
    );
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        draw_map(&chart_area, &map)?;
        draw_legend(&side, &legend)
    })
}

#[cfg(test)]
mod tests {
    use crate::kinds::JobResult;
    use crate::kinds::forensic::{
        AmplitudeRange, Bounds, ForensicFrequency, ForensicResult, ObservationSet,
    };
    use crate::plot::tests::typed;

    /// A computed forensic result of the Point Reyes observations (one
    /// frequency).
    fn computed_small() -> ForensicResult {
        let spec = r#"{"kind": "forensic", "pulse": {"type": "one_sine"},
            "observations": [
                {"name": "locomotive", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9}, "overturned": true},
                {"name": "transformer", "b": 0.6, "h": 1.2, "overturned": false}],
            "frequency_hz": [1.0], "a_p_g": {"from": 0.1, "to": 2.0},
            "scan_step_g": 0.1, "tolerance_g": 0.01, "formulation": "nonlinear"}"#;
        match typed(spec) {
            JobResult::Forensic(r) => *r,
            other => panic!("not a forensic result: {:?}", other.job_kind()),
        }
    }

    /// The computed result with six frequencies of known sets: the
    /// locomotive (overturned) rules out amplitudes below 0.3 + 0.2 f g, the
    /// transformer (survived) those above 1 + 0.3 f g.
    fn sample() -> ForensicResult {
        let mut r = computed_small();
        assert_eq!(r.observations.len(), 2);
        r.frequencies = (0..6)
            .map(|k| {
                let f = 0.5 + 0.5 * f64::from(k);
                let set = |name: &str, consistent_g| ObservationSet {
                    name: name.into(),
                    consistent_g,
                    mixed_g: vec![],
                    lift_off_above_g: None,
                };
                ForensicFrequency {
                    frequency_hz: f,
                    omega_p: f * std::f64::consts::TAU,
                    consistent_g: vec![[0.3 + 0.2 * f, 1.0 + 0.3 * f]],
                    mixed_g: vec![],
                    per_observation: vec![
                        set("locomotive", vec![[0.3 + 0.2 * f, 5.0]]),
                        set("transformer", vec![[0.1, 1.0 + 0.3 * f]]),
                    ],
                }
            })
            .collect();
        r.a_p_g = AmplitudeRange { from: 0.1, to: 5.0 };
        r.bounds = Bounds {
            min_g: Some(0.4),
            max_g: Some(2.8),
            frequency_hz: Some([0.5, 3.0]),
            min_scale: None,
            max_scale: None,
        };
        r
    }

    #[test]
    fn consistent_region_observations_and_bounds() {
        let svg = super::svg(&sample()).expect("svg");
        for needle in [
            "Forensic map: one-sine pulses consistent with what was seen (nonlinear)",
            "pulse frequency f_p (Hz)",
            "pulse amplitude a_p (g)",
            "consistent with every",
            "locomotive overturned",
            "transformer survived",
            "highest 2.8 g",
            "lowest 0.4 g",
            "envelope of 6 consistent",
            "intervals at 6 of 6",
            "frequencies: 0.4–2.8 g at",
            "not every pulse inside the envelope",
            "6 frequencies",
            "amplitudes 0.1–5 g",
        ] {
            assert!(
                svg.replace('\u{a0}', " ").contains(needle),
                "missing {needle:?}"
            );
        }
        // One cell per frequency (six) for the consistent region and for
        // each observation's excluded region, plus the legend swatch.
        for mask in [0, 1, 2] {
            let c = super::fill(mask);
            let f = format!("fill=\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2);
            assert_eq!(svg.matches(&f).count(), 6 + 1, "mask {mask}");
        }
    }

    #[test]
    fn point_reyes_cells_end_at_the_last_computed_frequency() {
        use crate::plot::bands::cells;
        use crate::plot::tests::{hex, shapes, x_extent};
        let JobResult::Forensic(result) =
            typed(include_str!("../../../specs/point_reyes_forensic.json"))
        else {
            panic!("not a forensic result");
        };
        let frequencies = &result.frequencies;
        assert_eq!(frequencies.len(), 12);
        assert_eq!(frequencies[11].frequency_hz, 3.0);
        // The computed result: pulses consistent with both observations up to
        // 2.5 Hz, none at 2.75 and 3 Hz.
        let consistent: Vec<f64> = frequencies
            .iter()
            .filter(|f| !f.consistent_g.is_empty())
            .map(|f| f.frequency_hz)
            .collect();
        assert_eq!(consistent.last(), Some(&2.5));
        let names = ["locomotive".to_string(), "transformer".to_string()];
        let tiling = cells(&super::columns(frequencies, &names, 0.05, 3.0), 0.025);
        let right = |class: Option<usize>| {
            tiling
                .pieces
                .iter()
                .filter(|p| class.is_none_or(|c| p.class == c))
                .flat_map(|p| p.polygon.iter().map(|q| q.0))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        // The map ends at the last computed frequency; the consistent region
        // half-way from 2.5 to 2.75 Hz, no wedge towards 2.75.
        assert_eq!(right(None), 3.0);
        assert_eq!(right(Some(0)), 2.625);
        // The figure: the consistent fill ends at the same fraction of the map.
        let svg = super::svg(&result).expect("svg");
        let (left, end) = x_extent(&shapes(&svg, "polygon", ""));
        let (_, green) = x_extent(&shapes(
            &svg,
            "polygon",
            &format!("fill=\"{}\"", hex(super::fill(0))),
        ));
        let expected = left + (2.625 - 0.25) / (3.0 - 0.25) * (end - left);
        assert!((green - expected).abs() <= 1.0, "{green} vs {expected}");
        assert!(svg.contains("interpolated"));
    }

    #[test]
    fn the_map_names_its_vertical_motion() {
        for (vertical, needle) in [
            (r#"{"ratio": -0.4}"#, "ü_v = -0.4 ü_g"),
            (
                r#"{"type": "one_sine", "amplitude_ratio": 0.5, "frequency_ratio": 2, "delay_s": 0.1}"#,
                "ü_v: a one-sine pulse, a_v = 0.5 a_p, ω_v = 2 ω_p, 0.1 s later",
            ),
        ] {
            let spec = format!(
                r#"{{"kind": "forensic", "pulse": {{"type": "one_sine"}},
                "observations": [{{"name": "locomotive",
                    "block": {{"alpha": 0.25, "p": 2.14, "eta": 0.9}}, "overturned": true}}],
                "frequency_hz": [1.0], "a_p_g": {{"from": 0.1, "to": 1.0}},
                "vertical": {vertical}}}"#
            );
            let JobResult::Forensic(r) = typed(&spec) else {
                panic!("not a forensic result")
            };
            let words = crate::plot::tests::words(&super::svg(&r).expect("draws"));
            assert!(
                words.contains(&format!("vertical ground motion {needle} (positive up)")),
                "{needle} missing: {words}"
            );
        }
        let svg = super::svg(&computed_small()).expect("draws");
        assert!(!svg.contains("ü_v"), "no vertical motion named without one");
        // One frequency is named once, not as a range from it to itself.
        let words = crate::plot::tests::words(&svg);
        assert!(
            words.contains(" at 1 Hz") && !words.contains("1–1 Hz"),
            "{words}"
        );
    }

    #[test]
    fn partition_labels_what_rules_each_piece_out() {
        let sets = vec![vec![(1.0, 5.0)], vec![(0.0, 2.0)]];
        let p = super::partition(&sets, 0.0, 5.0);
        let got: Vec<(f64, f64, usize)> = p.iter().map(|b| (b.lo, b.hi, b.class)).collect();
        assert_eq!(got, vec![(0.0, 1.0, 1), (1.0, 2.0, 0), (2.0, 5.0, 2)]);
    }

    #[test]
    fn intervals_leave_out_reversed_ones() {
        assert_eq!(
            super::intervals(&[[0.1, 0.5], [0.9, 0.7], [1.0, 1.0]]),
            vec![(0.1, 0.5), (1.0, 1.0)]
        );
    }

    #[test]
    fn nothing_consistent_is_said_so() {
        let mut doc = sample();
        for f in &mut doc.frequencies {
            f.per_observation[1].consistent_g = vec![[0.1, 0.2]];
            f.consistent_g = Vec::new();
        }
        doc.bounds.min_g = None;
        doc.bounds.max_g = None;
        doc.bounds.frequency_hz = None;
        let svg = super::svg(&doc).expect("svg");
        assert!(svg.contains("no consistent pulse"));
        assert!(svg.contains("no pulse of this family"));
        assert!(!svg.contains("max 2.8 g"));
    }
}
