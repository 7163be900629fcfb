//! Overturning spectra (paper Figs. 6, 10, 11): in the (ω_p/p, a_p/(αg))
//! plane, each computed frequency a cell reaching half-way to its
//! neighbours, the amplitudes that overturn the block shaded by mode, the
//! safe ones white, a dot at the minimum overturning acceleration; the
//! closed forms (eq. 21; the corrected eq. 47 for linear one-sine) as
//! reference curves. The right axis reads the amplitude in g. A spectrum on
//! a Coulomb floor with the pure-rocking one beside it (`no_sliding`) is two
//! such charts side by side on the same axes, pure rocking's boundary drawn
//! over the floor's.

use plotters::prelude::*;

use crate::dynamics::PulseShape;
use crate::kinds::spectrum::{FrequencyDoc, SpectrumJob, SpectrumResult, TransitionDoc};
use crate::plot::bands::{
    Band, Column, MIN_VISIBLE, Piece, cell_edges, joined_cells, over, tile, widen,
};
use crate::plot::style::{
    Area, Drawn, INK, LEGEND, LEGEND_WIDTH, Legend, MIXED, MODE1, MODE2, MUTED, Marker, NO_ROCKING,
    REFERENCE, Swatch, X_LABEL_AREA, Y_LABEL_AREA, axis_range, clip_y, draw_legend,
    draw_legend_columns, fmt_num, legend_height, marker, mesh, secondary_mesh, text, tint,
};
use crate::plot::{block_text, render, shape_title};

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
/// The ground falls away faster than gravity: the block leaves it, no
/// verdict (under a vertical motion only).
pub const CLASS_LIFT_OFF: usize = 4;
/// A mixed zone: the outcome alternates finer than the scan resolves, and
/// neither overturning nor safety is claimed.
pub const CLASS_MIXED: usize = 5;

/// Whether a region class is overturning.
pub fn overturns(class: usize) -> bool {
    class == CLASS_MODE1 || class == CLASS_MODE2
}

/// Whether a region class is kept visible however narrow: overturning, or
/// a mixed zone.
pub fn kept(class: usize) -> bool {
    overturns(class) || class == CLASS_MIXED
}

/// Fill of a region class.
pub fn fill(class: usize) -> RGBColor {
    match class {
        CLASS_MODE1 => tint(MODE1, 0.68),
        CLASS_MODE2 => tint(MODE2, 0.55),
        CLASS_LIFT_OFF => RGBColor(186, 200, 222),
        CLASS_MIXED => MIXED,
        _ => NO_ROCKING,
    }
}

/// A legend opening with the region classes a figure shades (`used`), the
/// white safe region always (on a Coulomb floor, `slides`, where the block
/// may slide instead of rocking), the no-rocking band under `no_rocking`.
pub fn region_legend(used: impl Fn(usize) -> bool, no_rocking: &str, slides: bool) -> Legend {
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
        if slides {
            "safe: rocks, slides or slide-rocks, does not overturn"
        } else {
            "safe: rocks, does not overturn"
        },
    );
    if used(CLASS_MIXED) {
        legend.entry(
            Swatch::Fill(fill(CLASS_MIXED)),
            "mixed: the outcome alternates finer than the scan resolves",
        );
    }
    if used(CLASS_NO_ROCKING) {
        legend.entry(Swatch::Fill(fill(CLASS_NO_ROCKING)), no_rocking);
    }
    if used(CLASS_LIFT_OFF) {
        legend.entry(
            Swatch::Fill(fill(CLASS_LIFT_OFF)),
            "lift-off: g + ü_v ≤ 0, the block leaves the ground (not computed)",
        );
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

/// The overturning regions (lo, hi, mode) of one line: every band of its
/// `transitions` (narrow ones included: a figure widens them rather than
/// drop them), cut where the mode changes (`changes`: amplitude, new mode).
pub fn regions_of(
    transitions: &[Crossing],
    changes: &[(f64, u8)],
    a_max: f64,
) -> Vec<(f64, f64, u8)> {
    split_at_changes(&intervals(transitions, a_max), changes)
}

/// The overturning regions of one frequency of a pulse spectrum with their
/// modes (see [`regions_of`]).
pub fn frequency_regions(line: &FrequencyDoc, a_max: f64) -> Vec<(f64, f64, u8)> {
    let crossings: Vec<Crossing> = line.transitions.iter().map(Crossing::from).collect();
    let changes: Vec<(f64, u8)> = line
        .mode_changes
        .iter()
        .map(|m| (m.a_alpha_g, m.to_mode))
        .collect();
    regions_of(&crossings, &changes, a_max)
}

/// One unit of a spectrum's amplitude axis in g: α. The spec stores every
/// amplitude in units of αg whichever unit it was given in (`a_max_g` is
/// divided by α) and whatever the formulation — the paper's unit, of eq. 21
/// and of the axes of Figs. 6, 10 and 11 — so a_p/g = α · a_p/(αg) (the
/// nonlinear rocking threshold, g tan α, reads tan α/α on it).
pub fn g_per_axis_unit(spec: &SpectrumJob) -> f64 {
    spec.block.alpha
}

/// What the figure of a pulse spectrum shades and marks.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// The ω_p/p axis.
    pub x_range: (f64, f64),
    /// The amplitude axis runs from 0 to this, αg.
    pub a_max: f64,
    /// Half the width of a lone frequency's cell.
    pub half: f64,
    /// The bands of each computed frequency.
    pub columns: Vec<Column>,
    /// The shaded pieces: the cells of [`joined_cells`], the safe ones left
    /// out (white).
    pub shaded: Vec<Piece>,
    /// The computed minimum overturning acceleration of each frequency
    /// that has one within the axis, (ω_p/p, αg): a dot each, nothing
    /// drawn between them.
    pub minimum: Vec<(f64, f64)>,
    /// The same where it lies in a mixed zone (a ring, not a dot).
    pub minimum_mixed: Vec<(f64, f64)>,
    /// Where the minimum lies in a mixed zone: the lowest certain
    /// overturning, at least the principal relative width wide (a triangle).
    pub certain: Vec<(f64, f64)>,
}

