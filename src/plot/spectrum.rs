//! Overturning spectra (paper Figs. 6, 10, 11): in the (ω_p/p, a_p/(αg))
//! plane, the amplitudes that overturn the block shaded by mode, the safe
//! ones white, the minimum overturning acceleration and the closed forms
//! (eq. 21; the corrected eq. 47 for linear one-sine) as reference curves.

use plotters::prelude::*;

use super::bands::{Band, Column, simplify, tile, tiling};
use super::style::{
    AXIS, Drawn, INK, LEGEND, LEGEND_WIDTH, Legend, MODE1, MODE2, MUTED, Marker, NO_ROCKING,
    REFERENCE, Swatch, TICKS, X_LABEL_AREA, Y_LABEL_AREA, axis_range, clip_y, draw_legend, fmt_num,
    marker, mesh, text, tick, tint,
};
use super::{block_text, render, shape_title};
use crate::dynamics::PulseShape;
use crate::jobs::record_spectrum::ScaleTransitionDoc;
use crate::jobs::spectrum::{FrequencyDoc, SpectrumResult, TransitionDoc};

const WIDTH: u32 = 1120;
const HEIGHT: u32 = 680;

/// Eq. 21 (Makris & Roussos) holds for 0 ≤ ω_p/p ≤ 3, where the minimum
/// overturning acceleration is nearly linear; beyond, the spectrum becomes
/// increasingly nonlinear (paper, after eq. 21).
pub const EQ21_HOLDS_TO: f64 = 3.0;

/// Eq. 21's straight line a_p0/(αg) = 1 + β ω_p/p over the part of the
/// drawn range `[x0, x1]` where it holds (ω_p/p ≤ 3); β from the lines'
/// own eq. 21 values. Empty when the range lies beyond 3 or the lines carry
/// no eq. 21 value.
pub fn eq21_line(lines: &[FrequencyDoc], x0: f64, x1: f64) -> Vec<(f64, f64)> {
    let beta = lines.iter().find_map(|l| {
        let r = Some(l.omega_ratio).filter(|r| *r > 0.0)?;
        Some((l.eq21_alpha_g? - 1.0) / r)
    });
    let (from, to) = (x0.max(0.0), x1.min(EQ21_HOLDS_TO));
    match beta {
        Some(b) if b.is_finite() && from < to => {
            vec![(from, 1.0 + b * from), (to, 1.0 + b * to)]
        }
        _ => Vec::new(),
    }
}

/// Region classes.
pub const CLASS_NO_ROCKING: usize = 0;
/// Overturning after impact.
pub const CLASS_MODE1: usize = 1;
/// Overturning without impact.
pub const CLASS_MODE2: usize = 2;
/// Rocks and survives (left white).
pub const CLASS_SAFE: usize = 3;

/// Fill of a region class.
pub fn fill(class: usize) -> RGBColor {
    match class {
        CLASS_MODE1 => tint(MODE1, 0.68),
        CLASS_MODE2 => tint(MODE2, 0.55),
        _ => NO_ROCKING,
    }
}

/// A legend opening with the region classes a figure shades (`used`), the
/// white safe region always, the no-rocking band under `no_rocking`.
pub fn region_legend(used: impl Fn(usize) -> bool, no_rocking: &str) -> Legend {
    let mut legend = Legend::default();
    if used(CLASS_MODE1) {
        legend.entry(
            Swatch::Fill(fill(CLASS_MODE1)),
            "overturns, mode 1 (after one or more impacts)",
        );
    }
    if used(CLASS_MODE2) {
        legend.entry(
            Swatch::Fill(fill(CLASS_MODE2)),
            "overturns, mode 2 (without impact)",
        );
    }
    legend.entry(
        Swatch::Boxed(WHITE, MUTED),
        "safe: rocks, does not overturn",
    );
    if used(CLASS_NO_ROCKING) {
        legend.entry(Swatch::Fill(fill(CLASS_NO_ROCKING)), no_rocking);
    }
    legend
}

/// A transition as the regions read it: where it lies on the amplitude
/// axis, whether overturning begins there as the amplitude grows ("up") or
/// a safe interval does, and the mode on the overturning side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Amplitude (αg in a pulse spectrum, a scale factor in a record's).
    pub at: f64,
    /// Overturning begins here.
    pub up: bool,
    /// Mode on the overturning side.
    pub mode: u8,
}

