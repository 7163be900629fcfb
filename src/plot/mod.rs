//! SVG figures (plotters, SVG backend: no system fonts needed).

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

/// Plots a result document: a time history (needs `outputs.series`).
pub fn plot_result(result: &serde_json::Value, path: &str) -> PlotResult {
    match result.get("kind").and_then(|k| k.as_str()) {
        Some("time_history") => time_history(result, path),
        Some("spectrum") => spectrum(result, path),
        Some("friction_spectrum") => friction_spectrum(result, path),
        other => Err(format!("no figure for result kind {other:?}").into()),
    }
}

fn column(v: &serde_json::Value, name: &str) -> Vec<f64> {
    v.get(name)
        .and_then(|a| a.as_array())
        .map(|a| a.iter().filter_map(|x| x.as_f64()).collect())
        .unwrap_or_default()
}

fn time_history(result: &serde_json::Value, path: &str) -> PlotResult {
    let series = result
        .get("series")
        .ok_or("the result has no series: add \"outputs\": {\"series\": 500} to the spec")?;
    let alpha = result
        .pointer("/spec/block/alpha")
        .and_then(|a| a.as_f64())
        .ok_or("result without spec")?;
    let t = column(series, "t");
    let theta: Vec<f64> = column(series, "theta").iter().map(|x| x / alpha).collect();
    let ratio = column(series, "fx_over_fz");
    let t_end = t.last().copied().unwrap_or(1.0).max(1e-9);
    let root = SVGBackend::new(path, (800, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(if ratio.is_empty() { 560 } else { 320 });
    let ymax = theta
        .iter()
        .fold(1.2f64, |m, v| m.max(v.abs() * 1.1))
        .min(8.0);
    let mut chart = ChartBuilder::on(&top)
        .caption("rotation θ/α", ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..t_end, -ymax..ymax)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("θ/α")
        .draw()?;
    chart.draw_series(LineSeries::new(
        t.iter().copied().zip(theta.iter().copied()),
        BLUE.stroke_width(2),
    ))?;
    if !ratio.is_empty() {
        let rmax = ratio
            .iter()
            .fold(0.3f64, |m, v| m.max(v.abs() * 1.1))
            .min(10.0);
        let mut c2 = ChartBuilder::on(&bottom)
            .caption("f_x/f_z", ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..t_end, -rmax..rmax)?;
        c2.configure_mesh()
            .x_desc("t (s)")
            .y_desc("f_x/f_z")
            .draw()?;
        c2.draw_series(LineSeries::new(
            t.iter().copied().zip(ratio.iter().copied()),
            RED.stroke_width(2),
        ))?;
    }
    root.present()?;
    Ok(())
}

fn num(v: &serde_json::Value, key: &str) -> Option<f64> {
    v.get(key).and_then(|x| x.as_f64())
}

/// Overturning regions of one frequency as (lo, hi, mode) in αg.
fn overturning_regions(line: &serde_json::Value, a_max: f64) -> Vec<(f64, f64, u8)> {
    let empty = Vec::new();
    let transitions = line
        .get("transitions")
        .and_then(|t| t.as_array())
        .unwrap_or(&empty);
    let changes: Vec<(f64, u8)> = line
        .get("mode_changes")
        .and_then(|t| t.as_array())
        .unwrap_or(&empty)
        .iter()
        .filter_map(|m| Some((num(m, "a_alpha_g")?, m.get("to_mode")?.as_u64()? as u8)))
        .collect();
    let mut regions = Vec::new();
    let mut open: Option<(f64, u8)> = None;
    for t in transitions {
        let (Some(a), Some(dir)) = (
            num(t, "a_alpha_g"),
            t.get("direction").and_then(|d| d.as_str()),
        ) else {
            continue;
        };
        let mode = t.get("mode").and_then(|m| m.as_u64()).unwrap_or(1) as u8;
        match dir {
            "up" => open = Some((a, mode)),
            _ => {
                if let Some((lo, m)) = open.take() {
                    regions.push((lo, a, m));
                }
            }
        }
    }
    if let Some((lo, m)) = open {
        regions.push((lo, a_max, m));
    }
    // Split regions at mode changes.
    let mut out = Vec::new();
    for (lo, hi, mut mode) in regions {
        let mut start = lo;
        for &(at, to) in changes.iter().filter(|(at, _)| *at > lo && *at < hi) {
            out.push((start, at, mode));
            start = at;
            mode = to;
        }
        out.push((start, hi, mode));
    }
    out
}

fn spectrum(result: &serde_json::Value, path: &str) -> PlotResult {
    let lines = result
        .get("spectrum")
        .and_then(|s| s.as_array())
        .ok_or("result without spectrum")?;
    let a_max = result
        .pointer("/spec/a_max_alpha_g")
        .and_then(|a| a.as_f64())
        .unwrap_or(20.0);
    let ratios: Vec<f64> = lines.iter().filter_map(|l| num(l, "omega_ratio")).collect();
    if ratios.is_empty() {
        return Err("empty spectrum".into());
    }
    let (rmin, rmax) = ratios
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| {
            (a.min(r), b.max(r))
        });
    let pad = if rmax > rmin {
        0.02 * (rmax - rmin)
    } else {
        0.5 * rmin.max(0.1)
    };
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let formulation = result
        .pointer("/spec/formulation")
        .and_then(|f| f.as_str())
        .unwrap_or("");
    let pulse = result
        .pointer("/spec/pulse/type")
        .and_then(|f| f.as_str())
        .unwrap_or("");
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("overturning spectrum — {pulse}, {formulation}"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d((rmin - pad)..(rmax + pad), 0.0..a_max)?;
    chart
        .configure_mesh()
        .x_desc("ω_p / p")
        .y_desc("a_p / (α g)")
        .light_line_style(TRANSPARENT)
        .draw()?;
    let mode1 = RGBColor(214, 69, 65);
    let mode2 = RGBColor(52, 101, 164);
    let below = RGBColor(225, 225, 225);
    for (i, line) in lines.iter().enumerate() {
        let Some(r) = num(line, "omega_ratio") else {
            continue;
        };
        let left = if i > 0 {
            0.5 * (r + ratios[i - 1])
        } else {
            r - pad
        };
        let right = if i + 1 < ratios.len() {
            0.5 * (r + ratios[i + 1])
        } else {
            r + pad
        };
        let threshold = num(line, "threshold_alpha_g").unwrap_or(1.0);
        chart.draw_series(std::iter::once(Rectangle::new(
            [(left, 0.0), (right, threshold.min(a_max))],
            below.filled(),
        )))?;
        for (lo, hi, mode) in overturning_regions(line, a_max) {
            let color = if mode == 2 { mode2 } else { mode1 };
            chart.draw_series(std::iter::once(Rectangle::new(
                [(left, lo), (right, hi.min(a_max))],
                color.mix(0.75).filled(),
            )))?;
        }
    }
    let curve = |key: &str| -> Vec<(f64, f64)> {
        lines
            .iter()
            .filter_map(|l| Some((num(l, "omega_ratio")?, num(l, key)?)))
            .filter(|p| p.1 <= a_max)
            .collect()
    };
    chart
        .draw_series(LineSeries::new(
            curve("min_overturn_alpha_g"),
            BLACK.stroke_width(2),
        ))?
        .label("minimum overturning acceleration")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
    chart
        .draw_series(DashedLineSeries::new(
            curve("eq21_alpha_g"),
            6,
            4,
            BLACK.into(),
        ))?
        .label("eq. 21: 1 + β ω_p/p")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    let closed = curve("closed_form_mode2_alpha_g");
    if !closed.is_empty() {
        chart
            .draw_series(DashedLineSeries::new(closed, 2, 3, GREEN.stroke_width(2)))?
            .label("mode-2 boundary, corrected eq. 47")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], GREEN.stroke_width(2)));
    }
    // Legend swatches for the shaded regions (an empty series carries each label).
    for (label, color) in [
        ("overturns, mode 1 (after impact)", mode1),
        ("overturns, mode 2 (no impact)", mode2),
        ("no rocking", below),
    ] {
        chart
            .draw_series(std::iter::empty::<Rectangle<(f64, f64)>>())?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], color.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn friction_spectrum(result: &serde_json::Value, path: &str) -> PlotResult {
    let points = result
        .get("points")
        .and_then(|s| s.as_array())
        .ok_or("result without points")?;
    let peak: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| Some((num(p, "a_alpha_g")?, num(p, "peak_over_tan_alpha")?)))
        .collect();
    let alpha = result
        .pointer("/spec/block/alpha")
        .and_then(|a| a.as_f64())
        .ok_or("result without spec")?;
    let init: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| {
            Some((
                num(p, "a_alpha_g")?,
                num(p, "initiation_friction_demand")? / alpha.tan(),
            ))
        })
        .collect();
    let xmax = peak.iter().fold(1.0f64, |m, p| m.max(p.0));
    let ymax = peak
        .iter()
        .chain(&init)
        .fold(1.5f64, |m, p| m.max(p.1 * 1.1))
        .min(50.0);
    let root = SVGBackend::new(path, (800, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("friction needed for pure rocking", ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..xmax * 1.05, 0.0..ymax)?;
    chart
        .configure_mesh()
        .x_desc("a_p / (α g)")
        .y_desc("μ_min / tan α")
        .draw()?;
    chart
        .draw_series(LineSeries::new(peak.clone(), RED.stroke_width(2)))?
        .label("peak |f_x/f_z| (eq. 20)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    chart
        .draw_series(DashedLineSeries::new(init, 6, 4, BLUE.stroke_width(2)))?
        .label("at initiation (eq. 7 / 51)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
