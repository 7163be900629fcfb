//! Survival of rocks under a hazard model: the probability that each rock
//! still stands after T years, P_s = exp(−λ_t T), on a logarithmic age axis;
//! the requested ages marked and labelled with their probability (labels
//! that would overlap stacked away, joined to their mark by a leader line);
//! an uncertain age at its median with E[exp(−λ_t T)]; several rocks' joint
//! probability noted.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::kinds::forensic::figure::colour;
use crate::kinds::survival::{RockResult, SurvivalResult};
use crate::plot::render;
use crate::plot::style::{
    Area, Drawn, INK, LEGEND_WIDTH, Legend, MUTED, Marker, NOTE, Swatch, axis_range, chart_on,
    draw_legend, fmt_num, left_top, legend_height, marker, mesh, right_top, text_width,
};
pub use crate::plot::style::{Box4, overlap};

const WIDTH: u32 = 1120;
/// Least height of the figure (taller when the legend needs it).
const HEIGHT: u32 = 620;
/// Room the figure's title takes, px.
const TITLE_AREA: u32 = 44;
/// Room kept under the legend for a note drawn with the chart, px.
const LATE_NOTE: u32 = 44;
/// Size of the ages' labels, px.
const LABEL: u32 = NOTE;
/// Room around a label's text, px.
const PAD: i32 = 2;
/// Line height of a label, px.
const LINE: i32 = LABEL as i32 + 2;
/// Distance of a label from its mark, px.
const GAP: i32 = 6;
/// Half the size of the room a mark takes, px.
const MARK: i32 = 5;
/// How many label heights a label may be stacked away from its mark.
const MAX_STACK: i32 = 24;

/// The room a label of `lines` takes, px (the legend's estimate of text
/// width).
pub fn label_size(lines: &[String]) -> (i32, i32) {
    let widest = lines
        .iter()
        .map(|l| text_width(l, LABEL).ceil() as i32)
        .max()
        .unwrap_or(0);
    let n = lines.len().max(1) as i32;
    (widest + 2 * PAD, (n - 1) * LINE + LABEL as i32 + 2 * PAD)
}

/// A label placed beside its mark.
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// Its box, px.
    pub area: Box4,
    /// Stacked away from its mark: a leader line joins them.
    pub led: bool,
}

/// Places a label of `sizes[k]` by each mark `anchors[k]` (px) inside
/// `bounds`, in order, none overlapping a label placed before or any
/// mark, and no leader line crossing a label: beside its mark when there
/// is room (first above right and below left, off the falling curves), else
/// stacked above or below it (with a leader line); off the points `clear`
/// (the curves) where it can be; `None` for a label that finds no room.
pub fn place_labels(
    anchors: &[(i32, i32)],
    sizes: &[(i32, i32)],
    bounds: Box4,
    clear: &[(i32, i32)],
) -> Vec<Option<Placed>> {
    let marks: Vec<Box4> = anchors
        .iter()
        .map(|&(x, y)| (x - MARK, y - MARK, x + MARK, y + MARK))
        .collect();
    let mut placed: Vec<Box4> = Vec::new();
    // Points along the leader lines drawn so far.
    let mut leaders: Vec<(i32, i32)> = Vec::new();
    let inside = |b: Box4| b.0 >= bounds.0 && b.1 >= bounds.1 && b.2 <= bounds.2 && b.3 <= bounds.3;
    let covers = |b: Box4, p: &(i32, i32)| p.0 >= b.0 && p.0 <= b.2 && p.1 >= b.1 && p.1 <= b.3;
    // Strictly inside: a leader may end on its own label's edge.
    let within = |b: Box4, p: &(i32, i32)| p.0 > b.0 && p.0 < b.2 && p.1 > b.1 && p.1 < b.3;
    anchors
        .iter()
        .zip(sizes)
        .map(|(&(x, y), &(w, h))| {
            let (right, left) = (x + GAP, x - GAP - w);
            let (above, below) = (y - GAP - h, y + GAP);
            let beside = [(right, above), (left, below), (right, below), (left, above)]
                .into_iter()
                .map(|corner| (corner, false));
            // A stacked label moves along to stay inside (a long one may
            // not fit at either side of its mark).
            let along = move |x: i32| x.min(bounds.2 - w).max(bounds.0);
            // Stacked: a row further up or down each time, at either side
            // and then further out (so that leaders can pass each other).
            let stacked = (1..=MAX_STACK).flat_map(move |k| {
                let step = k * (h + 2);
                [0, w / 2, w].into_iter().flat_map(move |out| {
                    [
                        (right + GAP + out, above - step),
                        (left - GAP - out, below + step),
                        (right + GAP + out, below + step),
                        (left - GAP - out, above - step),
                    ]
                    .into_iter()
                    .map(move |(x, y)| ((along(x), y), true))
                })
            });
            let candidates: Vec<Placed> = beside
                .chain(stacked)
                .map(|((bx, by), led)| Placed {
                    area: (bx, by, bx + w, by + h),
                    led,
                })
                .filter(|c| {
                    let b = c.area;
                    let lead = if c.led {
                        dense(&[(x, y), nearest(b, (x, y))])
                    } else {
                        Vec::new()
                    };
                    inside(b)
                        && !placed.iter().any(|p| overlap(*p, b))
                        && !marks.iter().any(|m| overlap(*m, b))
                        && !leaders.iter().any(|q| within(b, q))
                        && !lead.iter().any(|q| placed.iter().any(|p| within(*p, q)))
                })
                .collect();
            let found = candidates
                .iter()
                .find(|c| !clear.iter().any(|p| covers(c.area, p)))
                .or(candidates.first())
                .cloned();
            if let Some(p) = &found {
                placed.push(p.area);
                if p.led {
                    leaders.extend(dense(&[(x, y), nearest(p.area, (x, y))]));
                }
            }
            found
        })
        .collect()
}

