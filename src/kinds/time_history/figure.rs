//! Time histories (paper Figs. 7–8): ground acceleration ü_g/g, rotation
//! θ/α, angular velocity θ̇/p and the friction demand f_x/f_z in stacked
//! panels over time; the pulse (or the recorded ground motion) shaded,
//! impacts ticked, overturning or coming to rest marked.
//!
//! A short pulse followed by a long history (the pulse under a quarter of
//! it) gets two columns: at left the pulse and the first impacts, at right
//! the whole history. Under a record the time axis runs to the record's end
//! whenever the block stopped: a block at rest for good stays drawn at rest
//! (θ = 0, its friction demand ü_g/g) to the end, and when it stopped early
//! a column at left shows its response larger. A window draws the span asked
//! for instead.
//!
//! On a Coulomb floor a band along each time axis shades the block's modes
//! (rocking, sliding, slide-rocking, flight; sticking unshaded), and a panel
//! gives the base's slip: at each sample of a series, marked at each change
//! of mode; without a series at the changes only, joined by a dashed line.

use plotters::prelude::*;

use super::motion::{Motion, Vertical};
use crate::dynamics::Formulation;
use crate::jobs::contact::{ContactNorm, ModeDoc};
use crate::kinds::time_history::{SeriesDoc, TimeHistoryJob, TimeHistoryResult};
use crate::plot::style::{
    Area, Drawn, INK, LEGEND, Legend, MUTED, Marker, PULSE, REST, Swatch, draw_legend_columns,
    fmt_num, legend_height, mode_colour, text, tint,
};
use crate::plot::time_panel::{
    Band, End, Mark, Panel, Place, Scale, Shared, Span, ZOOMED, crop, draw_panel,
};
use crate::plot::window::Window;
use crate::plot::{block_text, render, shape_title};

const WIDTH: u32 = 1120;
const TITLE_AREA: u32 = 44;
const HEADING: u32 = 34;
const X_AXIS: u32 = 58;
/// Height of the stacked panels together (each at least `MIN_PANEL`).
const PANELS_HEIGHT: u32 = 600;
const MIN_PANEL: u32 = 150;
/// Legend columns under the panels.
const LEGEND_COLUMNS: usize = 3;
/// Width of the y labels of the first column (with the axis description)
/// and of the second (ticks only), px.
const Y_LABELS: (u32, u32) = (92, 62);
/// Share of the width the zoomed column takes.
const ZOOM_SHARE: f64 = 0.56;
/// A pulse shorter than this fraction of the history gets a zoomed column.
const ZOOM_BELOW: f64 = 0.25;
/// The zoomed column shows at most this many impacts …
const FIRST_IMPACTS: usize = 3;
/// … of those within this many pulse durations.
const IMPACT_REACH: f64 = 4.0;
/// A zoom reaching past this fraction of the history is no zoom.
const ZOOM_AT_MOST: f64 = 0.6;
/// Under a record, the block's response gets a column of its own when it
/// ends (with a margin) before this fraction of the record.
const RESPONSE_AT_MOST: f64 = 0.35;

/// Colour of the friction demand.
const RATIO: RGBColor = RGBColor(150, 80, 20);
/// Colour of the ground acceleration.
const GROUND: RGBColor = RGBColor(90, 90, 90);
/// Colour of the rotation.
const THETA: RGBColor = RGBColor(31, 78, 160);
/// Colour of the vertical ground acceleration.
const VERTICAL: RGBColor = RGBColor(120, 70, 150);
/// Axis description of the vertical ground acceleration's panel.
const VERTICAL_DESC: &str = "ü_v / g";
/// A vertical ground acceleration down to −`FALLING` g has its panel
/// show the level −g (where the ground falls away).
const FALLING: f64 = 0.5;
/// Colour of the base's slip.
const SLIP: RGBColor = RGBColor(175, 55, 30);
/// Axis description of the slip's panel.
const SLIP_DESC: &str = "slip (m)";
/// The modes of a block on a Coulomb floor, in the order the legend lists them.
const MODES: [&str; 5] = ["stick", "rock", "slide", "slide_rock", "flight"];

/// What the figure asks of a result without a series.
pub const NO_SERIES: &str = "no series in this result: add \"outputs\": {\"series\": 500} to the spec for θ(t), θ̇(t) and f_x/f_z(t)";
/// What the figure says of a history on a Coulomb floor without a series.
pub const NO_SERIES_COULOMB: &str = "no series in this result: its modes, its impacts and the slip at each change of mode are drawn";

/// How a mode of a block on a Coulomb floor shows in the band along the
/// time axis: its fill (none while it sticks) and its legend label.
fn mode_band(mode: &str) -> (Option<RGBColor>, String) {
    match mode {
        "stick" => (None, "sticking (no band along the time axis)".into()),
        "rock" => (Some(tint(RGBColor(86, 180, 233), 0.55)), "rocking".into()),
        "slide" => (Some(tint(RGBColor(213, 94, 0), 0.45)), "sliding".into()),
        "slide_rock" => (
            Some(tint(RGBColor(204, 121, 167), 0.7)),
            "sliding while rocking (slide-rock)".into(),
        ),
        "flight" => (
            Some(tint(RGBColor(0, 158, 115), 0.5)),
            "in flight (off the floor)".into(),
        ),
        other => (Some(tint(MUTED, 0.4)), other.replace('_', " ")),
    }
}

/// The base's slip on the floor where the result knows it: at the start of
/// the first mode and at each change of mode after it, (t, m).
fn slip_at_changes(modes: &[ModeDoc]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(modes.len() + 1);
    for m in modes {
        let start = (m.from, m.slide_from_m);
        if out.last() != Some(&start) {
            out.push(start);
        }
        out.push((m.to, m.slide_to_m));
    }
    out.retain(|q| q.0.is_finite() && q.1.is_finite());
    out
}

/// "towards +x" or "towards −x", the way `value` points (None at 0).
fn towards(value: f64) -> Option<&'static str> {
    if value > 0.0 {
        Some("towards +x")
    } else if value < 0.0 {
        Some("towards −x")
    } else {
        None
    }
}

/// The notes of a history on the Coulomb floor `contact`: the friction, how
/// the block first moved, its slip, the side it overturned to.
fn coulomb_notes(result: &TimeHistoryResult, contact: &ContactNorm) -> Vec<String> {
    let mut notes = vec![crate::plot::floor_note(contact)];
    if result.answered_by.as_deref() == Some("pure_rocking") {
        notes.push(
            "the friction pure rocking needs never exceeds μ: the block rocks without sliding"
                .into(),
        );
    }
    notes.push(match result.initial_mode.as_deref() {
        None => "the block never moved".into(),
        Some("rock") => "it first moved by rocking".into(),
        Some("slide") => "it first moved by sliding".into(),
        Some("slide_rock") => "it first moved by sliding while rocking".into(),
        Some("flight") => "it first moved by leaving the floor".into(),
        Some(other) => format!("it first moved by {}", other.replace('_', " ")),
    });
    if let (Some(peak), Some(residual)) = (result.peak_slide_m, result.residual_slide_m) {
        if peak > 0.0 {
            let way = towards(residual).map_or(String::new(), |w| format!(" ({w})"));
            let time = result.time_sliding_s.map_or(String::new(), |t| {
                format!(", {} s sliding or slide-rocking", fmt_num(t, 3))
            });
            notes.push(format!(
                "slip of the base: peak |slip| = {} m, residual {} m{way}{time}",
                fmt_num(peak, 3),
                fmt_num(residual, 3)
            ));
        } else {
            notes.push("the base never slipped".into());
        }
    }
    if let (Some(n), Some(t)) = (result.flights, result.time_in_flight_s)
        && n > 0
    {
        let times = if n == 1 {
            "once".to_string()
        } else {
            format!("{n} times")
        };
        notes.push(format!(
            "left the floor {times}, {} s in the air",
            fmt_num(t, 3)
        ));
    }
    if result.overturned
        && let Some(side) = result.overturn_direction.and_then(towards)
    {
        notes.push(format!("overturned {side}"));
    }
    notes
}

/// The end of a span showing the pulse (lasting `duration`) and the first
/// impacts, when the pulse takes less than a quarter of a history ending at
/// `t_end`; `None` when the whole history reads well enough.
pub fn zoom_end(duration: f64, impacts: &[f64], t_end: f64) -> Option<f64> {
    if !(duration > 0.0 && t_end.is_finite() && duration < ZOOM_BELOW * t_end) {
        return None;
    }
    let end = impacts
        .iter()
        .copied()
        .take_while(|t| *t <= IMPACT_REACH * duration)
        .take(FIRST_IMPACTS)
        .fold(1.5 * duration, f64::max);
    let end = (1.1 * end).min(t_end);
    (end < ZOOM_AT_MOST * t_end).then_some(end)
}

/// The end of a span showing the block's response under a record lasting
/// `record_end`, when the block stopped (came to rest for good or
/// overturned) at `stopped`, early enough that the whole record would
/// squeeze it; `None` when the whole record reads well enough.
pub fn response_end(stopped: f64, record_end: f64) -> Option<f64> {
    let end = 1.1 * stopped;
    (stopped > 0.0 && record_end.is_finite() && end < RESPONSE_AT_MOST * record_end).then_some(end)
}

/// `line` continued from its last point to `to` by `after` (points later
/// than the last; ordered in time).
fn continued(mut line: Vec<(f64, f64)>, after: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let last = line.last().map_or(f64::NEG_INFINITY, |p| p.0);
    line.extend(after.iter().copied().filter(|p| p.0 > last));
    line
}

