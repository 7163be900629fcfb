//! Forensic maps of a record query: the scale factor (left axis; the scaled
//! PGA in g on the right) against the observations. Each observation is a
//! column of its own — the scales it allows plain, those it rules out tinted
//! in its colour, a tick where its block starts to rock — and a last column
//! holds the scales consistent with all of them, framed by the bounds. Only
//! the computed columns are drawn: there is nothing between observations to
//! interpolate.

use plotters::prelude::*;
use plotters::style::text_anchor::HPos;

use super::figure::{
    Frame, block_notes, colour, draw_frame, fill, intervals, partition, sliding_note,
};
use crate::kinds::forensic::{ForensicResult, RecordObservationSet};
use crate::plot::bands::{Band, Column, MIN_VISIBLE, over, tile, widen};
use crate::plot::render;
use crate::plot::style::{
    Area, CONSISTENT, Drawn, INK, LEGEND_WIDTH, Legend, MIXED, Swatch, X_LABEL_AREA, Y_LABEL_AREA,
    axis_range, draw_legend, fmt_num, mesh, scaled_pga_axis, tint,
};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;
/// Half the width of a column, in column units.
const HALF: f64 = 0.38;
/// A scale allowed by one observation (its column only).
const ALLOWED: usize = usize::MAX;
/// A mixed zone: the outcome alternates finer than the scan resolves.
pub const MIXED_ZONE: usize = usize::MAX - 1;

fn shade(class: usize) -> RGBColor {
    match class {
        ALLOWED => tint(CONSISTENT, 0.12),
        MIXED_ZONE => MIXED,
        _ => fill(class),
    }
}

/// The zones of a list of mixed stretches, as `[from, to]`.
fn zones(mixed: &[crate::jobs::mixed::MixedDoc]) -> Vec<[f64; 2]> {
    mixed.iter().map(|z| [z.from, z.to]).collect()
}

/// The scale range of a record query, and its columns as drawn: column k
/// (1-based) is observation k, column n + 1 every observation, each with
/// its bands of scale from the bottom of the range up. An interval allowed
/// (consistent with every observation, in the last column) narrower than
/// [`MIN_VISIBLE`] of the range is drawn that tall: none vanishes.
pub fn columns(result: &ForensicResult) -> Result<((f64, f64), Vec<Column>), String> {
    let range = result.scale.ok_or("the result has no scale range")?;
    let (from, to) = (range.from, range.to);
    if to.partial_cmp(&from) != Some(std::cmp::Ordering::Greater) {
        return Err(format!("empty scale range {from}–{to}"));
    }
    let per = result
        .per_observation
        .as_deref()
        .ok_or("the result has no per_observation")?;
    if per.is_empty() {
        return Err("the forensic result has no observations".into());
    }
    let min = MIN_VISIBLE * (to - from);
    let sets: Vec<Vec<(f64, f64)>> = per.iter().map(|o| intervals(&o.consistent_scale)).collect();
    let mut columns: Vec<Column> = sets
        .iter()
        .enumerate()
        .map(|(k, set)| {
            let allowed: Vec<Band> = set
                .iter()
                .map(|&(lo, hi)| Band {
                    lo,
                    hi,
                    class: ALLOWED,
                })
                .collect();
            let allowed = over(&allowed, &zones(&per[k].mixed_scale), MIXED_ZONE);
            let bands = tile(from, to, &allowed, 1 << (k % usize::BITS as usize));
            Column {
                x: (k + 1) as f64,
                bands: widen(&bands, min, |class| class == ALLOWED || class == MIXED_ZONE),
            }
        })
        .collect();
    let combined = zones(result.mixed_scale.as_deref().unwrap_or_default());
    let all = tile(
        from,
        to,
        &over(&partition(&sets, from, to), &combined, MIXED_ZONE),
        0,
    );
    columns.push(Column {
        x: (per.len() + 1) as f64,
        bands: widen(&all, min, |class| class == 0 || class == MIXED_ZONE),
    });
    Ok(((from, to), columns))
}

/// A record query as its figure draws it: the scale range, one column per
/// observation and one for all of them, the observations' names.
struct Query<'a> {
    result: &'a ForensicResult,
    /// Each observation's sets of scales.
    per: &'a [RecordObservationSet],
    /// The observations' names.
    names: Vec<String>,
    /// Names too long for a column's label are numbered, spelt in the
    /// legend.
    numbered: bool,
    /// The scale range.
    from: f64,
    to: f64,
    /// The columns: observation k (1-based) at k, all at n + 1.
    columns: Vec<Column>,
    /// The unscaled record's PGA, g.
    pga_g: Option<f64>,
}

