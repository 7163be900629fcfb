//! Time histories (paper Figs. 7–8): ground acceleration ü_g/g, rotation
//! θ/α, angular velocity θ̇/p and the friction demand f_x/f_z in stacked
//! panels over one time axis; the pulse (or the recorded ground motion)
//! shaded, impacts ticked, overturning or coming to rest marked.

use plotters::element::DashedPathElement;
use plotters::prelude::*;
use serde_json::Value;

use super::style::{
    AXIS, Area, Drawn, INK, LEGEND, LEGEND_WIDTH, Legend, MUTED, Marker, PULSE, REST, Swatch,
    TICKS, clip_y, draw_legend, fmt_num, left_top, marker, mode_colour, right_top, text, tick,
};
use super::{at, block_note, column, num, pulse_name, render, text_at};
use crate::dynamics::{Pulse, PulseShape};

const WIDTH: u32 = 1120;
const TITLE_AREA: u32 = 40;
const X_AXIS: u32 = 50;
const MIN_HEIGHT: u32 = 600;

/// What the figure asks of a result without a series.
pub const NO_SERIES: &str = "no series in this result: add \"outputs\": {\"series\": 500} to the spec for θ(t), θ̇(t) and f_x/f_z(t)";

/// One panel: a quantity against time.
struct Panel {
    /// Axis description.
    desc: String,
    /// Legend label.
    label: String,
    colour: RGBColor,
    /// A curve.
    line: Vec<(f64, f64)>,
    /// Markers (without a curve).
    points: Vec<((f64, f64), Marker)>,
    /// y range.
    range: (f64, f64),
    /// Dotted reference levels.
    refs: Vec<f64>,
    /// Tick the impacts on the zero line.
    impacts: bool,
}

/// A vertical line across every panel.
struct Mark {
    t: f64,
    colour: RGBColor,
    label: String,
}

/// What every panel shares.
struct Shared {
    t_end: f64,
    motion_end: Option<f64>,
    impacts: Vec<f64>,
    marks: Vec<Mark>,
}

fn half_range(values: impl Iterator<Item = f64>, floor: f64) -> f64 {
    values
        .filter(|v| v.is_finite())
        .fold(floor, |m, v| m.max(v.abs() * 1.12))
}

/// The ground motion of a time-history spec.
enum Motion {
    /// A cycloidal pulse.
    Pulse(Pulse),
    /// A record: samples (m/s²) every `dt` s, linear in between.
    Record { dt: f64, acc: Vec<f64> },
}

impl Motion {
    fn of(spec: &Value) -> Option<Motion> {
        if let Some(g) = spec.get("ground_motion") {
            let dt = num(g, "dt").filter(|dt| *dt > 0.0)?;
            let acc = column(g, "acc");
            return (acc.len() >= 2).then_some(Motion::Record { dt, acc });
        }
        let shape = match text_at(spec, "/pulse/type") {
            "one_sine" => PulseShape::OneSine,
            "one_cosine" => PulseShape::OneCosine,
            "cn" => PulseShape::Cn(
                spec.pointer("/pulse/n")
                    .and_then(Value::as_u64)
                    .and_then(|n| u32::try_from(n).ok())
                    .unwrap_or(1),
            ),
            _ => return None,
        };
        Pulse::new(shape, at(spec, "/pulse/a_p")?, at(spec, "/pulse/omega_p")?)
            .ok()
            .map(Motion::Pulse)
    }

    /// When the ground stops moving, s.
    fn duration(&self) -> f64 {
        match self {
            Motion::Pulse(p) => p.duration,
            Motion::Record { dt, acc } => dt * (acc.len() - 1) as f64,
        }
    }