impl From<&TransitionDoc> for Crossing {
    fn from(t: &TransitionDoc) -> Self {
        Crossing {
            at: t.a_alpha_g,
            up: t.direction == "up",
            mode: t.mode,
        }
    }
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

/// Overturning intervals (lo, hi, mode) of a list of transitions: each "up"
/// opens one (of the mode above it), the next "down" closes it; an open one
/// ends at `a_max`.
pub fn intervals(transitions: &[Crossing], a_max: f64) -> Vec<(f64, f64, u8)> {
    let mut out = Vec::new();
    let mut open: Option<(f64, u8)> = None;
    for t in transitions {
        if t.up {
            open = Some((t.at, t.mode));
        } else if let Some((lo, m)) = open.take() {
            out.push((lo, t.at, m));
        }
    }
    if let Some((lo, m)) = open {
        out.push((lo, a_max.max(lo), m));
    }
    out
}

/// `regions` cut where the mode changes (`changes`: amplitude, new mode).
fn split_at_changes(regions: &[(f64, f64, u8)], changes: &[(f64, u8)]) -> Vec<(f64, f64, u8)> {
    let mut out = Vec::new();
    for &(lo, hi, mut mode) in regions {
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

/// The overturning regions of one line with their modes, from its
/// `transitions`, its mode `changes` (amplitude, new mode) and the
/// transitions of its `principal` view. The extents are those of the
/// principal view when there is one (bands narrower than its relative width
/// dropped); the modes come from the full view, a dropped safe gap taking
/// the mode below it.
pub fn regions_of(
    transitions: &[Crossing],
    changes: &[(f64, u8)],
    principal: Option<&[Crossing]>,
    a_max: f64,
) -> Vec<(f64, f64, u8)> {
    let fine = split_at_changes(&intervals(transitions, a_max), changes);
    let Some(principal) = principal else {
        return fine;
    };
    let mut out = Vec::new();
    for (lo, hi, mode) in intervals(principal, a_max) {
        let mut inside: Vec<(f64, f64, u8)> = fine
            .iter()
            .filter(|f| f.1 > lo && f.0 < hi)
            .map(|&(a, b, m)| (a.max(lo), b.min(hi), m))
            .collect();
        if inside.is_empty() {
            out.push((lo, hi, mode));
            continue;
        }
        inside[0].0 = lo;
        for k in 1..inside.len() {
            inside[k - 1].1 = inside[k].0;
        }
        if let Some(last) = inside.last_mut() {
            last.1 = hi;
        }
        for piece in inside {
            match out.last_mut() {
                Some(prev) if prev.2 == piece.2 && prev.1 >= piece.0 => prev.1 = piece.1,
                _ => out.push(piece),
            }
        }
    }
    out
}

/// The overturning regions of one frequency of a pulse spectrum with their
/// modes (see [`regions_of`]).
pub fn frequency_regions(line: &FrequencyDoc, a_max: f64) -> Vec<(f64, f64, u8)> {
    let crossings = |list: &[TransitionDoc]| list.iter().map(Crossing::from).collect::<Vec<_>>();
    let changes: Vec<(f64, u8)> = line
        .mode_changes
        .iter()
        .map(|m| (m.a_alpha_g, m.to_mode))
        .collect();
    regions_of(
        &crossings(&line.transitions),
        &changes,
        Some(&crossings(&line.principal.transitions)),
        a_max,
    )
}

/// The figure of a `spectrum` result.
pub fn svg(result: &SpectrumResult) -> Result<String, String> {
    let lines = &result.spectrum;
    if lines.is_empty() {
        return Err("the spectrum has no frequencies".into());
    }
    let spec = &result.spec;
    let a_max = spec.a_max_alpha_g.max(1.5);
    let (alpha, p) = (spec.block.alpha, spec.block.p);
    let ratios: Vec<f64> = lines.iter().map(|l| l.omega_ratio).collect();
    let rmin = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    let rmax = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let half = if rmax > rmin {
        0.5 * (rmax - rmin) / (ratios.len() as f64 - 1.0).max(1.0)
    } else {
        0.25 * rmin.max(0.1)
    };
    let (x0, x1) = if rmax > rmin {
        (rmin, rmax)
    } else {
        (rmin - 2.0 * half, rmax + 2.0 * half)
    };
    let columns: Vec<Column> = lines
        .iter()
        .map(|l| {
            let mut bands = vec![Band {
                lo: 0.0,
                hi: l.threshold_alpha_g,
                class: CLASS_NO_ROCKING,
            }];
            for (lo, hi, mode) in frequency_regions(l, a_max) {
                bands.push(Band {
                    lo,
                    hi,
                    class: if mode == 2 { CLASS_MODE2 } else { CLASS_MODE1 },
                });
            }
            let mut bands = tile(0.0, a_max, &bands, CLASS_SAFE);
            simplify(&mut bands, a_max / 1000.0, |_| false);
            Column {
                x: l.omega_ratio,
                bands,
            }
        })
        .collect();
    let shaded: Vec<_> = tiling(&columns, half)
        .pieces
        .into_iter()
        .filter(|p| p.class != CLASS_SAFE)
        .collect();
    let used = |class: usize| shaded.iter().any(|p| p.class == class);
    // The minimum overturning acceleration, broken where its mode changes
    // (the paper's finite jump).
    let mut minimum: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut last_mode = None;
    for l in lines {
        let Some(a) = l.min_overturn_alpha_g else {
            last_mode = None;
            continue;
        };
        let (r, mode) = (l.omega_ratio, l.min_overturn_mode);
        if last_mode.is_none() || last_mode != Some(mode) {
            minimum.push(Vec::new());
        }
        last_mode = Some(mode);
        if let Some(part) = minimum.last_mut() {
            part.push((r, a));
        }
    }
    // The closed-form mode-2 boundary; known at one frequency only, it is
    // drawn across that frequency's bar.
    let mode2_closed = {
        let points: Vec<(f64, f64)> = lines
            .iter()
            .filter_map(|l| Some((l.omega_ratio, l.closed_form_mode2_alpha_g?)))
            .collect();
        match points.as_slice() {
            [(x, y)] => vec![(x - half, *y), (x + half, *y)],
            _ => points,
        }
    };
    let eq21 = eq21_line(lines, x0, x1);
    let beta = match spec.pulse.shape() {
        PulseShape::OneCosine => "1/4",
        _ => "1/6",
    };

    let mut legend = region_legend(used, "no rocking (below the threshold)");
    if !minimum.is_empty() {
        legend.entry(
            Swatch::LineMark(INK, Marker::Dot),
            "minimum overturning acceleration (computed)",
        );
    }
    if !eq21.is_empty() {
        legend.entry(
            Swatch::Dashed(REFERENCE, 3),
            format!(
                "eq. 21: a_p0/(αg) ≈ 1 + β ω_p/p, β = {beta}, drawn where it holds: ω_p/p ≤ {}",
                fmt_num(EQ21_HOLDS_TO, 2)
            ),
        );
    } else if x0 > EQ21_HOLDS_TO {
        legend.note(format!(
            "eq. 21 not drawn: it holds for ω_p/p ≤ {}, this spectrum starts at {}",
            fmt_num(EQ21_HOLDS_TO, 2),
            fmt_num(x0, 3)
        ));
    }
    if !mode2_closed.is_empty() {
        legend.entry(
            Swatch::Dashed(RGBColor(0, 130, 60), 2),
            "mode-2 boundary, corrected eq. 47 (linear closed form)",
        );
    }
    legend.note(block_text(&spec.block));
    legend.note(format!(
        "{} pulse, {} formulation, {} frequenc{}",
        shape_title(spec.pulse.shape()),
        spec.formulation.name(),
        lines.len(),
        if lines.len() == 1 { "y" } else { "ies" }
    ));
    // Every line has its principal view: the shading follows it.
    legend.note(format!(
        "shading: principal view (bands narrower than {} % of their amplitude omitted; the result lists every transition)",
        fmt_num(spec.principal_relative_width * 100.0, 3)
    ));
    legend.note("top axis: f_p = (ω_p/p)·p/2π; right axis: a_p/g = α·a_p/(αg)");

    let title = format!(
        "Overturning spectrum: {} pulse, {} formulation",
        shape_title(spec.pulse.shape()),
        spec.formulation.name()
    );
    render((WIDTH, HEIGHT), &title, |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        let mut builder = ChartBuilder::on(&chart_area);
        builder
            .margin(10)
            .margin_right(14)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .top_x_label_area_size(X_LABEL_AREA)
            .right_y_label_area_size(Y_LABEL_AREA);
        let chart =
            builder.build_cartesian_2d(axis_range("x", x0, x1)?, axis_range("y", 0.0, a_max)?)?;
        let hz = |r: f64| r * p / std::f64::consts::TAU;
        let mut chart = chart.set_secondary_coord(
            axis_range("top", hz(x0), hz(x1))?,
            axis_range("right", 0.0, a_max * alpha)?,
        );
        for piece in &shaded {
            chart.draw_series(std::iter::once(Polygon::new(
                piece.polygon.clone(),
                fill(piece.class).filled(),
            )))?;
        }
        mesh(&mut chart, "ω_p / p", "a_p / (α g)").draw()?;
        chart
            .configure_secondary_axes()
            .x_desc("pulse frequency f_p (Hz)")
            .y_desc("a_p / g")
            .label_style(text(TICKS, INK))
            .axis_desc_style(text(AXIS, INK))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .draw()?;
        for part in clip_y(&mode2_closed, 0.0, a_max) {
            chart.draw_series(DashedLineSeries::new(
                part,
                3,
                3,
                RGBColor(0, 130, 60).stroke_width(2),
            ))?;
        }
        for part in &minimum {
            for piece in clip_y(part, 0.0, a_max) {
                chart.draw_series(LineSeries::new(piece, INK.stroke_width(2)))?;
            }
            chart.draw_series(
                part.iter()
                    .filter(|q| q.1 <= a_max)
                    .map(|&q| marker(q, Marker::Dot, 5, INK)),
            )?;
        }
        // Over the computed minimum, dashed so that both show where they agree;
        // its end (ω_p/p = 3) ticked and labelled.
        for part in clip_y(&eq21, 0.0, a_max) {
            chart.draw_series(DashedLineSeries::new(part, 9, 5, REFERENCE.stroke_width(3)))?;
        }
        if let Some(&end) = eq21.last().filter(|e| e.1 < a_max) {
            chart.draw_series(std::iter::once(marker(end, Marker::Tick, 12, REFERENCE)))?;
            chart.draw_series(std::iter::once(
                EmptyElement::at(end)
                    + Text::new(
                        format!("eq. 21 ends: ω_p/p = {}", fmt_num(end.0, 3)),
                        (8, 10),
                        text(LEGEND, REFERENCE),
                    ),
            ))?;
        }
        draw_legend(&side, &legend)
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::{Crossing, regions_of};
    use crate::jobs::JobResult;
    use crate::jobs::spectrum::{FrequencyDoc, ModeChangeDoc, SpectrumResult, TransitionDoc};

    /// The spectrum of the spec `text`.
    fn computed(text: &str) -> SpectrumResult {
        match crate::plot::tests::typed(text) {
            JobResult::Spectrum(r) => *r,
            other => panic!("a spectrum, not {:?}", other.job_kind()),
        }
    }

    fn transition(a: f64, direction: &str, mode: u8) -> TransitionDoc {
        TransitionDoc {
            a_alpha_g: a,
            direction: direction.into(),
            mode,
            impacts: if mode == 1 { 1 } else { 0 },
            bracket: [a - 1e-4, a + 1e-4],
            a_g: a * 0.25,
        }
    }

    /// `base` at ω_p/p = `r`: mode 1 from `up1` to `down`, mode 2 from `up2`.
    fn line(base: &FrequencyDoc, r: f64, up1: f64, down: f64, up2: f64) -> FrequencyDoc {
        let transitions = vec![
            transition(up1, "up", 1),
            transition(down, "down", 1),
            transition(up2, "up", 2),
        ];
        let mut l = base.clone();
        l.omega_ratio = r;
        l.threshold_alpha_g = 1.02;
        l.transitions = transitions.clone();
        l.mode_changes = Vec::new();
        l.min_overturn_alpha_g = Some(up1);
        l.min_overturn_mode = Some(1);
        l.principal.transitions = transitions;
        l.eq21_alpha_g = Some(1.0 + r / 6.0);
        l.closed_form_mode2_alpha_g = None;
        l
    }

    /// A one-sine spectrum up to 8 αg whose three frequencies (ω_p/p = 2,
    /// 2.25, 2.5) each overturn in mode 1, then are safe, then overturn in
    /// mode 2.
    pub(crate) fn sample() -> SpectrumResult {
        let mut result = computed(
            r#"{"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_sine"}, "formulation": "nonlinear",
                "omega_ratio": [2.0], "a_max_alpha_g": 8, "scan_step_alpha_g": 0.1}"#,
        );
        let base = result.spectrum[0].clone();
        result.spectrum = vec![
            line(&base, 2.0, 1.25, 2.37, 2.41),
            line(&base, 2.25, 1.29, 2.66, 2.71),
            line(&base, 2.5, 1.33, 2.96, 3.03),
        ];
        result
    }

    #[test]
    fn regions_by_mode_and_references() {
        let svg = super::svg(&sample()).expect("svg");
        for needle in [
            "Overturning spectrum: one-sine pulse, nonlinear formulation",
            "ω_p / p",
            "a_p / (α g)",
            "pulse frequency f_p (Hz)",
            "overturns, mode 1",
            "overturns, mode 2",
            "eq. 21",
            "minimum overturning",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
        // Three bands per frequency joined across two gaps: no rocking, mode 1,
        // mode 2 — one polygon each per gap.
        let fills = [super::fill(1), super::fill(2)]
            .map(|c| format!("fill=\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2));
        for f in fills {
            assert_eq!(svg.matches(&f).count(), 2 + 1, "{f}");
        }
    }

    #[test]
    fn eq21_is_drawn_only_where_it_holds() {
        use crate::plot::style::REFERENCE;
        use crate::plot::tests::{hex, shapes, x_extent};
        let mut result = computed(include_str!(
            "../../specs/locomotive_spectrum_nonlinear.json"
        ));
        assert_eq!(result.spectrum.len(), 40);
        let eq21 = super::eq21_line(&result.spectrum, 0.25, 10.0);
        // From the first frequency to ω_p/p = 3, β = 1/6 (one-sine).
        assert_eq!(eq21.len(), 2);
        assert_eq!((eq21[0].0, eq21[1].0), (0.25, 3.0));
        assert!((eq21[1].1 - 1.5).abs() < 1e-12, "{eq21:?}");
        // The figure: every eq. 21 dash left of ω_p/p = 3 (the no-rocking
        // band spans 0.25–10), and its end labelled.
        let svg = super::svg(&result).expect("svg");
        let no_rocking = format!("fill=\"{}\"", hex(super::fill(super::CLASS_NO_ROCKING)));
        let (left, right) = x_extent(&shapes(&svg, "polygon", &no_rocking));
        let at_3 = left + (3.0 - 0.25) / (10.0 - 0.25) * (right - left);
        // (The legend's swatch, right of the chart, left out.)
        let dashes: Vec<Vec<(f64, f64)>> =
            shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(REFERENCE)))
                .into_iter()
                .filter(|d| d.iter().all(|p| p.0 <= right))
                .collect();
        let (dashes_start, dashes_end) = x_extent(&dashes);
        assert!(
            (dashes_start - left).abs() <= 3.0,
            "{dashes_start} vs {left}"
        );
        assert!(dashes_end <= at_3 + 1.0, "{dashes_end} > {at_3}");
        assert!(dashes_end >= at_3 - 8.0, "{dashes_end} < {at_3}");
        assert!(svg.contains("eq. 21 ends: ω_p/p = 3"));
        // A spectrum that starts beyond 3 draws none, and says why.
        result.spectrum.retain(|l| l.omega_ratio > 3.0);
        let svg = super::svg(&result).expect("svg");
        assert!(svg.contains("eq. 21 not drawn"), "no note");
        assert!(!svg.contains("eq. 21 ends"));
    }

    #[test]
    fn principal_extents_take_modes_from_the_full_view() {
        let t = |at: f64, up: bool, mode: u8| Crossing { at, up, mode };
        let fine = [t(1.1, true, 1), t(1.28, false, 1), t(1.281, true, 2)];
        let principal = [t(1.1, true, 1)];
        let expected = vec![(1.1, 1.281, 1), (1.281, 20.0, 2)];
        assert_eq!(regions_of(&fine, &[], Some(&principal), 20.0), expected);
        // Without a principal view, the full one.
        assert_eq!(
            regions_of(&fine, &[], None, 20.0),
            vec![(1.1, 1.28, 1), (1.281, 20.0, 2)]
        );
    }

    #[test]
    fn a_mode_change_splits_a_region() {
        let base = sample().spectrum[0].clone();
        let mut l = line(&base, 2.0, 1.25, 2.37, 2.41);
        // Overturning from 1.25 αg on, mode 1 turning to mode 2 at 3 αg.
        l.transitions.truncate(1);
        l.principal.transitions.truncate(1);
        l.mode_changes = vec![ModeChangeDoc {
            a_alpha_g: 3.0,
            from_mode: 1,
            to_mode: 2,
            bracket: [3.0 - 1e-4, 3.0 + 1e-4],
        }];
        assert_eq!(
            super::frequency_regions(&l, 8.0),
            vec![(1.25, 3.0, 1), (3.0, 8.0, 2)]
        );
    }

    #[test]
    fn an_empty_spectrum_is_refused() {
        let mut result = sample();
        result.spectrum.clear();
        assert!(super::svg(&result).is_err());
    }
}