impl<'a> Query<'a> {
    fn of(result: &'a ForensicResult) -> Result<Query<'a>, String> {
        let ((from, to), columns) = columns(result)?;
        let per = result
            .per_observation
            .as_deref()
            .ok_or("the result has no per_observation")?;
        let names: Vec<String> = per.iter().map(|o| o.name.clone()).collect();
        let numbered = per.len() > 6 || names.iter().any(|name| name.chars().count() > 12);
        Ok(Query {
            result,
            per,
            names,
            numbered,
            from,
            to,
            columns,
            pga_g: result.record.as_ref().map(|r| r.peaks.pga_g),
        })
    }

    /// Some scale is consistent with every observation.
    fn consistent_anywhere(&self) -> bool {
        self.columns
            .last()
            .is_some_and(|all| all.bands.iter().any(|b| b.class == 0))
    }

    /// The label under each column: the observation's name (shortened), its
    /// number, or "all".
    fn labels(&self) -> Vec<String> {
        let n = self.per.len();
        (1..=n + 1)
            .map(|k| {
                if k == n + 1 {
                    "all".to_string()
                } else if self.numbered {
                    k.to_string()
                } else {
                    let name = &self.names[k - 1];
                    if name.chars().count() > 12 {
                        format!("{}…", name.chars().take(11).collect::<String>())
                    } else {
                        name.clone()
                    }
                }
            })
            .collect()
    }
}

/// The legend of a record query's figure: the fills, each observation and
/// what was seen of it, the rocking threshold and the bounds; then the
/// notes on the blocks, the record and the floor.
fn legend(q: &Query) -> Legend {
    let (result, per) = (q.result, q.per);
    let mut legend = Legend::default();
    legend.entry(
        Swatch::Fill(CONSISTENT),
        "consistent with every observation",
    );
    legend.entry(
        Swatch::Fill(tint(CONSISTENT, 0.12)),
        "allowed by this observation",
    );
    if per.iter().any(|o| !o.mixed_scale.is_empty()) {
        legend.entry(
            Swatch::Fill(MIXED),
            "mixed: the outcome alternates finer than the scan resolves",
        );
    }
    legend.entry(Swatch::Heading, "ruled out by:");
    for (k, name) in q.names.iter().enumerate() {
        let seen = result
            .observations
            .get(k)
            .filter(|o| o.name == per[k].name && o.overturned == per[k].overturned)
            .map_or_else(
                || {
                    if per[k].overturned {
                        "overturned"
                    } else {
                        "survived"
                    }
                    .to_string()
                },
                |o| o.seen(),
            );
        let label = if q.numbered {
            format!("{}: {name} {seen}", k + 1)
        } else {
            format!("{name} {seen}")
        };
        legend.entry(Swatch::Boxed(fill(1 << k), colour(k)), label);
    }
    legend.entry(
        Swatch::Line(INK, 3),
        if result.formulation.name() == "linear" {
            "starts to rock (PGA = g α)"
        } else {
            "starts to rock (PGA = g tan α)"
        },
    );
    bounds_entry(&mut legend, q);
    block_notes(&mut legend, &q.names, &result.observations);
    notes(&mut legend, q);
    legend
}

/// The legend's entry of the bounds of the consistent scales: one interval,
/// or the envelope of several (or of mixed zones) with a note on their
/// widths.
fn bounds_entry(legend: &mut Legend, q: &Query) {
    let result = q.result;
    let (Some(lo), Some(hi)) = (result.bounds.min_scale, result.bounds.max_scale) else {
        return;
    };
    let mixed_all = result.mixed_scale.as_deref().unwrap_or_default();
    let all = intervals(result.consistent_scale.as_deref().unwrap_or_default());
    let pga = |a: f64, b: f64| {
        q.pga_g.map_or(String::new(), |p| {
            format!(" (PGA {}–{} g)", fmt_num(a * p, 3), fmt_num(b * p, 3))
        })
    };
    if all.len() > 1 || !mixed_all.is_empty() {
        let measure: f64 = all.iter().map(|(a, b)| b - a).sum();
        let mixed_width: f64 = mixed_all
            .iter()
            .map(|z| z.to - z.from)
            .fold(0.0, |a, w| a + w);
        legend.entry(
            Swatch::Dashed(INK, 2),
            format!(
                "envelope of {} certain consistent interval{}: lowest {}, highest {}{}",
                all.len(),
                if all.len() == 1 { "" } else { "s" },
                fmt_num(lo, 4),
                fmt_num(hi, 4),
                pga(lo, hi)
            ),
        );
        let zones = if mixed_all.is_empty() {
            String::new()
        } else {
            format!(
                "; {} mixed zone{} {} wide in all",
                mixed_all.len(),
                if mixed_all.len() == 1 { "" } else { "s" },
                fmt_num(mixed_width, 4),
            )
        };
        legend.note(format!(
            "not every scale inside the envelope is consistent: the certain intervals are {} wide in all{zones} (CSV lists each)",
            fmt_num(measure, 4),
        ));
    } else {
        legend.entry(
            Swatch::Dashed(INK, 2),
            format!(
                "consistent: scale {}–{}{}, one interval",
                fmt_num(lo, 4),
                fmt_num(hi, 4),
                pga(lo, hi)
            ),
        );
    }
}

/// The legend's notes on the record, the vertical motion, the floor and
/// the formulation.
fn notes(legend: &mut Legend, q: &Query) {
    let result = q.result;
    if let Some(r) = &result.record {
        legend.note(format!(
            "record: {} samples, dt = {} s; PGA {} g, PGV {} m/s (unscaled)",
            r.samples,
            fmt_num(r.dt_s, 4),
            fmt_num(r.peaks.pga_g, 4),
            fmt_num(r.peaks.pgv_m_s, 4),
        ));
    }
    if let Some(v) = result.spec.scaled_vertical() {
        let g = result.observations.first().map_or(9.81, |o| o.block.g);
        legend.note(format!(
            "vertical ground motion {} (positive up)",
            crate::plot::scaled_vertical_text(&v, g)
        ));
    }
    if let Some(c) = &result.spec.contact {
        legend.note(sliding_note(c));
    }
    legend.note(format!(
        "{} formulation; each column is one computed observation, the last their intersection",
        result.formulation.name()
    ));
    if !q.consistent_anywhere() {
        legend.note("no scale of this record is consistent with every observation");
    }
}

/// Draws the chart of a record query in `area`: its columns, the axes
/// (scale, and the scaled PGA), each observation's threshold and the frame
/// of the bounds.
fn draw_chart(area: &Area, q: &Query) -> Drawn {
    let (from, to, n) = (q.from, q.to, q.per.len());
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(10)
        .margin_right(14)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA);
    if q.pga_g.is_some() {
        builder.right_y_label_area_size(Y_LABEL_AREA);
    }
    let x1 = n as f64 + 1.5;
    let chart = builder.build_cartesian_2d(0.5..x1, axis_range("y", from, to)?)?;
    let p = q.pga_g.unwrap_or(1.0);
    let mut chart = chart.set_secondary_coord(0.5..x1, axis_range("right", from * p, to * p)?);
    for Column { x, bands } in &q.columns {
        chart.draw_series(bands.iter().map(|b| {
            Rectangle::new(
                [(x - HALF, b.lo), (x + HALF, b.hi)],
                shade(b.class).filled(),
            )
        }))?;
    }
    let labels = q.labels();
    let label_of = |v: &f64| -> String {
        let k = v.round();
        if (v - k).abs() < 1e-9 && k >= 1.0 {
            labels.get(k as usize - 1).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    };
    mesh(&mut chart, "observation", "scale factor")
        .x_labels(n + 2)
        .x_label_formatter(&label_of)
        .disable_x_mesh()
        .draw()?;
    if q.pga_g.is_some() {
        scaled_pga_axis(&mut chart)?;
    }
    // Column outlines: observation k in its colour.
    for Column { x, .. } in &q.columns {
        let k = *x as usize;
        let c = if k <= n { colour(k - 1) } else { INK };
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x - HALF, from), (x + HALF, to)],
            c.stroke_width(2),
        )))?;
    }
    let thresholds = q
        .per
        .iter()
        .enumerate()
        .map(|(k, o)| ((k + 1) as f64, o.threshold_scale))
        .filter(|&(_, s)| s > from && s < to);
    chart.draw_series(
        thresholds.map(|(x, s)| {
            PathElement::new(vec![(x - HALF, s), (x + HALF, s)], INK.stroke_width(3))
        }),
    )?;
    let bounds = &q.result.bounds;
    if let (Some(lo), Some(hi)) = (bounds.min_scale, bounds.max_scale) {
        let x = (n + 1) as f64;
        // Inside the intersection's column, outside the consistent span;
        // right-aligned on the column's right edge: the text runs left over
        // the gap between columns, never into the frame.
        draw_frame(
            &mut chart,
            Frame {
                x: (x - HALF - 0.08, x + HALF + 0.08),
                y: (lo, hi),
                range: (from, to),
                labels_at: (x + HALF, 0, HPos::Right),
                labels: [
                    format!("highest {}", fmt_num(hi, 4)),
                    format!("lowest {}", fmt_num(lo, 4)),
                ],
            },
        )?;
    }
    Ok(())
}

