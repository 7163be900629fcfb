//! Rocking spectra of a record: in the (block size R, scale factor) plane,
//! each computed block size a bar of its own — the scales that overturn it
//! shaded by mode, the safe ones white, below the rocking threshold grey —
//! with a dot at its minimum overturning scale. Nothing is drawn between
//! the sizes: what lies between them was not computed. The right axis reads
//! the scaled record's PGA in g.

use plotters::prelude::*;

use crate::kinds::record_spectrum::{
    RecordSpectrumJob, RecordSpectrumResult, ScaleTransitionDoc, SizeDoc,
};
use crate::kinds::spectrum::figure::{
    CLASS_LIFT_OFF, CLASS_MIXED, CLASS_MODE1, CLASS_MODE2, CLASS_NO_ROCKING, CLASS_SAFE, Crossing,
    fill, kept, region_legend, regions_of,
};
use crate::plot::bands::{Band, MIN_VISIBLE, over, tile, widen};
use crate::plot::render;
use crate::plot::style::{
    Drawn, INK, LEGEND_WIDTH, Legend, Marker, Swatch, X_LABEL_AREA, Y_LABEL_AREA, axis_range,
    draw_legend, fmt_num, marker, mesh, scaled_pga_axis,
};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;
/// A bar's share of the distance to the nearest other size: the rest is a
/// gap, so that no bar reads as a range of sizes.
const BAR_SHARE: f64 = 0.6;
/// The widest bar, a fraction of the sizes' span (of the size itself when
/// there is one).
const BAR_MAX: f64 = 0.06;

/// The overturning regions (lo, hi, mode) of one block size, in scale
/// factors: every band of the result, narrow ones included (see
/// [`regions_of`]).
fn regions(line: &SizeDoc, s_max: f64) -> Vec<(f64, f64, u8)> {
    let crossings: Vec<Crossing> = line.transitions.iter().map(Crossing::from).collect();
    let changes: Vec<(f64, u8)> = line
        .mode_changes
        .iter()
        .map(|m| (m.scale, m.to_mode))
        .collect();
    regions_of(&crossings, &changes, s_max)
}

/// One computed block size as drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Bar {
    /// The size, m.
    pub r_m: f64,
    /// The bar's left and right ends, m (around `r_m`, clear of the others).
    pub x: (f64, f64),
    /// Its bands of scale factor from 0 to the highest, by class; overturning
    /// bands narrower than [`MIN_VISIBLE`] of the axis widened to it.
    pub bands: Vec<Band>,
}

/// What the figure of a record spectrum draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// The block size axis, m.
    pub x_range: (f64, f64),
    /// The highest scale factor (the axis runs from 0).
    pub s_max: f64,
    /// One bar per computed size, in increasing R.
    pub bars: Vec<Bar>,
    /// The minimum overturning scale of each size that has one within the
    /// axis, where it lies in a certain band: (R, scale), a dot.
    pub minimum: Vec<(f64, f64)>,
    /// The same where it lies in a mixed zone: a ring.
    pub minimum_mixed: Vec<(f64, f64)>,
    /// The lowest certain overturning scale (over a band at least the
    /// principal relative width wide) of each size: a triangle.
    pub certain: Vec<(f64, f64)>,
    /// How many certain bands and mixed zones, and their widths.
    pub counts: Counts,
}

/// How much of a figure is certain and how much mixed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counts {
    /// Certain overturning bands.
    pub bands: usize,
    /// Their total width.
    pub bands_width: f64,
    /// Mixed zones.
    pub zones: usize,
    /// Their total width.
    pub zones_width: f64,
}

