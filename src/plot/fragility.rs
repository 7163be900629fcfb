//! Fragility: the empirical probability of toppling at each stripe with its
//! 95 % Wilson interval (the primary answer), the fitted lognormal curve and
//! its 95 % bootstrap band (a summary); stripes where the probability falls
//! as the intensity rises are marked.

use plotters::prelude::*;
use serde_json::Value;

use super::style::{
    Drawn, INK, LEGEND_WIDTH, Legend, MODE1, Marker, Swatch, axis_range, chart_on, draw_legend,
    fmt_num, marker, mesh, tint,
};
use super::{num, render};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 620;

/// The figure of a `fragility` result.
pub fn svg(typed: &crate::jobs::fragility::FragilityResult) -> Result<String, String> {
    svg_doc(&super::document(typed))
}

/// The figure of the document (being replaced by [`svg`]).
pub(crate) fn svg_doc(result: &Value) -> Result<String, String> {
    let stripes: Vec<(f64, f64, f64, f64)> = result
        .get("stripes")
        .and_then(Value::as_array)
        .ok_or("the result has no stripes")?
        .iter()
        .filter_map(|s| {
            let i = s.get("interval_95")?;
            Some((
                num(s, "im")?,
                num(s, "p")?,
                i.get(0)?.as_f64()?,
                i.get(1)?.as_f64()?,
            ))
        })
        .collect();
    if stripes.is_empty() {
        return Err("the result has no stripes".into());
    }
    let fit = result.get("lognormal").filter(|v| !v.is_null());
    let curve: Vec<(f64, f64, f64, f64)> = fit
        .and_then(|f| f.get("curve"))
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|c| Some((num(c, "im")?, num(c, "p")?, num(c, "lo")?, num(c, "hi")?)))
        .collect();
    let x_max = stripes
        .iter()
        .map(|s| s.0)
        .chain(curve.iter().map(|c| c.0))
        .fold(0.0f64, f64::max)
        * 1.05;
    let falls: Vec<f64> = result
        .get("falls_at")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(Value::as_f64)
        .collect();
    let im = result.get("im").and_then(Value::as_str).unwrap_or("pga_g");
    let x_desc = if im == "pgv_m_s" {
        "PGV (m/s)"
    } else {
        "PGA (g)"
    };

    let mut legend = Legend::default();
    legend.entry(
        Swatch::Mark(Marker::Dot, INK),
        "P(topple) per stripe, 95 % Wilson interval",
    );
    if let Some(f) = fit {
        legend.entry(
            Swatch::Line(MODE1, 3),
            format!(
                "lognormal fit: θ = {}, β = {}",
                fmt_num(num(f, "median").unwrap_or(f64::NAN), 3),
                fmt_num(num(f, "beta").unwrap_or(f64::NAN), 3)
            ),
        );
        legend.entry(Swatch::Fill(tint(MODE1, 0.2)), "95 % bootstrap band");
    } else {
        legend.note("no lognormal fit: the counts do not bound one");
    }
    if !falls.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Ring, MODE1),
            "falls below the stripe before (safe regions)",
        );
    }
    if let Some(n) = result.pointer("/stripes/0/n").and_then(Value::as_u64) {
        legend.note(format!(
            "{n} simulations per stripe; the empirical points are the answer, the fit a summary"
        ));
    }

    render(
        (WIDTH, HEIGHT),
        "Fragility: probability of toppling",
        |area| -> Drawn {
            let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
            let mut chart =
                chart_on(&chart_area).build_cartesian_2d(axis_range("x", 0.0, x_max)?, 0.0..1.0)?;
            mesh(&mut chart, x_desc, "P(topple)").draw()?;
            if curve.len() > 1 {
                let mut band: Vec<(f64, f64)> = curve.iter().map(|c| (c.0, c.3)).collect();
                band.extend(curve.iter().rev().map(|c| (c.0, c.2)));
                chart.draw_series(std::iter::once(Polygon::new(
                    band,
                    tint(MODE1, 0.2).filled(),
                )))?;
                chart.draw_series(LineSeries::new(
                    curve.iter().map(|c| (c.0, c.1)),
                    MODE1.stroke_width(3),
                ))?;
            }
            chart.draw_series(stripes.iter().map(|&(x, _, lo, hi)| {
                PathElement::new(vec![(x, lo), (x, hi)], INK.stroke_width(2))
            }))?;
            chart.draw_series(
                stripes
                    .iter()
                    .map(|&(x, p, _, _)| marker((x, p), Marker::Dot, 6, INK)),
            )?;
            chart.draw_series(
                stripes
                    .iter()
                    .filter(|s| falls.contains(&s.0))
                    .map(|&(x, p, _, _)| marker((x, p), Marker::Ring, 11, MODE1)),
            )?;
            draw_legend(&side, &legend)
        },
    )
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    #[test]
    fn points_intervals_fit_and_falls() {
        let doc = json!({"kind": "fragility", "im": "pga_g",
            "stripes": [
                {"im": 0.4, "n": 200, "p": 0.1, "interval_95": [0.06, 0.15]},
                {"im": 0.8, "n": 200, "p": 0.7, "interval_95": [0.63, 0.76]},
                {"im": 1.0, "n": 200, "p": 0.6, "interval_95": [0.53, 0.67]}],
            "falls_at": [1.0],
            "lognormal": {"median": 0.6, "beta": 0.4, "curve": [
                {"im": 0.2, "p": 0.003, "lo": 0.001, "hi": 0.01},
                {"im": 1.2, "p": 0.96, "lo": 0.9, "hi": 0.99}]}});
        let svg = super::svg_doc(&doc).expect("svg");
        for needle in [
            "Fragility: probability of toppling",
            "PGA (g)",
            "P(topple)",
            "θ = 0.6",
            "95 % bootstrap band",
            "falls below",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
    }
}
