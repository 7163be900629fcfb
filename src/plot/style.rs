//! The shared look of every figure: fonts, colours, markers, the legend
//! panel beside the chart, and clipping of curves to a chart's range.

use plotters::chart::{DualCoordChartContext, MeshStyle, SecondaryMeshStyle};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::{CoordTranslate, Shift};
use plotters::element::ComposedElement;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A drawing area of an SVG figure.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// What drawing returns.
pub type Drawn = Result<(), Box<dyn std::error::Error>>;
/// A chart of an SVG figure on two axes of numbers (a time panel's: time
/// against its quantity).
pub type Chart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Font family (SVG viewers substitute their sans-serif).
pub const FONT: &str = "sans-serif";
// Sizes are the pixels of the SVG as drawn. Figures are 1120 px wide and the
// web page shows them in a pane of 700–900 px: the smallest text (17 px)
// reads at 10.6–13.7 px there (12.1 px at 800).
/// Figure title size, px.
pub const TITLE: u32 = 24;
/// Axis description size, px.
pub const AXIS: u32 = 19;
/// Tick label size, px.
pub const TICKS: u32 = 17;
/// Legend entry size, px.
pub const LEGEND: u32 = 18;
/// Notes under the legend, px.
pub const NOTE: u32 = 17;
/// Room for the tick labels and description of a horizontal axis, px.
pub const X_LABEL_AREA: u32 = 60;
/// Room for the tick labels and description of a vertical axis, px.
pub const Y_LABEL_AREA: u32 = 78;
/// Width of the legend panel at the right of a figure, px.
pub const LEGEND_WIDTH: u32 = 370;
/// Line height of legend entries, px.
const LEGEND_LINE: i32 = 21;
/// Line height of notes, px.
const NOTE_LINE: i32 = 20;
/// Average advance of a character of the sans-serif fonts SVG viewers pick,
/// in ems (DejaVu Sans is the widest common one): how many characters a line
/// of the legend holds.
const EM_PER_CHAR: f64 = 0.56;
/// plotters' SVG backend writes `font-size` as the size asked for / 1.24.
const SVG_FONT_SCALE: f64 = 1.24;

/// Text and axes.
pub const INK: RGBColor = RGBColor(33, 33, 33);
/// Secondary text.
pub const MUTED: RGBColor = RGBColor(110, 110, 110);
/// Overturning after at least one impact (mode 1).
pub const MODE1: RGBColor = RGBColor(200, 50, 45);
/// Overturning without impact (mode 2).
pub const MODE2: RGBColor = RGBColor(0, 114, 178);
/// Amplitudes too small to start rocking.
pub const NO_ROCKING: RGBColor = RGBColor(222, 222, 222);
/// A mixed zone: the outcome alternates finer than the scan resolves.
pub const MIXED: RGBColor = RGBColor(196, 160, 214);
/// The pulses consistent with every observation.
pub const CONSISTENT: RGBColor = RGBColor(0, 150, 105);
/// The duration of the pulse.
pub const PULSE: RGBColor = RGBColor(255, 233, 168);
/// Reference curves from closed forms.
pub const REFERENCE: RGBColor = RGBColor(120, 40, 140);
/// Coming to rest.
pub const REST: RGBColor = RGBColor(0, 140, 80);
/// One colour per observation of a forensic map (then repeated).
pub const OBSERVATIONS: [RGBColor; 6] = [
    RGBColor(230, 159, 0),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(160, 60, 40),
    RGBColor(90, 90, 200),
    RGBColor(150, 150, 0),
];

