//! The work-precision diagram of `topple precision`: each Runge–Kutta pair's
//! largest error against the closed form versus its work (right-hand-side
//! evaluations per simulation), down the tolerance ladder. Work, not time, so
//! that the figure is the same on every machine and run.

use plotters::prelude::*;

use crate::precision::PrecisionRow;

/// Errors below this are drawn on it (the closed form itself is exact to
/// rounding).
const FLOOR: f64 = 1e-16;

/// The diagram as SVG text.
pub fn precision_diagram(rows: &[PrecisionRow]) -> Result<String, String> {
    let mut out = String::new();
    draw(rows, &mut out).map_err(|e| format!("cannot draw the diagram: {e}"))?;
    Ok(out)
}

fn draw(rows: &[PrecisionRow], out: &mut String) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::with_string(out, (760, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let pts: Vec<(&str, Option<f64>, f64, f64)> = rows
        .iter()
        .filter(|r| r.method != "exact" && r.max_error.is_finite())
        .map(|r| {
            (
                r.method,
                r.rtol,
                r.evaluations_per_run,
                r.max_error.max(FLOOR),
            )
        })
        .collect();
    let exact = rows
        .iter()
        .find(|r| r.method == "exact")
        .map(|r| r.evaluations_per_run);
    let (lo, hi) = pts
        .iter()
        .map(|p| p.2)
        .chain(exact)
        .filter(|w| *w > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), w| (a.min(w), b.max(w)));
    let (lo, hi) = if lo.is_finite() {
        (lo * 0.7, hi * 1.5)
    } else {
        (1.0, 10.0)
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "work-precision: linear cases against the closed form (eqs. 25–31)",
            ("sans-serif", 20),
        )
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d((lo..hi).log_scale(), (FLOOR..1.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("right-hand-side evaluations per simulation")
        .y_desc("max |θ − θ_exact| (rad)")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    for (name, colour) in [("dopri5", BLUE), ("dop853", RED)] {
        let line: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.0 == name)
            .map(|p| (p.2, p.3))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))?
            .label(format!("{name} (rtol 1e-3 … 1e-12, atol = rtol/100)"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        chart.draw_series(line.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
        // Label the decades of the ladder on the line.
        chart.draw_series(
            pts.iter()
                .filter(|p| {
                    p.0 == name && matches!(p.1, Some(t) if [1e-4, 1e-8, 1e-12].contains(&t))
                })
                .map(|p| {
                    Text::new(
                        format!("{:.0e}", p.1.unwrap_or(0.0)),
                        (p.2, p.3),
                        ("sans-serif", 13).into_font().color(&colour),
                    )
                }),
        )?;
    }
    if let Some(w) = exact.filter(|w| *w > 0.0) {
        chart
            .draw_series(std::iter::once(Cross::new(
                (w, FLOOR * 3.0),
                7,
                BLACK.stroke_width(2),
            )))?
            .label("exact (closed form, eqs. 25–31): the reference")
            .legend(|(x, y)| Cross::new((x + 10, y), 5, BLACK));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
