//! The tasks of a job of scan lines (a record spectrum, a forensic query):
//! a part is a range of lines that share a scan grid and a range of their
//! levels. Lines are grouped while a task stays short; a line whose scan
//! alone costs more than a task is split along its level axis, into ranges
//! of levels that share their boundary level, so that every pair of
//! neighbouring levels is refined by exactly one task and the scan and
//! bisection guarantee ([`crate::spectrum::scan`]) holds across the split:
//! the parts assemble into what one task computes.
//!
//! A part's document keeps the levels as the bits of their `f64`s, so that
//! the assembled result is identical to one computed whole whatever the
//! text of a stored document.

use serde::{Deserialize, Serialize};

use crate::dynamics::Problem;
use crate::jobs::JobError;
use crate::spectrum::Control;
use crate::spectrum::overturning::{Found, ScanGrid, chunk_points, scan_range};
use crate::spectrum::scan::{
    Direction, ModeChange, Model, Scalable, ScanError, ScanStats, Transition,
};
use crate::spectrum::verify::Mixed;

/// A task of a job of scan lines: lines `[from, to)` (of one [`Group`]),
/// levels `[first, last]` (both included) of their scan grid.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Part {
    /// Lines `[from, to)`: a record spectrum's sizes (indices into its
    /// `p`), a forensic query's observations × frequencies.
    #[serde(alias = "sizes")]
    pub lines: [usize; 2],
    /// Levels `[first, last]` of the scan grid.
    pub levels: [usize; 2],
}

/// Consecutive lines of a job that share a scan grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Group {
    /// How many lines.
    pub lines: usize,
    /// Levels of their grid (0: nothing to scan, no part).
    pub points: usize,
    /// CPU seconds of one line's scan.
    pub line_s: f64,
}

/// A transition with its levels as `f64` bits.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct TransitionBits {
    at: u64,
    up: bool,
    /// An edge of a slide band (`up`: entering it).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    slide: bool,
    mode: u8,
    impacts: u64,
    bracket: [u64; 2],
}

/// A mode change with its levels as `f64` bits.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct ModeChangeBits {
    at: u64,
    from: u8,
    to: u8,
    bracket: [u64; 2],
}

/// A mixed zone with its levels as `f64` bits.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct MixedBits {
    from: u64,
    to: u64,
    probes: u64,
    overturned: u64,
    in_band: u64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    first_overturn: Option<u64>,
}

/// What one part found on one size.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
struct LineBits {
    transitions: Vec<TransitionBits>,
    mode_changes: Vec<ModeChangeBits>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    mixed: Vec<MixedBits>,
}

impl From<&Mixed> for MixedBits {
    fn from(z: &Mixed) -> Self {
        MixedBits {
            from: z.from.to_bits(),
            to: z.to.to_bits(),
            probes: z.probes,
            overturned: z.overturned,
            in_band: z.in_band,
            first_overturn: z.first_overturn.map(f64::to_bits),
        }
    }
}

impl From<&MixedBits> for Mixed {
    fn from(z: &MixedBits) -> Self {
        Mixed {
            from: f64::from_bits(z.from),
            to: f64::from_bits(z.to),
            probes: z.probes,
            overturned: z.overturned,
            in_band: z.in_band,
            first_overturn: z.first_overturn.map(f64::from_bits),
        }
    }
}

/// Scan statistics of a part.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
struct StatsDoc {
    simulations: u64,
    steps: u64,
    rejected: u64,
    rhs_evaluations: u64,
    events: u64,
    max_error_estimate: f64,
    #[serde(default)]
    probes: u64,
    #[serde(default)]
    undecided: u64,
}

/// The document of a part, assembled by [`assemble`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PartDoc {
    /// The job's kind and "_part": "record_spectrum_part".
    kind: String,
    part: Part,
    /// One entry per size of the part.
    lines: Vec<LineBits>,
    stats: StatsDoc,
    wall_time_s: f64,
}

impl From<&Transition> for TransitionBits {
    fn from(t: &Transition) -> Self {
        TransitionBits {
            at: t.at.to_bits(),
            up: matches!(t.direction, Direction::Up | Direction::SlideIn),
            slide: t.is_slide(),
            mode: t.mode,
            impacts: t.impacts,
            bracket: [t.bracket.0.to_bits(), t.bracket.1.to_bits()],
        }
    }
}

