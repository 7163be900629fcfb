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
use serde_json::Value;

use super::bands::{Band, Column, cell_edges, cells, simplify, tile};
use super::style::{
    AXIS, CONSISTENT, Drawn, INK, LEGEND, LEGEND_WIDTH, Legend, OBSERVATIONS, Swatch, TICKS,
    X_LABEL_AREA, axis_range, chart_on, draw_legend, fmt_num, text, tick, tint,
};
use super::{block_note, num, pulse_name, render, text_at};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;

/// Intervals `[lo, hi]` at `key` of `v`.
pub(crate) fn intervals(v: &Value, key: &str) -> Vec<(f64, f64)> {
    v.get(key)
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|i| {
            let i = i.as_array()?;
            let (lo, hi) = (i.first()?.as_f64()?, i.get(1)?.as_f64()?);
            (hi >= lo).then_some((lo, hi))
        })
        .collect()
}

fn contains(set: &[(f64, f64)], a: f64) -> bool {
    set.iter().any(|&(lo, hi)| a >= lo && a <= hi)
}

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
fn columns(frequencies: &[&Value], names: &[String], from: f64, to: f64) -> Vec<Column> {
    let gap = (to - from) / 900.0;
    let mut map = Vec::new();
    for f in frequencies {
        let x = num(f, "frequency_hz").unwrap_or(f64::NAN);
        let listed: Vec<&Value> = f
            .get("per_observation")
            .and_then(Value::as_array)
            .map(|a| a.iter().collect())
            .unwrap_or_default();
        let sets: Vec<Vec<(f64, f64)>> = names
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let entry = listed
                    .iter()
                    .find(|o| o.get("name").and_then(Value::as_str) == Some(name))
                    .or(listed.get(k));
                entry
                    .map(|o| intervals(o, "consistent_g"))
                    .unwrap_or_default()
            })
            .collect();
        let mut bands = if sets.is_empty() {
            let all: Vec<Band> = intervals(f, "consistent_g")
                .into_iter()
                .map(|(lo, hi)| Band { lo, hi, class: 0 })
                .collect();
            tile(from, to, &all, 1)
        } else {
            partition(&sets, from, to)
        };
        // Slivers of consistent pulses stay, however narrow.
        simplify(&mut bands, gap, |class| class == 0);
        map.push(Column { x, bands });
    }
    map
}

/// The figure of a `forensic` result.
pub fn svg(typed: &crate::jobs::forensic::ForensicResult) -> Result<String, String> {
    svg_doc(&super::document(typed))
}