    /// ü_g/g over [0, t_end]: the pulse sampled finely; a record by its
    /// samples, or by the least and largest sample of each of about 2000
    /// buckets when it has more (no peak is lost).
    fn curve(&self, t_end: f64, g: f64) -> Vec<(f64, f64)> {
        match self {
            Motion::Pulse(p) => (0..=1200)
                .map(|k| {
                    let t = t_end * f64::from(k) / 1200.0;
                    (t, p.acceleration(t) / g)
                })
                .collect(),
            Motion::Record { dt, acc } => {
                let n = acc.len().min((t_end / dt).floor() as usize + 1).max(2);
                let bucket = n.div_ceil(2000).max(1);
                let mut out = Vec::with_capacity(2 * n / bucket + 2);
                for (b, chunk) in acc[..n].chunks(bucket).enumerate() {
                    let first = b * bucket;
                    let (lo, hi) = chunk.iter().enumerate().fold(
                        ((0, f64::INFINITY), (0, f64::NEG_INFINITY)),
                        |(lo, hi), (k, &v)| {
                            (
                                if v < lo.1 { (k, v) } else { lo },
                                if v > hi.1 { (k, v) } else { hi },
                            )
                        },
                    );
                    let (a, b) = if lo.0 <= hi.0 { (lo, hi) } else { (hi, lo) };
                    for (k, v) in [a, b] {
                        out.push(((first + k) as f64 * dt, v / g));
                    }
                    if bucket == 1 {
                        out.pop();
                    }
                }
                // Still ground after the record ends.
                let end = (acc.len() - 1) as f64 * dt;
                if t_end > end {
                    out.push((end, 0.0));
                    out.push((t_end, 0.0));
                }
                out
            }
        }
    }
}