impl From<&TransitionBits> for Transition {
    fn from(t: &TransitionBits) -> Self {
        Transition {
            at: f64::from_bits(t.at),
            direction: match (t.slide, t.up) {
                (true, true) => Direction::SlideIn,
                (true, false) => Direction::SlideOut,
                (false, true) => Direction::Up,
                (false, false) => Direction::Down,
            },
            mode: t.mode,
            impacts: t.impacts,
            bracket: (f64::from_bits(t.bracket[0]), f64::from_bits(t.bracket[1])),
        }
    }
}

impl From<&ModeChange> for ModeChangeBits {
    fn from(m: &ModeChange) -> Self {
        ModeChangeBits {
            at: m.at.to_bits(),
            from: m.from,
            to: m.to,
            bracket: [m.bracket.0.to_bits(), m.bracket.1.to_bits()],
        }
    }
}

impl From<&ModeChangeBits> for ModeChange {
    fn from(m: &ModeChangeBits) -> Self {
        ModeChange {
            at: f64::from_bits(m.at),
            from: m.from,
            to: m.to,
            bracket: (f64::from_bits(m.bracket[0]), f64::from_bits(m.bracket[1])),
        }
    }
}

impl From<&ScanStats> for StatsDoc {
    fn from(s: &ScanStats) -> Self {
        StatsDoc {
            simulations: s.simulations,
            steps: s.steps,
            rejected: s.rejected,
            rhs_evaluations: s.rhs_evaluations,
            events: s.events,
            max_error_estimate: s.max_error_estimate,
            probes: s.probes,
            undecided: s.undecided,
        }
    }
}

impl From<&StatsDoc> for ScanStats {
    fn from(s: &StatsDoc) -> Self {
        ScanStats {
            simulations: s.simulations,
            steps: s.steps,
            rejected: s.rejected,
            rhs_evaluations: s.rhs_evaluations,
            events: s.events,
            max_error_estimate: s.max_error_estimate,
            probes: s.probes,
            undecided: s.undecided,
        }
    }
}

/// The group of line `line` and its first line, if any.
fn group_of(groups: &[Group], line: usize) -> Option<(usize, usize)> {
    let mut first = 0;
    for (g, group) in groups.iter().enumerate() {
        if line < first + group.lines {
            return Some((g, first));
        }
        first += group.lines;
    }
    None
}

impl Part {
    /// Whether the part, read back from a task, is a part of a job of
    /// `groups`, or why not.
    pub fn fits(&self, groups: &[Group]) -> Result<(), JobError> {
        let part = self;
        let [from, to] = part.lines;
        let [first, last] = part.levels;
        let fits = from < to
            && group_of(groups, from).is_some_and(|(g, start)| {
                let group = groups[g];
                to <= start + group.lines && first <= last && last < group.points
            });
        if fits {
            Ok(())
        } else {
            Err(JobError::Task(format!(
                "a task's part {} does not fit its job ({} lines)",
                serde_json::json!(part),
                groups.iter().map(|g| g.lines).sum::<usize>()
            )))
        }
    }

    /// The part's lines, as a range.
    pub fn range(&self) -> std::ops::Range<usize> {
        self.lines[0]..self.lines[1]
    }
}

/// The parts of a job of `groups`, each part at most about `budget` CPU
/// seconds, at most `max_tasks` of them (longer parts where there would be
/// more): cheap lines of a group together, a dear line in ranges of its
/// levels. A group of one part is whole.
pub fn parts(groups: &[Group], budget: f64, max_tasks: usize) -> Vec<Part> {
    let total: f64 = groups.iter().map(|g| g.lines as f64 * g.line_s).sum();
    let max_tasks = max_tasks.max(1);
    let mut budget = budget.max(total / max_tasks as f64).max(f64::MIN_POSITIVE);
    loop {
        let out = cut(groups, budget, total, max_tasks);
        // Rounding of lines to parts may leave a few too many.
        if out.len() <= max_tasks || !budget.is_finite() {
            return out;
        }
        budget *= 1.25;
    }
}