/// The cells and the minimum of a `spectrum` result: what [`svg`] draws.
/// Each computed frequency is a cell reaching half-way to its neighbours;
/// nothing is interpolated between frequencies.
pub fn drawing(result: &SpectrumResult) -> Result<Drawing, String> {
    drawing_of(&result.spectrum, &result.spec)
}

/// The cells and the minimum of the `lines` of a spectrum of `spec` (its
/// own, or the pure-rocking lines beside them), as [`drawing`] gives them.
pub fn drawing_of(lines: &[FrequencyDoc], spec: &SpectrumJob) -> Result<Drawing, String> {
    if lines.is_empty() {
        return Err("the spectrum has no frequencies".into());
    }
    let a_max = spec.a_max_alpha_g.max(1.5);
    let ratios: Vec<f64> = lines.iter().map(|l| l.omega_ratio).collect();
    let rmin = ratios.iter().copied().fold(f64::INFINITY, f64::min);
    let rmax = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let half = if rmax > rmin {
        0.5 * (rmax - rmin) / (ratios.len() as f64 - 1.0).max(1.0)
    } else {
        0.25 * rmin.max(0.1)
    };
    let x_range = if rmax > rmin {
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
            // Under a vertical motion nothing is claimed from the level
            // where the block would leave the ground.
            let top = l.lift_off_above_alpha_g.map_or(a_max, |v| v.min(a_max));
            for (lo, hi, mode) in frequency_regions(l, top) {
                bands.push(Band {
                    lo,
                    hi,
                    class: if mode == 2 { CLASS_MODE2 } else { CLASS_MODE1 },
                });
            }
            if top < a_max {
                bands.push(Band {
                    lo: top,
                    hi: a_max,
                    class: CLASS_LIFT_OFF,
                });
            }
            let zones: Vec<[f64; 2]> = l.mixed.iter().map(|z| [z.from, z.to]).collect();
            let bands = tile(0.0, a_max, &over(&bands, &zones, CLASS_MIXED), CLASS_SAFE);
            Column {
                x: l.omega_ratio,
                bands: widen(&bands, MIN_VISIBLE * a_max, kept),
            }
        })
        .collect();
    let shaded: Vec<Piece> = joined_cells(&columns, half)
        .into_iter()
        .filter(|p| p.class != CLASS_SAFE)
        .collect();
    let at = |mixed: bool| -> Vec<(f64, f64)> {
        lines
            .iter()
            .filter(|l| (l.min_overturn_in.as_deref() == Some("mixed")) == mixed)
            .filter_map(|l| Some((l.omega_ratio, l.min_overturn_alpha_g?)))
            .filter(|m| m.1 <= a_max)
            .collect()
    };
    let certain = lines
        .iter()
        .filter(|l| l.min_overturn_in.as_deref() == Some("mixed"))
        .filter_map(|l| Some((l.omega_ratio, l.min_certain_overturn_alpha_g?)))
        .filter(|m| m.1 <= a_max)
        .collect();
    Ok(Drawing {
        x_range,
        a_max,
        half,
        columns,
        shaded,
        minimum: at(false),
        minimum_mixed: at(true),
        certain,
    })
}

/// Size of the figure of a spectrum beside the pure-rocking one: two
/// charts side by side, the legend under them.
const BESIDE_WIDTH: u32 = 1500;
/// Height of the charts of that figure (each with its heading).
const BESIDE_CHARTS: u32 = 600;
/// Height of a chart's heading in that figure.
const HEADING: u32 = 34;
/// Room above the charts for the figure's title.
const TITLE_AREA: u32 = 44;
/// Columns of the legend under the charts.
const BESIDE_LEGEND_COLUMNS: usize = 3;

/// The pure-rocking boundary drawn over the Coulomb chart: grey, thin,
/// dashed, under the chart's own marks.
pub const PURE_ROCKING_BOUNDARY: RGBColor = RGBColor(60, 60, 60);