/// `c` mixed with white: `strength` 1 is `c`, 0 is white (opaque, so
/// neighbouring fills show no seams).
pub fn tint(c: RGBColor, strength: f64) -> RGBColor {
    let s = strength.clamp(0.0, 1.0);
    let mix = |v: u8| (f64::from(v) * s + 255.0 * (1.0 - s)).round() as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

/// The colour of overturning mode `mode`.
pub fn mode_colour(mode: u8) -> RGBColor {
    if mode == 2 { MODE2 } else { MODE1 }
}

/// A text style of `size` px (as drawn) in `colour`.
pub fn text(size: u32, colour: RGBColor) -> TextStyle<'static> {
    (FONT, f64::from(size) * SVG_FONT_SCALE)
        .into_font()
        .color(&colour)
}

/// About how wide `s` is in text of `size` px.
pub fn text_width(s: &str, size: u32) -> f64 {
    s.chars().count() as f64 * f64::from(size) * EM_PER_CHAR
}

/// How many characters of `size` px fit in `width` px.
pub fn chars_in(width: f64, size: u32) -> usize {
    (width / (f64::from(size) * EM_PER_CHAR)).max(12.0) as usize
}

/// Marker shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    /// Open circle.
    Ring,
    /// Filled circle.
    Dot,
    /// Filled triangle, point up.
    Triangle,
    /// Filled square.
    Square,
    /// Diagonal cross.
    Cross,
    /// Short vertical tick.
    Tick,
}

/// A marker drawn in pixels around a point of any coordinate system.
pub type MarkerElement<C, DB> =
    ComposedElement<C, DB, Polygon<(i32, i32)>, PathElement<(i32, i32)>>;

/// `kind` at `at`, `size` px across, in `colour`.
pub fn marker<C, DB: DrawingBackend>(
    at: C,
    kind: Marker,
    size: i32,
    colour: RGBColor,
) -> MarkerElement<C, DB> {
    let r = (size / 2).max(2);
    let ring: Vec<(i32, i32)> = (0..=16)
        .map(|k| {
            let a = f64::from(k) * std::f64::consts::TAU / 16.0;
            (
                (f64::from(r) * a.cos()).round() as i32,
                (f64::from(r) * a.sin()).round() as i32,
            )
        })
        .collect();
    let stroke = colour.stroke_width(2);
    let (fill, outline, fill_style) = match kind {
        Marker::Ring => (ring.clone(), ring, WHITE.filled()),
        Marker::Dot => (ring.clone(), ring, colour.filled()),
        Marker::Triangle => {
            let t = vec![(0, -r - 1), (r + 1, r), (-r - 1, r), (0, -r - 1)];
            (t.clone(), t, colour.filled())
        }
        Marker::Square => {
            let s = vec![(-r, -r), (r, -r), (r, r), (-r, r), (-r, -r)];
            (s.clone(), s, colour.filled())
        }
        Marker::Cross => (
            Vec::new(),
            vec![(-r, -r), (r, r), (0, 0), (r, -r), (-r, r)],
            TRANSPARENT.filled(),
        ),
        Marker::Tick => (
            Vec::new(),
            vec![(0, -r - 3), (0, r + 3)],
            TRANSPARENT.filled(),
        ),
    };
    EmptyElement::at(at) + Polygon::new(fill, fill_style) + PathElement::new(outline, stroke)
}

/// What a legend entry shows beside its label.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Swatch {
    /// A filled box.
    Fill(RGBColor),
    /// A filled box with a border.
    Boxed(RGBColor, RGBColor),
    /// A solid line of a width.
    Line(RGBColor, u32),
    /// A dashed line of a width.
    Dashed(RGBColor, u32),
    /// A marker.
    Mark(Marker, RGBColor),
    /// A line through a marker.
    LineMark(RGBColor, Marker),
    /// A dashed line through a marker: values known at the markers only.
    DashedMark(RGBColor, Marker),
    /// No swatch: the label is a heading.
    Heading,
}

/// A legend: entries, then free notes.
#[derive(Clone, Debug, Default)]
pub struct Legend {
    /// (swatch, label).
    pub entries: Vec<(Swatch, String)>,
    /// Lines of notes under the entries (parameters, outcome).
    pub notes: Vec<String>,
}

