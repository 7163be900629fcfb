//! Fragility: the empirical probability of toppling at each stripe with its
//! 95 % Wilson interval (the primary answer), the fitted lognormal curve and
//! its 95 % bootstrap band (a summary) over the computed intensities, the fit
//! dashed where it is extrapolated beyond them; stripes where the probability
//! falls as the intensity rises are marked; a box lists the inputs (the
//! uncertain block, the pulse or the suite, the samples and the seed).

use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::jobs::distribution::DistributionNorm;
use crate::jobs::names::Im;
use crate::kinds::fragility::{FragilityResult, UncertainNorm};
use crate::plot::style::{
    Area, Drawn, INK, LEGEND, LEGEND_WIDTH, Legend, MODE1, MUTED, Marker, NOTE, Swatch, axis_range,
    chars_in, chart_on, draw_legend, fmt_num, legend_height, marker, mesh, text, tint, wrap,
};
use crate::plot::time_panel::crop;
use crate::plot::{render, shape_title};

const WIDTH: u32 = 1120;
/// Least height of the figure (taller when the legend and inputs need it).
const HEIGHT: u32 = 620;
/// Room the figure's title takes, px.
const TITLE_AREA: u32 = 44;
/// How far past the last stripe the intensity axis runs, as a share of its
/// intensity: the fit is drawn there dashed, as extrapolated.
const BEYOND: f64 = 0.25;
/// Line height in the inputs box, px.
const BOX_LINE: i32 = 20;
/// Height of the inputs box's heading, px.
const BOX_HEADING: i32 = 28;

/// The unit of an intensity measure: "g" (PGA) or "m/s" (PGV).
pub fn im_unit(im: Im) -> &'static str {
    match im {
        Im::PgaG => "g",
        Im::PgvMS => "m/s",
    }
}

/// `x` and its unit, kept on one line.
fn with_unit(x: f64, unit: &str) -> String {
    if unit.is_empty() {
        fmt_num(x, 4)
    } else {
        format!("{}\u{a0}{unit}", fmt_num(x, 4))
    }
}

/// A piece of the fitted curve as the figure draws it.
#[derive(Clone, Debug, PartialEq)]
pub struct FitPiece {
    /// (intensity, P(topple)) along the piece.
    pub points: Vec<(f64, f64)>,
    /// Outside the computed intensities: drawn dashed, as extrapolated.
    pub extrapolated: bool,
}

/// The least and largest computed intensity (the stripes').
pub fn computed_range(result: &FragilityResult) -> Option<(f64, f64)> {
    let ims = result
        .stripes
        .iter()
        .map(|s| s.im)
        .filter(|x| x.is_finite());
    let (lo, hi) = ims.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    (lo <= hi).then_some((lo, hi))
}

/// The end of the intensity axis: the last stripe and [`BEYOND`] of it.
fn x_end(hi: f64) -> f64 {
    hi * (1.0 + BEYOND)
}

/// The fitted curve as drawn: solid over the computed intensities, dashed
/// (extrapolated) below the first stripe and from the last one to the end
/// of the axis; empty without a fit.
pub fn fit_pieces(result: &FragilityResult) -> Vec<FitPiece> {
    let (Some(fit), Some((lo, hi))) = (result.lognormal.as_ref(), computed_range(result)) else {
        return Vec::new();
    };
    let curve: Vec<(f64, f64)> = fit.curve.iter().map(|c| (c.im, c.p)).collect();
    let start = curve.first().map_or(lo, |c| c.0);
    [(start, lo, true), (lo, hi, false), (hi, x_end(hi), true)]
        .into_iter()
        .filter(|(a, b, _)| b > a)
        .map(|(a, b, extrapolated)| FitPiece {
            points: crop(&curve, a, b),
            extrapolated,
        })
        .filter(|piece| piece.points.len() > 1)
        .collect()
}

/// The outline of the bootstrap band over the computed intensities (its
/// upper edge rising, then its lower edge back); empty without a fit.
fn band(result: &FragilityResult) -> Vec<(f64, f64)> {
    let (Some(fit), Some((lo, hi))) = (result.lognormal.as_ref(), computed_range(result)) else {
        return Vec::new();
    };
    let upper: Vec<(f64, f64)> = fit.curve.iter().map(|c| (c.im, c.hi)).collect();
    let lower: Vec<(f64, f64)> = fit.curve.iter().map(|c| (c.im, c.lo)).collect();
    let mut outline = crop(&upper, lo, hi);
    outline.extend(crop(&lower, lo, hi).into_iter().rev());
    outline
}