/// The f_x/f_z series cut where it stops meaning anything, with that end:
/// at lift-off (f_z = 0, where the series turns null and the demand is
/// unbounded) or where the block is bound to overturn (its fall is not
/// counted), whichever comes first.
fn friction_demand(
    ratio: &[(f64, f64)],
    result: &TimeHistoryResult,
) -> (Vec<(f64, f64)>, Option<End>) {
    let lift_off = result.lift_off_time;
    let bound = result.friction_demand_followed_until;
    let stop = [lift_off, bound]
        .into_iter()
        .flatten()
        .fold(f64::INFINITY, f64::min);
    let defined: Vec<(f64, f64)> = ratio
        .iter()
        .copied()
        .take_while(|p| p.1.is_finite())
        .collect();
    let Some(&(first, _)) = defined.first() else {
        return (defined, None);
    };
    let line = crop(&defined, first, stop);
    let cut_by_null = defined.len() < ratio.len();
    let Some(&(t, value)) = line.last() else {
        return (line, None);
    };
    let label = match (lift_off, bound) {
        (Some(tl), _) if tl <= stop => "lift-off: f_z = 0".to_string(),
        (_, Some(_)) => "bound to overturn".to_string(),
        _ if cut_by_null => "f_z = 0".to_string(),
        _ => return (line, None),
    };
    (line, Some(End { t, value, label }))
}

/// `line` broken at each of `times` (ordered): f_x/f_z jumps at an impact,
/// where θ and with it the rocking corner change sides, and a line drawn
/// through the jump would be a demand that never was.
fn broken_at(line: &[(f64, f64)], times: &[f64]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(line.len() + times.len());
    let mut next = times.iter().peekable();
    for &p in line {
        while let Some(&&t) = next.peek() {
            if t > p.0 {
                break;
            }
            if out.last().is_some_and(|q: &(f64, f64)| q.0 < t) {
                out.push((t, f64::NAN));
            }
            next.next();
        }
        out.push(p);
    }
    out
}

/// What the figure reads of a time history beside its curves: the block,
/// the ground motion, how long the history runs, its impacts and modes.
struct History<'a> {
    result: &'a TimeHistoryResult,
    spec: &'a TimeHistoryJob,
    alpha: f64,
    p: f64,
    g: f64,
    mu: Option<f64>,
    linear: bool,
    motion: Option<Motion>,
    vertical: Option<Vertical>,
    series: Option<&'a SeriesDoc>,
    /// The series' times (none without a series), s.
    t: &'a [f64],
    /// The end of the history simulated (1 s when it has none).
    simulated: f64,
    /// Under a record, its end (or its vertical's, if later), s.
    record_end: Option<f64>,
    /// The end of the time axis, s.
    t_end: f64,
    /// The block at rest for good from then on (not after overturning).
    at_rest_from: Option<f64>,
    /// (t, θ̇ before, θ̇ after) of each impact listed.
    impacts: Vec<(f64, f64, f64)>,
    /// The times of the impacts listed, s.
    impact_times: Vec<f64>,
    /// Ground acceleration reaches the rocking threshold at g tan α (α g
    /// linearised), in g.
    threshold: f64,
    /// On a Coulomb floor with μ < tan α a block at rest starts to slide at
    /// μ g, before it could rock (without a vertical motion).
    sliding_level: Option<f64>,
    /// The modes of a block on a Coulomb floor (none elsewhere).
    modes: &'a [ModeDoc],
    /// The base's slip at each change of mode.
    slip: Vec<(f64, f64)>,
    /// Under a record, its peak |ü_g|, m/s².
    record_peak: Option<f64>,
}