impl Counts {
    /// Of lines given as (transitions, zones), on an axis ending at `top`.
    fn of<'a>(
        lines: impl Iterator<
            Item = (
                &'a Vec<crate::kinds::record_spectrum::ScaleTransitionDoc>,
                &'a Vec<crate::jobs::mixed::MixedDoc>,
            ),
        >,
        top: f64,
    ) -> Counts {
        let mut c = Counts::default();
        for (transitions, zones) in lines {
            let crossings: Vec<Crossing> = transitions.iter().map(Crossing::from).collect();
            let bands: Vec<[f64; 2]> = regions_of(&crossings, &[], top)
                .into_iter()
                .map(|(lo, hi, _)| [lo, hi])
                .collect();
            let z: Vec<[f64; 2]> = zones.iter().map(|z| [z.from, z.to]).collect();
            for b in over(
                &bands
                    .iter()
                    .map(|&[lo, hi]| Band { lo, hi, class: 1 })
                    .collect::<Vec<_>>(),
                &z,
                CLASS_MIXED,
            ) {
                if b.class == CLASS_MIXED {
                    c.zones += 1;
                    c.zones_width += b.hi - b.lo;
                } else {
                    c.bands += 1;
                    c.bands_width += b.hi - b.lo;
                }
            }
        }
        c
    }
}

/// The half-width of the bar of each of `xs` (ascending) and the axis
/// range: each bar [`BAR_SHARE`] of the distance to its nearest neighbour,
/// at most [`BAR_MAX`] of the span and half its size.
fn bar_layout(xs: &[f64]) -> (Vec<f64>, (f64, f64)) {
    let (first, last) = (xs[0], xs[xs.len() - 1]);
    let span = if last > first { last - first } else { first };
    let halves: Vec<f64> = (0..xs.len())
        .map(|k| {
            let nearest = [k.checked_sub(1), Some(k + 1)]
                .into_iter()
                .flatten()
                .filter_map(|j| xs.get(j))
                .map(|x| (x - xs[k]).abs())
                .filter(|d| *d > 0.0)
                .fold(f64::INFINITY, f64::min);
            (0.5 * BAR_SHARE * nearest)
                .min(0.5 * BAR_MAX * span)
                .min(0.5 * xs[k])
        })
        .collect();
    let range = if last > first {
        let pad = 0.02 * span;
        (
            (first - halves[0] - pad).max(0.0),
            last + halves[xs.len() - 1] + pad,
        )
    } else {
        (0.5 * first, 1.5 * first)
    };
    (halves, range)
}

/// The bars and markers of a `record_spectrum` result: what [`svg`] draws.
pub fn drawing(result: &RecordSpectrumResult) -> Result<Drawing, String> {
    let s_max = result.spec.scale.to;
    let mut sized: Vec<&SizeDoc> = result
        .spectrum
        .iter()
        .filter(|l| l.r_m.is_finite() && l.r_m > 0.0)
        .collect();
    if sized.is_empty() {
        return Err("the spectrum has no block sizes".into());
    }
    sized.sort_by(|a, b| a.r_m.total_cmp(&b.r_m));
    let xs: Vec<f64> = sized.iter().map(|l| l.r_m).collect();
    let (halves, x_range) = bar_layout(&xs);
    let bars = sized
        .iter()
        .zip(halves)
        .map(|(l, half)| {
            let mut bands = vec![Band {
                lo: 0.0,
                hi: l.threshold_scale.min(s_max),
                class: CLASS_NO_ROCKING,
            }];
            // Under a vertical motion nothing is claimed from the scale
            // where the block would leave the ground.
            let top = result.lift_off_above_scale.map_or(s_max, |v| v.min(s_max));
            bands.extend(regions(l, top).into_iter().map(|(lo, hi, mode)| Band {
                lo,
                hi,
                class: if mode == 2 { CLASS_MODE2 } else { CLASS_MODE1 },
            }));
            if top < s_max {
                bands.push(Band {
                    lo: top,
                    hi: s_max,
                    class: CLASS_LIFT_OFF,
                });
            }
            let zones: Vec<[f64; 2]> = l.mixed.iter().map(|z| [z.from, z.to]).collect();
            let bands = tile(0.0, s_max, &over(&bands, &zones, CLASS_MIXED), CLASS_SAFE);
            Bar {
                r_m: l.r_m,
                x: (l.r_m - half, l.r_m + half),
                bands: widen(&bands, MIN_VISIBLE * s_max, kept),
            }
        })
        .collect();
    let at = |mixed: bool| -> Vec<(f64, f64)> {
        sized
            .iter()
            .filter(|l| (l.min_overturn_in.as_deref() == Some("mixed")) == mixed)
            .filter_map(|l| Some((l.r_m, l.min_overturn_scale?)))
            .filter(|m| m.1 <= s_max)
            .collect()
    };
    let certain = sized
        .iter()
        .filter_map(|l| Some((l.r_m, l.min_certain_overturn_scale?)))
        .filter(|m| m.1 <= s_max)
        .collect();
    Ok(Drawing {
        x_range,
        s_max,
        bars,
        minimum: at(false),
        minimum_mixed: at(true),
        certain,
        counts: Counts::of(sized.iter().map(|l| (&l.transitions, &l.mixed)), s_max),
    })
}