impl Legend {
    /// Adds an entry.
    pub fn entry(&mut self, swatch: Swatch, label: impl Into<String>) {
        self.entries.push((swatch, label.into()));
    }

    /// Adds a note.
    pub fn note(&mut self, note: impl Into<String>) {
        self.notes.push(note.into());
    }
}

/// `s` broken into lines of at most `width` characters at spaces.
pub fn wrap(s: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in s.split(' ') {
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

fn dashed(area: &Area, from: (i32, i32), to: (i32, i32), style: ShapeStyle) -> Drawn {
    area.draw(&DashedPathElement::new(vec![from, to], 6, 4, style))?;
    Ok(())
}

/// Left edge of an entry's label: room for its swatch.
const LABEL_X: i32 = 50;

/// One block of a legend laid out: an entry, the rule above the notes, or a
/// note, with its lines.
enum Item {
    Entry(Swatch, Vec<String>),
    Rule,
    Note(Vec<String>),
}

impl Item {
    fn height(&self) -> i32 {
        match self {
            Item::Entry(_, lines) => lines.len() as i32 * LEGEND_LINE + 6,
            Item::Rule => 16,
            Item::Note(lines) => lines.len() as i32 * NOTE_LINE + 4,
        }
    }
}

/// `legend` as blocks poured into `columns` columns of `width` px, each
/// column about as tall as the others.
fn layout(legend: &Legend, width: u32, columns: usize) -> Vec<Vec<Item>> {
    let columns = columns.max(1);
    let w = f64::from(width) / columns as f64;
    let label_chars = chars_in(w - f64::from(LABEL_X) - 12.0, LEGEND);
    let note_chars = chars_in(w - 20.0, NOTE);
    let mut items: Vec<Item> = legend
        .entries
        .iter()
        .map(|(swatch, label)| {
            let width = if *swatch == Swatch::Heading {
                chars_in(w - 20.0, LEGEND)
            } else {
                label_chars
            };
            Item::Entry(*swatch, wrap(label, width))
        })
        .collect();
    if !legend.notes.is_empty() {
        items.push(Item::Rule);
        items.extend(legend.notes.iter().map(|n| Item::Note(wrap(n, note_chars))));
    }
    let total: i32 = items.iter().map(Item::height).sum();
    let target = total / columns as i32;
    let mut out: Vec<Vec<Item>> = vec![Vec::new()];
    let mut filled = 0;
    for item in items {
        let h = item.height();
        let room = out.len() < columns;
        if room && out.last().is_some_and(|c| !c.is_empty()) && filled + h / 2 > target {
            out.push(Vec::new());
            filled = 0;
        }
        // A rule at the top of a column says nothing.
        if matches!(item, Item::Rule) && out.last().is_some_and(Vec::is_empty) {
            continue;
        }
        filled += h;
        if let Some(current) = out.last_mut() {
            current.push(item);
        }
    }
    out
}

/// The height `legend` takes in `columns` columns of `width` px.
pub fn legend_height(legend: &Legend, width: u32, columns: usize) -> u32 {
    let tallest = layout(legend, width, columns)
        .iter()
        .map(|c| c.iter().map(Item::height).sum::<i32>())
        .max()
        .unwrap_or(0);
    (tallest + 16).max(0) as u32
}

/// Draws `legend` in `area` (the panel at the right of a figure).
pub fn draw_legend(area: &Area, legend: &Legend) -> Drawn {
    draw_legend_columns(area, legend, 1)
}

/// Draws `legend` in `area` in `columns` columns (under a figure).
pub fn draw_legend_columns(area: &Area, legend: &Legend, columns: usize) -> Drawn {
    let (w, _) = area.dim_in_pixel();
    let cols = layout(legend, w, columns);
    let col_w = (w / columns.max(1) as u32) as i32;
    for (c, items) in cols.iter().enumerate() {
        let left = c as i32 * col_w;
        let mut y = 12;
        for item in items {
            match item {
                Item::Entry(swatch, lines) => {
                    draw_entry(area, left, y, *swatch, lines)?;
                }
                Item::Rule => {
                    let mid = y + 6;
                    area.draw(&PathElement::new(
                        vec![(left + 8, mid), (left + col_w - 16, mid)],
                        MUTED.stroke_width(1),
                    ))?;
                }
                Item::Note(lines) => {
                    for (k, line) in lines.iter().enumerate() {
                        area.draw(&Text::new(
                            line.clone(),
                            (left + 8, y + k as i32 * NOTE_LINE),
                            text(NOTE, MUTED),
                        ))?;
                    }
                }
            }
            y += item.height();
        }
    }
    Ok(())
}

/// One entry: its swatch at `left`, its label lines beside it, from `y` down.
fn draw_entry(area: &Area, left: i32, y: i32, swatch: Swatch, lines: &[String]) -> Drawn {
    let mid = y + LEGEND_LINE / 2;
    let (x0, x1) = (left + 8, left + 42);
    let centre = (x0 + x1) / 2;
    match swatch {
        Swatch::Fill(c) => {
            area.draw(&Rectangle::new([(x0, mid - 8), (x1, mid + 8)], c.filled()))?;
        }
        Swatch::Boxed(fill, border) => {
            area.draw(&Rectangle::new(
                [(x0, mid - 8), (x1, mid + 8)],
                fill.filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(x0, mid - 8), (x1, mid + 8)],
                border.stroke_width(2),
            ))?;
        }
        Swatch::Line(c, width) => {
            area.draw(&PathElement::new(
                vec![(x0, mid), (x1, mid)],
                c.stroke_width(width),
            ))?;
        }
        Swatch::Dashed(c, width) => dashed(area, (x0, mid), (x1, mid), c.stroke_width(width))?,
        Swatch::Mark(kind, c) => {
            area.draw(&marker::<_, SVGBackend>((centre, mid), kind, 11, c))?;
        }
        Swatch::LineMark(c, kind) => {
            area.draw(&PathElement::new(
                vec![(x0, mid), (x1, mid)],
                c.stroke_width(2),
            ))?;
            area.draw(&marker::<_, SVGBackend>((centre, mid), kind, 10, c))?;
        }
        Swatch::DashedMark(c, kind) => {
            dashed(area, (x0, mid), (x1, mid), c.stroke_width(2))?;
            area.draw(&marker::<_, SVGBackend>((centre, mid), kind, 10, c))?;
        }
        Swatch::Heading => {}
    }
    let x = if swatch == Swatch::Heading {
        x0
    } else {
        left + LABEL_X
    };
    for (k, line) in lines.iter().enumerate() {
        area.draw(&Text::new(
            line.clone(),
            (x, y + 2 + k as i32 * LEGEND_LINE),
            text(LEGEND, INK),
        ))?;
    }
    Ok(())
}

/// Text anchored at its top right corner.
pub fn right_top(size: u32, colour: RGBColor) -> TextStyle<'static> {
    text(size, colour).pos(Pos::new(HPos::Right, VPos::Top))
}

