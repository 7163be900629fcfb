//! Survival of rocks under a hazard model: the probability that each rock
//! still stands after T years, P_s = exp(−λ_t T), on a logarithmic age axis;
//! the requested ages marked; an uncertain age at its median with
//! E[exp(−λ_t T)]; several rocks' joint probability noted.

use plotters::prelude::*;

use super::forensic::colour;
use super::render;
use super::style::{
    Drawn, INK, LEGEND_WIDTH, Legend, Marker, Swatch, axis_range, chart_on, draw_legend, fmt_num,
    marker, mesh,
};
use crate::jobs::survival::{RockResult, SurvivalResult};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 620;

/// The figure of a `survival` result.
pub fn svg(result: &SurvivalResult) -> Result<String, String> {
    let rocks = &result.rocks;
    if rocks.is_empty() {
        return Err("the result has no rocks".into());
    }
    let points = |r: &RockResult| -> Vec<(f64, f64, bool)> {
        let mut p: Vec<(f64, f64, bool)> = r
            .ages
            .iter()
            .map(|a| (a.age_years, a.survival_probability, false))
            .collect();
        if let Some(d) = &r.age_distribution {
            p.push((d.median_age_years, d.survival_probability, true));
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
                .map(|r| r.annual_toppling_rate)
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
            let l = r.annual_toppling_rate;
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
        let name = &r.name;
        legend.entry(
            Swatch::Line(colour(k), 3),
            format!(
                "{name}: λ_t = {}/yr (1 in {} yr)",
                fmt_num(r.annual_toppling_rate, 4),
                fmt_num(1.0 / r.annual_toppling_rate, 4)
            ),
        );
    }
    // An age is marked in its rock's colour: the legend's mark is that
    // colour for one rock, and says so for several.
    let (mark, whose) = if rocks.len() == 1 {
        (colour(0), "")
    } else {
        (INK, ", in the colour of its rock")
    };
    legend.entry(
        Swatch::Mark(Marker::Dot, mark),
        format!("an age asked for{whose}"),
    );
    if rocks.iter().any(|r| r.age_distribution.is_some()) {
        legend.entry(
            Swatch::Mark(Marker::Square, mark),
            format!("uncertain age: E[P_s] at its median{whose}"),
        );
    }
    if let Some(j) = &result.joint {
        legend.note(format!(
            "all {} rocks standing: P = {}; every hazard rate × {} brings it to 5 %",
            rocks.len(),
            fmt_num(j.survival_probability, 4),
            fmt_num(j.rate_scale_at_5_percent.unwrap_or(f64::NAN), 4)
        ));
    }
    legend
        .note("P_s = exp(−λ_t T): topplings as a Poisson process; λ_t = ∫ P(topple | im) |dλ(im)|");
    legend.note(format!(
        "hazard in {}, interpolated log-log",
        result.im.name()
    ));

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
    use crate::jobs::JobResult;
    use crate::jobs::survival::{
        AgeDistributionResult, AgeResult, FragilityNorm, JointResult, RockResult, SurvivalResult,
    };
    use crate::plot::style::fmt_num;
    use crate::plot::tests::typed;

    /// The computed survival of the power-law hazard (one rock, three ages).
    fn computed() -> SurvivalResult {
        match typed(include_str!("../../specs/survival_power_law.json")) {
            JobResult::Survival(r) => *r,
            other => panic!("not a survival result: {:?}", other.job_kind()),
        }
    }

    fn rock(name: &str, annual_toppling_rate: f64) -> RockResult {
        RockResult {
            name: name.into(),
            fragility: FragilityNorm {
                median: 0.38,
                beta: 0.38,
            },
            annual_toppling_rate,
            mean_years_between_topplings: Some(1.0 / annual_toppling_rate),
            extrapolated_share: 0.0,
            ages: Vec::new(),
            age_distribution: None,
        }
    }

    #[test]
    fn curves_and_ages_of_each_rock() {
        let mut doc = computed();
        let mut grass = rock("Grass Valley", 1.785e-4);
        grass.ages = vec![AgeResult {
            age_years: 1000.0,
            survival_probability: 0.8365,
            rate_scale_at_5_percent: Some(16.8),
        }];
        let mut lovejoy = rock("Lovejoy", 5e-5);
        lovejoy.age_distribution = Some(AgeDistributionResult {
            median_age_years: 15000.0,
            survival_probability: 0.47,
            rate_scale_at_5_percent: Some(4.0),
        });
        doc.rocks = vec![grass, lovejoy];
        doc.joint = Some(JointResult {
            survival_probability: 0.39,
            rate_scale_at_5_percent: Some(2.1),
        });
        let svg = super::svg(&doc).expect("svg");
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
        // Several rocks: the legend's mark says whose colour an age takes.
        assert!(
            words(&svg).contains("an age asked for, in the colour of its rock"),
            "{}",
            words(&svg)
        );
    }

    #[test]
    fn the_computed_rock_and_its_ages() {
        let doc = computed();
        assert_eq!(doc.rocks.len(), 1);
        let rate = doc.rocks[0].annual_toppling_rate;
        assert!(rate > 0.0, "{rate}");
        let svg = super::svg(&doc).expect("svg");
        for needle in [
            format!("rock: λ_t = {}/yr", fmt_num(rate, 4)),
            format!("{} yr)", fmt_num(1.0 / rate, 4)),
            "an age asked for".to_string(),
            "hazard in pga_g".to_string(),
        ] {
            assert!(svg.contains(&needle), "missing {needle:?}");
        }
        // One rock, no uncertain age and no joint probability.
        assert!(!svg.contains("uncertain age"));
        assert!(!svg.contains("rocks standing"));
        // The ages' marks and the legend's mark are the rock's colour.
        let fill = format!("fill=\"{}\"", crate::plot::tests::hex(super::colour(0)));
        let dots = svg
            .split("<polygon")
            .skip(1)
            .filter(|c| c.split('>').next().unwrap_or("").contains(&fill))
            .count();
        assert_eq!(dots, doc.rocks[0].ages.len() + 1, "{fill}");
        assert!(!words(&svg).contains("colour of its rock"));
    }

    /// The text of `svg`, its pieces joined by single spaces.
    fn words(svg: &str) -> String {
        let text: Vec<&str> = svg
            .split('>')
            .filter_map(|piece| piece.split('<').next())
            .map(str::trim)
            .filter(|t| !t.is_empty())
            .collect();
        text.join(" ")
    }
}