/// "b ~ normal: mean 0.6 m, sd 0.06 m, within 0.4–0.8 m" of an uncertain
/// input named `name`, its values × `scale` in `unit`.
fn uncertain_text(name: &str, u: &UncertainNorm, unit: &str, scale: f64) -> String {
    let number = |x: f64| fmt_num(x * scale, 4);
    let value = |x: f64| with_unit(x * scale, unit);
    let d = match u {
        UncertainNorm::Fixed(x) => return format!("{name} = {}", value(*x)),
        UncertainNorm::Distribution(d) => d,
    };
    match *d {
        DistributionNorm::Normal { mean, sd, min, max } => {
            let bounds = match (min, max) {
                (Some(a), Some(b)) => format!(", within {}–{}", number(a), value(b)),
                (Some(a), None) => format!(", at least {}", value(a)),
                (None, Some(b)) => format!(", at most {}", value(b)),
                (None, None) => String::new(),
            };
            format!(
                "{name} ~ normal: mean {}, sd {}{bounds}",
                value(mean),
                value(sd)
            )
        }
        DistributionNorm::Lognormal { median, beta } => format!(
            "{name} ~ lognormal: median {}, β = {}",
            value(median),
            fmt_num(beta, 3)
        ),
        DistributionNorm::Uniform { min, max } => {
            format!("{name} ~ uniform on {}–{}", number(min), value(max))
        }
    }
}

/// The inputs of a fragility, one line each, as its result holds them: the
/// block (each parameter fixed or distributed), the pulse family and its
/// frequency or the suite of records, the formulation and solver, the
/// stripes, the samples per stripe and the seed.
pub fn inputs(result: &FragilityResult) -> Vec<String> {
    let spec = &result.spec;
    let block = &spec.block;
    let mut lines = Vec::new();
    for (name, u, unit) in [
        ("α", &block.alpha, "rad"),
        ("p", &block.p, "rad/s"),
        ("b", &block.b, "m"),
        ("h", &block.h, "m"),
        ("η", &block.eta, ""),
    ] {
        if let Some(u) = u {
            lines.push(uncertain_text(name, u, unit, 1.0));
        }
    }
    if block.eta.is_none() {
        lines.push("η = 1 − 1.5\u{a0}sin²α of each sample".into());
    }
    if (block.g - 9.81).abs() > 1e-12 {
        lines.push(format!("g = {}", with_unit(block.g, "m/s²")));
    }
    let measure = match spec.im {
        Im::PgaG => "PGA",
        Im::PgvMS => "PGV",
    };
    if let Some(pulse) = &spec.pulse {
        lines.push(format!(
            "{} pulse scaled to each stripe's {measure}",
            shape_title(pulse.family.shape())
        ));
        if let Some(w) = &pulse.omega_p {
            let tau = std::f64::consts::TAU;
            lines.push(uncertain_text("f_p = ω_p/2π", w, "Hz", 1.0 / tau));
        }
        if let Some(r) = &pulse.omega_ratio {
            lines.push(uncertain_text("ω_p/p", r, "", 1.0));
        }
    }
    if let Some(suite) = &spec.ground_motions {
        let n = suite.len();
        let names: Vec<&str> = suite.iter().map(|m| m.name.as_str()).collect();
        let shown = if n > 4 {
            format!("{}, … ({} more)", names[..3].join(", "), n - 3)
        } else {
            names.join(", ")
        };
        lines.push(format!(
            "suite of {n} record{}, each scaled to the stripe's {measure} (sample j takes record j mod {n}): {shown}",
            if n == 1 { "" } else { "s" }
        ));
    }
    if let Some(v) = &spec.vertical {
        lines.push(uncertain_text("ü_v/ü_g", &v.ratio, "", 1.0));
    }
    if let Some(suite) = &spec.ground_motions {
        let own = suite.iter().filter(|m| m.motion.vertical.is_some()).count();
        if own > 0 {
            lines.push(format!(
                "{own} of the records with a vertical component of their own, scaled with them"
            ));
        }
    }
    lines.push(format!(
        "{} formulation, solver {}",
        spec.formulation.name(),
        spec.solver.method.name()
    ));
    let unit = im_unit(spec.im);
    if let (Some(first), Some(last)) = (spec.stripes.first(), spec.stripes.last()) {
        lines.push(format!(
            "{} stripes, {measure} {}–{}",
            spec.stripes.len(),
            fmt_num(*first, 4),
            with_unit(*last, unit)
        ));
    }
    lines.push(format!(
        "{} samples per stripe, seed {}",
        spec.samples, spec.seed
    ));
    lines
}