/// Text anchored at its top left corner.
pub fn left_top(size: u32, colour: RGBColor) -> TextStyle<'static> {
    text(size, colour).pos(Pos::new(HPos::Left, VPos::Top))
}

/// The parts of a polyline inside `lo ≤ y ≤ hi`, cut where it crosses the
/// limits (non-finite points break it).
pub fn clip_y(points: &[(f64, f64)], lo: f64, hi: f64) -> Vec<Vec<(f64, f64)>> {
    let inside = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && p.1 >= lo && p.1 <= hi;
    let cross = |a: (f64, f64), b: (f64, f64), level: f64| {
        let s = (level - a.1) / (b.1 - a.1);
        (a.0 + s * (b.0 - a.0), level)
    };
    let mut parts = Vec::new();
    let mut part: Vec<(f64, f64)> = Vec::new();
    for (k, &p) in points.iter().enumerate() {
        let prev = k.checked_sub(1).map(|j| points[j]);
        let finite = p.0.is_finite() && p.1.is_finite();
        let prev_finite = prev.is_some_and(|q| q.0.is_finite() && q.1.is_finite());
        if inside(&p) {
            if part.is_empty()
                && let Some(q) = prev.filter(|_| prev_finite)
            {
                if q.1 > hi {
                    part.push(cross(q, p, hi));
                } else if q.1 < lo {
                    part.push(cross(q, p, lo));
                }
            }
            part.push(p);
        } else {
            if let Some(&q) = part.last()
                && finite
            {
                part.push(cross(q, p, if p.1 > hi { hi } else { lo }));
            } else if finite
                && let Some(q) = prev.filter(|_| prev_finite)
                && ((q.1 > hi && p.1 < lo) || (q.1 < lo && p.1 > hi))
            {
                // Straight through the whole range between two samples.
                let (a, b) = (cross(q, p, hi), cross(q, p, lo));
                parts.push(vec![a, b]);
            }
            if !part.is_empty() {
                parts.push(std::mem::take(&mut part));
            }
        }
    }
    if !part.is_empty() {
        parts.push(part);
    }
    parts
}

