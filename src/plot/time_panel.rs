//! One panel of a time history (a quantity against time) drawn over one
//! span of time: the curve cut to the span, its y range fitted to what the
//! span shows, the pulse shaded, impacts ticked, overturning, rest and
//! lift-off marked, where a curve stops on purpose an open marker, and on a
//! Coulomb floor the block's modes as a band along the time axis.

use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::style::{
    AXIS, Area, Chart, Drawn, INK, LEGEND, MUTED, Marker, PULSE, TICKS, axis_range, clip_y,
    left_top, marker, right_top, text, text_width, tick,
};
use super::style::{Box4, overlap};

/// Shade of the span a zoomed column shows, in the whole-history column.
pub const ZOOMED: RGBColor = RGBColor(228, 233, 242);

/// Room above a panel's chart, px.
const MARGIN_TOP: u32 = 8;
/// Height of the band of modes along the time axis of a panel, px.
pub const BAND_HEIGHT: u32 = 14;
/// Gap between the band and the lowest value a panel shows, px.
const BAND_GAP: u32 = 3;
/// Distance of a mark's label from its line, px.
const LABEL_GAP: i32 = 6;
/// Distance of the first row of mark labels below the panel's top, px.
const LABEL_TOP: i32 = 4;
/// Height of a row of mark labels, px (a label is `LEGEND` px high).
pub const LABEL_ROW: i32 = LEGEND as i32 + 4;

/// How a panel's y range follows the values its span shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// ± the largest |value| shown (with a margin), at least `floor`.
    Symmetric {
        /// Least half range.
        floor: f64,
    },
    /// As `Symmetric`, at most `cap`: larger values leave the panel.
    Capped {
        /// Least half range.
        floor: f64,
        /// Largest half range.
        cap: f64,
    },
}

/// Where a curve stops on purpose (the quantity ceases to mean anything
/// there, e.g. f_x/f_z at lift-off).
#[derive(Clone, Debug, PartialEq)]
pub struct End {
    /// Its time, s.
    pub t: f64,
    /// The value there.
    pub value: f64,
    /// What happens there, written beside the marker.
    pub label: String,
}

/// One quantity against time.
pub struct Panel {
    /// Axis description.
    pub desc: String,
    /// Legend label.
    pub label: String,
    /// Colour of its curve or markers.
    pub colour: RGBColor,
    /// A curve (non-finite values break it).
    pub line: Vec<(f64, f64)>,
    /// The curve dashed: it only joins values known at its points.
    pub dashed: bool,
    /// Markers (without a curve).
    pub points: Vec<((f64, f64), Marker)>,
    /// How its y range is chosen.
    pub scale: Scale,
    /// Dotted reference levels.
    pub refs: Vec<f64>,
    /// Tick the impacts on the zero line.
    pub impacts: bool,
    /// Where the curve stops on purpose.
    pub end: Option<End>,
}

/// A vertical line across every panel.
pub struct Mark {
    /// Its time, s.
    pub t: f64,
    /// Its colour.
    pub colour: RGBColor,
    /// Its label, on the top panel.
    pub label: String,
}

/// A stretch of time shaded in the band along the time axis (one mode of
/// a block on a Coulomb floor).
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// Its start, s.
    pub from: f64,
    /// Its end, s.
    pub to: f64,
    /// Its fill.
    pub colour: RGBColor,
}

/// What every panel of a figure shares.
pub struct Shared {
    /// When the ground stops moving (shaded from 0), s.
    pub motion_end: Option<f64>,
    /// Impact times, s.
    pub impacts: Vec<f64>,
    /// Vertical lines.
    pub marks: Vec<Mark>,
    /// Stretches shaded along the bottom of every panel (none: no band).
    pub bands: Vec<Band>,
}

/// A span of time drawn as one column of panels.
#[derive(Clone, Debug, PartialEq)]
pub struct Span {
    /// First time shown, s.
    pub t0: f64,
    /// Last time shown, s.
    pub t1: f64,
    /// A span of it shown zoomed in another column, shaded here.
    pub zoomed: Option<(f64, f64)>,
}