/// The figure of a `time_history` result.
pub fn svg(result: &Value) -> Result<String, String> {
    let spec = result
        .get("spec")
        .ok_or("the result has no spec: cannot scale θ by α")?;
    let alpha = at(spec, "/block/alpha").ok_or("the result's spec has no block.alpha")?;
    let p = at(spec, "/block/p").unwrap_or(f64::NAN);
    let g = at(spec, "/block/g").unwrap_or(9.81);
    let mu = at(spec, "/block/mu");
    let linear = text_at(spec, "/formulation") == "linear";
    let motion = Motion::of(spec);
    let series = result.get("series");
    let t = series.map(|s| column(s, "t")).unwrap_or_default();
    let t_end = num(result, "end_time")
        .or_else(|| t.last().copied())
        .or(motion.as_ref().map(Motion::duration))
        .filter(|t| *t > 0.0 && t.is_finite())
        .unwrap_or(1.0);
    let impacts: Vec<(f64, f64, f64)> = result
        .get("impacts")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|i| {
            Some((
                num(i, "t")?,
                num(i, "theta_dot_before").unwrap_or(f64::NAN),
                num(i, "theta_dot_after").unwrap_or(f64::NAN),
            ))
        })
        .collect();
    // Ground acceleration reaches the rocking threshold at g tan α (α g linearised).
    let threshold = if linear { alpha } else { alpha.tan() };
    let mut panels = Vec::new();
    let mut clipped_ratio = None;
    if let Some(s) = series.filter(|_| !t.is_empty()) {
        let zip = |v: Vec<f64>, scale: f64| -> Vec<(f64, f64)> {
            t.iter().zip(v).map(|(&t, v)| (t, v / scale)).collect()
        };
        let ground = zip(column(s, "ground_acceleration"), g);
        let theta = zip(column(s, "theta"), alpha);
        let theta_dot = zip(column(s, "theta_dot"), p);
        let ratio = zip(column(s, "fx_over_fz"), 1.0);
        if !ground.is_empty() {
            let m = half_range(ground.iter().map(|q| q.1), threshold * 1.3);
            panels.push(Panel {
                desc: "ü_g / g".into(),
                label: "ground acceleration ü_g/g".into(),
                colour: RGBColor(90, 90, 90),
                line: ground,
                points: Vec::new(),
                range: (-m, m),
                refs: vec![threshold, -threshold],
                impacts: false,
            });
        }
        let m = half_range(theta.iter().map(|q| q.1), 1.25);
        panels.push(Panel {
            desc: "θ / α".into(),
            label: format!("rotation θ/α (α = {} rad)", fmt_num(alpha, 3)),
            colour: RGBColor(31, 78, 160),
            line: theta,
            points: Vec::new(),
            range: (-m, m),
            refs: vec![1.0, -1.0],
            impacts: true,
        });
        if !theta_dot.is_empty() {
            let m = half_range(theta_dot.iter().map(|q| q.1), 0.1);
            panels.push(Panel {
                desc: "θ̇ / p".into(),
                label: format!("angular velocity θ̇/p (p = {} rad/s)", fmt_num(p, 3)),
                colour: RGBColor(0, 120, 120),
                line: theta_dot,
                points: Vec::new(),
                range: (-m, m),
                refs: Vec::new(),
                impacts: false,
            });
        }
        if !ratio.is_empty() {
            // Near lift-off and overturning f_z → 0 and the ratio grows without
            // bound: the range follows the peak demand while rocking.
            // After lift-off the demand is unbounded (the series stops there):
            // the range then follows the demand when rocking starts.
            let largest = half_range(ratio.iter().map(|q| q.1), 0.0) / 1.12;
            let scale = num(result, "peak_friction_demand")
                .or_else(|| {
                    num(result, "lift_off_time")
                        .and(num(result, "initiation_friction_demand"))
                        .map(|d| 2.0 * d)
                })
                .unwrap_or(largest)
                .max(threshold.max(mu.unwrap_or(0.0)));
            let m = (largest * 1.12).min(scale * 1.3).max(alpha.tan() * 1.3);
            if largest > m {
                clipped_ratio = Some(largest);
            }
            let mut refs = vec![alpha.tan(), -alpha.tan()];
            refs.extend(mu.iter().flat_map(|m| [*m, -*m]));
            panels.push(Panel {
                desc: "f_x / f_z".into(),
                label: "friction demand f_x/f_z".into(),
                colour: RGBColor(150, 80, 20),
                line: ratio,
                points: Vec::new(),
                range: (-m, m),
                refs,
                impacts: false,
            });
        }
    } else {
        if let Some(motion) = &motion {
            let ground = motion.curve(t_end, g);
            let m = half_range(ground.iter().map(|q| q.1), threshold * 1.3);
            panels.push(Panel {
                desc: "ü_g / g".into(),
                label: match motion {
                    Motion::Pulse(_) => "ground acceleration ü_g/g (from the pulse)".into(),
                    Motion::Record { .. } => "ground acceleration ü_g/g (the record)".into(),
                },
                colour: RGBColor(90, 90, 90),
                line: ground,
                points: Vec::new(),
                range: (-m, m),
                refs: vec![threshold, -threshold],
                impacts: false,
            });
        }
        if !impacts.is_empty() {
            let mut points = Vec::new();
            for &(t, before, after) in &impacts {
                points.push(((t, before / p), Marker::Ring));
                points.push(((t, after / p), Marker::Dot));
            }
            let m = half_range(points.iter().map(|q| q.0.1), 0.05);
            panels.push(Panel {
                desc: "θ̇ / p at impacts".into(),
                label: "θ̇/p before (○) and after (●) each impact".into(),
                colour: RGBColor(0, 120, 120),
                line: Vec::new(),
                points,
                range: (-m, m),
                refs: Vec::new(),
                impacts: true,
            });
        }
        if panels.is_empty() {
            return Err(format!(
                "nothing to draw: {NO_SERIES} (the result has no impacts and its spec no ground motion)"
            ));
        }
    }

    let overturned = result.get("overturned").and_then(Value::as_bool) == Some(true);
    let mode = result.get("mode").and_then(Value::as_u64).unwrap_or(1) as u8;
    let mut marks = Vec::new();
    let mut legend = Legend::default();
    match &motion {
        Some(m @ Motion::Pulse(_)) => legend.entry(
            Swatch::Fill(PULSE),
            format!("pulse: 0 ≤ t ≤ {} s", fmt_num(m.duration(), 3)),
        ),
        Some(m @ Motion::Record { .. }) => legend.entry(
            Swatch::Fill(PULSE),
            format!("ground motion: 0 ≤ t ≤ {} s", fmt_num(m.duration(), 4)),
        ),
        None => {}
    }
    for panel in &panels {
        let swatch = if panel.line.is_empty() {
            Swatch::Mark(Marker::Dot, panel.colour)
        } else {
            Swatch::Line(panel.colour, 2)
        };
        legend.entry(swatch, panel.label.clone());
    }
    let mut refs = vec![format!("θ = ±α")];
    refs.push(if linear {
        "ü_g = ±αg (rocking starts)".to_string()
    } else {
        "ü_g = ±g\u{a0}tan\u{a0}α (rocking starts)".to_string()
    });
    if panels.iter().any(|p| p.desc == "f_x / f_z") {
        refs.push("f_x/f_z = ±tan\u{a0}α".into());
        if let Some(m) = mu {
            refs.push(format!("±μ = {}", fmt_num(m, 3)));
        }
    }
    legend.entry(
        Swatch::Dashed(MUTED, 1),
        format!("levels: {}", refs.join("; ")),
    );
    if !impacts.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Tick, INK),
            format!("impact ({} listed)", impacts.len()),
        );
    }
    if overturned && let Some(to) = num(result, "overturn_time") {
        let label = format!(
            "overturned, mode {mode} ({}), t = {} s",
            if mode == 2 {
                "no impact"
            } else {
                "after impact"
            },
            fmt_num(to, 4)
        );
        legend.entry(Swatch::Dashed(mode_colour(mode), 2), label.clone());
        marks.push(Mark {
            t: to,
            colour: mode_colour(mode),
            label: format!("overturns (mode {mode})"),
        });
    } else if let Some(tr) = num(result, "rest_time") {
        legend.entry(
            Swatch::Dashed(REST, 2),
            format!("at rest, t = {} s", fmt_num(tr, 4)),
        );
        marks.push(Mark {
            t: tr,
            colour: REST,
            label: "at rest".into(),
        });
    }
    if let Some(tl) = num(result, "lift_off_time") {
        marks.push(Mark {
            t: tl,
            colour: INK,
            label: "lift-off (f_z = 0)".into(),
        });
    }

    legend.note(block_note(spec.get("block")));
    let a_p = at(spec, "/pulse/a_p");
    let omega_p = at(spec, "/pulse/omega_p");
    if let (Some(a), Some(w)) = (a_p, omega_p) {
        legend.note(format!(
            "a_p = {} m/s² = {} g = {} αg",
            fmt_num(a, 4),
            fmt_num(a / g, 4),
            fmt_num(a / (alpha * g), 4)
        ));
        legend.note(format!(
            "ω_p = {} rad/s (f_p = {} Hz), ω_p/p = {}",
            fmt_num(w, 4),
            fmt_num(w / std::f64::consts::TAU, 3),
            fmt_num(w / p, 4)
        ));
    }
    let record_peak = match &motion {
        Some(Motion::Record { dt, acc }) => {
            let peak = acc.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            legend.note(format!(
                "record: {} samples every {} s, peak |ü_g| = {} g = {} αg",
                acc.len(),
                fmt_num(*dt, 3),
                fmt_num(peak / g, 3),
                fmt_num(peak / (alpha * g), 3)
            ));
            Some(peak)
        }
        _ => None,
    };
    legend.note(format!(
        "{} formulation, solver {}",
        text_at(spec, "/formulation"),
        text_at(spec, "/solver/method")
    ));
    if let Some(n) = result.get("impact_count").and_then(Value::as_u64) {
        let summed = result
            .get("chatter_impacts_summed")
            .and_then(Value::as_u64)
            .unwrap_or(0);
        let plural = if n == 1 { "" } else { "s" };
        legend.note(if summed > 0 {
            format!("{n} impact{plural} ({summed} of a chattering tail summed, not listed)")
        } else {
            format!("{n} impact{plural}")
        });
    }
    if let Some(peak) = num(result, "peak_theta_over_alpha") {
        legend.note(format!("peak |θ|/α = {}", fmt_num(peak, 3)));
    }
    if let Some(peak) = num(result, "peak_friction_demand") {
        legend.note(format!("peak f_x/f_z while rocking = {}", fmt_num(peak, 3)));
    } else if let Some(tl) = num(result, "lift_off_time") {
        legend.note(format!(
            "f_z → 0 at t = {} s (lift-off): friction demand unbounded",
            fmt_num(tl, 4)
        ));
    }
    if let Some(largest) = clipped_ratio {
        legend.note(format!(
            "f_x/f_z leaves the panel where f_z → 0 (|f_x/f_z| up to {})",
            fmt_num(largest, 3)
        ));
    }
    for w in result
        .get("warnings")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        if let Some(kind) = w.get("kind").and_then(Value::as_str) {
            legend.note(match num(w, "t") {
                Some(t) => format!("warning: {kind} at t = {} s", fmt_num(t, 4)),
                None => format!("warning: {kind}"),
            });
        }
    }
    if series.is_none() {
        legend.note(NO_SERIES);
    }

    let title = match (a_p, omega_p, record_peak) {
        (_, _, Some(peak)) => format!(
            "Rocking time history: recorded ground motion, peak {} αg ({})",
            fmt_num(peak / (alpha * g), 3),
            text_at(spec, "/formulation")
        ),
        (Some(a), Some(w), _) => format!(
            "Rocking time history: {} pulse, a_p = {} αg, ω_p/p = {} ({})",
            pulse_name(spec.get("pulse")),
            fmt_num(a / (alpha * g), 4),
            fmt_num(w / p, 4),
            text_at(spec, "/formulation")
        ),
        _ => "Rocking time history".to_string(),
    };
    let shared = Shared {
        t_end,
        motion_end: motion.as_ref().map(Motion::duration),
        impacts: impacts.iter().map(|i| i.0).collect(),
        marks,
    };
    let n = panels.len() as u32;
    let panel_h = ((MIN_HEIGHT - TITLE_AREA - X_AXIS) / n).max(170);
    let height = TITLE_AREA + X_AXIS + n * panel_h;
    render((WIDTH, height), &title, |area| {
        let (charts, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        let (h_charts, _) = (charts.dim_in_pixel().1, ());
        let (upper, bottom) = charts.split_vertically(h_charts - panel_h - X_AXIS);
        let mut areas = if n > 1 {
            upper.split_evenly((n as usize - 1, 1))
        } else {
            Vec::new()
        };
        areas.push(bottom);
        for (k, (panel, a)) in panels.iter().zip(&areas).enumerate() {
            draw_panel(a, panel, &shared, k == 0, k + 1 == panels.len())?;
        }
        draw_legend(&side, &legend)
    })
}