/// A tick step giving about `n` labels over `span`, from 1, 2 and 5 × 10^k.
pub fn nice_step(span: f64, n: f64) -> f64 {
    let raw = (span / n.max(1.0)).abs().max(f64::MIN_POSITIVE);
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let nice = if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

/// An axis range for plotters, `lo..hi`: both ends within ±10^300 and `hi`
/// above `lo` by more than their rounding, else an error naming the axis. Plotters' search for ticks does not end on an
/// infinite range, so every chart builds its axes through this.
pub fn axis_range(
    axis: &str,
    lo: f64,
    hi: f64,
) -> Result<std::ops::Range<f64>, Box<dyn std::error::Error>> {
    // Plotters steps from tick to tick, by powers of ten of the width: the
    // range must be wider than the rounding of its ends, and its width and
    // ten times it finite.
    let end = lo.abs().max(hi.abs());
    if end <= 1e300 && hi - lo > 1e-12 * end {
        Ok(lo..hi)
    } else {
        Err(format!("the {axis} axis would run from {lo} to {hi}").into())
    }
}

/// A tick label: `v` to at most 4 significant digits, never "-0".
pub fn tick(v: f64) -> String {
    if v.abs() < 1e-12 {
        "0".into()
    } else {
        fmt_num(v, 4)
    }
}

pub use crate::numbers::fmt_num;

/// A tick label in [`tick`]'s format.
fn tick_label(v: &f64) -> String {
    tick(*v)
}

/// The mesh every chart shares: its axis descriptions, tick labels in
/// [`tick`]'s format, faint major lines and no minor ones. The caller may add
/// to it (its own labels, no vertical lines) before `.draw()`.
pub fn mesh<'a, 'b, DB, X, Y>(
    chart: &'b mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    x_desc: &str,
    y_desc: &str,
) -> MeshStyle<'a, 'b, X, Y, DB>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(200, 200, 200).mix(0.6));
    mesh
}

/// The secondary axes (right, and top when the chart has room for it) in
/// the look of [`mesh`], the right one described `y_desc`; the caller may
/// describe the top one before `.draw()`.
pub fn secondary_mesh<'a, 'b, DB, CT, X, Y>(
    chart: &'b mut DualCoordChartContext<'a, DB, CT, Cartesian2d<X, Y>>,
    y_desc: &str,
) -> SecondaryMeshStyle<'a, 'b, X, Y, DB>
where
    DB: DrawingBackend,
    CT: CoordTranslate,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut axes = chart.configure_secondary_axes();
    axes.y_desc(y_desc)
        .label_style(text(TICKS, INK))
        .axis_desc_style(text(AXIS, INK))
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label);
    axes
}