/// Where a panel sits in the figure.
#[derive(Clone, Copy, Debug)]
pub struct Place {
    /// Top row: marks are labelled here.
    pub top: bool,
    /// Bottom row: the time axis is labelled here.
    pub bottom: bool,
    /// Write the axis description (first column).
    pub desc: bool,
    /// Width of the y labels, px.
    pub y_labels: u32,
    /// Height of the time axis under the bottom row, px.
    pub x_axis: u32,
}

/// The part of `points` (ordered in time) inside `[t0, t1]`, with the
/// points where it crosses `t0` and `t1` interpolated; non-finite values
/// are kept (they break the line) but never interpolated across.
pub fn crop(points: &[(f64, f64)], t0: f64, t1: f64) -> Vec<(f64, f64)> {
    let at = |a: (f64, f64), b: (f64, f64), t: f64| {
        let s = (t - a.0) / (b.0 - a.0);
        (t, a.1 + s * (b.1 - a.1))
    };
    let mut out = Vec::new();
    for (k, &p) in points.iter().enumerate() {
        if let Some(&q) = k.checked_sub(1).and_then(|j| points.get(j))
            && q.1.is_finite()
            && p.1.is_finite()
        {
            if q.0 < t0 && p.0 > t0 {
                out.push(at(q, p, t0));
            }
            if q.0 < t1 && p.0 > t1 {
                out.push(at(q, p, t1));
            }
        }
        if p.0 >= t0 && p.0 <= t1 {
            out.push(p);
        }
    }
    out
}

impl Panel {
    /// A solid curve `line` described `desc` and labelled `label`, its y
    /// range chosen by `scale`: without markers, reference levels, impact
    /// ticks or an end (a figure sets those it wants over this).
    pub fn curve(
        desc: impl Into<String>,
        label: impl Into<String>,
        colour: RGBColor,
        line: Vec<(f64, f64)>,
        scale: Scale,
    ) -> Panel {
        Panel {
            desc: desc.into(),
            label: label.into(),
            colour,
            line,
            dashed: false,
            points: Vec::new(),
            scale,
            refs: Vec::new(),
            impacts: false,
            end: None,
        }
    }

    /// The y range of this panel over `span`.
    pub fn range(&self, span: &Span) -> (f64, f64) {
        let shown = crop(&self.line, span.t0, span.t1)
            .into_iter()
            .map(|p| p.1)
            .chain(
                self.points
                    .iter()
                    .filter(|(p, _)| p.0 >= span.t0 && p.0 <= span.t1)
                    .map(|(p, _)| p.1),
            )
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let half = match self.scale {
            Scale::Symmetric { floor } => (shown * 1.12).max(floor),
            Scale::Capped { floor, cap } => (shown * 1.12).min(cap).max(floor),
        };
        (-half, half)
    }
}

