//! Rocking spectra of a record: in the (block size R, scale factor) plane,
//! the scales that overturn each block shaded by mode, the safe ones white,
//! below the rocking threshold grey, and the minimum overturning scale. The
//! right axis reads the scaled record's PGA in g.

use plotters::prelude::*;
use serde_json::{Value, json};

use super::bands::{Band, Column, simplify, tile, tiling};
use super::spectrum::{
    CLASS_MODE1, CLASS_MODE2, CLASS_NO_ROCKING, CLASS_SAFE, fill, region_legend, regions,
};
use super::style::{
    AXIS, Drawn, INK, LEGEND_WIDTH, Marker, Swatch, TICKS, X_LABEL_AREA, Y_LABEL_AREA, axis_range,
    clip_y, draw_legend, fmt_num, marker, mesh, text, tick,
};
use super::{at, block_note, num, render, text_at};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;

/// A line of the result in the keys of a pulse spectrum's line (`a_alpha_g`
/// for a scale factor), so that the pulse spectra's region logic applies.
fn as_pulse_line(line: &Value) -> Value {
    let rename = |list: Option<&Value>| -> Value {
        Value::Array(
            list.and_then(Value::as_array)
                .map(|l| {
                    l.iter()
                        .map(|t| {
                            let mut t = t.clone();
                            if let Some(s) = t.get("scale").cloned() {
                                t["a_alpha_g"] = s;
                            }
                            t
                        })
                        .collect()
                })
                .unwrap_or_default(),
        )
    };
    json!({
        "transitions": rename(line.get("transitions")),
        "mode_changes": rename(line.get("mode_changes")),
        "principal": {"transitions": rename(line.pointer("/principal/transitions"))},
    })
}

/// The figure of a `record_spectrum` result.
pub fn svg(typed: &crate::jobs::record_spectrum::RecordSpectrumResult) -> Result<String, String> {
    svg_doc(&super::document(typed))
}

/// The figure of the document (being replaced by [`svg`]).
pub(crate) fn svg_doc(result: &Value) -> Result<String, String> {
    let lines: Vec<&Value> = result
        .get("spectrum")
        .and_then(Value::as_array)
        .ok_or("the result has no spectrum")?
        .iter()
        .filter(|l| num(l, "R_m").is_some())
        .collect();
    if lines.is_empty() {
        return Err("the spectrum has no block sizes".into());
    }
    let spec = result.get("spec").unwrap_or(&Value::Null);
    let s_max = at(spec, "/scale/to").unwrap_or(1.0);
    let pga_g = at(result, "/record/pga_g");
    // Block sizes in increasing R (p decreasing).
    let mut sized: Vec<(f64, &Value)> = lines
        .iter()
        .filter_map(|l| Some((num(l, "R_m")?, *l)))
        .collect();
    sized.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xs: Vec<f64> = sized.iter().map(|s| s.0).collect();
    let (rmin, rmax) = (xs[0], xs[xs.len() - 1]);
    let half = if rmax > rmin {
        0.5 * (rmax - rmin) / (xs.len() as f64 - 1.0).max(1.0)
    } else {
        0.25 * rmin
    };
    let (x0, x1) = if rmax > rmin {
        (rmin, rmax)
    } else {
        (rmin - 2.0 * half, rmax + 2.0 * half)
    };
    let columns: Vec<Column> = sized
        .iter()
        .map(|&(x, l)| {
            let mut bands = Vec::new();
            if let Some(th) = num(l, "threshold_scale") {
                bands.push(Band {
                    lo: 0.0,
                    hi: th.min(s_max),
                    class: CLASS_NO_ROCKING,
                });
            }
            for (lo, hi, mode) in regions(&as_pulse_line(l), s_max) {
                bands.push(Band {
                    lo,
                    hi,
                    class: if mode == 2 { CLASS_MODE2 } else { CLASS_MODE1 },
                });
            }
            let mut bands = tile(0.0, s_max, &bands, CLASS_SAFE);
            simplify(&mut bands, s_max / 1000.0, |_| false);
            Column { x, bands }
        })
        .collect();
    let shaded: Vec<_> = tiling(&columns, half)
        .pieces
        .into_iter()
        .filter(|p| p.class != CLASS_SAFE)
        .collect();
    let used = |class: usize| shaded.iter().any(|p| p.class == class);
    let minimum: Vec<(f64, f64)> = sized
        .iter()
        .filter_map(|&(x, l)| Some((x, num(l, "min_overturn_scale")?)))
        .collect();

    let mut legend = region_legend(used, "no rocking (PGA below the threshold)");
    if !minimum.is_empty() {
        legend.entry(
            Swatch::LineMark(INK, Marker::Dot),
            "minimum overturning scale (computed)",
        );
    }
    legend.note(block_note(spec.get("block")));
    if let Some(r) = result.get("record") {
        legend.note(format!(
            "record: {} samples, dt = {} s; PGA {} g, PGV {} m/s, PGD {} m (unscaled)",
            r.get("samples").and_then(Value::as_u64).unwrap_or(0),
            fmt_num(num(r, "dt_s").unwrap_or(f64::NAN), 4),
            fmt_num(num(r, "pga_g").unwrap_or(f64::NAN), 4),
            fmt_num(num(r, "pgv_m_s").unwrap_or(f64::NAN), 4),
            fmt_num(num(r, "pgd_m").unwrap_or(f64::NAN), 4),
        ));
    }
    legend.note(format!(
        "{} formulation, {} block size{}; R = 3g/(4p²)",
        text_at(spec, "/formulation"),
        lines.len(),
        if lines.len() == 1 { "" } else { "s" }
    ));
    legend
        .note("shading: principal view (narrow bands omitted; the result lists every transition)");
    if pga_g.is_some() {
        legend.note("right axis: the scaled record's PGA = scale × PGA");
    }

    let title = format!(
        "Rocking spectrum of a record: {} formulation",
        text_at(spec, "/formulation")
    );
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        let mut builder = ChartBuilder::on(&chart_area);
        builder
            .margin(10)
            .margin_right(14)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA);
        if pga_g.is_some() {
            builder.right_y_label_area_size(Y_LABEL_AREA);
        }
        let chart =
            builder.build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", 0.0, s_max)?)?;
        let mut chart = chart.set_secondary_coord(
            x0..x1,
            axis_range("right", 0.0, s_max * pga_g.unwrap_or(1.0))?,
        );
        for piece in &shaded {
            chart.draw_series(std::iter::once(Polygon::new(
                piece.polygon.clone(),
                fill(piece.class).filled(),
            )))?;
        }
        mesh(&mut chart, "block size R (m)", "scale factor").draw()?;
        if pga_g.is_some() {
            chart
                .configure_secondary_axes()
                .y_desc("scaled PGA (g)")
                .label_style(text(TICKS, INK))
                .axis_desc_style(text(AXIS, INK))
                .y_label_formatter(&|v| tick(*v))
                .draw()?;
        }
        for piece in clip_y(&minimum, 0.0, s_max) {
            chart.draw_series(LineSeries::new(piece, INK.stroke_width(2)))?;
        }
        chart.draw_series(
            minimum
                .iter()
                .filter(|q| q.1 <= s_max)
                .map(|&q| marker(q, Marker::Dot, 5, INK)),
        )?;
        draw_legend(&side, &legend)
    })
}