/// `lines` wrapped to the inputs box's width `width`, px.
fn box_lines(lines: &[String], width: u32) -> Vec<Vec<String>> {
    let chars = chars_in(f64::from(width) - 24.0, NOTE);
    lines.iter().map(|l| wrap(l, chars)).collect()
}

/// The height of the inputs box holding `lines`, px.
fn box_height(lines: &[Vec<String>]) -> u32 {
    let n: usize = lines.iter().map(Vec::len).sum();
    (BOX_HEADING + n as i32 * BOX_LINE + 12).max(0) as u32
}

/// Draws the inputs box: a frame, its heading and `lines`.
fn draw_inputs(area: &Area, lines: &[Vec<String>]) -> Drawn {
    let (w, _) = area.dim_in_pixel();
    let height = box_height(lines) as i32;
    area.draw(&Rectangle::new(
        [(0, 0), (w as i32 - 1, height)],
        MUTED.stroke_width(1),
    ))?;
    area.draw(&Text::new("inputs", (10, 6), text(LEGEND, INK)))?;
    let mut y = BOX_HEADING;
    for line in lines.iter().flatten() {
        area.draw(&Text::new(line.clone(), (10, y), text(NOTE, INK)))?;
        y += BOX_LINE;
    }
    Ok(())
}

/// A fragility as drawn: its stripes, its fit and band, the axis's end.
struct Drawing<'a> {
    /// (intensity, P, 95 % interval) of each stripe with a probability
    /// (under a vertical motion, one whose every sample lifted off has
    /// none: marked apart).
    stripes: Vec<(f64, f64, f64, f64)>,
    /// The intensities of the stripes without a verdict.
    undecided: Vec<f64>,
    /// The fitted curve's pieces.
    pieces: Vec<FitPiece>,
    /// The outline of the bootstrap band.
    outline: Vec<(f64, f64)>,
    /// The end of the intensity axis.
    x_max: f64,
    /// The stripes where P falls below the one before.
    falls: &'a [f64],
}

impl<'a> Drawing<'a> {
    fn of(result: &'a FragilityResult, hi: f64) -> Drawing<'a> {
        Drawing {
            stripes: result
                .stripes
                .iter()
                .filter(|s| s.p.is_finite())
                .map(|s| (s.im, s.p, s.interval_95[0], s.interval_95[1]))
                .collect(),
            undecided: result
                .stripes
                .iter()
                .filter(|s| !s.p.is_finite())
                .map(|s| s.im)
                .collect(),
            pieces: fit_pieces(result),
            outline: band(result),
            x_max: x_end(hi),
            falls: &result.falls_at,
        }
    }
}

/// The legend of a fragility: the stripes, the fit and its band, the marks
/// of falling and undecided stripes, and the notes on lift-off and the fit.
fn legend(result: &FragilityResult, d: &Drawing, (lo, hi): (f64, f64)) -> Legend {
    let unit = im_unit(result.im);
    let mut legend = Legend::default();
    legend.entry(
        Swatch::Mark(Marker::Dot, INK),
        "P(topple) per stripe, 95 % Wilson interval",
    );
    if let Some(f) = &result.lognormal {
        let [m_lo, m_hi] = f.median_interval_95;
        let interval = if m_lo.is_finite() && m_hi.is_finite() {
            format!(" (95 %: {}–{})", fmt_num(m_lo, 3), with_unit(m_hi, unit))
        } else {
            String::new()
        };
        legend.entry(
            Swatch::Line(MODE1, 3),
            format!(
                "lognormal fit: median θ = {}\u{a0}{unit}{interval}, β = {}",
                fmt_num(f.median, 3),
                fmt_num(f.beta, 3)
            ),
        );
        if d.pieces.iter().any(|p| p.extrapolated) {
            legend.entry(
                Swatch::Dashed(MODE1, 2),
                format!(
                    "the fit extrapolated outside the computed levels ({}–{})",
                    fmt_num(lo, 3),
                    with_unit(hi, unit)
                ),
            );
        }
        legend.entry(Swatch::Fill(tint(MODE1, 0.2)), "95 % bootstrap band");
    } else {
        legend.note("no lognormal fit: the counts do not bound one");
    }
    if !d.falls.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Ring, MODE1),
            "falls below the stripe before (safe regions)",
        );
    }
    if !d.undecided.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Cross, MUTED),
            "every sample lifted off: no verdict",
        );
    }
    let lifted: u64 = result.stripes.iter().filter_map(|s| s.lift_off).sum();
    if lifted > 0 {
        let first = result
            .stripes
            .iter()
            .filter(|s| s.lift_off.unwrap_or(0) > 0)
            .map(|s| s.im)
            .fold(f64::INFINITY, f64::min);
        legend.note(format!(
            "lift-off (the ground falls away faster than g): {lifted} samples from {} on, without a verdict; each P is over the samples decided",
            with_unit(first, unit)
        ));
    }
    if result.lognormal.is_some() {
        legend.note("the empirical points are the answer, the fit a summary");
    }
    legend
}

