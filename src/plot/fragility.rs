//! Fragility: the empirical probability of toppling at each stripe with its
//! 95 % Wilson interval (the primary answer), the fitted lognormal curve and
//! its 95 % bootstrap band (a summary); stripes where the probability falls
//! as the intensity rises are marked.

use plotters::prelude::*;

use super::render;
use super::style::{
    Drawn, INK, LEGEND_WIDTH, Legend, MODE1, Marker, Swatch, axis_range, chart_on, draw_legend,
    fmt_num, marker, mesh, tint,
};
use crate::jobs::fragility::FragilityResult;
use crate::jobs::names::Im;

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 620;

/// The figure of a `fragility` result.
pub fn svg(result: &FragilityResult) -> Result<String, String> {
    let stripes: Vec<(f64, f64, f64, f64)> = result
        .stripes
        .iter()
        .map(|s| (s.im, s.p, s.interval_95[0], s.interval_95[1]))
        .collect();
    if stripes.is_empty() {
        return Err("the result has no stripes".into());
    }
    let fit = result.lognormal.as_ref();
    let curve: Vec<(f64, f64, f64, f64)> = fit
        .map(|f| f.curve.iter().map(|c| (c.im, c.p, c.lo, c.hi)).collect())
        .unwrap_or_default();
    let x_max = stripes
        .iter()
        .map(|s| s.0)
        .chain(curve.iter().map(|c| c.0))
        .fold(0.0f64, f64::max)
        * 1.05;
    let falls = &result.falls_at;
    let x_desc = match result.im {
        Im::PgvMS => "PGV (m/s)",
        Im::PgaG => "PGA (g)",
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
                fmt_num(f.median, 3),
                fmt_num(f.beta, 3)
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
    if let Some(n) = result.stripes.first().map(|s| s.n) {
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
    use crate::jobs::JobResult;
    use crate::jobs::fragility::{CurvePoint, FragilityResult, LognormalFit, StripeResult};
    use crate::plot::style::{MODE1, tint};
    use crate::plot::tests::hex;

    /// A small computed fragility (two stripes of 20 simulations).
    fn computed() -> FragilityResult {
        let spec = r#"{"kind": "fragility",
            "block": {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.4, "max": 0.8},
                      "h": 1.5},
            "pulse": {"type": "one_sine", "frequency_hz": 1.0},
            "im": "pga_g", "stripes": [0.4, 1.0], "samples": 20, "seed": 42}"#;
        match crate::plot::tests::typed(spec) {
            JobResult::Fragility(r) => *r,
            other => panic!("not a fragility result: {:?}", other.job_kind()),
        }
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
        };
        doc.stripes = vec![
            stripe(0.4, 20, [0.06, 0.15]),
            stripe(0.8, 140, [0.63, 0.76]),
            stripe(1.0, 120, [0.53, 0.67]),
        ];
        doc.falls_at = vec![1.0];
        doc.monotone = false;
        let point = |im, p, lo, hi| CurvePoint { im, p, lo, hi };
        doc.lognormal = Some(LognormalFit {
            median: 0.6,
            beta: 0.4,
            median_interval_95: [0.55, 0.65],
            beta_interval_95: [0.3, 0.5],
            log_likelihood: -300.0,
            curve: vec![point(0.2, 0.003, 0.001, 0.01), point(1.2, 0.96, 0.9, 0.99)],
        });
        doc
    }

    #[test]
    fn points_intervals_fit_and_falls() {
        let svg = super::svg(&sample()).expect("svg");
        for needle in [
            "Fragility: probability of toppling",
            "PGA (g)",
            "P(topple)",
            "θ = 0.6",
            "95 % bootstrap band",
            "falls below",
            "200 simulations per stripe",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
        // The band is drawn (and its legend swatch).
        assert!(svg.contains(&hex(tint(MODE1, 0.2))), "band");
    }

    #[test]
    fn without_a_fit_the_points_stand_alone() {
        let mut doc = sample();
        doc.lognormal = None;
        doc.falls_at.clear();
        let svg = super::svg(&doc).expect("svg");
        assert!(svg.contains("no lognormal fit"), "said");
        assert!(!svg.contains("bootstrap band"));
        assert!(!svg.contains("falls below"));
        assert!(!svg.contains(&hex(tint(MODE1, 0.2))), "no band");
    }

    #[test]
    fn the_computed_stripes() {
        let doc = computed();
        assert_eq!(doc.stripes.len(), 2);
        let svg = super::svg(&doc).expect("svg");
        assert!(svg.contains("20 simulations per stripe"), "counts");
        assert!(svg.contains("PGA (g)"));
    }
}