/// "α = 0.25 rad, η = 0.9": the block of every size.
fn block_text(alpha: f64, eta: f64) -> String {
    format!(
        "α\u{a0}=\u{a0}{}\u{a0}rad, η\u{a0}=\u{a0}{}",
        fmt_num(alpha, 3),
        fmt_num(eta, 3)
    )
}

/// The legend of a record spectrum's figure: the regions and markers it
/// draws, then notes on the blocks, the record and how to read the bars.
fn legend(result: &RecordSpectrumResult, drawn: &Drawing) -> Legend {
    let spec = &result.spec;
    let used = |class: usize| {
        drawn
            .bars
            .iter()
            .any(|b| b.bands.iter().any(|band| band.class == class))
    };

    let mut legend = region_legend(
        used,
        "no rocking (PGA below the threshold)",
        result.spec.contact.is_some(),
    );
    if !drawn.minimum.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Dot, INK),
            "lowest overturning, in a certain band",
        );
    }
    if !drawn.minimum_mixed.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Ring, INK),
            "lowest overturning found, in a mixed zone",
        );
    }
    if !drawn.certain.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Triangle, INK),
            format!(
                "lowest certain overturning (a band ≥ {} % wide)",
                fmt_num(spec.principal_relative_width * 100.0, 3)
            ),
        );
    }
    let c = drawn.counts;
    legend.note(format!(
        "{} certain band{} (width {} in all), {} mixed zone{} (width {})",
        c.bands,
        if c.bands == 1 { "" } else { "s" },
        fmt_num(c.bands_width, 4),
        c.zones,
        if c.zones == 1 { "" } else { "s" },
        fmt_num(c.zones_width, 4),
    ));
    legend.note(block_text(spec.block.alpha, spec.block.eta));
    if let Some(v) = vertical_text(spec) {
        legend.note(format!(
            "vertical ground motion {v} (positive up){}",
            result
                .lift_off_above_scale
                .map_or(String::new(), |s| format!(
                    "; the block leaves the ground from scale {}",
                    fmt_num(s, 4)
                ))
        ));
    }
    let r = &result.record;
    legend.note(format!(
        "record: {} samples, dt = {} s; PGA {} g, PGV {} m/s, PGD {} m (unscaled)",
        r.samples,
        fmt_num(r.dt_s, 4),
        fmt_num(r.peaks.pga_g, 4),
        fmt_num(r.peaks.pgv_m_s, 4),
        fmt_num(r.peaks.pgd_m, 4),
    ));
    let formulation = spec.formulation.name();
    let n = drawn.bars.len();
    legend.note(format!(
        "{formulation} formulation, {n} block size{}; R = 3g/(4p²)",
        if n == 1 { "" } else { "s" }
    ));
    legend.note(
        "each bar is one computed size, R at its middle; its width is not a range of sizes, and nothing is drawn between sizes",
    );
    legend.note(format!(
        "shading: every overturning band of the result, those narrower than {} % of the axis drawn that tall",
        fmt_num(MIN_VISIBLE * 100.0, 2)
    ));
    legend.note("right axis: the scaled record's PGA = scale × PGA");

    legend
}