/// Draws the chart of a fragility in `area`: the band, the fit, each
/// stripe's probability and interval, the marks of falling and undecided
/// stripes.
fn draw_chart(area: &Area, result: &FragilityResult, d: &Drawing) -> Drawn {
    let x_desc = match result.im {
        Im::PgvMS => "PGV (m/s)",
        Im::PgaG => "PGA (g)",
    };
    let mut chart = chart_on(area).build_cartesian_2d(axis_range("x", 0.0, d.x_max)?, 0.0..1.0)?;
    mesh(&mut chart, x_desc, "P(topple)").draw()?;
    if d.outline.len() > 2 {
        chart.draw_series(std::iter::once(Polygon::new(
            d.outline.clone(),
            tint(MODE1, 0.2).filled(),
        )))?;
    }
    for piece in &d.pieces {
        if piece.extrapolated {
            chart.draw_series(std::iter::once(DashedPathElement::new(
                piece.points.clone(),
                9,
                6,
                MODE1.stroke_width(2),
            )))?;
        } else {
            chart.draw_series(LineSeries::new(piece.points.clone(), MODE1.stroke_width(3)))?;
        }
    }
    chart.draw_series(
        d.stripes
            .iter()
            .map(|&(x, _, lo, hi)| PathElement::new(vec![(x, lo), (x, hi)], INK.stroke_width(2))),
    )?;
    chart.draw_series(
        d.stripes
            .iter()
            .map(|&(x, p, _, _)| marker((x, p), Marker::Dot, 6, INK)),
    )?;
    chart.draw_series(
        d.stripes
            .iter()
            .filter(|s| d.falls.contains(&s.0))
            .map(|&(x, p, _, _)| marker((x, p), Marker::Ring, 11, MODE1)),
    )?;
    chart.draw_series(
        d.undecided
            .iter()
            .map(|&x| marker((x, 0.5), Marker::Cross, 8, MUTED)),
    )?;
    Ok(())
}

/// The figure of a `fragility` result.
pub fn svg(result: &FragilityResult) -> Result<String, String> {
    let Some(range) = computed_range(result) else {
        return Err("the result has no stripes".into());
    };
    let drawing = Drawing::of(result, range.1);
    let legend = legend(result, &drawing, range);
    let listed = box_lines(&inputs(result), LEGEND_WIDTH - 16);
    let legend_h = legend_height(&legend, LEGEND_WIDTH, 1);
    let height = HEIGHT.max(TITLE_AREA + legend_h + box_height(&listed) + 24);
    render(
        (WIDTH, height),
        "Fragility: probability of toppling",
        |area| -> Drawn {
            let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
            draw_chart(&chart_area, result, &drawing)?;
            let (upper, lower) = side.split_vertically(legend_h);
            draw_legend(&upper, &legend)?;
            draw_inputs(&lower.margin(8, 0, 8, 16), &listed)
        },
    )
}

#[cfg(test)]
mod tests {
    use super::{computed_range, fit_pieces, im_unit, inputs};
    use crate::jobs::names::Im;
    use crate::kinds::JobResult;
    use crate::kinds::fragility::{CurvePoint, FragilityResult, LognormalFit, StripeResult};
    use crate::plot::style::{INK, LEGEND_WIDTH, MODE1, MUTED, fmt_num, tint};
    use crate::plot::tests::{hex, shapes, x_extent};