/// Draws `panel` over `span` in `area`.
pub fn draw_panel(area: &Area, panel: &Panel, span: &Span, shared: &Shared, place: Place) -> Drawn {
    let (lo, hi) = panel.range(span);
    // A band of modes takes the bottom of the panel, under the values: the
    // axis reaches below `lo` by the band's height and a gap.
    let axis_lo = if shared.bands.is_empty() {
        lo
    } else {
        let x_axis = if place.bottom { place.x_axis } else { 0 };
        let plot = f64::from(area.dim_in_pixel().1.saturating_sub(MARGIN_TOP + x_axis));
        let room = f64::from(BAND_HEIGHT + BAND_GAP);
        lo - (hi - lo) * room / (plot - room).max(1.0)
    };
    let (t0, t1) = (span.t0, span.t1);
    let mut chart = ChartBuilder::on(area)
        .margin_top(MARGIN_TOP)
        .margin_right(16)
        .margin_left(4)
        .x_label_area_size(if place.bottom { place.x_axis } else { 0 })
        .y_label_area_size(place.y_labels)
        .build_cartesian_2d(axis_range("time", t0, t1)?, axis_range("y", axis_lo, hi)?)?;
    let mut mesh = chart.configure_mesh();
    mesh.label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .light_line_style(RGBColor(243, 243, 243))
        .bold_line_style(RGBColor(222, 222, 222))
        .y_labels(5)
        .x_labels(8)
        .y_label_formatter(&|v| tick(*v))
        .x_label_formatter(&|v| tick(*v));
    if place.desc {
        mesh.y_desc(panel.desc.as_str());
    }
    if place.bottom {
        mesh.x_desc("t (s)");
    }
    mesh.draw()?;
    draw_shading(&mut chart, shared, span, [axis_lo, lo, hi])?;
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(t0, 0.0), (t1, 0.0)],
        RGBColor(160, 160, 160).stroke_width(1),
    )))?;
    for &level in panel.refs.iter().filter(|l| **l > lo && **l < hi) {
        chart.draw_series(std::iter::once(DashedPathElement::new(
            vec![(t0, level), (t1, level)],
            3,
            3,
            MUTED.stroke_width(1),
        )))?;
    }
    for part in clip_y(&crop(&panel.line, t0, t1), lo, hi) {
        if panel.dashed {
            chart.draw_series(std::iter::once(DashedPathElement::new(
                part,
                6,
                5,
                panel.colour.stroke_width(2),
            )))?;
        } else {
            chart.draw_series(LineSeries::new(part, panel.colour.stroke_width(2)))?;
        }
    }
    chart.draw_series(
        panel
            .points
            .iter()
            .filter(|(q, _)| q.1 >= lo && q.1 <= hi && q.0 >= t0 && q.0 <= t1)
            .map(|&(q, kind)| marker(q, kind, 10, panel.colour)),
    )?;
    if panel.impacts {
        chart.draw_series(
            shared
                .impacts
                .iter()
                .filter(|t| **t >= t0 && **t <= t1)
                .map(|&t| marker((t, 0.0), Marker::Tick, 9, INK)),
        )?;
    }
    draw_marks(&mut chart, shared, span, (axis_lo, hi), place.top)?;
    // The plot's width, px.
    let plot_width = f64::from(area.dim_in_pixel().0.saturating_sub(place.y_labels + 20));
    draw_end(&mut chart, panel, span, (lo, hi), plot_width)?;
    Ok(())
}

/// Shades, over `span` of `chart` between `y` = [axis bottom, lowest value,
/// top], the span a zoomed column shows, the time the ground moves and,
/// under the values, the band of modes.
fn draw_shading(chart: &mut Chart<'_, '_>, shared: &Shared, span: &Span, y: [f64; 3]) -> Drawn {
    let [axis_lo, lo, hi] = y;
    let (t0, t1) = (span.t0, span.t1);
    let band = |a: f64, b: f64| (a.max(t0), b.min(t1));
    if let Some((a, b)) = span.zoomed.map(|(a, b)| band(a, b)).filter(|(a, b)| a < b) {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(a, axis_lo), (b, hi)],
            ZOOMED.filled(),
        )))?;
    }
    if let Some((a, b)) = shared
        .motion_end
        .map(|end| band(0.0, end))
        .filter(|(a, b)| a < b)
    {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(a, axis_lo), (b, hi)],
            PULSE.mix(0.65).filled(),
        )))?;
    }
    if !shared.bands.is_empty() {
        // The band's top in the panel's y units, a gap under the values.
        let plot_height = f64::from(chart.plotting_area().dim_in_pixel().1.max(1));
        let top = lo - (hi - axis_lo) * f64::from(BAND_GAP) / plot_height;
        chart.draw_series(
            shared
                .bands
                .iter()
                .map(|b| (band(b.from, b.to), b.colour))
                .filter(|((a, b), _)| a < b)
                .map(|((a, b), colour)| Rectangle::new([(a, axis_lo), (b, top)], colour.filled())),
        )?;
    }
    Ok(())
}