/// The points of the polyline `line` (px) with none more than 4 px from
/// the next.
fn dense(line: &[(i32, i32)]) -> Vec<(i32, i32)> {
    let mut out: Vec<(i32, i32)> = line.first().copied().into_iter().collect();
    for pair in line.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 4).max(1);
        out.extend(
            (1..=steps).map(|k| (a.0 + (b.0 - a.0) * k / steps, a.1 + (b.1 - a.1) * k / steps)),
        );
    }
    out
}

/// The point of `b` nearest to `p`.
fn nearest(b: Box4, p: (i32, i32)) -> (i32, i32) {
    (p.0.clamp(b.0, b.2), p.1.clamp(b.1, b.3))
}

/// The lines of the label of an age's mark: "1000 yr: P_s = 0.837", or for
/// an uncertain age "median 15000 yr: E[P_s] = 0.47"; under the rock's name
/// when there are several.
pub fn age_label(rock: Option<&str>, age: f64, p: f64, uncertain: bool) -> Vec<String> {
    let value = if uncertain {
        format!("median {} yr: E[P_s] = {}", fmt_num(age, 4), fmt_num(p, 3))
    } else {
        format!("{} yr: P_s = {}", fmt_num(age, 4), fmt_num(p, 3))
    };
    rock.map(str::to_string)
        .into_iter()
        .chain([value])
        .collect()
}

/// The ages marked on a rock's curve: (age, P_s, uncertain) of each age
/// asked for, and of its uncertain age at the median.
fn marked(r: &RockResult) -> Vec<(f64, f64, bool)> {
    let mut p: Vec<(f64, f64, bool)> = r
        .ages
        .iter()
        .map(|a| (a.age_years, a.survival_probability, false))
        .collect();
    if let Some(d) = &r.age_distribution {
        p.push((d.median_age_years, d.survival_probability, true));
    }
    p
}

/// The age axis: two decades around the rocks' mean return periods and
/// ages, years.
fn age_range(rocks: &[RockResult]) -> (f64, f64) {
    let mut ts: Vec<f64> = rocks
        .iter()
        .flat_map(|r| marked(r).into_iter().map(|p| p.0))
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
    match (ts.first(), ts.last()) {
        (Some(&a), Some(&b)) => (a / 10.0, b * 10.0),
        _ => (1.0, 1e6),
    }
}

/// Each rock's survival curve exp(−λ_t T) over the ages `lo`–`hi`.
fn curves(rocks: &[RockResult], (lo, hi): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    rocks
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
        .collect()
}

/// The legend of a survival figure: each rock's rate, the marks of the
/// ages, then the joint probability and the model.
fn legend(result: &SurvivalResult) -> Legend {
    let rocks = &result.rocks;
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
    legend
}

/// A mark of an age on the chart: (age, P_s, its label's lines).
type AgeMark = (f64, f64, Vec<String>);