    /// The fragility computed for the spec `text`.
    fn fragility(text: &str) -> FragilityResult {
        match crate::plot::tests::typed(text) {
            JobResult::Fragility(r) => *r,
            other => panic!("not a fragility result: {:?}", other.job_kind()),
        }
    }

    /// A small computed fragility (two stripes of 20 simulations).
    fn computed() -> FragilityResult {
        fragility(
            r#"{"kind": "fragility",
            "block": {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.4, "max": 0.8},
                      "h": 1.5},
            "pulse": {"type": "one_sine", "frequency_hz": 1.0},
            "im": "pga_g", "stripes": [0.4, 1.0], "samples": 20, "seed": 42}"#,
        )
    }

    /// A computed fragility with a fit: five stripes of 40 simulations
    /// over uncertain b, h and pulse frequency.
    fn fitted() -> FragilityResult {
        let doc = fragility(
            r#"{"kind": "fragility",
            "block": {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.4, "max": 0.8},
                      "h": {"dist": "uniform", "min": 1.3, "max": 1.7}},
            "pulse": {"type": "one_sine",
                      "frequency_hz": {"dist": "lognormal", "median": 1.0, "beta": 0.4}},
            "im": "pga_g", "stripes": {"from": 0.2, "to": 1.0, "steps": 5},
            "samples": 40, "seed": 7}"#,
        );
        assert!(doc.lognormal.is_some(), "the counts bound a fit");
        doc
    }

    /// Three stripes of 200, the last below the one before, and a fit.
    fn sample() -> FragilityResult {
        let mut doc = computed();
        let stripe = |im, overturned: u64, interval_95| StripeResult {
            im,
            n: 200,
            overturned,
            p: overturned as f64 / 200.0,
            interval_95,
            mode_1: overturned,
            mode_2: 0,
            lift_off: None,
            undecided: None,
        };
        doc.stripes = vec![
            stripe(0.4, 20, [0.06, 0.15]),
            stripe(0.8, 140, [0.63, 0.76]),
            stripe(1.0, 120, [0.53, 0.67]),
        ];
        doc.spec.stripes = vec![0.4, 0.8, 1.0];
        doc.spec.samples = 200;
        doc.falls_at = vec![1.0];
        doc.monotone = false;
        let point = |im, p, lo, hi| CurvePoint { im, p, lo, hi };
        doc.lognormal = Some(LognormalFit {
            median: 0.6,
            beta: 0.4,
            median_interval_95: [0.55, 0.65],
            beta_interval_95: [0.3, 0.5],
            log_likelihood: -300.0,
            curve: vec![point(0.2, 0.003, 0.001, 0.01), point(1.6, 0.96, 0.9, 0.99)],
        });
        doc
    }

    /// The texts of `svg` joined by spaces (a line of the inputs box or the
    /// legend may wrap over several texts).
    fn words(svg: &str) -> String {
        svg.split("<text")
            .skip(1)
            .filter_map(|rest| rest.split_once('>')?.1.split("</text>").next())
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(" ")
            .replace('\u{a0}', " ")
            .replace("&apos;", "'")
            .replace("&amp;", "&")
    }

    #[test]
    fn points_intervals_fit_and_falls() {
        let doc = sample();
        let svg = super::svg(&doc).expect("svg");
        let text = words(&svg);
        for needle in [
            "Fragility: probability of toppling",
            "PGA (g)",
            "P(topple)",
            "median θ = 0.6 g (95 %: 0.55–0.65 g), β = 0.4",
            "95 % bootstrap band",
            "falls below",
            "extrapolated outside the computed levels (0.4–1 g)",
            "200 samples per stripe",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        // The band is drawn (and its legend swatch).
        assert!(svg.contains(&hex(tint(MODE1, 0.2))), "band");
    }

    #[test]
    fn without_a_fit_the_points_stand_alone() {
        let mut doc = sample();
        doc.lognormal = None;
        doc.falls_at.clear();
        assert!(fit_pieces(&doc).is_empty());
        let svg = super::svg(&doc).expect("svg");
        assert!(svg.contains("no lognormal fit"), "said");
        assert!(!svg.contains("bootstrap band"));
        assert!(!svg.contains("extrapolated"));
        assert!(!svg.contains("falls below"));
        assert!(!svg.contains(&hex(tint(MODE1, 0.2))), "no band");
    }

    #[test]
    fn the_computed_stripes() {
        let doc = computed();
        assert_eq!(doc.stripes.len(), 2);
        let svg = super::svg(&doc).expect("svg");
        assert!(words(&svg).contains("20 samples per stripe, seed 42"));
        assert!(svg.contains("PGA (g)"));
    }

    /// Under ü_v = −0.5 ü_g the strongest stripes lift off: they are drawn
    /// as crosses (no probability), the lift-offs and the ratio are named,
    /// and no number of the drawing is NaN.
    #[test]
    fn stripes_that_lifted_off_are_marked_and_named() {
        let doc = fragility(
            r#"{"kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
            "pulse": {"type": "one_sine", "frequency_hz": 0.8},
            "vertical": {"ratio": -0.5},
            "stripes": [0.3, 0.6, 2.2, 3.0], "samples": 8, "seed": 1}"#,
        );
        let undecided = doc.stripes.iter().filter(|s| s.decided() == 0).count();
        assert!(undecided >= 1, "{:?}", doc.stripes);
        let svg = super::svg(&doc).expect("svg");
        let text = words(&svg);
        assert!(text.contains("every sample lifted off"), "{text}");
        assert!(text.contains("lift-off (the ground falls away"), "{text}");
        assert!(
            text.contains("ü_v/ü_g = -0.5") || text.contains("ü_v/ü_g = −0.5"),
            "{text}"
        );
        assert!(!svg.contains("NaN"), "a NaN drawn");
        // One cross per stripe without a verdict, plus the legend's.
        let cross = hex(MUTED);
        assert!(svg.matches(&cross).count() > undecided, "crosses");
    }

    /// The fit is drawn solid over the stripes' intensities only, and
    /// dashed outside them; the solid line in the SVG spans the stripes'
    /// interval bars and no more.
    #[test]
    fn the_fit_is_solid_only_over_the_computed_levels() {
        let doc = fitted();
        let (lo, hi) = computed_range(&doc).expect("stripes");
        let fit = doc.lognormal.as_ref().expect("fit");
        // The computed curve reaches past the last stripe.
        let curve_end = fit.curve.last().expect("curve").im;
        assert!(fit.curve[0].im <= lo && curve_end > hi, "{curve_end}");
        let pieces = fit_pieces(&doc);
        let solid: Vec<_> = pieces.iter().filter(|p| !p.extrapolated).collect();
        assert_eq!(solid.len(), 1);
        let xs = solid[0].points.iter().map(|p| p.0);
        let (a, b) = xs.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        assert!((a - lo).abs() < 1e-12 && (b - hi).abs() < 1e-12, "{a}–{b}");
        // The extrapolated pieces lie outside, and the one above ends at
        // the axis' end (a quarter past the last stripe), before the curve.
        for piece in pieces.iter().filter(|p| p.extrapolated) {
            assert!(piece.points.iter().all(|p| p.0 <= lo || p.0 >= hi));
        }
        let last = pieces
            .last()
            .and_then(|p| p.points.last())
            .expect("a point");
        assert!((last.0 - 1.25 * hi).abs() < 1e-12, "{last:?}");
        // What the SVG draws: the solid curve (3 px) between the first and
        // the last stripe's interval bar (vertical 2 px ink lines).
        let svg = super::svg(&doc).expect("svg");
        let red = format!("stroke=\"{}\" stroke-width=\"3\"", hex(MODE1));
        // In the chart, not the legend's swatch beside it.
        let chart_right = f64::from(super::WIDTH - LEGEND_WIDTH);
        let solid: Vec<Vec<(f64, f64)>> = shapes(&svg, "polyline", &red)
            .into_iter()
            .filter(|s| s.iter().all(|p| p.0 < chart_right))
            .collect();
        assert_eq!(solid.len(), 1);
        let drawn = x_extent(&solid);
        let ink = format!("stroke=\"{}\" stroke-width=\"2\"", hex(INK));
        let bars: Vec<Vec<(f64, f64)>> = shapes(&svg, "polyline", &ink)
            .into_iter()
            .filter(|s| s.len() == 2 && s[0].0 == s[1].0)
            .collect();
        assert_eq!(bars.len(), doc.stripes.len());
        let stripes = x_extent(&bars);
        assert!(
            drawn.0 >= stripes.0 - 1.0 && drawn.1 <= stripes.1 + 1.0,
            "solid {drawn:?}, stripes {stripes:?}"
        );
        assert!(
            drawn.1 - drawn.0 > 0.9 * (stripes.1 - stripes.0),
            "{drawn:?}"
        );
        assert!(words(&svg).contains("extrapolated outside the computed levels"));
    }

    #[test]
    fn the_median_is_written_with_its_unit() {
        let mut doc = fitted();
        let theta = doc.lognormal.as_ref().expect("fit").median;
        for (im, unit) in [(Im::PgaG, "g"), (Im::PgvMS, "m/s")] {
            doc.im = im;
            assert_eq!(im_unit(im), unit);
            let text = words(&super::svg(&doc).expect("svg"));
            let median = format!("median θ = {} {unit}", fmt_num(theta, 3));
            assert!(text.contains(&median), "missing {median:?} in {text}");
        }
    }

    #[test]
    fn the_inputs_box_names_block_pulse_samples_and_seed() {
        let doc = fitted();
        let listed = inputs(&doc);
        let run = format!(
            "{} samples per stripe, seed {}",
            doc.spec.samples, doc.spec.seed
        );
        assert_eq!(run, "40 samples per stripe, seed 7");
        assert!(listed.contains(&run), "{listed:?}");
        let plain: Vec<String> = listed.iter().map(|l| l.replace('\u{a0}', " ")).collect();
        for line in [
            "b ~ normal: mean 0.6 m, sd 0.06 m, within 0.4–0.8 m",
            "h ~ uniform on 1.3–1.7 m",
            "η = 1 − 1.5 sin²α of each sample",
            "one-sine pulse scaled to each stripe's PGA",
            "f_p = ω_p/2π ~ lognormal: median 1 Hz, β = 0.4",
            "5 stripes, PGA 0.2–1 g",
        ] {
            assert!(plain.iter().any(|l| l == line), "no {line:?} in {plain:?}");
        }
        // Drawn in a framed box: every line's text inside the frame.
        let svg = super::svg(&doc).expect("svg");
        let text = words(&svg);
        for line in &plain {
            assert!(text.contains(line.as_str()), "not drawn: {line:?}");
        }
        let frame = svg
            .split("<rect ")
            .skip(1)
            .filter_map(|r| r.split('>').next())
            .find(|r| r.contains(&format!("stroke=\"{}\"", hex(MUTED))))
            .expect("a frame");
        let attr = |tag: &str, name: &str| -> f64 {
            format!(" {tag}")
                .split(&format!(" {name}=\""))
                .nth(1)
                .and_then(|v| v.split('"').next())
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN)
        };
        let (fx, fy) = (attr(frame, "x"), attr(frame, "y"));
        let (fw, fh) = (attr(frame, "width"), attr(frame, "height"));
        let tag = svg
            .split("<text")
            .find(|t| t.contains("samples per stripe"))
            .expect("the samples' line");
        let (x, y) = (attr(tag, "x"), attr(tag, "y"));
        assert!(
            x > fx && x < fx + fw && y > fy && y < fy + fh,
            "({x}, {y}) outside {fx} {fy} {fw} {fh}"
        );
    }

    #[test]
    fn the_inputs_of_a_suite_name_its_records() {
        let acc: Vec<String> = (0..200)
            .map(|k| ((f64::from(k) * 0.12).sin() * 0.3).to_string())
            .collect();
        let record = |name: &str| {
            format!(
                r#"{{"name": "{name}", "dt": 0.01, "acc": [{}], "unit": "g"}}"#,
                acc.join(", ")
            )
        };
        let doc = fragility(&format!(
            r#"{{"kind": "fragility", "block": {{"alpha": 0.2, "p": 2.0}},
                "ground_motions": [{}, {}], "stripes": [0.3, 0.6], "samples": 4, "seed": 3}}"#,
            record("north"),
            record("east")
        ));
        let listed = inputs(&doc).join("\n");
        for needle in [
            "α = 0.2",
            "p = 2",
            "suite of 2 records, each scaled to the stripe's PGA",
            ": north, east",
            "4 samples per stripe, seed 3",
        ] {
            assert!(listed.contains(needle), "no {needle:?} in {listed}");
        }
        assert!(!listed.contains("pulse"), "{listed}");
    }
}