/// The figure of a `record_spectrum` result.
pub fn svg(result: &RecordSpectrumResult) -> Result<String, String> {
    let drawn = drawing(result)?;
    let spec = &result.spec;
    let s_max = drawn.s_max;
    let pga_g = result.record.peaks.pga_g;
    let legend = legend(result, &drawn);
    let formulation = spec.formulation.name();
    let (x0, x1) = drawn.x_range;
    let title = match spec
        .scaled_vertical()
        .map(|v| crate::plot::scaled_vertical_title(&v))
    {
        None => format!("Rocking spectrum of a record: {formulation} formulation"),
        Some(v) => format!("Rocking spectrum of a record: {formulation} formulation, {v}"),
    };
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        let mut builder = ChartBuilder::on(&chart_area);
        builder
            .margin(10)
            .margin_right(14)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .right_y_label_area_size(Y_LABEL_AREA);
        let chart =
            builder.build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", 0.0, s_max)?)?;
        let mut chart = chart.set_secondary_coord(x0..x1, axis_range("right", 0.0, s_max * pga_g)?);
        for bar in &drawn.bars {
            chart.draw_series(bar.bands.iter().filter(|b| b.class != CLASS_SAFE).map(|b| {
                Rectangle::new([(bar.x.0, b.lo), (bar.x.1, b.hi)], fill(b.class).filled())
            }))?;
        }
        mesh(&mut chart, "block size R (m)", "scale factor").draw()?;
        scaled_pga_axis(&mut chart)?;
        chart.draw_series(
            drawn
                .minimum
                .iter()
                .map(|&q| marker(q, Marker::Dot, 7, INK)),
        )?;
        chart.draw_series(
            drawn
                .minimum_mixed
                .iter()
                .map(|&q| marker(q, Marker::Ring, 9, INK)),
        )?;
        chart.draw_series(
            drawn
                .certain
                .iter()
                .map(|&q| marker(q, Marker::Triangle, 9, INK)),
        )?;
        draw_legend(&side, &legend)
    })
}

/// The vertical motion of a record spectrum, as its figure names it.
fn vertical_text(spec: &RecordSpectrumJob) -> Option<String> {
    spec.scaled_vertical()
        .map(|v| crate::plot::scaled_vertical_text(&v, spec.block.g))
}