/// Draws the marks of `shared` inside `span` as dashed lines across `chart`
/// from `y.0` to `y.1`; on the top row (`top`) with their labels, placed
/// by [`mark_label_boxes`]: beside their lines, none over another.
fn draw_marks(
    chart: &mut Chart<'_, '_>,
    shared: &Shared,
    span: &Span,
    y: (f64, f64),
    top: bool,
) -> Drawn {
    let ((t0, t1), (axis_lo, hi)) = ((span.t0, span.t1), y);
    let marks: Vec<&Mark> = shared
        .marks
        .iter()
        .filter(|m| m.t >= t0 && m.t <= t1)
        .collect();
    for mark in &marks {
        chart.draw_series(std::iter::once(DashedPathElement::new(
            vec![(mark.t, axis_lo), (mark.t, hi)],
            7,
            4,
            mark.colour.stroke_width(2),
        )))?;
    }
    if top {
        // Each label's box, in px from the top of the panel's plot.
        let x = |t: f64| chart.backend_coord(&(t, hi)).0;
        let at: Vec<(i32, i32)> = marks
            .iter()
            .map(|m| (x(m.t), text_width(&m.label, LEGEND).ceil() as i32))
            .collect();
        let boxes = mark_label_boxes(&at, (x(t0), x(t1)));
        for ((mark, (line, _)), b) in marks.iter().zip(&at).zip(&boxes) {
            let (style, dx) = if b.2 <= *line {
                (right_top(LEGEND, mark.colour), b.2 - line)
            } else {
                (left_top(LEGEND, mark.colour), b.0 - line)
            };
            chart.draw_series(std::iter::once(
                EmptyElement::at((mark.t, hi)) + Text::new(mark.label.clone(), (dx, b.1), style),
            ))?;
        }
    }
    Ok(())
}

/// Marks where `panel`'s curve stops on purpose (its `end`, inside `span`)
/// with an open marker and its label, in `chart` showing `y` = (lo, hi)
/// over `plot_width` px.
fn draw_end(
    chart: &mut Chart<'_, '_>,
    panel: &Panel,
    span: &Span,
    y: (f64, f64),
    plot_width: f64,
) -> Drawn {
    let ((t0, t1), (lo, hi)) = ((span.t0, span.t1), y);
    if let Some(end) = panel.end.as_ref().filter(|e| e.t >= t0 && e.t <= t1) {
        let at = (end.t, end.value.clamp(lo, hi));
        chart.draw_series(std::iter::once(marker(at, Marker::Ring, 12, panel.colour)))?;
        // After the marker when the label fits there (the curve has stopped),
        // else before it; above it when it sits low, below when high.
        let room_after = (t1 - end.t) / (t1 - t0) * plot_width;
        let needed = text_width(&end.label, LEGEND) + 16.0;
        let (h, dx) = if room_after >= needed {
            (HPos::Left, 10)
        } else {
            (HPos::Right, -10)
        };
        let (v, dy) = if at.1 < 0.5 * (lo + hi) {
            (VPos::Bottom, -8)
        } else {
            (VPos::Top, 8)
        };
        let style = text(LEGEND, panel.colour).pos(Pos::new(h, v));
        chart.draw_series(std::iter::once(
            EmptyElement::at(at) + Text::new(end.label.clone(), (dx, dy), style),
        ))?;
    }
    Ok(())
}