impl<'a> History<'a> {
    fn of(result: &'a TimeHistoryResult) -> History<'a> {
        let spec = &result.spec;
        let alpha = spec.block.alpha;
        let linear = spec.formulation == Formulation::Linear;
        let motion = Motion::of(spec);
        let vertical = Vertical::of(spec);
        let series = result.series.as_ref();
        let simulated = Some(result.end_time)
            .filter(|t| *t > 0.0 && t.is_finite())
            .unwrap_or(1.0);
        // Under a record the axis runs to its end, however early the block
        // stopped: the record did not end there.
        let record_end = match (&motion, &vertical) {
            (Some(m @ Motion::Record { .. }), Some(v)) => Some(m.duration().max(v.end(m))),
            (Some(m @ Motion::Record { .. }), None) => Some(m.duration()),
            _ => None,
        };
        let impacts: Vec<(f64, f64, f64)> = result
            .impacts
            .iter()
            .flatten()
            .map(|i| (i.t, i.theta_dot_before, i.theta_dot_after))
            .collect();
        let sliding_level = spec
            .contact
            .as_ref()
            .map(|c| c.mu)
            .filter(|m| vertical.is_none() && *m < alpha.tan());
        let modes: &[ModeDoc] = result.modes.as_deref().unwrap_or(&[]);
        let record_peak = match &motion {
            Some(m @ Motion::Record { .. }) => Some(m.peak()),
            _ => None,
        };
        History {
            result,
            spec,
            alpha,
            p: spec.block.p,
            g: spec.block.g,
            mu: spec.block.mu,
            linear,
            series,
            t: series.map_or(&[], |s| &s.t),
            simulated,
            record_end,
            t_end: record_end.map_or(simulated, |r| r.max(simulated)),
            at_rest_from: result.rest_time.filter(|_| !result.overturned),
            impact_times: impacts.iter().map(|i| i.0).collect(),
            impacts,
            threshold: if linear { alpha } else { alpha.tan() },
            sliding_level,
            modes,
            slip: slip_at_changes(modes),
            record_peak,
            motion,
            vertical,
        }
    }

    /// The series `v` against its times, divided by `scale`.
    fn sampled(&self, v: &[f64], scale: f64) -> Vec<(f64, f64)> {
        self.t.iter().zip(v).map(|(&t, v)| (t, v / scale)).collect()
    }

    /// The levels of the ground acceleration's panel: ± the rocking
    /// threshold and, where the block slides first, ± μ.
    fn ground_refs(&self) -> Vec<f64> {
        let mut refs = vec![self.threshold, -self.threshold];
        refs.extend(self.sliding_level.iter().flat_map(|m| [*m, -*m]));
        refs
    }
}

/// The end of the zoomed column, if the figure has one: the block's
/// response under a record, the pulse and its first impacts under a pulse
/// (none over a window).
fn zoom(h: &History, window: Option<Window>) -> Option<f64> {
    match (window, &h.motion) {
        (Some(_), _) | (None, None) => None,
        (None, Some(Motion::Record { .. })) => response_end(h.simulated, h.t_end),
        (None, Some(m)) => zoom_end(m.duration(), &h.impact_times, h.t_end),
    }
}

/// The spans drawn, one column each, with their headings: the window, or
/// the zoomed span and the whole history, or the whole history alone
/// (without a heading).
fn spans(h: &History, window: Option<Window>, zoom: Option<f64>) -> Vec<(Span, String)> {
    let t_end = h.t_end;
    let (zoom_heading, whole_heading) = if h.record_end.is_some() {
        ("the block's response", "the whole record")
    } else {
        ("the pulse and first impacts", "the whole history")
    };
    match (window, zoom) {
        (Some(w), _) => vec![(
            Span {
                t0: w.start(),
                t1: w.end(),
                zoomed: None,
            },
            format!(
                "t = {}–{} s (the history runs 0–{} s)",
                fmt_num(w.start(), 4),
                fmt_num(w.end(), 4),
                fmt_num(t_end, 4)
            ),
        )],
        (None, Some(z)) => vec![
            (
                Span {
                    t0: 0.0,
                    t1: z,
                    zoomed: None,
                },
                format!("{zoom_heading}, t = 0–{} s", fmt_num(z, 3)),
            ),
            (
                Span {
                    t0: 0.0,
                    t1: t_end,
                    zoomed: Some((0.0, z)),
                },
                format!("{whole_heading}, t = 0–{} s", fmt_num(t_end, 4)),
            ),
        ],
        (None, None) => vec![(
            Span {
                t0: 0.0,
                t1: t_end,
                zoomed: None,
            },
            String::new(),
        )],
    }
}

/// The ground's accelerations from the spec's motion over the time drawn,
/// in g: none without a motion, the vertical one only under a vertical
/// motion.
struct GroundCurves {
    horizontal: Option<Vec<(f64, f64)>>,
    vertical: Option<Vec<(f64, f64)>>,
}

impl GroundCurves {
    fn of(h: &History, from: f64, to: f64) -> GroundCurves {
        GroundCurves {
            horizontal: h.motion.as_ref().map(|m| m.curve(from, to, h.g)),
            // ü_v/g from the spec (as ü_g), else from the series.
            vertical: match (&h.motion, &h.vertical) {
                (Some(m), Some(v)) => Some(v.curve(m, from, to, h.g)),
                _ => None,
            },
        }
    }
}

/// The panels of the figure, with what its legend says of them.
struct Panels {
    list: Vec<Panel>,
    /// The largest |f_x/f_z| when its curve leaves the panel.
    clipped_ratio: Option<f64>,
    /// Where the f_x/f_z curve stops on purpose.
    ratio_end: Option<End>,
}

/// The panels of the figure over the time drawn (to `to`): those of the
/// series, or without one those of the ground motion and the impacts; then
/// the base's slip on a Coulomb floor.
fn panels(h: &History, to: f64, curves: GroundCurves) -> Result<Panels, String> {
    let mut panels = match h.series.filter(|_| !h.t.is_empty()) {
        Some(s) => series_panels(h, s, curves, to),
        None => {
            let list = motion_panels(h, curves);
            if list.is_empty() && h.slip.is_empty() {
                return Err(format!(
                    "nothing to draw: {NO_SERIES} (the result has no impacts and its spec no ground motion)"
                ));
            }
            Panels {
                list,
                clipped_ratio: None,
                ratio_end: None,
            }
        }
    };
    panels.list.extend(slip_panel(h, slip_line(h, to)));
    Ok(panels)
}

/// The series' curves in the panels' units; once the block is at rest for
/// good, held still to the end of what is drawn (`to`).
struct Sampled {
    /// ü_g/g, from the spec's motion where it has one.
    ground: Vec<(f64, f64)>,
    /// θ/α.
    theta: Vec<(f64, f64)>,
    /// θ̇/p.
    theta_dot: Vec<(f64, f64)>,
    /// f_x/f_z, NaN where f_z ≤ 0.
    ratio: Vec<(f64, f64)>,
}

impl Sampled {
    fn of(
        h: &History,
        s: &SeriesDoc,
        ground_from_motion: Option<&Vec<(f64, f64)>>,
        to: f64,
    ) -> Sampled {
        let ground = ground_from_motion
            .cloned()
            .unwrap_or_else(|| h.sampled(&s.ground_acceleration, h.g));
        let mut theta = h.sampled(&s.theta, h.alpha);
        let mut theta_dot = h.sampled(&s.theta_dot, h.p);
        // Null where f_z ≤ 0: NaN, so that the line stops there.
        let fx_over_fz: Vec<f64> = s
            .fx_over_fz
            .iter()
            .flatten()
            .map(|v| v.unwrap_or(f64::NAN))
            .collect();
        let mut ratio = h.sampled(&fx_over_fz, 1.0);
        // At rest for good the block stays still to the end of what is
        // drawn, its friction demand f_x/f_z = ü_g/g (the series' own at rest).
        if let Some(tr) = h.at_rest_from {
            let still = [(tr, 0.0), (to, 0.0)];
            theta = continued(theta, &still);
            theta_dot = continued(theta_dot, &still);
            if !ratio.is_empty() {
                let demand = ground_from_motion.map_or(still.to_vec(), |g| crop(g, tr, to));
                ratio = continued(ratio, &demand);
            }
        }
        Sampled {
            ground,
            theta,
            theta_dot,
            ratio,
        }
    }
}

/// The panels of a history with a series: ü_g/g, ü_v/g under a vertical
/// motion, θ/α, θ̇/p and f_x/f_z (those the series has).
fn series_panels(h: &History, s: &SeriesDoc, curves: GroundCurves, to: f64) -> Panels {
    let sampled = Sampled::of(h, s, curves.horizontal.as_ref(), to);
    let mut list = Vec::new();
    if !sampled.ground.is_empty() {
        list.push(ground_panel(
            h,
            sampled.ground,
            "ground acceleration ü_g/g".into(),
        ));
    }
    let vertical_line = curves.vertical.or_else(|| {
        s.ground_vertical_acceleration
            .as_deref()
            .map(|v| h.sampled(v, h.g))
    });
    if let Some(line) = vertical_line.filter(|l| !l.is_empty()) {
        list.push(vertical_panel(line, ""));
    }
    list.push(Panel {
        refs: vec![1.0, -1.0],
        impacts: true,
        ..Panel::curve(
            "θ / α",
            format!("rotation θ/α (α = {} rad)", fmt_num(h.alpha, 3)),
            THETA,
            sampled.theta,
            Scale::Symmetric { floor: 1.25 },
        )
    });
    if !sampled.theta_dot.is_empty() {
        list.push(Panel::curve(
            "θ̇ / p",
            format!("angular velocity θ̇/p (p = {} rad/s)", fmt_num(h.p, 3)),
            RGBColor(0, 120, 120),
            sampled.theta_dot,
            Scale::Symmetric { floor: 0.1 },
        ));
    }
    let mut clipped_ratio = None;
    let mut ratio_end = None;
    if !sampled.ratio.is_empty() {
        let (panel, clipped) = friction_panel(h, &sampled.ratio);
        clipped_ratio = clipped;
        ratio_end.clone_from(&panel.end);
        list.push(panel);
    }
    Panels {
        list,
        clipped_ratio,
        ratio_end,
    }
}

/// The panel of the ground acceleration ü_g/g, labelled `label`.
fn ground_panel(h: &History, line: Vec<(f64, f64)>, label: String) -> Panel {
    Panel {
        refs: h.ground_refs(),
        ..Panel::curve(
            "ü_g / g",
            label,
            GROUND,
            line,
            Scale::Symmetric {
                floor: h.threshold * 1.3,
            },
        )
    }
}

/// The panel of the vertical ground acceleration ü_v/g, its label ended by
/// `label`.
fn vertical_panel(line: Vec<(f64, f64)>, label: &str) -> Panel {
    // ü_v = −g, where the ground falls away and the block leaves it,
    // is shown once the ground falls at half that.
    let falls = line.iter().any(|p| p.1 <= -FALLING);
    Panel {
        refs: if falls { vec![-1.0] } else { Vec::new() },
        ..Panel::curve(
            VERTICAL_DESC,
            format!("vertical ground acceleration ü_v/g, positive up{label}"),
            VERTICAL,
            line,
            Scale::Symmetric {
                floor: if falls { 1.1 } else { 0.1 },
            },
        )
    }
}

/// The panel of the friction demand f_x/f_z of the series (`ratio`), with
/// the largest |f_x/f_z| when its curve leaves the panel.
fn friction_panel(h: &History, ratio: &[(f64, f64)]) -> (Panel, Option<f64>) {
    let result = h.result;
    let alpha = h.alpha;
    let (line, end) = friction_demand(ratio, result);
    let line = broken_at(&line, &h.impact_times);
    // Close to lift-off f_z is small and the demand large: the range
    // follows the peak demand while rocking, or, when the block lifts
    // off, twice the demand when rocking starts.
    let largest = line
        .iter()
        .map(|q| q.1.abs())
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    let scale = result
        .peak_friction_demand
        .or_else(|| {
            result
                .lift_off_time
                .and(result.initiation_friction_demand)
                .map(|d| 2.0 * d)
        })
        .unwrap_or(largest)
        .max(h.threshold.max(h.mu.unwrap_or(0.0)));
    let (floor, cap) = (alpha.tan() * 1.3, scale * 1.3);
    let clipped = (largest * 1.12 > cap.max(floor)).then_some(largest);
    let mut refs = vec![alpha.tan(), -alpha.tan()];
    refs.extend(h.mu.iter().flat_map(|m| [*m, -*m]));
    let panel = Panel {
        refs,
        end,
        ..Panel::curve(
            "f_x / f_z",
            "friction demand f_x/f_z",
            RATIO,
            line,
            Scale::Capped { floor, cap },
        )
    };
    (panel, clipped)
}

/// The panels of a history without a series: the ground's accelerations
/// from the spec's motion, and θ̇/p before and after each impact.
fn motion_panels(h: &History, curves: GroundCurves) -> Vec<Panel> {
    let mut list = Vec::new();
    if let (Some(motion), Some(ground)) = (&h.motion, curves.horizontal) {
        let label = match motion {
            Motion::Pulse(_) => "ground acceleration ü_g/g (from the pulse)",
            Motion::Record { .. } => "ground acceleration ü_g/g (the record)",
        };
        list.push(ground_panel(h, ground, label.into()));
    }
    if let (Some(motion), Some(line)) = (&h.motion, curves.vertical) {
        list.push(vertical_panel(
            line,
            match motion {
                Motion::Pulse(_) => " (from the spec)",
                Motion::Record { .. } => " (the record)",
            },
        ));
    }
    if !h.impacts.is_empty() {
        let mut points = Vec::new();
        for &(t, before, after) in &h.impacts {
            points.push(((t, before / h.p), Marker::Ring));
            points.push(((t, after / h.p), Marker::Dot));
        }
        list.push(Panel {
            points,
            impacts: true,
            ..Panel::curve(
                "θ̇ / p at impacts",
                "θ̇/p before (○) and after (●) each impact",
                RGBColor(0, 120, 120),
                Vec::new(),
                Scale::Symmetric { floor: 0.05 },
            )
        });
    }
    list
}

/// The base's slip at each sample, where the series has it (on a Coulomb
/// floor): kept still to the end of what is drawn (`to`) once the block is
/// at rest for good.
fn slip_line(h: &History, to: f64) -> Vec<(f64, f64)> {
    h.series
        .and_then(|s| s.slide_m.as_deref())
        .map(|slide| {
            let line: Vec<(f64, f64)> = h.t.iter().copied().zip(slide.iter().copied()).collect();
            match (h.at_rest_from, line.last()) {
                (Some(tr), Some(&(_, last))) => continued(line, &[(tr, last), (to, last)]),
                _ => line,
            }
        })
        .unwrap_or_default()
}

/// The panel of the base's slip on a Coulomb floor: the `slip_line` of the
/// series marked at each change of mode, or without one the slip at the
/// changes only, joined by a dashed line; none when the slip is unknown.
fn slip_panel(h: &History, slip_line: Vec<(f64, f64)>) -> Option<Panel> {
    let points = || h.slip.iter().map(|&q| (q, Marker::Dot)).collect();
    let scale = Scale::Symmetric { floor: 0.01 };
    if !slip_line.is_empty() {
        // A marker between two stretches of one mode: the base slides the
        // other way from there.
        let reversals = h
            .modes
            .windows(2)
            .any(|w| w[0].mode == w[1].mode && w[0].direction != w[1].direction);
        let label = format!(
            "slip of the base on the floor (m, + towards +x); ● at each change of mode{}",
            if reversals {
                " or of the way it slides"
            } else {
                ""
            }
        );
        Some(Panel {
            points: points(),
            ..Panel::curve(SLIP_DESC, label, SLIP, slip_line, scale)
        })
    } else if !h.slip.is_empty() {
        Some(Panel {
            dashed: true,
            points: points(),
            ..Panel::curve(
                SLIP_DESC,
                "slip at mode changes (m, + towards +x): the base's slip on the floor, known at the markers only; the dashed line joins them",
                SLIP,
                h.slip.clone(),
                scale,
            )
        })
    } else {
        None
    }
}

/// The legend of the figure and the lines marked across its panels.
fn legend(h: &History, zoom: Option<f64>, panels: &Panels) -> (Legend, Vec<Mark>) {
    let mut legend = Legend::default();
    motion_entries(&mut legend, h, zoom);
    mode_entries(&mut legend, h.modes);
    panel_entries(&mut legend, &panels.list);
    if let Some(end) = &panels.ratio_end {
        legend.entry(
            Swatch::Mark(Marker::Ring, RATIO),
            match end.label.as_str() {
                "bound to overturn" => format!(
                    "f_x/f_z stops at t = {} s: the block is bound to overturn (its fall is not counted)",
                    fmt_num(end.t, 4)
                ),
                _ => format!(
                    "f_x/f_z stops at t = {} s: lift-off, f_z = 0 (the demand is unbounded)",
                    fmt_num(end.t, 4)
                ),
            },
        );
    }
    legend.entry(
        Swatch::Dashed(MUTED, 1),
        format!("levels: {}", levels(h, &panels.list).join("; ")),
    );
    if !h.impacts.is_empty() {
        legend.entry(
            Swatch::Mark(Marker::Tick, INK),
            format!("impact ({} listed)", h.impacts.len()),
        );
    }
    let marks = ending(&mut legend, h);
    legend.note(block_text(&h.spec.block));
    motion_notes(&mut legend, h);
    legend.note(format!(
        "{} formulation, solver {}",
        h.spec.formulation.name(),
        h.spec.solver.method.name()
    ));
    if let Some(contact) = &h.spec.contact {
        for note in coulomb_notes(h.result, contact) {
            legend.note(note);
        }
    }
    outcome_notes(&mut legend, h, panels.clipped_ratio);
    (legend, marks)
}

/// The legend's entries of the ground motion shaded and of the span drawn
/// larger at left (ending at `zoom`).
fn motion_entries(legend: &mut Legend, h: &History, zoom: Option<f64>) {
    match &h.motion {
        Some(m @ Motion::Pulse(_)) => legend.entry(
            Swatch::Fill(PULSE),
            format!("pulse: 0 ≤ t ≤ {} s", fmt_num(m.duration(), 3)),
        ),
        Some(m @ Motion::Record { .. }) => legend.entry(
            Swatch::Fill(PULSE),
            format!("ground motion: 0 ≤ t ≤ {} s", fmt_num(m.duration(), 4)),
        ),
        None => {}
    }
    if let Some(z) = zoom {
        legend.entry(
            Swatch::Fill(ZOOMED),
            format!("0–{} s, drawn larger at left", fmt_num(z, 3)),
        );
    }
}

/// The legend's entries of the modes that occur, each with its fill in the
/// band along the time axis, in the order of [`MODES`].
fn mode_entries(legend: &mut Legend, modes: &[ModeDoc]) {
    let mut occurring: Vec<&str> = Vec::new();
    for m in modes {
        if !occurring.contains(&m.mode.as_str()) {
            occurring.push(&m.mode);
        }
    }
    occurring.sort_by_key(|m| MODES.iter().position(|k| k == m).unwrap_or(MODES.len()));
    for name in occurring {
        let (fill, label) = mode_band(name);
        let swatch = fill.map_or(Swatch::Boxed(WHITE, MUTED), Swatch::Fill);
        legend.entry(swatch, format!("mode: {label}"));
    }
}

/// The legend's entry of each panel: its curve, its markers or both.
fn panel_entries(legend: &mut Legend, panels: &[Panel]) {
    for panel in panels {
        let swatch = if panel.dashed {
            Swatch::DashedMark(panel.colour, Marker::Dot)
        } else if panel.line.is_empty() {
            Swatch::Mark(Marker::Dot, panel.colour)
        } else if !panel.points.is_empty() {
            Swatch::LineMark(panel.colour, Marker::Dot)
        } else {
            Swatch::Line(panel.colour, 2)
        };
        legend.entry(swatch, panel.label.clone());
    }
}

/// The reference levels the `panels` draw, as the legend names them.
fn levels(h: &History, panels: &[Panel]) -> Vec<String> {
    let mut refs = vec!["θ = ±α".to_string()];
    refs.push(if h.linear {
        "ü_g = ±αg (rocking starts)".to_string()
    } else {
        "ü_g = ±g\u{a0}tan\u{a0}α (rocking starts)".to_string()
    });
    if panels
        .iter()
        .any(|p| p.desc == VERTICAL_DESC && !p.refs.is_empty())
    {
        refs.push("ü_v = −g (the ground falls away)".into());
    }
    if let Some(m) = h.sliding_level {
        refs.push(format!(
            "ü_g = ±μg = ±{}\u{a0}g (sliding starts)",
            fmt_num(m, 3)
        ));
    }
    if panels.iter().any(|p| p.desc == "f_x / f_z") {
        refs.push("f_x/f_z = ±tan\u{a0}α".into());
        if let Some(m) = h.mu {
            refs.push(format!("±μ = {}", fmt_num(m, 3)));
        }
    }
    refs
}

/// How the history ends, in the legend and as lines across the panels:
/// overturning or rest for good; and lift-off marked.
fn ending(legend: &mut Legend, h: &History) -> Vec<Mark> {
    let result = h.result;
    let mode = result.mode.unwrap_or(1);
    let mut marks = Vec::new();
    if result.overturned
        && let Some(to) = result.overturn_time
    {
        let label = format!(
            "overturned, mode {mode} ({}), t = {} s",
            if mode == 2 {
                "no impact"
            } else {
                "after impact"
            },
            fmt_num(to, 4)
        );
        legend.entry(Swatch::Dashed(mode_colour(mode), 2), label);
        marks.push(Mark {
            t: to,
            colour: mode_colour(mode),
            label: format!("overturns (mode {mode})"),
        });
    } else if let Some(tr) = h.at_rest_from {
        let until = if h.record_end.is_some_and(|r| r > tr) {
            format!(
                ", to the record's end at {} s (the ground stays below the rocking threshold)",
                fmt_num(h.t_end, 4)
            )
        } else {
            String::new()
        };
        legend.entry(
            Swatch::Dashed(REST, 2),
            format!("at rest for good from t = {} s{until}", fmt_num(tr, 4)),
        );
        marks.push(Mark {
            t: tr,
            colour: REST,
            label: format!("at rest from t = {} s", fmt_num(tr, 4)),
        });
    }
    if let Some(tl) = result.lift_off_time {
        marks.push(Mark {
            t: tl,
            colour: INK,
            label: "lift-off (f_z = 0)".into(),
        });
    }
    marks
}

/// The legend's notes on the ground motion: the pulse's amplitude and
/// frequency, the record's samples and peak, the vertical motion.
fn motion_notes(legend: &mut Legend, h: &History) {
    let (alpha, p, g) = (h.alpha, h.p, h.g);
    if let Some(pulse) = &h.spec.pulse {
        let (a, w) = (pulse.a_p, pulse.omega_p);
        legend.note(format!(
            "a_p = {} m/s² = {} g = {} αg",
            fmt_num(a, 4),
            fmt_num(a / g, 4),
            fmt_num(a / (alpha * g), 4)
        ));
        legend.note(format!(
            "ω_p = {} rad/s (f_p = {} Hz), ω_p/p = {}",
            fmt_num(w, 4),
            fmt_num(w / std::f64::consts::TAU, 3),
            fmt_num(w / p, 4)
        ));
    }
    if let (Some(Motion::Record { dt, acc }), Some(peak)) = (&h.motion, h.record_peak) {
        legend.note(format!(
            "record: {} samples every {} s, peak |ü_g| = {} g = {} αg",
            acc.len(),
            fmt_num(*dt, 3),
            fmt_num(peak / g, 3),
            fmt_num(peak / (alpha * g), 3)
        ));
    }
    if let (Some(m), Some(v)) = (&h.motion, &h.vertical) {
        legend.note(vertical_note(h, m, v));
    }
}

/// The legend's note on the vertical motion `v` beside the horizontal `m`:
/// a ratio, a record or a pulse of its own, with its peak.
fn vertical_note(h: &History, m: &Motion, v: &Vertical) -> String {
    let g = h.g;
    let peak = v.peak(m);
    match (v, &h.spec.ground_motion) {
        (Vertical::Ratio(r), _) => format!(
            "vertical: ü_v = {} ü_g, peak |ü_v| = {} g",
            fmt_num(*r, 4),
            fmt_num(peak / g, 3)
        ),
        (Vertical::Own { motion: own, .. }, Some(_)) => format!(
            "vertical record: {} samples, peak |ü_v| = {} g",
            match own {
                Motion::Record { acc, .. } => acc.len(),
                Motion::Pulse(_) => 0,
            },
            fmt_num(peak / g, 3)
        ),
        (Vertical::Own { motion: own, delay }, None) => format!(
            "vertical pulse: a_v = {} g, {} ≤ t ≤ {} s",
            fmt_num(
                match own {
                    Motion::Pulse(p) => p.amplitude,
                    Motion::Record { .. } => peak,
                } / g,
                4
            ),
            fmt_num(*delay, 4),
            fmt_num(delay + own.duration(), 4)
        ),
    }
}

/// The legend's notes on the outcome: the impacts, the peaks of θ/α and
/// f_x/f_z (and the largest f_x/f_z, `clipped_ratio`, when it leaves its
/// panel), the warnings, and what a result without a series lacks.
fn outcome_notes(legend: &mut Legend, h: &History, clipped_ratio: Option<f64>) {
    let result = h.result;
    let n = result.impact_count;
    let summed = result.chatter_impacts_summed;
    let plural = if n == 1 { "" } else { "s" };
    legend.note(if summed > 0 {
        format!("{n} impact{plural} ({summed} of a chattering tail summed, not listed)")
    } else {
        format!("{n} impact{plural}")
    });
    if !result.overturned {
        legend.note(format!(
            "peak |θ|/α = {}",
            fmt_num(result.peak_theta_over_alpha, 3)
        ));
    }
    if let Some(peak) = result.peak_friction_demand {
        legend.note(format!("peak f_x/f_z while rocking = {}", fmt_num(peak, 3)));
    }
    if let Some(largest) = clipped_ratio {
        legend.note(format!(
            "f_x/f_z leaves the panel as f_z → 0 (|f_x/f_z| up to {} before it stops)",
            fmt_num(largest, 3)
        ));
    }
    for w in &result.warnings {
        let kind = &w.kind;
        legend.note(match w.t {
            Some(t) => format!("warning: {kind} at t = {} s", fmt_num(t, 4)),
            None => format!("warning: {kind}"),
        });
    }
    if h.series.is_none() {
        legend.note(if h.spec.contact.is_some() {
            NO_SERIES_COULOMB
        } else {
            NO_SERIES
        });
    }
}

/// The figure's title: the record's peak or the pulse's shape, amplitude
/// and frequency, and the formulation.
fn title(h: &History) -> String {
    let (alpha, g) = (h.alpha, h.g);
    let spec = h.spec;
    match (&spec.pulse, h.record_peak) {
        (_, Some(peak)) => format!(
            "Rocking time history: recorded ground motion, peak {} αg ({})",
            fmt_num(peak / (alpha * g), 3),
            spec.formulation.name()
        ),
        (Some(pulse), None) => format!(
            "Rocking time history: {} pulse, a_p = {} αg, ω_p/p = {} ({})",
            shape_title(pulse.shape),
            fmt_num(pulse.a_p / (alpha * g), 4),
            fmt_num(pulse.omega_p / h.p, 4),
            spec.formulation.name()
        ),
        _ => "Rocking time history".to_string(),
    }
}

/// What every panel shares: the ground motion's end, the impacts, the
/// `marks` and the band of modes.
fn shared(h: History, marks: Vec<Mark>) -> Shared {
    Shared {
        motion_end: h.motion.as_ref().map(Motion::duration),
        impacts: h.impact_times,
        marks,
        bands: h
            .modes
            .iter()
            .filter_map(|m| {
                mode_band(&m.mode).0.map(|colour| Band {
                    from: m.from,
                    to: m.to,
                    colour,
                })
            })
            .collect(),
    }
}

/// The figure of a `time_history` result, over `window` or, without one,
/// the whole history (with a zoomed column for a short pulse).
pub fn svg(result: &TimeHistoryResult, window: Option<Window>) -> Result<String, String> {
    let h = History::of(result);
    let zoom = zoom(&h, window);
    let spans = spans(&h, window, zoom);
    let (from, to) = spans.iter().fold((0.0f64, h.t_end), |(a, b), (s, _)| {
        (a.min(s.t0), b.max(s.t1))
    });
    let panels = panels(&h, to, GroundCurves::of(&h, from, to))?;
    let (legend, marks) = legend(&h, zoom, &panels);
    let title = title(&h);
    let shared = shared(h, marks);
    let panels = panels.list;
    let layout = Layout::new(panels.len(), !spans[0].1.is_empty(), &legend);
    render((WIDTH, layout.height), &title, |area| {
        draw(area, &layout, &panels, &spans, &shared, &legend)
    })
}

/// Heights of the parts of the figure, px.
struct Layout {
    /// Column headings (0: none).
    heading: u32,
    /// One panel (the bottom one also has the time axis).
    panel: u32,
    /// The panels with the time axis.
    charts: u32,
    /// The whole figure.
    height: u32,
}

impl Layout {
    fn new(panels: usize, headings: bool, legend: &Legend) -> Layout {
        let n = panels.max(1) as u32;
        let heading = if headings { HEADING } else { 0 };
        let panel = (PANELS_HEIGHT / n).max(MIN_PANEL);
        let charts = heading + n * panel + X_AXIS;
        let height = TITLE_AREA + charts + legend_height(legend, WIDTH, LEGEND_COLUMNS) + 12;
        Layout {
            heading,
            panel,
            charts,
            height,
        }
    }
}

fn draw(
    area: &Area,
    layout: &Layout,
    panels: &[Panel],
    spans: &[(Span, String)],
    shared: &Shared,
    legend: &Legend,
) -> Drawn {
    let (charts, below) = area.split_vertically(layout.charts);
    let columns = match spans.len() {
        1 => vec![charts],
        _ => {
            let (left, right) =
                charts.split_horizontally((f64::from(WIDTH) * ZOOM_SHARE).round() as u32);
            vec![left, right]
        }
    };
    for (c, ((span, heading), column)) in spans.iter().zip(&columns).enumerate() {
        let (head, body) = column.split_vertically(layout.heading);
        if !heading.is_empty() {
            let x = if c == 0 { Y_LABELS.0 } else { Y_LABELS.1 } as i32;
            head.draw(&Text::new(
                heading.clone(),
                (x + 4, 8),
                text(LEGEND + 1, INK),
            ))?;
        }
        let n = panels.len();
        let (upper, bottom) = body.split_vertically(layout.panel * (n as u32 - 1));
        let mut areas = if n > 1 {
            upper.split_evenly((n - 1, 1))
        } else {
            Vec::new()
        };
        areas.push(bottom);
        for (k, (panel, a)) in panels.iter().zip(&areas).enumerate() {
            let place = Place {
                top: k == 0,
                bottom: k + 1 == n,
                desc: c == 0,
                y_labels: if c == 0 { Y_LABELS.0 } else { Y_LABELS.1 },
                x_axis: X_AXIS,
            };
            draw_panel(a, panel, span, shared, place)?;
        }
    }
    draw_legend_columns(&below.margin(6, 0, 12, 12), legend, LEGEND_COLUMNS)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::{
        GROUND, MODES, NO_SERIES_COULOMB, RATIO, SLIP, THETA, TimeHistoryResult, VERTICAL,
        mode_band, response_end, slip_at_changes, zoom_end,
    };
    use crate::jobs::contact::ModeDoc;
    use crate::kinds::JobResult;
    use crate::plot::style::{REST, fmt_num};
    use crate::plot::tests::{hex, shapes, x_extent};
    use crate::plot::time_panel::BAND_HEIGHT;
    use crate::plot::window::Window;
    use plotters::style::RGBColor;

    /// The time history of the spec `text`.
    pub(crate) fn computed(text: &str) -> TimeHistoryResult {
        match crate::plot::tests::typed(text) {
            JobResult::TimeHistory(r) => *r,
            other => panic!("a time history, not {:?}", other.job_kind()),
        }
    }

    /// The texts of `svg` joined by spaces (a legend entry wraps over
    /// several texts).
    fn text_of(svg: &str) -> String {
        svg.split("<text")
            .skip(1)
            .filter_map(|rest| rest.split_once('>')?.1.split("</text>").next())
            .map(str::trim)
            .collect::<Vec<_>>()
            .join(" ")
            .replace("&apos;", "'")
    }

    /// Fig. 7: a one-sine pulse of 3.02 αg at ω_p/p = 5, linear, exact;
    /// `series` samples.
    fn fig7(series: usize) -> TimeHistoryResult {
        let spec = include_str!("../../../specs/fig7_linear_exact.json")
            .replace("\"series\": 400", &format!("\"series\": {series}"));
        computed(&spec)
    }

    #[test]
    fn four_panels_with_labels_marks_and_legend() {
        let result = fig7(200);
        assert!(result.overturned && result.mode == Some(1));
        assert_eq!(result.impacts.as_ref().map(Vec::len), Some(1));
        let svg = super::svg(&result, None).expect("svg");
        for needle in [
            "Rocking time history: one-sine pulse, a_p = 3.02 αg, ω_p/p = 5 (linear)",
            "ü_g / g",
            "θ / α",
            "θ̇ / p",
            "f_x / f_z",
            "t (s)",
            "impact (1 listed)",
            "overturns (mode 1)",
            "pulse: 0 ≤ t ≤ 0.587 s",
            "linear formulation, solver exact",
            "levels: θ = ±α; ü_g = ±αg",
        ] {
            assert!(svg.contains(needle), "missing {needle:?}");
        }
    }

    #[test]
    fn without_series_the_pulse_and_impacts_are_drawn_with_a_hint() {
        let result = fig7(0);
        assert!(result.series.is_none());
        let svg = super::svg(&result, None).expect("svg");
        assert!(svg.contains("θ̇ / p at impacts"));
        assert!(text_of(&svg).contains("ground acceleration ü_g/g (from the pulse)"));
        assert!(svg.contains("outputs"));
        // No impacts and no ground motion: nothing to draw.
        let mut bare = result;
        bare.impacts = Some(Vec::new());
        bare.spec.pulse = None;
        let e = super::svg(&bare, None).unwrap_err();
        assert!(e.contains("\"outputs\": {\"series\": 500}"), "{e}");
    }

    #[test]
    fn a_recorded_ground_motion_is_drawn_from_its_samples() {
        let acc: Vec<String> = (0..300)
            .map(|k| ((f64::from(k) * 0.1).sin() * 5.0).to_string())
            .collect();
        let result = computed(&format!(
            r#"{{"kind": "time_history", "block": {{"alpha": 0.25, "p": 2.14, "eta": 0.9}},
                "ground_motion": {{"dt": 0.01, "acc": [{}], "unit": "m/s2"}},
                "formulation": "linear"}}"#,
            acc.join(", ")
        ));
        let svg = super::svg(&result, None).expect("svg");
        assert!(
            svg.contains("Rocking time history: recorded ground motion, peak 2.04 αg (linear)")
        );
        assert!(text_of(&svg).contains("ground acceleration ü_g/g (the record)"));
        assert!(svg.contains("ground motion: 0 ≤ t ≤ 2.99 s"));
        assert!(svg.contains("record: 300 samples"));
    }

    #[test]
    fn zoom_on_a_short_pulse_and_its_first_impacts_only() {
        // A 0.4 s pulse, impacts at 0.85, 2 and 7 s, a 5.2 s history: the
        // zoom reaches the first impact (the later ones are too far).
        let z = zoom_end(0.4, &[0.85, 2.0, 7.0], 5.24).expect("zoom");
        assert!((z - 0.935).abs() < 1e-12, "{z}");
        // No impact near: one and a half pulses.
        assert!((zoom_end(0.4, &[], 5.0).expect("zoom") - 0.66).abs() < 1e-12);
        // A pulse of a quarter of the history or more reads as it is.
        assert_eq!(zoom_end(0.4, &[], 1.6), None);
        assert_eq!(zoom_end(0.0, &[], 1.0), None);
    }

    /// f_x/f_z of a computed result as the figure reads it: (t, value).
    fn ratio_of(result: &TimeHistoryResult) -> Vec<(f64, f64)> {
        let s = result.series.as_ref().expect("a series");
        let ratio = s.fx_over_fz.as_ref().expect("reactions");
        s.t.iter()
            .zip(ratio)
            .map(|(&t, v)| (t, v.unwrap_or(f64::NAN)))
            .collect()
    }

    /// No segment of the f_x/f_z curve in `svg` is a vertical bar.
    fn assert_no_vertical_bar(svg: &str) {
        let colour = format!("stroke=\"{}\"", crate::plot::tests::hex(RATIO));
        let curves = crate::plot::tests::shapes(svg, "polyline", &colour);
        assert!(!curves.is_empty());
        for w in curves.iter().flat_map(|c| c.windows(2)) {
            let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
            assert!(dx.abs() > 0.5 || dy.abs() < 30.0, "a bar {w:?}");
        }
    }

    #[test]
    fn friction_demand_stops_at_lift_off() {
        // One-cosine, ω_p/p = 1, 6 αg: f_z reaches 0 at 0.4105 s.
        let result = computed(
            r#"{"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_cosine", "omega_ratio": 1.0, "a_p_alpha_g": 6.0},
                "formulation": "nonlinear", "outputs": {"series": 400, "reactions": true}}"#,
        );
        let lift_off = result.lift_off_time.expect("lifts off");
        assert!((lift_off - 0.410_511_6).abs() < 1e-6, "{lift_off}");
        let (line, end) = super::friction_demand(&ratio_of(&result), &result);
        let last = line.last().expect("a curve").0;
        assert!(line.iter().all(|p| p.0 <= lift_off && p.1.is_finite()));
        // The last sample before lift-off (400 samples over 0.765 s).
        assert!(last > lift_off - 0.002, "{last}");
        let end = end.expect("an end");
        assert_eq!((end.t, end.label.as_str()), (last, "lift-off: f_z = 0"));
        let svg = super::svg(&result, None).expect("svg");
        assert!(svg.contains("lift-off: f_z = 0"));
        // No peak demand (unbounded): the range follows twice the demand
        // when rocking starts, and the curve rising towards lift-off leaves it.
        assert_eq!(result.peak_friction_demand, None);
        assert!(svg.contains("f_x/f_z leaves the panel as f_z → 0"));
        assert_no_vertical_bar(&svg);
    }

    #[test]
    fn friction_demand_stops_when_the_block_is_bound_to_overturn() {
        let result = computed(include_str!("../../../specs/locomotive_nonlinear.json"));
        let bound = result
            .friction_demand_followed_until
            .expect("bound to overturn");
        let (line, end) = super::friction_demand(&ratio_of(&result), &result);
        assert_eq!(line.last().map(|p| p.0), Some(bound));
        assert_eq!(end.map(|e| e.label), Some("bound to overturn".to_string()));
        // Its pulse lasts 0.4 s of 5.24: the figure zooms on it and on the
        // first impact (0.848 s) beside the whole history.
        let svg = super::svg(&result, None).expect("svg");
        assert!(svg.contains("the pulse and first impacts, t = 0–0.932 s"));
        assert!(svg.contains("the whole history, t = 0–5.237 s"));
        assert_no_vertical_bar(&svg);
    }

    /// A 40 s record (every 0.01 s): 3 s of shaking at 0.5 g, 2 Hz, then
    /// 0.05 g, below the rocking threshold of α = 0.25 (0.255 g), to the end.
    fn quiet_tail() -> TimeHistoryResult {
        let acc: Vec<String> = (0..4000)
            .map(|k| {
                let t = f64::from(k) * 0.01;
                let a = if t < 3.0 { 0.5 } else { 0.05 };
                (a * (std::f64::consts::TAU * 2.0 * t).sin()).to_string()
            })
            .collect();
        computed(&format!(
            r#"{{"kind": "time_history", "block": {{"alpha": 0.25, "p": 2.14, "eta": 0.9}},
                "ground_motion": {{"dt": 0.01, "acc": [{}], "unit": "g"}},
                "formulation": "nonlinear", "solver": {{"method": "dopri5"}},
                "outputs": {{"series": 600, "reactions": true}}}}"#,
            acc.join(", ")
        ))
    }

    /// The y (px) of the time axis' description in `svg`: the legend is
    /// below it.
    fn axis_y(svg: &str) -> f64 {
        svg.split("<text")
            .find(|t| t.contains(">\nt (s)\n<"))
            .and_then(|t| {
                t.split(" y=\"")
                    .nth(1)?
                    .split('"')
                    .next()?
                    .parse::<f64>()
                    .ok()
            })
            .expect("a time axis")
    }

    /// The polylines of `svg` in `colour` whose every point lies right of
    /// `left` px and above the time axis' description (the legend is
    /// below it).
    fn lines_right_of(svg: &str, colour: RGBColor, left: f64) -> Vec<Vec<(f64, f64)>> {
        let axis = axis_y(svg);
        let stroke = format!("stroke=\"{}\"", hex(colour));
        shapes(svg, "polyline", &stroke)
            .into_iter()
            .filter(|l| l.iter().all(|p| p.0 > left && p.1 < axis))
            .collect()
    }

    #[test]
    fn under_a_record_the_axis_runs_to_its_end_and_says_when_the_block_came_to_rest() {
        let result = quiet_tail();
        let record_end = 3999.0 * 0.01;
        let rest = result.rest_time.expect("comes to rest");
        assert!(
            !result.overturned && rest > 3.0 && rest < 0.3 * record_end,
            "{rest}"
        );
        // The simulation stops at rest: the series ends there.
        assert_eq!(result.end_time, rest);
        let svg = super::svg(&result, None).expect("svg");
        let text = text_of(&svg).replace('\u{a0}', " ");
        let at_rest = format!("at rest from t = {} s", fmt_num(rest, 4));
        for needle in [
            at_rest.as_str(),
            "the whole record, t = 0–39.99 s",
            "the block's response, t = 0–",
            "to the record's end at 39.99 s",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        // In the whole record's column (at right): the ground motion and
        // the rotation (at rest, θ = 0) reach the same right end, and the
        // rest mark stands where rest / record_end puts it between t = 0
        // (where both start) and that end.
        let left = f64::from(super::WIDTH) * super::ZOOM_SHARE;
        let ground = x_extent(&lines_right_of(&svg, GROUND, left));
        let theta = x_extent(&lines_right_of(&svg, THETA, left));
        assert!((ground.1 - theta.1).abs() < 1.0, "{ground:?} {theta:?}");
        assert!((ground.0 - theta.0).abs() < 1.0, "{ground:?} {theta:?}");
        let mark: Vec<f64> = lines_right_of(&svg, REST, left)
            .into_iter()
            .filter(|l| l.len() == 2 && l[0].0 == l[1].0)
            .map(|l| l[0].0)
            .collect();
        let x = mark.first().copied().expect("the rest mark");
        let share = (x - ground.0) / (ground.1 - ground.0);
        assert!(
            (share - rest / record_end).abs() < 0.01,
            "{share} vs {}",
            rest / record_end
        );
    }

    #[test]
    fn a_window_on_a_record_keeps_the_block_at_rest() {
        let result = quiet_tail();
        let rest = result.rest_time.expect("comes to rest");
        // A window past the rest time: the block drawn still, the ground moving.
        let w = Window::new(rest + 1.0, 35.0).expect("window");
        let svg = super::svg(&result, Some(w)).expect("svg");
        let text = text_of(&svg);
        assert!(text.contains("(the history runs 0–39.99 s)"), "{text}");
        // Right of the y labels: the chart, not the legend's swatch.
        let left = f64::from(super::Y_LABELS.0);
        let theta = lines_right_of(&svg, THETA, left);
        assert_eq!(theta.len(), 1, "{theta:?}");
        let ys: Vec<f64> = theta[0].iter().map(|p| p.1).collect();
        assert!(ys.windows(2).all(|w| w[0] == w[1]), "θ flat at rest");
        let ground = x_extent(&lines_right_of(&svg, GROUND, left));
        assert!((x_extent(&theta).1 - ground.1).abs() < 1.0);
    }

    #[test]
    fn the_response_column_only_when_the_block_stops_early() {
        assert_eq!(response_end(8.0, 40.0), Some(8.8));
        assert_eq!(response_end(15.0, 30.0), None);
        assert_eq!(response_end(0.0, 40.0), None);
    }

    /// A one-sine pulse with the vertical motion `vertical`, `series` samples.
    fn with_vertical(vertical: &str, series: usize) -> TimeHistoryResult {
        computed(&format!(
            r#"{{"kind": "time_history", "block": {{"alpha": 0.25, "p": 2.14, "eta": 0.9}},
                "pulse": {{"type": "one_sine", "omega_ratio": 4, "a_p_alpha_g": 3.2}},
                "vertical": {vertical}, "outputs": {{"series": {series}, "duration": 5}}}}"#
        ))
    }

    #[test]
    fn a_vertical_ground_motion_is_drawn_under_the_horizontal_one() {
        let result = with_vertical(r#"{"ratio": -0.5}"#, 400);
        let svg = super::svg(&result, None).expect("svg");
        let text = text_of(&svg).replace('\u{a0}', " ");
        for needle in [
            "ü_v / g",
            "vertical ground acceleration ü_v/g, positive up",
            "vertical: ü_v = -0.5 ü_g, peak |ü_v| = 0.4 g",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        // Down to −0.4 g only: no level −g.
        assert!(!text.contains("ü_v = −g"), "{text}");
        let falling = super::svg(&with_vertical(r#"{"ratio": 1.0}"#, 400), None).expect("svg");
        assert!(text_of(&falling).contains("ü_v = −g (the ground falls away)"));
        // Its curve spans the time axis as the horizontal one does, in the
        // panel below it.
        let ground = shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(GROUND)));
        let vertical = shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(VERTICAL)));
        assert!(!vertical.is_empty(), "a ü_v curve");
        let (g, v) = (x_extent(&ground), x_extent(&vertical));
        assert!(
            (g.0 - v.0).abs() < 1.0 && (g.1 - v.1).abs() < 1.0,
            "{g:?} {v:?}"
        );
        let top = |l: &[Vec<(f64, f64)>]| l.iter().flatten().fold(f64::INFINITY, |m, p| m.min(p.1));
        assert!(top(&vertical) > top(&ground), "ü_v below ü_g");
        // Without a vertical motion nothing of it is drawn.
        let plain = super::svg(&fig7(200), None).expect("svg");
        assert!(!plain.contains("ü_v"));
        assert!(!plain.contains(&hex(VERTICAL)));
    }

    #[test]
    fn a_vertical_pulse_of_its_own_is_drawn_where_it_acts_with_or_without_series() {
        let vertical = r#"{"type": "one_cosine", "omega_p": 14, "a_p_g": 0.5, "delay_s": 0.3}"#;
        for series in [400, 0] {
            let result = with_vertical(vertical, series);
            let svg = super::svg(&result, None).expect("svg");
            let text = text_of(&svg).replace('\u{a0}', " ");
            let end = fmt_num(0.3 + std::f64::consts::TAU / 14.0, 4);
            let note = format!("vertical pulse: a_v = 0.5 g, 0.3 ≤ t ≤ {end} s");
            assert!(text.contains(&note), "missing {note:?} in {text}");
            assert!(text.contains("ü_v / g"), "{text}");
            if series == 0 {
                assert!(text.contains("positive up (from the spec)"), "{text}");
            }
        }
    }

    #[test]
    fn a_window_draws_the_span_asked_for() {
        let result = fig7(200);
        let w = Window::new(0.0, 1.2).expect("window");
        let svg = super::svg(&result, Some(w)).expect("svg");
        assert!(svg.contains("t = 0–1.2 s (the history runs 0–5.931 s)"));
        // Overturning at 5.931 s is outside the window: not marked.
        assert!(!svg.contains("overturns (mode 1)"));
        assert_ne!(svg, super::svg(&result, None).expect("svg"));
    }

    /// The rectangles (x, y, width, height, px) of `svg` filled with
    /// `colour` above the time axis' description: in the panels, not in
    /// the legend.
    fn filled_rects(svg: &str, colour: RGBColor) -> Vec<[f64; 4]> {
        let axis = axis_y(svg);
        let fill = format!("fill=\"{}\"", hex(colour));
        svg.split("<rect ")
            .skip(1)
            .filter_map(|rest| rest.split('>').next())
            .filter(|tag| tag.contains(&fill))
            .map(|tag| format!(" {tag}"))
            .filter_map(|tag| {
                let attr = |name: &str| -> Option<f64> {
                    tag.split(&format!(" {name}=\""))
                        .nth(1)?
                        .split('"')
                        .next()?
                        .parse()
                        .ok()
                };
                Some([attr("x")?, attr("y")?, attr("width")?, attr("height")?])
            })
            .filter(|r| r[1] < axis)
            .collect()
    }

    /// A one-sine pulse of 4 αg at ω_p/p = 3, on a floor of friction
    /// `contact` (None: pure rocking).
    fn one_sine_on(contact: Option<&str>) -> TimeHistoryResult {
        let contact = contact.map_or(String::new(), |c| format!(r#", "contact": {c}"#));
        computed(&format!(
            r#"{{"kind": "time_history", "block": {{"alpha": 0.25, "p": 2.14}},
                "pulse": {{"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0}}{contact}}}"#
        ))
    }

    #[test]
    fn on_a_coulomb_floor_the_modes_are_banded_and_the_slip_marked_at_each_change() {
        let result = one_sine_on(Some(r#"{"model": "coulomb", "mu": 0.3}"#));
        let modes = result.modes.as_deref().expect("modes");
        let occurring = |name: &str| modes.iter().any(|m| m.mode == name);
        assert!(occurring("rock") && occurring("slide_rock"), "{modes:?}");
        let svg = super::svg(&result, None).expect("svg");
        let text = text_of(&svg).replace('\u{a0}', " ");
        for needle in [
            "slip (m)",
            "slip at mode changes (m, + towards +x)",
            "known at the markers only",
            "mode: sticking (no band along the time axis)",
            "mode: rocking",
            "mode: sliding while rocking (slide-rock)",
            "floor: Coulomb friction, μ = 0.3",
            "it first moved by rocking",
            "slip of the base: peak |slip| = 0.295 m, residual -0.239 m (towards −x)",
            "overturned towards +x",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        // Never asks for the series the coulomb model refuses.
        assert!(text.contains(NO_SERIES_COULOMB), "{text}");
        assert!(!svg.contains("outputs"));
        // The modes absent from the history are not in the legend.
        assert_eq!(text.matches("mode: sliding").count(), 1, "{text}");
        assert!(!text.contains("in flight"));
        // Each shaded mode: a band of its stretches along the bottom of
        // each of the three panels (ü_g, θ̇ at its one impact, slip).
        assert_eq!(result.impacts.as_ref().map(Vec::len), Some(1));
        for name in ["rock", "slide_rock"] {
            let colour = mode_band(name).0.expect("shaded");
            let rects = filled_rects(&svg, colour);
            let visible = modes
                .iter()
                .filter(|m| m.mode == name && m.to - m.from > 0.01)
                .count();
            assert!(rects.len() >= 3 * visible, "{name}: {rects:?}");
            assert!(rects.iter().all(|r| r[3] <= f64::from(BAND_HEIGHT)));
        }
        assert!(filled_rects(&svg, mode_band("slide").0.expect("shaded")).is_empty());
        // The slip: a marker at each change (and at the start and end), in
        // time order, joined by a dashed line (many short pieces).
        let slip = slip_at_changes(modes);
        assert_eq!(slip.len(), modes.len() + 1);
        let axis = axis_y(&svg);
        let markers: Vec<(f64, f64)> = shapes(&svg, "polygon", &format!("fill=\"{}\"", hex(SLIP)))
            .into_iter()
            .filter(|m| m.iter().all(|p| p.1 < axis))
            .map(|m| {
                let n = m.len() as f64;
                let (x, y) = m.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
                (x / n, y / n)
            })
            .collect();
        assert_eq!(markers.len(), slip.len(), "{markers:?}");
        assert!(markers.windows(2).all(|w| w[0].0 <= w[1].0));
        // It ends slipped towards −x: below where it started.
        let (first, last) = (markers[0], markers[markers.len() - 1]);
        assert!(last.1 > first.1 + 20.0, "{first:?} {last:?}");
        let dashes = shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(SLIP)));
        assert!(dashes.len() > 2 * slip.len(), "{}", dashes.len());
        // The band lies under the values: the lowest slip marker clears the
        // top of the slip panel's band.
        let band_top = filled_rects(&svg, mode_band("rock").0.expect("shaded"))
            .iter()
            .map(|r| r[1])
            .fold(0.0, f64::max);
        let lowest = markers.iter().map(|m| m.1).fold(0.0, f64::max);
        assert!(lowest + 5.0 <= band_top, "{lowest} {band_top}");
    }

    /// The centres (px) of the slip's markers in `svg`, in the panels.
    fn slip_markers(svg: &str) -> Vec<(f64, f64)> {
        let axis = axis_y(svg);
        shapes(svg, "polygon", &format!("fill=\"{}\"", hex(SLIP)))
            .into_iter()
            .filter(|m| m.iter().all(|p| p.1 < axis))
            .map(|m| {
                let n = m.len() as f64;
                let (x, y) = m.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
                (x / n, y / n)
            })
            .collect()
    }

    /// A one-sine pulse of 4 αg at ω_p/p = 3 on a Coulomb floor of friction
    /// `mu`, with a series of `series` samples.
    fn coulomb_series(mu: f64, series: usize) -> TimeHistoryResult {
        computed(&format!(
            r#"{{"kind": "time_history", "block": {{"alpha": 0.25, "p": 2.14}},
                "pulse": {{"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 4.0}},
                "contact": {{"model": "coulomb", "mu": {mu}}},
                "outputs": {{"series": {series}}}}}"#
        ))
    }

    #[test]
    fn with_a_series_the_slip_is_a_solid_line_through_every_sample() {
        // μ = 0.2 < tan α: the block slides, and stands at the end.
        let result = coulomb_series(0.2, 400);
        assert!(!result.overturned && result.rest_time.is_some());
        let residual = result.residual_slide_m.expect("a residual slip");
        assert!(residual < -0.1, "{residual}");
        let s = result.series.as_ref().expect("a series");
        let slide = s.slide_m.as_deref().expect("the slip at each sample");
        assert_eq!(slide.len(), s.t.len());
        assert_eq!(slide.last(), Some(&residual));
        let svg = super::svg(&result, None).expect("svg");
        let text = text_of(&svg).replace('\u{a0}', " ");
        assert!(
            text.contains(
                "slip of the base on the floor (m, + towards +x); ● at each change of mode"
            ),
            "{text}"
        );
        for gone in [
            "known at the markers only",
            "dashed line",
            NO_SERIES_COULOMB,
        ] {
            assert!(!text.contains(gone), "{gone:?} in {text}");
        }
        // The rocking panels of the series are there, the band too.
        // It slides towards −x, then back: a marker where it turns.
        assert!(text.contains("● at each change of mode or of the way it slides"));
        for needle in ["θ / α", "θ̇ / p", "mode: sliding"] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        // The markers at the changes of mode, from the first (t = 0, no
        // slip) to the last (the end, the residual slip): they fix the
        // slip panel's scales.
        let modes = result.modes.as_deref().expect("modes");
        let changes = slip_at_changes(modes);
        let markers = slip_markers(&svg);
        assert_eq!(markers.len(), changes.len(), "{markers:?}");
        let (first, last) = (changes[0], changes[changes.len() - 1]);
        assert_eq!(first, (0.0, 0.0));
        assert_eq!(last, (result.end_time, residual));
        let (m0, m1) = (markers[0], markers[markers.len() - 1]);
        let x_of = |t: f64| m0.0 + (m1.0 - m0.0) * t / last.0;
        let y_of = |v: f64| m0.1 + (m1.1 - m0.1) * v / residual;
        // One solid line (not dashes), a point at each sample, each where
        // its slip puts it; the last at the residual slip.
        let axis = axis_y(&svg);
        let lines: Vec<Vec<(f64, f64)>> =
            shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(SLIP)))
                .into_iter()
                .filter(|l| l.iter().all(|p| p.1 < axis))
                // Not the markers' rings (closed).
                .filter(|l| l.first() != l.last())
                .collect();
        assert_eq!(lines.len(), 1, "{}", lines.len());
        let line = &lines[0];
        assert_eq!(line.len(), s.t.len());
        for (p, (&t, &v)) in line.iter().zip(s.t.iter().zip(slide)) {
            assert!((p.0 - x_of(t)).abs() < 1.5, "{p:?} at t = {t}");
            assert!((p.1 - y_of(v)).abs() < 1.5, "{p:?} for {v} m at t = {t}");
        }
        let end = line[line.len() - 1];
        assert!(
            (end.0 - m1.0).abs() < 1.5 && (end.1 - m1.1).abs() < 1.5,
            "{end:?} {m1:?}"
        );
    }

    #[test]
    fn with_a_series_an_overturning_block_shows_its_rocking_and_its_slip() {
        let result = coulomb_series(0.3, 600);
        assert!(result.overturned);
        let svg = super::svg(&result, None).expect("svg");
        let text = text_of(&svg).replace('\u{a0}', " ");
        for needle in [
            "θ / α",
            "rotation θ/α",
            "slip of the base on the floor (m, + towards +x); ● at each change of mode",
            "mode: rocking",
            "mode: sliding while rocking (slide-rock)",
            "overturned towards +x",
        ] {
            assert!(text.contains(needle), "missing {needle:?} in {text}");
        }
        // No marker between two stretches of one mode.
        assert!(!text.contains("of the way it slides"), "{text}");
        // θ drawn, and the slip solid: no dashes.
        assert!(!shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(THETA))).is_empty());
        let axis = axis_y(&svg);
        let slip: Vec<_> = shapes(&svg, "polyline", &format!("stroke=\"{}\"", hex(SLIP)))
            .into_iter()
            .filter(|l| l.iter().all(|p| p.1 < axis) && l.first() != l.last())
            .collect();
        // One piece: a dashed line would be many.
        assert_eq!(slip.len(), 1);
        let markers = slip_markers(&svg);
        let modes = result.modes.as_deref().expect("modes");
        assert_eq!(markers.len(), slip_at_changes(modes).len());
    }

    #[test]
    fn pure_rocking_has_no_bands_and_no_slip() {
        let result = one_sine_on(None);
        assert!(result.modes.is_none());
        let svg = super::svg(&result, None).expect("svg");
        for name in MODES {
            if let Some(colour) = mode_band(name).0 {
                assert!(filled_rects(&svg, colour).is_empty(), "{name}");
                assert!(!svg.contains(&hex(colour)), "{name}");
            }
        }
        assert!(!svg.contains(&hex(SLIP)));
        let text = text_of(&svg);
        assert!(!text.contains("slip") && !text.contains("mode:") && !text.contains("Coulomb"));
        // Named pure rocking, the same figure.
        let named = one_sine_on(Some(r#"{"model": "no_sliding"}"#));
        assert_eq!(super::svg(&named, None).expect("svg"), svg);
    }

    #[test]
    fn a_coulomb_history_pure_rocking_answers_never_slips() {
        let result = computed(
            r#"{"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
                "pulse": {"type": "one_sine", "omega_ratio": 6.0, "a_p_alpha_g": 3.0},
                "contact": {"model": "coulomb", "mu": 10}}"#,
        );
        assert_eq!(result.answered_by.as_deref(), Some("pure_rocking"));
        let svg = super::svg(&result, None).expect("svg");
        let text = text_of(&svg);
        assert!(text.contains("the base never slipped"), "{text}");
        assert!(text.contains("never exceeds μ"), "{text}");
        // A rocking band, and no other.
        assert!(!filled_rects(&svg, mode_band("rock").0.expect("shaded")).is_empty());
        for name in ["slide", "slide_rock", "flight"] {
            assert!(filled_rects(&svg, mode_band(name).0.expect("shaded")).is_empty());
        }
    }

    #[test]
    fn a_flight_is_banded_and_said_with_its_time_in_the_air() {
        // A vertical pulse of 1.6 g lifts the slide-rocking block off the
        // floor for 0.54 s; it lands on a corner and later overturns.
        let result = computed(
            r#"{"kind": "time_history", "block": {"alpha": 0.2, "p": 2.0},
                "pulse": {"type": "one_sine", "omega_p": 4.0, "a_p_g": 0.304},
                "vertical": {"type": "one_sine", "omega_p": 8.0, "a_p_g": 1.6, "delay_s": 0.15},
                "contact": {"model": "coulomb", "mu": 0.3}, "outputs": {"series": 400}}"#,
        );
        assert_eq!(result.flights, Some(1));
        let flight = result
            .modes
            .as_deref()
            .expect("modes")
            .iter()
            .find(|m| m.mode == "flight")
            .expect("flies")
            .clone();
        let svg = super::svg(&result, None).expect("svg");
        assert!(!filled_rects(&svg, mode_band("flight").0.expect("shaded")).is_empty());
        let text = text_of(&svg);
        let said = format!(
            "left the floor once, {} s in the air",
            fmt_num(flight.to - flight.from, 3)
        );
        assert!(text.contains(&said), "{text}");
        assert!(text.contains("in flight (off the floor)"), "{text}");
    }

    #[test]
    fn the_slip_is_known_at_each_change_of_mode() {
        let doc = |mode: &str, from: f64, to: f64, slip: (f64, f64)| ModeDoc {
            mode: mode.into(),
            from,
            to,
            direction: None,
            slide_from_m: slip.0,
            slide_to_m: slip.1,
        };
        let modes = [
            doc("stick", 0.0, 0.1, (0.0, 0.0)),
            doc("slide", 0.1, 0.5, (0.0, -0.2)),
            doc("rock", 0.5, 0.9, (-0.2, -0.2)),
        ];
        assert_eq!(
            slip_at_changes(&modes),
            vec![(0.0, 0.0), (0.1, 0.0), (0.5, -0.2), (0.9, -0.2)]
        );
        // A stretch not starting where the last ended keeps both ends.
        let gap = [
            doc("slide", 0.0, 1.0, (0.0, 0.1)),
            doc("rock", 1.0, 2.0, (0.2, 0.2)),
        ];
        assert_eq!(slip_at_changes(&gap).len(), 4);
        assert!(slip_at_changes(&[]).is_empty());
    }

    /// The boxes (left, top, right, bottom; px, by the figures' estimate of
    /// text width) of the texts of `svg` reading `label`.
    fn label_boxes(svg: &str, label: &str) -> Vec<(i32, i32, i32, i32)> {
        use crate::plot::style::{LEGEND, text_width};
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                let (tag, rest) = t.split_once('>')?;
                let text = rest.split("</text>").next()?.trim();
                let attr = |name: &str| -> Option<&str> {
                    tag.split(&format!(" {name}=\"")).nth(1)?.split('"').next()
                };
                let (x, y): (i32, i32) = (attr("x")?.parse().ok()?, attr("y")?.parse().ok()?);
                let w = text_width(text, LEGEND).ceil() as i32;
                let left = if attr("text-anchor") == Some("end") {
                    x - w
                } else {
                    x
                };
                (text == label).then_some((left, y, left + w, y + LEGEND as i32))
            })
            .collect()
    }

    /// Under ü_v = −0.5 ü_g a one-sine pulse of 6 αg at ω_p/p = 3 lifts the
    /// block off (f_z = 0) at 0.977 s and overturns it at 1.032 s, 54 px
    /// further: both labels went left of their lines at the same height,
    /// one over the other. The second now goes a row lower; no two labels
    /// of marks overlap.
    #[test]
    fn labels_of_close_marks_do_not_overlap() {
        use crate::kinds::survival::figure::overlap;
        use crate::plot::time_panel::LABEL_ROW;
        let result = computed(
            r#"{"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
                "pulse": {"type": "one_sine", "omega_ratio": 3, "a_p_alpha_g": 6},
                "vertical": {"ratio": -0.5}, "outputs": {"series": 400}}"#,
        );
        let (to, tl) = (
            result.overturn_time.expect("overturns"),
            result.lift_off_time.expect("lifts off"),
        );
        assert!(
            (to - 1.0323).abs() < 1e-4 && (tl - 0.9773).abs() < 1e-4,
            "{to} {tl}"
        );
        let svg = super::svg(&result, None).expect("svg");
        let over = label_boxes(&svg, "overturns (mode 2)");
        let lift = label_boxes(&svg, "lift-off (f_z = 0)");
        assert_eq!((over.len(), lift.len()), (1, 1), "{over:?} {lift:?}");
        let (a, b) = (over[0], lift[0]);
        assert!(!overlap(a, b), "{a:?} overlaps {b:?}");
        // Both left of their lines; the later-placed one a row lower.
        assert!(a.0 > b.0 && a.2 > b.2, "{a:?} {b:?}");
        assert_eq!(b.1 - a.1, LABEL_ROW, "{a:?} {b:?}");
    }
}