/// The figure of the document (being replaced by [`svg`]).
pub(crate) fn svg_doc(result: &Value) -> Result<String, String> {
    let spec = result.get("spec").unwrap_or(&Value::Null);
    let range = result
        .get("a_p_g")
        .or_else(|| spec.get("a_p_g"))
        .ok_or("the result has no a_p_g range")?;
    let (from, to) = (
        num(range, "from").ok_or("a_p_g has no from")?,
        num(range, "to").ok_or("a_p_g has no to")?,
    );
    if to.partial_cmp(&from) != Some(std::cmp::Ordering::Greater) {
        return Err(format!("empty amplitude range {from}–{to} g"));
    }
    let observations: Vec<&Value> = result
        .get("observations")
        .and_then(Value::as_array)
        .map(|a| a.iter().collect())
        .unwrap_or_default();
    let names: Vec<String> = observations
        .iter()
        .enumerate()
        .map(|(k, o)| {
            o.get("name")
                .and_then(Value::as_str)
                .map_or_else(|| format!("observation {}", k + 1), str::to_string)
        })
        .collect();
    let frequencies: Vec<&Value> = result
        .get("frequencies")
        .and_then(Value::as_array)
        .ok_or("the result has no frequencies")?
        .iter()
        .filter(|f| num(f, "frequency_hz").is_some())
        .collect();
    if frequencies.is_empty() {
        return Err("the forensic result has no frequencies".into());
    }
    let mut map = columns(&frequencies, &names, from, to);
    map.sort_by(|a, b| a.x.total_cmp(&b.x));
    let xs: Vec<f64> = map.iter().map(|c| c.x).collect();
    let (fmin, fmax) = (xs[0], xs[xs.len() - 1]);
    // A lone frequency is a cell a fifth of itself wide.
    let half = 0.1 * fmin.max(0.01);
    let edges = cell_edges(&xs, half);
    let (x0, x1) = (edges[0].0, edges[edges.len() - 1].1);
    let drawn = cells(&map, half);
    let mut shaded = drawn.pieces;
    // The consistent region on top: nothing hides a sliver of it.
    shaded.sort_by_key(|p| p.class == 0);
    // An observation's boundary: where its verdict changes across an edge.
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
    let bounds = result.get("bounds");
    let min_g = bounds.and_then(|b| num(b, "min_g"));
    let max_g = bounds.and_then(|b| num(b, "max_g"));
    let f_bounds = bounds
        .and_then(|b| b.get("frequency_hz"))
        .and_then(Value::as_array)
        .and_then(|a| Some((a.first()?.as_f64()?, a.get(1)?.as_f64()?)));
    let consistent_anywhere = shaded.iter().any(|p| p.class == 0);

    let mut legend = Legend::default();
    legend.entry(
        Swatch::Fill(CONSISTENT),
        "consistent with every observation",
    );
    legend.entry(Swatch::Heading, "ruled out by (shade), boundary (line):");
    for (k, (name, o)) in names.iter().zip(&observations).enumerate() {
        let seen = if o.get("overturned").and_then(Value::as_bool) == Some(true) {
            "overturned"
        } else {
            "survived"
        };
        legend.entry(
            Swatch::Boxed(fill(1 << k), colour(k)),
            format!("{name} {seen}"),
        );
    }
    if shaded.iter().any(|p| p.class.count_ones() > 1) {
        legend.entry(
            Swatch::Fill(fill((1 << names.len().min(2)) - 1)),
            "ruled out by several (mixed shade)",
        );
    }
    if let (Some(lo), Some(hi)) = (min_g, max_g) {
        legend.entry(
            Swatch::Dashed(INK, 2),
            format!(
                "bounds: {}–{} g{}",
                fmt_num(lo, 3),
                fmt_num(hi, 3),
                f_bounds.map_or(String::new(), |(a, b)| format!(
                    " at {}–{} Hz",
                    fmt_num(a, 3),
                    fmt_num(b, 3)
                ))
            ),
        );
    }
    for (name, o) in names.iter().zip(&observations) {
        legend.note(format!("{name}: {}", block_note(o.get("block"))));
    }
    let formulation = result
        .get("formulation")
        .and_then(Value::as_str)
        .unwrap_or_else(|| text_at(spec, "/formulation"));
    let pulse = result.get("pulse").or_else(|| spec.get("pulse"));
    legend.note(format!(
        "{} pulses, {formulation} formulation; {} frequenc{}, amplitudes {}–{} g",
        pulse_name(pulse),
        frequencies.len(),
        if frequencies.len() == 1 { "y" } else { "ies" },
        fmt_num(from, 3),
        fmt_num(to, 3)
    ));
    legend.note(if xs.len() > 1 {
        format!(
            "each computed frequency is a cell reaching half-way to its neighbours; the map spans the computed {}–{} Hz; nothing is interpolated between frequencies",
            fmt_num(fmin, 3),
            fmt_num(fmax, 3)
        )
    } else {
        format!("one frequency computed: {} Hz", fmt_num(fmin, 3))
    });
    if !consistent_anywhere {
        legend.note("no pulse of this family is consistent with every observation");
    }

    let title = format!(
        "Forensic map: {} pulses consistent with what was seen ({formulation})",
        pulse_name(pulse)
    );
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        let chart = chart_on(&chart_area)
            .top_x_label_area_size(X_LABEL_AREA)
            .build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", from, to)?)?;
        let tau = std::f64::consts::TAU;
        let mut chart = chart.set_secondary_coord(axis_range("top", x0 * tau, x1 * tau)?, from..to);
        for piece in &shaded {
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
        for (k, lines) in boundaries.iter().enumerate() {
            chart.draw_series(
                lines
                    .iter()
                    .map(|e| PathElement::new(e.to_vec(), colour(k).stroke_width(2))),
            )?;
        }
        if let (Some(lo), Some(hi), Some((fa, fb))) = (min_g, max_g, f_bounds) {
            // Around the cells of the bounding frequencies.
            let cell = |f: f64| {
                xs.iter()
                    .position(|x| (x - f).abs() <= 1e-9 * f.abs().max(1.0))
                    .map(|k| edges[k])
            };
            let fa = cell(fa).map_or(fa, |c| c.0);
            let fb = cell(fb).map_or(fb, |c| c.1);
            let frame = vec![(fa, lo), (fb, lo), (fb, hi), (fa, hi), (fa, lo)];
            chart.draw_series(std::iter::once(DashedPathElement::new(
                frame,
                8,
                5,
                INK.stroke_width(2),
            )))?;
            let label = |s: String, at: (f64, f64), above: bool| {
                let (v, dy) = if above {
                    (VPos::Bottom, -5)
                } else {
                    (VPos::Top, 5)
                };
                EmptyElement::at(at)
                    + Text::new(s, (5, dy), text(LEGEND, INK).pos(Pos::new(HPos::Left, v)))
            };
            let room = 0.06 * (to - from);
            chart.draw_series([
                label(
                    format!("max {} g", fmt_num(hi, 3)),
                    (fa, hi),
                    hi < to - room,
                ),
                label(
                    format!("min {} g", fmt_num(lo, 3)),
                    (fa, lo),
                    lo < from + room,
                ),
            ])?;
        }
        if !consistent_anywhere {
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
        draw_legend(&side, &legend)
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use serde_json::{Value, json};

    pub(crate) fn sample() -> Value {
        let freqs: Vec<Value> = (0..6)
            .map(|k| {
                let f = 0.5 + 0.5 * f64::from(k);
                let loco = vec![[0.3 + 0.2 * f, 5.0]];
                let trafo = vec![[0.1, 1.0 + 0.3 * f]];
                let all = vec![[0.3 + 0.2 * f, 1.0 + 0.3 * f]];
                json!({"frequency_hz": f, "omega_p": f * std::f64::consts::TAU,
                       "consistent_g": all,
                       "per_observation": [{"name": "locomotive", "consistent_g": loco},
                                           {"name": "transformer", "consistent_g": trafo}]})
            })
            .collect();
        json!({"kind": "forensic", "formulation": "nonlinear", "pulse": {"type": "one_sine"},
               "a_p_g": {"from": 0.1, "to": 5.0},
               "observations": [
                   {"name": "locomotive", "overturned": true, "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9, "g": 9.81}},
                   {"name": "transformer", "overturned": false, "block": {"alpha": 0.46, "p": 2.34, "eta": 0.7, "g": 9.81}}],
               "frequencies": freqs,
               "bounds": {"min_g": 0.4, "max_g": 2.8, "frequency_hz": [0.5, 3.0]},
               "numerics": {}, "spec": {}})
    }

    #[test]
    fn consistent_region_observations_and_bounds() {
        let svg = super::svg_doc(&sample()).expect("svg");
        for needle in [
            "Forensic map: one-sine pulses consistent with what was seen (nonlinear)",
            "pulse frequency f_p (Hz)",
            "pulse amplitude a_p (g)",
            "consistent with every",
            "locomotive overturned",
            "transformer survived",
            "max 2.8 g",
            "min 0.4 g",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
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
        use crate::plot::tests::{computed, hex, shapes, x_extent};
        let result = computed(include_str!("../../specs/point_reyes_forensic.json"));
        let frequencies: Vec<&Value> = result["frequencies"]
            .as_array()
            .expect("frequencies")
            .iter()
            .collect();
        let hz = |f: &Value| f["frequency_hz"].as_f64().expect("hz");
        assert_eq!(frequencies.len(), 12);
        assert_eq!(hz(frequencies[11]), 3.0);
        // The computed result: pulses consistent with both observations up to
        // 2.5 Hz, none at 2.75 and 3 Hz.
        let consistent: Vec<f64> = frequencies
            .iter()
            .filter(|f| f["consistent_g"].as_array().is_some_and(|a| !a.is_empty()))
            .map(|f| hz(f))
            .collect();
        assert_eq!(consistent.last(), Some(&2.5));
        let names = ["locomotive".to_string(), "transformer".to_string()];
        let tiling = cells(&super::columns(&frequencies, &names, 0.05, 3.0), 0.025);
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
        let svg = super::svg_doc(&result).expect("svg");
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
    fn partition_labels_what_rules_each_piece_out() {
        let sets = vec![vec![(1.0, 5.0)], vec![(0.0, 2.0)]];
        let p = super::partition(&sets, 0.0, 5.0);
        let got: Vec<(f64, f64, usize)> = p.iter().map(|b| (b.lo, b.hi, b.class)).collect();
        assert_eq!(got, vec![(0.0, 1.0, 1), (1.0, 2.0, 0), (2.0, 5.0, 2)]);
    }

    #[test]
    fn nothing_consistent_is_said_so() {
        let mut doc = sample();
        for f in doc["frequencies"].as_array_mut().expect("array") {
            f["per_observation"][1]["consistent_g"] = json!([[0.1, 0.2]]);
            f["consistent_g"] = json!([]);
        }
        doc["bounds"] = json!({"min_g": null, "max_g": null, "frequency_hz": null});
        let svg = super::svg_doc(&doc).expect("svg");
        assert!(svg.contains("no consistent pulse"));
    }
}
