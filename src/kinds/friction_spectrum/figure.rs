//! Friction demand (paper Fig. 9): the least friction coefficient pure
//! rocking needs, over tan α, against the pulse amplitude; amplitudes that
//! overturn the block marked by mode.

use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::kinds::friction_spectrum::FrictionResult;
use crate::plot::style::{
    AXIS, Area, Drawn, INK, LEGEND_WIDTH, Legend, MODE1, MODE2, MUTED, Marker, REFERENCE, Swatch,
    TICKS, X_LABEL_AREA, Y_LABEL_AREA, axis_range, clip_y, draw_legend, fmt_num, marker, text,
    tick,
};
use crate::plot::{block_text, render, shape_title};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 620;
const PEAK: RGBColor = RGBColor(40, 40, 40);
const INITIATION: RGBColor = RGBColor(0, 114, 178);

/// One amplitude of the spectrum.
struct Point {
    a: f64,
    /// None: unbounded (lift-off).
    peak: Option<f64>,
    initiation: Option<f64>,
    overturned: bool,
    mode: Option<u8>,
    lift_off: bool,
}

/// The amplitudes of a friction spectrum drawn: those with a bounded peak
/// demand, and those that lift off.
fn points(result: &FrictionResult) -> Vec<Point> {
    let tan = result.spec.block.alpha.tan();
    result
        .points
        .iter()
        .filter_map(|p| {
            let lift_off = p.lift_off || p.lift_off_time.is_some();
            let peak = p
                .peak_over_tan_alpha
                .or_else(|| p.peak_friction_demand.map(|d| d / tan))
                .filter(|d| d.is_finite() && !lift_off);
            if peak.is_none() && !lift_off {
                return None;
            }
            Some(Point {
                a: p.a_alpha_g,
                peak,
                initiation: p.initiation_friction_demand.map(|d| d / tan),
                overturned: p.overturned,
                mode: p.mode,
                lift_off,
            })
        })
        .collect()
}

/// The friction spectrum as drawn: its points, the ranges of its axes and
/// its curves.
struct Drawing {
    points: Vec<Point>,
    /// The amplitude axis, a_p/(αg).
    x0: f64,
    x1: f64,
    /// The top of the demand axis, μ_min/tan α.
    top: f64,
    /// The block's μ over tan α, where it is near the demand.
    mu_on_scale: Option<f64>,
    /// The peak demands above the top.
    off_scale: Vec<f64>,
    /// The demand curve, broken wherever the demand is unbounded.
    peak_runs: Vec<Vec<(f64, f64)>>,
    /// The demand when rocking starts.
    initiation: Vec<(f64, f64)>,
}

impl Drawing {
    fn of(result: &FrictionResult) -> Result<Drawing, String> {
        let spec = &result.spec;
        let tan = spec.block.alpha.tan();
        let points = points(result);
        if points.is_empty() {
            return Err("the friction spectrum has no points".into());
        }
        // μ of the block over tan α; μ can be any size (1e308 for "never
        // slides"), so it sets the scale only when it is near the demand.
        let mu = spec.block.mu.map(|m| m / tan);
        let (x0, x1) = amplitude_range(&points);
        let without_mu = demand_scale(&points, None);
        let mu_on_scale = mu.filter(|m| m.is_finite() && *m <= 2.0 * without_mu);
        let top = demand_scale(&points, mu_on_scale);
        let off_scale: Vec<f64> = points
            .iter()
            .filter_map(|p| p.peak)
            .filter(|d| *d > top)
            .collect();
        let peak_runs: Vec<Vec<(f64, f64)>> = points
            .chunk_by(|a, b| a.peak.is_some() == b.peak.is_some())
            .filter(|run| run[0].peak.is_some())
            .map(|run| run.iter().filter_map(|p| Some((p.a, p.peak?))).collect())
            .collect();
        let initiation: Vec<(f64, f64)> = points
            .iter()
            .filter_map(|p| Some((p.a, p.initiation?)))
            .collect();
        Ok(Drawing {
            points,
            x0,
            x1,
            top,
            mu_on_scale,
            off_scale,
            peak_runs,
            initiation,
        })
    }
}