/// The parts of `groups` (of `total` CPU seconds) of about `budget` each.
fn cut(groups: &[Group], budget: f64, total: f64, max_tasks: usize) -> Vec<Part> {
    let mut out = Vec::new();
    let mut start = 0;
    for group in groups {
        let (n, line_s) = (group.lines, group.line_s.max(0.0));
        let end = start + n;
        if group.points == 0 || n == 0 {
            start = end;
            continue;
        }
        let last = group.points - 1;
        if line_s <= budget || last == 0 {
            let per = ((budget / line_s.max(f64::MIN_POSITIVE)).floor() as usize).clamp(1, n);
            out.extend((start..end).step_by(per).map(|from| Part {
                lines: [from, (from + per).min(end)],
                levels: [0, last],
            }));
        } else {
            // Each line in ranges of levels sharing their boundaries, no
            // more than its share of the tasks.
            let share = (max_tasks as f64 * line_s / total.max(f64::MIN_POSITIVE)).floor() as usize;
            let ranges = ((line_s / budget).ceil() as usize)
                .min(share.max(1))
                .clamp(1, last);
            // At multiples of the grid's chunk length: each part is then
            // scanned and verified in the chunks of the whole line.
            let chunk = chunk_points(group.points);
            let per = last.div_ceil(ranges).div_ceil(chunk) * chunk;
            for i in start..end {
                out.extend((0..last).step_by(per).map(|k0| Part {
                    lines: [i, i + 1],
                    levels: [k0, (k0 + per).min(last)],
                }));
            }
        }
        start = end;
    }
    out
}

/// Scans `problems` (the lines of `part`, in order) over the levels of
/// `part` on `grid`; the document is of kind `kind` ("record_spectrum_part").
pub fn run<G: Scalable + Sync>(
    kind: &str,
    part: Part,
    problems: &[Problem<G>],
    model: Model,
    grid: &ScanGrid,
    control: &Control,
) -> Result<PartDoc, ScanError> {
    let started = std::time::Instant::now();
    let (found, stats) = scan_range(problems, model, grid, part.levels, control)?;
    Ok(PartDoc {
        kind: kind.into(),
        part,
        lines: found
            .iter()
            .map(|f| LineBits {
                transitions: f.transitions.iter().map(TransitionBits::from).collect(),
                mode_changes: f.mode_changes.iter().map(ModeChangeBits::from).collect(),
                mixed: f.mixed.iter().map(MixedBits::from).collect(),
            })
            .collect(),
        stats: StatsDoc::from(&stats),
        wall_time_s: started.elapsed().as_secs_f64(),
    })
}

