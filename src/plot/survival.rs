//! Survival of rocks under a hazard model: the probability that each rock
//! still stands after T years, P_s = exp(−λ_t T), on a logarithmic age axis;
//! the requested ages marked; an uncertain age at its median with
//! E[exp(−λ_t T)]; several rocks' joint probability noted.

use plotters::prelude::*;
use serde_json::Value;

use super::forensic::colour;
use super::style::{
    Drawn, INK, LEGEND_WIDTH, Legend, Marker, Swatch, axis_range, chart_on, draw_legend, fmt_num,
    marker, mesh,
};
use super::{num, render};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 620;

/// The figure of a `survival` result.
pub fn svg(typed: &crate::jobs::survival::SurvivalResult) -> Result<String, String> {
    svg_doc(&super::document(typed))
}

/// The figure of the document (being replaced by [`svg`]).
pub(crate) fn svg_doc(result: &Value) -> Result<String, String> {
    let rocks: Vec<&Value> = result
        .get("rocks")
        .and_then(Value::as_array)
        .ok_or("the result has no rocks")?
        .iter()
        .collect();
    if rocks.is_empty() {
        return Err("the result has no rocks".into());
    }
    let rate = |r: &Value| num(r, "annual_toppling_rate").unwrap_or(0.0);
    let points = |r: &Value| -> Vec<(f64, f64, bool)> {
        let mut p: Vec<(f64, f64, bool)> = r
            .get("ages")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .filter_map(|a| Some((num(a, "age_years")?, num(a, "survival_probability")?, false)))
            .collect();
        if let Some(d) = r.get("age_distribution")
            && let (Some(t), Some(ps)) =
                (num(d, "median_age_years"), num(d, "survival_probability"))
        {
            p.push((t, ps, true));
        }
        p
    };
    // The age axis: two decades around the rocks' mean return periods and ages.
    let mut ts: Vec<f64> = rocks
        .iter()
        .flat_map(|r| points(r).into_iter().map(|p| p.0))
        .chain(
            rocks
                .iter()
                .map(|r| rate(r))
                .filter(|l| *l > 0.0)
                .map(|l| 1.0 / l),
        )
        .filter(|t| t.is_finite() && *t > 0.0)
        .collect();
    ts.sort_by(f64::total_cmp);
    let (lo, hi) = match (ts.first(), ts.last()) {
        (Some(&a), Some(&b)) => (a / 10.0, b * 10.0),
        _ => (1.0, 1e6),
    };
    let curves: Vec<Vec<(f64, f64)>> = rocks
        .iter()
        .map(|r| {
            let l = rate(r);
            (0..=240)
                .map(|k| {
                    let t = lo * (hi / lo).powf(f64::from(k) / 240.0);
                    (t, (-l * t).exp())
                })
                .collect()
        })
        .collect();

    let mut legend = Legend::default();
    for (k, r) in rocks.iter().enumerate() {
        let name = r.get("name").and_then(Value::as_str).unwrap_or("rock");
        legend.entry(
            Swatch::Line(colour(k), 3),
            format!(
                "{name}: λ_t = {}/yr (1 in {} yr)",
                fmt_num(rate(r), 4),
                fmt_num(1.0 / rate(r), 4)
            ),
        );
    }
    legend.entry(Swatch::Mark(Marker::Dot, INK), "an age asked for");
    if rocks.iter().any(|r| r.get("age_distribution").is_some()) {
        legend.entry(
            Swatch::Mark(Marker::Square, INK),
            "uncertain age: E[P_s] at its median",
        );
    }
    if let Some(j) = result.get("joint") {
        legend.note(format!(
            "all {} rocks standing: P = {}; every hazard rate × {} brings it to 5 %",
            rocks.len(),
            fmt_num(num(j, "survival_probability").unwrap_or(f64::NAN), 4),
            fmt_num(num(j, "rate_scale_at_5_percent").unwrap_or(f64::NAN), 4)
        ));
    }
    legend
        .note("P_s = exp(−λ_t T): topplings as a Poisson process; λ_t = ∫ P(topple | im) |dλ(im)|");
    let im = result.get("im").and_then(Value::as_str).unwrap_or("pga_g");
    legend.note(format!("hazard in {im}, interpolated log-log"));

    render(
        (WIDTH, HEIGHT),
        "Survival under the hazard model",
        |area| -> Drawn {
            let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
            let mut chart = chart_on(&chart_area)
                .build_cartesian_2d(axis_range("x", lo, hi)?.log_scale(), 0.0..1.0)?;
            mesh(&mut chart, "age T (years)", "P(still standing)").draw()?;
            for (k, c) in curves.iter().enumerate() {
                chart.draw_series(LineSeries::new(c.clone(), colour(k).stroke_width(3)))?;
            }
            for (k, r) in rocks.iter().enumerate() {
                chart.draw_series(points(r).into_iter().map(|(t, p, uncertain)| {
                    marker(
                        (t, p),
                        if uncertain {
                            Marker::Square
                        } else {
                            Marker::Dot
                        },
                        6,
                        colour(k),
                    )
                }))?;
            }
            draw_legend(&side, &legend)
        },
    )
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    #[test]
    fn curves_and_ages_of_each_rock() {
        let doc = json!({"kind": "survival", "im": "pga_g", "rocks": [
            {"name": "Grass Valley", "annual_toppling_rate": 1.785e-4,
             "ages": [{"age_years": 1000.0, "survival_probability": 0.8365}]},
            {"name": "Lovejoy", "annual_toppling_rate": 5e-5, "ages": [],
             "age_distribution": {"median_age_years": 15000.0, "survival_probability": 0.47}}],
            "joint": {"survival_probability": 0.39, "rate_scale_at_5_percent": 2.1}});
        let svg = super::svg_doc(&doc).expect("svg");
        for needle in [
            "Survival under the hazard model",
            "age T (years)",
            "P(still standing)",
            "Grass Valley",
            "1 in 5602 yr",
            "uncertain age",
            "all 2 rocks standing",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
    }
}
