//! The work-precision diagram of `topple precision`.

use plotters::prelude::*;

use crate::precision::PrecisionRow;

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// The work-precision diagram: error against time per run, one line per method.
pub fn precision_diagram(rows: &[PrecisionRow], path: &str) -> PlotResult {
    let root = SVGBackend::new(path, (720, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let floor = 1e-16;
    let pts: Vec<(&str, f64, f64)> = rows
        .iter()
        .filter(|r| r.method != "exact" && r.max_error.is_finite())
        .map(|r| (r.method, r.time_per_run * 1e6, r.max_error.max(floor)))
        .collect();
    let (tmin, tmax) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    let exact_time = rows
        .iter()
        .find(|r| r.method == "exact")
        .map(|r| r.time_per_run * 1e6);
    let tmin = exact_time.map_or(tmin, |e| tmin.min(e)) * 0.7;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "topple work-precision (linear cases vs closed form)",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((tmin..tmax * 1.4).log_scale(), (floor..1.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("time per simulation (µs)")
        .y_desc("max |θ − θ_exact| (rad)")
        .draw()?;
    for (name, color) in [("dopri5", BLUE), ("dop853", RED)] {
        let line: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.0 == name)
            .map(|p| (p.1, p.2))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart.draw_series(line.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
    }
    if let Some(t) = exact_time {
        chart
            .draw_series(std::iter::once(Cross::new(
                (t, floor * 2.0),
                6,
                BLACK.stroke_width(2),
            )))?
            .label("exact (closed form)")
            .legend(|(x, y)| Cross::new((x + 10, y), 5, BLACK));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