impl From<&ScaleTransitionDoc> for Crossing {
    fn from(t: &ScaleTransitionDoc) -> Self {
        Crossing {
            at: t.scale,
            up: t.direction == "up",
            mode: t.mode,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{BAR_MAX, Drawing, drawing};
    use crate::kinds::JobResult;
    use crate::kinds::record_spectrum::{
        RecordSpectrumResult, ScaleModeChangeDoc, ScalePrincipalDoc, ScaleTransitionDoc, SizeDoc,
    };
    use crate::kinds::spectrum::figure::overturns;
    use crate::kinds::spectrum::figure::{CLASS_MODE1, CLASS_MODE2, CLASS_SAFE, fill};
    use crate::plot::bands::MIN_VISIBLE;
    use crate::plot::style::fmt_num;
    use crate::plot::tests::{hex, typed};

    fn transition(scale: f64, up: bool, mode: u8) -> ScaleTransitionDoc {
        ScaleTransitionDoc {
            scale,
            pga_g: 0.5 * scale,
            direction: if up { "up" } else { "down" }.into(),
            mode,
            impacts: u64::from(mode == 1),
            bracket: [scale - 1e-4, scale + 1e-4],
        }
    }

    /// A block size overturning in mode 2 from scale 1, in mode 1 from 1.2,
    /// with a narrow safe band 1.5–1.52 that the principal view drops.
    fn size() -> SizeDoc {
        SizeDoc {
            p: 2.0,
            r_m: 1.84,
            threshold_scale: 0.4,
            transitions: vec![
                transition(1.0, true, 2),
                transition(1.5, false, 1),
                transition(1.52, true, 1),
            ],
            mode_changes: vec![ScaleModeChangeDoc {
                scale: 1.2,
                from_mode: 2,
                to_mode: 1,
                bracket: [1.1999, 1.2001],
            }],
            min_overturn_scale: Some(1.0),
            min_overturn_pga_g: Some(0.5),
            min_overturn_mode: Some(2),
            safe_intervals: vec![[1.5, 1.52]],
            overturns_above_scale: Some(1.52),
            lift_off_above_scale: None,
            mixed: Vec::new(),
            min_overturn_in: Some("band".into()),
            min_overturn_zone: None,
            min_certain_overturn_scale: Some(1.0),
            min_certain_overturn_pga_g: Some(0.5),
            principal: ScalePrincipalDoc {
                transitions: vec![transition(1.0, true, 2)],
                min_overturn_scale: Some(1.0),
                min_overturn_mode: Some(2),
                safe_intervals: Vec::new(),
                overturns_above_scale: Some(1.0),
            },
        }
    }

    #[test]
    fn regions_are_every_band_with_its_mode() {
        // The narrow safe band 1.5–1.52 the principal view drops is kept.
        assert_eq!(
            super::regions(&size(), 3.0),
            vec![(1.0, 1.2, 2), (1.2, 1.5, 1), (1.52, 3.0, 1)]
        );
    }

    fn computed() -> RecordSpectrumResult {
        match typed(include_str!("../../../specs/record_spectrum_one_sine.json")) {
            JobResult::RecordSpectrum(r) => *r,
            other => panic!("not a record spectrum: {:?}", other.job_kind()),
        }
    }

    #[test]
    fn the_computed_spectrum_and_its_record() {
        let doc = computed();
        assert_eq!(doc.spectrum.len(), 4);
        let svg = super::svg(&doc).expect("svg");
        let r = &doc.record;
        for needle in [
            "Rocking spectrum of a record: nonlinear formulation".to_string(),
            "block size R (m)".to_string(),
            "scaled PGA (g)".to_string(),
            format!(
                "α\u{a0}=\u{a0}{}\u{a0}rad",
                fmt_num(doc.spec.block.alpha, 3)
            ),
            format!(
                "record: {} samples, dt = {} s;",
                r.samples,
                fmt_num(r.dt_s, 4)
            ),
            "4 block".to_string(),
        ] {
            assert!(svg.contains(&needle), "missing {needle:?}");
        }
        // A block size without p: the note names α and η only.
        assert!(!svg.contains("rad/s"), "no p in the block note");
    }

    #[test]
    fn a_size_shades_its_modes() {
        let mut doc = computed();
        doc.spec.scale.to = 3.0;
        let mut other = size();
        other.r_m = 2.0;
        doc.spectrum = vec![size(), other];
        let svg = super::svg(&doc).expect("svg");
        for class in [CLASS_MODE1, CLASS_MODE2] {
            assert!(svg.contains(&hex(fill(class))), "class {class}");
        }
        assert!(svg.contains("overturns, mode 2"));
    }

    /// Each bar holds its own computed size and no other, bars do not touch
    /// and none is wider than [`BAR_MAX`] of the axis; the figure draws one
    /// rectangle per shaded cell (and a swatch per shaded class).
    fn assert_one_size_per_bar(doc: &RecordSpectrumResult) -> Drawing {
        let d = drawing(doc).expect("drawing");
        let sizes: Vec<f64> = doc.spectrum.iter().map(|l| l.r_m).collect();
        assert_eq!(d.bars.len(), sizes.len());
        let span = d.x_range.1 - d.x_range.0;
        for bar in &d.bars {
            let inside: Vec<f64> = sizes
                .iter()
                .copied()
                .filter(|r| bar.x.0 <= *r && *r <= bar.x.1)
                .collect();
            assert_eq!(inside, vec![bar.r_m], "{bar:?}");
            assert!(bar.x.1 - bar.x.0 <= BAR_MAX * span + 1e-12, "{bar:?}");
            assert!(bar.x.0 >= d.x_range.0 && bar.x.1 <= d.x_range.1);
        }
        for w in d.bars.windows(2) {
            assert!(
                w[0].x.1 < w[1].x.0,
                "a gap between {:?} and {:?}",
                w[0],
                w[1]
            );
        }
        let svg = super::svg(doc).expect("svg");
        let shaded: Vec<usize> = d
            .bars
            .iter()
            .flat_map(|b| b.bands.iter().map(|band| band.class))
            .filter(|c| *c != CLASS_SAFE)
            .collect();
        let mut classes = shaded.clone();
        classes.sort_unstable();
        classes.dedup();
        let rects: usize = classes
            .iter()
            .map(|c| {
                let needle = format!("fill=\"{}\"", hex(fill(*c)));
                svg.split("<rect ")
                    .skip(1)
                    .filter(|tag| tag.split('>').next().is_some_and(|t| t.contains(&needle)))
                    .count()
            })
            .sum();
        assert_eq!(rects, shaded.len() + classes.len(), "cells and swatches");
        d
    }

    #[test]
    fn each_computed_size_is_a_bar_of_its_own() {
        let doc = computed();
        let d = assert_one_size_per_bar(&doc);
        assert_eq!(d.bars.len(), 4);
        // One size: one narrow bar, not a band over a range of sizes.
        let mut one = computed();
        one.spectrum.truncate(1);
        let d = assert_one_size_per_bar(&one);
        let bar = &d.bars[0];
        assert!(bar.x.1 - bar.x.0 <= BAR_MAX * bar.r_m + 1e-12, "{bar:?}");
        // Ten sizes 0.25 m apart.
        let mut ten = computed();
        let base = ten.spectrum[0].clone();
        ten.spectrum = (0..10)
            .map(|k| {
                let mut l = base.clone();
                l.r_m = 0.25 + 0.25 * f64::from(k);
                l
            })
            .collect();
        let d = assert_one_size_per_bar(&ten);
        // Each bar a share of the spacing: the rest is white.
        for bar in &d.bars {
            assert!(bar.x.1 - bar.x.0 <= 0.6 * 0.25 + 1e-12, "{bar:?}");
        }
    }

    /// Every dot is in a drawn overturning cell of its size's bar, at least
    /// [`MIN_VISIBLE`] of the axis tall.
    fn assert_minima_in_overturning_cells(d: &Drawing) {
        assert!(!d.minimum.is_empty(), "dots to check");
        for &(r, s) in &d.minimum {
            let cell = d
                .bars
                .iter()
                .filter(|b| b.x.0 <= r && r <= b.x.1)
                .flat_map(|b| &b.bands)
                .find(|band| overturns(band.class) && band.lo <= s && s <= band.hi);
            assert!(
                cell.is_some_and(|c| c.hi - c.lo >= MIN_VISIBLE * d.s_max - 1e-12),
                "the dot at R = {r} m, scale {s} in {:?}",
                d.bars
            );
        }
    }

    #[test]
    fn every_minimum_lies_in_an_overturning_cell() {
        let doc = computed();
        let d = drawing(&doc).expect("drawing");
        assert_minima_in_overturning_cells(&d);
        // A size whose lowest overturning band is far narrower than a pixel.
        let mut narrow = computed();
        narrow.spec.scale.to = 3.0;
        let mut line = size();
        line.transitions = vec![
            transition(1.0, true, 2),
            transition(1.0004, false, 2),
            transition(2.0, true, 1),
        ];
        line.mode_changes.clear();
        line.safe_intervals = vec![[1.0004, 2.0]];
        line.principal.transitions = vec![transition(2.0, true, 1)];
        line.principal.min_overturn_scale = Some(2.0);
        narrow.spectrum = vec![line];
        let d = drawing(&narrow).expect("drawing");
        assert_eq!(d.minimum, vec![(1.84, 1.0)]);
        assert_minima_in_overturning_cells(&d);
    }

    #[test]
    fn the_right_axis_reads_the_scaled_pga() {
        let doc = computed();
        let svg = super::svg(&doc).expect("svg");
        crate::kinds::spectrum::figure::tests::assert_right_axis_is_left_times(
            &svg,
            doc.record.peaks.pga_g,
        );
    }
}