/// The figure of a `forensic` result on a `ground_motion`.
pub fn svg(result: &ForensicResult) -> Result<String, String> {
    let q = Query::of(result)?;
    let legend = legend(&q);
    let title = format!(
        "Forensic map: scales of the record consistent with what was seen ({})",
        result.formulation.name()
    );
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        draw_chart(&chart_area, &q)?;
        draw_legend(&side, &legend)
    })
}

#[cfg(test)]
mod tests {
    use crate::kinds::JobResult;
    use crate::kinds::forensic::{ForensicResult, RecordObservationSet};
    use crate::kinds::record_spectrum::ScaleRangeNorm;
    use crate::plot::bands::{Column, MIN_VISIBLE};
    use crate::plot::style::{CONSISTENT, OBSERVATIONS};
    use crate::plot::tests::{hex, typed};

    /// The computed Point Reyes record query.
    fn computed() -> ForensicResult {
        match typed(include_str!(
            "../../../specs/point_reyes_forensic_record.json"
        )) {
            JobResult::Forensic(r) => *r,
            other => panic!("not a forensic result: {:?}", other.job_kind()),
        }
    }

    /// The computed query with known sets: scales 0.1–6 of a record of PGA
    /// 0.5 g; the locomotive allows 0.7–1.76 and 1.82–6, the transformer
    /// 0.1–1.42 and 2.87–3.26.
    fn sample() -> ForensicResult {
        let mut r = computed();
        let record = r.record.as_mut().expect("a record query has its record");
        record.peaks.pga_g = 0.5;
        r.scale = Some(ScaleRangeNorm { from: 0.1, to: 6.0 });
        let set = |name: &str, overturned, threshold_scale, consistent_scale: Vec<[f64; 2]>| {
            RecordObservationSet {
                name: name.into(),
                overturned,
                consistent_pga_g: consistent_scale
                    .iter()
                    .map(|[a, b]| [0.5 * a, 0.5 * b])
                    .collect(),
                consistent_scale,
                mixed_scale: Vec::new(),
                mixed_pga_g: Vec::new(),
                overturning_scale: Vec::new(),
                threshold_scale,
                lift_off_above_scale: None,
            }
        };
        r.per_observation = Some(vec![
            set("locomotive", true, 0.51, vec![[0.7, 1.76], [1.82, 6.0]]),
            set("transformer", false, 1.0, vec![[0.1, 1.42], [2.87, 3.26]]),
        ]);
        r.consistent_scale = Some(vec![[0.7, 1.42], [2.87, 3.26]]);
        r.bounds.min_scale = Some(0.7);
        r.bounds.max_scale = Some(3.26);
        r
    }