/// Draws the right axis of a figure over a record's scale factor: the
/// scaled record's PGA in g (its secondary range: the scale range × PGA).
pub fn scaled_pga_axis<DB, CT, X, Y>(
    chart: &mut DualCoordChartContext<'_, DB, CT, Cartesian2d<X, Y>>,
) -> Drawn
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    secondary_mesh(chart, "scaled PGA (g)").draw()?;
    Ok(())
}

/// The chart of a figure with its legend beside it: margins and the room
/// for both axes' labels; the caller adds its own (a top axis) and builds.
pub fn chart_on<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(10)
        .margin_right(24)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA);
    builder
}

/// A box in pixels: left, top, right, bottom.
pub type Box4 = (i32, i32, i32, i32);

/// Whether two boxes overlap (touching is not overlapping).
pub fn overlap(a: Box4, b: Box4) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_cuts_at_the_limits() {
        let pts = [(0.0, 0.0), (1.0, 2.0), (2.0, 0.0)];
        let parts = clip_y(&pts, -1.0, 1.0);
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0], vec![(0.0, 0.0), (0.5, 1.0)]);
        assert_eq!(parts[1], vec![(1.5, 1.0), (2.0, 0.0)]);
        let through = clip_y(&[(0.0, 5.0), (1.0, -5.0)], -1.0, 1.0);
        assert_eq!(through, vec![vec![(0.4, 1.0), (0.6, -1.0)]]);
        assert!(clip_y(&[(0.0, f64::NAN), (1.0, 9.0)], 0.0, 1.0).is_empty());
    }

    #[test]
    fn axes_are_finite_and_not_empty() {
        assert_eq!(axis_range("x", 0.0, 2.0).ok(), Some(0.0..2.0));
        for (lo, hi) in [
            (0.0, f64::INFINITY),
            (f64::NAN, 1.0),
            (1.0, 1.0),
            (2.0, 1.0),
            (1e300, 1e300 * (1.0 + 1e-15)),
        ] {
            let e = axis_range("y", lo, hi).err().map(|e| e.to_string());
            assert!(e.is_some_and(|e| e.starts_with("the y axis would run")));
        }
    }

    /// Every range the guard lets through is drawn, with its ticks, in a
    /// bounded time: extreme ends, narrow and wide.
    #[test]
    fn extreme_ranges_draw() {
        for (lo, hi) in [
            (0.0, f64::MAX),
            (-f64::MAX, f64::MAX),
            (-1e300, 1e300),
            (1e300, 1e300 * (1.0 + 1e-11)),
            (1e-300, 2e-300),
            (0.0, 5e-324),
            (1e15, 1e15 + 1.0),
        ] {
            let Ok(range) = axis_range("x", lo, hi) else {
                continue;
            };
            let mut out = String::new();
            let root = SVGBackend::with_string(&mut out, (400, 300)).into_drawing_area();
            let mut chart = chart_on(&root)
                .build_cartesian_2d(range.clone(), range)
                .expect("chart");
            chart.configure_mesh().draw().expect("mesh");
        }
    }

    #[test]
    fn wrapping_and_numbers() {
        assert_eq!(wrap("a bb ccc", 4), vec!["a bb", "ccc"]);
        assert_eq!(fmt_num(0.25, 3), "0.25");
        assert_eq!(fmt_num(2.140001, 3), "2.14");
        assert_eq!(fmt_num(15.94125, 4), "15.94");
        assert_eq!(fmt_num(1.2663572206001402e307, 3), "1.27e307");
        assert_eq!(fmt_num(-2.5e-9, 4), "-2.5e-9");
        assert_eq!(fmt_num(3.0e12, 4), "3e12");
        assert_eq!(nice_step(10.0, 5.0), 2.0);
        assert_eq!(tint(RGBColor(0, 0, 0), 0.0), RGBColor(255, 255, 255));
    }
}