/// The top of the demand axis, over the demands of `points` and `extra`.
///
/// Lift-off makes the demand unbounded: the range follows the others, and
/// lift-off amplitudes are marked on the top edge. Near lift-off f_z is
/// small and the demand very large though bounded: the range stops at a few
/// times the demand when rocking starts, and points above it sit on the top
/// edge (their values are in the JSON and CSV).
fn demand_scale(points: &[Point], extra: Option<f64>) -> f64 {
    let start_demand = points
        .iter()
        .filter_map(|p| p.initiation)
        .chain(extra)
        .filter(|d| d.is_finite())
        .fold(1.0f64, f64::max);
    let cap = (4.0 * start_demand).max(6.0);
    let highest = points
        .iter()
        .filter_map(|p| p.peak)
        .chain(points.iter().filter_map(|p| p.initiation))
        .chain(extra)
        .filter(|d| d.is_finite())
        .fold(1.2f64, f64::max);
    highest.min(cap) * 1.12
}

/// The amplitude axis of `points`, with a margin.
fn amplitude_range(points: &[Point]) -> (f64, f64) {
    let xmin = points.iter().map(|p| p.a).fold(f64::INFINITY, f64::min);
    let xmax = points.iter().map(|p| p.a).fold(f64::NEG_INFINITY, f64::max);
    if xmax > xmin {
        (
            0.0f64.max(xmin - 0.03 * (xmax - xmin)),
            xmax + 0.03 * (xmax - xmin),
        )
    } else {
        (xmin * 0.9, xmax * 1.1 + 0.1)
    }
}

/// The legend of a friction spectrum: its curves and markers, the levels of
/// μ, then the notes on the block, the pulse and the outcome.
fn legend(result: &FrictionResult, d: &Drawing) -> Legend {
    let spec = &result.spec;
    let tan = spec.block.alpha.tan();
    let points = &d.points;
    let mut legend = Legend::default();
    legend.entry(
        Swatch::Line(PEAK, 2),
        "peak |f_x/f_z| / tan α over the rocking history (eq. 20)",
    );
    marker_entries(&mut legend, points);
    if !d.off_scale.is_empty() {
        legend.note(format!(
            "{} amplitude{} above the scale (up to {} tan α), drawn on the top edge",
            d.off_scale.len(),
            if d.off_scale.len() == 1 { "" } else { "s" },
            fmt_num(d.off_scale.iter().copied().fold(0.0, f64::max), 3)
        ));
    }
    if !d.initiation.is_empty() {
        legend.entry(
            Swatch::Dashed(INITIATION, 2),
            "when rocking starts (eq. 7; eq. 51 for one-cosine)",
        );
    }
    legend.entry(Swatch::Dashed(MUTED, 1), "μ = tan α");
    match (spec.block.mu, d.mu_on_scale) {
        (_, Some(m)) => legend.entry(
            Swatch::Dashed(REFERENCE, 2),
            format!("μ of the block = {} (slides above)", fmt_num(m * tan, 3)),
        ),
        (Some(m), None) => legend.note(format!(
            "μ of the block = {}: far above the demand drawn (no sliding here)",
            fmt_num(m, 3)
        )),
        (None, None) => {}
    }
    legend.note(block_text(&spec.block));
    legend.note(format!(
        "{} pulse, ω_p/p = {}, {} formulation",
        shape_title(spec.pulse.shape()),
        fmt_num(result.omega_ratio, 4),
        spec.formulation.name()
    ));
    let vertical = crate::jobs::vertical::ScaledVertical::of(spec.vertical.as_ref(), None)
        .map(|v| crate::plot::scaled_vertical_text(&v, spec.block.g));
    if let Some(v) = &vertical {
        legend.note(format!("vertical ground motion {v} (positive up)"));
    }
    legend.note(format!(
        "right axis: μ_min = tan α × left axis (tan α = {})",
        fmt_num(tan, 3)
    ));
    if let Some(first) = points.iter().find(|p| p.overturned) {
        legend.note(format!(
            "first overturning amplitude: {} αg",
            fmt_num(first.a, 4)
        ));
    }
    legend
}