fn draw_panel(area: &Area, panel: &Panel, shared: &Shared, first: bool, bottom: bool) -> Drawn {
    let (lo, hi) = panel.range;
    let t_end = shared.t_end;
    let mut chart = ChartBuilder::on(area)
        .margin_top(8)
        .margin_right(18)
        .margin_left(6)
        .x_label_area_size(if bottom { X_AXIS } else { 0 })
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..t_end, lo..hi)?;
    let mut mesh = chart.configure_mesh();
    mesh.y_desc(panel.desc.as_str())
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .light_line_style(RGBColor(243, 243, 243))
        .bold_line_style(RGBColor(222, 222, 222))
        .y_labels(5)
        .x_labels(10)
        .y_label_formatter(&|v| tick(*v))
        .x_label_formatter(&|v| tick(*v));
    if bottom {
        mesh.x_desc("t (s)");
    }
    mesh.draw()?;
    if let Some(end) = shared.motion_end {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(0.0, lo), (end.min(t_end), hi)],
            PULSE.mix(0.65).filled(),
        )))?;
    }
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(0.0, 0.0), (t_end, 0.0)],
        RGBColor(160, 160, 160).stroke_width(1),
    )))?;
    for &level in panel.refs.iter().filter(|l| **l > lo && **l < hi) {
        chart.draw_series(std::iter::once(DashedPathElement::new(
            vec![(0.0, level), (t_end, level)],
            3,
            3,
            MUTED.stroke_width(1),
        )))?;
    }
    for part in clip_y(&panel.line, lo, hi) {
        chart.draw_series(LineSeries::new(part, panel.colour.stroke_width(2)))?;
    }
    chart.draw_series(
        panel
            .points
            .iter()
            .filter(|(q, _)| q.1 >= lo && q.1 <= hi && q.0 <= t_end)
            .map(|&(q, kind)| marker(q, kind, 8, panel.colour)),
    )?;
    if panel.impacts {
        chart.draw_series(
            shared
                .impacts
                .iter()
                .filter(|t| **t <= t_end)
                .map(|&t| marker((t, 0.0), Marker::Tick, 8, INK)),
        )?;
    }
    for mark in &shared.marks {
        chart.draw_series(std::iter::once(DashedPathElement::new(
            vec![(mark.t, lo), (mark.t, hi)],
            7,
            4,
            mark.colour.stroke_width(2),
        )))?;
        if first {
            let style = if mark.t > 0.35 * t_end {
                right_top(LEGEND, mark.colour)
            } else {
                left_top(LEGEND, mark.colour)
            };
            let dx = if mark.t > 0.35 * t_end { -6 } else { 6 };
            chart.draw_series(std::iter::once(
                EmptyElement::at((mark.t, hi)) + Text::new(mark.label.clone(), (dx, 4), style),
            ))?;
        }
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use serde_json::{Value, json};

    pub(crate) fn sample(series: bool) -> Value {
        let n = 200;
        let t: Vec<f64> = (0..n).map(|k| f64::from(k) * 0.03).collect();
        let mut doc = json!({
            "kind": "time_history", "rocked": true, "overturned": true, "mode": 1,
            "impact_count": 2, "chatter_impacts_summed": 0,
            "impacts": [{"t": 1.5, "theta_dot_before": 0.5, "theta_dot_after": -0.45},
                        {"t": 3.7, "theta_dot_before": -0.4, "theta_dot_after": 0.36}],
            "overturn_time": 5.9, "rest_time": null, "end_time": 5.97,
            "peak_theta_over_alpha": 6.3, "peak_friction_demand": 0.5, "warnings": [],
            "spec": {"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9, "g": 9.81},
                     "pulse": {"type": "one_sine", "omega_p": 10.7, "a_p": 7.4},
                     "formulation": "linear", "solver": {"method": "exact"}}
        });
        if series {
            doc["series"] = json!({
                "t": t,
                "theta": t.iter().map(|t| 0.3 * (t * 1.3).sin()).collect::<Vec<_>>(),
                "theta_dot": t.iter().map(|t| 0.4 * (t * 1.3).cos()).collect::<Vec<_>>(),
                "ground_acceleration": t.iter().map(|t| if *t < 0.587 { 7.4 * (10.7 * t).sin() } else { 0.0 }).collect::<Vec<_>>(),
                "fx_over_fz": t.iter().map(|t| if *t > 5.8 { 1e4 } else { 0.25 + 0.1 * t.sin() }).collect::<Vec<_>>(),
            });
        }
        doc
    }

    #[test]
    fn four_panels_with_labels_marks_and_legend() {
        let svg = super::svg(&sample(true)).expect("svg");
        for needle in [
            "Rocking time history: one-sine pulse",
            "ü_g / g",
            "θ / α",
            "θ̇ / p",
            "f_x / f_z",
            "t (s)",
            "impact (2 listed)",
            "overturns (mode 1)",
            "pulse: 0 ≤ t ≤ 0.587 s",
            "leaves the panel",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
    }

    #[test]
    fn without_series_the_pulse_and_impacts_are_drawn_with_a_hint() {
        let svg = super::svg(&sample(false)).expect("svg");
        assert!(svg.contains("θ̇ / p at impacts"));
        assert!(svg.contains("ü_g / g"));
        assert!(svg.contains("outputs"));
        let mut bare = sample(false);
        bare["impacts"] = json!([]);
        bare["spec"]["pulse"] = json!({"type": "record"});
        let e = super::svg(&bare).unwrap_err();
        assert!(e.contains("\"outputs\": {\"series\": 500}"), "{e}");
    }

    #[test]
    fn a_recorded_ground_motion_is_drawn_from_its_samples() {
        let mut doc = sample(false);
        doc["spec"]["pulse"] = Value::Null;
        doc["spec"].as_object_mut().map(|o| o.remove("pulse"));
        doc["spec"]["ground_motion"] = json!({"dt": 0.01, "acc": (0..300).map(|k| (f64::from(k) * 0.1).sin() * 5.0).collect::<Vec<_>>(), "unit": "m/s2"});
        let svg = super::svg(&doc).expect("svg");
        assert!(svg.contains("recorded ground motion"));
        assert!(svg.contains("ground motion: 0 ≤ t ≤ 2.99 s"));
        assert!(svg.contains("record: 300 samples"));
    }

    #[test]
    fn a_result_without_spec_is_refused() {
        let mut doc = sample(true);
        doc.as_object_mut().map(|o| o.remove("spec"));
        assert!(super::svg(&doc).unwrap_err().contains("spec"));
    }
}