/// Draws the chart of a survival figure in `area`: each rock's curve, its
/// ages marked and labelled; returns how many labels were left out for
/// room, of how many.
fn draw_chart(
    area: &Area,
    rocks: &[RockResult],
    curves: &[Vec<(f64, f64)>],
    (lo, hi): (f64, f64),
) -> Result<(usize, usize), Box<dyn std::error::Error>> {
    let mut chart =
        chart_on(area).build_cartesian_2d(axis_range("x", lo, hi)?.log_scale(), 0.0..1.0)?;
    mesh(&mut chart, "age T (years)", "P(still standing)").draw()?;
    for (k, c) in curves.iter().enumerate() {
        chart.draw_series(LineSeries::new(c.clone(), colour(k).stroke_width(3)))?;
    }
    for (k, r) in rocks.iter().enumerate() {
        chart.draw_series(marked(r).into_iter().map(|(t, p, uncertain)| {
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
    // Every mark labelled, left to right, placed among the others.
    let several = rocks.len() > 1;
    let mut marks: Vec<AgeMark> = rocks
        .iter()
        .flat_map(|r| {
            let name = several.then_some(r.name.as_str());
            marked(r)
                .into_iter()
                .map(move |(t, p, uncertain)| (t, p, age_label(name, t, p, uncertain)))
        })
        .filter(|(t, p, _)| *t >= lo && *t <= hi && p.is_finite())
        .collect();
    marks.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    let anchors: Vec<(i32, i32)> = marks
        .iter()
        .map(|(t, p, _)| chart.backend_coord(&(*t, *p)))
        .collect();
    let sizes: Vec<(i32, i32)> = marks.iter().map(|m| label_size(&m.2)).collect();
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let bounds = (xs.start, ys.start, xs.end, ys.end);
    let clear: Vec<(i32, i32)> = curves
        .iter()
        .flat_map(|c| {
            let px: Vec<(i32, i32)> = c.iter().map(|q| chart.backend_coord(q)).collect();
            dense(&px)
        })
        .collect();
    let places = place_labels(&anchors, &sizes, bounds, &clear);
    for ((mark, at), place) in marks.iter().zip(&anchors).zip(&places) {
        if let Some(place) = place {
            draw_label(&mut chart, mark, *at, place)?;
        }
    }
    let left_out = places.iter().filter(|p| p.is_none()).count();
    Ok((left_out, places.len()))
}

/// Draws the label of `mark` (at `at`, px) where it was placed: beside it,
/// or stacked away with a leader line to it.
fn draw_label<X: Ranged<ValueType = f64>>(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<X, RangedCoordf64>>,
    mark: &AgeMark,
    at: (i32, i32),
    place: &Placed,
) -> Drawn {
    let (l, t, r, _) = place.area;
    let offset = |q: (i32, i32)| (q.0 - at.0, q.1 - at.1);
    // Left of its mark the text ends at the box's right edge, so
    // that it stands by the mark (or its leader) whatever its width.
    let (text_at, style) = if r <= at.0 {
        (offset((r - PAD, t + PAD)), right_top(LABEL, INK))
    } else {
        (offset((l + PAD, t + PAD)), left_top(LABEL, INK))
    };
    let lead = if place.led {
        vec![(0, 0), offset(nearest(place.area, at))]
    } else {
        Vec::new()
    };
    chart.draw_series(std::iter::once(
        EmptyElement::at((mark.0, mark.1)) + PathElement::new(lead, MUTED.stroke_width(1)),
    ))?;
    chart.draw_series(mark.2.iter().enumerate().map(|(k, line)| {
        let at = (text_at.0, text_at.1 + k as i32 * LINE);
        EmptyElement::at((mark.0, mark.1)) + Text::new(line.clone(), at, style.clone())
    }))?;
    Ok(())
}

/// The figure of a `survival` result.
pub fn svg(result: &SurvivalResult) -> Result<String, String> {
    let rocks = &result.rocks;
    if rocks.is_empty() {
        return Err("the result has no rocks".into());
    }
    let range = age_range(rocks);
    let curves = curves(rocks, range);
    let legend = legend(result);
    let height = HEIGHT.max(TITLE_AREA + legend_height(&legend, LEGEND_WIDTH, 1) + LATE_NOTE);
    render(
        (WIDTH, height),
        "Survival under the hazard model",
        |area| -> Drawn {
            let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
            let (left_out, labels) = draw_chart(&chart_area, rocks, &curves, range)?;
            let mut legend = legend.clone();
            if left_out > 0 {
                legend.note(format!(
                    "{left_out} of {labels} ages' labels left out for room (their marks stand)"
                ));
            }
            draw_legend(&side, &legend)
        },
    )
}

#[cfg(test)]
mod tests {
    use super::{Box4, LABEL, age_label, overlap, place_labels};
    use crate::kinds::JobResult;
    use crate::kinds::survival::{
        AgeDistributionResult, AgeResult, FragilityNorm, JointResult, RockResult, SurvivalResult,
    };
    use crate::plot::style::{MUTED, fmt_num, text_width};
    use crate::plot::tests::{hex, shapes, typed};

    /// The computed survival of the power-law hazard (one rock, three ages).
    fn computed() -> SurvivalResult {
        match typed(include_str!("../../../specs/survival_power_law.json")) {
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

    /// The hazard of specs/survival_power_law.json.
    fn hazard() -> String {
        let spec: serde_json::Value =
            serde_json::from_str(include_str!("../../../specs/survival_power_law.json"))
                .expect("json");
        spec["hazard"].to_string()
    }

    /// Six rocks of close fragilities and ages (900 to 1200 years, one
    /// uncertain), their marks crowded on close curves.
    fn crowded_rocks() -> SurvivalResult {
        let rocks = [
            ("Grass Valley", 0.38, "1000"),
            ("Lovejoy", 0.40, "1000"),
            (
                "Echo Cliffs",
                0.42,
                r#"{"dist": "lognormal", "median": 1100, "beta": 0.3}"#,
            ),
            ("Pacifico", 0.36, "1100"),
            ("Mojave", 0.39, "1200"),
            ("Silverwood", 0.41, "900"),
        ]
        .map(|(name, median, age)| {
            format!(
                r#"{{"name": "{name}", "fragility": {{"median_g": {median}, "beta": 0.38}},
                    "age_years": {age}}}"#
            )
        });
        let spec = format!(
            r#"{{"kind": "survival", "hazard": {}, "rocks": [{}]}}"#,
            hazard(),
            rocks.join(", ")
        );
        match typed(&spec) {
            JobResult::Survival(r) => *r,
            other => panic!("not a survival result: {:?}", other.job_kind()),
        }
    }

    /// One rock and eight ages from 800 to 2000 years.
    fn close_ages() -> SurvivalResult {
        let spec = format!(
            r#"{{"kind": "survival", "hazard": {}, "fragility": {{"median_g": 0.38, "beta": 0.38}},
                "age_years": [800, 900, 1000, 1100, 1200, 1300, 1500, 2000]}}"#,
            hazard()
        );
        match typed(&spec) {
            JobResult::Survival(r) => *r,
            other => panic!("not a survival result: {:?}", other.job_kind()),
        }
    }

    /// The texts drawn in the chart of `svg` (left of the legend): each
    /// with its box as drawn (from its anchor, the width the figures
    /// estimate for it, and its size).
    fn chart_texts(svg: &str) -> Vec<(String, Box4)> {
        let chart_right = (super::WIDTH - super::LEGEND_WIDTH) as i32;
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                let (tag, rest) = t.split_once('>')?;
                let text = rest.split("</text>").next()?.trim().to_string();
                let attr = |name: &str| -> Option<&str> {
                    tag.split(&format!(" {name}=\"")).nth(1)?.split('"').next()
                };
                let (x, y): (i32, i32) = (attr("x")?.parse().ok()?, attr("y")?.parse().ok()?);
                let w = text_width(&text, LABEL).ceil() as i32;
                let left = if attr("text-anchor") == Some("end") {
                    x - w
                } else {
                    x
                };
                (x < chart_right).then(|| (text, (left, y, left + w, y + LABEL as i32)))
            })
            .collect()
    }

    /// Every mark of `doc` labelled in `svg` (each line of its label drawn
    /// once), no two lines of labels overlapping; the number of leader
    /// lines drawn.
    fn assert_labels_apart(doc: &SurvivalResult, svg: &str) -> usize {
        let several = doc.rocks.len() > 1;
        let lines: Vec<String> = doc
            .rocks
            .iter()
            .flat_map(|r| {
                let name = several.then_some(r.name.as_str());
                let asked = r
                    .ages
                    .iter()
                    .map(move |a| age_label(name, a.age_years, a.survival_probability, false));
                let uncertain = r.age_distribution.iter().map(move |d| {
                    age_label(name, d.median_age_years, d.survival_probability, true)
                });
                asked.chain(uncertain).flatten()
            })
            .collect();
        let drawn = chart_texts(svg);
        let boxes: Vec<&(String, Box4)> = drawn.iter().filter(|(t, _)| lines.contains(t)).collect();
        assert_eq!(boxes.len(), lines.len(), "{lines:?} {boxes:?}");
        for (i, (a, ba)) in boxes.iter().enumerate() {
            for (b, bb) in &boxes[i + 1..] {
                assert!(!overlap(*ba, *bb), "{a:?} {ba:?} overlaps {b:?} {bb:?}");
            }
        }
        assert!(!svg.contains("left out for room"));
        // Leader lines are in the chart (the legend's rule is of their
        // colour too).
        let chart_right = f64::from(super::WIDTH - super::LEGEND_WIDTH);
        let muted = format!("stroke=\"{}\"", hex(MUTED));
        let leaders: Vec<Vec<(f64, f64)>> = shapes(svg, "polyline", &muted)
            .into_iter()
            .filter(|l| l.len() == 2 && l.iter().all(|p| p.0 < chart_right))
            .collect();
        // No leader crosses a label.
        for l in &leaders {
            let (a, b) = (l[0], l[1]);
            for k in 0..=100 {
                let s = f64::from(k) / 100.0;
                let p = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
                for (t, bx) in &boxes {
                    let inside = p.0 > f64::from(bx.0)
                        && p.0 < f64::from(bx.2)
                        && p.1 > f64::from(bx.1)
                        && p.1 < f64::from(bx.3);
                    assert!(!inside, "the leader {l:?} crosses {t:?} {bx:?}");
                }
            }
        }
        leaders.len()
    }

    #[test]
    fn labels_of_crowded_rocks_never_overlap() {
        let doc = crowded_rocks();
        assert_eq!(doc.rocks.len(), 6);
        let svg = super::svg(&doc).expect("svg");
        let leaders = assert_labels_apart(&doc, &svg);
        // The marks are that close: some labels stand away, led by a line.
        assert!(leaders > 0, "no leader line");
        // Each label names its rock, the probability computed under it.
        let lovejoy = &doc.rocks[1];
        let label = age_label(
            Some("Lovejoy"),
            1000.0,
            lovejoy.ages[0].survival_probability,
            false,
        );
        let drawn = chart_texts(&svg);
        let at = |line: &str| {
            drawn
                .iter()
                .find(|(t, _)| t == line)
                .map(|(_, b)| b)
                .expect("drawn")
        };
        let (name, value) = (at(&label[0]), at(&label[1]));
        assert_eq!(name.1 + super::LINE, value.1, "{name:?} {value:?}");
        assert!(name.0 == value.0 || name.2 == value.2, "aligned");
        let echo = doc.rocks[2]
            .age_distribution
            .as_ref()
            .expect("uncertain age");
        let label = age_label(Some("Echo Cliffs"), 1100.0, echo.survival_probability, true);
        assert!(label[1].starts_with("median 1100 yr: E[P_s] = "));
        assert!(at(&label[1]).1 > at(&label[0]).1);
    }

    #[test]
    fn labels_of_close_ages_never_overlap() {
        let doc = close_ages();
        let svg = super::svg(&doc).expect("svg");
        assert_labels_apart(&doc, &svg);
        let age = &doc.rocks[0].ages[3];
        let label = age_label(None, 1100.0, age.survival_probability, false);
        assert_eq!(label.len(), 1, "one rock: no name");
        assert!(svg.contains(&label[0]), "no {label:?}");
    }

    #[test]
    fn labels_on_one_spot_are_stacked_and_led() {
        let sizes = [(80, 21); 4];
        let places = place_labels(&[(200, 200); 4], &sizes, (0, 0, 600, 400), &[]);
        let boxes: Vec<Box4> = places.iter().flatten().map(|p| p.area).collect();
        assert_eq!(boxes.len(), 4);
        for (i, a) in boxes.iter().enumerate() {
            for b in &boxes[i + 1..] {
                assert!(!overlap(*a, *b), "{a:?} {b:?}");
            }
        }
        // The four places beside the mark first, then stacked.
        let led: Vec<bool> = places.iter().flatten().map(|p| p.led).collect();
        assert_eq!(led, [false, false, false, false]);
        let more = place_labels(&[(200, 200); 6], &[(80, 21); 6], (0, 0, 600, 400), &[]);
        assert!(more[4].as_ref().is_some_and(|p| p.led), "{more:?}");
        // No room at all: left out.
        let none = place_labels(&[(5, 5)], &[(80, 21)], (0, 0, 40, 40), &[]);
        assert_eq!(none, vec![None]);
        // A point to keep clear of above right of the mark: the label goes
        // below left, where it is clear; with no clear place, the first.
        let clear = [(230, 185)];
        let off = place_labels(&[(200, 200)], &[(80, 21)], (0, 0, 600, 400), &clear);
        assert_eq!(off[0].as_ref().map(|p| p.area), Some((114, 206, 194, 227)));
        let crowded: Vec<(i32, i32)> = (0..600)
            .step_by(5)
            .flat_map(|x| (0..400).step_by(5).map(move |y| (x, y)))
            .collect();
        let first = place_labels(&[(200, 200)], &[(80, 21)], (0, 0, 600, 400), &crowded);
        assert_eq!(
            first[0].as_ref().map(|p| p.area),
            Some((206, 173, 286, 194))
        );
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