/// One chart of a spectrum figure: the cells and minimum of its lines
/// ([`drawing_of`]) and the closed forms drawn over them.
struct Panel<'a> {
    /// Its lines.
    lines: &'a [FrequencyDoc],
    /// Their cells and minimum.
    drawn: Drawing,
    /// The closed-form mode-2 boundary (corrected eq. 47, linear one-sine);
    /// known at one frequency only, it is drawn across that frequency's bar.
    mode2_closed: Vec<(f64, f64)>,
    /// Eq. 21's line where it holds ([`eq21_line`]).
    eq21: Vec<(f64, f64)>,
}

impl<'a> Panel<'a> {
    fn of(lines: &'a [FrequencyDoc], spec: &SpectrumJob) -> Result<Self, String> {
        let drawn = drawing_of(lines, spec)?;
        let half = drawn.half;
        let (x0, x1) = drawn.x_range;
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
        Ok(Panel {
            lines,
            drawn,
            mode2_closed,
            eq21,
        })
    }

    /// Whether the chart shades a region of `class`.
    fn shades(&self, class: usize) -> bool {
        self.drawn.shaded.iter().any(|p| p.class == class)
    }
}

/// The lower edge of the lowest overturning cells of `panel`: at each
/// frequency whose minimum overturning acceleration lies on the axis, a
/// level step across its cell at that minimum, joined upright to its
/// neighbours' steps; broken where a frequency has none. (Steps, as the
/// cells: nothing is interpolated between frequencies.)
fn boundary(panel: &Panel) -> Vec<Vec<(f64, f64)>> {
    let mut columns: Vec<(f64, Option<f64>)> = panel
        .lines
        .iter()
        .map(|l| {
            let lowest = l.min_overturn_alpha_g.filter(|a| *a <= panel.drawn.a_max);
            (l.omega_ratio, lowest)
        })
        .collect();
    columns.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xs: Vec<f64> = columns.iter().map(|c| c.0).collect();
    let mut runs = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for ((_, lowest), (lo, hi)) in columns.iter().zip(cell_edges(&xs, panel.drawn.half)) {
        match lowest {
            Some(a) => run.extend([(lo, *a), (hi, *a)]),
            None if !run.is_empty() => runs.push(std::mem::take(&mut run)),
            None => {}
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// The legend of a spectrum figure: what any of its `panels` shades and
/// draws (with `beside`, the pure-rocking boundary over the floor's chart),
/// then the notes on `spec` and its own lines, `own`.
fn legend(spec: &SpectrumJob, own: &Panel, panels: &[&Panel], beside: bool) -> Legend {
    let used = |class: usize| panels.iter().any(|p| p.shades(class));
    let mut legend = region_legend(
        used,
        "no rocking (below the threshold)",
        spec.contact.is_some(),
    );
    mark_entries(&mut legend, spec, panels, beside);
    closed_form_entries(&mut legend, spec, own, panels);
    notes(&mut legend, spec, own.lines);
    legend
}

/// The legend's entries of the markers any of `panels` draws (the computed
/// minimum, in a mixed zone, the lowest certain overturning) and, `beside`,
/// of the pure-rocking boundary over the floor's chart.
fn mark_entries(legend: &mut Legend, spec: &SpectrumJob, panels: &[&Panel], beside: bool) {
    if panels.iter().any(|p| !p.drawn.minimum.is_empty()) {
        legend.entry(
            Swatch::Mark(Marker::Dot, INK),
            "minimum overturning acceleration (computed)",
        );
    }
    if panels.iter().any(|p| !p.drawn.minimum_mixed.is_empty()) {
        legend.entry(
            Swatch::Mark(Marker::Ring, INK),
            "minimum found inside a mixed zone",
        );
    }
    if panels.iter().any(|p| !p.drawn.certain.is_empty()) {
        legend.entry(
            Swatch::Mark(Marker::Triangle, INK),
            format!(
                "there, the lowest certain overturning (a band ≥ {} % wide)",
                fmt_num(spec.principal_relative_width * 100.0, 3)
            ),
        );
    }
    if beside {
        legend.entry(
            Swatch::Dashed(PURE_ROCKING_BOUNDARY, 2),
            "pure rocking boundary: its minimum overturning acceleration (left), drawn over the Coulomb floor's chart",
        );
    }
}

/// The legend's entries of the closed forms any of `panels` draws (eq. 21,
/// the mode-2 boundary), or a note on why eq. 21 is not drawn over `own`.
fn closed_form_entries(legend: &mut Legend, spec: &SpectrumJob, own: &Panel, panels: &[&Panel]) {
    let (x0, _) = own.drawn.x_range;
    let beta = match spec.pulse.shape() {
        PulseShape::OneCosine => "1/4",
        _ => "1/6",
    };
    if panels.iter().any(|p| !p.eq21.is_empty()) {
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
    if panels.iter().any(|p| !p.mode2_closed.is_empty()) {
        legend.entry(
            Swatch::Dashed(RGBColor(0, 130, 60), 2),
            "mode-2 boundary, corrected eq. 47 (linear closed form)",
        );
    }
}

/// The legend's notes on the spectrum's `lines` and `spec`: its mixed
/// zones, the block, the pulse, the floor, the vertical motion, the shading
/// and the axes.
fn notes(legend: &mut Legend, spec: &SpectrumJob, lines: &[FrequencyDoc]) {
    let zones: Vec<&crate::jobs::mixed::MixedDoc> = lines.iter().flat_map(|l| &l.mixed).collect();
    if !zones.is_empty() {
        legend.note(format!(
            "{} mixed zone{} at {} of {} frequencies, {} αg wide in all; elsewhere every band and safe interval is verified",
            zones.len(),
            if zones.len() == 1 { "" } else { "s" },
            lines.iter().filter(|l| !l.mixed.is_empty()).count(),
            lines.len(),
            fmt_num(zones.iter().map(|z| z.to - z.from).sum::<f64>(), 3),
        ));
    }
    legend.note(block_text(&spec.block));
    legend.note(format!(
        "{} pulse, {} formulation, {} frequenc{}",
        shape_title(spec.pulse.shape()),
        spec.formulation.name(),
        lines.len(),
        if lines.len() == 1 { "y" } else { "ies" }
    ));
    if let Some(c) = &spec.contact {
        let lift = lines
            .iter()
            .filter_map(|l| l.lift_off_above_alpha_g)
            .reduce(f64::min);
        legend.note(format!(
            "floor: Coulomb friction, μ = {}{}: the block may slide and slide-rock{}",
            fmt_num(c.mu, 4),
            if c.mu_kinetic < c.mu {
                format!(", μ_k = {}", fmt_num(c.mu_kinetic, 4))
            } else {
                String::new()
            },
            lift.map_or(String::new(), |v| format!(
                "; it leaves the floor from {} αg on some frequencies, where their lines stop",
                fmt_num(v, 4)
            ))
        ));
    }
    if let Some(v) = vertical_text(spec) {
        let lift = lines.iter().find_map(|l| l.lift_off_above_alpha_g);
        let from = if spec.vertical_ratio().is_some() {
            "rocking from"
        } else {
            "scanned from"
        };
        legend.note(format!(
            "vertical ground motion {v} (positive up): {from} {} αg{}",
            fmt_num(lines[0].threshold_alpha_g, 4),
            lift.map_or(String::new(), |v| format!(
                "; the block leaves the ground from {} αg",
                fmt_num(v, 4)
            ))
        ));
    }
    legend.note(format!(
        "shading: every overturning band of the result, those narrower than {} % of the axis drawn that tall; each frequency a cell reaching half-way to the next",
        fmt_num(MIN_VISIBLE * 100.0, 2)
    ));
    legend.note("top axis: f_p = (ω_p/p)·p/2π; right axis: a_p in g = α × a_p/(αg)");
}

/// The title of a spectrum figure.
fn title(spec: &SpectrumJob) -> String {
    format!(
        "Overturning spectrum: {} pulse, {} formulation{}",
        shape_title(spec.pulse.shape()),
        spec.formulation.name(),
        crate::jobs::vertical::ScaledVertical::of(spec.vertical.as_ref(), None).map_or(
            String::new(),
            |v| format!(", {}", crate::plot::scaled_vertical_title(&v))
        )
    )
}

/// Draws the chart of `panel` in `area`: its regions, the axes (ω_p/p and
/// f_p, αg and g), the `boundary` lines (dashed grey), the closed forms and
/// the minimum.
fn draw_chart(
    area: &Area,
    spec: &SpectrumJob,
    panel: &Panel,
    boundary: &[Vec<(f64, f64)>],
) -> Drawn {
    let p = spec.block.p;
    let a_max = panel.drawn.a_max;
    let (x0, x1) = panel.drawn.x_range;
    let mut builder = ChartBuilder::on(area);
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
        axis_range("right", 0.0, a_max * g_per_axis_unit(spec))?,
    );
    for piece in &panel.drawn.shaded {
        chart.draw_series(std::iter::once(Polygon::new(
            piece.polygon.clone(),
            fill(piece.class).filled(),
        )))?;
    }
    mesh(&mut chart, "ω_p / p", "a_p / (α g)").draw()?;
    secondary_mesh(&mut chart, "a_p (g)")
        .x_desc("pulse frequency f_p (Hz)")
        .draw()?;
    for run in boundary {
        for part in clip_y(run, 0.0, a_max) {
            chart.draw_series(DashedLineSeries::new(
                part,
                7,
                4,
                PURE_ROCKING_BOUNDARY.stroke_width(2),
            ))?;
        }
    }
    for part in clip_y(&panel.mode2_closed, 0.0, a_max) {
        chart.draw_series(DashedLineSeries::new(
            part,
            3,
            3,
            RGBColor(0, 130, 60).stroke_width(2),
        ))?;
    }
    chart.draw_series(
        panel
            .drawn
            .minimum
            .iter()
            .map(|&q| marker(q, Marker::Dot, 5, INK)),
    )?;
    chart.draw_series(
        panel
            .drawn
            .minimum_mixed
            .iter()
            .map(|&q| marker(q, Marker::Ring, 7, INK)),
    )?;
    chart.draw_series(
        panel
            .drawn
            .certain
            .iter()
            .map(|&q| marker(q, Marker::Triangle, 7, INK)),
    )?;
    // Over the computed minimum, dashed so that both show where they agree;
    // its end (ω_p/p = 3) ticked and labelled.
    for part in clip_y(&panel.eq21, 0.0, a_max) {
        chart.draw_series(DashedLineSeries::new(part, 9, 5, REFERENCE.stroke_width(3)))?;
    }
    if let Some(&end) = panel.eq21.last().filter(|e| e.1 < a_max) {
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
    Ok(())
}

/// The figure of a `spectrum` result: its chart and legend; with the
/// pure-rocking lines beside it (`no_sliding`), both charts side by side
/// ([`svg_beside`]).
pub fn svg(result: &SpectrumResult) -> Result<String, String> {
    if !result.no_sliding.is_empty() {
        return svg_beside(result);
    }
    let spec = &result.spec;
    let own = Panel::of(&result.spectrum, spec)?;
    let legend = legend(spec, &own, &[&own], false);
    render((WIDTH, HEIGHT), &title(spec), |area| -> Drawn {
        let (chart_area, side) = area.split_horizontally(WIDTH - LEGEND_WIDTH);
        draw_chart(&chart_area, spec, &own, &[])?;
        draw_legend(&side, &legend)
    })
}

/// The heading of the Coulomb floor's chart: "Coulomb floor, μ = 0.3"
/// (and μ_k when it differs).
fn floor_heading(contact: Option<&crate::jobs::contact::ContactNorm>) -> String {
    match contact {
        Some(c) if c.mu_kinetic < c.mu => format!(
            "Coulomb floor, μ = {}, μ_k = {}",
            fmt_num(c.mu, 4),
            fmt_num(c.mu_kinetic, 4)
        ),
        Some(c) => format!("Coulomb floor, μ = {}", fmt_num(c.mu, 4)),
        None => "Pure rocking (no sliding)".into(),
    }
}

/// The figure of a spectrum on a Coulomb floor beside the pure-rocking
/// spectrum of the same grid: pure rocking on the left, the floor on the
/// right with pure rocking's boundary drawn over it, both on the same axes;
/// one legend under them.
fn svg_beside(result: &SpectrumResult) -> Result<String, String> {
    let spec = &result.spec;
    let own = Panel::of(&result.spectrum, spec)?;
    let pure = Panel::of(&result.no_sliding, spec)?;
    let over = boundary(&pure);
    let legend = legend(spec, &own, &[&pure, &own], !over.is_empty());
    let headings = [
        "Pure rocking (no sliding)".to_string(),
        floor_heading(spec.contact.as_ref()),
    ];
    let charts = HEADING + BESIDE_CHARTS;
    let height =
        TITLE_AREA + charts + legend_height(&legend, BESIDE_WIDTH, BESIDE_LEGEND_COLUMNS) + 12;
    render((BESIDE_WIDTH, height), &title(spec), |area| -> Drawn {
        let (top, below) = area.split_vertically(charts);
        let (left, right) = top.split_horizontally(BESIDE_WIDTH / 2);
        for ((column, heading), (panel, over)) in [left, right]
            .iter()
            .zip(&headings)
            .zip([(&pure, &[][..]), (&own, &over[..])])
        {
            let (head, chart) = column.split_vertically(HEADING);
            head.draw(&Text::new(
                heading.clone(),
                (10 + Y_LABEL_AREA as i32 + 4, 6),
                text(LEGEND + 2, INK),
            ))?;
            draw_chart(&chart, spec, panel, over)?;
        }
        draw_legend_columns(&below.margin(6, 0, 12, 12), &legend, BESIDE_LEGEND_COLUMNS)
    })
}

/// The vertical motion of a spectrum, as its figure names it.
fn vertical_text(spec: &SpectrumJob) -> Option<String> {
    crate::jobs::vertical::ScaledVertical::of(spec.vertical.as_ref(), None)
        .map(|v| crate::plot::scaled_vertical_text(&v, spec.block.g))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::{CLASS_SAFE, Crossing, regions_of};
    use crate::kinds::JobResult;
    use crate::kinds::spectrum::{FrequencyDoc, ModeChangeDoc, SpectrumResult, TransitionDoc};
    use crate::plot::bands::MIN_VISIBLE;

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
    fn a_coulomb_floor_is_named_and_its_flights_end_no_line() {
        let r = computed(
            r#"{"kind": "spectrum", "block": {"alpha": 0.4, "p": 2.14},
                "pulse": {"type": "one_cosine"}, "omega_ratio": [2.0], "a_max_alpha_g": 10,
                "tolerance": 1e-3, "scan_step_alpha_g": 0.05,
                "contact": {"model": "coulomb", "mu": 0.6, "mu_kinetic": 0.5}}"#,
        );
        // The block leaves the floor in this range; its flights are followed.
        assert_eq!(r.spectrum[0].lift_off_above_alpha_g, None);
        // The legend wraps its notes: their words, in order, on joined lines.
        let svg = super::svg(&r).expect("svg");
        let words: Vec<&str> = svg
            .lines()
            .filter(|l| !l.trim_start().starts_with('<'))
            .flat_map(str::split_whitespace)
            .collect();
        let text = words.join(" ");
        assert!(
            text.contains("floor: Coulomb friction, μ = 0.6, μ_k = 0.5"),
            "{text}"
        );
        assert!(!text.contains("leaves the floor"), "{text}");
        assert!(!super::svg(&sample()).expect("svg").contains("floor:"));
    }

    /// The words of a figure's text, joined by single spaces (the legend
    /// wraps its labels and notes).
    fn words(svg: &str) -> String {
        svg.lines()
            .filter(|l| !l.trim_start().starts_with('<'))
            .flat_map(str::split_whitespace)
            .collect::<Vec<_>>()
            .join(" ")
    }

    #[test]
    fn the_pure_rocking_spectrum_beside_the_floor_shares_its_axes_and_boundary() {
        use crate::plot::tests::{hex, shapes, x_extent};
        let spec = r#"{"kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine"}, "omega_ratio": [3.0, 4.5, 6.0], "a_max_alpha_g": 6,
            "tolerance": 1e-3, "scan_step_alpha_g": 0.05,
            "contact": {"model": "coulomb", "mu": 0.3}, "no_sliding_beside": true}"#;
        let r = computed(spec);
        assert_eq!(r.no_sliding.len(), 3);
        let svg = super::svg(&r).expect("svg");
        let text = words(&svg);
        for needle in [
            "Pure rocking (no sliding)",
            "Coulomb floor, μ = 0.3",
            "pure rocking boundary",
            "minimum overturning acceleration",
            "floor: Coulomb friction, μ = 0.3",
        ] {
            assert!(text.contains(needle), "missing {needle:?}: {text}");
        }
        // Two charts on the same axes.
        assert_eq!(svg.matches("ω_p / p").count(), 2);
        assert_eq!(svg.matches("a_p / (α g)").count(), 2);
        let (own, pure) = (
            super::drawing(&r).expect("drawing"),
            super::drawing_of(&r.no_sliding, &r.spec).expect("drawing"),
        );
        assert_eq!((own.x_range, own.a_max), (pure.x_range, pure.a_max));
        // The boundary: pure rocking's minimum across each cell, drawn on
        // the right chart only (the legend's swatch, under the charts, left
        // out).
        let panel = super::Panel::of(&r.no_sliding, &r.spec).expect("panel");
        let steps = super::boundary(&panel);
        let levels: Vec<f64> = steps.iter().flatten().map(|p| p.1).collect();
        let minima: Vec<f64> = r
            .no_sliding
            .iter()
            .filter_map(|l| l.min_overturn_alpha_g)
            .flat_map(|a| [a, a])
            .collect();
        assert_eq!(levels, minima);
        assert_eq!(steps.len(), 1, "every frequency overturns below 6 αg");
        let stroke = format!("stroke=\"{}\"", hex(super::PURE_ROCKING_BOUNDARY));
        let charts = f64::from(super::TITLE_AREA + super::HEADING + super::BESIDE_CHARTS);
        let dashes: Vec<Vec<(f64, f64)>> = shapes(&svg, "polyline", &stroke)
            .into_iter()
            .filter(|d| d.iter().all(|p| p.1 < charts))
            .collect();
        assert!(!dashes.is_empty());
        let (left, _) = x_extent(&dashes);
        assert!(left > f64::from(super::BESIDE_WIDTH / 2), "{left}");
        // Without the pure-rocking lines, the figure of the floor alone.
        let mut alone = r.clone();
        alone.no_sliding.clear();
        let plain = computed(&spec.replace(r#", "no_sliding_beside": true"#, ""));
        assert_eq!(super::svg(&alone), super::svg(&plain));
        assert!(!super::svg(&plain).expect("svg").contains("Pure rocking"));
    }

    #[test]
    fn the_floor_chart_names_mu_and_mu_k_where_they_differ() {
        use crate::jobs::contact::ContactNorm;
        let floor = |mu: f64, mu_kinetic: f64| ContactNorm {
            model: "coulomb".into(),
            mu,
            mu_kinetic,
        };
        assert_eq!(
            super::floor_heading(Some(&floor(0.3, 0.3))),
            "Coulomb floor, μ = 0.3"
        );
        assert_eq!(
            super::floor_heading(Some(&floor(0.3, 0.25))),
            "Coulomb floor, μ = 0.3, μ_k = 0.25"
        );
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
        // Three bands per frequency, no rocking, mode 1, mode 2, each joined
        // across the three cells: one polygon each (and a legend swatch).
        let fills = [super::fill(1), super::fill(2)]
            .map(|c| format!("fill=\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2));
        for f in fills {
            assert_eq!(svg.matches(&f).count(), 1 + 1, "{f}");
        }
    }

    #[test]
    fn eq21_is_drawn_only_where_it_holds() {
        use crate::plot::style::REFERENCE;
        use crate::plot::tests::{hex, shapes, x_extent};
        let mut result = computed(include_str!(
            "../../../specs/locomotive_spectrum_nonlinear.json"
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
    fn every_band_is_a_region() {
        let t = |at: f64, up: bool, mode: u8| Crossing { at, up, mode };
        // A band 0.001 αg wide, then overturning from 1.281 αg on.
        let fine = [t(1.1, true, 1), t(1.101, false, 1), t(1.281, true, 2)];
        assert_eq!(
            regions_of(&fine, &[], 20.0),
            vec![(1.1, 1.101, 1), (1.281, 20.0, 2)]
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

    /// Whether `q` lies inside `polygon` (crossings of a ray to the right).
    fn inside(polygon: &[(f64, f64)], q: (f64, f64)) -> bool {
        let n = polygon.len();
        (0..n)
            .filter(|&k| {
                let (a, b) = (polygon[k], polygon[(k + 1) % n]);
                (a.1 > q.1) != (b.1 > q.1) && q.0 < a.0 + (q.1 - a.1) / (b.1 - a.1) * (b.0 - a.0)
            })
            .count()
            % 2
            == 1
    }

    /// Whether `polygon` has a vertical side at `x` across `y`.
    fn side_at(polygon: &[(f64, f64)], x: f64, y: f64) -> bool {
        let n = polygon.len();
        (0..n).any(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % n]);
            a.0 == x && b.0 == x && a.1.min(b.1) <= y && y <= a.1.max(b.1)
        })
    }

    #[test]
    fn cells_of_a_class_meet_without_a_gap() {
        use crate::plot::bands::cell_edges;
        let result = computed(include_str!(
            "../../../specs/locomotive_spectrum_nonlinear.json"
        ));
        let d = super::drawing(&result).expect("drawing");
        let mut columns = d.columns.clone();
        columns.sort_by(|a, b| a.x.total_cmp(&b.x));
        let xs: Vec<f64> = columns.iter().map(|c| c.x).collect();
        let edges = cell_edges(&xs, d.half);
        // Nothing between frequencies: every side level or upright, the
        // upright ones on the edges of the cells.
        let on_edge = |x: f64| edges.iter().any(|e| e.0 == x || e.1 == x);
        for piece in &d.shaded {
            let n = piece.polygon.len();
            for k in 0..n {
                let (a, b) = (piece.polygon[k], piece.polygon[(k + 1) % n]);
                assert!(a.0 == b.0 || a.1 == b.1, "a slanted side {a:?}–{b:?}");
                assert!(on_edge(a.0), "a vertex off the cells' edges: {a:?}");
            }
        }
        // Wherever a class continues across the edge of two cells, one piece
        // holds both sides, or two pieces share that edge exactly.
        let mut crossings = 0;
        let mut joined = 0;
        for (k, pair) in columns.windows(2).enumerate() {
            let x = edges[k].1;
            assert_eq!(x, edges[k + 1].0);
            let eps = 1e-6 * (pair[1].x - pair[0].x);
            for a in pair[0].bands.iter().filter(|a| a.class != CLASS_SAFE) {
                for b in pair[1].bands.iter().filter(|b| b.class == a.class) {
                    let (lo, hi) = (a.lo.max(b.lo), a.hi.min(b.hi));
                    if hi <= lo {
                        continue;
                    }
                    let y = 0.5 * (lo + hi);
                    let holder = |q: (f64, f64)| {
                        d.shaded
                            .iter()
                            .position(|p| p.class == a.class && inside(&p.polygon, q))
                    };
                    let (left, right) = (holder((x - eps, y)), holder((x + eps, y)));
                    let (Some(l), Some(r)) = (left, right) else {
                        panic!("a hole at ({x}, {y}): {left:?} {right:?}");
                    };
                    crossings += 1;
                    if l == r {
                        joined += 1;
                    } else {
                        assert!(side_at(&d.shaded[l].polygon, x, y), "left of {x}");
                        assert!(side_at(&d.shaded[r].polygon, x, y), "right of {x}");
                    }
                }
            }
        }
        assert!(crossings > 40, "{crossings}");
        assert!(joined > crossings / 2, "{joined} of {crossings} joined");
        // Far fewer pieces than cells.
        let cells: usize = columns
            .iter()
            .map(|c| c.bands.iter().filter(|b| b.class != CLASS_SAFE).count())
            .sum();
        assert!(
            d.shaded.len() * 4 < cells,
            "{} pieces, {cells} cells",
            d.shaded.len()
        );
    }

    #[test]
    fn every_minimum_lies_in_an_overturning_cell() {
        use crate::plot::bands::cell_edges;
        let result = computed(include_str!(
            "../../../specs/locomotive_spectrum_nonlinear.json"
        ));
        let d = super::drawing(&result).expect("drawing");
        let xs: Vec<f64> = d.columns.iter().map(|c| c.x).collect();
        let edges = cell_edges(&xs, d.half);
        for &(r, a) in &d.minimum {
            let k = xs
                .iter()
                .position(|x| *x == r)
                .expect("a computed frequency");
            assert!(edges[k].0 <= r && r <= edges[k].1);
            let cell = d.columns[k]
                .bands
                .iter()
                .find(|b| super::overturns(b.class) && b.lo <= a && a <= b.hi);
            assert!(
                cell.is_some_and(|c| c.hi - c.lo >= MIN_VISIBLE * d.a_max - 1e-12),
                "ω_p/p = {r}, {a} αg in {:?}",
                d.columns[k].bands
            );
        }
        // Among them a minimum whose band is far narrower than a pixel (the
        // locomotive at ω_p/p = 0.25, just above 1.046 αg).
        let narrow = result.spectrum.iter().any(|l| {
            super::frequency_regions(l, d.a_max)
                .first()
                .is_some_and(|r| {
                    Some(r.0) == l.min_overturn_alpha_g && r.1 - r.0 < d.a_max / 1000.0
                })
        });
        assert!(narrow, "a narrow lowest band");
    }

    /// Tick labels of an axis: (y px, value).
    type Ticks = Vec<(f64, f64)>;

    /// Tick labels of the left (anchored at their end) and right (at their
    /// start, left of the legend) axes of a figure: (y px, value).
    fn y_ticks(svg: &str) -> (Ticks, Ticks) {
        let attr = |tag: &str, name: &str| -> Option<String> {
            Some(
                tag.split(&format!(" {name}=\""))
                    .nth(1)?
                    .split('"')
                    .next()?
                    .to_string(),
            )
        };
        let legend_left = f64::from(super::WIDTH - super::LEGEND_WIDTH);
        let (mut left, mut right) = (Vec::new(), Vec::new());
        for rest in svg.split("<text").skip(1) {
            let Some((tag, body)) = rest.split_once('>') else {
                continue;
            };
            let Some(label) = body.split("</text>").next() else {
                continue;
            };
            let (Some(x), Some(y), Some(anchor)) =
                (attr(tag, "x"), attr(tag, "y"), attr(tag, "text-anchor"))
            else {
                continue;
            };
            let (Ok(x), Ok(y), Ok(v)) = (
                x.parse::<f64>(),
                y.parse::<f64>(),
                label.trim().parse::<f64>(),
            ) else {
                continue;
            };
            if tag.contains("rotate") {
                continue;
            }
            match anchor.as_str() {
                "end" if x < 150.0 => left.push((y, v)),
                "start" if x > 150.0 && x < legend_left => right.push((y, v)),
                _ => {}
            }
        }
        (left, right)
    }

    /// The right axis of a figure as drawn reads its left axis × `factor`:
    /// each right tick label is the left axis' value at its height times
    /// `factor`, to two pixels (each axis rounds its ticks to a pixel) and
    /// the label's four digits.
    pub(crate) fn assert_right_axis_is_left_times(svg: &str, factor: f64) {
        let (left, right) = y_ticks(svg);
        assert!(left.len() >= 3 && right.len() >= 3, "{left:?} {right:?}");
        // The left axis as drawn: value = v0 + slope × (y − y0).
        let (a, b) = (left[0], left[left.len() - 1]);
        let slope = (b.1 - a.1) / (b.0 - a.0);
        let at = |y: f64| a.1 + slope * (y - a.0);
        for &(y, v) in &left {
            assert!((at(y) - v).abs() <= slope.abs(), "left {v} at {y}");
        }
        for &(y, r) in &right {
            let expected = factor * at(y);
            assert!(
                (r - expected).abs() <= 2.0 * (factor * slope).abs() + 5e-4 * r.abs(),
                "right {r} at {y}: {expected}"
            );
        }
    }

    #[test]
    fn the_right_axis_reads_the_left_in_g() {
        for (text, a_max_g) in [
            (
                include_str!("../../../specs/locomotive_spectrum_nonlinear.json"),
                None,
            ),
            (
                r#"{"kind": "spectrum", "block": {"alpha": 0.15, "p": 3.0}, "pulse": {"type": "one_cosine"},
                    "formulation": "linear", "frequency_hz": [0.5, 1.0], "a_max_g": 1.2}"#,
                Some(1.2),
            ),
        ] {
            let result = computed(text);
            let factor = super::g_per_axis_unit(&result.spec);
            assert_eq!(factor, result.spec.block.alpha);
            // The result's own conversion: a transition's g over its αg.
            let t = result
                .spectrum
                .iter()
                .flat_map(|l| &l.transitions)
                .next()
                .expect("a transition");
            assert!((t.a_g - factor * t.a_alpha_g).abs() < 1e-12);
            assert_right_axis_is_left_times(&super::svg(&result).expect("svg"), factor);
            // A highest amplitude given in g tops the right axis.
            if let Some(g) = a_max_g {
                let d = super::drawing(&result).expect("drawing");
                assert!((d.a_max * factor - g).abs() < 1e-12, "{}", d.a_max * factor);
            }
        }
    }
}