/// The legend's entries of the markers the `points` show: survival,
/// overturning in mode 1 or 2, lift-off.
fn marker_entries(legend: &mut Legend, points: &[Point]) {
    let survived = points.iter().any(|p| !p.overturned);
    let mode1 = points.iter().any(|p| p.overturned && p.mode != Some(2));
    let mode2 = points.iter().any(|p| p.overturned && p.mode == Some(2));
    if survived {
        legend.entry(Swatch::Mark(Marker::Ring, PEAK), "block survives");
    }
    if mode1 {
        legend.entry(
            Swatch::Mark(Marker::Triangle, MODE1),
            "block overturns, mode 1 (after impact)",
        );
    }
    if mode2 {
        legend.entry(
            Swatch::Mark(Marker::Square, MODE2),
            "block overturns, mode 2 (no impact)",
        );
    }
    if points.iter().any(|p| p.lift_off) {
        legend.entry(
            Swatch::Mark(Marker::Cross, INK),
            "lift-off (f_z → 0): demand unbounded, no μ suffices",
        );
    }
}

/// Draws the chart of a friction spectrum in `area`: the axes (a_p in αg
/// and g, the demand over tan α and μ_min), the levels of μ, the curves and
/// the markers of each amplitude.
fn draw_chart(area: &Area, result: &FrictionResult, d: &Drawing) -> Drawn {
    let alpha = result.spec.block.alpha;
    let tan = alpha.tan();
    let (x0, x1, top) = (d.x0, d.x1, d.top);
    let chart = ChartBuilder::on(area)
        .margin(10)
        .margin_right(14)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .top_x_label_area_size(X_LABEL_AREA)
        .right_y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", 0.0, top)?)?;
    let mut chart = chart.set_secondary_coord(
        axis_range("top", x0 * alpha, x1 * alpha)?,
        axis_range("right", 0.0, top * tan)?,
    );
    chart
        .configure_mesh()
        .x_desc("a_p / (α g)")
        .y_desc("μ_min / tan α")
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(RGBColor(245, 245, 245))
        .bold_line_style(RGBColor(220, 220, 220))
        .draw()?;
    chart
        .configure_secondary_axes()
        .x_desc("a_p / g")
        .y_desc("μ_min")
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;
    let level = |y: f64, style: ShapeStyle, dash: u32| {
        DashedPathElement::new(vec![(x0, y), (x1, y)], dash, dash, style)
    };
    chart.draw_series(std::iter::once(level(1.0, MUTED.stroke_width(1), 4)))?;
    if let Some(m) = d.mu_on_scale.filter(|m| *m < top) {
        chart.draw_series(std::iter::once(level(m, REFERENCE.stroke_width(2), 7)))?;
    }
    for part in clip_y(&d.initiation, 0.0, top) {
        chart.draw_series(DashedLineSeries::new(
            part,
            8,
            5,
            INITIATION.stroke_width(2),
        ))?;
    }
    for run in &d.peak_runs {
        for part in clip_y(run, 0.0, top) {
            chart.draw_series(LineSeries::new(part, PEAK.stroke_width(2)))?;
        }
    }
    chart.draw_series(
        d.points
            .iter()
            .filter_map(|p| Some((p, p.peak?.min(top * 0.995))))
            .map(|(p, peak)| {
                let (kind, colour) = match (p.overturned, p.mode) {
                    (false, _) => (Marker::Ring, PEAK),
                    (true, Some(2)) => (Marker::Square, MODE2),
                    (true, _) => (Marker::Triangle, MODE1),
                };
                marker((p.a, peak), kind, 8, colour)
            }),
    )?;
    let lift_off_edge = top * 0.94;
    chart.draw_series(
        d.points
            .iter()
            .filter(|p| p.lift_off)
            .map(|p| marker((p.a, lift_off_edge), Marker::Cross, 12, INK)),
    )?;
    Ok(())
}