/// The boxes of the labels of marks drawn as vertical lines, px: left and
/// right in the frame of `marks`, top and bottom below the top of the plot
/// (the labels hang from it). `marks[k]` is the x of line k (px) and the
/// width of its label; `plot` the plot's (left, right), px.
///
/// Each label is placed in order beside its line, `LABEL_GAP` from it, on
/// the side with more room (left of a line past 55 % of the plot, right of
/// it otherwise), unless its box would overlap one placed before; then on
/// the other side where it fits in the plot and overlaps none; else one
/// row (`LABEL_ROW`) lower, and so on. No two boxes overlap: a label finds
/// room at the latest in a row below every label placed before it.
pub fn mark_label_boxes(marks: &[(i32, i32)], plot: (i32, i32)) -> Vec<Box4> {
    let (left, right) = plot;
    let split = f64::from(left) + 0.55 * f64::from(right - left);
    let mut placed: Vec<Box4> = Vec::with_capacity(marks.len());
    for &(x, w) in marks {
        let before = (x - LABEL_GAP - w, x - LABEL_GAP);
        let after = (x + LABEL_GAP, x + LABEL_GAP + w);
        let (first, other) = if f64::from(x) > split {
            (before, after)
        } else {
            (after, before)
        };
        let fits = |(a, b): (i32, i32)| a >= left && b <= right;
        let found = (0..=placed.len() as i32)
            .flat_map(|row| {
                let top = LABEL_TOP + row * LABEL_ROW;
                [(first, true), (other, fits(other))]
                    .into_iter()
                    .filter(|(_, allowed)| *allowed)
                    .map(move |((a, b), _)| (a, top, b, top + LEGEND as i32))
            })
            .find(|b| !placed.iter().any(|p| overlap(*p, *b)));
        // Row placed.len() is below every box placed: always found.
        let top = LABEL_TOP + placed.len() as i32 * LABEL_ROW;
        placed.push(found.unwrap_or((first.0, top, first.1, top + LEGEND as i32)));
    }
    placed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_of_close_marks_never_overlap() {
        let plot = (0, 1000);
        // Far apart, each on its side with more room, in the top row.
        let apart = mark_label_boxes(&[(100, 150), (900, 150)], plot);
        assert_eq!(apart, vec![(106, 4, 256, 22), (744, 4, 894, 22)]);
        // Close at the right end: the second cannot go right of its line
        // (out of the plot), so it goes one row lower, left of it.
        let close = mark_label_boxes(&[(980, 180), (930, 180)], plot);
        assert_eq!(close, vec![(794, 4, 974, 22), (744, 26, 924, 44)]);
        // Close in the middle: the other side of its line, same row; a
        // line under the first label has its own below it.
        let middle = mark_label_boxes(&[(600, 180), (640, 120)], plot);
        assert_eq!(middle, vec![(414, 4, 594, 22), (646, 4, 766, 22)]);
        let under = mark_label_boxes(&[(600, 180), (560, 120)], plot);
        assert_eq!(under, vec![(414, 4, 594, 22), (434, 26, 554, 44)]);
        // Many marks on one spot: each a row lower, none overlapping.
        let pile = mark_label_boxes(&[(500, 100); 5], plot);
        for (i, a) in pile.iter().enumerate() {
            for b in &pile[i + 1..] {
                assert!(!overlap(*a, *b), "{a:?} {b:?}");
            }
        }
        assert_eq!(pile.iter().map(|b| b.1).max(), Some(4 + 2 * LABEL_ROW));
    }

    #[test]
    fn cropping_interpolates_the_ends_and_keeps_gaps() {
        let pts = [(0.0, 0.0), (1.0, 2.0), (2.0, f64::NAN), (3.0, 4.0)];
        let c = crop(&pts, 0.5, 2.5);
        assert_eq!(c[0], (0.5, 1.0));
        assert_eq!(c[1], (1.0, 2.0));
        assert!(c[2].1.is_nan());
        assert_eq!(c.len(), 3);
        // A span inside one segment.
        assert_eq!(
            crop(&[(0.0, 0.0), (4.0, 4.0)], 1.0, 2.0),
            vec![(1.0, 1.0), (2.0, 2.0)]
        );
    }

    #[test]
    fn ranges_follow_the_span_shown() {
        let panel = Panel {
            desc: String::new(),
            label: String::new(),
            colour: INK,
            line: vec![(0.0, 0.5), (1.0, -0.5), (2.0, 8.0)],
            dashed: false,
            points: Vec::new(),
            scale: Scale::Symmetric { floor: 1.25 },
            refs: Vec::new(),
            impacts: false,
            end: None,
        };
        let early = Span {
            t0: 0.0,
            t1: 1.0,
            zoomed: None,
        };
        assert_eq!(panel.range(&early), (-1.25, 1.25));
        let all = Span {
            t0: 0.0,
            t1: 2.0,
            zoomed: None,
        };
        assert!((panel.range(&all).1 - 8.96).abs() < 1e-12);
    }
}