/// What the parts (of kind `kind`) found on each line of a job of `groups`,
/// their statistics summed and their compute time: every line's levels
/// covered (but those of a group of no levels), else an error naming the
/// first gap.
pub fn assemble(
    kind: &str,
    groups: &[Group],
    parts: &[PartDoc],
) -> Result<(Vec<Found>, ScanStats, f64), JobError> {
    let n: usize = groups.iter().map(|g| g.lines).sum();
    let mut found: Vec<Found> = vec![Found::default(); n];
    let mut covered: Vec<Vec<[usize; 2]>> = vec![Vec::new(); n];
    let mut stats = ScanStats::default();
    let mut wall = 0.0;
    for doc in parts {
        let [from, to] = doc.part.lines;
        let fits = doc.kind == kind && from <= to && to <= n && to - from == doc.lines.len();
        if !fits {
            return Err(JobError::Task(format!(
                "a task's part {:?} does not fit its job",
                doc.part
            )));
        }
        for (i, line) in (from..to).zip(&doc.lines) {
            found[i].extend(Found {
                transitions: line.transitions.iter().map(Transition::from).collect(),
                mode_changes: line.mode_changes.iter().map(ModeChange::from).collect(),
                mixed: line.mixed.iter().map(Mixed::from).collect(),
            });
            covered[i].push(doc.part.levels);
        }
        stats.absorb(&ScanStats::from(&doc.stats));
        wall += doc.wall_time_s;
    }
    for (i, ranges) in covered.iter_mut().enumerate() {
        let points = group_of(groups, i).map_or(0, |(g, _)| groups[g].points);
        if points == 0 {
            continue;
        }
        let last = points - 1;
        ranges.sort_unstable();
        let mut reached = 0;
        for &[first, end] in ranges.iter() {
            if first > reached {
                break;
            }
            reached = reached.max(end);
        }
        if reached < last || ranges.first().is_none_or(|r| r[0] != 0) {
            return Err(JobError::Task(format!(
                "the tasks' parts do not cover line {i}: its levels end at {reached} of {last}"
            )));
        }
    }
    Ok((found, stats, wall))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn group(lines: usize, points: usize, line_s: f64) -> Group {
        Group {
            lines,
            points,
            line_s,
        }
    }

    #[test]
    fn parts_stay_in_their_group_and_cover_every_level() {
        // Three observations' grids: cheap lines, one with nothing to scan,
        // dear lines.
        let groups = [group(5, 40, 0.25), group(2, 0, 1.0), group(2, 90, 1.0)];
        let p = parts(&groups, 0.8, 256);
        // Cheap lines three at a time, whole levels.
        let cheap: Vec<Part> = p.iter().copied().filter(|q| q.lines[1] <= 5).collect();
        assert_eq!(
            cheap.iter().map(|q| q.lines).collect::<Vec<_>>(),
            vec![[0, 3], [3, 5]]
        );
        assert!(cheap.iter().all(|q| q.levels == [0, 39]));
        // No part for the group of no levels (lines 5 and 6).
        assert!(
            p.iter().all(|q| q.lines[0] >= 7 || q.lines[1] <= 5),
            "{p:?}"
        );
        // Dear lines alone, in 2 ranges sharing boundaries.
        for i in [7, 8] {
            let ranges: Vec<[usize; 2]> = p
                .iter()
                .filter(|q| q.lines == [i, i + 1])
                .map(|q| q.levels)
                .collect();
            assert_eq!(ranges.len(), 2, "{ranges:?}");
            assert_eq!(ranges[0][0], 0);
            assert_eq!(ranges[1][1], 89);
            assert!(ranges.windows(2).all(|w| w[0][1] == w[1][0]), "{ranges:?}");
        }
        // Every part, as stored and read back, fits the job; a part across
        // groups does not.
        let read = |v: serde_json::Value| serde_json::from_value::<Part>(v).expect("a part");
        for q in &p {
            let back = read(serde_json::to_value(q).expect("writes"));
            assert_eq!(back, *q);
            back.fits(&groups).expect("fits");
        }
        let across = read(serde_json::json!({"lines": [4, 6], "levels": [0, 1]}));
        assert!(across.fits(&groups).is_err());
        let beyond = read(serde_json::json!({"lines": [7, 8], "levels": [0, 90]}));
        assert!(beyond.fits(&groups).is_err());
    }

    #[test]
    fn tasks_are_capped_and_grow_instead() {
        let groups = [group(3, 1000, 100.0), group(40, 1000, 1.0)];
        for max in [10, 100, 256] {
            let p = parts(&groups, 0.01, max);
            assert!(p.len() <= max, "{} > {max}", p.len());
            // Still every line is in some part.
            for i in 0..43 {
                assert!(p.iter().any(|q| q.range().contains(&i)), "line {i}");
            }
        }
    }

    #[test]
    fn assembly_refuses_a_gap_and_a_foreign_part() {
        let groups = [group(1, 10, 1.0)];
        let doc = |kind: &str, levels: [usize; 2]| PartDoc {
            kind: kind.into(),
            part: Part {
                lines: [0, 1],
                levels,
            },
            lines: vec![LineBits::default()],
            stats: StatsDoc::from(&ScanStats::default()),
            wall_time_s: 0.5,
        };
        let whole = assemble(
            "a_part",
            &groups,
            &[doc("a_part", [0, 4]), doc("a_part", [4, 9])],
        )
        .expect("covers");
        assert_eq!(whole.2, 1.0);
        let gap = assemble(
            "a_part",
            &groups,
            &[doc("a_part", [0, 4]), doc("a_part", [5, 9])],
        );
        assert!(gap.is_err());
        let foreign = assemble("a_part", &groups, &[doc("b_part", [0, 9])]);
        assert!(foreign.is_err());
    }
}