/// The figure of a `friction_spectrum` result.
pub fn svg(result: &FrictionResult) -> Result<String, String> {
    let spec = &result.spec;
    let drawing = Drawing::of(result)?;
    let legend = legend(result, &drawing);
    let title = format!(
        "Friction needed for pure rocking: {} pulse, ω_p/p = {}{}",
        shape_title(spec.pulse.shape()),
        fmt_num(result.omega_ratio, 4),
        crate::jobs::vertical::ScaledVertical::of(spec.vertical.as_ref(), None).map_or(
            String::new(),
            |v| format!(", {}", crate::plot::scaled_vertical_title(&v))
        )
    );
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        draw_chart(&chart_area, result, &drawing)?;
        draw_legend(&side, &legend)
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::kinds::JobResult;
    use crate::kinds::friction_spectrum::{FrictionPointDoc, FrictionResult};

    /// The friction spectrum of the spec `text`.
    fn computed(text: &str) -> FrictionResult {
        match crate::plot::tests::typed(text) {
            JobResult::FrictionSpectrum(r) => *r,
            other => panic!("a friction spectrum, not {:?}", other.job_kind()),
        }
    }

    /// A one-sine friction spectrum at ω_p/p = 7.336 whose twenty amplitudes
    /// (1.1 to 10.6 αg) survive up to 8 αg, overturn in mode 1 up to 9.5 αg
    /// and in mode 2 above.
    pub(crate) fn sample() -> FrictionResult {
        let mut result = computed(
            r#"{"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_sine"}, "formulation": "nonlinear",
                "omega_ratio": 7.336, "a_alpha_g": [1.1]}"#,
        );
        let tan = 0.25f64.tan();
        result.points = (0..20)
            .map(|k| {
                let a = 1.1 + 0.5 * f64::from(k);
                let over = a > 8.0;
                FrictionPointDoc {
                    a_alpha_g: a,
                    a_p_g: a * 0.25,
                    peak_friction_demand: Some(0.25 + 0.04 * a),
                    peak_over_tan_alpha: Some((0.25 + 0.04 * a) / tan),
                    initiation_friction_demand: Some(0.255),
                    overturned: over,
                    mode: over.then_some(if a > 9.5 { 2 } else { 1 }),
                    lift_off: false,
                    lift_off_time: None,
                    friction_demand_followed_until: None,
                }
            })
            .collect();
        result
    }

    #[test]
    fn demand_curve_axes_and_overturned_points() {
        let svg = super::svg(&sample()).expect("svg");
        for needle in [
            "Friction needed for pure rocking: one-sine pulse, ω_p/p = 7.336",
            "a_p / (α g)",
            "μ_min / tan α",
            "block survives",
            "block overturns, mode 1",
            "block overturns, mode 2",
            "when rocking starts",
            "first overturning amplitude: 8.1 αg",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
    }

    /// μ of any size (1e308 stands for "never slides") is drawn as a line
    /// only near the demand; far above it is a note, and the scale follows
    /// the demand (an infinite μ/tan α once made plotters' tick search spin).
    #[test]
    fn a_huge_mu_leaves_the_scale_to_the_demand() {
        let mut result = sample();
        result.spec.block.mu = Some(1.1962447537642911e308);
        let svg = super::svg(&result).expect("svg");
        assert!(svg.contains("μ of the block = 1.2e308: far above"), "{svg}");
        assert!(!svg.contains("(slides above)"));
        result.spec.block.mu = Some(0.4);
        let svg = super::svg(&result).expect("svg");
        assert!(svg.contains("μ of the block = 0.4 (slides"), "{svg}");
    }

    #[test]
    fn lift_off_is_marked_on_the_top_edge() {
        // One-cosine at ω_p/p = 1: 6 αg lifts the block off, 2 αg does not.
        let result = computed(
            r#"{"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_cosine"}, "omega_ratio": 1.0, "a_alpha_g": [2.0, 6.0]}"#,
        );
        let lifted: Vec<bool> = result.points.iter().map(|p| p.lift_off).collect();
        assert_eq!(lifted, [false, true]);
        let svg = super::svg(&result).expect("svg");
        assert!(svg.contains("lift-off (f_z → 0): demand"), "{svg}");
    }

    #[test]
    fn the_figure_names_its_vertical_motion() {
        let r = computed(
            r#"{"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_sine"}, "omega_ratio": 4, "a_alpha_g": [2, 3],
                "vertical": {"type": "one_cosine", "amplitude_ratio": -0.3,
                             "omega_p": 20}}"#,
        );
        let words = crate::plot::tests::words(&super::svg(&r).expect("draws"));
        let needle = "ü_v: a one-cosine pulse, a_v = -0.3 a_p, ω_v = 20 rad/s";
        assert_eq!(words.matches(needle).count(), 1, "the legend: {words}");
        assert!(
            words.contains("ω_p/p = 4, with a vertical pulse of its own"),
            "the title: {words}"
        );
        assert!(!super::svg(&sample()).expect("draws").contains("ü_v"));
        assert!(!super::svg(&sample()).expect("draws").contains("vertical"));
    }

    #[test]
    fn no_points_no_figure() {
        let mut result = sample();
        result.points.clear();
        assert!(super::svg(&result).is_err());
    }
}