    #[test]
    fn columns_per_observation_and_their_intersection() {
        let svg = super::svg(&sample()).expect("svg");
        for needle in [
            "Forensic map: scales of the record consistent with what was seen (nonlinear)",
            "scale factor",
            "scaled PGA (g)",
            "observation",
            "locomotive overturned",
            "transformer survived",
            "all",
            "highest 3.26",
            "lowest 0.7",
            "envelope of 2 certain",
            "consistent intervals: lowest",
            "0.7, highest 3.26 (PGA",
            "not every scale inside the envelope",
            "1.11 wide in all",
            "0.35–1.63 g",
            "record: 101 samples",
        ] {
            assert!(svg.contains(needle), "missing {needle:?} in {svg}");
        }
        // The consistent fill and each observation's outline are drawn.
        assert!(svg.contains(&hex(CONSISTENT)), "consistent fill");
        for c in &OBSERVATIONS[..2] {
            assert!(svg.contains(&hex(*c)), "outline {}", hex(*c));
        }
    }

    #[test]
    fn one_interval_is_called_one_and_several_an_envelope() {
        let mut one = sample();
        one.consistent_scale = Some(vec![[0.7, 1.42]]);
        one.bounds.max_scale = Some(1.42);
        let svg = super::svg(&one).expect("svg");
        assert!(svg.contains("consistent: scale 0.7–1.42"), "{svg}");
        assert!(
            !svg.contains("envelope"),
            "a single interval is no envelope"
        );
        let several = super::svg(&sample()).expect("svg");
        assert!(several.contains("envelope of 2 certain"));
        assert!(!several.contains("consistent: scale"));
    }

    #[test]
    fn the_computed_bounds_are_framed() {
        let r = computed();
        let (lo, hi) = (
            r.bounds.min_scale.expect("a consistent scale"),
            r.bounds.max_scale.expect("a consistent scale"),
        );
        assert!(lo < hi, "{lo} < {hi}");
        let svg = super::svg(&r).expect("svg");
        let fmt = |v: f64| crate::plot::style::fmt_num(v, 4);
        assert!(
            svg.contains(&format!("highest {}", fmt(hi))),
            "highest {hi}"
        );
        assert!(svg.contains(&format!("lowest {}", fmt(lo))), "lowest {lo}");
    }

    #[test]
    fn a_result_without_a_scale_range_is_refused() {
        let mut r = sample();
        r.scale = None;
        assert_eq!(super::svg(&r).unwrap_err(), "the result has no scale range");
        let mut r = sample();
        r.per_observation = None;
        assert_eq!(
            super::svg(&r).unwrap_err(),
            "the result has no per_observation"
        );
    }

    #[test]
    fn nothing_consistent_is_said() {
        let mut doc = sample();
        if let Some(per) = doc.per_observation.as_mut() {
            per[1].consistent_scale = vec![[0.1, 0.5]];
        }
        doc.bounds.min_g = None;
        doc.bounds.max_g = None;
        doc.bounds.min_scale = None;
        doc.bounds.max_scale = None;
        let svg = super::svg(&doc).expect("svg");
        assert!(svg.contains("no scale of this record"), "said");
        assert!(!svg.contains("max 3.26"));
    }

    /// Every interval the result lists — each observation's allowed scales
    /// in its column, those consistent with all in the last — lies inside a
    /// drawn band of its class at least [`MIN_VISIBLE`] of the range tall,
    /// and every such band holds one.
    fn assert_every_interval_drawn(doc: &ForensicResult) {
        let ((from, to), columns) = super::columns(doc).expect("columns");
        let min = MIN_VISIBLE * (to - from);
        let per = doc.per_observation.as_deref().expect("per observation");
        let all = doc.consistent_scale.clone().unwrap_or_default();
        let listed = per
            .iter()
            .map(|o| (super::ALLOWED, &o.consistent_scale))
            .chain(std::iter::once((0, &all)));
        for ((class, set), Column { bands, .. }) in listed.zip(&columns) {
            let drawn: Vec<_> = bands.iter().filter(|b| b.class == class).collect();
            for &[lo, hi] in set {
                let (lo, hi) = (lo.max(from), hi.min(to));
                let holder = drawn.iter().find(|b| b.lo <= lo && hi <= b.hi);
                assert!(
                    holder.is_some_and(|b| b.hi - b.lo >= min - 1e-12),
                    "[{lo}, {hi}] in {bands:?}"
                );
            }
            for b in drawn {
                assert!(
                    set.iter().any(|&[lo, hi]| lo < b.hi && hi > b.lo),
                    "{b:?} holds none of {set:?}"
                );
            }
        }
    }

    #[test]
    fn every_interval_is_drawn_however_narrow() {
        assert_every_interval_drawn(&computed());
        assert_every_interval_drawn(&sample());
        // A transformer allowing 2.5–2.5006 too: a sliver of the 0.1–6 axis.
        let mut narrow = sample();
        if let Some(per) = narrow.per_observation.as_mut() {
            per[1].consistent_scale = vec![[0.1, 1.42], [2.5, 2.5006], [2.87, 3.26]];
        }
        narrow.consistent_scale = Some(vec![[0.7, 1.42], [2.5, 2.5006], [2.87, 3.26]]);
        assert_every_interval_drawn(&narrow);
    }

    #[test]
    fn the_right_axis_reads_the_scaled_pga() {
        let doc = computed();
        let pga = doc.record.as_ref().expect("a record").peaks.pga_g;
        let svg = super::svg(&doc).expect("svg");
        crate::kinds::spectrum::figure::tests::assert_right_axis_is_left_times(&svg, pga);
    }
}
